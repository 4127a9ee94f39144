"""Octahedral forward kinematics: the three tiers, single and batched, against generic
baselines that do not use the octic (Rojas et al., ICRA 2012, Sec. III and VI).

Problem: the Griffis-Duffy example of Sec. VI (6 real roots, 12 poses) and, for the
batched run, 2000 leg sets around it (legs x (1 + 1% noise), seeded).

Baselines:

* ``scan (no octic)``: the paper's trilateration sequence as a 1-D problem in s15: the
  leg-5 residual of the four (P4, P6) branches sampled at 400 points of the feasible
  interval, sign changes refined by bisection (40 steps);
* ``9-coordinate Newton (no octic)``: ``scipy.optimize.least_squares`` on the 9
  unknown coordinates of P4, P5, P6 (6 legs + 3 platform sides) from 48 random starts,
  distinct converged solutions kept.
"""

from __future__ import annotations

import numpy as np

from benchmarks.harness import fmt_time, interleaved

__all__ = ["TITLE", "DEFAULT", "run"]

TITLE = "Octahedral forward kinematics (octic) vs generic baselines"
DEFAULT = True

BASE = np.array([[0, 0, 0], [6, np.sqrt(108), 0], [12, 0, 0]])
PLAT = np.array([[0, 0, 0], [6, 0, 0], [3, np.sqrt(27), 0]])
LEGS = np.array([19.8, 18, 18, 17, 14.9, 17.8])
PAIRS = ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))


def _scan_baseline(base, plat, legs, samples=400, refine=40):
    """All assembly modes from a 1-D scan of s15 along the trilateration sequence."""
    from distkin.octahedral.assembly import trilaterate_masked
    from distkin.octahedral.closure import feasible_interval
    pts = np.vstack([base, plat])
    sides = np.array([np.sum((pts[i - 1] - pts[j - 1]) ** 2)
                      for i, j in ((1, 2), (1, 3), (2, 3), (4, 5), (4, 6), (5, 6))])
    l2 = legs ** 2
    lo, hi, _ = feasible_interval(sides, l2)
    if lo > hi:
        return []

    def residual(x):
        f5, o5, h5 = trilaterate_masked(base[0], base[1], base[2], x, l2[2], l2[3])
        P5 = f5 + o5
        f4, o4, h4 = trilaterate_masked(base[0], base[1], P5, l2[0], l2[1], sides[3])
        out = []
        for tau in (1, -1):
            P4 = f4 + tau * o4
            f6, o6, h6 = trilaterate_masked(base[0], P4, P5, l2[5], sides[4], sides[5])
            for rho in (1, -1):
                P6 = f6 + rho * o6
                r = np.sum((P6 - base[2]) ** 2, axis=-1) - l2[4]
                ok = (h5 >= 0) & (h4 >= 0) & (h6 >= 0)
                out.append(np.where(ok, r, np.nan))
        return np.stack(out)                                        # (4, M)

    xs = np.linspace(lo, hi, samples)
    R = residual(xs)
    roots = []
    for b in range(4):
        r = R[b]
        idx = np.flatnonzero(np.isfinite(r[:-1]) & np.isfinite(r[1:]) & (r[:-1] * r[1:] < 0))
        if idx.size == 0:
            continue
        a, c = xs[idx], xs[idx + 1]
        fa = r[idx]
        for _ in range(refine):
            m = 0.5 * (a + c)
            fm = residual(m)[b]
            left = np.sign(fm) == np.sign(fa)
            a, fa = np.where(left, m, a), np.where(left, fm, fa)
            c = np.where(left, c, m)
        roots.extend((0.5 * (a + c)).tolist())
    return sorted(roots)


def _newton9_baseline(base, plat, legs, starts=48, seed=0):
    """Distinct solutions of the 9 coordinate equations from random starts."""
    from scipy.optimize import least_squares
    rng = np.random.default_rng(seed)
    qs = np.array([np.sum((plat[i] - plat[j]) ** 2) for i, j in ((0, 1), (0, 2), (1, 2))])
    l2 = legs ** 2

    def f(z):
        P = {1: base[0], 2: base[1], 3: base[2], 4: z[0:3], 5: z[3:6], 6: z[6:9]}
        r = [np.sum((P[i] - P[j]) ** 2) - s for (i, j), s in zip(PAIRS, l2)]
        r += [np.sum((P[4] - P[5]) ** 2) - qs[0], np.sum((P[4] - P[6]) ** 2) - qs[1],
              np.sum((P[5] - P[6]) ** 2) - qs[2]]
        return np.array(r)
    size = np.abs(base).max() + legs.max()
    sols = []
    for _ in range(starts):
        z0 = rng.uniform(-size, size, 9)
        res = least_squares(f, z0, xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=200)
        if np.max(np.abs(res.fun)) < 1e-8 * size ** 2:
            if all(np.max(np.abs(res.x - s)) > 1e-6 * size for s in sols):
                sols.append(res.x)
    return sols


def _table(times: dict, baseline: str, per: str) -> str:
    wb, cb = times[baseline]
    lines = [f"| competitor | wall per {per} | CPU per {per} | wall ratio to {baseline} |",
             "|---|---|---|---|"]
    for n, (w, c) in times.items():
        lines.append(f"| {n} | {fmt_time(w)} | {fmt_time(c)} | {w / wb:.3g}× |")
    return "\n".join(lines)


def run():
    import os
    from distkin.octahedral import forward_kinematics, forward_kinematics_batched
    from distkin.octahedral.reference import GD_BASE, GD_LEGS, GD_PLATFORM
    rng = np.random.default_rng(1)
    n_batch = 2000
    batch = LEGS * (1 + 0.01 * rng.normal(size=(n_batch, 6)))
    # correctness of every competitor on the example, first
    found = {
        "fast (octic)": len(forward_kinematics(BASE, PLAT, LEGS)),
        "precise dps=30 (octic)": len(forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS,
                                                         method="precise")),
        "certified (octic)": len(forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS,
                                                    method="certified")),
        "scan (no octic)": 2 * len(_scan_baseline(BASE, PLAT, LEGS)),
        "9-coordinate Newton (no octic)": len(_newton9_baseline(BASE, PLAT, LEGS)),
    }
    load0 = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    single = interleaved({
        "fast (octic)": lambda: forward_kinematics(BASE, PLAT, LEGS, warn=False),
        "fast + conditioning estimate (default call)": lambda: forward_kinematics(
            BASE, PLAT, LEGS),
        "certified (octic)": lambda: forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS,
                                                        method="certified"),
        "precise dps=30 (octic)": lambda: forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS,
                                                             method="precise"),
        "scan (no octic)": lambda: _scan_baseline(BASE, PLAT, LEGS),
        "9-coordinate Newton (no octic)": lambda: _newton9_baseline(BASE, PLAT, LEGS),
    }, rounds=5, number=3, cpu=True)
    single.update(interleaved(
        {"fast (octic)": lambda: forward_kinematics(BASE, PLAT, LEGS, warn=False),
         "fast + conditioning estimate (default call)": lambda: forward_kinematics(
             BASE, PLAT, LEGS)},
        rounds=15, number=50, cpu=True))
    single["certified (octic)"] = interleaved(
        {"certified (octic)": lambda: forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS,
                                                         method="certified")},
        rounds=15, number=5, cpu=True)["certified (octic)"]
    batched = interleaved({
        "fast batched (octic)": lambda: forward_kinematics_batched(BASE, PLAT, batch),
        "fast single, looped (octic)": lambda: [forward_kinematics(BASE, PLAT, b, warn=False)
                                                for b in batch[:200]],
    }, rounds=7, number=1, cpu=True)
    load1 = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    per_solve = {"fast batched (octic)": tuple(v / n_batch for v in
                                               batched["fast batched (octic)"]),
                 "fast single, looped (octic)": tuple(v / 200 for v in
                                                      batched["fast single, looped (octic)"])}
    br = forward_kinematics_batched(BASE, PLAT, batch)
    targets = [
        ("fast, single solve", single["fast (octic)"], 100e-6),
        ("fast, batched, per solve", per_solve["fast batched (octic)"], 10e-6),
        ("certified, single solve", single["certified (octic)"], 5e-3),
    ]
    lines = [
        f"Load average (1 min) when measured: {load0:.1f} at the start, {load1:.1f} at the "
        f"end, on {os.cpu_count()} cores (the machine is shared). Wall times scale with the "
        "load; CPU time (`time.process_time` of this process) much less, and the targets "
        "are judged on it.",
        "",
        "Griffis-Duffy example (Sec. VI): 6 real roots of the octic, 12 poses. Poses found "
        "by each competitor:",
        "",
        "| competitor | poses found (of 12) |",
        "|---|---|",
        *[f"| {k} | {v} |" for k, v in found.items()],
        "",
        "Time per single solve (all poses), interleaved rounds, medians:",
        "",
        _table(single, "fast (octic)", "solve"),
        "",
        f"Batched: {n_batch} leg sets around the example (legs x (1 + 1% noise)); "
        f"{int(br.count.sum())} poses in all. Time per solve:",
        "",
        _table(per_solve, "fast batched (octic)", "solve"),
        "",
        "Targets (issue 3), judged on CPU time:",
        "",
        "| measure | wall (median) | CPU (median) | target | met (CPU)? |",
        "|---|---|---|---|---|",
        *[f"| {n} | {fmt_time(w)} | {fmt_time(c)} | {fmt_time(g)} | "
          f"{'yes' if c <= g else 'no, ' + format(c / g, '.2g') + '× the target'} |"
          for n, (w, c), g in targets],
        "",
        "Single solve: `fast (octic)` is the bare fast tier (`warn=False`), the one the "
        "target is judged on; the default call adds the conditioning estimate of "
        "`distkin.octahedral.conditioning` (its own eigenvalues and Horner passes in "
        "numpy) on top. Before this round of work the bare fast tier took ~245 µs and "
        "the batched one ~31 µs per solve on this machine.",
        "",
        "Where the fast tier's time goes (Griffis-Duffy, CPU time, stages timed in "
        "isolation on this shared machine; in the full call they take ~1.2-1.5x longer). "
        "Single solve (`fast_single`, CPython floats, 6 real roots, 12 poses): input "
        "checks in plain floats ~5 µs; the generated scalar kernel ~12 µs (~170 common "
        "subexpressions); LAPACK `dgeev` on the 8x8 companion matrix ~8 µs plus ~7 µs "
        "of handling (scaling, isolation test of each eigenvalue); per real root ~6-8 µs "
        "(two Newton steps on eq. (3) with its sign branches, the trilateration sequence "
        "of Sec. III with four (P4, P6) candidates, the triangle frame: ~250 float "
        "operations at 25-35 ns each); one numpy pass for the 12 poses ~35 µs (about 20 "
        "numpy calls of 1-3 µs each on tiny arrays: points, rotations, translations, leg "
        "residuals of both mirror poses); the 12 `Pose` and 6 `RootInfo` objects "
        "(frozen dataclasses, ~1 µs each) and the result ~20 µs. The floor of this "
        "design in CPython is therefore ~120 µs: kernel, eigenvalues, ~40 µs of "
        "per-root arithmetic and ~55 µs to build 12 poses as numpy arrays and objects "
        "cannot be cut much further without compiled code; the 100 µs target is not "
        "met. Batched (`fast.py`, `rootscan.py`): the companion eigenvalues "
        "(~8 µs per problem for `dgeev` alone) are replaced by a projective sign scan "
        "of the octic, rebuilt around the middle of the feasible interval from the "
        "quadratic parts of eq. (3) so that it keeps its digits, over 96 fixed angles "
        "(one matrix product for all problems, chunked by 256 rows so that OpenBLAS "
        "stays single-threaded: its threads cost ~7x the CPU time of this small "
        "product on the loaded 2-core machine), brackets refined by safeguarded Halley "
        "steps, "
        "pairs found at the minima of |O|, a float Sturm count as a check, then a "
        "polish on eq. (3) (or on the factored octic); the ~0.5 % of problems the scan "
        "doubts (9 % of random octahedra) go the eigenvalue way. Per problem, stages "
        "timed separately: kernel 0.7 µs, rebuilt octic 0.25 µs, scan 2.2 µs, Sturm "
        "check 0.3-0.6 µs, polish and classification 1.2 µs, the careful way 0.3-0.9 µs "
        "amortised (a few hundred µs of numpy calls on small arrays, whatever the "
        "number of doubted problems), trilateration sequence 1.0 µs, rotations and "
        "translations 0.8 µs, leg residuals 0.55 µs, the (N, 16, 3, 3) result arrays "
        "1.4 µs, sorting and glue the rest (the stages sum to ~10 µs; the whole call "
        "takes 10-11 µs on a quiet machine, 13-15 µs under a load of 2-3, while the "
        "previous eigenvalue code measured side by side takes 22-28 µs): no stage "
        "dominates, each is a few dozen numpy operations at ~0.5-1 ns per element, so "
        "the 10 µs target is at the edge of what this design gives; see the table for "
        "this run. A vectorised Aberth-Ehrlich iteration on (N, 8) complex "
        "arrays was tried earlier in place of the eigenvalues and was slower (10-13 "
        "iterations of ~1 µs per problem each). The scan baseline misses roots closer "
        "than its sample spacing and the 9-coordinate Newton baseline misses modes "
        "that no start reaches; neither can certify a count.",
    ]
    data = {"load_average": [load0, load1], "found": found,
            "single_s": {k: {"wall": w, "cpu": c} for k, (w, c) in single.items()},
            "per_solve_s": {k: {"wall": w, "cpu": c} for k, (w, c) in per_solve.items()},
            "targets": {n: {"wall_s": w, "cpu_s": c, "target_s": g}
                        for n, (w, c), g in targets}}
    return "\n".join(lines) + "\n", data
