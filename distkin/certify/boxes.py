r"""Certified singularity-free workspace: interval branch-and-prune over boxes of poses.

Kühne et al. (*Design and Evaluation of a Haptic Interface With Octopod Kinematics*,
Sec. II-C-1, III-B-1, Fig. 3) detect direct-kinematic singularities with CuikSuite and
add that "this is not a formal proof since any numerical software tool has
tolerances", and that redundant kinematics such as the Octopod cannot be analysed with
it.  This module gives the proof, for L = 6 and for the redundant L = 8.

What a box ``X`` (m, rad; poses as in :mod:`distkin.spatial`) can be proved to be
----------------------------------------------------------------------------------------
``regular``
    For every pose in ``X``:

    1. every leg closes: the reach margin :math:`\rho_i^2 - C_i^2` of the IK equation
       :math:`A_i\cos q_i + B_i\sin q_i = C_i` (:mod:`distkin.mechanisms.symbolic`) is
       > 0, so both crank solutions exist, are distinct, and the IK branch of
       :mod:`distkin.mechanisms.presets` is a smooth function of the pose; and every
       crank of a leg with a revolute joint range is strictly inside it: the range
       margin :math:`\rho_i^2(\cos(q_i - m_i) - \cos w_i)` (m, w the range's middle
       and half-width; :func:`.intervals.margins`) is > 0 (a prismatic leg's stroke is
       its reach margin already);
    2. ``Jq`` is regular: every diagonal entry :math:`J_{q,ii} = \partial\Phi_i/\partial q_i`
       of eq. (1) is enclosed away from 0 (no inverse-kinematic singularity);
    3. ``Jx`` (L x 6, eq. (1)) has full column rank 6: no direct-kinematic
       singularity.  We certify ``Jx`` itself, not ``J = Jq^{-1} Jx``; with 2. the
       two are equivalent.

    The rank test is a preconditioned criterion around a midpoint factorisation
    (Rump 2010, Sec. 10): with :math:`Y \approx J_x(m)^+` (a floating-point
    pseudo-inverse at the midpoint ``m``; any matrix would do) and the enclosure
    :math:`J_x(p) \in J_0 + \sum_k T_k \varepsilon_k \pm e` of :mod:`.intervals`
    (``ε ∈ [-1, 1]``), every ``Jx`` of the box satisfies, entrywise,

    .. math:: |I_6 - Y J_x| \le B := |I_6 - Y J_0| + \sum_k |Y T_k| + |Y|\,e .

    If :math:`\rho(B) < 1` then :math:`\rho(I - Y J_x) \le \rho(|I - Y J_x|) \le
    \rho(B) < 1`, so :math:`Y J_x` is regular and :math:`\operatorname{rank} J_x = 6`.
    ``ρ(B) < 1`` is certified by Collatz-Wielandt: ``(B v)_i < v_i`` in ``arb`` for a
    positive float vector ``v`` (an approximate Perron vector); this is the scaled
    ∞-norm :math:`\|D^{-1}(I - Y J_x)D\|_\infty < 1`, ``D = diag(v)``, and it is
    invariant to the units of the columns of ``Jx``; so is ``v`` (:func:`perron_vectors`
    balances the off-diagonal blocks of ``B``, of order ``s`` and ``1/s`` for a device of
    length scale ``s``, before its regularised power iteration).  From it,
    :math:`\sigma_{\min}(J_x) \ge (1 - c)/(\sqrt 6\,\max_i v_i\,
    \max_i \|(D^{-1}Y)_{i,:}\|_2)` with ``c = max_i (Bv)_i/v_i``, reported as
    ``sigma_lower`` (same units as ``Jx``, L x 6: its first three columns (force) are
    dimensionless, its last three (moment) in m, so σ mixes them as eq. (1) does; a coarse bound, for information).  For
    L = 6, ``det Jx`` keeps one sign over the box (it is continuous and never 0 on a
    connected set); ``det_sign`` is that sign, certified at the midpoint.
``singular`` (L = 6 only)
    Every leg closes over ``X`` (so ``Jx`` is continuous on ``X``) and ``det Jx`` is
    certified positive at one pose of ``X`` and negative at another: by the
    intermediate value theorem on the segment between them, ``X`` contains a pose with
    ``det Jx = 0``.  Boxes are split down to the resolution before this is tried, so
    the singular boxes cover the singular surface at that resolution; their volume is
    an upper bound of a covering, the singular set itself has measure zero.  For
    L = 8 a rank loss of the 8 x 6 ``Jx`` is not a sign change of a scalar; such boxes
    stay ``undecided``.
``unreachable``
    Some leg's reach margin, or range margin, is < 0 over the whole box (no pose of
    ``X`` is assembled with every crank inside its range).
``undecided``
    None of the above at the resolution ``min_width``, or left unsplit when the box
    budget was spent (flagged ``budget`` by :func:`branch_and_prune`).

Enclosure forms (:data:`.intervals.FORMS`): ``quadratic`` (second-order Taylor
models, the default), ``affine`` (first order), ``centred`` (the mean-value form with
interval derivative enclosures) and ``plain`` (the natural interval extension); the
benchmark ``python -m benchmarks certify`` compares them.  ``auto`` tries ``affine``
and, where it fails the rank test, ``quadratic``.  ``quadratic64`` is the quadratic
form with binary64 coefficients and every rounding error in the remainder, evaluated on
batches of boxes (:mod:`.fptaylor`, :mod:`.batch`; the default of
:func:`.workspace.certify_workspace`, about 10x faster per box evaluated).

Accuracy: ``method="certified"`` only.  The certificates hold for the mechanism as the
generated kernels define it: parameters and the derived constants of
``distkin._generated.rss_<name>_arb`` are the binary64 numbers of the fast kernels,
taken exactly; box corners are binary64 numbers.  Nothing is decided by a float
comparison; floats only choose the preconditioner ``Y`` and the candidate points of a
sign change, which are then checked in ``arb``.

References
----------
R. E. Moore, R. B. Kearfott, M. J. Cloud, *Introduction to Interval Analysis*, SIAM,
2009 (centred forms, Sec. 6.4; branch and bound, Ch. 9).
S. M. Rump, Verification methods: rigorous results using floating-point arithmetic,
*Acta Numerica* 19 (2010), doi:10.1017/S096249291000005X (Sec. 10, regularity of
interval matrices by preconditioning).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..argcheck import as_floats, choice, float_array, positive_int
from ..errors import InputError
from .intervals import FORMS, enclose_box, point_values

__all__ = ["UNDECIDED", "REGULAR", "SINGULAR", "UNREACHABLE", "STATUS_NAMES", "Verdict",
           "regularity_certificate", "sign_change_certificate", "certify_box",
           "branch_and_prune", "split_dimension", "bisect", "leaves", "check_box",
           "check_resolution", "check_mechanism", "BOX_FORMS", "REASONS", "block_balance",
           "perron_vectors", "finite_rows"]

UNDECIDED, REGULAR, SINGULAR, UNREACHABLE = 0, 1, 2, 3
STATUS_NAMES = {UNDECIDED: "undecided", REGULAR: "regular", SINGULAR: "singular",
                UNREACHABLE: "unreachable"}
#: why a box was left undecided at the resolution, by code (the leaves' ``reason``): the
#: first test whose enclosure did not decide (a diagnosis, not a proof of what is in the
#: box): 0 none (decided, or left by the budget: ``budget``), 1 "reach" (a leg's reach
#: or range margin not enclosed away from 0: the edge of the reachable set, a leg's reach
#: limit or joint range, may cross the box),
#: 2 "jq" (a diagonal entry of Jq not enclosed away from 0: a serial singularity may
#: cross it), 3 "rank" (the regularity test of Jx failed: a parallel singularity may
#: cross it, or the enclosure is too wide at the resolution)
REASONS = {"": 0, "reach": 1, "jq": 2, "rank": 3}


@dataclass(frozen=True)
class Verdict:
    """The outcome of :func:`certify_box`.

    Attributes
    ----------
    status : int
        :data:`REGULAR`, :data:`SINGULAR`, :data:`UNREACHABLE` or :data:`UNDECIDED`.
    sigma_lower : float
        Regular boxes: a certified lower bound of σmin(Jx) over the box (may be 0.0:
        the bound is coarse); otherwise 0.0.
    det_sign : int
        L = 6 regular boxes: the sign of det Jx over the box; otherwise 0.
    reason : str
        Why a box is undecided: "reach" (a reach or range margin straddles 0), "jq" (a Jq entry
        not enclosed away from 0), "rank" (the rank test failed), "" otherwise.
    contraction : float
        Upper bound of the scaled norm of ``I - Y Jx`` over the box (inf if not
        computed; < 1 for a regular box).
    vary, weights : tuple
        The varying coordinates and, per coordinate, how much its term contributes to a
        failed test (for :func:`split_dimension`).
    """

    status: int
    sigma_lower: float = 0.0
    det_sign: int = 0
    reason: str = ""
    contraction: float = math.inf
    vary: tuple = ()
    weights: tuple = ()


#: enclosure forms of :func:`certify_box` and :func:`branch_and_prune`
BOX_FORMS = FORMS + ("auto",)


def check_mechanism(mech, field: str = "mech"):
    """``mech`` if it is a mechanism the certifier can use (its ``kernels`` and
    ``geometry_key``, e.g. :func:`distkin.mechanisms.preset`), else :class:`InputError`
    naming ``field`` (QA F8: None or a preset's name raised AttributeError)."""
    if not (callable(getattr(mech, "kernels", None)) and hasattr(mech, "geometry_key")
            and hasattr(mech, "L")):
        raise InputError(f"expected an RSS mechanism (distkin.mechanisms.preset(name) or an "
                         f"RSSMechanism), got {type(mech).__name__} {mech!r:.60}", field=field,
                         hint="build it with distkin.mechanisms.preset" if isinstance(mech, str)
                         else None)
    return mech


def check_box(lo, hi, names=("lo", "hi")):
    """The corners of a box of poses, checked at a public entry point: (6,) finite
    numbers (m for x, y, z; rad for rx, ry, rz), no booleans, ``lo <= hi``.  A box with
    its corners swapped or a NaN corner would otherwise be classified from one corner.

    Parameters
    ----------
    lo, hi : array_like (6,)
    names : (str, str)
        The argument names the messages give (``("lower", "upper")`` for a region).

    Returns
    -------
    lo, hi : ndarray (6,) float

    Raises
    ------
    InputError
        Naming the corner: not 6 finite numbers, a boolean, or ``lo[k] > hi[k]``.
    """
    a, b = names
    lo = float_array(lo, a, (6,))
    hi = float_array(hi, b, (6,))
    if np.any(hi < lo):
        k = int(np.argmax(hi < lo))
        raise InputError(f"expected {a} <= {b} (m for x, y, z; rad for rx, ry, rz), got "
                         f"{a}[{k}] = {float(lo[k])!r} > {b}[{k}] = {float(hi[k])!r}",
                         field=b)
    return lo, hi


def check_resolution(min_width, field: str = "min_width") -> np.ndarray:
    """A branch-and-prune resolution, checked: a positive finite number or 6 of them
    (m for x, y, z; rad for rx, ry, rz), no booleans (``True`` is not 1 m); a resolution
    <= 0 would bisect until the box budget runs out.  Returns it as an ndarray (6,)."""
    minw = as_floats(min_width, field, "a resolution (m, rad): a number or 6 numbers")
    if minw.shape not in ((), (6,)) or not np.all(np.isfinite(minw)) or np.any(minw <= 0):
        raise InputError(f"expected a positive finite resolution (m, rad), a number or 6 "
                         f"numbers, got {minw.tolist()!r}", field=field)
    return np.broadcast_to(minw, (6,)).astype(float)


def _down(x) -> float:
    """A double <= the arb ``x`` (for lower bounds)."""
    v = float(x.lower())
    return float(np.nextafter(v, -np.inf))


def _up(x) -> float:
    """A double >= the arb ``x``."""
    v = float(x.upper())
    return float(np.nextafter(v, np.inf))


def block_balance(B):
    """Power-of-two weights ``λ`` balancing the two 3×3 off-diagonal blocks of ``B``.

    ``B >= |I - Y Jx|`` mixes units: the columns 3..5 of ``Jx`` (moments) are in m, so
    ``B[:3, 3:]`` scales like a length ``s`` and ``B[3:, :3]`` like ``1/s``.  With
    ``D = diag(1, 1, 1, λ, λ, λ)`` and ``λ = 2^⌊e/2⌋`` (``e`` the binary exponent of
    ``ΣB[3:, :3] / ΣB[:3, 3:]``), ``D⁻¹ B D`` no longer depends on the device's
    physical scale: scaling every length by ``2^k`` scales ``λ`` by ``2^-k`` exactly, so
    the balanced matrix is the same to the bit.  ``B`` is a (..., 6, 6) array; returns
    ``λ`` of shape ``B.shape[:-2]`` (1 where the ratio is not a positive finite number).
    """
    with np.errstate(all="ignore"):
        r = B[..., 3:, :3].sum(axis=(-2, -1)) / B[..., :3, 3:].sum(axis=(-2, -1))
    ok = np.isfinite(r) & (r > 0)
    _, e = np.frexp(np.where(ok, r, 1.0))
    k = np.clip(np.floor_divide(e, 2), -400, 400)
    return np.where(ok, np.ldexp(1.0, k), 1.0)


def perron_vectors(B, iterations: int = 60):
    """Positive approximate Perron vectors of non-negative (..., 6, 6) matrices ``B``.

    Scale-invariant: the power iteration runs on ``D⁻¹ B D`` of :func:`block_balance`
    (so its regularisation ``1e-12 (max + 1)`` is relative to entries of one order) and
    ``v = D v_bal`` is normalised by a power of two (max in [0.5, 1)); a device scaled
    by ``2^k`` gets the same vector up to exact powers of two.  Any positive ``v`` is
    admissible for the Collatz-Wielandt test; this one makes ``max (B v)_i / v_i`` close
    to ``ρ(B)``.
    """
    B = np.asarray(B, dtype=float)
    lam = block_balance(B)
    d = np.ones(B.shape[:-1])
    d[..., 3:] = lam[..., None]
    with np.errstate(all="ignore"):
        Bb = B * d[..., None, :] / d[..., :, None]
        Bp = Bb + 1e-12 * (Bb.max(axis=(-2, -1), keepdims=True) + 1.0)
        v = np.ones(B.shape[:-1])
        for _ in range(iterations):
            w = np.einsum("...ij,...j->...i", Bp, v)
            s = w.max(axis=-1, keepdims=True)
            v = w / np.where(np.isfinite(s) & (s > 0), s, 1.0)
        v = np.where(np.all(np.isfinite(v), axis=-1, keepdims=True), v, 1.0)
        v = np.maximum(v, 1e-12) * d
        _, e = np.frexp(v.max(axis=-1, keepdims=True))
        return np.ldexp(v, -e)


def regularity_certificate(Y, jx0, jx_terms=(), jx_err=None):
    """The preconditioned rank test of the module docstring.

    Parameters
    ----------
    Y : ndarray (6, L)
        A floating-point preconditioner (pseudo-inverse of ``Jx`` at the midpoint).
    jx0, jx_terms, jx_err
        The enclosure ``Jx ∈ J0 + Σ_k T_k ε_k ± e`` of :class:`.intervals.BoxEnclosure`.

    Returns
    -------
    ok : bool
        ``ρ(B) < 1`` is certified for a non-negative ``B >= |I - Y Jx|`` entrywise, for
        every ``Jx`` enclosed (Collatz-Wielandt: ``B v < v`` for a positive ``v``), so
        ``Y Jx`` is regular and rank Jx = 6.
    contraction : float
        Upper bound of ``max_i (B v)_i / v_i`` (>= ρ(B)); inf if not finite.
    sigma_lower : float
        Certified lower bound of σmin(Jx) over the box (0.0 if ``ok`` is False):
        ``(1 - c) / (sqrt(6) max_i v_i max_i ||row_i(diag(v)^-1 Y)||_2)``.
    weights : list of float
        Per term ``T_k``: the sum of the bounds of ``|Y T_k|`` (which coordinate to
        split).
    """
    from flint import arb, arb_mat
    Ya = arb_mat(Y.tolist())
    E = arb_mat(6, 6, [arb(1) if i == j else arb(0) for i in range(6) for j in range(6)])
    E = E - Ya * arb_mat(jx0)
    Ba = [[abs(E[i, j]).upper() for j in range(6)] for i in range(6)]
    weights = []
    for T in jx_terms:
        M = Ya * arb_mat(T)
        wk = arb(0)
        for i in range(6):
            for j in range(6):
                m = abs(M[i, j]).upper()
                Ba[i][j] += m
                wk += m
        weights.append(float(wk.mid()) if wk.is_finite() else math.inf)
    if jx_err is not None:
        M = arb_mat(np.abs(Y).tolist()) * arb_mat(jx_err)
        for i in range(6):
            for j in range(6):
                Ba[i][j] += abs(M[i, j]).upper()
    if not all(x.is_finite() for row in Ba for x in row):
        return False, math.inf, 0.0, weights
    B = np.array([[_up(x) for x in row] for row in Ba])
    v = perron_vectors(B)
    Bv = [sum((arb(float(B[i, j])) * arb(float(v[j])) for j in range(6)), arb(0))
          for i in range(6)]
    ratios = [Bv[i] / arb(float(v[i])) for i in range(6)]
    c = max(_up(r) for r in ratios)
    ok = all(r < 1 for r in ratios)
    sigma = 0.0
    if ok:
        cmax = ratios[0]
        for r in ratios[1:]:
            cmax = cmax.max(r)
        rn = arb(0)
        for i in range(6):
            s2 = arb(0)
            for j in range(Y.shape[1]):
                t = arb(float(Y[i, j])) / arb(float(v[i]))
                s2 += t * t
            rn = rn.max(s2.sqrt())
        denom = arb(6).sqrt() * arb(float(v.max())) * rn
        sigma = max(0.0, _down((1 - cmax) / denom))
    return ok, c, sigma, weights


def _det_sign(jx) -> int:
    from flint import arb_mat
    d = arb_mat(jx).det()
    return 1 if d > 0 else (-1 if d < 0 else 0)


def sign_change_certificate(mech, kernels, lo, hi):
    """Two poses of the box with certified opposite signs of det Jx (L = 6), or None.

    Candidates are the box's corners (over the varying coordinates) and its midpoint,
    ranked by the fast float kernels; the extreme two are then evaluated in ``arb``.

    Returns
    -------
    (pose_neg, pose_pos) : two arrays (6,), or None
    """
    lo = np.asarray(lo, dtype=float)
    hi = np.asarray(hi, dtype=float)
    vary = [k for k in range(6) if hi[k] > lo[k]]
    pts = np.repeat(lo[None], 2 ** len(vary), axis=0)
    for b in range(2 ** len(vary)):
        for j, k in enumerate(vary):
            if (b >> j) & 1:
                pts[b, k] = hi[k]
    mid = np.clip(lo + 0.5 * (hi - lo), lo, hi)
    pts = np.vstack([pts, mid[None]])
    _, Jx = mech.jq_jx(pts)
    d = np.linalg.det(Jx)
    i, j = int(np.argmin(d)), int(np.argmax(d))
    if not (d[i] < 0 < d[j]):
        return None
    sn = _det_sign(point_values(kernels, pts[i])[2])
    sp = _det_sign(point_values(kernels, pts[j])[2])
    if sn == -1 and sp == 1:
        return pts[i], pts[j]
    return None


def certify_box(mech, kernels, lo, hi, *, form: str = "quadratic",
                at_resolution: bool = False) -> Verdict:
    """Classify one box (module docstring).

    Parameters
    ----------
    mech : RSSMechanism
    kernels : KernelSet
        ``mech.kernels("arb")``.
    lo, hi : array (6,)
        Box corners (m, rad).
    form : {"quadratic", "affine", "centred", "plain", "auto"}
        Enclosure of ``Jx`` and of the reach margins (:mod:`.intervals`); ``auto``:
        ``affine``, then ``quadratic`` where the first fails.  (The binary64 form
        ``quadratic64`` works on batches: :func:`.batch.certify_batch`.)
    at_resolution : bool
        The box will not be split: also try the singular certificate (L = 6).

    Returns
    -------
    Verdict
        ``weights`` (per varying coordinate) says which split would help most.

    Raises
    ------
    InputError
        ``lo``, ``hi`` not 6 finite numbers each with ``lo <= hi`` (:func:`check_box`).
    """
    lo, hi = check_box(lo, hi)
    form = choice(form, "form", BOX_FORMS)
    return _certify_box(mech, kernels, lo, hi, form=form, at_resolution=at_resolution)


def _certify_box(mech, kernels, lo, hi, *, form: str = "quadratic",
                 at_resolution: bool = False) -> Verdict:
    """:func:`certify_box` of corners already checked (the branch-and-prune loops)."""
    if form == "auto":
        first = _certify_box(mech, kernels, lo, hi, form="affine", at_resolution=False)
        if first.status != UNDECIDED or first.reason == "reach":
            return first
        second = _certify_box(mech, kernels, lo, hi, form="quadratic",
                              at_resolution=at_resolution)
        if second.status == UNDECIDED and first.contraction < second.contraction:
            return Verdict(UNDECIDED, reason=first.reason, contraction=first.contraction,
                           vary=first.vary, weights=first.weights) if not at_resolution \
                else _singular_or(mech, kernels, lo, hi, first)
        return second
    enc = enclose_box(kernels, lo, hi, form=form)
    if any(r < 0 for r in enc.reach):
        return Verdict(UNREACHABLE)
    if not all(r > 0 for r in enc.reach):
        open_legs = [i for i, r in enumerate(enc.reach) if not r > 0]
        return Verdict(UNDECIDED, reason="reach", vary=enc.vary,
                       weights=tuple(finite_rows(enc.reach_weights[open_legs]).sum(axis=0)))
    if enc.jq is None or not all(q > 0 or q < 0 for q in enc.jq):
        # every leg closes, so Jx is continuous on the box: a sign change of det Jx is
        # a singular box whatever Jq does (it was reported "jq" before, QA P)
        if at_resolution and mech.L == 6 and enc.vary \
                and sign_change_certificate(mech, kernels, lo, hi) is not None:
            return Verdict(SINGULAR)
        return Verdict(UNDECIDED, reason="jq", vary=enc.vary)
    _, Jxm = mech.jq_jx(enc.mid)
    Y = np.linalg.pinv(Jxm) if np.all(np.isfinite(Jxm)) else np.zeros((6, mech.L))
    ok, contraction, sigma, tw = regularity_certificate(Y, enc.jx0, enc.jx_terms, enc.jx_err)
    weights = [0.0] * len(enc.vary)
    for w, dims in zip(tw, enc.term_dims):
        for j in dims:
            weights[j] += w / len(dims)
    if ok:
        sign = 0
        if mech.L == 6:
            jm = enc.jx0 if form == "centred" else point_values(kernels, enc.mid)[2]
            sign = _det_sign(jm)
        return Verdict(REGULAR, sigma, sign, "", contraction)
    if at_resolution and mech.L == 6 and enc.vary:
        if sign_change_certificate(mech, kernels, lo, hi) is not None:
            return Verdict(SINGULAR, contraction=contraction)
    return Verdict(UNDECIDED, reason="rank", contraction=contraction, vary=enc.vary,
                   weights=tuple(weights))


def _singular_or(mech, kernels, lo, hi, verdict):
    if mech.L == 6 and sign_change_certificate(mech, kernels, lo, hi) is not None:
        return Verdict(SINGULAR, contraction=verdict.contraction)
    return verdict


def finite_rows(w):
    """The rows of the margins' split weights ``w`` (m, n) that are finite; the others
    zero.  A range margin is not finite where its leg's reach margin straddles 0 (the
    square root at its branch point): its weights, inf or NaN, said "any coordinate"
    and the first one was split (review of the ranges' commit: 2.3x the boxes for the
    same volumes); that leg's reach row still points the split."""
    w = np.asarray(w, dtype=float)
    return np.where(np.all(np.isfinite(w), axis=-1, keepdims=True), w, 0.0)


def split_dimension(lo, hi, min_width, verdict=None):
    """The coordinate to bisect, None at the resolution.

    Among the coordinates wider than ``min_width``: the one whose term contributes
    most to the failed test (``verdict.weights``, the "smear" rule of interval
    branch-and-bound), else the widest relative to its ``min_width``.
    """
    width = np.asarray(hi) - np.asarray(lo)
    open_ = width > np.asarray(min_width)
    if not open_.any():
        return None
    rel = np.where(open_, width / np.asarray(min_width), -np.inf)
    if verdict is not None and verdict.weights and len(verdict.weights) == len(verdict.vary):
        score = np.full(6, -np.inf)
        for k, wk in zip(verdict.vary, verdict.weights):
            if open_[k]:
                score[k] = wk if np.isfinite(wk) else 1e300
        if np.isfinite(score).any() and score.max() > 0:
            return int(np.argmax(score))
    return int(np.argmax(rel))


def branch_and_prune(mech, lo, hi, min_width, *, form: str = "quadratic",
                     max_boxes: int = 200_000) -> dict:
    """Branch-and-prune over one box of poses.

    Parameters
    ----------
    mech : RSSMechanism
    lo, hi : array (6,)
        The region (m, rad), ``lo <= hi``.
    min_width : float or array (6,)
        A box is bisected along coordinate k only while wider than ``min_width[k]``
        (m or rad, positive; the resolution).
    form : {"quadratic", "affine", "centred", "plain"}
        (``quadratic64``: :func:`.batch.branch_and_prune_batched`.)
    max_boxes : int
        Budget of box evaluations; boxes left when it is spent are returned undecided,
        flagged in ``budget`` (not undecided at the resolution: QA F4).

    Returns
    -------
    dict of ndarray
        ``lo, hi`` (n, 6), ``status`` (n,) int8 (:data:`STATUS_NAMES`),
        ``sigma_lower`` (n,), ``det_sign`` (n,) int8, ``budget`` (n,) bool (undecided
        because the budget ran out), ``reason`` (n,) int8 (why undecided at the
        resolution, :data:`REASONS`), ``evaluated`` (): the number of boxes evaluated,
        ``seconds`` ().

    Raises
    ------
    InputError
        ``lo``, ``hi`` not 6 finite numbers each with ``lo <= hi`` (:func:`check_box`);
        a resolution not positive and finite (:func:`check_resolution`); ``mech`` not a
        mechanism, an unknown ``form``, ``max_boxes`` < 1.
    """
    t0 = time.perf_counter()
    check_mechanism(mech)
    lo, hi = check_box(lo, hi)
    minw = check_resolution(min_width)
    form = choice(form, "form", BOX_FORMS)
    max_boxes = positive_int(max_boxes, "max_boxes")
    ks = mech.kernels("arb")
    stack = [(lo, hi)]
    out_lo, out_hi, status, sigma, dsign, why = [], [], [], [], [], []
    budget = []                          # indices of the leaves left by the budget
    evaluated = 0
    while stack:
        blo, bhi = stack.pop()
        if evaluated >= max_boxes:
            budget.append(len(status))
            out_lo.append(blo)
            out_hi.append(bhi)
            status.append(UNDECIDED)
            sigma.append(0.0)
            dsign.append(0)
            why.append(0)
            continue
        at_res = split_dimension(blo, bhi, minw) is None
        v = _certify_box(mech, ks, blo, bhi, form=form, at_resolution=at_res)
        evaluated += 1
        if v.status in (REGULAR, UNREACHABLE, SINGULAR) or at_res:
            out_lo.append(blo)
            out_hi.append(bhi)
            status.append(v.status)
            sigma.append(v.sigma_lower)
            dsign.append(v.det_sign)
            why.append(REASONS.get(v.reason, 0) if v.status == UNDECIDED else 0)
            continue
        k = split_dimension(blo, bhi, minw, v)
        left, right = bisect(blo, bhi, k)
        stack.append(right)
        stack.append(left)
    return leaves(out_lo, out_hi, status, sigma, dsign, evaluated, t0, budget, why)


def bisect(lo, hi, k):
    """The two halves ``(lo, hi)`` of a box cut at the midpoint of coordinate ``k``."""
    c = lo[k] + 0.5 * (hi[k] - lo[k])
    left_hi, right_lo = hi.copy(), lo.copy()
    left_hi[k] = c
    right_lo[k] = c
    return (lo, left_hi), (right_lo, hi)


def leaves(out_lo, out_hi, status, sigma, dsign, evaluated, t0, budget=(),
           reason=None) -> dict:
    """The result dict of :func:`branch_and_prune` from lists of leaves; ``budget``:
    the indices of the undecided leaves left when the box budget ran out; ``reason``:
    per leaf, why it is undecided at the resolution (:data:`REASONS` codes)."""
    spent = np.zeros(len(status), dtype=bool)
    spent[list(budget)] = True
    why = np.zeros(len(status), np.int8) if reason is None else np.array(reason, np.int8)
    return {"lo": np.array(out_lo).reshape(-1, 6), "hi": np.array(out_hi).reshape(-1, 6),
            "status": np.array(status, dtype=np.int8),
            "sigma_lower": np.array(sigma, dtype=float),
            "det_sign": np.array(dsign, dtype=np.int8), "budget": spent, "reason": why,
            "evaluated": np.array(evaluated), "seconds": np.array(time.perf_counter() - t0)}
