r"""The three tiers of the forward kinematics of RSS and leg mechanisms.

Given the joint coordinates q (crank angles in rad, prismatic leg lengths in m), the
pose p = (x, y, z, rx, ry, rz) (m, rad; R = Rz Ry Rx, :mod:`distkin.spatial`) solves the
leg closures :math:`\Phi_i(q_i, p) = 0` (Kühne et al., Sec. II-C, eq. (1); the generated
``closure`` kernel: :math:`\Phi_i` in m and its derivatives with respect to the twist
(v, ω)).  With :math:`\omega = E(r)\dot r` (:func:`distkin.spatial.omega_entries`) the
derivative with respect to p is :math:`[\partial\Phi/\partial v,\;
\partial\Phi/\partial\omega\,E(r)]`.

``fast``
    Gauss-Newton in float64 from a warm start (:func:`.forward.forward_kinematics`).
    Error estimate (first order, not a bound; :func:`.forward.pose_error_estimate`):
    the condition number times (eps x the leg length + the closure residual), in m,
    and over the length scale in rad; only of an answer that passes the round trip
    (:func:`.forward.round_trip`: the closed-form IK at the pose gives back the joint
    values), another is refused with :class:`~distkin.errors.NotFoundError` (no pose found
    from the start; not a proof that none exists).
``precise``
    Newton (L = 6, or six ``legs``) or Gauss-Newton (L > 6: the least-squares pose of
    inconsistent angles) on the same generated kernel in its arb flavour run on mpmath numbers at
    ``dps`` digits (:class:`.kinematics_tiers.MPNumber`), from the fast answer.  Error
    estimate of the float64 pose given: the last Newton step (quadratic convergence:
    the error after it is far smaller), at least :math:`10^{1-dps}`, plus the pose's
    rounding to float64 (the ``dps``-digit pose is ``native``); not a bound.
``certified``
    Krawczyk's test (:mod:`distkin.certify.krawczyk`) on python-flint ``arb`` balls at
    :data:`BITS` bits, around the fast answer: a box of poses in which exactly one pose
    closes the legs, with per-coordinate radii (m, rad).  The joint values are taken
    exactly (a float is its exact binary value), and so is the mechanism (the exact
    model of :mod:`.kinematics_tiers`: the closure kernel's constants are exact).  For
    L > 6 (the redundant Octopod) the system is over-determined and float angles are in
    general not exactly consistent, so no pose
    closes all legs exactly: the test proves the pose that closes six legs (by default
    the six whose rows of the scaled closure Jacobian are best conditioned, by QR with
    column pivoting; or ``legs``), centred on the float64 Newton zero of those six, and
    bounds the closure errors of the others over the proved box (m).  Near a direct
    singularity (two assembly modes about to merge) the test refuses:
    :class:`~distkin.errors.UncertifiedError`, never a wrong box.

Joint values outside their legs' declared ranges (a leg table's ``range``: a crank's
arc modulo 2π, a prismatic leg's stroke) are no configuration of the device: every tier
refuses them before it solves (:func:`.joint_values.check_joint_ranges`,
:class:`~distkin.errors.InfeasibleError` naming the leg, its value and its range), so no
pose outside them is given an accuracy or called certified.  (The batched fast solver
:func:`.forward.forward_kinematics` solves them and flags them: ``in_range`` and
``verified`` False.)

The precise and certified poses pass the same round trip as the fast one (float64, the
closed-form IK at the tier's pose against the joint values, within their closure
errors over the crank's lever and the tier's error through J), and no leg may provably
fail to close at that pose, decided in the tier's own arithmetic (:func:`_reach_check`:
a reach margin within its error of 0 is ``reach_undecided``, warned, not refused; the
certified square system's legs close by the proof): the closures alone
hold on either crank branch of the IK, so a pose on the other branch (a start on it) is
refused with :class:`~distkin.errors.NotFoundError` (field ``guess``: no pose found from
that start, which proves nothing about other starts), not proved.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..argcheck import as_floats
from ..errors import (InfeasibleError, InputError, NotFoundError,
                      SingularConfigurationError, UncertifiedError)
from ..exact import check_method, float_mpf
from .description import read_only
from .kinematics_tiers import BITS, check_bits, check_dps

__all__ = ["TieredFK", "forward_tier", "fast_tier", "six_legs", "BITS"]


@dataclass(frozen=True)
class TieredFK:
    """The forward kinematics of one set of joint values, in one tier.

    Attributes
    ----------
    pose : (6,) float64
        m and rad (the midpoint of the certified box; the precise pose rounded).
    method : str
        "fast", "precise" or "certified".
    error : (6,) float64
        Per coordinate (m, m, m, rad, rad, rad), of the float ``pose``: an error
        estimate (fast, precise, with the pose's rounding to float64) or a proved radius,
        ``|p* - pose| <= error`` (certified).
    certified : bool
    legs : tuple of int
        The legs (1-based) whose closures define the pose: all (fast; precise without
        ``legs``), or the six of the square system (certified for L > 6; ``legs``).
    residual : float
        rms closure error at ``pose`` over all legs (m), in the tier's arithmetic.
    other_legs : dict
        Certified, L > 6: leg (1-based) -> upper bound of its closure error over the
        proved box (m); empty otherwise.
    native : tuple or None
        The six coordinates in the tier's own numbers: ``mpf`` (precise) or ``arb``
        balls (certified).
    fast : object
        The float64 answer (:class:`.forward.FKResult`) the tier started from.
    iterations : int
        Newton steps of the precise tier (0 otherwise).
    contraction : float
        Certified: the bound of ``|I - Y F'(X)|`` of Krawczyk's test (< 1).
    reach_undecided : tuple of int
        The revolute legs (1-based) at their reach boundary within the tier's accuracy
        at ``pose`` (:func:`_reach_check`): whether they close there is undecided, said
        in a :class:`~distkin.errors.ConditioningWarning`; not a refusal.
    """

    pose: np.ndarray
    method: str
    error: np.ndarray
    certified: bool
    legs: tuple
    residual: float
    other_legs: dict
    native: tuple | None
    fast: object
    iterations: int = 0
    contraction: float = math.nan
    reach_undecided: tuple = ()

    def __post_init__(self):
        read_only(self)


def _derivative_rows(rows, legs, omega):
    """dPhi/dp for the rows of the closure kernel (lists or balls): translation columns
    as they are, rotation columns times E(r) (``omega`` = its entries)."""
    out = []
    for i in legs:
        row = rows[i]
        out.append([row[1], row[2], row[3]] + [
            row[4] * omega[0][j] + row[5] * omega[1][j] + row[6] * omega[2][j]
            for j in range(3)])
    return out


def _omega_of(r):
    """E(r) of :func:`distkin.spatial.omega_entries` for balls or mpmath-like numbers
    (methods ``.sin()``, ``.cos()``)."""
    from ..spatial import omega_entries
    return omega_entries(r[4].cos(), r[4].sin(), r[5].cos(), r[5].sin())


def six_legs(legs, L: int, field: str = "legs") -> list:
    """Six distinct leg numbers 1..L (a list, tuple or 1-d integer array) -> sorted
    0-based indices; :class:`InputError` naming ``field`` otherwise."""
    if isinstance(legs, np.ndarray) and legs.ndim == 1 and legs.dtype.kind in "iu":
        legs = legs.tolist()                # numpy's integers (were refused, QA)
    ok = (isinstance(legs, (list, tuple)) and len(legs) == 6
          and all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) and 1 <= v <= L
                  for v in legs) and len(set(int(v) for v in legs)) == 6)
    if not ok:
        raise InputError(f"expected 6 distinct leg numbers 1..{L}, got {legs!r}", field=field)
    return sorted(int(v) - 1 for v in legs)


def _choose_legs(fast_pose, mech, q, legs):
    """The six legs of the certified square system (0-based), checked or chosen."""
    L = mech.legs
    if legs is not None:
        return six_legs(legs, L)
    if L == 6:
        return list(range(6))
    import scipy.linalg
    G = np.array(mech.kernels("scalar").closure(list(map(float, q)),
                                                list(map(float, fast_pose))), dtype=float)
    scale = np.array([1.0] * 3 + [mech.length_scale] * 3)
    _, _, piv = scipy.linalg.qr((G[:, 1:] / scale).T, pivoting=True)
    return sorted(int(v) for v in piv[:6])


def forward_tier(mech, q, guess=None, *, method: str = "fast", dps: int | None = None,
                 bits: int | None = None, legs=None, fast=None, units=None,
                 **options) -> TieredFK:
    """The pose of ``mech`` (RSS or leg mechanism) from one set of joint values ``q``
    (L,), in the tier ``method`` (see the module docstring).

    ``guess`` (6,) m, rad: the warm start of the fast tier (default the mechanism's
    home); ``options`` go to the fast tier (``tol``, ``max_iter``, ``max_condition``).
    ``dps``: digits of the precise tier (default :func:`distkin.exact.default_dps`);
    ``bits``: working precision of the certified tier's balls (default :data:`BITS`).
    ``legs``: six legs (1-based) whose closures define the pose (precise, certified;
    L > 6): the certified tier's square system (default: the best-conditioned six), and
    the precise tier's instead of the least-squares pose of all legs.  ``units``: the
    display units of a refusal's joint mismatch (:func:`fast_tier`; default SI).

    The precise and certified tiers start from the fast answer, converged or not (near a
    singularity Gauss-Newton may stall on a good pose).  Raises :class:`NotFoundError`
    (field ``guess``) when there is no finite start or the precise Newton does not converge,
    :class:`SingularConfigurationError` when its Jacobian is singular, and
    :class:`UncertifiedError` when Krawczyk's test refuses.
    """
    method = check_method(method)
    bits = check_bits(bits, method)
    dps = check_dps(dps, method)
    from .forward import forward_kinematics
    qa = as_floats(q, "q", f"{mech.legs} joint values (rad, or m for prismatic legs)")
    if qa.shape != (mech.legs,):
        raise InputError(f"expected {mech.legs} joint values, got shape {qa.shape}", field="q")
    from .joint_values import check_joint_ranges, check_joint_values
    check_joint_values(mech, qa)
    check_joint_ranges(mech, qa, units=units)     # no configuration: no tier answers
    if fast is None:
        fast = forward_kinematics(mech, qa, guess, **{**options, "warn": False})
    if method != "fast" and not np.all(np.isfinite(fast.pose)):
        raise NotFoundError(f"expected the fast tier to give a start for the {method} "
                            f"tier, got: {fast.message} (no pose found from the start; not a "
                            f"proof that none exists)", field="guess",
                            margin=float(fast.residual), hint="another guess")
    if legs is not None and method == "fast":
        raise InputError("expected 'legs' only with method 'precise' or 'certified', got "
                         "method 'fast'", field="legs")
    if method == "fast":
        return fast_tier(mech, fast, qa, units)
    if method == "precise":
        sub = list(range(mech.legs)) if legs is None else _choose_legs(fast.pose, mech, qa,
                                                                       legs)
        res = _precise(mech, qa, fast, dps, sub)
    else:
        chosen = _choose_legs(fast.pose, mech, qa, legs)
        res = _certified(mech, qa, fast, chosen, _polish(mech, qa, fast.pose, chosen), bits)
    res = _check_round_trip(mech, qa, res, units, fast, dps, bits)
    _warn_inconsistent(res, fast.residual_tol, units)
    return res


def _warn_inconsistent(res, tol, units=None):
    """A :class:`~distkin.errors.ConditioningWarning` where the tier's pose leaves the legs
    open by more than the fast tier's ``residual_tol`` (m, rms over all legs, the fast
    tier's own criterion): joint values that no pose closes (L > 6: a sensor offset, one
    leg's value in another unit).  The precise tier's least-squares pose and the
    certified tier's six-leg pose are then what they say (``error``: how precisely that
    point is computed, or proved), but not a configuration of the device, and nothing
    else said so (QA 23b, 8: a precise error of 1e-17 m at an rms closure of 5.7 mm, a
    certified box with two legs 16 mm open)."""
    if not res.residual > tol:
        return
    lu, lf = (units or _SI_SHOWN)["length"]
    what = f"the rms closure residual over all legs is {res.residual * lf:.3g} {lu}"
    if res.other_legs:
        worst = max(res.other_legs.values())
        what += (f" (legs {sorted(res.other_legs)}, outside the square system of legs "
                 f"{list(res.legs)}, stay open by up to {worst * lf:.3g} {lu} over the "
                 f"proved box)")
    else:
        what += " at this least-squares pose"
    from ..errors import ConditioningWarning, warn
    warn(f"{res.method} forward kinematics: {what}, above residual_tol = {tol * lf:.3g} "
         f"{lu}: the joint values are inconsistent (no pose closes every leg: a sensor "
         f"offset, or a value in another unit?); the stated error is that of this pose, "
         f"which is not the device's configuration", ConditioningWarning)


#: display units of a refusal's joint mismatch (:func:`.joint_values.joint_amount`): SI
_SI_SHOWN = {"length": ("m", 1.0), "angle": ("rad", 1.0)}


def _refusal(mech, what, mismatch, detail, units=None):
    """:class:`NotFoundError` for a pose that fails the round trip; ``mismatch`` (L,)
    per leg (rad, m), shown per joint type in ``units`` (default SI; QA R 10)."""
    from .joint_values import joint_amount
    mismatch = np.asarray(mismatch, dtype=float)
    amount = joint_amount(mismatch, mech.leg_arrays()["prismatic"], **(units or _SI_SHOWN))
    worst = float(np.max(np.where(np.isnan(mismatch), np.inf, mismatch)))
    return NotFoundError(
        f"expected a pose whose inverse kinematics gives back the joint values, got none "
        f"from the start: {what} misses them by up to {amount} ({detail}): "
        f"the closures hold there with cranks on the other branch of the IK, or it is a "
        f"least-squares minimum that closes no leg; not the device's configuration, and not "
        f"a proof that no such pose exists", field="guess",
        margin=worst, hint="another guess, near the device's pose")


def _flagged(mech, what, valid, mismatch, units=None):
    """:class:`NotFoundError` for a pose whose IK gives back the joint values but where
    legs provably do not close (``valid`` (L,) False; :func:`_reach_check`: the reach
    margin below minus its error estimate, or certainly so over the certified box): the
    joint values are in range (:func:`.joint_values.check_joint_ranges` refused the
    others)."""
    from .joint_values import joint_amount
    legs = [int(i) + 1 for i in np.flatnonzero(~np.asarray(valid, dtype=bool))]
    amount = joint_amount(np.asarray(mismatch, dtype=float),
                          mech.leg_arrays()["prismatic"], **(units or _SI_SHOWN))
    return NotFoundError(
        f"expected a pose at which every leg closes, got {what} where legs {legs} do "
        f"not (beyond their reach or stroke by more than rounding), though the inverse "
        f"kinematics gives back the joint values within {amount}: not verified",
        field="guess", margin=float(np.nanmax(mismatch)),
        hint="joint values inside the reach boundary or the stroke")


def _check_round_trip(mech, q, res, units, fast, dps, bits):
    """``res`` (precise or certified :class:`TieredFK`) with its ``reach_undecided``
    legs, or :class:`NotFoundError` unless the closed-form IK at its pose gives back
    ``q`` (:func:`.forward.round_trip`, with the pose's error) and no leg provably fails
    to close there (:func:`_reach_check`)."""
    from .forward import round_trip
    mismatch, allowed, _, _ = round_trip(mech, q, res.pose, np.asarray(res.error)[None],
                                         with_valid=True)
    bad = ~(mismatch[0] <= allowed[0])
    if bad.any():
        legs = [int(i) + 1 for i in np.flatnonzero(bad)]
        raise _refusal(mech, f"a {res.method} pose", np.where(bad, mismatch[0], 0.0),
                       f"legs {legs}", units)
    closes, undecided = _reach_check(mech, q, res, fast, dps, bits)
    if not closes.all():
        raise _flagged(mech, f"a {res.method} pose", closes, mismatch[0], units)
    return _undecided(res, undecided)


def _reach_check(mech, q, res, fast, dps, bits):
    """(closes, undecided) (L,) bool at the pose of ``res``, in the tier's arithmetic: a
    revolute leg *closes* unless its reach margin is below minus its error estimate
    (:func:`.fast_errors.reach_decision`), and is *undecided* within it of 0.  A leg of
    a square system (six legs: L = 6, or ``legs``) has its closure zero at the pose: in
    the certified tier it closes by the proof (the box holds that zero), in the precise
    one its margin's error is the model of :func:`.fast_errors.reach_margin_error` at
    10^(1 - dps) with the pose's own error.  Another leg (outside the six, or every leg
    of the precise least-squares pose of L > 6) closes only as far as the float joint
    values are consistent: its error adds the fast pose's error estimate (of a residual
    at most ``residual_tol``), and the certified tier decides it on the arb ball of its
    margin over the box (``bits``: certainly > 0 closes, certainly below minus that
    error does not).  A prismatic leg's stroke is checked on the length given
    (:func:`.forward.round_trip`).  QA 25a finding 1: the certified tier's float test
    refused "legs [5] do not close" at a pose whose box it had proved to close every
    leg."""
    from .fast_errors import reach_decision, reach_margin_error
    from .forward import pose_error_estimate
    L = mech.legs
    pris = np.asarray(mech.leg_arrays()["prismatic"])
    exact = np.isin(np.arange(1, L + 1), res.legs if len(res.legs) == 6 else ())
    closes, undecided = np.ones(L, dtype=bool), np.zeros(L, dtype=bool)
    if exact.all() and res.method == "certified":
        return closes, undecided
    X, Q = np.asarray(res.pose, dtype=float)[None], np.asarray(q, dtype=float)[None]
    floats = pose_error_estimate(mech, fast.condition, min(fast.residual, fast.residual_tol))
    if res.method == "precise":
        import mpmath

        from .kinematics_tiers import MPNumber, on_mpmath
        reach = on_mpmath(mech.kernels("arb").reach)
        with mpmath.workdps(dps + 5):
            m = np.array([float(v.v) for v in reach([MPNumber(v) for v in res.native])])
            own = np.array([float_mpf(v)[1] for v in res.native])  # the float pose's rounding
        tol = 10.0 ** (1 - dps)
        pe = np.maximum(res.error - own, tol)
        error = np.where(exact, reach_margin_error(mech, X, Q, pe, unit=tol)[0],
                         reach_margin_error(mech, X, Q, pe + floats, unit=tol)[0])
        closes, undecided = reach_decision(m, error)
    else:
        from flint import arb

        from ..exact_roots import working_precision
        error = reach_margin_error(mech, X, Q, floats)[0]
        with working_precision(bits):
            m = [v if isinstance(v, arb) else arb(v)
                 for v in mech.kernels("arb").reach(list(res.native))]
            for j in range(L):
                if exact[j] or pris[j] or m[j] > 0:
                    continue
                closes[j] = not m[j] < arb(-float(error[j]))
                undecided[j] = closes[j]
    return closes | pris, undecided & ~pris


def _undecided(res, undecided):
    """``res`` with ``reach_undecided`` the legs of the (L,) bool ``undecided``, and a
    :class:`~distkin.errors.ConditioningWarning` naming them when there is one."""
    legs = tuple(int(j) + 1 for j in np.flatnonzero(undecided))
    if legs:
        from ..errors import ConditioningWarning, warn
        how = ("float64 does not decide it; method='certified' does" if res.method == "fast"
               else f"not decided in the {res.method} tier's arithmetic; a leg outside a "
                    f"square system of six legs closes only as far as the float joint "
                    f"values are consistent, to their rounding")
        warn(f"{res.method} forward kinematics: legs {list(legs)} are at their reach "
             f"boundary within rounding at the pose (reach margin within its error "
             f"estimate of 0): whether they close there is undecided ({how}); the pose "
             f"solves the closures within its stated error", ConditioningWarning)
    from dataclasses import replace
    return replace(res, reach_undecided=legs)


def fast_tier(mech, fast, q=None, units=None) -> TieredFK:
    """The :class:`TieredFK` of a fast answer ``fast`` (:class:`.forward.FKResult` of one
    pose), with its error estimate (:func:`.forward.pose_error_estimate`);
    :class:`NotFoundError` when the answer fails the round trip (``fast.round_trip``,
    :func:`.forward.round_trip`): no accuracy is stated for a wrong pose.  ``q`` (L,):
    the joint values ``fast`` answered (the refusal then states the mismatch per joint
    type; without them, the largest one for every leg), first checked against their
    legs' declared ranges (:func:`.joint_values.check_joint_ranges`:
    :class:`~distkin.errors.InfeasibleError`, as without them for ``fast.in_range``
    False).  ``units``:
    {"length": (name, factor from m), "angle": (name, factor from rad)}, the units of
    the refusal's numbers (default SI)."""
    from .forward import pose_error_estimate, round_trip
    from .joint_values import check_joint_ranges
    err = pose_error_estimate(mech, fast.condition, fast.residual)
    if q is not None:
        check_joint_ranges(mech, np.asarray(q, dtype=float), units=units)
    elif not fast.in_range:
        raise InfeasibleError("expected joint values within their legs' declared ranges, "
                              f"got a fast answer flagged outside them: {fast.message}",
                              field="q", hint="pass q to name the legs")
    if not fast.round_trip:
        mismatch, allowed, valid, _ = (
            round_trip(mech, np.asarray(q, dtype=float)[None], np.asarray(fast.pose)[None],
                       err, with_valid=True, reach_pose_error=pose_error_estimate(
                           mech, fast.condition, min(fast.residual, fast.residual_tol)))
            if q is not None else
            (np.full((1, mech.legs), float(fast.q_mismatch)), None, None, None))
        mismatch = mismatch[0]
        if allowed is not None and np.all(mismatch <= allowed[0]) and not valid[0].all():
            raise _flagged(mech, "a fast pose", valid[0], mismatch, units)
        lu, lf = (units or _SI_SHOWN)["length"]
        raise _refusal(mech, "a fast pose", mismatch,
                       f"the fast tier's Gauss-Newton pose: "
                       f"{'converged' if fast.converged else 'not converged'} in "
                       f"{fast.iterations} iterations, rms closure residual "
                       f"{float(fast.residual) * lf:.3g} {lu}", units)
    undecided = (np.zeros(mech.legs, dtype=bool) if fast.reach_undecided is None
                 else np.asarray(fast.reach_undecided, dtype=bool))
    return _undecided(TieredFK(np.array(fast.pose), "fast", err[0], False,
                               tuple(range(1, mech.legs + 1)), float(fast.residual), {},
                               None, fast), undecided)


def _polish(mech, q, pose, legs, steps: int = 4):
    """The float64 zero of the square system of ``legs`` near ``pose`` (Newton on the
    scalar closure kernel, at most ``steps`` steps; the fast tier's Gauss-Newton answer
    is the least-squares pose of all legs, off the six-leg pose when the angles are
    inconsistent): the centre of Krawczyk's box."""
    from ..spatial import omega_map
    closure = mech.kernels("scalar").closure
    x = np.array(pose, dtype=float)
    ql = [float(v) for v in q]
    for _ in range(steps):
        G = np.array(closure(ql, x.tolist()), dtype=float)
        J = np.array(_derivative_rows(G, legs, omega_map(x[3:])))
        try:
            d = np.linalg.solve(J, -G[legs, 0])
        except np.linalg.LinAlgError:
            return np.array(pose, dtype=float)
        if not np.all(np.isfinite(d)):
            return np.array(pose, dtype=float)
        x = x + d
        if np.all(np.abs(d) <= 4 * np.finfo(float).eps * np.maximum(np.abs(x), 1.0)):
            break
    return x


def _precise(mech, q, fast, dps, legs):
    import mpmath

    from .kinematics_tiers import MPNumber, on_mpmath
    closure = on_mpmath(mech.kernels("arb").closure)
    L = mech.legs
    with mpmath.workdps(dps + 5):
        qm = [MPNumber(float(v)) for v in q]
        p = [MPNumber(float(v)) for v in fast.pose]
        tol = mpmath.mpf(10) ** (1 - dps)
        last = None
        it = 0
        for it in range(1, 30):
            rows = closure(qm, p)
            c = mpmath.matrix([rows[i][0].v for i in legs])
            J = mpmath.matrix([[v.v for v in row]
                               for row in _derivative_rows(rows, legs, _omega_of(p))])
            try:
                d = (mpmath.lu_solve(J, -c) if len(legs) == 6
                     else mpmath.lu_solve(J.T * J, -(J.T * c)))
            except ZeroDivisionError:
                raise SingularConfigurationError(
                    f"expected a pose away from direct singularities, got a singular closure "
                    f"Jacobian at {dps} digits (fast tier: {fast.message})", field="q") from None
            p = [MPNumber(p[k].v + d[k]) for k in range(6)]
            size = max(abs(d[k]) for k in range(6))
            if last is not None and (size <= tol or size >= last):
                break
            last = size
        if size > mpmath.sqrt(tol):
            raise NotFoundError(
                f"expected Newton at {dps} digits to converge from the fast answer, got a "
                f"last step of {mpmath.nstr(size, 3)} (m, rad) after {it} steps (fast tier: "
                f"{fast.message}; not a proof that no pose exists)", field="guess",
                margin=float(size), hint="another guess")
        rows = closure(qm, p)
        res = mpmath.sqrt(mpmath.fsum(rows[i][0].v ** 2 for i in range(L)) / L)
        native = tuple(v.v for v in p)
        # of the float pose given: the last step, and the pose's rounding to float64
        err = np.array([float(max(abs(d[k]), tol)) + float_mpf(native[k])[1]
                        for k in range(6)])
    return TieredFK(np.array([float(v) for v in native]), "precise", err, False,
                    tuple(i + 1 for i in legs), float(res), {}, native, fast, it)


def _certified(mech, q, fast, legs, centre, bits):
    from flint import arb

    from ..certify.boxes import _up
    from ..certify.krawczyk import krawczyk
    from ..exact_roots import working_precision
    closure = mech.kernels("arb").closure
    L = mech.legs
    with working_precision(bits):
        qa = [arb(float(v)) for v in q]

        def F(P):
            rows = closure(qa, P)
            return [rows[i][0] for i in legs]

        def J(P):
            return _derivative_rows(closure(qa, P), legs, _omega_of(P))

        res = krawczyk(F, J, centre)
        if not res.proved:
            raise UncertifiedError(
                f"expected a box of poses that Krawczyk's test proves to hold exactly one "
                f"solution of the closures of legs {[i + 1 for i in legs]}, got none: "
                f"{res.reason} (fast tier: {fast.message})", field="q")
        box = [arb(float(res.centre[k]), float(res.radii[k])) for k in range(6)]
        rows = closure(qa, box)
        other = {i + 1: _up(abs(rows[i][0])) for i in range(L) if i not in legs}
        sq = sum((rows[i][0] * rows[i][0] for i in range(L)), arb(0))
        # (a ball of squares around 0 has no arb square root: the float root of its
        # upper bound, rounded up)
        rms = float(np.nextafter(math.sqrt(_up(sq / L)), np.inf))
    return TieredFK(np.array(res.centre), "certified", np.array(res.radii), True,
                    tuple(i + 1 for i in legs), rms, other, tuple(box), fast,
                    contraction=float(res.contraction))
