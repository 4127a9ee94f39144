"""Speed against accuracy (issue 8): accuracy-cost curves of the worst-case capability
grid, the generated kernels near a singularity and the GII sampling.

1. Worst-case capabilities (Kühne et al., eqs. (5)-(15), Table III) of the Octopod over
   the orientation grid at 10°, 5° and 2.5° (±20°, Table II's range) on a 4³ position
   grid (±75 mm, 50 mm step: the corners and two inner planes of Table II's cube):
   how much each coarser grid overstates the minimum at each position, the time, a
   local refinement (zoomed grids, then scipy's bounded Powell search) and a Lipschitz
   estimate of a lower bound.
2. The generated HEXA Jacobian kernel (float64) against mpmath evaluation of the very
   sympy expression it was generated from (50 digits), approaching a parallel
   singularity: digits lost in J's entries, det J and σmin against the κ·eps
   prediction.
3. The global isotropy index (Sec. II-C-2): sampling density against the GII of the
   Octopod and the Table I design sweep with Stocco's culling, and their time.

Plots go to ``benchmarks/figures/`` (matplotlib, Agg), drawn by :func:`plot`
(:mod:`benchmarks.plot_tradeoffs`) from the numbers the run returns, at its end and by
``python -m benchmarks --replot tradeoffs``.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .harness import fmt_time, interleaved, ratio_table
from .plot_tradeoffs import plot

__all__ = ["TITLE", "DEFAULT", "run", "plot"]

TITLE = "Speed against accuracy: capability grids, kernels near singularity, GII sampling"
DEFAULT = True

EPS = float(np.finfo(float).eps)
_ROT_STEPS = (10.0, 5.0, 2.5)                 # degrees
_ROT = 20.0                                   # ± degrees (Table II)
_BATCH = 20000                                # poses per evaluate_poses call


def _link(name):
    return f"benchmarks/figures/{name}"


# ============================================================ 1. capability grids
def _evaluate(mech, poses):
    """The study's per-pose indices (:func:`distkin.indices.study.evaluate_poses`), in
    batches; every pose must be reachable (the Octopod reaches the whole Table II box)."""
    from distkin.indices.study import CAPABILITIES, evaluate_poses
    out = {c[0]: np.empty(len(poses)) for c in CAPABILITIES}
    for a in range(0, len(poses), _BATCH):
        ok, v = evaluate_poses(mech, poses[a:a + _BATCH])
        if not ok.all():
            raise RuntimeError("expected every pose of the box to be reachable")
        for c in CAPABILITIES:
            out[c[0]][a:a + _BATCH] = v[c[0]]
    return out


def _one_capability(mech, cap):
    """f(poses (N, 6)) -> (N,) one worst-case capability through the public API
    (output_generators + worst_case_output), for the refinement."""
    from distkin.indices.capability import output_generators, worst_case_output
    from distkin.indices.study import ACTUATORS
    M = np.diag(mech.cartesian_mass_matrix())
    lim = float(ACTUATORS[cap[4]])

    def f(poses):
        poses = np.atleast_2d(poses)
        J = mech.jacobian(poses)
        if cap[3] == "twist":
            G = np.linalg.pinv(J)
        elif cap[3] == "wrench":
            G = np.swapaxes(J, -1, -2)
        else:
            G = output_generators(J, mass=M)["acceleration"]
        return worst_case_output(G, -lim, lim, keep=cap[5])
    return f


def _zoom(f, position, starts, h, box, levels=4, n=5):
    """Local refinement of min over orientations at one position: a 5³ grid of half
    width w around the best point so far, w = h, h/2, h/4, ... (clipped to the box).
    Returns (value, orientation)."""
    best_v, best_o = np.inf, None
    for o0 in starts:
        c, w = np.array(o0, dtype=float), h
        v0 = float(f(np.r_[position, c])[0])
        for _ in range(levels):
            ax = [np.clip(c[i] + np.linspace(-w, w, n), -box, box) for i in range(3)]
            A, B, C = np.meshgrid(*ax, indexing="ij")
            O = np.stack([A.ravel(), B.ravel(), C.ravel()], axis=1)
            vals = f(np.hstack([np.broadcast_to(position, (len(O), 3)), O]))
            k = int(np.argmin(vals))
            if vals[k] < v0:
                v0, c = float(vals[k]), O[k]
            w /= 2
        if v0 < best_v:
            best_v, best_o = v0, c
    return best_v, best_o


def _polish(f, position, o0, box):
    """scipy's bounded Powell search over the orientation from ``o0``."""
    from scipy.optimize import minimize
    res = minimize(lambda o: float(f(np.r_[position, o])[0]), o0, method="Powell",
                   bounds=[(-box, box)] * 3, options={"xtol": 1e-6, "ftol": 1e-12,
                                                      "maxfev": 600})
    return float(res.fun), res.x


def _capability_device(name_, data):
    """Section 1 for one preset: grids at every orientation step, refinement,
    Lipschitz estimate, tables and plot; fills ``data[name_]``."""
    from distkin.indices.study import CAPABILITIES
    from distkin.indices.workspace import table2_grid
    from distkin.mechanisms import preset
    # the HEXA under the radial reading of Fig. 2 (layout="radial", the presets' reading
    # before issue 15): a device with singularities inside its workspace, like the
    # paper's HEXA (Fig. 3); the hexa preset's tangential reading has none at zero rotation
    mech = preset(name_, layout="radial") if name_ == "hexa" else preset(name_)
    box = math.radians(_ROT)
    grids = {s: table2_grid(step=0.050, rot_deg=_ROT, rot_step_deg=s) for s in _ROT_STEPS}
    npos = grids[_ROT_STEPS[0]].n_positions
    positions = grids[_ROT_STEPS[0]].positions()
    per_pos, argmin, seconds = {}, {}, {}
    fine = None
    for s, g in grids.items():
        poses = g.poses(np.arange(npos))
        t0 = time.perf_counter()
        vals = _evaluate(mech, poses)
        seconds[s] = time.perf_counter() - t0
        no = g.n_orientations
        per_pos[s] = {k: v.reshape(npos, no).min(axis=1) for k, v in vals.items()}
        argmin[s] = {k: v.reshape(npos, no).argmin(axis=1) for k, v in vals.items()}
        if s == _ROT_STEPS[-1]:
            fine = {k: v.reshape(npos, no) for k, v in vals.items()}
    gfine = grids[_ROT_STEPS[-1]]
    O_fine = gfine.orientations()
    h = math.radians(_ROT_STEPS[-1])
    nax = len(gfine.rx)
    # refinement: zoom from the two best fine-grid orientations at every position,
    # then scipy's bounded Powell at the position of the global minimum
    refined, lips, t_ref = {}, {}, 0.0
    polish = {}
    for cap in CAPABILITIES:
        name = cap[0]
        f = _one_capability(mech, cap)
        t0 = time.perf_counter()
        V = fine[name]
        best2 = np.argsort(V, axis=1)[:, :2]
        r = np.empty(npos)
        where = np.empty((npos, 3))
        for p in range(npos):
            r[p], where[p] = _zoom(f, positions[p], O_fine[best2[p]], h, box)
        ip = int(np.argmin(r))
        pv, po = _polish(f, positions[ip], where[ip], box)
        if pv < r[ip]:
            r[ip], where[ip] = pv, po
        t_ref += time.perf_counter() - t0
        polish[name] = {"position_mm": (positions[ip] - [0, 0, mech.z0]) * 1e3,
                        "orientation_deg": np.degrees(where[ip]), "value": r[ip]}
        # a refined value can only be >= the true minimum; the grid may not be below it
        refined[name] = np.minimum(r, per_pos[_ROT_STEPS[-1]][name])
        # Lipschitz estimate: largest finite-difference slope between neighbours of
        # the 2.5° grid, per position and axis (rad⁻¹ in the capability's unit)
        W = V.reshape(npos, nax, nax, nax)
        L = np.stack([np.max(np.abs(np.diff(W, axis=ax)), axis=(1, 2, 3)) / h
                      for ax in (1, 2, 3)], axis=1)
        lips[name] = L.sum(axis=1)
    sign_change = _det_sign_changes(mech, gfine, npos) if mech.L == 6 else None
    data[name_] = {"positions": npos, "rot_steps_deg": list(_ROT_STEPS),
                   "seconds": {str(k): v for k, v in seconds.items()},
                   "refine_seconds": t_ref}
    unit = {c[0]: c[2] for c in CAPABILITIES}
    label = {c[0]: c[1] for c in CAPABILITIES}
    # --- table 1: the reported (global) minima
    rows = ["| capability | " + " | ".join(f"min, {s:g}° grid" for s in _ROT_STEPS)
            + " | refined min (upper bound) | Lipschitz estimate of a lower bound (2.5°) |",
            "|---|" + "---|" * (len(_ROT_STEPS) + 2)]
    table = {}
    for cap in CAPABILITIES:
        n = cap[0]
        mins = [float(per_pos[s][n].min()) for s in _ROT_STEPS]
        ref = float(refined[n].min())
        lb_pos = per_pos[_ROT_STEPS[-1]][n] - (h / 2) * lips[n]
        lb = float(lb_pos.min())
        # consistency of the estimate: a refined value below it at some position
        # would prove the finite-difference Lipschitz constant too small there
        broken = int(np.sum(refined[n] < lb_pos - 1e-12 * np.abs(lb_pos)))
        table[n] = {"grid_min": dict(zip(map(str, _ROT_STEPS), mins)), "refined_min": ref,
                    "lipschitz_lower_estimate": lb, "lipschitz_violations": broken}
        cells = [f"{m:.4g} ({_excess(m, ref)})" for m in mins]
        rows.append(f"| {label[n]} ({unit[n]}) | " + " | ".join(cells)
                    + f" | {ref:.4g} | {lb:.4g} |")
    # --- table 2: where a coarser grid misses the per-position minimum
    miss_rows = ["| capability | " + " | ".join(
        f"{s:g}°: positions > 1 % high / worst miss" for s in _ROT_STEPS) + " |",
        "|---|" + "---|" * len(_ROT_STEPS)]
    misses = {}
    for cap in CAPABILITIES:
        n = cap[0]
        cells = []
        misses[n] = {}
        for s in _ROT_STEPS:
            over = per_pos[s][n] / refined[n] - 1
            k = int(np.argmax(over))
            pos_mm = (positions[k] - [0, 0, mech.z0]) * 1e3
            ob = float(argmin[s][n][k])
            cells.append(f"{int(np.sum(over > 0.01))}/{npos} / "
                         f"{_excess(per_pos[s][n][k], refined[n][k])} at "
                         f"({pos_mm[0]:+.0f}, {pos_mm[1]:+.0f}, {pos_mm[2]:+.0f}) mm")
            misses[n][str(s)] = {"count_over_1pct": int(np.sum(over > 0.01)),
                                 "worst_rel": float(over[k]), "worst_position_mm":
                                 pos_mm.tolist(), "grid_argmin": ob,
                                 "median_rel": float(np.median(over))}
        miss_rows.append(f"| {label[n]} | " + " | ".join(cells) + " |")
    data[name_]["table"] = table
    data[name_]["misses"] = misses
    data[name_]["global_min_pose"] = {
        k: {kk: (vv.tolist() if hasattr(vv, "tolist") else vv) for kk, vv in v.items()}
        for k, v in polish.items()}
    # --- timing table
    med = {f"{s:g}° ({grids[s].size:,} poses)": seconds[s] for s in _ROT_STEPS}
    timing = ratio_table(med, next(iter(med)), per="grid")
    plot_name = f"tradeoffs_capability_grid_{name_}.png"     # drawn by plot(data)
    f_ref = table["force"]
    gm = data[name_]["global_min_pose"]["force"]
    text = [
        f"#### {mech.name}: the reported minima",
        "",
        *rows,
        "",
        f"Smallest force capability found by the refinement: {f_ref['refined_min']:.4g} N "
        f"at position ({gm['position_mm'][0]:+.0f}, {gm['position_mm'][1]:+.0f}, "
        f"{gm['position_mm'][2]:+.0f}) mm, orientation "
        f"({gm['orientation_deg'][0]:+.2f}, {gm['orientation_deg'][1]:+.2f}, "
        f"{gm['orientation_deg'][2]:+.2f})°. The refined minima at the {npos} "
        f"positions contradict the Lipschitz estimate at "
        f"{sum(t['lipschitz_violations'] for t in table.values())} of "
        f"{npos * len(table)} (position, capability) pairs.",
        "",
        _summary(mech.name, per_pos, refined, seconds, label),
    ]
    if sign_change is not None:
        data[name_]["det_sign_change_positions"] = sign_change
        text += ["",
                 f"det J changes sign between neighbouring 2.5° grid orientations at "
                 f"**{sign_change}/{npos} positions**: a singular pose lies between them "
                 f"(intermediate value theorem), and at a singular pose the worst-case "
                 f"wrench and acceleration capabilities vanish (unless the null wrench "
                 f"lies entirely outside the slice; tests/stability checks the linear "
                 f"approach to 0 at one crossing). The refinement indeed drives them to "
                 f"about 0: the true minimum is 0, and every grid minimum is an artefact "
                 f"of the grid, however fine. (Our HEXA preset's γ = 30° is our choice, "
                 f"distkin.mechanisms.presets; Table III's 0.57 N minimum for "
                 f"the paper's HEXA is not comparable.)"]
    text += [
        "",
        f"#### {mech.name}: where a coarser grid misses the minimum at a position",
        "",
        "Positions whose grid minimum lies more than 1 % above the refined one, and the "
        "worst miss with its position (relative to (0, 0, z0)); per-position minima feed "
        "the dexterous workspace of eq. (17).",
        "",
        *miss_rows,
        "",
        f"Time of the grid evaluation, {mech.name} (one run each; the cost per pose is "
        f"the same, so the time follows the pose count); the refinement of all six "
        f"capabilities at all {npos} positions took {t_ref:.1f} s.",
        "",
        timing,
        "",
        f"![{mech.name}: grid minimum above the refined minimum, against time]"
        f"({_link(plot_name)})",
    ]
    return "\n".join(text)


def _summary(device, per_pos, refined, seconds, label):
    """One sentence per device: how close the coarsest grid is, and at what cost."""
    coarse, fine = _ROT_STEPS[0], _ROT_STEPS[-1]
    worst = {n: float(np.max(per_pos[coarse][n] / refined[n] - 1)) for n in label}
    good = [label[n].lower() for n, w in worst.items() if w < 0.01]
    bad = [label[n].lower() for n, w in worst.items() if w >= 0.01]
    speed = seconds[fine] / seconds[coarse]
    text = (f"**Summary, {device}.** The {coarse:g}° grid costs 1/{speed:.0f} of the "
            f"{fine:g}° grid's time. ")
    if good:
        text += (f"It is within 1 % of the refined minimum at every position for "
                 f"{', '.join(good)}")
        text += (f" (worst {100 * max(worst[n] for n in worst if worst[n] < 0.01):.2f} %)"
                 if good else "")
        text += ". "
    if bad:
        text += (f"It misses the minimum by more than 1 % for {', '.join(bad)}: those "
                 f"minima lie between grid points inside the orientation box.")
    return text


def _excess(value, ref):
    """How far a grid minimum lies above the refined one: a percentage, or a factor
    when the refined minimum is (close to) 0."""
    if ref > 0 and value / ref < 10:
        return f"{(value / ref - 1) * 100:+.2f} %"
    return f"{value / ref:.3g}× the refined value" if ref > 0 else "refined value 0"


def _det_sign_changes(mech, grid, npos):
    """Positions at which det J (L = 6) changes sign between neighbouring grid
    orientations: a singular pose lies in between (intermediate value theorem)."""
    n = len(grid.rx)
    count = 0
    for p in range(npos):
        d = np.linalg.det(mech.jacobian(grid.poses([p]))).reshape(n, n, n)
        sg = np.sign(d)
        if any(np.any(np.diff(sg, axis=ax) != 0) for ax in range(3)):
            count += 1
    return count


def _capability_section(data):
    parts = [_capability_device(n, data) for n in ("octopod", "hexa")]
    head = [
        "### 1. Worst-case capabilities: orientation grid step against the reported minima",
        "",
        "The six worst-case capabilities of Table III (±2.5 N·m, ±34.2 N·m, ±51 rad/s), "
        "evaluated as the study does (`evaluate_poses`, zonotope kernel) for the Octopod "
        "and the HEXA on 64 positions (±75 mm about z0 in 50 mm steps: the 4³ sub-grid "
        "of Table II's cube through its corners, chosen to keep the 2.5° grid at 314,432 "
        "poses per device) × the orientation grid over ±20° at 10°, 5° (Table II's step) "
        "and 2.5°. Minimum over the orientations at each position, then over positions, "
        "as Table III reports it. Each orientation grid contains the corners (±20°)³ of "
        "the orientation box, so a minimum that sits at a corner is found by all three.",
        "",
        "**Refined minimum** (an *upper bound* of the true minimum over the continuous "
        "orientation box at each grid position: every value is attained by a pose): from "
        "the two best 2.5° grid orientations, four zoomed 5³ grids (half width 2.5°, "
        "1.25°, 0.625°, 0.3125°), then scipy's bounded Powell search at the position of "
        "the global minimum. **Lipschitz estimate of a lower bound**: the 2.5° grid "
        "minimum minus (h/2)·Σᵢ Lᵢ at each position (h = 2.5°), with Lᵢ the largest "
        "finite-difference slope between neighbouring grid points along orientation axis "
        "i. It is *not rigorous*: a slope between grid points under-estimates the "
        "largest derivative, so this is an estimate of a bound, not a bound. "
        "Percentages: grid minimum relative to the refined minimum.",
    ]
    return "\n".join(head) + "\n\n" + "\n\n".join(parts)


# ================================================== 2. kernels near a singularity
_DISTANCES = 10.0 ** -np.arange(1, 13)          # m
_HEXA_TARGET = (-0.075, -0.075, 0.375)          # det J < 0 there, > 0 at the centre


def _mp_singular_point(mech, f_mp, dps):
    """The crossing of det J = 0 on the line from (0, 0, z0) towards ``_HEXA_TARGET``
    (zero rotation): float64 bisection, then the Illinois bracketing solver of mpmath
    on det J of the mpmath expression at ``dps`` digits.  Returns (t* as mpf, u)."""
    import mpmath
    home = mech.home
    u = np.r_[np.asarray(_HEXA_TARGET) - home[:3], 0.0, 0.0, 0.0]
    u /= np.linalg.norm(u[:3])
    kern = mech.kernels("batched").jacobian

    def det_f(t):
        return np.linalg.det(kern(home + t * u))
    a, b = 0.0, float(np.linalg.norm(np.asarray(_HEXA_TARGET) - home[:3]))
    sa = np.sign(det_f(a))
    for _ in range(60):
        c = 0.5 * (a + b)
        if np.sign(det_f(c)) == sa:
            a = c
        else:
            b = c
    with mpmath.workdps(dps):
        hm = [mpmath.mpf(float(x)) for x in home]
        um = [mpmath.mpf(float(x)) for x in u]

        def det_mp(t):
            return mpmath.det(mpmath.matrix(f_mp(*[h + t * v for h, v in zip(hm, um)])))
        lo, hi = mpmath.mpf(a) - mpmath.mpf("1e-6"), mpmath.mpf(b) + mpmath.mpf("1e-6")
        t_star = mpmath.findroot(det_mp, (lo, hi), solver="illinois",
                                 tol=mpmath.mpf(10) ** (-2 * dps // 3))
    return t_star, u, hm, um


def _kernel_section(data):
    import mpmath
    import sympy as sp

    from distkin.mechanisms import preset
    from distkin.mechanisms.symbolic import POSE, model_expressions
    dps = 50
    mech = preset("hexa", layout="radial")           # singular at zero rotation (see above)
    t0 = time.perf_counter()
    expr = model_expressions(mech).get("jacobian")    # what its kernel was generated from
    f_mp = sp.lambdify(POSE, expr, modules="mpmath")
    t_derive = time.perf_counter() - t0
    kern = mech.kernels("batched").jacobian
    t_star, u, hm, um = _mp_singular_point(mech, f_mp, dps)
    rows, recs = [], []
    with mpmath.workdps(dps):
        for d in _DISTANCES:
            pose_mp = [h + (t_star - mpmath.mpf(float(d))) * v for h, v in zip(hm, um)]
            pose = np.array([float(x) for x in pose_mp])      # the float64 pose both see
            Jf = kern(pose)
            Jm = mpmath.matrix(f_mp(*[mpmath.mpf(float(x)) for x in pose]))
            Jm_np = np.array(Jm.tolist(), dtype=object)
            scale = max(abs(x) for x in Jm_np.ravel())
            err_entries = float(max(abs(mpmath.mpf(float(a)) - b)
                                    for a, b in zip(Jf.ravel(), Jm_np.ravel())) / scale)
            det_m = mpmath.det(Jm)
            det_f = float(np.linalg.det(Jf))
            err_det = float(abs((mpmath.mpf(det_f) - det_m) / det_m))
            sv_m = mpmath.svd_r(Jm, compute_uv=False)
            smin_m, smax_m = min(sv_m), max(sv_m)
            sv_f = np.linalg.svd(Jf, compute_uv=False)
            err_smin = float(abs((mpmath.mpf(float(sv_f[-1])) - smin_m) / smin_m))
            # the kernel's own share: the float64 matrix, its SVD done exactly
            sv_k = mpmath.svd_r(mpmath.matrix(Jf.tolist()), compute_uv=False)
            err_smin_k = float(abs((min(sv_k) - smin_m) / smin_m))
            kappa = float(smax_m / smin_m)
            rec = {"distance_m": float(d), "sigma_min": float(smin_m), "kappa": kappa,
                   "rel_err_entries": err_entries, "rel_err_det": err_det,
                   "rel_err_sigma_min_lapack": err_smin,
                   "rel_err_sigma_min_kernel_only": err_smin_k}
            recs.append(rec)

    def lost(e):
        return max(0.0, math.log10(e / EPS)) if e > 0 else 0.0
    for r in recs:
        rows.append(f"| 1e{round(math.log10(r['distance_m'])):d} | {r['sigma_min']:.3g} | "
                    f"{r['kappa']:.3g} | {lost(r['rel_err_entries']):.1f} | "
                    f"{lost(r['rel_err_det']):.1f} | {lost(r['rel_err_sigma_min_lapack']):.1f} | "
                    f"{lost(r['rel_err_sigma_min_kernel_only']):.1f} | "
                    f"{math.log10(r['kappa']):.1f} |")
        r["digits_lost"] = {k: lost(r[k]) for k in ("rel_err_entries", "rel_err_det",
                                                      "rel_err_sigma_min_lapack",
                                                      "rel_err_sigma_min_kernel_only")}
    data["kernels"] = {"dps": dps, "t_star_m": float(t_star), "direction": u.tolist(),
                       "records": recs, "derive_and_lambdify_s": t_derive}
    # slope check: digits lost in σmin against log10 κ over the near part
    near = [r for r in recs if r["kappa"] > 1e4]
    slope = float(np.polyfit([math.log10(r["kappa"]) for r in near],
                             [r["digits_lost"]["rel_err_sigma_min_lapack"] for r in near],
                             1)[0]) if len(near) > 2 else float("nan")
    data["kernels"]["slope_digits_vs_log10_kappa"] = slope
    worst_entries = max(r["digits_lost"]["rel_err_entries"] for r in recs)
    over = max(r["rel_err_sigma_min_lapack"] / (r["kappa"] * EPS) for r in recs)
    cost_rows = _kernel_cost(mech, f_mp, t_star, hm, um, data)
    return "\n".join([
        "### 2. Generated kernels near a singularity: float64 against mpmath",
        "",
        f"HEXA preset under the radial reading of Fig. 2 (`preset('hexa', layout='radial')`, "
        f"the reading before issue 15: singular at zero rotation like the paper's Fig. 3), "
        f"generated `jacobian` kernel (float64) "
        f"against mpmath evaluation at {dps} digits of the same sympy expression "
        f"(`model_expressions(mech).get('jacobian')`, lambdified with `modules='mpmath'`). "
        f"Both evaluate the *same float64 pose*, so only evaluation error is measured. "
        f"The singular pose: det J = 0 on the line from (0, 0, z0) towards "
        f"(-75, -75, +75) mm at zero rotation, found by bisection and mpmath's Illinois "
        f"solver at {dps} digits (t* = {float(t_star) * 1e3:.12f} mm from the centre); "
        f"the poses approach it from the regular side. Digits lost = log10(relative "
        f"error / eps), eps = 2.2e-16; the prediction for det J and σmin is κ·eps, i.e. "
        f"log10 κ digits (κ = σmax/σmin in mpmath).",
        "",
        "| distance (m) | σmin (1/m, mixed) | κ | digits lost: J entries (normwise) | det J "
        "(numpy) | σmin (LAPACK) | σmin of the float64 J, exact SVD | predicted log10 κ |",
        "|---|---|---|---|---|---|---|---|",
        *rows,
        "",
        f"The kernel itself is stable: its entries lose at most {worst_entries:.1f} digits "
        f"however close the pose is to the singularity (J = Jq⁻¹Jx is smooth there; only "
        f"its determinant vanishes). What is lost near σmin → 0 is lost in the "
        f"ill-conditioned quantities computed *from* J, as predicted: the relative error "
        f"of σmin stays within {over:.2g}×κ·eps, and digits lost in σmin grow with "
        f"log10 κ at slope {slope:.2f} (κ > 1e4). σmin of the float64 J computed exactly "
        f"(mpmath SVD) loses the same digits as LAPACK's: the error sits in J's entries "
        f"(about 10 eps normwise, ordinary float64 evaluation error), amplified by κ, not "
        f"in the SVD; even correctly rounded entries would leave up to κ·eps/2.",
        "",
        f"![digits lost against log10 σmin]({_link('tradeoffs_kernel_digits.png')})",
        "",
        f"The trade at one pose, {_COST_DISTANCE:g} m from the singularity "
        f"(κ ≈ {data['kernels']['cost']['kappa']:.2g}): σmin by the float64 kernel and "
        "LAPACK against mpmath evaluation of the expression and mpmath's SVD at several "
        "precisions; correct digits against a 100-digit reference; times interleaved "
        "(median of 7 rounds).",
        "",
        *cost_rows,
    ])


_COST_DISTANCE = 1e-8
_COST_DPS = (20, 30, 50)


def _kernel_cost(mech, f_mp, t_star, hm, um, data):
    """Accuracy against time for σmin at one near-singular pose."""
    import mpmath
    kern = mech.kernels("scalar").jacobian              # one pose: the scalar flavour
    with mpmath.workdps(100):
        pose = np.array([float(h + (t_star - mpmath.mpf(_COST_DISTANCE)) * v)
                         for h, v in zip(hm, um)])
        Jr = mpmath.matrix(f_mp(*[mpmath.mpf(float(x)) for x in pose]))
        sv = mpmath.svd_r(Jr, compute_uv=False)
        ref, kappa = min(sv), max(sv) / min(sv)
    out = {}

    def fast():
        out["float64 kernel + LAPACK"] = float(np.linalg.svd(np.array(kern(pose.tolist())),
                                                             compute_uv=False)[-1])

    def precise(dps):
        def f():
            with mpmath.workdps(dps):
                J = mpmath.matrix(f_mp(*[mpmath.mpf(float(x)) for x in pose]))
                out[f"mpmath, {dps} digits"] = min(mpmath.svd_r(J, compute_uv=False))
        return f
    comps = {"float64 kernel + LAPACK": fast}
    comps.update({f"mpmath, {d} digits": precise(d) for d in _COST_DPS})
    med = interleaved(comps, rounds=7)
    digits = {}
    with mpmath.workdps(100):
        for n, v in out.items():
            err = abs((mpmath.mpf(v) if not isinstance(v, mpmath.mpf) else v) - ref) / ref
            digits[n] = float(min(100, -mpmath.log10(err))) if err > 0 else 100.0
    base = "float64 kernel + LAPACK"
    rows = ["| route | time per σmin | ratio | correct digits of σmin |", "|---|---|---|---|"]
    for n, t in med.items():
        rows.append(f"| {n} | {fmt_time(t)} | {t / med[base]:.3g}× | {digits[n]:.1f} |")
    data["kernels"]["cost"] = {"distance_m": _COST_DISTANCE, "kappa": float(kappa),
                               "seconds": med, "correct_digits": digits}
    return rows


# ============================================================= 3. GII sampling
_GII_POS = (3, 5, 9, 17)            # positions per axis over ±75 mm (nested grids)
_GII_ROT = (20.0, 10.0, 5.0, 2.5)   # orientation steps over ±20° (nested)


def _grid_poses(z0, n_pos, rot_step):
    from distkin.indices.workspace import table2_grid
    g = table2_grid(z0=z0, step=0.150 / (n_pos - 1), rot_deg=_ROT, rot_step_deg=rot_step)
    return g.poses(np.arange(g.n_positions)), g


def _sigmas(mech, poses, block=100000):
    from distkin.indices.design import design_sigmas
    lo, hi = np.empty(len(poses)), np.empty(len(poses))
    for a in range(0, len(poses), block):
        lo[a:a + block], hi[a:a + block] = design_sigmas(mech, poses[a:a + block])
    return lo, hi


def _refine_extreme(mech, pose, sign):
    """Local refinement of min σmin (sign = +1) or max σmax (sign = -1) over the whole
    pose box (±75 mm, ±20°): zoomed 3⁶ grids, then scipy's bounded Powell search."""
    from scipy.optimize import minimize

    from distkin.indices.design import design_sigmas
    half = np.r_[[0.075] * 3, [math.radians(_ROT)] * 3]
    centre = np.r_[0, 0, mech.z0, 0, 0, 0]
    lo_b, hi_b = centre - half, centre + half

    def f(P):
        s = design_sigmas(mech, np.atleast_2d(P))
        return sign * (s[0] if sign > 0 else s[1])
    c = np.array(pose, dtype=float)
    v = float(f(c)[0])
    w = half / 4
    for _ in range(4):
        axes = [np.clip(c[i] + np.linspace(-w[i], w[i], 3), lo_b[i], hi_b[i]) for i in range(6)]
        G = np.stack([a.ravel() for a in np.meshgrid(*axes, indexing="ij")], axis=1)
        vals = f(G)
        k = int(np.argmin(vals))
        if vals[k] < v:
            v, c = float(vals[k]), G[k]
        w = w / 2
    res = minimize(lambda x: float(f(x)[0]), c, method="Powell",
                   bounds=list(zip(lo_b, hi_b)), options={"xtol": 1e-7, "maxfev": 1500})
    if res.fun < v:
        v, c = float(res.fun), res.x
    return sign * v, c


def _gii_section(data):
    from distkin.indices.design import DesignSpace, sweep_designs
    from distkin.indices.isotropy import gii
    from distkin.mechanisms import preset
    mech = preset("octopod")
    runs = []
    combos = ([(n, 10.0) for n in _GII_POS] + [(5, r) for r in _GII_ROT if r != 10.0])
    best = {"smin": (np.inf, None), "smax": (-np.inf, None)}
    for n, r in combos:
        poses, g = _grid_poses(mech.z0, n, r)
        t0 = time.perf_counter()
        lo, hi = _sigmas(mech, poses)
        g_val, smin, smax = gii(lo, hi)
        sec = time.perf_counter() - t0
        runs.append({"positions_per_axis": n, "position_step_mm": 150 / (n - 1),
                     "rot_step_deg": r, "poses": len(poses), "gii": g_val,
                     "sigma_min": smin, "sigma_max": smax, "seconds": sec})
        i, j = int(np.argmin(lo)), int(np.argmax(hi))
        if lo[i] < best["smin"][0]:
            best["smin"] = (float(lo[i]), poses[i])
        if hi[j] > best["smax"][0]:
            best["smax"] = (float(hi[j]), poses[j])
    t0 = time.perf_counter()
    smin_ref, p_min = _refine_extreme(mech, best["smin"][1], +1)
    smax_ref, p_max = _refine_extreme(mech, best["smax"][1], -1)
    t_ref = time.perf_counter() - t0
    smin_ref, smax_ref = min(smin_ref, best["smin"][0]), max(smax_ref, best["smax"][0])
    gii_ref = smin_ref / smax_ref
    data["gii_octopod"] = {"runs": runs, "refined": {"sigma_min": smin_ref,
                                                     "sigma_max": smax_ref, "gii": gii_ref,
                                                     "pose_min": p_min.tolist(),
                                                     "pose_max": p_max.tolist(),
                                                     "seconds": t_ref}}
    rows = ["| positions | position step | orientation step | poses | GII | σmin | σmax | "
            "GII above refined | time |", "|---|---|---|---|---|---|---|---|---|"]
    for r in runs:
        rows.append(f"| {r['positions_per_axis']}³ | {r['position_step_mm']:.4g} mm | "
                    f"{r['rot_step_deg']:g}° | {r['poses']:,} | {r['gii']:.5f} | "
                    f"{r['sigma_min']:.5f} | {r['sigma_max']:.4f} | "
                    f"{(r['gii'] / gii_ref - 1) * 100:+.2f} % | {fmt_time(r['seconds'])} |")

    def fmt_pose(p):
        return (f"({(p[0]) * 1e3:+.1f}, {p[1] * 1e3:+.1f}, {(p[2] - mech.z0) * 1e3:+.1f}) mm, "
                f"({math.degrees(p[3]):+.1f}, {math.degrees(p[4]):+.1f}, "
                f"{math.degrees(p[5]):+.1f})°")
    # --- the Table I design sweep (Stocco's culling) at three sampling densities
    deg = math.pi / 180
    space = DesignSpace("hunt", (("l2", tuple(np.arange(7) * 0.005)),
                                 ("beta", tuple(np.arange(4) * 10 * deg)),
                                 ("gamma", tuple(np.arange(4) * 10 * deg)),
                                 ("ld", tuple(0.020 + np.arange(5) * 0.005))))
    sweeps = []
    for n, r in ((3, 20.0), (5, 20.0), (5, 10.0), (9, 10.0)):
        poses, _ = _grid_poses(0.30, n, r)
        res = sweep_designs(space, poses, algorithm="culling", progress=False)
        c = res["culling"]
        p = res["parameters"]
        sweeps.append({"positions_per_axis": n, "rot_step_deg": r, "poses": len(poses),
                       "seconds": c["seconds"], "evaluations": c["evaluations"],
                       "brute_force_evaluations": c["brute_force_evaluations"],
                       "gii": res["gii"], "best": p})
    data["gii_culling"] = sweeps
    srows = ["| sampling | poses | culling time | (design, pose) evaluations (brute force) | "
             "optimum l2, β, γ, ld | its GII |", "|---|---|---|---|---|---|"]
    for sw in sweeps:
        p = sw["best"]
        srows.append(
            f"| {sw['positions_per_axis']}³ × {sw['rot_step_deg']:g}° | {sw['poses']:,} | "
            f"{fmt_time(sw['seconds'])} | {sw['evaluations']:,} "
            f"({sw['brute_force_evaluations']:,}) | {p['l2'] * 1e3:g} mm, "
            f"{math.degrees(p['beta']):.0f}°, {math.degrees(p['gamma']):.0f}°, "
            f"{p['ld'] * 1e3:g} mm | {sw['gii']:.5f} |")
    same = len({tuple(sorted(s["best"].items())) for s in sweeps}) == 1
    return "\n".join([
        "### 3. Global isotropy index: sampling density against value and time",
        "",
        "GII = min σmin / max σmax of W = ST⁻¹Jᵀ (Sec. II-C-2, ST = diag(15 N, 15 N, 15 N, "
        "1 N·m, 1 N·m, 1 N·m), Sec. III-B-2) of the Octopod over nested grids of the Table II box (±75 mm, ±20°): the "
        "position step at a 10° orientation step, and the orientation step at 5³ "
        "positions. Every grid GII is an upper bound of the GII of the continuous box "
        "(more samples can only lower min σmin and raise max σmax). **Refined**: min σmin "
        "and max σmax searched over the continuous box (zoomed 3⁶ grids, then scipy's "
        "bounded Powell search, from the grids' extreme poses) — still an upper bound "
        "of the true GII, the tightest we have.",
        "",
        *rows,
        "",
        f"Refined: GII {gii_ref:.5f} (σmin {smin_ref:.5f} at {fmt_pose(p_min)}; σmax "
        f"{smax_ref:.4f} at {fmt_pose(p_max)}; {t_ref:.1f} s).",
        "",
        "The Table I design sweep (560 designs, Stocco's culling, `sweep_designs`) at "
        "increasing sampling density: the optimum "
        + ("is the same design at every density." if same else
           "**changes with the sampling density**: a coarse grid can pick a different "
           "design.") + " Time and evaluations grow with the pose count; culling "
        "evaluates a small fraction of the brute-force (design, pose) pairs.",
        "",
        *srows,
        "",
        f"![GII against sampling]({_link('tradeoffs_gii_sampling.png')})",
    ])


def run():
    data = {}
    parts = [_capability_section(data), _kernel_section(data), _gii_section(data)]
    plot(data)                      # the figures, from the numbers returned (--replot)
    return "\n\n".join(parts) + "\n", data
