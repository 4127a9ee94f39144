"""Maximum sensitivities (Kühne et al., Sec. II-C-4, eqs. (14), (16); Cardou et al. [1]).

With the actuator displacements normalised to ``||δq||∞ <= 1 rad`` the maximum
point-displacement and rotation sensitivities are the farthest points of the
translational and rotational parts of ``{J# δq}`` (eq. (5)); with actuator torques
normalised to ``||τ||∞ <= 1 N·m`` the force and torque sensitivities are the farthest
points of the parts of ``{Jᵀ τ}`` (eq. (6)).  "Part" has two meanings:

``mode="slice"`` (the default: the paper's definition)
    the paper's polytope algorithm: slice the polytope (eq. (14): the other part is
    zero, e.g. translation at zero rotation), then the farthest point, eq. (16).  Every
    vertex of the slice has at least L − 3 actuators at a limit; the
    C(L, 3)·2^(L−3) candidates are enumerated exactly by the compiled kernel of
    :mod:`.slice_farthest` (for L = 6 the twist slices are the slab polytopes
    ``{u : |J_S u|∞ <= 1}``, computed from J so that they stay accurate next to a
    singularity, and +inf at it, where the slice is unbounded).  At a singular wrench
    map (e.g. no actuator makes torque about z) the zero row is no constraint and the
    force slice is that of the other rows (:mod:`.constraint_basis`).
``mode="projection"`` (Cardou et al. [1])
    the farthest point of the projection (the other part unconstrained), a box vertex
    of the zonotope (the 2^L vertices, :func:`distkin.indices.best_case_output`).  It is
    never smaller than the slice and about twice the paper's values on the presets.

At an exactly singular Jacobian (σmin/σmax of J at the rounding level,
:func:`~.zonotope.flat_tol`) a twist ẋ with J ẋ = 0 moves the platform with the
actuators locked, so a twist sensitivity whose part that motion reaches is **+inf**
(unbounded), the limit of its regular neighbours, in every mode and for every L: in
slice mode where the null space of J holds a vector whose other part is zero (e.g.
J e_z = 0: translation along z at zero rotation), in projection mode where a null
vector has a nonzero component in the part.  J# = pinv(J) would truncate that direction
and give a finite value that depends on nothing near it (and a projection smaller than
the slice).  A *nearly* singular J (flat_tol < σmin/σmax <= :data:`~.zonotope.RANK_TOL`)
has bounded sets, every value finite (about 1/σmin where the near-null twist reaches
the part), but float64 cannot give them where they are computed from ~1/σmin entries:
those values are NaN with a :class:`~distkin.errors.ConditioningWarning`, never +inf.

How each route decides, for the poses with σmin/σmax <= RANK_TOL:

* the L = 6 slice (the slab route) works on J itself: the slice of the part S is
  ``{u : |J_S u|∞ <= 1}``, which depends on the three columns J_S alone, so κ_S =
  σmin/σmax of J_S (never below that of J) decides: +inf at κ_S <= flat_tol(3, 6)
  (J_S u = 0, i.e. the null twist (u, 0) of J); NaN with a warning for flat_tol < κ_S
  <= RANK_TOL (the slab is bounded, about 1/σmin of J_S, but its vertices and their
  feasibility come from cancellation); otherwise the value,
  finite and continuous in J (relative error about 1e-16 / κ_S), without a warning,
  at an exactly singular J too (e.g. a null twist with both parts, or the
  translational slice of J whose null twist is a pure rotation);
* the J# routes (projection mode, and L > 6 in slice mode): at an exactly singular J,
  +inf where a null vector reaches the part (components below 1e-9 of a unit null
  vector count as zero, as in :func:`.zonotope._flat_worst`), and otherwise the values
  of the set of eq. (5) with the Moore-Penrose J#, which is discontinuous at a singular
  J (the limits from regular neighbours depend on the direction of approach): such
  poses warn; at a nearly singular J both twist sensitivities are NaN, with a warning
  (pinv(J) has entries ~1/σmin).

The force and torque sensitivities stay finite
(Jᵀ·box is flat there, not unbounded).

.. [1] P. Cardou, S. Bouchard, C. Gosselin, "Kinematic-sensitivity indices for
   dimensionally nonhomogeneous Jacobian matrices", IEEE Trans. Robotics 26(1), 2010.
"""

from __future__ import annotations

import numpy as np

from ..argcheck import as_floats
from ..errors import ConditioningWarning, InputError, warn as _warn
from .capability import _jacobian
from .float_scale import pow2_exponent, scale_back
from .tiers import fast_only
from .slice_farthest import slab_farthest_unit, slice_farthest_unit
from .zonotope import (RANK_TOL, check_enumeration, flat_tol, memory_guard, vertex_candidates,
                       zonotope_best)

__all__ = ["max_sensitivities", "SENSITIVITY_UNITS", "SENSITIVITY_MODES"]

#: ``slice``: the paper's eqs. (14), (16); ``projection``: Cardou's definition
SENSITIVITY_MODES = ("slice", "projection")

#: name -> unit of each maximum sensitivity
SENSITIVITY_UNITS = {"translational": "m/rad", "rotational": "rad/rad",
                     "force": "N/(N·m)", "torque": "(N·m)/(N·m)"}


def max_sensitivities(J, mode: str = "slice", *, twist=None, walk: bool = False,
                      kappa=None, method: str = "fast"):
    """The four maximum sensitivities at each pose (module docstring).

    Parameters
    ----------
    J : ndarray (N, L, 6), or (L, 6) for one pose
        Jacobian, q̇ = J·(v, ω).
    mode : {"slice", "projection"}
        The paper's definition (slice, then farthest point) or Cardou's (projection).
    twist : ndarray (N, 6, L) ((6, L) with one J), optional
        ``pinv(J)`` if already computed (its shape is checked, not its values: a pose
        where it is not finite gives values that are not either).
    walk : bool
        Slice mode: the Gray-code kernel of :mod:`.slice_farthest` for every L (the
        reference of its split-sign kernel for L = 8).
    kappa : ndarray (N,) (a float with one J), optional
        σmin/σmax of J per pose if already computed (the study has it), for the test of
        a singular J (module docstring); otherwise from numpy's SVD.  A ratio of
        singular values: finite, in [0, 1] (1 + 1e-12 allowed for rounding).
    method : "fast"
        The only tier (float64; "precise" and "certified" are refused, :mod:`.tiers`).
        Accuracy of the fast answer: relative error about 1e-16 / κ of J for the twist
        sensitivities (J# = pinv(J); the L = 6 slice works on J itself: 1e-16 / κ_S,
        κ_S = σmin/σmax of the part's columns J_S), 1e-16 for the force and torque
        ones; NaN with a ConditioningWarning at a nearly singular J (flat_tol < κ <=
        RANK_TOL, QA Z2 3; for the L = 6 slice where κ_S is in that band, module
        docstring); inputs scaled by powers of two into range
        (:mod:`.float_scale`), a result beyond float64 warns.

    Returns
    -------
    dict of ndarray (N,) (of floats for one J (L, 6))
        ``translational`` [m/rad], ``rotational`` [rad/rad], ``force`` [N/(N·m)],
        ``torque`` [(N·m)/(N·m)].  Exact up to float64 rounding (vertex enumeration);
        +inf for a twist sensitivity that a null twist of an exactly singular J
        reaches, NaN for one a nearly singular J leaves to float64 (module docstring).

    Raises
    ------
    InputError
        A bad ``mode``; ``J`` not finite numbers of shape (L, 6) or (N, L, 6), L >= 6 (as
        :func:`~.capability.worst_case_output`, L >= d); ``twist`` not of shape
        (N, 6, L); ``kappa`` not N numbers in [0, 1] (NaN, negative, above 1, text, a
        wrong length); more than :data:`~.zonotope.MAX_CANDIDATES` vertex candidates per
        pose (C(L, 3)·2^(L−3) for slices, 2^L for projections: L <= 12 and 18).
    """
    fast_only(method, "the maximum sensitivity")
    if mode not in SENSITIVITY_MODES:
        raise InputError(f"expected mode 'slice' or 'projection', got {mode!r}", field="mode")
    J = _jacobian(J, "(L, 6) or (N, L, 6)")
    if J.ndim > 3:
        raise InputError(f"expected a Jacobian of shape (L, 6) or (N, L, 6), got shape "
                         f"{J.shape}", field="J")
    single = J.ndim == 2                  # one J as worst_case_output takes it (QA T 9)
    if single:
        J = J[None]
        twist = None if twist is None else np.asarray(twist)[None]
    N, L, _ = J.shape
    kappa = None if kappa is None else _kappa(kappa, N, single)
    if L < 6:
        raise InputError(f"expected at least 6 actuators (rows of J, L >= 6), got shape "
                         f"{J.shape}", field="J")
    # counted before anything is allocated (slices: C(L, 3)·2^(L−3) vertex candidates;
    # projections: the 2^L box vertices)
    check_enumeration(vertex_candidates(L, 3 if mode == "slice" else 0), L,
                      "slice-vertex candidates (C(L, 3)·2^(L−3))" if mode == "slice" else
                      "box vertices (2^L)", field="J")
    # exact power-of-two rescaling into the float64 range (:mod:`.float_scale`): the
    # twist sensitivities scale as 1/J, the force and torque ones as J (QA Z2 4)
    e = pow2_exponent(J, (1, 2))
    if e.any():
        J = np.ldexp(J, -e[:, None, None])
        twist = None if twist is None else np.ldexp(np.asarray(twist, dtype=float),
                                                    e[:, None, None])
    with memory_guard(L, "maximum sensitivities", field="J"):
        out = _max_sensitivities(J, mode, twist, walk, kappa)
    if e.any():
        for name, sign in (("translational", -1), ("rotational", -1), ("force", 1),
                           ("torque", 1)):
            out[name] = scale_back(out[name], sign * e, f"{name} sensitivity")
    return {k: float(v[0]) for k, v in out.items()} if single else out


def _kappa(kappa, N, single):
    """``kappa`` checked: N finite numbers in [0, 1] (σmin/σmax of J), shape (N,), or one
    number with one J; an :class:`InputError` naming ``kappa`` otherwise (QA IX 2)."""
    shape = "a number" if single else f"shape ({N},)"
    k = as_floats(kappa, "kappa", f"σmin/σmax of J ({shape}, in [0, 1])")
    if k.shape != (() if single else (N,)) and not (single and k.shape == (1,)):
        raise InputError(f"expected σmin/σmax of J of {shape}, one per pose, got shape "
                         f"{k.shape}", field="kappa")
    bad = ~((k >= 0) & (k <= 1 + 1e-12))                      # NaN is bad too
    if bad.any():
        i = int(np.flatnonzero(bad.ravel())[0])
        raise InputError(f"expected σmin/σmax of J in [0, 1] (a ratio of singular values), "
                         f"got {float(k.ravel()[i])!r}" + ("" if single else f" at pose {i}"),
                         field="kappa")
    return k.reshape(N)


def _max_sensitivities(J, mode, twist, walk, kappa):
    """:func:`max_sensitivities` after its checks of ``mode``, J and the cost."""
    N, L, _ = J.shape
    if twist is not None:
        # its shape only: the compiled study passes NaN at the poses it redoes in numpy
        twist = as_floats(twist, "twist", f"pinv(J), shape ({N}, 6, {L})")
        if twist.shape != (N, 6, L):
            raise InputError(f"expected pinv(J) of shape ({N}, 6, {L}), got shape "
                             f"{twist.shape}", field="twist")
    # J# only where it is used (L = 6 in slice mode takes the slab route on J itself)
    need_pinv = mode == "projection" or L != 6
    Gt = (np.linalg.pinv(J) if need_pinv else None) if twist is None else twist
    # Jᵀ: read in place by the slice kernels (transposed), copied once for projections
    Gw = np.ascontiguousarray(np.swapaxes(J, 1, 2)) if mode == "projection" else None
    if mode == "projection":
        c, r = np.zeros((N, L)), np.ones((N, L))
    out = {}
    for name, G, rows in (("translational", Gt, (0, 1, 2)), ("rotational", Gt, (3, 4, 5)),
                          ("force", Gw, (0, 1, 2)), ("torque", Gw, (3, 4, 5))):
        if mode == "projection":
            out[name] = zonotope_best(np.ascontiguousarray(G[:, list(rows), :]), c, r,
                                      [(0, 1, 2)])[0]
        elif name in ("translational", "rotational") and L == 6:
            # J# = J⁻¹: the slice is {u : |J_S u|∞ <= 1}, computed from J itself
            out[name] = slab_farthest_unit(J[:, :, list(rows)])
        elif G is None:
            out[name] = slice_farthest_unit(J, rows, walk=walk, transposed=True)
        else:
            out[name] = slice_farthest_unit(G, rows, walk=walk)
    if kappa is None:
        s = np.linalg.svd(J, compute_uv=False)
        kappa = np.divide(s[:, -1], s[:, 0], out=np.zeros(N), where=s[:, 0] > 0)
    kappa = np.asarray(kappa, dtype=float).reshape(N)
    sing = np.flatnonzero(~(kappa > RANK_TOL))
    if len(sing) and not need_pinv:
        # the slab route: its slices depend on J_S alone (σmin/σmax of J_S >= that of J)
        _flag_singular_slabs(out, J[sing], sing, N)
    elif len(sing):
        unb, deficient = _null_twist_reaches(J[sing], mode)
        for a, name in enumerate(("translational", "rotational")):
            out[name][sing[unb[:, a]]] = np.inf
        # the poses whose own SVD finds the rank deficiency (a caller's kappa of 0 at a
        # regular J, e.g. the study's for σ that overflowed, flags nothing)
        _flag_near_singular(out, sing[deficient], unb[deficient], kappa[sing][deficient],
                            J.shape[1], N)
    return out


def _flag_singular_slabs(out, J, idx, N):
    """The L = 6 slice route at the poses ``idx`` whose J is singular or nearly so
    (σmin/σmax <= RANK_TOL): the slice of a part S is the slab polytope
    ``{u : |J_S u|∞ <= 1}`` (:func:`.slice_farthest.slab_farthest_unit`), so its value
    is decided by J_S (6 × 3) alone, by κ_S = σmin/σmax of J_S:

    * κ_S <= :func:`.zonotope.flat_tol` (3, 6): J_S u = 0 for some u (to the rounding of
      its entries), i.e. a null twist (u, 0) of J reaches the part: unbounded, +inf;
    * flat_tol < κ_S <= RANK_TOL: the slab is bounded (its farthest point is about
      1/σmin of J_S) but its vertices solve 3 × 3 blocks of condition ~1/κ_S, and the
      tests of |J_S u| <= 1 cancel terms ~1/κ_S: float64 cannot give the value (the
      kernel's determinant test may reject every block, which gave +inf; a solve without its determinant test is
      off by 3e-4 relative at κ_S = 6e-14, tests/indices/test_sensitivity_slab_band.py):
      NaN and one :class:`~distkin.errors.ConditioningWarning`;
    * κ_S > RANK_TOL: the kernel's value (relative error about 1e-16 / κ_S), whatever
      κ of J (a null twist with both parts leaves both slabs bounded).

    J : ndarray (n, 6, 6), the poses ``idx`` (n,) of the N."""
    tol = flat_tol(3, J.shape[1])
    near_poses, example = np.zeros(len(J), bool), None
    for name, S in (("translational", [0, 1, 2]), ("rotational", [3, 4, 5])):
        s = np.linalg.svd(J[:, :, S], compute_uv=False)
        k = np.divide(s[:, -1], s[:, 0], out=np.zeros(len(J)), where=s[:, 0] > 0)
        near = (k > tol) & (k <= RANK_TOL)
        out[name][idx[~(k > tol)]] = np.inf
        out[name][idx[near]] = np.nan
        if near.any() and example is None:
            example = float(k[near][0])
        near_poses |= near
    if near_poses.any():
        _warn(ConditioningWarning(
            f"maximum sensitivities: {int(near_poses.sum())} of {N} pose(s) with a nearly "
            f"singular J whose translational or rotational columns J_S are nearly "
            f"singular themselves ({tol:.2g} < σmin/σmax of J_S <= RANK_TOL = "
            f"{RANK_TOL:g}, e.g. {example:.3g}): those twist sensitivities are NaN (the "
            "slab {u : |J_S u| <= 1} is bounded, its farthest point about 1/σmin, but "
            "float64 cannot give it)"))


def _flag_near_singular(out, sing, unb, kappa, L, N):
    """NaN + one ConditioningWarning for the finite twist sensitivities of a nearly (not
    exactly) singular J, flat_tol < σmin/σmax <= RANK_TOL, on the J# route: pinv(J)
    then has entries ~1/κ and the farthest point computed from it is not that of the
    set (QA Z2 3: 2.78 for 1.98 at κ = 3e-14); a part the near-null twist reaches is
    bounded too (about 1/σmin: +inf only at an exactly singular J).  An exactly singular J (σmin/σmax at
    the rounding level, :func:`.zonotope.flat_tol`) keeps the values of eq. (5) with
    the Moore-Penrose pinv, with another ConditioningWarning: J# is discontinuous
    there, and the limits from regular neighbours depend on the direction from which
    J is approached (the neighbours' sets keep a stretched copy of the null twist,
    weighted by the left singular vector the approach picks: e.g. L = 8 slice 0.913 at
    J against 1.071-1.094 m/rad towards four random directions, tests/indices/
    test_sensitivity_exact_singular.py; L = 6 projection 3.04 at J against 3.05-3.45).
    The L = 6 slab route (slice mode) works on J: :func:`_flag_singular_slabs`."""
    near = kappa > flat_tol(6, L)
    count = exact = 0
    for a, name in enumerate(("translational", "rotational")):
        # a part the near-null twist reaches too: bounded (about 1/σmin), not +inf
        bad = sing[near]
        out[name][bad] = np.nan
        count = max(count, len(bad))
        exact = max(exact, int(np.sum(np.isfinite(out[name][sing[~near & ~unb[:, a]]]))))
    if count:
        _warn(ConditioningWarning(
            f"maximum sensitivities: {count} of {N} pose(s) with a nearly singular J "
            f"({flat_tol(6, L):.2g} < σmin/σmax <= RANK_TOL = {RANK_TOL:g}, e.g. "
            f"{kappa[near][0]:.3g}): their twist sensitivities are NaN (pinv(J) cannot "
            "give them in float64)"))
    if exact:
        _warn(ConditioningWarning(
            f"maximum sensitivities: {exact} of {N} pose(s) with a singular J "
            f"(σmin/σmax <= {flat_tol(6, L):.2g}): their finite twist sensitivities are "
            "eq. (5)'s with the Moore-Penrose J#, which is discontinuous there (regular "
            "neighbours give other values, depending on the direction of approach)"))


#: a component of a unit null twist below this counts as zero (as zonotope._flat_worst)
_NULL_TOL = 1e-9


def _null_twist_reaches(J, mode):
    """``(reaches, deficient)``: (n, 2) bool, whether the null space of each J (σ below
    RANK_TOL·σmax) reaches the translational / rotational part (module docstring):
    projection, a null vector with a component in S; slice, one with zero S^c part
    (N_{S^c} of the orthonormal null basis N has a kernel); and (n,) bool, whether that
    null space is not empty."""
    _, s, Vt = np.linalg.svd(J)
    out = np.zeros((len(J), 2), bool)
    deficient = np.zeros(len(J), bool)
    for k in range(len(J)):
        rank = int(np.sum(s[k] > RANK_TOL * s[k, 0])) if s[k, 0] > 0 else 0
        Nb = Vt[k, rank:].T                                    # (6, r) orthonormal
        r = Nb.shape[1]
        deficient[k] = r > 0
        if r == 0:
            continue
        for a, (S, Sc) in enumerate((((0, 1, 2), (3, 4, 5)), ((3, 4, 5), (0, 1, 2)))):
            if mode == "projection":
                out[k, a] = np.linalg.norm(Nb[list(S)]) > _NULL_TOL
            else:
                sv = np.linalg.svd(Nb[list(Sc)], compute_uv=False)
                out[k, a] = r > len(Sc) or sv[-1] <= _NULL_TOL
    return out, deficient
