r"""Numeric forward kinematics of RSS/RRRS mechanisms (Gauss-Newton on the leg closures).

Given the crank angles q, find the pose x with Phi_i(q_i, x) = 0 for every leg
(:mod:`.symbolic`; Phi in metres, about the distal-length error).  For L = 6 this is
Newton's method; for L = 8 the system is over-determined and the iteration is
Gauss-Newton on the least-squares problem min sum Phi_i^2, whose minimum (the
*residual*) is zero for consistent angles and measures their inconsistency otherwise.

Each step solves G delta = -Phi by SVD, with G = dPhi/d(v, omega) from the generated
``closure`` kernel (angular columns scaled by lp to make the problem dimensionless),
and updates the pose on the rotation group: x <- x + delta_v, R <- exp(delta_omega) R.
The iteration is warm started (the controller passes the last pose), stops when the
step is below ``tol`` times the mechanism's length scale (``length_scale``: ``tol`` is
relative, so the iteration is the same for a device in nanometres or in kilometres),
and reports:

* ``converged`` -- the step fell below ``tol`` x the length scale within ``max_iter``
  iterations;
* ``residual`` -- rms of Phi at the answer (m);
* ``sigma_min`` / ``condition`` -- of the scaled G at the answer; ``near_singular`` when
  the condition exceeds ``max_condition`` (a direct-kinematic singularity is near and
  the pose is ill-determined by q).

* ``verified`` -- the answer is checked (:func:`round_trip`): the closed-form inverse
  kinematics at the returned pose gives back the joint values (modulo 2π for a crank;
  Gauss-Newton on the closures alone can land on the other crank branch of the IK, or
  on a least-squares minimum that closes no leg), each within

  .. math:: 2|\Phi_i(q_i, x)| / |J_{q,ii}| + \delta q_i + \textstyle\sum_k |J_{ik}|\,\delta x_k
            + 8\,\mathrm{eps}\max(1, |q_i|)

  (the closure residual over the crank's lever, the IK's own error estimate δq
  (:mod:`.kinematics_tiers`), the pose's error estimate δx (below) through J, and
  rounding), and the rms closure residual is at most ``residual_tol`` (default
  :data:`RESIDUAL_ULPS` eps times a leg length: what float64 leaves of consistent
  angles; raise it for measured, hence inconsistent, angles of a redundant device),
  and every leg closes at the pose (its reach margin, a prismatic stroke's included,
  not below minus its error estimate; within it of 0 the leg is ``reach_undecided``,
  flagged, not refused; ``round_trip`` is both checks of the IK);
* ``in_range`` -- every joint value given lies in its leg's declared ``range`` (a crank
  modulo 2π, :func:`.legs.in_revolute_range`; a prismatic leg within its stroke): joint
  values outside their ranges are no configuration of the device, so such an answer is
  never ``verified`` (the pose solves the closures, nothing more;
  :func:`.joint_values.check_joint_ranges` refuses them, as the tiers of :mod:`.forward_tiers` do).

It never returns a wrong pose silently: a failed answer says so in ``converged`` /
``near_singular`` / ``verified`` (which includes ``in_range``) / ``message`` (``ok`` is
all three) and, unless ``warn=False``, in a
:class:`~distkin.errors.ConditioningWarning` when no verified pose came out
(:mod:`.fk_failure`: the values, a singular Jacobian, a likely unit slip), and
``strict=True`` raises instead.  Accuracy of a verified answer (first
order, not a bound; :func:`pose_error_estimate`): the condition number times (eps x a leg length +
the rms closure residual) in m, and that over the length scale in rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..argcheck import as_floats
from ..errors import InputError, NotFoundError, SingularConfigurationError
from ..spatial import exp_so3, rotate_pose_scalar, rotation_angles, rotation_matrix
from .description import _poses, _rows, read_only
from .joint_values import check_joint_ranges, check_joint_values, joint_amount, outside_ranges

__all__ = ["FKResult", "forward_kinematics", "gauss_newton", "round_trip",
           "pose_error_estimate", "leg_length", "RESIDUAL_ULPS", "TOL", "MIN_TOL",
           "check_step_tol"]

#: default ``residual_tol`` of :func:`forward_kinematics`: this many eps times a leg
#: length (:func:`leg_length`; 7.9e-14 m for the Octopod's l3 = 349.7 mm).  Consistent
#: float angles leave an rms closure residual of about 1e-16 m on the presets.
RESIDUAL_ULPS = 1024


@dataclass(frozen=True)
class FKResult:
    """Result of :func:`forward_kinematics` (arrays over N, or scalars for one pose).

    Attributes
    ----------
    pose : array (N, 6) or (6,)
        m and rad (:mod:`distkin.spatial`).
    converged : bool array (N,) or bool
    iterations : int array (N,) or int
    residual : array (N,) or float
        rms closure error at ``pose`` (m).
    sigma_min, condition : array (N,) or float
        Smallest singular value and condition number of the scaled closure Jacobian.
    near_singular : bool array (N,) or bool
    message : str
        A summary, naming the failures.
    modes : array (M, 6) (or a list of them), or None
        Every assembly mode, when the exact octic answered (an octahedral leg table,
        :mod:`.octahedral_fk`).
    verified : bool array (N,) or bool
        The inverse kinematics at ``pose`` gives back the joint values within the
        module docstring's tolerance and every leg closes there (``round_trip``),
        ``residual`` is at most ``residual_tol``, and the joint values lie in their
        declared ranges (``in_range``).
    round_trip : bool array (N,) or bool
        The inverse kinematics' check alone (the answer is on the device's IK branch,
        and no leg provably fails to close there, :func:`round_trip`; for inconsistent
        angles of a redundant device, their least-squares pose).
    q_mismatch : array (N,) or float
        The largest |IK(pose) - q| over the legs (rad, or m for a prismatic leg;
        cranks modulo 2π).
    residual_tol : float
        The residual tolerance used (m).
    in_range : bool array (N,) or bool
        Every joint value given lies in its leg's declared range
        (:func:`.joint_values.outside_ranges`; True for legs without one).  False: not a configuration of the device, and the
        answer is not ``verified``.
    reach_undecided : bool array (N, L) or (L,)
        The revolute legs at their reach boundary within rounding at ``pose``: the
        reach margin within its error estimate of 0 (:func:`round_trip`), so float64
        does not decide whether they close there; not a reason to refuse (a pose at a
        leg's full stretch is right to 1e-15 m there), said in ``message`` and, with
        ``warn``, a :class:`~distkin.errors.ConditioningWarning`; the certified tier
        (:mod:`.forward_tiers`) decides.
    """

    pose: np.ndarray
    converged: object
    iterations: object
    residual: object
    sigma_min: object
    condition: object
    near_singular: object
    message: str
    modes: object = None
    verified: object = False
    round_trip: object = False
    q_mismatch: object = math.nan
    residual_tol: float = math.nan
    in_range: object = True
    reach_undecided: object = None

    def __post_init__(self):
        read_only(self)

    @property
    def ok(self):
        """Converged, verified and not near a singularity."""
        return np.logical_and(np.logical_and(self.converged, self.verified),
                              np.logical_not(self.near_singular))

    @property
    def matrix(self) -> np.ndarray:
        """``pose`` as 4x4 homogeneous transforms (N, 4, 4) or (4, 4)
        (:func:`distkin.spatial.pose_to_matrix`)."""
        from ..spatial import pose_to_matrix
        return pose_to_matrix(self.pose)

    @property
    def rotation(self):
        """``pose`` as (scipy ``Rotation``, translation (m)) (:func:`distkin.spatial.pose_to_rotation`)."""
        from ..spatial import pose_to_rotation
        return pose_to_rotation(self.pose)


def _solve(G, r, scale):
    Gs = G * scale
    U, S, Vt = np.linalg.svd(Gs, full_matrices=False)
    smin = S[..., -1]
    Sinv = np.where(S > S[..., :1] * 1e-14, 1.0 / np.where(S == 0, 1.0, S), 0.0)
    d = -np.einsum("...ji,...j,...j->...i", Vt, Sinv, np.einsum("...ji,...j->...i", U, r))
    return d * scale, smin, S[..., 0] / np.where(smin > 0, smin, np.nan)


#: default ``tol`` of :func:`forward_kinematics`: the step (m; rotations times the length
#: scale) below which Gauss-Newton stops, relative to the length scale (1.1e-13 m for the
#: presets' lp = 55 mm, the 1e-13 m it was as an absolute figure)
TOL = 2e-12
#: the smallest ``tol``: float64 resolves steps down to about 2.2e-16 of the length scale
MIN_TOL = 1e-15


def check_step_tol(tol, field: str = "tol") -> float:
    """``tol`` of :func:`forward_kinematics` checked: a number, at least :data:`MIN_TOL`
    (a relative step float64 cannot take would end as a non-convergence blamed on the
    start, QA P 6)."""
    if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not tol > 0:
        raise InputError(f"expected a positive relative step tolerance, got {tol!r}",
                         field=field)
    if tol < MIN_TOL:
        raise InputError(f"expected tol >= {MIN_TOL:g} (relative to the length scale; "
                         f"float64 resolves steps down to about 2.2e-16 of it), got {tol:g}",
                         field=field, hint=f"the default is {TOL:g}")
    return float(tol)


def forward_kinematics(mech, q, guess=None, *, tol=TOL, max_iter=50, max_condition=300.0,
                       residual_tol=None, strict=False, warn=True):
    """Pose of ``mech`` from its crank angles, by Gauss-Newton from a warm start.

    Parameters
    ----------
    mech : RSSMechanism
    q : array (L,) or (N, L)
        Crank angles (rad).
    guess : array (6,) or (N, 6), or 4x4 matrices (4, 4) or (N, 4, 4), optional
        Starting pose (m, rad), one or one per q; default the workspace centre.  Away from direct
        singularities it converges to the answer from within a centimetre and 10 deg
        (1000 Table II poses of the hunt, ergin, octopod and octo presets); near one
        (the hexa preset has them inside the Table II workspace) a start a few mm away
        can reach a neighbouring assembly mode, flagged only if its condition exceeds
        ``max_condition``.  The control loop's warm start is microns away.
    tol : float
        Step size below which the iteration stops, relative to the mechanism's length
        scale (dimensionless: the step in m, rotations times the length scale, over
        the length scale; default :data:`TOL`).  Scale invariant: the same iterations for
        the mechanism scaled by any factor.
    max_iter : int
    max_condition : float
        Condition number of the scaled closure Jacobian above which the answer is
        flagged ``near_singular``.  In the Table II workspace (rotations up to 20 deg)
        the hunt, ergin, octopod and octo presets stay between about 3 and 17; the hexa
        preset reaches 1e4 near its direct singularities (Sec. III-B.1), where two
        assembly modes come close (8-25 mm apart at condition 60-260) and a warm start
        may land on the other one.
    residual_tol : float, optional
        rms closure residual (m) above which an answer is not ``verified`` (default
        :data:`RESIDUAL_ULPS` eps x :func:`leg_length`).  Measured angles of a redundant
        device (L > 6) are inconsistent: pass their expected residual to accept their
        least-squares pose.
    strict : bool
        Raise :class:`~distkin.errors.SingularConfigurationError` (near a singularity)
        or :class:`~distkin.errors.NotFoundError` (field ``guess``: no convergence, or an
        answer that fails verification, from that start; not a proof that no pose
        exists; field ``q``, saying the values look out of the mechanism's reach and
        naming the unit slip, when Gauss-Newton did not converge for values in another
        unit, :func:`.fk_failure.unreachable_error`) instead of returning a flagged
        answer; first
        :class:`~distkin.errors.InfeasibleError` for joint values outside their legs'
        declared ranges (:func:`.joint_values.check_joint_ranges`; without ``strict`` they are
        solved and flagged: ``in_range`` and ``verified`` False).
    warn : bool
        Without ``strict``: emit one :class:`~distkin.errors.ConditioningWarning` when a
        joint-value set gets no verified pose (not converged, or not verified: out of
        range, round trip, residual), naming the flags, the joint values and their
        units, a singular closure Jacobian when that stopped Gauss-Newton and a likely
        unit slip (:func:`.fk_failure.warn_unsolved`; default True).  ``warn=False``:
        the flags alone (the tiers and the scene query, which refuse such answers).

    Returns
    -------
    FKResult
    """
    L = mech.legs
    what = "joint coordinates (rad, or m for prismatic legs)"
    qa, single = _rows(as_floats(q, "q", f"{L} {what}"), "q", L, what)
    check_joint_values(mech, qa[0] if single else qa)
    N = len(qa)
    if guess is None:
        X = np.tile(mech.home, (N, 1))
    else:
        g, _ = _poses(guess, "guess", mech.length_scale)   # as the IK: (6,), (N, 6), 4x4
        if len(g) not in (1, N):
            raise InputError(f"expected {N} guesses or one, got {len(g)}", field="guess")
        X = np.array(np.broadcast_to(g, (N, 6)))
    if residual_tol is None:
        residual_tol = RESIDUAL_ULPS * np.finfo(float).eps * leg_length(mech)
    elif (isinstance(residual_tol, bool) or not isinstance(residual_tol, (int, float))
          or not residual_tol > 0):
        raise InputError(f"expected a positive residual tolerance (m), got {residual_tol!r}",
                         field="residual_tol")
    residual_tol = float(residual_tol)
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 1:
        raise InputError(f"expected max_iter as a positive integer, got {max_iter!r}",
                         field="max_iter")
    if (isinstance(max_condition, bool) or not isinstance(max_condition, (int, float))
            or not max_condition >= 1):        # a condition number is >= 1; NaN flags none
        raise InputError(f"expected max_condition as a number >= 1 (a condition number), "
                         f"got {max_condition!r}", field="max_condition")
    check = (mech, qa, residual_tol, warn)
    ls = mech.length_scale
    tol = check_step_tol(tol)
    scale = np.array([1.0, 1.0, 1.0, 1.0 / ls, 1.0 / ls, 1.0 / ls])
    step_tol = tol * ls                    # m: the stopping test, scale invariant
    if single:
        # the control loop's path: scalar kernel, 6x6 normal equations, plain-float
        # rotation updates (no per-pose numpy overhead beyond one small solve)
        X[0], done1, it1 = _single(mech.kernels("scalar").closure, qa[0].tolist(),
                                   X[0].tolist(), scale, step_tol, max_iter)
        closure = mech.kernels("scalar").closure

        def evaluate(qq, XX):
            return np.array(closure(qq[0].tolist(), XX[0].tolist()))[None]
        out = evaluate(qa, X)
        return _finish(out, X, np.array([done1]), np.array([it1]), scale, tol, max_iter,
                       max_condition, strict, single, check)
    closure = mech.kernels("batched").closure

    def evaluate(qq, XX):
        return closure(qq, XX)

    R = rotation_matrix(X[:, 3:])
    iters = np.zeros(N, dtype=int)
    done = np.zeros(N, dtype=bool)
    for it in range(max_iter):
        out = evaluate(qa, X)
        d, _, _ = _solve(out[..., 1:], out[..., 0], scale)
        d = np.where(done[:, None], 0.0, d)
        d = np.where(np.isfinite(d), d, 0.0)
        step = np.linalg.norm(d / scale, axis=-1)
        X[:, :3] += d[:, :3]
        R = exp_so3(d[:, 3:]) @ R
        X[:, 3:] = rotation_angles(R)
        iters += ~done
        done |= step < step_tol
        if done.all():
            break
    out = evaluate(qa, X)
    return _finish(out, X, done, iters, scale, tol, max_iter, max_condition, strict, single,
                   check)


def _finish(out, X, done, iters, scale, tol, max_iter, max_condition, strict, single, check):
    mech, qa, residual_tol, warn = check
    N = len(X)
    res = np.sqrt(np.mean(out[..., 0] ** 2, axis=-1))
    _, smin, cond = _solve(out[..., 1:], out[..., 0], scale)
    cond = np.where(np.isfinite(cond), cond, np.inf)
    near = cond > max_condition
    mismatch, allowed, ik_valid, undecided = round_trip(
        mech, qa, X, pose_error_estimate(mech, cond, res), with_valid=True,
        reach_pose_error=pose_error_estimate(mech, cond, np.minimum(res, residual_tol)))
    undecided &= done[:, None]
    gives_back = np.all(mismatch <= allowed, axis=-1)    # False where nan
    flagged = ~np.all(ik_valid, axis=-1)                 # a leg does not close there
    back = gives_back & ~flagged
    small = res <= residual_tol
    outside = outside_ranges(mech, qa)                   # (N, L)
    in_range = ~outside.any(axis=-1)
    verified = back & small & in_range
    ok = done & ~near & verified
    worst = np.max(np.where(np.isnan(mismatch), np.inf, mismatch), axis=-1)
    failed = done & ~verified
    pris = mech.leg_arrays()["prismatic"]
    ls = float(mech.length_scale)
    flag_only = done & gives_back & flagged & in_range
    missed = done & ~gives_back
    bad_range, bad_closure = (~in_range).any(), flag_only.any()   # (the names only then)
    outside_legs = ([int(j) + 1 for j in np.flatnonzero(outside.any(axis=0))]
                    if bad_range else [])
    flagged_legs = ([int(j) + 1 for j in np.flatnonzero((~ik_valid[flag_only]).any(axis=0))]
                    if bad_closure else [])
    msg = (f"{int(ok.sum())} of {N} solved (a solved pose: Gauss-Newton converged, step < "
           f"tol x length scale = {tol:g} x {ls:.3g} m, verified by the round trip and "
           f"in range, not near a singularity)"
           + (f"; {int((~done).sum())} did not converge in {max_iter} iterations"
              if (~done).any() else "")
           + (f"; {int(near.sum())} near a singularity (condition > {max_condition:g})"
              if near.any() else "")
           + (f"; {int((~in_range).sum())} with joint values outside their legs' declared "
              f"ranges (legs {outside_legs}): not a configuration of the device, the pose "
              f"only solves the leg closures, not verified" if bad_range else "")
           + (f"; {int(missed.sum())} converged to a pose whose inverse kinematics "
              f"does not give back the joint values (by up to "
              f"{joint_amount(np.max(mismatch[missed], axis=0), pris)}: another crank "
              f"branch or a least-squares minimum, not a solution)" if missed.any() else "")
           + (f"; {int(flag_only.sum())} converged to a pose where legs {flagged_legs} do "
              f"not close (beyond their reach or stroke by more than rounding; not "
              f"verified)" if bad_closure else "")
           + (f"; {int(undecided.any(axis=-1).sum())} with legs "
              f"{[int(j) + 1 for j in np.flatnonzero(undecided.any(axis=0))]} at their "
              f"reach boundary within rounding (reach margin within its error estimate of "
              f"0: whether they close is undecided in float64; the certified tier "
              f"decides)" if undecided.any() else "")
           + (f"; {int((done & ~small).sum())} with an rms closure residual above "
              f"residual_tol = {residual_tol:.3g} m (inconsistent angles, or no solution "
              f"near the guess)" if (done & ~small).any() else "")
           + f"; rms closure residual up to {float(res.max(initial=0.0)):.3g} m")
    if strict and (~in_range).any():
        check_joint_ranges(mech, qa[0] if single else qa)
    if strict and failed.any():
        i = int(np.argmax(failed))
        raise NotFoundError(
            f"expected a pose whose inverse kinematics gives back the joint values and "
            f"whose rms closure residual is at most {residual_tol:.3g} m, got at pose {i} "
            f"a mismatch of {joint_amount(mismatch[i], pris)} and a residual of {res[i]:.3g} m from "
            f"the start (no pose found from it; not a proof that none exists)",
            field="guess", margin=float(res[i]),
            hint="another guess (the crank branch or assembly mode differs), or "
                 "residual_tol for measured angles")
    if strict and (near.any() or (~done).any()):
        from .fk_failure import unit_hint, unreachable_error  # a unit slip strands G-N
        i = int(np.argmax(near | ~done))
        slip = unit_hint(mech, qa[i], leg_length(mech)) or None
        if slip and not done[i]:            # not a pose near a singularity: out of reach
            raise unreachable_error(mech, qa[i], slip, cond[i], res[i], max_iter,
                                    max_condition)
    if strict and near.any():
        raise SingularConfigurationError(
            f"expected a pose away from singularities, got condition {float(cond.max()):.3g} "
            f"> {max_condition:g}", field="q", hint=slip)
    if strict and (~done).any():
        raise NotFoundError(
            f"expected Gauss-Newton to converge from the start, got step still above {tol:g} "
            f"x the length "
            f"scale {float(mech.length_scale):.3g} m after "
            f"{max_iter} iterations (residual {float(res.max()):.3g} m; no pose found from it, "
            f"not a proof that none exists)", field="guess", margin=float(res.max()),
            hint=slip or "another guess, near the device's pose")
    if warn and not (done & verified).all():          # fast or warn (:mod:`.fk_failure`)
        from .fk_failure import warn_unsolved
        warn_unsolved(mech, qa, single, done & verified, done, verified, in_range, cond, msg,
                      leg_length(mech))
    if warn and (undecided.any(axis=-1) & done & verified).any():
        from ..errors import ConditioningWarning, warn as _warn
        _warn(f"forward kinematics: {msg}", ConditioningWarning)
    if single:
        return FKResult(X[0], bool(done[0]), int(iters[0]), float(res[0]), float(smin[0]),
                        float(cond[0]), bool(near[0]), msg, None, bool(verified[0]),
                        bool(back[0]), float(worst[0]), residual_tol, bool(in_range[0]),
                        undecided[0])
    return FKResult(X, done, iters, res, smin, cond, near, msg, None, verified, back, worst,
                    residual_tol, in_range, undecided)


def leg_length(mech) -> float:
    """A typical leg length (m): l3, or the mean distance between base and platform
    joints at home."""
    if mech.kind == "rss":
        return float(mech.l3)
    d = mech.arrays()
    from ..spatial import rotation_matrix
    P = mech.home[:3] + d["p"] @ rotation_matrix(mech.home[3:]).T
    return float(np.mean(np.linalg.norm(P - d["B"], axis=1)))


def pose_error_estimate(mech, condition, residual):
    """Error estimate (N, 6) (m, m, m, rad, rad, rad) of converged fast poses: the
    condition number of the scaled closure Jacobian times (eps x a leg length,
    :func:`leg_length`, + the rms closure residual); the rotations that much over the
    length scale of the angular columns.  First order, not a bound."""
    e = (np.asarray(condition, dtype=float)
         * (np.finfo(float).eps * leg_length(mech) + np.asarray(residual, dtype=float)))
    e = np.atleast_1d(e)[:, None]
    return np.concatenate([np.repeat(e, 3, axis=1),
                           np.repeat(e / float(mech.length_scale), 3, axis=1)], axis=1)


def round_trip(mech, q, poses, pose_error, *, with_valid: bool = False,
               reach_pose_error=None):
    """The check of an answer of the forward kinematics (module docstring): the
    closed-form inverse kinematics at ``poses`` (N, 6) against the joint values ``q``
    (N, L) (rad or m).  ``with_valid``: also return whether each leg closes at
    ``poses``, which the round trip requires as well (an IK value where the leg does
    not close is no answer to compare): its reach margin (a prismatic leg's stroke is
    part of it) not below minus its error estimate
    (:func:`.fast_errors.reach_margin_error`, with ``reach_pose_error``, default
    ``pose_error``: the callers pass that of a residual at most ``residual_tol``, as
    consistent joint values leave), and a prismatic leg a length; and the revolute legs
    undecided, their margin within that estimate of 0 (a prismatic leg's stroke end is
    decided on the length given, :func:`.joint_values.check_joint_ranges`: given at the
    end, it came back 5.6e-17 m beyond it, review 2026-11-29).  A fixed slack of 64 eps
    length_scale² was below the margin's rounding at a leg's full stretch (QA 25a
    finding 1: hunt poses right to 1e-15 m refused, "legs [4] do not close", where arb
    proves every leg closes).

    Returns
    -------
    mismatch : array (N, L)
        |IK(pose) - q| (a crank's difference taken modulo 2π into [-π, π)).
    allowed : array (N, L)
        2 |Phi_i(q_i, pose)| / |Jq_ii| + the IK's error estimate + |J| ``pose_error``
        ((N, 6), m and rad) + 8 eps max(1, |q_i|); inf where Jq_ii = 0 exactly (the
        branch point).  A leg on the other IK branch misses by the distance between the
        branches (about a radian; they meet only at the reach boundary, where the IK's
        estimate grows to match).
    valid : bool array (N, L)
        Only with ``with_valid``: the legs that close at ``poses`` (not provably open).
    undecided : bool array (N, L)
        Only with ``with_valid``: of them, those whose margin is within its error of 0.
    """
    from .fast_errors import _leg_terms, fast_ik_error, reach_decision, reach_margin_error
    X = np.atleast_2d(np.asarray(poses, dtype=float))
    q = np.atleast_2d(np.asarray(q, dtype=float))
    qi, reach, phi, phi_ik, jq, J = _kernel_rows(mech, X, q)
    pris = mech.leg_arrays()["prismatic"]
    d = qi - q
    d = np.where(pris, d, (d + np.pi) % (2 * np.pi) - np.pi)
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = _leg_terms(mech, X, qi)
        e_ik = fast_ik_error(mech, X, qi, reach, phi_ik, jq, terms)
        allowed = (2 * np.abs(phi) / np.abs(jq) + e_ik
                   + np.einsum("nlk,nk->nl", np.abs(J), np.asarray(pose_error, dtype=float))
                   + 8 * np.finfo(float).eps * np.maximum(1.0, np.abs(q)))
    # nan: 0/0 where Jq_ii = 0 exactly, the branch point, where both branches meet
    allowed = np.where(np.isnan(allowed), np.inf, allowed)
    if with_valid:
        with np.errstate(invalid="ignore"):
            closes, undecided = reach_decision(
                reach, reach_margin_error(mech, X, qi, pose_error if reach_pose_error is None
                                          else reach_pose_error, terms=terms))
        closes &= ~(pris & (qi == 0.0))
        # (a prismatic leg's stroke end is decided on the length given, check_joint_ranges)
        return np.abs(d), allowed, closes, undecided & ~pris
    return np.abs(d), allowed


def gauss_newton(closure, q, pose, *, tol, max_iter, scale=None):
    """Gauss-Newton for one pose on a scalar closure kernel: the one implementation of
    the single-pose forward kinematics (this module's one-pose path and the control
    loop's reference route, :meth:`distkin.control.kinematics.KinematicModel.forward`;
    the compiled control cycle is its numba twin, held to it by tests/control).

    Each step solves the normal equations ``(AᵀA) δs = -Aᵀc`` with ``A = D S`` (columns
    scaled by ``scale``, default none), ``δ = S δs``, then moves the pose by
    ``δ[:3]`` and rotates it by ``exp(δ[3:])`` (:func:`distkin.spatial.rotate_pose_scalar`).
    It stops after a step with ``|δ / scale| < tol``.

    Parameters
    ----------
    closure : callable
        ``closure(q, pose) -> (L, 7)`` (lists of floats): the residuals ``c`` (m) and
        their derivatives ``D`` w.r.t. (v, omega) (the generated scalar ``closure``).
    q : sequence of L floats
        Crank angles (rad) or leg lengths (m).
    pose : sequence of 6 floats
        The start (m, rad).
    tol : float
    max_iter : int
    scale : array (6,), optional

    Returns
    -------
    pose : array (6,)
        The last pose.
    converged : bool
    iterations : int
    c, D, step : arrays (L,), (L, 6), (6,) or None
        The residuals and derivatives at the pose before the last step, and that step
        (``step`` is None when an evaluation or a solve failed: not finite, singular);
        ``c + D @ step`` is the linearised residual at the returned pose.
    """
    x = np.array(pose, dtype=float)
    s = np.ones(6) if scale is None else np.asarray(scale, dtype=float)
    q = [float(v) for v in q]
    c = D = d = None
    for it in range(1, max_iter + 1):
        try:
            G = np.array(closure(q, x.tolist()), dtype=float)
        except (ZeroDivisionError, OverflowError, ValueError):
            # Python floats raise where numpy gives inf or NaN (a zero-length prismatic
            # leg, QA R 1): no evaluation, as a non-finite one
            return x, False, it, c, D, None
        if not np.isfinite(G).all():
            return x, False, it, c, D, None
        c, D = G[:, 0], G[:, 1:]
        A = D * s
        try:
            d = np.linalg.solve(A.T @ A, -(A.T @ c)) * s
        except np.linalg.LinAlgError:
            return x, False, it, c, D, None
        if not np.isfinite(d).all():
            return x, False, it, c, D, None
        x = rotate_pose_scalar(x, d[:3], d[3:])
        if math.sqrt(float(((d / s) ** 2).sum())) < tol:
            return x, True, it, c, D, d
    return x, False, max_iter, c, D, d


def _kernel_rows(mech, X, q):
    """At the poses X (N, 6) and joint values q (N, L): the IK qi (N, L), the reach
    margin (N, L), Phi(q, X) and Phi(qi, X) (N, L), Jq (N, L) and J (N, L, 6).  The
    scalar kernels for a few poses (a batched kernel costs ~0.5 ms of numpy overhead on
    one pose), else the batched."""
    if 0 < len(X) <= 4:                    # (an empty batch: the batched kernels)
        k = mech.kernels("scalar")
        try:
            rows = []
            for x, qq in zip(X.tolist(), q.tolist()):
                qi = k.ik(x)
                rows.append((qi, k.reach(x), [r[0] for r in k.closure(qq, x)],
                             [r[0] for r in k.closure(qi, x)], [r[0] for r in k.jq_jx(x)],
                             k.jacobian(x)))
            return tuple(np.array(v, dtype=float) for v in zip(*rows))
        except (ZeroDivisionError, ValueError, OverflowError):
            pass                      # Python floats raise where numpy gives inf or nan
    k = mech.kernels("batched")
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        qi = k.ik(X)
        return (qi, k.reach(X), k.closure(q, X)[..., 0], k.closure(qi, X)[..., 0],
                k.jq_jx(X)[..., 0], k.jacobian(X))


def _single(closure, q, x, scale, tol, max_iter):
    """The one-pose path of :func:`forward_kinematics`: :func:`gauss_newton`."""
    x, done, it, _, _, _ = gauss_newton(closure, q, x, tol=tol, max_iter=max_iter, scale=scale)
    return x, done, it
