"""Running and reporting the study queries: Table III/IV analogues beside the paper's
values (:mod:`.study_tables`: every row the same definition as the paper or not, ours,
the paper's, the ratio and the reason for a gap beyond 2×), the paper's findings as
held / not held / not comparable (:mod:`.study_findings`), the six design criteria of
Sec. II-A, the dexterous workspace (eq. (17)), the Fig. 3 certificate, and the figures
(Fig. 5 for the ``plot_device`` only, Figs. 6 and 7 for every device, Tables III/IV as
bar charts).
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np

from .query import Outcome
from ..numfmt import sig
from .units import display_length as length_unit_of
from .study_tables import (_f, _sigma_unit, _subset, _unit, _unlike_paper,
                           _unlike_paper_table4, markdown_tables)
from ..indices.study import (CAPABILITIES, SENSITIVITIES, Device, planned_chunk, run_device,
                             summarise)
from ..indices.actuators import leg_limits, limit_text
from ..indices.study_findings import findings, row_definition
from ..indices.workspace import design_criteria, dexterous_workspace

#: markdown_tables (the Table III/IV analogues, :mod:`.study_tables`) stays importable here
__all__ = ["performance_report", "design_sweep_report", "markdown_tables", "certify_cube"]


def certify_cube(mech, width: float, executor=None, half: float = 0.075):
    """Fig. 3 analogue: the cube of half-width ``half`` (m; the paper's 150 mm cube by
    default) about the home position at the home rotation certified (regular / singular
    / undecided, :func:`distkin.certify.certify_workspace`)."""
    from ..certify.boxes import REGULAR, SINGULAR
    from ..certify.workspace import certify_workspace
    h = half
    c = np.asarray(mech.home, dtype=float)
    lo = c - np.array([h, h, h, 0, 0, 0])
    hi = c + np.array([h, h, h, 0, 0, 0])
    cert = certify_workspace(mech, lo, hi, [width] * 3 + [1.0] * 3, executor=executor)
    if np.any(cert.status == SINGULAR):
        return "singular", cert
    return ("regular" if np.all(cert.status == REGULAR) else "undecided"), cert


def _yes_no(v) -> str:
    """A flag of a criterion in words: yes / no / — (not evaluated), never Python's
    True / False / None."""
    return {True: "yes", False: "no", None: "—"}.get(v, str(v))


def _criteria_text(c, lu="mm", sigma_unit="1/(N·m)"):
    """One design criterion in words; lengths in the scene's unit ``lu``, σmin of
    ST⁻¹Jᵀ in ``sigma_unit`` (the device's: :func:`.study_tables._sigma_unit`; QA 25b
    F3: it was printed without one)."""
    v = c["value"]
    mark = {True: "held", False: "NOT held", None: "undecided"}[c["held"]]
    if c["held"] is None and v.get("note"):
        mark = v["note"] if v["note"].startswith("undecided") else f"undecided: {v['note']}"
    if c["number"] == 1:
        sig = _f(v["sigma_min"]) + ("" if v["sigma_min"] is None else f" {sigma_unit}")
        val = (f"σmin {sig}, all reachable {_yes_no(v['all_reachable'])}, "
               f"det sign changes {_yes_no(v['det_sign_changes'])}")
    elif c["number"] == 2:
        val = f"L = {v['L']}, min |Jq|/l1 {_f(v['transmission_min'])}"
    elif c["number"] == 3:
        val = (f"{_f(v['velocity_m_s'])} m/s ({v['velocity_set']}), "
               f"{_f(v['acceleration_m_s2'])} m/s²")
    elif c["number"] == 4:
        cert = v["certificate_zero_rotation"]      # None: not run (QA IX 6: "None")
        val = (f"grid {_length(v['cube_edge_m'], lu)}, ±{v['rotation_deg']:.0f}°, det sign "
               f"changes {_yes_no(v['det_sign_changes'])}, certificate "
               + (cert if cert is not None else "not run (certify = true in the "
                  "performance query runs it)"))
    elif c["number"] == 5:
        others = ", ".join(f"{k} {_f(g)}" for k, g in v["others"].items())
        more = ", ".join(f"{k} {_f(g)}" for k, g in v.get("more_legs", {}).items())
        val = f"GII {_f(v['gii'])} vs " + others if others else (
            f"GII {_f(v['gii'])}; no other device with at most as many legs in this study"
            + (f" (not compared: {more}, more legs)" if more else ""))
        if others and more:
            val += f" (not compared: {more}, more legs)"
    else:
        ms, units = v["max_sensitivities"], v.get("units", {})
        if isinstance(ms, dict):
            val = "max " + ", ".join(f"{k} {_f(x)}" + (f" {units[k]}" if k in units else "")
                                     for k, x in ms.items())
        else:                           # a bare list (design_criteria's own form)
            val = "max " + ", ".join(_f(x) for x in ms)
    return f"{c['number']}) {mark} [{val}]"


def _named_sensitivities(criteria, s) -> None:
    """Criterion 6's four maximum sensitivities by name, with their units (QA Z2 8: the
    text read ``max 0.3949, 25.87, 43.13, 0.6176`` and the JSON held a bare list):
    ``value["max_sensitivities"]`` becomes ``{"translational", "rotational", "force",
    "torque"}`` (the keys of :func:`distkin.indices.max_sensitivities`) and
    ``value["units"]`` the same keys' units, those of the Table III rows of the device
    (per rad of joint error and per N·m of actuator torque for revolute actuators; per m
    and per N for prismatic ones).  In place; any other criterion is left alone."""
    for c in criteria:
        v = c["value"]
        if c["number"] != 6 or isinstance(v.get("max_sensitivities"), dict):
            continue
        vals = list(v["max_sensitivities"])
        if len(vals) != len(SENSITIVITIES):       # nothing reachable: no values to name
            vals = [None] * len(SENSITIVITIES)
        names = [q[0].removeprefix("sens_") for q in SENSITIVITIES]
        v["max_sensitivities"] = dict(zip(names, vals))
        v["units"] = {n: _unit(q[0], q[2], s) for n, q in zip(names, SENSITIVITIES)}


def _inner_note(s, d, ctx):
    """Table IV's GII is over the inner orientations of the grid: when the range asked
    for (``inner_rotation``, ±20° by default) is not on the grid, say which range was
    covered (in the JSON, the text and one warning line on stderr)."""
    iso = s["isotropy"]
    want = iso.get("rotation_requested_deg")
    if want is None or abs(want - iso["rotation_deg"]) <= 1e-6:
        return
    iso["rotation_note"] = (
        f"inner_rotation ±{want:g}° is not on the grid: Table IV's GII is over the "
        f"orientations within it, which cover ±{iso['rotation_deg']:g}° (a rotation_step "
        f"that divides {want:g}° gives ±{want:g}°)")
    ctx.warn(f"{d.label}: {iso['rotation_note']}")


def _finding_text(f):
    def show(d):                        # None (nothing reachable): "—", not "None"
        if isinstance(d, dict):
            return ", ".join(f"{k} {_f(v) if v is None or isinstance(v, (int, float)) else v}"
                             for k, v in d.items())
        return "—" if d is None else str(d)
    unit = f" {f['unit']}" if f["unit"] else ""
    note = f" ({f['note']})" if f["note"] else ""
    return (f"- [{f['status']}] {f['finding']} ({f['source']}): ours {show(f['ours'])}{unit}; "
            f"paper {show(f['paper'])}{note}")


_NOTES = (
    "Every row is over the positions of the scene's grid (Table II's by default) and the "
    "device's "
    "orientations (the ± range of each row; the paper: ±20° for L = 6, ±30° for L = 8, "
    "Table IV over ±20°){subset}.  The geometry "
    "the paper does not print (l3, the reading of Fig. 2, the HEXA's and Ergin's "
    "parameters) is ours (distkin.mechanisms.presets; every reading tried, with its "
    "Table IV figures: docs/fig2_readings.md).  Table III's rows are extremes over the "
    "grid (a sampled minimum).  The velocity rows follow eq. (5) as written (the J# "
    "zonotope); for L = 8 it contains velocities the device cannot make, and the "
    "true-set rows give the worst case of {ẋ : |Jẋ|∞ <= q̇max}.")


def _notes(summaries) -> str:
    """The notes; when a device misses some grid poses, which poses its rows are over."""
    part = [f"{s['label']}'s rows {_subset(s) or 'over every pose'}, Table IV "
            f"{_subset(s['isotropy']) or 'over every pose'}"
            for s in summaries if _subset(s) or _subset(s["isotropy"])]
    unlike = [f"{s['label']}: {s['unlike_paper']}" for s in summaries if s.get("unlike_paper")]
    unlike4 = [f"{s['label']}: {s['isotropy']['unlike_paper']}" for s in summaries
               if s["isotropy"].get("unlike_paper") and s["isotropy"].get("paper_gii")
               is not None]
    return _NOTES.replace("{subset}", ", the poses the device reaches only: " + "; ".join(
        part) + " (the unreachable poses are left out, not scored σmin = 0 as a design_sweep's "
        "unreachable = \"zero\" does; the ratios to the paper are not like for like)"
        if part else "") + ("  Not the paper's poses (Table III's ratios not like for like): "
                            + "; ".join(unlike) + "." if unlike else "") + (
        "  Not Table II's poses (Table IV's ratios not like for like): "
        + "; ".join(unlike4) + "." if unlike4 else "")


def _sigma_of_devices(summaries) -> str:
    """The unit of the devices' σmin of ST⁻¹Jᵀ as Table IV's header gives it: one unit
    when every device shares it, else each device's (QA 25b F3)."""
    units = {s["label"]: _sigma_unit(s) for s in summaries}
    if len(set(units.values())) <= 1:
        return next(iter(units.values()), "1/(N·m) for revolute actuators, 1/N for "
                                          "prismatic ones")
    return "by device: " + ", ".join(f"{k} {u}" for k, u in units.items())


def _units_block(actuators, summaries=()) -> dict:
    """The units of the study JSON's fields that carry none in their name or entry
    (QA V: worst poses, actuator figures and dexterous-workspace thresholds had none;
    the table rows carry theirs, ``table[q]["unit"]``).  ``summaries``: the devices,
    whose actuators give the unit of σmin in the diagnostics and the criteria (QA 25b
    F3: those had no entry)."""
    from ..indices.actuators import KEY_UNITS
    from ..indices.isotropy import SIGMA_UNITS
    sig = (f"{_sigma_of_devices(summaries)} (the smallest σ of ST⁻¹Jᵀ over the device's "
           "grid, per unit of actuator effort)")
    return {"actuators": {k: KEY_UNITS.get(k, "see actuator_limits.units")
                          for k in actuators},
            "devices[].worst_poses": "x, y, z in m, rx, ry, rz in rad: the grid pose of "
                                     "each row's minimum",
            "devices[].worst_force_pose": "m, rad",
            "devices[].dexterous_workspace.thresholds": {"velocity": "m/s",
                                                         "acceleration": "m/s²",
                                                         "force": "N"},
            "devices[].rotation_deg": "deg", "seconds": "s (wall)",
            # QA 25a F5: σ of ST⁻¹Jᵀ are per unit of actuator effort, not dimensionless
            "devices[].isotropy": "gii, gii_full_range, readings[].gii: 1 (dimensionless); "
                                  "sigma_min, sigma_max (and *_full_range, readings.wrench): "
                                  "1/(N·m) for revolute actuators, 1/N for prismatic ones "
                                  "(ST⁻¹Jᵀ maps the actuator effort to the wrench in units "
                                  "of ST); readings' σ: "
                                  + "; ".join(f"{r} {rev} (revolute), {pri} (prismatic)"
                                              if rev != pri else f"{r} {rev}"
                                              for r, (rev, pri) in SIGMA_UNITS.items()
                                              if r != "wrench"),
            "devices[].diagnostics.sigma_min": sig,
            "devices[].criteria[].value.sigma_min": sig}


def _cm3(volume_m3: float, lu: str = "cm") -> str:
    """A volume (m³) in the scene's length unit cubed (``lu``: m, mm, cm, km; cm³ by
    default): whole units from 0.5 on (below 1e7), else 4 significant digits (a grid of
    0.025 mm cells, a unit slip, said "0 cm³ of 0 cm³": QA)."""
    x = volume_m3 * length_unit_of(lu)[0] ** 3
    return f"{x:.0f}" if (0.5 <= abs(x) < 1e7) or x == 0 else sig(x, 4 if abs(x) >= 1 else 3)


def _length(length_m: float, lu: str) -> str:
    """A length (m) in the scene's unit ``lu`` with its unit, 4 significant digits."""
    f, lu = length_unit_of(lu)
    return f"{sig(length_m * f)} {lu}"


def _grid_text(grid, lu: str) -> str:
    """The resolution of ``grid`` in words (QA 25a F6: the text gave "343 positions" and
    Table II's step, never its own): per axis its half-range about the middle and its
    step, axes with the same values named together, lengths in the scene's unit."""
    def group(names, axes, show):
        words = {}
        for name, a in zip(names, axes):
            a = np.asarray(a, dtype=float)
            words.setdefault(f"at {show(a[0])}" if len(a) == 1 else
                             f"±{show((a[-1] - a[0]) / 2)} in steps of {show(a[1] - a[0])} "
                             f"({len(a)} values", []).append(name)
        return "; ".join(f"{', '.join(n)}: {w}" + ("" if w.startswith("at") else
                                                     " each)" if len(n) > 1 else ")")
                         for w, n in words.items())
    z = np.asarray(grid.z, dtype=float)
    pos = group(("x", "y", "z"), (grid.x, grid.y, z - (z.max() + z.min()) / 2),
                lambda v: _length(v, lu))
    rot = group(("rx", "ry", "rz"), (grid.rx, grid.ry, grid.rz),
                lambda v: f"{sig(math.degrees(v))}°")
    return (f"positions {pos} about z = {_length((z.max() + z.min()) / 2, lu)}; "
            f"orientations {rot}")


def _refuse_unreachable(summaries, grids, scene):
    """A study none of whose devices reaches a pose of its grid has no capability to
    report: an InfeasibleError (exit 2, "a query whose data admit no answer"), naming each
    device's home; it was exit 0 with every value null (QA V 14).  A device among others
    that reaches none keeps its empty rows, said in the text."""
    if any(s["reachable_poses"] for s in summaries):
        return
    from ..errors import InfeasibleError
    from .units import length_factor
    lf = 1.0 / length_factor(scene.units, "units")
    homes = "; ".join(
        f"{s['label']}: home z = {grids[s['label']][1].mech.home[2] * lf:.6g} "
        f"{scene.units.length}, {s['poses']:,} poses" for s in summaries)
    raise InfeasibleError(f"expected a device that reaches some pose of its grid, got none "
                          f"that does ({homes}), so there is no capability to report",
                          field="grid", hint="a grid about the devices' home pose, or a "
                          f"unit slip? the scene's [units] length is \"{scene.units.length}\"")


def performance_report(p, scene, ctx, *, grid_of, store_of, executor):
    actuators = dict(p.actuators)
    thr = dict(p.thresholds)
    summaries, per_all, grids, certs, certified = [], {}, {}, {}, {}
    t_all = time.perf_counter()
    with executor() as ex:
        for d in p.devices:
            grid = grid_of(d)
            nchunks = -(-grid.n_positions // planned_chunk(grid.n_positions, p.chunk_positions))
            ctx.notice(f"performance: {d.label}: {grid.size:,} poses ({grid.n_positions:,} "
                       f"positions × {grid.n_orientations:,} orientations) in "
                       f"{nchunks:,} chunks")
            dev = Device(d.label, d.mech, grid, d.paper, d.inner)
            stats: dict = {}
            per, sec = run_device(dev, store=store_of(d.label), executor=ex,
                                  chunk_positions=p.chunk_positions, actuators=actuators,
                                  ST=p.scaling, route=p.route, progress=ctx.progress,
                                  sensitivity=p.sensitivity, stats=stats)
            lim = leg_limits(d.mech, actuators)
            nominal = lim["nominal"]
            s = summarise(dev, per, tau_nominal=(float(nominal[0]) if np.all(
                nominal == nominal[0]) else None))
            s["actuator_limits"] = {
                "nominal": lim["nominal"].tolist(), "stall": lim["stall"].tolist(),
                "rate": lim["rate"].tolist(), "prismatic": lim["prismatic"].tolist(),
                "units": "nominal/stall: N·m (revolute), N (prismatic); rate: rad/s "
                         "(revolute), m/s (prismatic)",
                "text": {w: limit_text(lim, w) for w in ("nominal", "stall", "rate")}}
            for q, entry in s["table"].items():      # sensitivities per the actuators' units
                entry["unit"] = _unit(q, entry["unit"], s)
            if p.certify:
                t0 = time.perf_counter()
                half = 0.075 if d.mech.kind == "rss" else (max(grid.x) - min(grid.x)) / 2
                certified[d.label], certs[d.label] = certify_cube(d.mech, p.certify_width, ex,
                                                                  half)
                s["certificate"] = {"zero_rotation_cube": certified[d.label], "cube_half_m": half,
                                    "seconds": time.perf_counter() - t0,
                                    **{k: v for k, v in certs[d.label].summary().items()
                                       if k.endswith("fraction")}}
            reach_all = s.pop("all_orientations_reachable")
            s.pop("inner_all_reachable")
            minima = {"velocity": per["velocity_min"], "acceleration": per["acceleration_min"],
                      "force": per["force_min"], "velocity_true": per["velocity_true_min"]}
            fthr = thr["force"] if thr["force"] > 0 else np.nextafter(0.0, 1.0)
            vkey = "velocity_true" if d.mech.L > 6 else "velocity"
            dex = dexterous_workspace(grid, reach_all, minima,
                                      {vkey: thr["velocity"],
                                       "acceleration": thr["acceleration"], "force": fthr})
            s["dexterous_workspace"] = {k: v for k, v in dex.items() if k != "mask"}
            s["dexterous_workspace"]["thresholds"] = thr
            s["seconds"] = sec
            s["chunks"] = nchunks
            s["chunks_resumed"] = int(stats.get("loaded", 0))
            _inner_note(s, d, ctx)
            s["positions_all_orientations_reachable"] = int(np.sum(reach_all))
            s["unlike_paper"] = _unlike_paper(s, grid)
            s["isotropy"]["unlike_paper"] = _unlike_paper_table4(s, grid)
            summaries.append(s)
            per_all[d.label] = (per, dex["mask"], reach_all, minima)
            grids[d.label] = (grid, dev)
    _refuse_unreachable(summaries, grids, scene)
    for s in summaries:                       # criterion 5 needs every device's GII
        per, _, reach_all, minima = per_all[s["label"]]
        others = {o["label"]: o["isotropy"]["gii"] for o in summaries
                  if o is not s and o["L"] <= s["L"]}
        more = {o["label"]: o["isotropy"]["gii"] for o in summaries
                if o is not s and o["L"] > s["L"]}
        dg = s["diagnostics"]
        s["criteria"] = design_criteria(
            s["L"], grids[s["label"]][0], reach_all, minima, s["isotropy"]["gii"],
            sigma_min=dg["sigma_min"], transmission_min=dg["transmission_min"],
            det_sign_changes=dg["det_sign_changes"], sensitivities_max=dg["sensitivities_max"],
            gii_others=others, certified=certified.get(s["label"]),
            any_reachable=s["reachable_poses"] > 0, gii_more_legs=more)
        _named_sensitivities(s["criteria"], s)
    total = time.perf_counter() - t_all
    fnd = findings(summaries, certified if p.certify else None)
    tables = markdown_tables(summaries, sensitivity=p.sensitivity,
                             certified=certified if p.certify else None)
    lu = length_unit_of(scene.units.length)[1]          # the scene's length unit
    lines = [f"Performance study of {len(summaries)} kinematics "
             f"({', '.join(s['label'] for s in summaries)}), {total:.1f} s; sensitivities: "
             f"{p.sensitivity} ({row_definition('sens_force', p.sensitivity)[1]}); "
             f"route: {p.route}"]
    for s in summaries:
        dw = s["dexterous_workspace"]
        cert = s.get("certificate")
        lines.append(f"  {s['label']}: {s['poses']:,} poses ({s['positions']:,} positions × "
                     f"{s['orientations']:,} orientations, ±{s['rotation_deg']:.0f}°: "
                     f"{_grid_text(grids[s['label']][0], lu)}), "
                     f"{100 * s['reachable_fraction']:.2f} % reachable"
                     + (" (every row below is over the reachable poses only)"
                        if s["reachable_only"] and s["reachable_poses"] else "") + ", "
                     f"{s['seconds']:.1f} s this run"
                     + (f" ({s['chunks_resumed']} of {s['chunks']} chunks resumed from the "
                        "run store, computed by an earlier run)" if s["chunks_resumed"] else "")
                     + "; dexterous workspace "
                     f"{dw['cells']} of {dw['cells_total']} grid cells = "
                     f"{_cm3(dw['volume_m3'], lu)} {lu}³ of {_cm3(dw['grid_volume_m3'], lu)} "
                     f"{lu}³ ({_cm3(dw['volume_nodes_m3'], lu)} {lu}³ by dual cells)"
                     + (f"; {_length(2 * cert.get('cube_half_m', 0.075), lu)} cube about home "
                        f"at its rotation certified {cert['zero_rotation_cube']}"
                        if cert else ""))
    from .design_report import scaling_note
    lines.append(f"  GII, σmin, σmax of ST⁻¹Jᵀ for every device: {scaling_note(p.scaling)}")
    lines += [f"  {s['label']}: {s['isotropy']['rotation_note']}" for s in summaries
              if s["isotropy"].get("rotation_note")]
    lines += [f"  {s['label']}: reaches no pose of its grid: its rows below are empty (—)"
              for s in summaries if s["reachable_poses"] == 0]
    lines += [f"  {s['label']}: {s['flagged_poses']:,} poses near-flat (σmin/σmax of J at "
              "most 1e-12): each left out of the rows whose value float64 cannot give "
              "there (ConditioningWarning; distkin.indices.zonotope)"
              for s in summaries if s.get("flagged_poses")]
    lines += [f"  {s['label']}: {s['unresolved_poses']:,} reachable poses where float64 does "
              "not resolve J (a leg within rounding of its reach boundary: J's error estimate "
              "above 1e-6 of a row): left out of every row (ConditioningWarning; "
              "distkin.indices.jacobian_resolution)"
              for s in summaries if s.get("unresolved_poses")]
    lines += ["", tables, "", "Findings of the paper:"]
    lines += [_finding_text(f) for f in fnd]
    lines += ["", "Design criteria (Sec. II-A; each with its own test, see the JSON):"]
    for s in summaries:
        lines.append(f"  {s['label']}: " + "; ".join(_criteria_text(c, lu, _sigma_unit(s))
                                                     for c in s["criteria"]))
    lines += ["", "Notes: " + _notes(summaries)]
    result = {"devices": summaries, "findings": fnd, "seconds": total,
              "chunks_resumed": sum(s["chunks_resumed"] for s in summaries),
              "actuators": actuators, "scaling": list(p.scaling),
              "sensitivity": p.sensitivity,
              # which route computed the numbers (the store is keyed by it: QA)
              "route": p.route,
              "grid": {s["label"]: grids[s["label"]][0].as_dict() for s in summaries},
              "markdown": tables, "unit": _units_block(actuators, summaries)}

    def plot(stem):
        return _plots(stem, grids, per_all, summaries, actuators, tables, result, certs,
                      p.plot_device, scene.units)
    return Outcome(result, "\n".join(lines), plot)


def _plots(stem, grids, per_all, summaries, actuators, tables, result, certs, pick, units):
    """The study's files: its tables (Markdown, JSON), Tables III/IV as plots, Figs. 5-7
    and the certified cube, lengths in the scene's ``units.length``."""
    from .report import jsonable
    from ..indices.plots import plot_force_polytope, plot_plane, plot_table3_bars, plot_table4_bars
    stem = Path(stem)
    lu = length_unit_of(units.length)[1]
    out = []
    md = stem.with_name(stem.name + "_tables.md")
    md.write_text(tables + "\n", encoding="utf-8")
    js = stem.with_name(stem.name + "_tables.json")
    js.write_text(json.dumps(jsonable({"devices": result["devices"],
                                       "findings": result["findings"]}), indent=1),
                  encoding="utf-8")
    out += [md, js, plot_table3_bars(stem, summaries), plot_table4_bars(stem, summaries)]
    pick = pick or next((s["label"] for s in summaries if s["L"] == 8), summaries[0]["label"])
    for s in summaries:
        label = s["label"]
        grid, dev = grids[label]
        per, mask, _, _ = per_all[label]
        mech = dev.mech
        dstem = stem.with_name(stem.name + "_" + "".join(ch if ch.isalnum() else "_"
                                                          for ch in label).strip("_").lower())
        if label == pick:
            out.append(_fig5(dstem, label, mech, grid, mask, lu))
        # Fig. 6: the plane nearest z = z0
        nx, ny, nz = len(grid.x), len(grid.y), len(grid.z)
        iz = int(np.argmin(np.abs(np.asarray(grid.z) - mech.home[2])))
        panels = [(title, unit, per[f"{name}_min"].reshape(nx, ny, nz)[:, :, iz])
                  for name, title, unit, *_ in CAPABILITIES]
        rot = math.degrees(max(abs(v) for v in grid.rx))
        out.append(plot_plane(dstem, label, grid.x, grid.y, grid.z[iz], panels, rot,
                              length_unit=lu))
        # Fig. 7: the force polytope at the worst-force pose
        if s["worst_force_pose"] is not None:
            pose = np.asarray(s["worst_force_pose"])
            J = mech.jacobian(pose[None])[0]
            out.append(plot_force_polytope(dstem, label, J.T,
                                           np.asarray(s["actuator_limits"]["nominal"]),
                                           pose, length_unit=lu))
        if label in certs:
            from ..certify.plot import plot_certificate
            out.append(plot_certificate(certs[label], dstem, length_unit=lu,
                                        angle_unit=units.angle))
    return out


def _fig5(stem, label, mech, grid, mask, lu="mm"):
    """Fig. 5: reachable positions at zero rotation on a larger grid, boundary only."""
    from ..indices.plots import plot_workspace
    half = (max(grid.x) - min(grid.x)) / 2
    cube = max(half, 0.075) if mech.kind == "rss" else half   # rss: the paper's 150 mm cube
    ax = np.linspace(-4 * cube, 4 * cube, 41)                # rss: -300 ... 300 mm, 15 mm
    c = np.asarray(mech.home, dtype=float)
    X, Y, Z = np.meshgrid(c[0] + ax, c[1] + ax, c[2] + ax, indexing="ij")
    P = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)
    ok = mech.reachable(np.hstack([P, np.broadcast_to(c[3:], P.shape)])).reshape(X.shape)
    inner = ok.copy()                      # boundary: reachable with an unreachable neighbour
    for axis in range(3):
        for shift in (1, -1):
            nb = np.roll(ok, shift, axis=axis)
            edge = [slice(None)] * 3
            edge[axis] = 0 if shift == 1 else -1
            nb[tuple(edge)] = False
            inner &= nb
    boundary = (ok & ~inner).ravel()
    return plot_workspace(stem, label, P[boundary], cube, c[:3],
                          grid.positions()[mask], length_unit=lu)


from .design_report import design_sweep_report  # noqa: E402  (re-exported)
