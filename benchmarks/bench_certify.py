"""Certified singularity-free workspace (issue 9): cost of one box per enclosure form,
boxes needed per form on the Fig. 3 cube, the Fig. 3 analogues, the Octopod's and the
Octo's 6-D workspaces at ±20° and ±30°, and an untuned map of Table I's (β, γ, l2).

The Fig. 3 analogues' certificates are stored with the numbers (``fig3_figures``,
:mod:`benchmarks.plot_certify`) and the figures drawn from them by :func:`plot`, at the
end of the run and by ``python -m benchmarks --replot certify``."""

from __future__ import annotations

import math
import os
import time

import numpy as np

from .harness import fmt_time, interleaved, ratio_table
from .plot_certify import RECORDS, certificate_record, figure_name, plot

__all__ = ["TITLE", "DEFAULT", "run", "plot"]

TITLE = "Certified workspace: interval branch-and-prune (centred forms, Fig. 3, 6-D Octo)"
DEFAULT = False          # 339 s on 2 cores in BENCHMARKS.md's run (33): `python -m benchmarks certify`

_H = 0.075
_FORMS = ("quadratic", "affine", "centred", "plain")


def _cube(mech, rot=0.0):
    lo = np.array([-_H, -_H, mech.z0 - _H, -rot, -rot, -rot])
    hi = np.array([_H, _H, mech.z0 + _H, rot, rot, rot])
    return lo, hi


def _fractions(r, vary):
    v = np.prod((r["hi"] - r["lo"])[:, vary], axis=1)
    tot = v.sum()
    return {name: float(v[r["status"] == code].sum() / tot)
            for code, name in ((1, "regular"), (2, "singular"), (0, "undecided"),
                               (3, "unreachable"))}


def _per_box_section(data):
    from distkin.certify.boxes import certify_box
    from distkin.mechanisms import preset
    cases = {
        "hexa (radial reading), 3-D box ±10 mm": (preset("hexa", layout="radial"),
                                                  np.array([0.02, -0.01, 0.31, 0, 0, 0]),
                                                  np.array([0.01] * 3 + [0] * 3)),
        "octo, 6-D box ±10 mm ±2.5°": (preset("octo"), np.array([0.02, -0.01, 0.31, 0.05,
                                                                 -0.03, 0.02]),
                                       np.array([0.01] * 3 + [math.radians(2.5)] * 3)),
    }
    lines = ["### Cost of one box", "",
             "One call of `certify_box` (enclosure, reach, Jq and rank certificates; "
             "interleaved medians, 9 rounds).  The verdict of each form on the same box is "
             "given: a form that cannot certify a box pays with splits (next table).", ""]
    data["per_box"] = {}
    for label, (mech, c, h) in cases.items():
        ks = mech.kernels("arb")
        comp = {f: (lambda f=f: certify_box(mech, ks, c - h, c + h, form=f)) for f in _FORMS}
        med = interleaved(comp, rounds=9)
        verdicts = {f: certify_box(mech, ks, c - h, c + h, form=f) for f in _FORMS}
        lines += [f"**{label}**", "", ratio_table(med, "plain", per="box"), "",
                  "| form | boxes/s (1 process) | verdict | contraction bound |",
                  "|---|---|---|---|"]
        for f in _FORMS:
            v = verdicts[f]
            st = {0: f"undecided ({v.reason})", 1: "regular", 2: "singular",
                  3: "unreachable"}[v.status]
            lines.append(f"| {f} | {1 / med[f]:.0f} | {st} | {v.contraction:.3g} |")
        lines.append("")
        data["per_box"][label] = {f: {"seconds": med[f], "status": int(verdicts[f].status),
                                      "contraction": verdicts[f].contraction} for f in _FORMS}
    return "\n".join(lines)


def _forms_section(data):
    from distkin.certify.boxes import branch_and_prune
    from distkin.mechanisms import preset
    lines = ["### Boxes needed per form", "",
             "Branch-and-prune of the 150 mm cube at zero rotation (the HEXA under the "
             "radial reading of Fig. 2, `preset('hexa', layout='radial')`, which has "
             "singular regions there like the paper's Fig. 3; resolution "
             "150/16 = 9.4 mm, one process) and of a 6-D corner of the Octo's ±20° region "
             "(x, y, z ∈ [−75, −37.5] mm, z about z0, rx, ry, rz ∈ [−20°, −10°], resolution "
             "9.4 mm / 2.5°).  The plain interval form and the centred (mean-value) form "
             "with interval derivative enclosures leave most of the volume undecided at the "
             "resolution; the Taylor forms certify it.", "",
             "| region | form | boxes evaluated | leaves | regular | singular | undecided | "
             "time |", "|---|---|---|---|---|---|---|---|"]
    data["forms"] = {}
    hexa = preset("hexa", layout="radial")
    octo = preset("octo")
    a = math.radians(20)
    lo6 = np.array([-_H, -_H, octo.z0 - _H, -a, -a, -a])
    hi6 = lo6 + np.array([_H / 2] * 3 + [a / 2] * 3)
    regions = {"hexa cube": (hexa, *_cube(hexa), [0.15 / 16] * 3 + [1] * 3, [0, 1, 2]),
               "octo 6-D corner": (octo, lo6, hi6, [0.15 / 16] * 3 + [2 * a / 16] * 3,
                                   list(range(6)))}
    for name, (mech, lo, hi, minw, vary) in regions.items():
        for f in _FORMS:
            t0 = time.perf_counter()
            r = branch_and_prune(mech, lo, hi, minw, form=f, max_boxes=20_000)
            sec = time.perf_counter() - t0
            fr = _fractions(r, vary)
            lines.append(f"| {name} | {f} | {int(r['evaluated'])} | {len(r['status'])} | "
                         f"{100 * fr['regular']:.1f} % | {100 * fr['singular']:.1f} % | "
                         f"{100 * fr['undecided']:.1f} % | {sec:.1f} s |")
            data["forms"][f"{name}/{f}"] = {"evaluated": int(r["evaluated"]),
                                            "leaves": len(r["status"]), "seconds": sec, **fr}
    lines += ["", "Budget: 20,000 box evaluations per run (boxes left over count as "
              "undecided)."]
    return "\n".join(lines)


def _fig3_section(data):
    from distkin.certify.workspace import certify_workspace
    from distkin.runstore import local_executor
    from distkin.mechanisms import preset
    lines = ["### Fig. 3 analogue: the 150 mm cube at zero rotation", "",
             "Quadratic Taylor form (`quadratic64`, the default of `certify_workspace`), resolution 9.4 mm, 2 worker processes.  Kühne et al. "
             "(Fig. 3, Sec. III-B-1): Hunt-type free of singularities, HEXA with singular "
             "regions, Ergin's device with singularities throughout its workspace.  The "
             "presets use the tangential reading of Fig. 2 (presets.py); the last row is "
             "the HEXA under the radial reading (the reading before issue 15).", "",
             "| preset | regular | singular | undecided | σmin(Jx) ≥ (certified) | "
             "the boxes' own bound | tightening | "
             "det signs | boxes | wall time | figure |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    data["fig3"], data[RECORDS] = {}, {}
    with local_executor(2) as ex:
        for name in ("hunt", "hexa", "ergin", "hexa, radial reading"):
            mech = preset("hexa", layout="radial") if "radial" in name else preset(name)
            lo, hi = _cube(mech)
            cert = certify_workspace(mech, lo, hi, [0.15 / 16] * 3 + [1] * 3, executor=ex)
            s = cert.summary()
            # the figure is drawn from this record by plot() (the run's end, --replot)
            data[RECORDS][name] = certificate_record(cert)
            lines.append(f"| {name} | {100 * s['regular_fraction']:.1f} % | "
                         f"{100 * s['singular_fraction']:.1f} % | "
                         f"{100 * s['undecided_fraction']:.1f} % | {_sig(s['sigma_lower_min'])} | "
                         f"{_sig(s['sigma_lower_min_boxes'])} | {_tightening(s)} | "
                         f"{s.get('det_signs')} | {s['boxes_evaluated']} | "
                         f"{s['wall_seconds']:.1f} s | [png](benchmarks/figures/{figure_name(name)}) |")
            data["fig3"][name] = {k: v for k, v in s.items()}
    lines += ["", "Our `hexa` (γ = 30°) and `ergin` (β = 10°, γ = 13.18°, l2 = 25.6 mm) "
              "presets (the paper prints none of their parameters) are certified free over "
              "the cube at zero rotation under the presets' reading, unlike the paper's "
              "Fig. 3 (our ergin preset has singularities inside its ±20° box, as the "
              "paper's Table III says); the study report marks comparisons with them "
              "\"not comparable\".  See the design map below for where singular regions "
              "appear in Table I's ranges."]
    return "\n".join(lines)


def _sig(v) -> str:
    return "—" if v is None else f"{v:.3g}"


def _tightening(s) -> str:
    t = s.get("sigma_tightening")
    return "—" if t is None else f"{t['boxes']} boxes, {t['seconds']:.1f} s"


_SIX_D_RUNS = (("octopod", 20, 8, 8), ("octo", 20, 8, 8), ("octo", 30, 6, 6))


def _load() -> float:
    return os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")


def _six_d_section(data, form="quadratic64", runs=_SIX_D_RUNS):
    from distkin.certify.workspace import certify_workspace
    from distkin.runstore import local_executor
    from distkin.mechanisms import preset
    lines = ["### 6-D workspaces: the 150 mm cube × rotations about every axis", "",
             f"Form `{form}` (second-order Taylor models with binary64 coefficients and "
             "every rounding in the remainder, boxes evaluated 256 at a time, the arb "
             "`quadratic` form on the boxes it leaves undecided at the resolution: "
             "`distkin.certify.fptaylor`, `distkin.certify.batch`), 2 worker processes, 64 "
             "resumable chunks.  Volumes in m³·rad³ (x, y, z in m times rx, ry, rz in rad); "
             "fractions of the region.  Resolution 150 mm/n and (2 × rotation)/n.  Boxes "
             "per wall second: all boxes evaluated over the wall time of the run (both "
             "processes together); per process: over the sum of the chunks' own times.  "
             "Load: the 1-minute load average before and after the row (2 cores).", "",
             "| device | rotations | n | regular | singular | undecided | unreachable | "
             "undecided volume | σmin(Jx) ≥ | the boxes' own bound | tightening | "
             "sampled σmin | boxes | "
             "boxes per wall second | boxes/s per process | wall time | load |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    data["six_d"] = {}
    with local_executor(2) as ex:
        for name, deg, dp, dr in runs:
            mech = preset(name)
            a = math.radians(deg)
            lo, hi = _cube(mech, a)
            load0 = _load()
            cert = certify_workspace(mech, lo, hi, [0.15 / dp] * 3 + [2 * a / dr] * 3,
                                     executor=ex, form=form)
            load1 = _load()
            s = cert.summary()
            sig = f"{_sig(s['sigma_lower_min'])} | {_sig(s['sigma_lower_min_boxes'])} | " \
                  f"{_tightening(s)}"
            smp = _sampled_sigma(cert)
            lines.append(f"| {name} | ±{deg}° | {dp} | {100 * s['regular_fraction']:.2f} % | "
                         f"{100 * s['singular_fraction']:.2f} % | "
                         f"{100 * s['undecided_fraction']:.2f} % | "
                         f"{100 * s['unreachable_fraction']:.2f} % | "
                         f"{s['undecided_volume']:.3g} m³·rad³ | {sig} | {smp:.3g} | "
                         f"{s['boxes_evaluated']} | {s['boxes_per_second']:.0f} | "
                         f"{s['boxes_per_process_second']:.0f} | "
                         f"{s['wall_seconds']:.0f} s | {load0:.2f} / {load1:.2f} |")
            data["six_d"][f"{name}±{deg}"] = dict(s, resolution=dp, form=form,
                                                  load=(load0, load1), sampled_sigma=smp)
    lines += ["", "The Octopod row is the time to certify its dexterous workspace at ±20° "
              "(the desired workspace of Sec. II-A: the 150 mm cube with ±20° about every "
              "axis); the wall time is the classification's.  σmin(Jx) ≥ is the certified "
              "lower bound over every regular box (Jx force rows dimensionless, moment "
              "rows in m).  The rank test's own bound of a box, (1 − c)/(√6 max v "
              "‖D⁻¹Y‖), falls to zero as the box's contraction c nears 1, and the "
              "classification stops splitting a box as soon as c < 1, so the minimum over "
              "its boxes (next column) is set by a few boxes certified with c just below 1 "
              "and says little about the device.  `certify_workspace` then bisects the "
              "boxes with the weakest bounds and certifies the halves again, weakest first "
              "(`distkin.certify.tighten`; a half keeps the larger of its own bound and its "
              "box's; 4096 boxes at most, or until the bound rises by less than 1 % in "
              "four rounds: the tightening column).  Sampled σmin: the smallest float "
              "σmin(Jx) at 20,000 random poses of the regular part of the region and 500 of "
              "the final box with "
              "the weakest bound: the certified bound must stay below it (in this run: "
              + ("it does in every row" if all(
                  v["sigma_lower_min"] is None or v["sigma_lower_min"] <= v["sampled_sigma"]
                  for v in data["six_d"].values()) else "**it does not in every row**")
              + "), and the ratio says how much the bound gives away."]
    return "\n".join(lines)


def _sampled_sigma(cert, n=500, n_region=20_000):
    """The smallest float σmin(Jx) at ``n_region`` random poses of the regular part of
    the region (uniform: boxes drawn by volume) and ``n`` of the regular box with the
    weakest certified bound (the final boxes of the tightening when it ran); nan if
    there is no regular box."""
    reg = np.flatnonzero(cert.status == 1)
    if reg.size == 0:
        return float("nan")
    rng = np.random.default_rng(0)
    tb = cert.sigma_bound
    if tb is not None:
        b = int(np.argmin(tb.sigma))
        blo, bhi = tb.lo[b], tb.hi[b]
    else:
        b = reg[np.argmin(cert.sigma_lower[reg])]
        blo, bhi = cert.lo[b], cert.hi[b]
    P = blo + rng.uniform(size=(n, 6)) * (bhi - blo)
    vol = cert.volumes()[reg]
    pick = reg[rng.choice(reg.size, size=n_region, p=vol / vol.sum())]
    X = cert.lo[pick] + rng.uniform(size=(n_region, 6)) * (cert.hi[pick] - cert.lo[pick])
    P = np.concatenate([P, X])
    return float(np.linalg.svd(cert.mechanism.jq_jx(P)[1], compute_uv=False)[:, -1].min())


def _routes_task(spec):
    from distkin.certify.batch import branch_and_prune_batched
    from distkin.certify.boxes import branch_and_prune
    from distkin.mechanisms import preset
    name, lo, hi, minw, form = spec
    t0 = time.perf_counter()
    r = (branch_and_prune_batched(preset(name), lo, hi, minw) if form == "quadratic64"
         else branch_and_prune(preset(name), lo, hi, minw, form=form))
    return form, int(r["evaluated"]), _fractions(r, list(range(6))), time.perf_counter() - t0


def _routes_section(data, chunks=(0, 21, 42, 63)):
    """The arb and binary64 routes of the quadratic form on the same chunks of the Octo's
    ±30° region, one process each, alternated."""
    from distkin.certify.workspace import initial_boxes
    from distkin.mechanisms import preset
    mech = preset("octo")
    a = math.radians(30)
    lo, hi = _cube(mech, a)
    minw = np.array([0.15 / 6] * 3 + [2 * a / 6] * 3)
    boxes = initial_boxes(lo, hi, 2)
    rows = {f: [0, 0.0, 0.0] for f in ("quadratic", "quadratic64")}
    undecided = {f: 0.0 for f in rows}
    load0 = _load()
    for i in chunks:
        for f in ("quadratic64", "quadratic") if i % 2 else ("quadratic", "quadratic64"):
            _, n, fr, sec = _routes_task(("octo", *boxes[i], minw, f))
            rows[f][0] += n
            rows[f][1] += sec
            undecided[f] = max(undecided[f], fr["undecided"])
    load1 = _load()
    ratio = (rows["quadratic"][1] / rows["quadratic"][0]) / (
        rows["quadratic64"][1] / rows["quadratic64"][0])
    lines = ["### The quadratic form in arb and in binary64, same chunks", "",
             f"Chunks {', '.join(map(str, chunks))} of the 64 of the Octo's 150 mm × ±30° "
             "region (resolution 25 mm / 10°), branch-and-prune in one process, the two "
             f"routes alternated; load average {load0:.2f} before, {load1:.2f} after (2 "
             "cores).  `quadratic`: `distkin.certify.taylor` models in python-flint arb, "
             "one box at a time; `quadratic64`: the same models with binary64 "
             "coefficients, up to 256 boxes per numpy call.", "",
             "| route | boxes evaluated | time | per box | boxes/s | largest undecided share |",
             "|---|---|---|---|---|---|"]
    for f, (n, sec, _) in rows.items():
        lines.append(f"| {f} | {n} | {sec:.1f} s | {fmt_time(sec / n)} | {n / sec:.0f} | "
                     f"{100 * undecided[f]:.1f} % |")
    lines += ["", f"Per box evaluated, the binary64 route is {ratio:.1f}× faster; it "
              "evaluates more boxes where its enclosures are wider (no Chebyshev "
              "enclosure of sqrt and 1/x, see `distkin.certify.batch`)."]
    data["routes"] = {"chunks": list(chunks), "load": (load0, load1), "ratio_per_box": ratio,
                      **{f: {"evaluated": n, "seconds": sec} for f, (n, sec, _) in rows.items()}}
    return "\n".join(lines)


def _design_task(spec):
    from distkin.certify.boxes import branch_and_prune
    from distkin.mechanisms import preset
    beta, gamma, l2 = spec
    mech = preset("hunt", beta=math.radians(beta), gamma=math.radians(gamma), l2=l2 * 1e-3)
    lo, hi = _cube(mech)
    t0 = time.perf_counter()
    r = branch_and_prune(mech, lo, hi, [0.15 / 8] * 3 + [1] * 3)
    return spec, _fractions(r, [0, 1, 2]), int(np.sum(r["status"] == 2)), \
        time.perf_counter() - t0


def _design_section(data):
    from distkin.runstore import local_executor
    betas, gammas, l2s = (0, 10, 20, 30), (0, 10, 20, 30), (0, 15, 30)
    specs = [(b, g, l) for l in l2s for b in betas for g in gammas]
    t0 = time.perf_counter()
    with local_executor(2) as ex:
        res = list(ex.map(_design_task, specs))
    wall = time.perf_counter() - t0
    lines = ["### Where singular regions appear in Table I's ranges (untuned)", "",
             "Each (β, γ, l2) of Table I's grid (ld = 20 mm, l3 = 349.7 mm − l2, the presets' "
             "tangential reading of `distkin.mechanisms.presets`), the 150 mm cube at zero "
             "rotation, quadratic "
             "form, resolution 18.75 mm.  Cell: **free** (all certified regular), "
             "**S n** (n boxes certified singular; the percentage is the undecided volume), "
             "or the undecided volume alone.  Derivations of the kernels for each design "
             f"are included in the wall time, {wall:.0f} s on 2 processes.", ""]
    data["design_map"] = {}
    by = {s: (fr, ns) for s, fr, ns, _ in res}
    for l in l2s:
        lines += [f"l2 = {l} mm:", "", "| β \\ γ | " + " | ".join(f"{g}°" for g in gammas)
                  + " |", "|---" * (len(gammas) + 1) + "|"]
        for b in betas:
            cells = []
            for g in gammas:
                fr, ns = by[(b, g, l)]
                if fr["regular"] == 1.0:
                    cells.append("free")
                elif ns:
                    cells.append(f"S {ns} ({100 * fr['undecided']:.0f} %)")
                else:
                    cells.append(f"undecided {100 * fr['undecided']:.0f} %")
                data["design_map"][f"beta={b},gamma={g},l2={l}"] = {**fr, "singular_boxes": ns}
            lines.append(f"| {b}° | " + " | ".join(cells) + " |")
        lines.append("")
    return "\n".join(lines)


def run():
    data = {}
    t0 = time.perf_counter()
    parts = [_per_box_section(data), _forms_section(data), _fig3_section(data),
             _six_d_section(data), _design_section(data)]
    data["total_seconds"] = time.perf_counter() - t0
    plot(data)
    parts.append(f"Total benchmark time {fmt_time(data['total_seconds'])}.")
    return "\n\n".join(parts) + "\n", data
