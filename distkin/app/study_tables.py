"""The Table III/IV analogues of the study queries as Markdown tables: every row of
the paper's capabilities, velocities and sensitivities with ours, the paper's value,
the ratio and whether the definitions, grid and subset are the paper's
(:func:`markdown_tables`), and the per-row words the report reuses (:func:`_unit`,
:func:`_subset`, :func:`_unlike_paper`, :func:`_unlike_paper_table4`).  The report that
runs the study and prints them is :mod:`.study_report`.
"""

from __future__ import annotations

import math

import numpy as np

from ..indices.isotropy import SCALING_READINGS
from ..indices.study import CAPABILITIES, PAPER_TABLE4, SENSITIVITIES, TRUE_VELOCITIES
from ..indices.study_findings import row_definition, row_reason, summary_sigma_unit
from ..indices.workspace import table2_grid
from ..numfmt import fixed as _f           # the tables' digits (also Table V's)

__all__ = ["markdown_tables"]

_ROWS = ([(c[0], c[1], c[2]) for c in CAPABILITIES] + [(t[0], t[1], t[2]) for t in
                                                        TRUE_VELOCITIES]
         + [(s[0], s[1], s[2]) for s in SENSITIVITIES])


def _ratio(x):
    return "—" if x is None or not math.isfinite(x) else f"{x:.3g}×"


def _limits_text(summaries) -> dict:
    """The run's actuator limits as text with units per actuator type (one text, or one
    per device when they differ), for the row definitions."""
    out = {}
    for which in ("nominal", "stall", "rate"):
        texts = {s["label"]: s["actuator_limits"]["text"][which] for s in summaries
                 if "actuator_limits" in s}
        if not texts:
            continue
        vals = set(texts.values())
        out[which] = vals.pop() if len(vals) == 1 else " / ".join(
            f"{t} ({label})" for label, t in texts.items())
    return out


#: the sensitivity rows' units by actuator type: per unit of joint error (rad for a
#: revolute leg, m for a prismatic one) and per unit of actuator effort (N·m, N)
_JOINT_UNITS = {
    "sens_translational": ("m/rad", "m/m", "m per joint unit"),
    "sens_rotational": ("rad/rad", "rad/m", "rad per joint unit"),
    "sens_force": ("N/(N·m)", "N/N", "N per actuator unit"),
    "sens_torque": ("(N·m)/(N·m)", "(N·m)/N", "N·m per actuator unit"),
}


def _unit(q, unit, s) -> str:
    """The unit of row ``q`` for device summary ``s``: the sensitivities' denominators
    follow its actuators (revolute, prismatic, or mixed)."""
    if q not in _JOINT_UNITS:
        return unit
    pris = (s.get("actuator_limits") or {}).get("prismatic") or [False]
    revolute, prismatic, mixed = _JOINT_UNITS[q]
    return prismatic if all(pris) else mixed if any(pris) else revolute


def _sigma_unit(s, reading="wrench") -> str:
    """The unit of device summary ``s``'s σ of ``reading`` (:func:`.isotropy.sigma_unit`,
    by its actuators: 1/(N·m) for ST⁻¹Jᵀ of revolute legs, 1/N of prismatic ones; QA 25a
    F5: Table IV printed them without one, and the text called them dimensionless); the
    same source as the reasons' and the design criteria's σ
    (:func:`.study_findings.summary_sigma_unit`)."""
    return summary_sigma_unit(s, reading)


def _common_unit(summaries, reading="wrench"):
    """The unit every device's σ of ``reading`` shares, or None."""
    units = {_sigma_unit(s, reading) for s in summaries}
    return units.pop() if len(units) == 1 else None


def _subset(e) -> str:
    """"" when a row's extremes are over every grid pose; else which poses they are over
    (``summarise``'s ``reachable_only``, ``poses_used``, ``poses_total``).  A device
    that reaches no pose has empty rows (—), said on its own line."""
    if not e.get("reachable_only") or not e["poses_used"]:
        return ""
    used, total = e["poses_used"], e["poses_total"]
    return f"over the {100 * used / total:.3g} % reachable poses ({used:,} of {total:,})"


def _same(same, e) -> str:
    """The "same def." cell: never "yes" for extremes over a subset of the grid (the
    ratio to the paper is then not like for like)."""
    sub = _subset(e)
    return same if not sub else f"no: {sub}; ratio not like for like"


def _unlike_grid(grid, positions, rotation_deg, rot, column) -> str:
    """What keeps ``grid`` (orientations over ±``rotation_deg``) from the paper's poses:
    Table II's positions (±75 mm in steps of 10 mm about the device's home height) and
    its orientations in steps of 5° over ±``rot`` (``column``: whose range that is); ""
    when nothing does."""
    why, ref = [], table2_grid(0.0)
    if not math.isclose(rotation_deg, rot, abs_tol=1e-6):
        why.append(f"orientations over ±{rotation_deg:.4g}° ({column} ±{rot:.0f}°)")
    z = np.asarray(grid.z) - 0.5 * (max(grid.z) + min(grid.z))
    if not all(len(a) == len(b) and np.allclose(a, b, rtol=0.0, atol=1e-9)
               for a, b in ((grid.x, ref.x), (grid.y, ref.y), (z, ref.z))):
        why.append(f"{positions:,} positions, not Table II's 4,096 (±75 mm, step 10 mm)")
    steps = np.degrees(np.concatenate([np.diff(a) for a in (grid.rx, grid.ry, grid.rz)]))
    if steps.size and not np.allclose(steps, 5.0, rtol=0.0, atol=1e-6):
        why.append(f"rotation steps of {float(np.max(steps)):.4g}° (Table II: 5°)")
    return "; ".join(why)


def _unlike_paper(s, grid) -> str:
    """"" when device summary ``s``'s Table III rows are over the paper's poses: Table
    II's positions and orientations in steps of 5° over the range of the paper's column
    (±20° for L = 6, ±30° for L = 8, Sec. III-B-3 and Table III's note); else what
    differs.  QA 2026-11-29: an Octopod row over ±20° stood beside the paper's ±30°
    column, and a grid of 8 positions at a 150 mm step was called "the Table II
    positions", both without a word."""
    if not s.get("paper_column"):
        return ""
    return _unlike_grid(grid, s["positions"], s["rotation_deg"],
                        30.0 if s["L"] == 8 else 20.0, "the paper's column:")


def _unlike_paper_table4(s, grid) -> str:
    """"" when device summary ``s``'s Table IV row (GII, σmin, σmax over the inner
    orientations, ``s["isotropy"]["rotation_deg"]``) is over the paper's poses: Table
    II's grid, ±20° in steps of 5° (Kühne et al. Sec. III-B-2, Table II) for every
    device; else what differs.  QA 23: the Table IV rows said "yes" on the coarse grid
    while the Table III rows beside them said "no".  Also for a paper device without a
    Table IV value (Ergin's, the HEXA: QA 25a F6, their rows said "yes" on the grid that
    made the others' "no"); "" for a device that is not the paper's."""
    if not s.get("paper_column"):
        return ""
    return _unlike_grid(grid, s["positions"], s["isotropy"]["rotation_deg"], 20.0,
                        "Table IV: Table II's")


def markdown_tables(summaries, *, sensitivity="slice", certified=None) -> str:
    """Table III and Table IV analogues (markdown), one row per quantity and device.
    A row whose extremes leave unreachable grid poses out says so in "same def." (never
    "yes") and in its reason."""
    lines = ["Table III analogue: min (max) over the workspace grid of each worst-case "
             "output capability and maximum sensitivity; ours beside Kühne et al. Table "
             "III, ratio = ours / paper.  \"same def.\": our quantity has the paper's "
             "definition (yes/no; the definitions are listed below the table).  The last "
             "column names the reason for any gap beyond 2×.", "",
             "| Output capability | Kinematics (rotation) | same def. | ours min (max) | "
             "paper min (max) | ratio min (max) | reason for a gap beyond 2× |",
             "|---|---|---|---|---|---|---|"]
    for q, label, unit in _ROWS:
        same = row_definition(q, sensitivity)[0]
        for s in summaries:
            e = s["table"][q]
            ours = f"{_f(e['min'])} ({_f(e['max'])})"
            if "paper_min" in e:
                paper = f"{_f(e['paper_min'])} ({_f(e['paper_max'])})"
                ratio = f"{_ratio(e['ratio_min'])} ({_ratio(e['ratio_max'])})"
                why = [f"min: {r}" for r in [row_reason(q, "min", s, certified)] if r] + \
                    [f"max: {r}" for r in [row_reason(q, "max", s, certified)] if r]
                reason = "; ".join(why) or "—"
            else:
                paper = ratio = reason = "—"
            if _subset(e):
                reason = f"{_subset(e)}, the unreachable ones left out" + (
                    "" if reason == "—" else f"; {reason}")
            cell = _same(same, e)
            if s.get("unlike_paper") and "paper_min" in e:
                cell = (f"no: {s['unlike_paper']}; ratio not like for like" if cell == same
                        else f"{cell}; {s['unlike_paper']}")
            lines.append(f"| {label} [{_unit(q, unit, s)}] | {s['label']} "
                         f"(±{s['rotation_deg']:.0f}°) | "
                         f"{cell} | {ours} | {paper} | {ratio} | {reason} |")
    limits = _limits_text(summaries)
    lines += ["", "Definitions: " + "; ".join(
        f"{lab}: {row_definition(q, sensitivity, limits)[1]}" for q, lab, _ in _ROWS)]
    rots = sorted({f"±{s['isotropy']['rotation_deg']:.0f}°" for s in summaries})
    su = _common_unit(summaries)
    lines += ["", "Table IV analogue: GII = min σmin / max σmax of ST⁻¹Jᵀ over the "
              f"orientations ({', '.join(rots)}; the paper: Table II's ±20°), same "
              "definition as the paper (yes; which matrix ST "
              "scales is not printed: our reading ST⁻¹Jᵀ, distkin.indices.isotropy); ours "
              "beside Kühne et al. Table IV.  The GII is dimensionless; σmin and σmax are "
              "per unit of actuator effort (ST⁻¹Jᵀ maps it to the wrench in units of ST): "
              + (f"{su}" if su else "their unit by device, in the first column")
              + " (the paper prints none).", "",
              f"| Kinematics | same def. | GII ours | paper | ratio | σmin ours [{su or 'unit'}] "
              f"| paper | ratio | σmax ours [{su or 'unit'}] | paper | ratio | reason for a gap "
              "beyond 2× |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for s in summaries:
        i = s["isotropy"]
        gaps = [k for k in ("gii", "sigma_min", "sigma_max")
                if i.get(f"ratio_{k}") is not None and not 0.5 <= i[f"ratio_{k}"] <= 2]
        reason = "—"
        if gaps:
            reason = ("σ depend on l3 and the Fig. 2 reading (not printed) and on which "
                      "matrix ST scales (readings below); ")
            if "sigma_max" in gaps:
                reason += "no unit-consistent reading with the paper's ST reaches its σmax"
        if _subset(i):
            reason = f"{_subset(i)}, the unreachable ones left out" + (
                "" if reason == "—" else f"; {reason}")
        cell = _same("yes", i)
        if i.get("unlike_paper"):
            tail = ("ratio not like for like" if i.get("paper_gii") is not None
                    else "the paper prints no Table IV value for it")
            cell = (f"no: {i['unlike_paper']}; {tail}" if cell == "yes"
                    else f"{cell}; {i['unlike_paper']}")
        label = s["label"] if su else f"{s['label']} (σ in {_sigma_unit(s)})"
        row = [label, cell, _f(i["gii"]), _f(i.get("paper_gii")),
               _ratio(i.get("ratio_gii")), _f(i["sigma_min"]), _f(i.get("paper_sigma_min")),
               _ratio(i.get("ratio_sigma_min")), _f(i["sigma_max"]),
               _f(i.get("paper_sigma_max")), _ratio(i.get("ratio_sigma_max")), reason]
        lines.append("| " + " | ".join(row) + " |")
    part = [f"{s['label']} {_subset(s['isotropy'])}" for s in summaries
            if _subset(s["isotropy"])]
    lines += ["", f"Readings of Stocco's scaling (σmin / σmax over the {', '.join(rots)} "
              "orientations" + (f", {'; '.join(part)}" if part else "") + "; "
              "the GII is the same for the readings that differ by a factor or an "
              "inverse); the paper's Table IV in the last column.  Units of σ per reading: "
              + "; ".join(f"{text}: " + (_common_unit(summaries, r) or "by device ("
                                         + ", ".join(f"{s['label']} {_sigma_unit(s, r)}"
                                                     for s in summaries) + ")")
                          for r, text in SCALING_READINGS.items()) + ".", "",
              "| Kinematics | " + " | ".join(SCALING_READINGS.values()) + " | paper |",
              "|---|" + "---|" * (len(SCALING_READINGS) + 1)]
    for s in summaries:
        rd = s["isotropy"]["readings"]
        cells = [f"{_f(rd[r]['sigma_min'])} / {_f(rd[r]['sigma_max'])}" if r in rd else "—"
                 for r in SCALING_READINGS]
        p = PAPER_TABLE4.get(s["paper_column"])
        cells.append(f"{p[1]} / {p[2]}" if p else "—")
        lines.append(f"| {s['label']} | " + " | ".join(cells) + " |")
    return "\n".join(lines)
