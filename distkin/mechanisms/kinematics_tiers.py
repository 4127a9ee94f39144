r"""The three tiers of the inverse kinematics and the Jacobian of RSS and leg mechanisms.

Kühne et al., Sec. II-C, eqs. (1)-(2): per leg the closure gives
:math:`A\cos q + B\sin q = C`, the crank angle
:math:`q = \operatorname{atan2}(B C - \sigma A h,\ A C + \sigma B h)` with
:math:`h = \sqrt{\rho^2 - C^2}`, :math:`\rho^2 = A^2 + B^2` (:mod:`.symbolic`), and
:math:`J = J_q^{-1} J_x` with a diagonal :math:`J_q`; a prismatic leg has
:math:`q = |P - B|`, :math:`J_{q,ii} = -1` and its normalised Plücker line as row of J
(Rojas et al., eq. (5)).

``fast``
    the batched generated kernels in float64 (:class:`.kinematics.KernelMethods`).
    Error estimate of q (first order, not a bound): the closure residual
    :math:`|\Phi_i(q_i)| / |J_{q,ii}|` of the float answer plus 2 eps max(|q|, 1), plus
    the rounding of the leg's data at the pose (P, w, A, B, C: :func:`_fast_ik_error`),
    plus for a revolute leg the cancellation in :math:`\rho^2 - C^2` (rounding
    :math:`\delta m = 4\,\mathrm{eps}\,\rho^2` moves q by
    :math:`\delta m / (2 \rho \sqrt{\max(|m|, \delta m)})`: up to
    :math:`\sqrt{\mathrm{eps}}` at the reach boundary).  Whether a leg closes is the sign
    of its reach margin, decided only beyond the margin's own error estimate
    (:func:`.fast_errors.reach_margin_error`): within it the leg is ``reach_undecided``,
    with a :class:`~distkin.errors.ConditioningWarning`.  Of Jq, Jx and J: first-order
    propagation of that IK error :math:`\delta q_i` and of the rounding into the
    formulas at q (:func:`_fast_jacobian_error`),

    .. math::
        \delta J_{q,ii} = 4\,\mathrm{eps}\max(|J_{q,ii}|, \ell)
            + |\partial J_{q,ii}/\partial q_i|\,\delta q_i, \qquad
        \delta J_{x,ij} = 4\,\mathrm{eps}\max_k |J_{x,ik}|
            + |\partial J_{x,ij}/\partial q_i|\,\delta q_i,

    .. math::
        \delta J_{ij} = (\delta J_{x,ij} + |J_{ij}|\,\delta J_{q,ii}) / |J_{q,ii}|

    (ℓ the mechanism's length scale; the q-derivatives of
    :func:`.reference.jacobian_q_derivatives`).
    Near a serial singularity, which for an RSS leg is its reach boundary
    (:math:`J_{q,ii} = \mp l_1 h / l_3 \to 0`), the IK's :math:`\delta q \sim \delta m /
    (2\rho h)` gives J a relative error of about :math:`\delta m / (2 h^2)`: 1e-12 at
    0.1 mm from the boundary, 1e-6 at 1e-10 m, O(1) at it.  Where that first-order
    figure exceeds :data:`J_FIRST_ORDER` of the row the estimate is ``inf`` (the
    linearisation fails: the margin's rounding is comparable to the margin), and a pose
    with a row above :data:`J_REL_USEFUL` is flagged (``TieredJacobian.inaccurate``, a
    :class:`~distkin.errors.ConditioningWarning`): float64 cannot give J there, the
    precise or certified tier can.
``precise``
    the arb-flavour generated kernels (``ik_arb``, ``reach_arb``, ``jq_jx_arb``:
    only ``+ - * /``, ``abs``, ``sqrt``, ``sin``, ``cos``, ``atan2`` and ``_A(number)``)
    run on mpmath numbers at ``dps`` digits (:class:`MPNumber` of :mod:`.mpmath_kernels`
    gives mpmath those methods; the kernels' rational constants are divided at those
    digits, from exact integers).  Error estimate of the float64 value given (``q``,
    ``J``, ...): the difference of the ``dps``-digit value from a second evaluation at
    ``dps + GUARD`` digits, at least :math:`10^{1-dps}\max(|v|, 1)`, plus its rounding to
    float64; an estimate, not a bound.  The ``dps``-digit numbers themselves are in
    ``values``.  A revolute leg that does not close (reach margin < 0 at either number
    of digits) has numbers but no answer: its q, Jq, Jx and J errors are ``inf`` and it
    is not ``valid``, as in the fast tier's J.  Where J has no value, a leg with :math:`J_{q,ii} = 0` exactly (a serial
    singularity: a revolute leg at its reach boundary) or a prismatic leg of zero length
    (its line 0/0) at either number of digits, the Jacobian raises
    :class:`~distkin.errors.SingularConfigurationError` naming the pose and leg; near
    such a leg it is an estimate like any other (the second evaluation shows the digits
    lost).
``certified``
    the same kernels on python-flint ``arb`` balls at ``bits`` of working precision.
    The pose is taken exactly: a float64 pose (m, rad) is its exact binary value.  So
    is the mechanism: the arb kernels are derived from the *exact model*
    (:class:`.symbolic.ModelExprs` with ``exact=True``): an RSS mechanism's parameters
    (SI floats) and a leg table's numbers, each its exact binary value, the pair
    azimuths' trigonometry exact and cos, sin of beta and gamma evaluated on balls;
    sympy keeps every product and quotient of them exact (1/(2 l1) is a rational,
    rounded only on the ball), so each ball encloses the exact answer for the
    mechanism as stated (the closure of :mod:`.legs`), and every kernel (IK, Jacobian,
    closure) describes the same one (tests/mechanisms/test_certified_exact.py: against
    the closed form in mpmath at 60 digits).  The fast kernels round it to float64 (their
    constants ~1e-16 relative off), which their error estimates cover
    (tests/mechanisms/test_kinematics_tiers.py).  A leg is *certified* when its reach
    margin :math:`\rho^2 - C^2` is certainly > 0 (a ball containing 0 is the branch
    point :math:`h = 0` of the two assembly branches, which no ball decides),
    its angle ball is finite (not on the ±π cut of atan2), its joint range (if any)
    decided, and, for the Jacobian, its :math:`J_{q,ii}` ball excludes 0 (a serial
    singularity).  Every other leg is named, with the reason, in ``reasons``; the
    methods of :class:`.kinematics.KernelMethods` raise :class:`UncertifiedError` (or
    :class:`InfeasibleError` where the leg certainly does not close) instead of
    returning them.

Units: q in rad (revolute legs) or m (prismatic legs); J columns 1-3 per m, 4-6 per rad;
``Jq`` in m/rad (revolute; the closures are in m) or m/m (prismatic); reach margins m^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import (ConditioningWarning, InfeasibleError, InputError,
                      SingularConfigurationError, UncertifiedError)
from ..exact import check_method, default_dps, float_ball
from .description import _poses, read_only
from .fast_errors import fast_ik_error as _fast_ik_error
from .fast_errors import _leg_terms, reach_decision, reach_margin_error
from .mpmath_kernels import GUARD, MPNumber, _to_float, estimate, on_mpmath, precise_runs
from ..errors import warn as _warn

__all__ = ["MPNumber", "on_mpmath", "TieredIK", "TieredJacobian", "ik_tier", "jacobian_tier",
           "raise_uncertified", "check_bits", "check_dps", "GUARD", "BITS", "J_REL_USEFUL",
           "J_FIRST_ORDER"]

#: working precision (bits) of the certified tier's balls
BITS = 128
#: fast tier: a pose is flagged ``inaccurate`` when the error estimate of a row of J
#: exceeds this fraction of the row's largest entry (more than 10 of float64's 16 digits
#: lost; near a leg's reach boundary, within about 1e-10 m of it on the presets)
J_REL_USEFUL = 1e-6
#: fast tier: beyond this fraction of the row the first-order estimate of J is not
#: one (the rounding of the reach margin is comparable to the margin): ``inf``
J_FIRST_ORDER = 0.1
_EPS = np.finfo(float).eps


def _arb_kernels(mech):
    if getattr(mech, "route", "generated") == "numpy":
        raise InputError("expected route 'generated' for the precise and certified tiers "
                         "(they run the generated arb-flavour kernels), got 'numpy'",
                         field="route")
    return mech.kernels("arb")


_is_zero = np.vectorize(lambda v: v == 0, otypes=[bool])


def _precise_singular(hit, what, why, dps):
    """Raise :class:`SingularConfigurationError` naming the first pose and leg of the
    (N, L) bool ``hit`` (a leg ``what`` at ``dps`` or ``dps + GUARD`` digits, so ``why``)."""
    if not hit.any():
        return
    i, j = (int(k) for k in np.argwhere(hit)[0])
    more = int(hit.sum()) - 1
    raise SingularConfigurationError(
        f"expected a finite Jacobian at pose {i}, got leg {j + 1} {what} (at {dps} or "
        f"{dps + GUARD} digits)" + (f" (and {more} more leg(s))" if more else "")
        + f": {why}", field="poses",
        hint="method='certified' names every such leg with its reason")


def _precise_jacobian(mech, ks, X, dps, prec):
    """The precise tier of :func:`jacobian_tier` (module docstring).  The IK first, so
    a prismatic leg of zero length (its line 0/0), then a leg with Jq_ii = 0 exactly (a
    serial singularity: J = Jx / Jq unbounded) is named in a
    :class:`SingularConfigurationError`, not mpmath's ZeroDivisionError."""
    import mpmath
    runs = precise_runs(ks, ("reach", "ik"), X, dps)
    pris = np.asarray(mech.leg_arrays()["prismatic"])
    _precise_singular(pris[None] & np.any([_is_zero(r["ik"]) for r in runs], axis=0),
                      "(prismatic) of zero length", "its line, its row of J, is undefined",
                      dps)
    for run, more in zip(runs, precise_runs(ks, ("jq_jx",), X, dps)):
        run.update(more)
    _precise_singular(np.any([_is_zero(r["jq_jx"][..., 0]) for r in runs], axis=0),
                      "at a serial singularity, Jq_ii = 0 exactly", "J = Jx / Jq is unbounded "
                      "(the leg at its reach boundary, crank and distal link aligned)", dps)
    for run, digits in zip(runs, (dps, dps + GUARD)):
        with mpmath.workdps(digits):
            run["J"] = run["jq_jx"][..., 1:] / run["jq_jx"][..., :1]
    vals, ref = runs
    jq, jx = vals["jq_jx"][..., 0], vals["jq_jx"][..., 1:]
    open_ = _open_legs(mech, runs)
    err = np.where(open_[..., None], np.inf, estimate(vals["jq_jx"], ref["jq_jx"], dps))
    valid = mech._valid(_to_float(vals["ik"]), _to_float(vals["reach"]))
    none = np.zeros(valid.shape, dtype=bool)
    return TieredJacobian("precise", prec, _to_float(vals["J"]),
                          np.where(open_[..., None], np.inf, estimate(vals["J"], ref["J"], dps)),
                          _to_float(jq), err[..., 0], _to_float(jx), err[..., 1:], valid, none,
                          (), vals["J"], jq, jx, none.copy(), np.zeros(len(X), dtype=bool))


_is_negative = np.vectorize(lambda v: v < 0, otypes=[bool])


def _open_legs(mech, runs):
    """(N, L) bool: the revolute legs that do not close (reach margin < 0 at ``dps``
    or ``dps + GUARD`` digits, the two ``runs`` of :func:`.mpmath_kernels.precise_runs`
    with "reach").  Their q, Jq, Jx and J are numbers of no closure; the precise tier
    gives them an infinite error, as the fast tier's J (QA T 2)."""
    return (~np.asarray(mech.leg_arrays()["prismatic"])[None]
            & np.any([_is_negative(r["reach"]) for r in runs], axis=0))


def _certified_eval(ks, names, X, bits):
    """{name: object array of arb} of the kernels ``names`` at the exact poses X."""
    from flint import arb

    from ..exact_roots import working_precision
    out = {}
    with working_precision(bits):
        for n in names:
            fn = getattr(ks, n)
            out[n] = np.array([_as_ball(fn([arb(float(c)) for c in x])) for x in X],
                              dtype=object)
    return out


def _as_ball(v):
    from flint import arb
    if isinstance(v, list):
        return [_as_ball(x) for x in v]
    return v if isinstance(v, arb) else arb(v)


_mid = np.vectorize(lambda b: float(b.mid()) if b.is_finite() else math.nan, otypes=[float])
#: (float mids, the radii about them that enclose the balls) of an array of balls, in one
#: pass (:func:`~distkin.exact.float_ball`; nan, inf where a ball is not finite)
_split = np.vectorize(float_ball, otypes=[float, float])


def _ball_text(b, unit):
    if not b.is_finite():
        return f"[not finite] {unit}".rstrip()
    return f"{float(b.mid()):.10g} ± {float_ball(b)[1]:.2g} {unit}".rstrip()


@dataclass(frozen=True)
class TieredIK:
    """Inverse kinematics at one tier (module docstring), arrays (N, L).

    Attributes
    ----------
    method : str
    precision : str
        "float64", "mpmath at D digits" or "arb at B bits".
    q : float array, rad (revolute) or m (prismatic)
        The fast values; the precise ones rounded to float64; the balls' midpoints.
    q_error : float array, same units
        Of the float ``q`` itself: an error estimate (fast; precise, with ``q``'s rounding
        to float64) or a certified radius (the ball within ``q +- q_error``: its radius
        and the rounding of its midpoint to ``q``, :func:`~distkin.exact.float_ball`;
        inf where not finite).  The tier's own numbers, more digits, are ``values``.
    reach_margin : float array, m^2
    valid : bool array
        The leg closes and q is in its joint range (certified tier: certainly so).
    certified : bool array
        Certified tier: the leg's answer is certified (module docstring); else False.
    reasons : tuple of (pose, leg, str)
        Certified tier: why each uncertified leg is not (0-based pose and leg).
    values : object array or None
        The tier's own numbers (mpmath mpf, flint arb); None for ``fast``.
    infeasible : bool array
        Certified tier: the leg certainly does not close.
    reach_undecided : bool array
        The leg's reach margin is within the tier's accuracy of 0, which decides
        nothing: it is at its reach boundary (a prismatic leg at a stroke end) within
        rounding.  fast: |margin| below its error estimate
        (:func:`.fast_errors.reach_margin_error`; ``valid`` is then the float sign's
        guess, wrong either way in that band, QA 25a finding 2); precise: below its
        estimate (the second run); certified: the margin's ball contains 0 (the leg is
        also named in ``reasons``).  The fast and precise tiers warn
        (:class:`~distkin.errors.ConditioningWarning`).
    """

    method: str
    precision: str
    q: np.ndarray
    q_error: np.ndarray
    reach_margin: np.ndarray
    valid: np.ndarray
    certified: np.ndarray
    reasons: tuple
    values: np.ndarray | None
    infeasible: np.ndarray
    reach_undecided: np.ndarray | None = None

    def __post_init__(self):
        read_only(self)


@dataclass(frozen=True)
class TieredJacobian:
    """J = Jq^-1 Jx (eqs. (1)-(2)) at one tier: ``J``, ``Jx`` (N, L, 6), ``Jq`` (N, L)
    as floats with ``*_error`` alike (estimates, inf where the fast tier's first-order
    estimate fails, or certified radii), ``valid``, ``certified``, ``reasons``,
    ``infeasible`` as :class:`TieredIK`, the tier's own numbers ``values`` (J),
    ``jq_values``, ``jx_values`` (None for ``fast``), and ``inaccurate`` (N,) bool: fast
    tier, a row of J whose estimated error exceeds :data:`J_REL_USEFUL` of the row (a
    leg at or next to its reach boundary, a serial singularity; module docstring):
    float64 does not give J there, use ``method="precise"``.  False in the other tiers
    (the precise estimate and the certified radii cover themselves)."""

    method: str
    precision: str
    J: np.ndarray
    J_error: np.ndarray
    Jq: np.ndarray
    Jq_error: np.ndarray
    Jx: np.ndarray
    Jx_error: np.ndarray
    valid: np.ndarray
    certified: np.ndarray
    reasons: tuple
    values: np.ndarray | None
    jq_values: np.ndarray | None
    jx_values: np.ndarray | None
    infeasible: np.ndarray
    inaccurate: np.ndarray | None = None
    ik: object = None       # certified: the TieredIK its rows come from (reach_undecided)

    def __post_init__(self):
        read_only(self)


def check_bits(bits, method: str, field: str = "bits") -> int:
    """The certified tier's working precision: ``bits`` (an integer 53..4096, given only
    with method "certified") or :data:`BITS`; :class:`InputError` naming ``field``."""
    if bits is None:
        return BITS
    if not (isinstance(bits, (int, np.integer)) and not isinstance(bits, bool)
            and 53 <= bits <= 4096):
        raise InputError(f"expected bits as an integer 53..4096, got {bits!r}", field=field)
    if method != "certified":
        raise InputError(f"expected 'bits' with method 'certified' (the working precision "
                         f"of its balls), got method {method!r}", field=field,
                         hint="method='certified' with bits, or method='precise' with dps")
    return int(bits)


def check_dps(dps, method: str, field: str = "dps") -> int | None:
    """The precise tier's digits: ``dps`` (an integer 5..1233, given only with method
    "precise", as ``bits`` only with "certified": :func:`check_bits`; a scene's
    :func:`~distkin.argcheck.dps_field` the same) or its default
    (:func:`~distkin.exact.default_dps`); None for the other tiers.
    :class:`InputError` naming ``field``."""
    if dps is None:
        return default_dps(None) if method == "precise" else None
    try:
        digits = default_dps(dps)
    except InputError as exc:
        raise InputError(exc.message, field=field) from None
    if method != "precise":
        raise InputError(f"expected 'dps' only with method 'precise' (the mpmath digits), "
                         f"got method {method!r}", field=field,
                         hint="method='precise' with dps, or method='certified' with bits")
    return digits


def _setup(mech, poses, method, dps, bits):
    check_method(method)
    X, _ = _poses(poses, scale=mech.length_scale)
    dps = check_dps(dps, method)
    bits = check_bits(bits, method)
    prec = {"fast": "float64", "precise": f"mpmath at {dps} digits",
            "certified": f"arb at {bits} bits"}[method]
    return X, dps, bits, prec


def _fast_jacobian_error(mech, X, q, J, Jq, Jx):
    """Error estimates of the fast Jq (N, L), Jx and J (N, L, 6), first order (module
    docstring): the IK error (:func:`_fast_ik_error`) through the q-derivatives of
    :func:`.reference.jacobian_q_derivatives`, and the rounding at q; J's ``inf`` where
    the formula gives no finite J or the estimate exceeds :data:`J_FIRST_ORDER` of its
    row (so also for a leg that does not close: its closure residual is its IK error).
    Also the (N,) flag ``inaccurate``: a leg that closes with a row above
    :data:`J_REL_USEFUL`.  ``q``: the IK at ``X``, ``Jq``, ``Jx``, ``J`` the fast ones
    (computed once by the caller)."""
    margin = mech.reach_margin(X)
    from .reference import jacobian_q_derivatives
    with np.errstate(divide="ignore", invalid="ignore"):    # a prismatic leg of length 0
        phi = mech.kernels("batched").closure(q, X)[..., 0]
        djq, djx = jacobian_q_derivatives(mech, X, q)
    dq = _fast_ik_error(mech, X, q, margin, phi, Jq)
    aq = np.abs(Jq)
    jq_err = 4 * _EPS * np.maximum(aq, mech.length_scale) + np.abs(djq) * dq
    jx_err = (4 * _EPS * np.max(np.abs(Jx), axis=-1, keepdims=True)
              + np.abs(djx) * dq[..., None])
    with np.errstate(divide="ignore", invalid="ignore"):
        err = (jx_err + np.abs(J) * jq_err[..., None]) / aq[..., None]
        rel = np.max(err, axis=-1) / np.max(np.abs(J), axis=-1)
    bad = ~np.all(np.isfinite(J), axis=-1) | ~(rel <= J_FIRST_ORDER)
    err = np.where(bad[..., None], np.inf, err)
    # of the legs that close (a leg that does not has no J: its Phi != 0 makes it inf)
    inaccurate = np.any((bad | (rel > J_REL_USEFUL)) & (margin >= 0), axis=-1)
    return jq_err, jx_err, err, inaccurate


def _range_check(mech, qv, i, j, reasons):
    """Certified joint-range test of ball ``qv`` of pose i, leg j, modulo 2π (as
    :func:`.legs.in_revolute_range`): True (some qv + 2πk certainly in range), False
    (certainly none: the shift k0 the float midpoint gives is certainly outside, k0 - 1
    certainly below the range and k0 + 1 certainly above, so every other k too, the
    range being narrower than 2π) or None (undecided, reason appended).  A full turn
    (:func:`.legs.full_turn`) is in range."""
    from .legs import full_turn
    lo, hi = mech._joint_ranges()
    if lo is None or full_turn(lo[j], hi[j]):
        return True
    from flint import arb
    a, b = arb(float(lo[j])), arb(float(hi[j]))
    two_pi = 2 * arb.pi()
    k0 = math.ceil((float(lo[j]) - float(qv.mid())) / (2 * math.pi))
    shifted = {k: qv + k * two_pi for k in (k0 - 1, k0, k0 + 1)}
    if any(v >= a and v <= b for v in shifted.values()):
        return True
    if shifted[k0 - 1] < a and shifted[k0 + 1] > b and (shifted[k0] < a or shifted[k0] > b):
        return False
    reasons.append((i, j, f"the angle ball {_ball_text(qv, 'rad')} (modulo 2π) meets an end "
                          f"of the joint range [{lo[j]:.6g}, {hi[j]:.6g}] rad"))
    return None


def _reach_status(m, i, j, prismatic, reasons, infeasible, length=None, stroke=None):
    """Certified reach test of margin ball ``m`` (m^2) of pose i, leg j: True when
    certainly > 0; otherwise the reason is appended (and ``infeasible`` set when the leg
    certainly does not close, or a prismatic leg's ``length`` ball is certainly beyond
    its ``stroke`` (min, max) m)."""
    if m > 0:
        return True
    if m < 0:
        infeasible[i, j] = True
        if prismatic and stroke is not None:
            reasons.append((i, j, f"the leg's length {_ball_text(length, 'm')} is beyond its "
                                  f"stroke [{stroke[0]:.6g}, {stroke[1]:.6g}] m (margin "
                                  f"(q - min)(max - q) certainly negative, "
                                  f"{_ball_text(m, 'm^2')}): outside the stroke"))
        else:
            reasons.append((i, j, f"the leg does not close (reach margin certainly negative, "
                                  f"{_ball_text(m, 'm^2')}): no joint value to certify"))
    else:
        where = ("at an end of the leg's stroke (or at zero length)" if prismatic else
                 "at the leg's reach boundary, the branch point of its two assembly branches")
        reasons.append((i, j, f"the reach margin ball {_ball_text(m, 'm^2')} contains 0: the "
                              f"pose is {where}, which no ball decides"))
    return False


def _empty(cls, method, prec, L):
    """``cls`` (:class:`TieredIK`, :class:`TieredJacobian`) of an empty batch without
    running a kernel: (0, L) arrays, (0, L, 6) for J and Jx (it was an IndexError)."""
    from dataclasses import fields
    row = ("J", "J_error", "Jx", "Jx_error", "values", "jx_values") * (cls is TieredJacobian)
    kind = dict.fromkeys(("valid", "certified", "infeasible", "inaccurate", "reach_undecided"),
                         bool)
    kind.update(dict.fromkeys(("values", "jq_values", "jx_values"), object))
    arrays = {f.name: np.zeros((0,) if f.name == "inaccurate" else (0, L) + (6,) * (f.name in row),
                               dtype=kind.get(f.name, float))
              for f in fields(cls) if f.name not in ("method", "precision", "reasons")}
    return cls(method=method, precision=prec, reasons=(), **arrays)


def ik_tier(mech, poses, method: str = "fast", dps: int | None = None,
            bits: int | None = None) -> TieredIK:
    """Inverse kinematics of ``mech`` at ``poses`` (N, 6) or (6,) (m, rad) at one tier,
    with its accuracy (module docstring).  ``dps``: precise tier (default 30; given
    with another tier it is refused, :func:`check_dps`, as ``bits`` is but with the
    certified tier); ``bits``: certified tier (default :data:`BITS`)."""
    X, dps, bits, prec = _setup(mech, poses, method, dps, bits)
    N, L = len(X), mech.L
    none = np.zeros((N, L), dtype=bool)
    if not N and method != "fast":
        return _empty(TieredIK, method, prec, L)
    if method == "fast":
        q, valid = mech.inverse_kinematics(X)
        margin = mech.reach_margin(X)
        terms = _leg_terms(mech, X, q)                      # (shared by both estimates)
        err = _fast_ik_error(mech, X, q, margin, terms=terms)
        # a revolute leg that does not close has no angle: no finite error (as the J's
        # rows and the precise tier, QA T 2; it was a first-order 0.9 rad at z = 3 m)
        err = np.where(~mech.leg_arrays()["prismatic"][None] & (margin < 0), np.inf, err)
        undecided = _warn_undecided(mech, margin, reach_margin_error(mech, X, q, terms=terms),
                                    method)
        return TieredIK(method, prec, q, err, margin, valid, none, (), None, none, undecided)
    ks = _arb_kernels(mech)
    if method == "precise":
        vals, ref = precise_runs(ks, ("ik", "reach"), X, dps)
        q, margin = _to_float(vals["ik"]), _to_float(vals["reach"])
        err = np.where(_open_legs(mech, (vals, ref)), np.inf,
                       estimate(vals["ik"], ref["ik"], dps))
        undecided = _warn_undecided(mech, margin, estimate(vals["reach"], ref["reach"], dps),
                                    method)
        return TieredIK(method, prec, q, err, margin, mech._valid(q, margin), none, (),
                        vals["ik"], none, undecided)
    vals = _certified_eval(ks, ("ik", "reach"), X, bits)
    reasons, infeasible = [], none.copy()
    certified, valid = none.copy(), none.copy()
    prismatic = [leg.prismatic for leg in mech.leg_description().leg_table]
    strokes = [leg.range if leg.prismatic else None
               for leg in mech.leg_description().leg_table]
    for i in range(N):
        for j in range(L):
            if not _reach_status(vals["reach"][i, j], i, j, prismatic[j], reasons, infeasible,
                                 vals["ik"][i, j], strokes[j]):
                continue
            qv = vals["ik"][i, j]
            if not qv.is_finite():
                reasons.append((i, j, "the angle ball is not finite (the crank is on the ±π "
                                      "cut of atan2 within the balls' width)"))
                continue
            in_range = _range_check(mech, qv, i, j, reasons)
            if in_range is None:
                continue
            certified[i, j], valid[i, j] = True, in_range
    return TieredIK(method, prec, *_split(vals["ik"]), _mid(vals["reach"]),
                    valid, certified, tuple(reasons), vals["ik"], infeasible,
                    _contains_zero(vals["reach"]))


_contains_zero = np.vectorize(lambda b: not (b > 0) and not (b < 0), otypes=[bool])


def _warn_undecided(mech, margin, error, method):
    """(N, L) bool: the legs whose reach ``margin`` (m^2) is within its ``error`` of 0
    (:func:`.fast_errors.reach_decision`; not a prismatic leg without a stroke, whose
    margin q^2 is never negative), with a
    :class:`~distkin.errors.ConditioningWarning` naming the first pose and its legs
    when there is one (QA 25a finding 2: the fast tier answered valid or not valid
    silently there, wrong both ways in that band)."""
    free = [leg.prismatic and leg.range is None for leg in mech.leg_description().leg_table]
    undecided = reach_decision(margin, error)[1] & ~np.array(free, dtype=bool)[None]
    if undecided.any():
        i = int(np.argmax(undecided.any(axis=-1)))
        legs = [int(j) + 1 for j in np.flatnonzero(undecided[i])]
        _warn(f"{method} inverse kinematics: at {int(undecided.any(axis=-1).sum())} of "
              f"{len(margin)} pose(s) (first: pose {i}, legs {legs}, reach margins "
              f"{', '.join(f'{float(v):.2g}' for v in margin[i][undecided[i]])} m^2 within "
              f"their error estimates of 0) a leg is at its reach boundary (or a stroke "
              f"end) within rounding: whether it closes is undecided, and its valid "
              f"flag is the float sign's guess; see .reach_undecided, or use "
              f"method='certified' (it decides the leg, or names it undecided)",
              ConditioningWarning)
    return undecided


def jacobian_tier(mech, poses, method: str = "fast", dps: int | None = None,
                  bits: int | None = None) -> TieredJacobian:
    """J = Jq^-1 Jx, Jq and Jx of ``mech`` at ``poses`` at one tier, with its accuracy
    (module docstring; arguments as :func:`ik_tier`)."""
    X, dps, bits, prec = _setup(mech, poses, method, dps, bits)
    N, L = len(X), mech.L
    none = np.zeros((N, L), dtype=bool)
    if not N and method != "fast":
        return _empty(TieredJacobian, method, prec, L)
    if method == "fast":
        J = mech._fast("jacobian", X, warn=False)       # the warning below says more
        out = mech._fast("jq_jx", X, warn=False)
        Jq, Jx = out[..., 0], out[..., 1:]
        q, valid = mech.inverse_kinematics(X)
        jq_err, jx_err, err, inaccurate = _fast_jacobian_error(mech, X, q, J, Jq, Jx)
        if inaccurate.any():
            _warn(f"fast Jacobian: at {int(inaccurate.sum())} of {N} pose(s) (first: "
                          f"{int(np.argmax(inaccurate))}) a row of J has an estimated error "
                          f"above {J_REL_USEFUL:g} of the row (inf where first order fails): "
                          f"a leg at or next to its reach boundary (a serial singularity) or "
                          f"a prismatic leg of zero length, where float64 does not give J; "
                          f"see .J_error and .inaccurate, or use method='precise' (it raises "
                          f"SingularConfigurationError where J is unbounded or undefined)",
                          ConditioningWarning)
        return TieredJacobian(method, prec, J, err, Jq, jq_err, Jx, jx_err, valid, none,
                              (), None, None, None, none.copy(), inaccurate)
    ks = _arb_kernels(mech)
    if method == "precise":
        return _precise_jacobian(mech, ks, X, dps, prec)
    ik = ik_tier(mech, X, "certified", bits=bits)
    vals = _certified_eval(ks, ("jq_jx",), X, bits)["jq_jx"]
    jq, jx = vals[..., 0], vals[..., 1:]
    from ..exact_roots import working_precision
    reasons = list(ik.reasons)
    certified = ik.certified.copy()
    with working_precision(bits):
        J = np.empty_like(jx)
        for i in range(N):
            for j in range(L):
                J[i, j] = [c / jq[i, j] for c in jx[i, j]]
                if certified[i, j] and jq[i, j].contains(0):
                    certified[i, j] = False
                    reasons.append((i, j, f"the Jq_ii ball {_ball_text(jq[i, j], '')} contains "
                                          "0: the leg is at (or within the balls' width of) a "
                                          "serial singularity, J is unbounded there"))
    reasons.sort(key=lambda r: r[:2])
    return TieredJacobian(method, prec, *_split(J), *_split(jq), *_split(jx),
                          ik.valid & certified, certified, tuple(reasons), J, jq, jx,
                          ik.infeasible, np.zeros(N, dtype=bool), ik)


def raise_uncertified(res, what: str):
    """Raise for the first leg of a certified result ``res`` (:class:`TieredIK` or
    :class:`TieredJacobian`) that is not certified: :class:`InfeasibleError` where the
    leg certainly does not close, else :class:`UncertifiedError`; nothing when every leg
    is certified (or the tier is not ``certified``)."""
    if res.method != "certified" or not res.reasons:
        return
    i, j, why = res.reasons[0]
    more = len(res.reasons) - 1
    msg = (f"expected a certified {what} at pose {i}, got leg {j + 1} uncertified: {why}"
           + (f" (and {more} more leg(s))" if more else ""))
    if res.infeasible[i, j]:
        raise InfeasibleError(msg, field="poses")
    hint = 'method="precise" gives an estimate there'
    if isinstance(res, TieredJacobian):
        hint += (" unless J is unbounded or undefined (Jq_ii = 0 exactly, or a prismatic "
                 "leg of zero length: SingularConfigurationError)")
    raise UncertifiedError(msg, field="poses", hint=hint)
