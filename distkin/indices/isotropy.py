"""Isotropy: the local condition number κ (eq. (4)), the global isotropy index and
Stocco's culling algorithm for design sweeps (Kühne et al., Sec. II-C-2, III-B-2).

The Jacobian J (L × 6, q̇ = J·(v, ω)) mixes units; following Stocco et al. [2] it is
normalised with the scaling matrix ``ST = diag(15 N, 15 N, 15 N, 1 N·m, 1 N·m, 1 N·m)``
(the intended wrench magnitudes of Ergin's device, Sec. III-B-2).  ``κ = σmin/σmax``
(eq. (4)); over a workspace, ``GII = min σmin / max σmax`` [1] (Table IV prints GII,
σmin, σmax this way: 0.0127 / 20.0052 = 0.0006).

Which matrix ST scales is not printed; the readings (:data:`SCALING_READINGS`) and
our choice:

``"wrench"`` (chosen)
    ``W = ST⁻¹ Jᵀ`` (6 × L): actuator torques in N·m to the wrench in units of the
    intended wrench (eq. (3) normalised on the task side, the only side the paper
    names: "ST ... contains the desired magnitude of the end effector wrench").
    Stocco [2] pre- and post-multiplies the design matrix; with the actuator side
    left in N·m (the paper gives no actuator scaling) this is the literal reading.
``"wrench_nominal"``
    ``ST⁻¹ Jᵀ τ_nom``: Stocco's two-sided normalisation with the actuator side at the
    actuators' nominal limit (σ × τ_nom, the same GII; the paper's 2.5 N·m for the
    presets, the legs' own limit when they all share one, left out when they differ).
``"unscaled"``
    ``Jᵀ`` (no scaling; 1/m and 1 mixed).
``"task_multiplied"``
    ``ST Jᵀ`` (ST applied the other way round).
``"inverse"``
    ``J#ᵀ ST = pinv(W)``: actuator torque per unit normalised wrench (the direction of
    τ = J#ᵀ f); its singular values are the reciprocals of W's, so σmin = 1/σmax(W),
    σmax = 1/σmin(W) pose by pose and the same GII.
``"jx"``
    ``ST⁻¹ Jxᵀ``: the direct-kinematics matrix of eq. (1) alone ("singular values of Jx
    or J", Sec. II-C-1; rows are the unit Plücker lines of the distal links).

Units (QA 25a F5): W has the units of the actuator effort's reciprocal, 1/(N·m) for
revolute actuators (J in rad/m, rad/rad; ST in N, N·m) and 1/N for prismatic ones, and
so have σmin and σmax (:data:`SIGMA_UNITS`, :func:`sigma_unit`); κ and the GII, their
ratios, are dimensionless.  A length unit changes the singular values by its factor and
leaves κ and the GII alone: J in rad/mm with ST in N and N·mm gives W/1000 (the wrench per N·mm of actuator
torque instead of per N·m: consistent units, a different unit of the input), so σmin
and σmax are 1000 times smaller and σmin/σmax is the same (tests/indices:
test_a_length_unit_scales_sigma_and_keeps_kappa).  The study reports σmin and σmax of every
reading beside Table IV.  Measured on the presets (Table II grid, ±20°;
``docs/fig2_readings.md``): W gives σmax 0.06-0.16× the paper's; the unscaled Jᵀ
comes closest to the printed σmax (0.7-2×) but then σmin is 0.2-0.8× and the paper
states that ST was applied; no reading matches σmin and σmax together (they also
depend on the unprinted geometry).  We keep W by its definition, not by a match.

References
----------
.. [1] L. Stocco, S. E. Salcudean, F. Sassani, "Fast constrained global minimax
   optimization of robot parameters", Robotica 16(6), 1998 (GII, culling).
.. [2] L. Stocco, S. E. Salcudean, F. Sassani, "Matrix normalization for optimal robot
   design", IEEE ICRA 1998.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..argcheck import as_floats, float_array, positive_number
from ..errors import InputError
from .capability import _jacobian
from .tiers import fast_only

__all__ = ["ST_DEFAULT", "scaled_singular_values", "condition_number", "gii",
           "CullingResult", "culling_sweep", "brute_force_sweep", "SCALING_READINGS",
           "reading_singular_values", "check_scaling", "SIGMA_UNITS", "sigma_unit"]

#: the scaling matrix of Sec. III-B-2, diagonal, (N, N, N, N·m, N·m, N·m)
ST_DEFAULT = (15.0, 15.0, 15.0, 1.0, 1.0, 1.0)

#: the readings of Stocco's scaling tried (module docstring); "wrench" is ours
SCALING_READINGS = {
    "wrench": "ST⁻¹Jᵀ (chosen)",
    "wrench_nominal": "ST⁻¹Jᵀ·τnom (actuator side at the nominal limit)",
    "unscaled": "Jᵀ",
    "task_multiplied": "ST·Jᵀ",
    "inverse": "J#ᵀ·ST = pinv(ST⁻¹Jᵀ)",
    "jx": "ST⁻¹Jxᵀ (Jx of eq. (1) only)",
}


#: units of the singular values of each reading (revolute actuators, prismatic ones):
#: J has rows rad/m, rad/rad (revolute) or m/m, m/rad (prismatic), ST is in N and N·m,
#: so W = ST⁻¹Jᵀ maps an actuator effort (N·m, N) to the wrench in units of ST: its σ
#: are per N·m or per N; Jx = Jq J has rows m/m, m/rad for both (QA 25a F5)
SIGMA_UNITS = {
    "wrench": ("1/(N·m)", "1/N"),
    "wrench_nominal": ("1", "1"),
    "unscaled": ("mixed (rows 1/m and 1)", "mixed (rows 1 and m)"),
    "task_multiplied": ("mixed (rows N/m and N·m)", "mixed (rows N and N·m²)"),
    "inverse": ("N·m", "N"),
    "jx": ("1/N", "1/N"),
}


def sigma_unit(prismatic, reading: str = "wrench") -> str:
    """The unit of the singular values of ``reading`` (:data:`SIGMA_UNITS`) for legs
    ``prismatic`` ((L,) bool; one bool for all): a table of both kinds mixes per-N·m
    and per-N columns, which the text says.  κ and the GII are dimensionless."""
    rev, pri = SIGMA_UNITS[reading]
    pris = np.asarray(prismatic, dtype=bool)
    if rev == pri or not pris.any():
        return rev
    return pri if pris.all() else f"mixed ({rev} revolute, {pri} prismatic columns)"


def check_scaling(ST):
    """The diagonal of the scaling matrix as an array (6,): :class:`InputError` naming
    ``ST`` unless it is 6 positive finite numbers."""
    st = as_floats(ST, "ST", "6 positive scaling factors")
    if st.shape != (6,) or not np.all(st > 0) or not np.all(np.isfinite(st)):
        raise InputError(f"expected 6 positive finite scaling factors, got {ST!r}", field="ST")
    return st


def _scaled(J, ST):
    J = _jacobian(J, "(..., L, 6)")
    return np.swapaxes(J, -1, -2) / check_scaling(ST)[:, None]


def scaled_singular_values(J, ST=ST_DEFAULT, *, method: str = "fast"):
    """Smallest and largest singular value of ``W = ST⁻¹ Jᵀ`` (Sec. II-C-2).

    Parameters
    ----------
    J : ndarray (..., L, 6)
        Jacobian, q̇ = J·(v, ω) (m/s, rad/s -> rad/s).
    ST : sequence of 6 floats
        Diagonal of the scaling matrix (N, N, N, N·m, N·m, N·m).
    method : "fast"
        The only tier (float64 SVD; "precise" and "certified" are refused with an
        InputError naming ``method``, :mod:`.tiers`).

    Returns
    -------
    smin, smax : ndarray (...)
        In 1/(N·m) for revolute actuators, 1/N for prismatic ones (:func:`sigma_unit`):
        W maps an actuator effort (N·m, N) to the wrench in units of ST (dimensionless),
        so its σ are per unit of actuator effort; only κ and the GII are dimensionless
        (QA 25a F5: they were labelled dimensionless).  float64 SVD,
        relative accuracy about 1e-16 × κ⁻¹ for σmin.  Fewer than 6 legs (L < 6):
        σmin = 0 (W of rank L < 6 misses a wrench direction), so κ = 0.

    Raises
    ------
    InputError
        ``J`` not numbers of shape (..., L, 6), or not finite (NaN, inf: an unreachable
        pose's J is the caller's to filter); ``ST`` not 6 positive finite numbers.
    """
    fast_only(method, "the scaled singular values")
    W = _scaled(J, ST)
    return _sigma_range(np.linalg.svd(W, compute_uv=False), W.shape[-1])


def _sigma_range(s, L):
    """(σmin, σmax) of a 6 × L map from its min(6, L) singular values: with fewer than
    6 actuators (L < 6) the image misses a wrench direction, so σmin is 0 (the six
    singular values of the map onto the 6-D wrench space, padded with zeros)."""
    smin = s[..., -1] if L >= 6 else np.zeros(s.shape[:-1])
    return smin, s[..., 0]


def reading_singular_values(J, ST=ST_DEFAULT, *, Jq=None, tau_nominal: float = 2.5):
    """σmin and σmax per pose of every reading of :data:`SCALING_READINGS`.

    Parameters
    ----------
    J : ndarray (N, L, 6)
    ST : 6 floats
    Jq : ndarray (N, L), optional
        The diagonal of eq. (1)'s Jq (m), for the ``jx`` reading (Jx = Jq J, row-wise);
        without it ``jx`` is left out.
    tau_nominal : float
        Actuator torque of the ``wrench_nominal`` reading (N·m).

    Returns
    -------
    dict name -> (smin (N,), smax (N,))
    """
    smin, smax = scaled_singular_values(J, ST)
    J = np.asarray(J, dtype=float)
    st = np.asarray(ST, dtype=float)
    tau_nominal = positive_number(tau_nominal, "tau_nominal")
    out = {"wrench": (smin, smax),
           "wrench_nominal": (smin * tau_nominal, smax * tau_nominal)}
    with np.errstate(divide="ignore"):
        out["inverse"] = (1.0 / smax, 1.0 / smin)
    L = J.shape[-2]
    s = np.linalg.svd(np.swapaxes(J, -1, -2), compute_uv=False)
    out["unscaled"] = _sigma_range(s, L)
    s = np.linalg.svd(np.swapaxes(J, -1, -2) * st[:, None], compute_uv=False)
    out["task_multiplied"] = _sigma_range(s, L)
    if Jq is not None:
        Jx = J * float_array(Jq, "Jq", J.shape[:-1])[..., None]
        out["jx"] = scaled_singular_values(Jx, ST)
    return out


def condition_number(J, ST=ST_DEFAULT, *, method: str = "fast"):
    """Local condition number κ = σmin/σmax, eq. (4), of the scaled Jacobian; (...).

    ``J`` (..., L, 6) and ``ST`` as :func:`scaled_singular_values` (which checks them:
    one J gives a float, a batch an array;
    :class:`~distkin.errors.InputError` for a J that is not finite).  0 for fewer than
    6 legs (L < 6: the wrench map has rank < 6).  ``method``: "fast" only (float64
    SVD, the tier of every index; DESIGN §3; accuracy: absolute error about 1e-16 in κ);
    "precise" and "certified" are refused with an :class:`~distkin.errors.InputError`
    naming ``method`` and the certified routes (:mod:`.tiers`, QA T 9)."""
    fast_only(method, "the condition number")
    smin, smax = scaled_singular_values(J, ST)
    kappa = np.divide(smin, smax, out=np.zeros_like(smin), where=smax > 0)
    return float(kappa) if kappa.ndim == 0 else kappa    # one J: a float (QA T 9)


def gii(smin, smax, *, method: str = "fast"):
    """Global isotropy index [1]: ``min σmin / max σmax`` over the workspace samples.

    ``smin``, ``smax``: one pair per pose, σmin <= σmax at each (else an
    :class:`~distkin.errors.InputError` naming the pose: the index is in [0, 1]).
    Returns (gii, min σmin, max σmax).

    Raises :class:`~distkin.errors.InputError` (QA IX 3) for an empty sample (a
    minimum over no pose is not defined: the caller says "no reachable pose", as
    :func:`distkin.indices.study.summarise` does; it returned 0) and for max σmax = 0,
    where min σmin / max σmax is 0/0 (every pose a zero J; it returned 0); also for
    non-finite values (a singular value of a finite J is finite).

    ``method``: "fast" only (a min and a max of the given floats, exact; "precise" and
    "certified" are refused, :mod:`.tiers`).
    """
    fast_only(method, "the GII")
    smin = as_floats(smin, "smin", "singular values (numbers)")
    smax = as_floats(smax, "smax", "singular values (numbers)")
    if smin.shape != smax.shape:
        raise InputError(f"expected smin and smax of one shape (one pair per pose), got "
                         f"{smin.shape} and {smax.shape}", field="smax")
    if smin.size == 0:
        raise InputError("expected at least one pose (one pair σmin, σmax per pose), got "
                         "an empty sample: the GII, a minimum over the poses, is not "
                         "defined on none", field="smin")
    for v, name in ((smin, "smin"), (smax, "smax")):
        if np.isnan(v).any():
            raise InputError("expected singular values (not NaN), got NaN", field=name)
        if np.isinf(v).any():
            raise InputError(f"expected finite singular values, got "
                             f"{float(v.flat[np.flatnonzero(np.isinf(v.ravel()))[0]])!r}",
                             field=name)
        low = float(np.nanmin(v, initial=0.0))
        if low < 0:
            raise InputError(f"expected singular values >= 0, got {low!r}", field=name)
    bad = np.flatnonzero(smin.ravel() > smax.ravel())        # QA T 10
    if bad.size:
        k = int(bad[0])
        raise InputError(f"expected smin <= smax at every pose, got smin="
                         f"{float(smin.flat[k])!r} > smax={float(smax.flat[k])!r} at pose {k}"
                         + (f" (and {bad.size - 1} more)" if bad.size > 1 else ""),
                         field="smin", hint="pass the smallest and largest singular value of "
                         "each pose, in that order (scaled_singular_values)")
    lo, hi = float(smin.min()), float(smax.max())
    if hi == 0:
        raise InputError(f"expected some σmax > 0, got max σmax = 0 over {smax.size} "
                         "pose(s): min σmin / max σmax is 0/0, undefined (every J zero)",
                         field="smax")
    return lo / hi, lo, hi


# ---------------------------------------------------------------------- design sweeps
@dataclass
class CullingResult:
    """Outcome of a GII design sweep.

    ``best`` is the index of the optimal design (the smallest index among exact ties,
    as ``numpy.argmax``), ``gii``/``smin``/``smax`` its exact values, ``complete`` the
    designs evaluated at every pose (with their exact GII in ``exact``), ``bounds`` the
    upper bound on the GII of every design when it was culled (or its exact value),
    ``evaluations`` the number of (design, pose) evaluations performed.
    """

    best: int
    gii: float
    smin: float
    smax: float
    exact: dict = field(default_factory=dict)
    bounds: np.ndarray | None = None
    evaluations: int = 0
    n_designs: int = 0
    n_poses: int = 0
    #: max σmax of every design over the poses it was evaluated at (exact for the
    #: designs in ``exact``; 0 where no evaluated pose was reachable)
    smax_all: np.ndarray | None = None

    def as_dict(self):
        return {"best": self.best, "gii": self.gii, "sigma_min": self.smin,
                "sigma_max": self.smax, "evaluations": self.evaluations,
                "brute_force_evaluations": self.n_designs * self.n_poses,
                "complete_designs": sorted(self.exact)}


def _check_eval(out, nd, npo):
    lo, hi = (np.asarray(a, dtype=float) for a in out)
    if lo.shape != (nd, npo) or hi.shape != (nd, npo):
        raise InputError(f"expected evaluate() to return two arrays of shape ({nd}, {npo}), "
                         f"got {lo.shape} and {hi.shape}", field="evaluate")
    if np.isnan(lo).any() or np.isnan(hi).any():
        # a NaN GII compares false with everything: argmax would pick its design
        raise InputError("expected evaluate() to return singular values, got NaN (an "
                         "unreachable pose should give smin = 0 or +inf, smax = 0)",
                         field="evaluate")
    return lo, hi


def _check_sweep(n_designs, n_poses, block):
    if isinstance(block, (bool, np.bool_)) or not isinstance(block, (int, np.integer)) \
            or block < 1:
        raise InputError(f"expected an integer >= 1 (poses per call), got {block!r}",
                         field="block")
    if n_designs < 1 or n_poses < 1:
        raise InputError(f"expected at least one design and one pose, got {n_designs} "
                         f"designs and {n_poses} poses", field="sweep")


def brute_force_sweep(evaluate, n_designs: int, n_poses: int, *, block: int = 4096):
    """GII of every design at every pose (the reference for :func:`culling_sweep`).

    ``evaluate(designs (k,), poses (m,)) -> (smin (k, m), smax (k, m))``.  Returns
    ``(CullingResult, gii (n_designs,))``.
    """
    _check_sweep(n_designs, n_poses, block)
    lo = np.full(n_designs, np.inf)
    hi = np.zeros(n_designs)
    designs = np.arange(n_designs)
    for a in range(0, n_poses, block):
        poses = np.arange(a, min(n_poses, a + block))
        smin, smax = _check_eval(evaluate(designs, poses), n_designs, len(poses))
        lo = np.minimum(lo, smin.min(axis=1))
        hi = np.maximum(hi, smax.max(axis=1))
    g = np.divide(lo, hi, out=np.zeros(n_designs), where=hi > 0)
    b = int(np.argmax(g))
    res = CullingResult(b, float(g[b]), float(lo[b]), float(hi[b]),
                        exact={i: float(g[i]) for i in range(n_designs)}, bounds=g,
                        evaluations=n_designs * n_poses, n_designs=n_designs,
                        n_poses=n_poses, smax_all=hi.copy())
    return res, g


def culling_sweep(evaluate, n_designs: int, n_poses: int, *, block: int = 4096,
                  seed_poses=None):
    """Maximise the GII over designs with Stocco's culling algorithm [1].

    The GII of a design after any subset of poses, ``min σmin / max σmax``, is an
    **upper bound** of its GII over all poses (more poses can only lower the min and
    raise the max).  The algorithm repeatedly evaluates the most promising design at
    every pose, which gives an exact GII and so a lower bound of the optimum; it then
    evaluates every surviving design at that design's critical poses (argmin σmin,
    argmax σmax: the poses that are likely critical for its neighbours too) and culls
    every design whose bound is strictly below the best exact GII.  A culled design
    cannot be optimal, and the optimum is never culled, so the result is exactly the
    brute-force answer (same floating-point operations, min/max being exact), with
    far fewer evaluations.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(designs (k,), poses (m,)) -> (smin (k, m), smax (k, m))``, the
        scaled singular values (an unreachable pose should give smin = 0).
    n_designs, n_poses : int
    block : int
        Poses per call when a design is evaluated completely.
    seed_poses : array of int, optional
        Poses evaluated for every design first (default: 8 evenly spread poses);
        non-empty, indices in 0..n_poses-1.

    Returns
    -------
    CullingResult
    """
    _check_sweep(n_designs, n_poses, block)
    if seed_poses is not None:
        sp = np.asarray(seed_poses)
        if sp.ndim != 1 or not sp.size or sp.dtype.kind not in "iu" \
                or sp.min() < 0 or sp.max() >= n_poses:
            raise InputError(f"expected a non-empty list of pose indices in 0..{n_poses - 1}, "
                             f"got {seed_poses!r}", field="seed_poses")
    lo = np.full(n_designs, np.inf)
    hi = np.zeros(n_designs)
    evaluations = 0

    def bounds():
        return np.divide(lo, hi, out=np.full(n_designs, np.inf), where=hi > 0)

    def probe(designs, poses):
        nonlocal evaluations
        poses = np.unique(np.asarray(poses, dtype=np.intp))
        smin, smax = _check_eval(evaluate(designs, poses), len(designs), len(poses))
        lo[designs] = np.minimum(lo[designs], smin.min(axis=1))
        hi[designs] = np.maximum(hi[designs], smax.max(axis=1))
        evaluations += len(designs) * len(poses)
        return smin, smax

    seed = (np.linspace(0, n_poses - 1, min(8, n_poses)).round().astype(np.intp)
            if seed_poses is None else np.asarray(seed_poses, dtype=np.intp))
    probe(np.arange(n_designs), seed)
    alive = np.ones(n_designs, bool)
    exact: dict[int, float] = {}
    best_val = -np.inf
    while True:
        b = bounds()
        open_ = alive & ~np.isin(np.arange(n_designs), list(exact))
        if not open_.any():
            break
        cand = np.flatnonzero(open_)
        leader = int(cand[np.argmax(b[cand])])       # first index among equal bounds
        crit_lo, crit_hi, vlo, vhi = 0, 0, np.inf, -np.inf
        for a in range(0, n_poses, block):
            poses = np.arange(a, min(n_poses, a + block))
            smin, smax = probe(np.array([leader]), poses)
            i, j = int(np.argmin(smin[0])), int(np.argmax(smax[0]))
            if smin[0, i] < vlo:
                vlo, crit_lo = smin[0, i], int(poses[i])
            if smax[0, j] > vhi:
                vhi, crit_hi = smax[0, j], int(poses[j])
        g = float(lo[leader] / hi[leader]) if hi[leader] > 0 else 0.0
        exact[leader] = g
        best_val = max(best_val, g)
        others = np.flatnonzero(alive & ~np.isin(np.arange(n_designs), list(exact)))
        if len(others):
            probe(others, [crit_lo, crit_hi])
        b = bounds()
        alive &= ~(b < best_val)
        for k in list(exact):
            alive[k] = True
    g_exact = np.array([exact.get(i, -np.inf) for i in range(n_designs)])
    best = int(np.argmax(g_exact))
    bnd = bounds()
    for k, v in exact.items():
        bnd[k] = v
    return CullingResult(best, float(g_exact[best]), float(lo[best]), float(hi[best]),
                         exact=exact, bounds=bnd, evaluations=evaluations,
                         n_designs=n_designs, n_poses=n_poses, smax_all=hi.copy())
