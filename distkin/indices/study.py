"""The performance study of Kühne et al. (Sec. III-B/C, Tables III and IV) over a pose
grid, in resumable chunks.

For every pose of a :class:`~distkin.indices.workspace.PoseGrid`: inverse kinematics,
the Jacobian, the six worst-case output capabilities of eqs. (5)-(7) with the
zero-torque / zero-force slices (zonotope kernel), the true velocity worst cases of a
redundant device (:mod:`.velocity_set`), the four maximum sensitivities (the paper's
slice, eqs. (14)/(16), or Cardou's projection: :mod:`.sensitivity`), the scaled
singular values of the isotropy index under every reading of the scaling
(:mod:`.isotropy`) and the smallest transmission |Jq_ii|/l1 of the legs.  A chunk covers whole positions
(all orientations of each), and reduces its poses to per-position minima and maxima, so
a sweep of 3 million poses keeps a few hundred kB.

Actuators and mass (docs/design.md §5, Sec. III-B-3): nominal torque ±2.5 N·m (continuous
force/torque), stall torque ±34.2 N·m (accelerations), velocity ±51 rad/s;
M̂ = diag(m, m, m, I, I, I) from the mechanism (0.17 kg, 3e-4 kg·m²).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .capability import output_generators
from .isotropy import ST_DEFAULT, gii, reading_singular_values
from .jacobian_resolution import unresolved_poses, warn_unresolved
from .paper_tables import PAPER_TABLE3, PAPER_TABLE4
from .sensitivity import max_sensitivities
from .velocity_set import true_velocity_worst
from .workspace import inner_covered
from .zonotope import _facets, _ratio_min, zonotope_worst

__all__ = ["CAPABILITIES", "SENSITIVITIES", "TRUE_VELOCITIES", "QUANTITIES", "ACTUATORS",
           "inner_covered", "PAPER_TABLE3", "PAPER_TABLE4", "SIGMA_READINGS", "evaluate_poses", "study_chunk",
           "Device", "run_device", "summarise", "planned_chunk", "MIN_CHUNKS"]

#: name, label (Table III), unit, generator, actuator limit, slice
CAPABILITIES = (
    ("force", "Continuous force", "N", "wrench", "nominal_torque", (0, 1, 2)),
    ("torque", "Continuous torque", "N·m", "wrench", "nominal_torque", (3, 4, 5)),
    ("velocity", "Velocity", "m/s", "twist", "velocity", (0, 1, 2)),
    ("angular_velocity", "Angular velocity", "rad/s", "twist", "velocity", (3, 4, 5)),
    ("acceleration", "Acceleration", "m/s²", "acceleration", "stall_torque", (0, 1, 2)),
    ("angular_acceleration", "Angular acceleration", "rad/s²", "acceleration",
     "stall_torque", (3, 4, 5)),
)
#: name, label, unit, generator, rows (unit actuator limits; slice or projection)
SENSITIVITIES = (
    ("sens_translational", "Max. translational sensitivity", "m/rad", "twist", (0, 1, 2)),
    ("sens_rotational", "Max. rotational sensitivity", "rad/rad", "twist", (3, 4, 5)),
    ("sens_force", "Max. force sensitivity", "N/(N·m)", "wrench", (0, 1, 2)),
    ("sens_torque", "Max. torque sensitivity", "(N·m)/(N·m)", "wrench", (3, 4, 5)),
)
#: name, label, unit, slice: the true velocity set {ẋ : |J ẋ|∞ <= q̇max} (.velocity_set);
#: for L = 6 the same set as eq. (5)'s J⁻¹·box, whose velocity rows are computed as these
TRUE_VELOCITIES = (
    ("velocity_true", "Velocity, true set", "m/s", (0, 1, 2)),
    ("angular_velocity_true", "Angular velocity, true set", "rad/s", (3, 4, 5)),
)
#: readings of the scaling whose σ need their own SVD (the others follow from W's)
SIGMA_READINGS = ("unscaled", "task_multiplied", "jx")
QUANTITIES = (tuple(c[0] for c in CAPABILITIES) + tuple(t[0] for t in TRUE_VELOCITIES)
              + tuple(s[0] for s in SENSITIVITIES) + ("sigma_min", "sigma_max")
              + tuple(f"sigma_{m}_{r}" for r in SIGMA_READINGS for m in ("min", "max"))
              + ("transmission_min", "det_sign"))

#: actuator figures of Sec. III-B-3 (N·m, N·m, rad/s)
ACTUATORS = {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51.0}

_ROWS = [c[0] for c in CAPABILITIES] + [s[0] for s in SENSITIVITIES]
#: evaluate_poses' flag of the poses whose J float64 does not resolve, and all its keys
_UNRES = "J_unresolved"
_KEYS = QUANTITIES + (_UNRES,)
#: quantities whose worst pose (orientation index) each chunk keeps
_ARGMIN = tuple(c[0] for c in CAPABILITIES) + tuple(t[0] for t in TRUE_VELOCITIES)


# ----------------------------------------------------------------------- per pose
def evaluate_poses(mech, poses, *, actuators=ACTUATORS, ST=ST_DEFAULT, route="kernels",
                   sensitivity="slice", compiled: bool = True, chunk: int = 2048,
                   warn: bool = True):
    """Every index of the study at each pose.

    Parameters
    ----------
    mech : RSSMechanism
    poses : ndarray (N, 6)
        m and rad.
    actuators : dict
        ``nominal_torque`` [N·m], ``stall_torque`` [N·m], ``velocity`` [rad/s]
        (symmetric limits ±value) for revolute legs; ``nominal_force`` [N],
        ``stall_force`` [N], ``speed`` [m/s] for prismatic legs; a leg's own effort
        ``limit`` is its nominal effort (:mod:`.actuators`: per-leg limits, units per
        actuator type).
    ST : 6 floats
        Scaling matrix diagonal (:mod:`.isotropy`).
    route : {"kernels", "numpy"}
        The generated kernels of the mechanism, or :mod:`distkin.mechanisms.reference` (no codegen).
    sensitivity : {"slice", "projection"}
        The paper's definition (eqs. (14), (16)) or Cardou's (:mod:`.sensitivity`).
    compiled : bool
        True: the capabilities, true velocities, J# and singular values pose by pose in
        one compiled kernel (:mod:`.study_compiled`; 6 <= L <= 8); False: the numpy
        route (batched array operations), the reference.  They agree to about 1e-13
        relative (tests/indices/test_study_compiled.py).
    chunk : int
        Poses evaluated together: the work memory is bounded by the chunk, not by N
        (the numpy route needs about 10 KiB per pose for L = 8; 2048 keeps the compiled
        route's arrays in the CPU's L2 cache, about 3 % faster than 8192).
    warn : bool
        False: no warning for the ``J_unresolved`` poses (a caller that counts them).

    Returns
    -------
    ok : ndarray (N,) bool
        Every leg closes and the Jacobian is finite.
    values : dict name -> ndarray (ok.sum(),)
        ``J_unresolved`` (bool): J is not resolved in float64 there (a leg within
        rounding of its reach boundary; :mod:`.jacobian_resolution`), so every index at
        that pose is inaccurate (QA 25a F4: σmax 15 % off), with one
        :class:`~distkin.errors.ConditioningWarning` per call; :func:`study_chunk`
        leaves such poses out.  :data:`QUANTITIES`, in the units of :data:`CAPABILITIES`,
        :data:`TRUE_VELOCITIES` and :data:`SENSITIVITIES`; ``sigma_min``/``sigma_max``
        of the chosen reading ST⁻¹Jᵀ in 1/(N·m) (1/N for prismatic actuators; not
        dimensionless, QA 25a F5), ``sigma_*_<reading>`` of the others of
        :data:`SIGMA_READINGS` in theirs (:data:`.isotropy.SIGMA_UNITS`);
        ``transmission_min`` = min_i |Jq_ii|/l1_i
        (l1_i the crank of leg i, 1 for a prismatic leg);
        ``det_sign`` the sign of det J (L = 6; 1 for L = 8).

    Raises
    ------
    InputError
        Checked once per call, for both routes: ``poses`` not finite numbers of shape
        (N, 6); ``ST`` not 6 positive finite numbers; an actuator limit that is not a
        positive finite number (or missing for a leg's type); ``route`` or
        ``sensitivity`` not one of its choices.
    """
    poses, ST, lim = _check_evaluate(mech, poses, actuators, ST, route, sensitivity)
    ok, out = _evaluate(mech, poses, lim, ST, route, sensitivity, compiled, max(1, int(chunk)))
    if warn:
        warn_unresolved(ok, out[_UNRES], poses)
    return ok, out


def _check_evaluate(mech, poses, actuators, ST, route, sensitivity):
    """The entry checks of :func:`evaluate_poses`, once per call (not per pose or chunk):
    poses (N, 6) finite, ST 6 positive finite factors, the actuator limits positive and
    finite (:func:`.actuators.leg_limits`), route and sensitivity among their choices.
    Returns the poses, ST as a tuple and the per-leg limits."""
    from ..argcheck import choice, float_array
    from .actuators import leg_limits
    from .isotropy import check_scaling
    poses = float_array(poses, "poses", (None, 6))
    ST = tuple(check_scaling(ST))
    choice(route, "route", ("kernels", "numpy"))
    choice(sensitivity, "sensitivity", ("slice", "projection"))
    return poses, ST, leg_limits(mech, actuators)


def _evaluate(mech, poses, lim, ST, route, sensitivity, compiled, chunk):
    """:func:`evaluate_poses` on checked input (``lim``: :func:`.actuators.leg_limits`)."""
    if len(poses) > chunk:
        # results written in place chunk after chunk: besides them, only one chunk's
        # work memory is alive at a time
        ok = np.empty(len(poses), bool)
        out = {q: np.empty(len(poses), bool if q == _UNRES else float) for q in _KEYS}
        n = 0
        for a in range(0, len(poses), chunk):
            ok_c, v = _evaluate(mech, poses[a:a + chunk], lim, ST, route, sensitivity,
                                compiled, chunk)
            ok[a:a + chunk] = ok_c
            k = int(ok_c.sum())
            for q in _KEYS:
                out[q][n:n + k] = v[q]
            n += k
        return ok, {q: out[q][:n] for q in _KEYS}
    kin = None
    if route == "numpy":
        from ..mechanisms.reference import ik_jacobian
        _, valid, J, Jq = ik_jacobian(mech, poses, return_jq=True)
    else:
        # the legs' reach margins only (the crank angles of inverse_kinematics are not
        # needed here); compiled when the kernels have loop twins
        from .study_compiled import reach_jq_jx
        kin = reach_jq_jx(mech, poses) if compiled else None
        if kin is not None:
            ok, Jq, J = kin                  # reach and finiteness tested there
        else:
            valid = mech.reachable(poses)[:, None]
            Jq, Jx = mech.jq_jx(poses, warn=False)     # unreachable poses: filtered below
            with np.errstate(divide="ignore", invalid="ignore"):
                J = Jx / Jq[..., None]
    if kin is None:
        ok = valid.all(axis=1) & np.all(np.isfinite(J), axis=(1, 2))
    if not ok.all():
        J, Jq = J[ok], Jq[ok]
    n = len(J)
    M = np.diag(mech.cartesian_mass_matrix()) if hasattr(mech, "cartesian_mass_matrix") \
        else np.array([mech.mass] * 3 + [mech.inertia] * 3)
    if not n:
        return ok, {q: np.zeros(0, bool if q == _UNRES else float) for q in _KEYS}
    from .actuators import per_leg_capabilities, transmission_lengths, uniform_limits
    act = uniform_limits(lim)
    act_run = act if act is not None else dict(ACTUATORS)
    if compiled and 6 <= mech.L <= 8:
        out = _indices_compiled(J, Jq, M, act_run, ST, sensitivity)
    else:
        out = _indices_numpy(J, Jq, M, act_run, ST, sensitivity)
    if act is None:                    # limits differ between legs (or actuator types)
        out.update(per_leg_capabilities(J, M, lim, CAPABILITIES, TRUE_VELOCITIES))
    out["transmission_min"] = np.min(np.abs(Jq) / transmission_lengths(mech), axis=1)
    # L = 6: a sign change of det J between reachable poses encloses a singularity
    out["det_sign"] = np.sign(np.linalg.det(J)) if mech.L == 6 else np.ones(n)
    out[_UNRES] = unresolved_poses(mech, poses[ok], J)        # QA 25a F4
    return ok, out


def _indices_numpy(J, Jq, M, actuators, ST, sensitivity):
    """The reference route: batched numpy, module by module (and the Gray-code walk of
    :mod:`.slice_farthest`), the arithmetic of the study before the compiled kernel."""
    gens = output_generators(J, mass=M)
    out = _worst_cases(J, gens, M, actuators)
    for name, _, _, keep in TRUE_VELOCITIES:
        out[name] = true_velocity_worst(J, actuators["velocity"], keep)
    if J.shape[1] == 6:
        # a square J: J⁻¹·box is the slab set of the true velocities (.study_compiled),
        # whose worst cases stay continuous through a singularity (the flat route of the
        # zonotope gives 0 there)
        out["velocity"] = out["velocity_true"].copy()
        out["angular_velocity"] = out["angular_velocity_true"].copy()
    sig = reading_singular_values(J, ST, Jq=Jq)
    un_min, un_max = sig["unscaled"]
    sens = max_sensitivities(J, sensitivity, twist=gens["twist"], walk=True,
                             kappa=np.clip(np.nan_to_num(np.divide(
                                 un_min, un_max, out=np.zeros(len(J)), where=un_max > 0),
                                 nan=0.0, posinf=0.0), 0.0, 1.0))
    for name in SENSITIVITIES:
        out[name[0]] = sens[name[0].removeprefix("sens_")]
    out["sigma_min"], out["sigma_max"] = sig["wrench"]
    for r in SIGMA_READINGS:
        out[f"sigma_min_{r}"], out[f"sigma_max_{r}"] = sig[r]
    return out


def _indices_compiled(J, Jq, M, actuators, ST, sensitivity):
    """:mod:`.study_compiled` for the capabilities, true velocities, J# and σ; the
    compiled vertex enumeration (:mod:`.slice_farthest`) for the sensitivities; the
    poses the kernel flags go through :func:`_indices_numpy`."""
    from .study_compiled import study_indices
    caps, truev, twist, sig, flag = study_indices(J, Jq, M, actuators, ST)
    out = {cap[0]: caps[:, i] for i, cap in enumerate(CAPABILITIES)}
    for i, (name, _, _, _) in enumerate(TRUE_VELOCITIES):
        out[name] = truev[:, i]
    # σmin/σmax of Jᵀ (the unscaled reading) for the singular-J test of the sensitivities
    # (a pose the kernel flags may have NaN σ: 0 treats it as singular, as before; it
    # is redone below)
    kappa = np.divide(sig[:, 2], sig[:, 3], out=np.zeros(len(J)), where=sig[:, 3] > 0)
    kappa = np.clip(np.nan_to_num(kappa, nan=0.0, posinf=0.0), 0.0, 1.0)
    sens = max_sensitivities(J, sensitivity, twist=twist if J.shape[1] > 6 else None,
                             kappa=kappa)
    for name in SENSITIVITIES:
        out[name[0]] = sens[name[0].removeprefix("sens_")]
    out["sigma_min"], out["sigma_max"] = sig[:, 0], sig[:, 1]
    for k, r in enumerate(SIGMA_READINGS):
        out[f"sigma_min_{r}"], out[f"sigma_max_{r}"] = sig[:, 2 + 2 * k], sig[:, 3 + 2 * k]
    bad = np.flatnonzero(flag)
    if len(bad):
        ref = _indices_numpy(J[bad], Jq[bad], M, actuators, ST, sensitivity)
        for q, v in ref.items():
            out[q][bad] = v
    return out


def _worst_cases(J, gens, M, actuators):
    """The six worst cases from ONE facet computation.

    With symmetric limits equal for every actuator all three generator matrices share the
    facets of Jᵀ: ``J# = (JᵀJ)⁻¹Jᵀ`` and ``M̂⁻¹Jᵀ`` are invertible 6 × 6 maps of Jᵀ, so a
    facet normal n of Jᵀ becomes ``(JᵀJ) n`` and ``M̂ n`` with the same ``n·g_i`` and an
    offset scaled by the limit.  Exact, and three times cheaper than three kernels.
    Singular poses go through :func:`~.zonotope.zonotope_worst` generator by generator.
    """
    n_poses, L, _ = J.shape
    nw, h1, regular = _facets(gens["wrench"], np.zeros((n_poses, L)), np.ones((n_poses, L)))
    JtJ = np.einsum("nli,nlj->nij", J, J)
    normals = {"wrench": nw, "twist": np.einsum("nkd,nde->nke", nw, JtJ),
               "acceleration": nw * M[None, None, :]}
    out = {}
    for gen, nn in normals.items():
        caps = [cap for cap in CAPABILITIES if cap[3] == gen]
        lim = float(actuators[caps[0][4]])
        for cap in caps:
            out[cap[0]] = _ratio_min(h1 * lim, nn[:, :, list(cap[5])])
        bad = np.flatnonzero(~regular)
        if len(bad):
            vals = zonotope_worst(gens[gen][bad], np.zeros((len(bad), L)),
                                  np.full((len(bad), L), lim), [cap[5] for cap in caps])
            for cap, v in zip(caps, vals):
                out[cap[0]][bad] = v
    return out


def study_chunk(spec: dict) -> dict:
    """One chunk of a study sweep (module level: runs in pool or dask workers).

    ``spec``: ``mech`` (RSSMechanism), ``grid`` (PoseGrid), ``lo``/``hi`` position
    range, ``actuators``, ``ST``, ``inner`` (rad or None: the inner orientation range
    reduced separately), ``route``, ``batch`` (poses per evaluation), ``compiled``
    (default True: :mod:`.study_compiled`; False: the numpy route, the reference).

    Returns per-position arrays: ``{q}_min``, ``{q}_max`` (and ``_in`` variants over the
    inner orientations) for every quantity, ``n_ok``, ``n_ok_in``, ``n_flagged`` (poses
    with a value float64 cannot give, NaN, left out of the extremes), ``n_unresolved``
    and ``n_unresolved_in`` (poses whose J float64 does not resolve, left out of every
    extreme and not flagged again: :mod:`.jacobian_resolution`), ``{q}_argmin``
    (orientation index of the worst case) for the capabilities.  Positions without a reachable
    orientation hold +inf (min) / -inf (max).
    """
    grid, mech = spec["grid"], spec["mech"]
    lo, hi = spec["lo"], spec["hi"]
    no = grid.n_orientations
    O = grid.orientations()
    inner = spec.get("inner")
    in_mask = (np.all(np.abs(O) <= inner + 1e-9, axis=1) if inner is not None
               else np.ones(no, bool))
    per = max(1, int(spec.get("batch", 20000)) // no)
    npos = hi - lo
    res = {}
    for q in QUANTITIES:
        for suf, fill in (("_min", np.inf), ("_max", -np.inf), ("_min_in", np.inf),
                          ("_max_in", -np.inf)):
            res[q + suf] = np.full(npos, fill)
    res["n_ok"] = np.zeros(npos, np.int64)
    res["n_ok_in"] = np.zeros(npos, np.int64)
    res["n_flagged"] = np.zeros(npos, np.int64)
    res["n_unresolved"] = np.zeros(npos, np.int64)
    res["n_unresolved_in"] = np.zeros(npos, np.int64)
    for q in _ARGMIN:
        res[f"{q}_argmin"] = np.full(npos, -1, np.int64)
    for a in range(lo, hi, per):
        b = min(hi, a + per)
        poses = grid.poses(np.arange(a, b))
        ok, vals = evaluate_poses(mech, poses, actuators=spec["actuators"], ST=spec["ST"],
                                  route=spec.get("route", "kernels"),
                                  sensitivity=spec.get("sensitivity", "slice"),
                                  compiled=spec.get("compiled", True), warn=False)
        # poses whose J float64 does not resolve: reachable, but left out of every
        # extreme (+inf / -inf as unreachable ones) and counted (QA 25a F4)
        unres = np.zeros(len(ok), bool)
        unres[ok] = vals[_UNRES]
        okm = ok.reshape(b - a, no)
        sl = slice(a - lo, b - lo)
        res["n_ok"][sl] = okm.sum(axis=1)
        res["n_ok_in"][sl] = (okm & in_mask).sum(axis=1)
        res["n_unresolved"][sl] = unres.reshape(b - a, no).sum(axis=1)
        res["n_unresolved_in"][sl] = (unres.reshape(b - a, no) & in_mask).sum(axis=1)
        # all quantities at once: V (quantity, position, orientation), unreachable
        # poses +inf for the minima and -inf for the maxima
        lo_v = np.full((len(QUANTITIES), len(ok)), np.inf)
        lo_v[:, ok] = np.stack([vals[q] for q in QUANTITIES])
        lo_v[:, unres] = np.inf
        lo_v = lo_v.reshape(len(QUANTITIES), b - a, no)
        okm = (ok & ~unres).reshape(b - a, no)
        # NaN: a value float64 cannot give (near-flat zonotope, QA Z2): left out of the
        # extremes and counted (``n_flagged``), never a silent NaN or a wrong extreme
        bad = np.isnan(lo_v)
        res["n_flagged"][sl] = bad.any(axis=0).sum(axis=1)
        hi_v = np.where(okm & ~bad, lo_v, -np.inf)
        lo_v = np.where(bad, np.inf, lo_v)
        mins, maxs = lo_v.min(axis=2), hi_v.max(axis=2)
        inn = okm & in_mask
        mins_in = np.where(inn, lo_v, np.inf).min(axis=2)
        maxs_in = np.where(inn, hi_v, -np.inf).max(axis=2)
        for k, q in enumerate(QUANTITIES):
            res[f"{q}_min"][sl], res[f"{q}_max"][sl] = mins[k], maxs[k]
            res[f"{q}_min_in"][sl], res[f"{q}_max_in"][sl] = mins_in[k], maxs_in[k]
        for q in _ARGMIN:
            res[f"{q}_argmin"][sl] = lo_v[QUANTITIES.index(q)].argmin(axis=1)
    return res


# ------------------------------------------------------------------------ devices
@dataclass(frozen=True)
class Device:
    """One kinematics of the study: a label, the mechanism, its orientation range and
    the Table III/IV column it is compared with (``paper``, or None)."""

    label: str
    mech: object
    grid: object
    paper: str | None = None
    inner: float | None = None


#: a sweep of few chunks is cut into at least this many (the progress bar moves in
#: steps of 1/16 at most; QA: "0/4 chunks" for 18 s, then 4/4 at once)
MIN_CHUNKS = 16


def planned_chunk(n_positions: int, chunk_positions: int) -> int:
    """Positions per chunk of a sweep of ``n_positions``: ``chunk_positions`` (the
    scene's), smaller when that gives fewer than :data:`MIN_CHUNKS` chunks, at least 1.
    Each position's values are its own (:func:`study_chunk` reduces over orientations
    per position), so the chunking changes no number, only the progress steps."""
    return max(1, min(int(chunk_positions), int(n_positions) // MIN_CHUNKS))


def run_device(dev: Device, *, store, executor=None, chunk_positions: int = 64,
               actuators=ACTUATORS, ST=ST_DEFAULT, route="kernels", progress=True,
               batch: int = 20000, sensitivity: str = "slice", stats: dict | None = None):
    """Sweep one device over its grid in resumable chunks; returns the per-position
    arrays (concatenated) and the seconds the run took.  The grid is cut into chunks of
    :func:`planned_chunk` positions (``chunk_positions``, smaller for a small grid).
    In process, one position is evaluated first (and dropped) to load the compiled
    kernels while the bar says so (:func:`~distkin.runstore.run_chunks`'s ``warmup``).
    Chunks live in ``store/<key of the sweep's definition>/``, so a changed grid,
    mechanism, limit or route starts a new sweep and an unchanged one resumes; ``stats`` is filled as
    :func:`~distkin.runstore.run_chunks` fills it (``loaded``: the chunks resumed)."""
    import time
    from pathlib import Path

    from ..runstore import run_chunks, sweep_key
    grid = dev.grid
    specs = []
    chunk_positions = planned_chunk(grid.n_positions, chunk_positions)
    for a in range(0, grid.n_positions, chunk_positions):
        specs.append({"mech": dev.mech, "grid": grid, "lo": a,
                      "hi": min(grid.n_positions, a + chunk_positions),
                      "actuators": dict(actuators), "ST": tuple(ST), "inner": dev.inner,
                      "route": route, "batch": batch, "sensitivity": sensitivity})
    # every parameter that changes a number (QA: a numpy-route run resumed the compiled
    # route's chunks); batch changes none (each pose on its own)
    definition = {"kind": "study", "mech": repr(dev.mech), "grid": grid.as_dict(),
                  "actuators": dict(actuators), "ST": list(ST), "inner": dev.inner,
                  "chunk_positions": chunk_positions, "sensitivity": sensitivity,
                  "route": route, "quantities": list(QUANTITIES), "version": 4}
    t0 = time.perf_counter()
    store = Path(store) / sweep_key(definition)       # a changed definition starts afresh
    chunks = run_chunks(study_chunk, specs, store, definition=definition,
                        executor=executor, progress=progress,
                        desc=f"{dev.label} ({grid.size:,} poses)", stats=stats,
                        warmup=lambda: study_chunk({**specs[0], "hi": specs[0]["lo"] + 1}))
    seconds = time.perf_counter() - t0
    merged = {k: np.concatenate([c[k] for c in chunks]) for k in chunks[0]}
    return merged, seconds


def _finite(x):
    x = float(x)
    return x if math.isfinite(x) else None


def _extreme(per, q, mask, kind):
    if not mask.any():
        return None
    v = per[f"{q}_{kind}"][mask]
    return _finite(v.min() if kind == "min" else v.max())


def summarise(dev: Device, per: dict, *, tau_nominal: float | None = 2.5) -> dict:
    """Table III/IV values of one device from its per-position arrays.

    ``tau_nominal``: the actuators' common nominal effort (N·m, or N for prismatic legs)
    of the ``wrench_nominal`` reading (σ × τnom); None leaves that reading out (legs
    whose nominal limits differ have no single factor).

    ``table`` holds the Table III rows (paper's values and ratios where the device has a
    paper column) and the true-velocity rows; ``isotropy`` Table IV over the inner
    orientations (±20°) with every reading of the scaling in ``readings``;
    ``worst_poses`` the pose (m, rad) of each capability's worst case; ``diagnostics``
    the smallest σmin, transmission |Jq|/l1 and whether every sensitivity is finite.
    Non-finite extremes are None in ``table`` (JSON); ``max_unbounded`` says a row's
    maximum is +inf (a sensitivity at a singular J), not missing.
    Extremes are over the poses the device reaches: each row of ``table``, ``isotropy``
    and the summary carry ``reachable_only`` (some grid pose unreachable, left out, not
    scored σmin = 0 as design_sweep's ``unreachable = "zero"``), ``poses_used`` and
    ``poses_total`` (Table IV: of the inner orientations).
    ``rotation_covered_deg``: the largest r such that every rotation axis of the grid
    reaches -r and +r.
    """
    from .isotropy import SCALING_READINGS
    grid = dev.grid
    # positions with a pose whose values the extremes use: reachable, J resolved
    n_un, n_un_in = (per.get(k, np.zeros_like(per["n_ok"])) for k in ("n_unresolved",
                                                                      "n_unresolved_in"))
    has, has_in = per["n_ok"] - n_un > 0, per["n_ok_in"] - n_un_in > 0
    n_in = (grid.n_orientations if dev.inner is None else
            int(np.sum(np.all(np.abs(grid.orientations()) <= dev.inner + 1e-9, axis=1))))
    table = {}
    units = ({c[0]: c[2] for c in CAPABILITIES} | {s[0]: s[2] for s in SENSITIVITIES}
             | {t[0]: t[2] for t in TRUE_VELOCITIES})
    labels = ({c[0]: c[1] for c in CAPABILITIES} | {s[0]: s[1] for s in SENSITIVITIES}
              | {t[0]: t[1] for t in TRUE_VELOCITIES})
    full = per["n_ok"] == grid.n_orientations          # positions reaching every orientation
    n_ok, n_ok_in = int(per["n_ok"].sum()), int(per["n_ok_in"].sum())
    # unreachable poses are left out of every extreme (not scored 0 as design_sweep's
    # unreachable = "zero" does): say so, with the counts (QA IX 1)
    over = {"reachable_only": n_ok < grid.size, "poses_used": n_ok - int(n_un.sum()),
            "poses_total": grid.size}
    for q in _ROWS + [t[0] for t in TRUE_VELOCITIES]:
        lo, hi = _extreme(per, q, has, "min"), _extreme(per, q, has, "max")
        entry = {"label": labels[q], "unit": units[q], "min": lo, "max": hi,
                 "min_full_positions": _extreme(per, q, full, "min"),
                 # +inf maxima (an unbounded sensitivity at a singular J) are None above
                 # (JSON); this keeps them apart from "no reachable pose"
                 "max_unbounded": bool(has.any() and np.any(per[f"{q}_max"][has] == np.inf)),
                 **over}
        col = q.removesuffix("_true")
        if dev.paper in PAPER_TABLE3:
            pmin, pmax = PAPER_TABLE3[dev.paper][col]
            entry.update(paper_min=pmin, paper_max=pmax,
                         ratio_min=(lo / pmin if pmin and lo is not None else None),
                         ratio_max=(hi / pmax if pmax and hi is not None else None))
        table[q] = entry
    # no reachable pose: no GII (None, "—"), not the 0 of gii() on an empty sample
    g_full = gii(per["sigma_min_min"][has], per["sigma_max_max"][has]) if has.any() \
        else (None, None, None)
    g_in = gii(per["sigma_min_min_in"][has_in], per["sigma_max_max_in"][has_in]) \
        if has_in.any() else (None, None, None)
    covered = inner_covered(grid, dev.inner)
    iso = {"gii": g_in[0], "sigma_min": g_in[1], "sigma_max": g_in[2],
           # the range the inner orientations of the grid cover (what was reduced), and
           # the one asked for (Table IV's ±20°), which a grid may not have
           "rotation_deg": math.degrees(covered),
           "rotation_requested_deg": (math.degrees(dev.inner) if dev.inner is not None
                                      else None),
           "gii_full_range": g_full[0], "sigma_min_full_range": g_full[1],
           "sigma_max_full_range": g_full[2],
           # over the inner orientations' poses the device reaches
           "reachable_only": n_ok_in < n_in * grid.n_positions,
           "poses_used": n_ok_in - int(n_un_in.sum()),
           "poses_total": n_in * grid.n_positions}
    readings = {}
    for r in (SCALING_READINGS if has_in.any() else ()):
        if r == "wrench":
            lo, hi = g_in[1], g_in[2]
        elif r == "wrench_nominal":
            if tau_nominal is None:
                continue
            lo, hi = tau_nominal * g_in[1], tau_nominal * g_in[2]
        elif r == "inverse":
            lo = 1 / g_in[2] if g_in[2] > 0 else 0.0
            hi = 1 / g_in[1] if g_in[1] > 0 else math.inf
        else:
            lo = float(per[f"sigma_min_{r}_min_in"][has_in].min()) if has_in.any() else 0.0
            hi = float(per[f"sigma_max_{r}_max_in"][has_in].max()) if has_in.any() else 0.0
        readings[r] = {"gii": lo / hi if hi > 0 else 0.0, "sigma_min": lo, "sigma_max": hi}
    iso["readings"] = readings
    if dev.paper in PAPER_TABLE4:
        pg, ps, pS = PAPER_TABLE4[dev.paper]
        iso.update(paper_gii=pg, paper_sigma_min=ps, paper_sigma_max=pS,
                   **{f"ratio_{k}": (None if iso[k] is None else iso[k] / v)
                      for k, v in (("gii", pg), ("sigma_min", ps), ("sigma_max", pS))})
    worst = {}
    for q in _ARGMIN:
        v = np.where(has, per[f"{q}_min"], np.inf)
        if has.any():
            ip = int(np.argmin(v))
            io = int(per[f"{q}_argmin"][ip])
            worst[q] = np.r_[grid.positions([ip])[0], grid.orientations()[io]].tolist()
    sens_max = [_extreme(per, s_[0], has, "max") for s_ in SENSITIVITIES]
    diagnostics = {
        "sigma_min": _extreme(per, "sigma_min", has, "min"),
        "transmission_min": _extreme(per, "transmission_min", has, "min"),
        "sensitivities_max": sens_max,
        "sensitivities_finite": bool(all(v is not None and math.isfinite(v) for v in sens_max)),
        "det_sign_changes": bool(has.any() and per["det_sign_min"][has].min() < 0
                                 < per["det_sign_max"][has].max()),
    }
    return {
        "label": dev.label, "mechanism": dev.mech.name, "L": dev.mech.L,
        "paper_column": dev.paper,
        "poses": grid.size, "positions": grid.n_positions,
        "orientations": grid.n_orientations,
        "rotation_deg": math.degrees(max(abs(v) for v in grid.rx)),
        # the largest r with ±r on every rotation axis (the "±30°" claims need 30)
        "rotation_covered_deg": max(0.0, math.degrees(min(min(-min(a), max(a))
                                                          for a in (grid.rx, grid.ry,
                                                                    grid.rz)))),
        "reachable_poses": n_ok,
        # poses whose values float64 cannot give (near-flat, QA Z2), left out of the rows
        "flagged_poses": int(per["n_flagged"].sum()) if "n_flagged" in per else 0,
        # poses whose J float64 does not resolve (QA 25a F4), left out of every row
        "unresolved_poses": int(n_un.sum()),
        **over,
        "reachable_fraction": float(per["n_ok"].sum() / grid.size),
        "all_orientations_reachable": per["n_ok"] == grid.n_orientations,
        "inner_all_reachable": per["n_ok_in"] == n_in,
        "table": table, "isotropy": iso, "diagnostics": diagnostics,
        "worst_poses": worst,
        "worst_force_pose": worst.get("force"),
    }
