"""Octahedral forward kinematics: accuracy against cost, for every tier and ``auto``.

Rojas, Borràs and Thomas, ICRA 2012, Sec. III and VI.  Three measurements in one run:

1. **correct digits against time.**  Problems: the Griffis-Duffy example (Sec. VI), 6
   random assembled octahedra (:func:`distkin.octahedral.hardset.easy_set`) and 4
   problems of the hard set near the Griffis-Duffy fold (2^-16 and 2^-32 from it), all
   as exact float data.  Reference: the precise tier at 200 digits, checked against the
   certified tier's enclosures (refined to 1e-60).  Correct digits of a result = -log10
   of the largest error of a pose point relative to the size of the mechanism, over
   all poses (0 when a pose is missing or extra); the tier's own native numbers (mpf,
   arb midpoints) are compared, so more than 16 digits can show;
2. **miscounted real roots on the hard set** (:func:`~distkin.octahedral.hardset.hard_set`:
   folds, the edge of assemblability, a flat configuration, extreme scales) and on the
   families of issue 14 (:func:`~distkin.octahedral.hardset.hard_families`:
   near-coplanar, near-line, clustered roots, at three scales): the share of problems
   whose assembly-mode or pose count differs from the certified one, for every tier;
   for the fast tier also how many of those it did not announce (no
   ``ConditioningWarning``), for the batched tier how many it did not flag
   (``BatchResult.trusted``);
3. **the cost of ``auto``** against the fast tier, on the easy set (200 random
   octahedra), the hard set and the families: CPU time per solve, and how often auto
   escalated -- and, from the same run, the previous implementation (main at
   :data:`BASELINE_REV`, a calibrated conditioning estimate instead of the proof),
   extracted with ``git archive``, against this tree, both timed by the same script in
   fresh subprocesses, alternated, on the same easy set.

The figure (``accuracy_fk.png``) is drawn by :func:`plot`
(:mod:`benchmarks.plot_accuracy`) from the numbers the run returns (``rows``,
``miscount``), at its end and by ``python -m benchmarks --replot accuracy``.
"""

from __future__ import annotations

import math
import time
import warnings
from pathlib import Path

import numpy as np

from benchmarks.harness import before_after, fmt_time, interleaved
from benchmarks.plot_accuracy import NAME as _FIG_NAME
from benchmarks.plot_accuracy import plot

__all__ = ["TITLE", "DEFAULT", "run", "plot", "BASELINE_REV"]

#: the implementation before issue 14 (the calibrated estimate), for "before" numbers
BASELINE_REV = "4f55e18"

TITLE = "Speed against accuracy: octahedral forward kinematics (fast, precise, certified, auto)"
DEFAULT = True
FIG = Path(__file__).resolve().parent / "figures" / _FIG_NAME

TIERS = {
    "fast (bare)": dict(method="fast", warn=False),
    "fast + proof": dict(method="fast"),
    "auto": dict(method="auto"),
    "precise dps=15": dict(method="precise", dps=15),
    "precise dps=20": dict(method="precise", dps=20),
    "precise dps=30": dict(method="precise", dps=30),
    "precise dps=50": dict(method="precise", dps=50),
    "precise dps=100": dict(method="precise", dps=100),
    "certified tol=1e-15": dict(method="certified", tol=1e-15),
    "certified tol=1e-30": dict(method="certified", tol=1e-30),
    "certified tol=1e-60": dict(method="certified", tol=1e-60),
}


def _solve(case, **kw):
    from distkin.octahedral import forward_kinematics
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return forward_kinematics(case.base, case.platform, list(case.legs), **kw)


def _native_points(pose):
    import mpmath
    if pose.native is None:
        return [[mpmath.mpf(float(v)) for v in row] for row in pose.points]
    out = []
    for row in pose.native["points"]:
        r = []
        for v in row:
            if hasattr(v, "mid") and callable(v.mid):          # arb ball
                r.append(mpmath.mpf(v.mid().str(80, radius=False)))
            else:
                r.append(mpmath.mpf(v))
        out.append(r)
    return out


def _digits(res, ref, size):
    """Correct digits of ``res`` against the reference result ``ref``."""
    import mpmath
    if len(res) != len(ref) or len(res.assembly_roots) != len(ref.assembly_roots):
        return 0.0
    worst = mpmath.mpf(0)
    used = set()
    for p in res.poses:
        cand = [(abs(p.s15 - q.s15), k) for k, q in enumerate(ref.poses)
                if q.side == p.side and k not in used]
        if not cand:
            return 0.0
        _, k = min(cand)
        used.add(k)
        a, b = _native_points(p), _native_points(ref.poses[k])
        for ra, rb in zip(a, b):
            for x, y in zip(ra, rb):
                worst = max(worst, abs(x - y))
    if worst == 0:
        return 200.0
    return float(min(200.0, -mpmath.log10(worst / size)))


def _digit_set():
    from distkin.octahedral.hardset import Case, easy_set, hard_set
    gd = Case("griffis-duffy", "easy",
              ((0.0, 0.0, 0.0), (6.0, math.sqrt(108.0), 0.0), (12.0, 0.0, 0.0)),
              ((0.0, 0.0, 0.0), (6.0, 0.0, 0.0), (3.0, math.sqrt(27.0), 0.0)),
              (19.8, 18.0, 18.0, 17.0, 14.9, 17.8), 0.0, 6, 6, 12)
    hard = [c for c in hard_set() if c.name.startswith("griffis-duffy leg5")
            and c.family == "fold" and c.name.split()[-1] in ("-2^-16", "+2^-16", "-2^-32",
                                                              "+2^-32")]
    return [gd] + list(easy_set()[:6]) + hard


def _curve():
    import mpmath
    cases = _digit_set()
    refs = []
    for c in cases:
        mpmath.mp.dps = 200
        ref = _solve(c, method="precise", dps=200)
        cert = _solve(c, method="certified", tol=1e-60)
        size = max(abs(v) for r in c.base for v in r)
        agree = _digits(cert, ref, size)
        refs.append((ref, size, agree))
    rows = {}
    for name, kw in TIERS.items():
        digits, times = [], []
        for c, (ref, size, _) in zip(cases, refs):
            t0 = time.process_time()
            res = _solve(c, **kw)
            times.append(time.process_time() - t0)
            digits.append(_digits(res, ref, size))
        rows[name] = {"digits": digits, "median_digits": float(np.median(digits)),
                      "min_digits": float(np.min(digits)),
                      "cpu_per_solve_median": float(np.median(times))}
    gd = cases[0]
    # the float64 tiers (sub-millisecond) and the others are timed in separate
    # interleaved groups, so that each fast measurement averages many warm calls
    quick = ("fast (bare)", "fast + proof", "auto")
    timing = interleaved({n: (lambda kw=TIERS[n]: _solve(gd, **kw)) for n in quick},
                         rounds=15, number=50, cpu=True)
    timing.update(interleaved({n: (lambda kw=kw: _solve(gd, **kw)) for n, kw in TIERS.items()
                               if n not in quick}, rounds=7, cpu=True))
    for n, (w, cpu) in timing.items():
        rows[n]["gd_wall"], rows[n]["gd_cpu"] = w, cpu
    return cases, refs, rows


def _miscounts(cases):
    """Per tier: problems whose counts differ from the certified truth; for fast also
    the silent ones, for batched the unflagged ones; errors raised (honest refusals)."""
    from distkin.errors import ConditioningWarning
    from distkin.octahedral import forward_kinematics, forward_kinematics_batched
    out = {}
    for name, kw in TIERS.items():
        if name.startswith("certified tol=1e-") and name != "certified tol=1e-15":
            continue
        wrong, err, silent = 0, 0, 0
        for c in cases:
            try:
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always", ConditioningWarning)
                    res = forward_kinematics(c.base, c.platform, list(c.legs), **kw)
            except Exception:                       # an honest refusal is not a miscount
                err += 1
                continue
            bad = (len(res.assembly_roots), len(res)) != (c.modes, c.poses)
            wrong += bad
            silent += bad and not caught and not (res.method == "auto")
        out[name] = {"wrong": wrong, "refused": err, "n": len(cases)}
        if name == "fast + proof":
            out[name]["silent"] = silent
    B = np.array([c.base for c in cases])
    Q = np.array([c.platform for c in cases])
    L = np.array([c.legs for c in cases])
    truth = np.array([c.poses for c in cases])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fast = forward_kinematics_batched(B, Q, L)
        auto = forward_kinematics_batched(B, Q, L, method="auto")
    bad = fast.count != truth
    out["batched fast"] = {"wrong": int(bad.sum()), "refused": 0, "n": len(cases),
                           "silent": int((bad & fast.trusted).sum()),
                           "flagged": int((~fast.trusted).sum())}
    out["batched auto"] = {"wrong": int((auto.count != truth).sum()), "refused": 0,
                           "n": len(cases)}
    return out


def _radii(cases):
    """What each root's radius says (``RootInfo.radius_kind``), against the certified
    roots of the same exact floats: per form (single default call, bare, batched) and
    kind, the roots, how many lie farther from the nearest certified root than their
    radius, the median factor by which those do, and the median radius relative to the
    root."""
    from distkin.octahedral import forward_kinematics, forward_kinematics_batched
    B, Q, L = (np.array([getattr(c, k) for c in cases]) for k in ("base", "platform", "legs"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        batch = forward_kinematics_batched(B, Q, L)
        seen = []
        for i, c in enumerate(cases):
            cert = np.array([r.value for r in forward_kinematics(
                c.base, c.platform, list(c.legs), method="certified").roots])
            for form, res in (("single", forward_kinematics(c.base, c.platform, list(c.legs))),
                              ("bare", forward_kinematics(c.base, c.platform, list(c.legs),
                                                          warn=False)),
                              ("batched", batch.result(i))):
                for r in res.roots:
                    d = np.min(np.abs(cert - r.value)) if cert.size else np.inf
                    seen.append((form, r.radius_kind, r.radius, d, abs(r.value)))
    out = {}
    for form in ("single", "bare", "batched"):
        for kind in ("proved", "estimate"):
            rows = [s for s in seen if s[:2] == (form, kind)]
            if not rows:
                continue
            over = [d / rad for _, _, rad, d, _ in rows if d > rad]
            out[f"{form}, {kind}"] = {
                "roots": len(rows), "exceeded": len(over),
                "median_factor": float(np.median(over)) if over else None,
                "median_relative": float(np.median([rad / max(x, 1e-300)
                                                    for _, _, rad, _, x in rows]))}
    return out


def _auto_cost():
    from distkin.octahedral.hardset import easy_set, hard_families, hard_set
    out = {}
    for label, cases in (("easy", easy_set()), ("hard", hard_set()),
                         ("families", hard_families())):
        res = {}
        for name in ("fast (bare)", "fast + proof", "auto"):
            kw = TIERS[name]
            best = np.inf
            for _ in range(3):
                t0 = time.process_time()
                for c in cases:
                    _solve(c, **kw)
                best = min(best, (time.process_time() - t0) / len(cases))
            res[name] = best
        res["escalated"] = sum(_solve(c, method="auto").tier != "fast" for c in cases)
        res["n"] = len(cases)
        out[label] = res
    return out


_BASELINE_SCRIPT = """
import json, time, warnings
import distkin
from distkin.octahedral import forward_kinematics
from distkin.octahedral.hardset import easy_set
cases = easy_set()
kws = {"fast (bare)": dict(warn=False), "fast + check": {}, "auto": dict(method="auto")}
out = {}
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    for name, kw in kws.items():
        for c in cases[:5]:
            forward_kinematics(c.base, c.platform, list(c.legs), **kw)   # compile
        best = float("inf")
        for _ in range(3):
            t0 = time.process_time()
            for c in cases:
                forward_kinematics(c.base, c.platform, list(c.legs), **kw)
            best = min(best, (time.process_time() - t0) / len(cases))
        out[name] = best
    out["escalated"] = sum(forward_kinematics(c.base, c.platform, list(c.legs),
                                              method="auto").tier != "fast" for c in cases)
out["tree"] = distkin.__file__
print(json.dumps(out))
"""


def _before_after(rounds: int = 3):
    """Auto's cost on the easy set before (main at :data:`BASELINE_REV`) and after
    (this tree), each measured by the same script in a fresh subprocess, the two
    alternated ``rounds`` times and the best of each kept (module docstring, item 3).
    Returns {"before": {...}, "after": {...}}, or None without git or the revision."""
    return before_after(_BASELINE_SCRIPT, BASELINE_REV, rounds=rounds, skip=("escalated",))


def run():
    import os
    from distkin.octahedral.hardset import hard_families, hard_set
    load0 = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    cases, refs, rows = _curve()
    miscount = {"hard set": _miscounts(hard_set()), "families": _miscounts(hard_families())}
    radii = _radii(hard_families())
    cost = _auto_cost()
    ba = _before_after()
    load1 = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    fig = FIG                       # drawn by plot(data) below, from the numbers
    agree = min(a for _, _, a in refs)
    lines = [
        f"Load average (1 min): {load0:.1f} at the start, {load1:.1f} at the end, on "
        f"{os.cpu_count()} cores (shared with other work: absolute times vary by 10-30 % "
        "from run to run, the ratios much less).",
        "",
        f"Digit set: {len(cases)} problems (Griffis-Duffy, 6 random octahedra, 4 near the "
        "Griffis-Duffy fold). Reference: precise tier at 200 digits; the certified tier "
        f"(enclosures refined to 1e-60) agrees with it to at least {agree:.0f} digits on "
        "every problem.",
        "",
        f"![accuracy against cost]({fig.relative_to(FIG.parents[2]).as_posix()})",
        "",
        "| tier | correct digits (median) | (min) | CPU per solve, digit set (median) "
        "| Griffis-Duffy: CPU per solve (interleaved) | ratio to fast (bare) |",
        "|---|---|---|---|---|---|",
    ]
    base = rows["fast (bare)"]["gd_cpu"]
    for name, r in rows.items():
        lines.append(f"| {name} | {r['median_digits']:.1f} | {r['min_digits']:.1f} | "
                     f"{fmt_time(r['cpu_per_solve_median'])} | {fmt_time(r['gd_cpu'])} | "
                     f"{r['gd_cpu'] / base:.3g}× |")
    lines += [
        "",
        "A minimum of 0 digits means a pose was missing or extra on some problem (a "
        "miscount). Float64 tiers cannot show more than ~16 digits. The precise tier "
        "works at `dps + 20` digits, so its poses carry about `dps + 17` correct digits "
        "(minus what the conditioning takes near the fold), while its decisions (is a "
        "root real, is a residual zero: thresholds of 10^(8-dps)) follow `dps` -- hence "
        "many correct digits and still miscounts at dps = 15-30. The certified tier's "
        "digits are set by its `tol`, and it is the cheapest way to many digits.",
        "",
        "Wrong counts (assembly modes or poses differ from the certified count) on the "
        "hard set (folds, edge of assemblability, flat pose, extreme scales) and on the "
        "families of issue 14 (`hard_families()`: near-coplanar, near-line, clustered "
        "roots, each at scales 1e-3, 1, 1e3). *Silent*: a wrong count the tier did not "
        "announce (fast: no `ConditioningWarning`; batched: `trusted` True):",
        "",
        "| tier | " + " | ".join(f"{k}: wrong | {k}: silent" for k in miscount)
        + " | refused (error raised) |",
        "|---|" + "---|---|" * len(miscount) + "---|",
    ]
    for name in miscount["hard set"]:
        cells = []
        for label, m in miscount.items():
            r = m[name]
            silent = r.get("silent")
            cells.append(f"{r['wrong']} of {r['n']} ({100 * r['wrong'] / r['n']:.1f} %)")
            cells.append("-" if silent is None else str(silent))
        refused = sum(m[name]["refused"] for m in miscount.values())
        lines.append(f"| {name} | " + " | ".join(cells) + f" | {refused} |")
    tot = lambda name, key: sum(m[name].get(key, 0) for m in miscount.values())  # noqa
    lines += [
        "",
        f"In all: auto wrong {tot('auto', 'wrong')} (single) and {tot('batched auto', 'wrong')} "
        f"(batched); the fast tier wrong {tot('fast + proof', 'wrong')} times, unannounced "
        f"{tot('fast + proof', 'silent')}; the batched tier wrong "
        f"{tot('batched fast', 'wrong')} times, unflagged {tot('batched fast', 'silent')} "
        f"(it flagged {miscount['hard set']['batched fast']['flagged']} problems of the "
        f"hard set and {miscount['families']['batched fast']['flagged']} of the families). "
        "The certified tier is the reference of the count (its real-root count is also "
        "checked against sympy's Sturm count in "
        "`tests/stability/test_stability_octahedral.py`).",
        "",
        "What the root radii say (`RootInfo.radius_kind`) on the families, against the "
        "certified roots of the same floats: a `proved` radius (the fast tier's proof, "
        "around the spurious roots outside the feasible interval too since step 8 of "
        "`distkin/octahedral/descartes.py`; `certified` in the certified tier) must never "
        "be exceeded; an `estimate` (the last Newton step: the bare tier, unproved "
        "answers, a root around which the proof found no radius) is not a bound, and this "
        "says how far from one it is (on an unproved answer a fast root may have no "
        "certified root near it at all):",
        "",
        "| form, kind | roots | farther than their radius | by (median factor) "
        "| radius / root (median) |",
        "|---|---|---|---|---|",
    ]
    for label, r in radii.items():
        f = "-" if r["median_factor"] is None else f"{r['median_factor']:.3g}"
        lines.append(f"| {label} | {r['roots']} | {r['exceeded']} | {f} | "
                     f"{r['median_relative']:.1e} |")
    lines += [
        "",
        "Cost of `method=\"auto\"` (best of 3 passes, CPU time per solve; `fast + proof` "
        "is the default fast call):",
        "",
        "| set | fast (bare) | fast + proof | auto | auto / fast (bare) "
        "| auto / fast + proof | escalated |",
        "|---|---|---|---|---|---|---|",
    ]
    for label, r in cost.items():
        lines.append(f"| {label} ({r['n']}) | {fmt_time(r['fast (bare)'])} | "
                     f"{fmt_time(r['fast + proof'])} | {fmt_time(r['auto'])} | "
                     f"{r['auto'] / r['fast (bare)']:.2f}× | "
                     f"{r['auto'] / r['fast + proof']:.2f}× | "
                     f"{r['escalated']} of {r['n']} |")
    if ba is not None:
        lines += [
            "",
            f"Before and after on the easy set, from this same run: main at "
            f"`{BASELINE_REV}` (the calibrated conditioning estimate, extracted with `git "
            "archive`) and this tree (the proof), each timed by the same script in a fresh "
            "process, alternated three times, best of each:",
            "",
            "| implementation | fast (bare) | fast + its check | auto | auto / fast (bare) "
            "| escalated |",
            "|---|---|---|---|---|---|",
        ]
        for label, what in (("before", f"before ({BASELINE_REV}, estimate)"),
                            ("after", "after (proof)")):
            b = ba[label]
            lines.append(f"| {what} | {fmt_time(b['fast (bare)'])} | "
                         f"{fmt_time(b['fast + check'])} | {fmt_time(b['auto'])} | "
                         f"{b['auto'] / b['fast (bare)']:.2f}× | {b['escalated']} of "
                         f"{cost['easy']['n']} |")
    lines += [
        "",
        "The fast tier's proof (`distkin/octahedral/descartes.py`: Descartes' rule in "
        "the Bernstein basis on the octic rebuilt from eq. (3)'s quadratic parts, with "
        "rigorous rounding bounds derived from the generated kernel's source) is part of "
        "the fast tier by default (it is what makes it warn); `warn=False` skips it. "
        "Auto escalates to the certified tier when the proof fails or a leg is "
        "reproduced worse than 1e-9 relative.",
    ]
    data = {"load_average": [load0, load1], "rows": rows, "miscount": miscount,
            "auto_cost": cost, "before_after": ba, "radii": radii,
            "reference_agreement_digits": agree}
    plot(data)
    return "\n".join(lines) + "\n", data
