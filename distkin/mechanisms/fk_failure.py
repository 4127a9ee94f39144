"""What the fast forward kinematics says when it returns no answer ("fast or warn").

:func:`.forward.forward_kinematics` returns a flagged result rather than raising
(``converged``, ``verified``, ``in_range``; ``strict=True`` raises).  A result that is no
answer is not left to the flags alone: :func:`warn_unsolved` emits one
:class:`~distkin.errors.ConditioningWarning` (the category of a fast answer its tier
cannot vouch for, as the octahedral fast tier's, :mod:`distkin.octahedral.forward`)
naming what failed, the joint values given with their units, the legs outside their
declared ranges, a singular closure Jacobian when that is the cause
(:func:`singular_cause`) and a likely unit slip (:func:`unit_hint`: leg lengths in mm
given to a mechanism in m are 1000x its legs).  With ``strict=True`` the same unit slip
words the error of joint values Gauss-Newton cannot close (:func:`unreachable_error`).  Nothing of this runs on a solved pose:
the single forward kinematics keeps its speed.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ConditioningWarning, InfeasibleError, warn as _warn

__all__ = ["singular_condition", "singular_cause", "unit_hint", "joint_values_text",
           "unreachable_error", "warn_unsolved"]


def singular_condition() -> float:
    """The condition number of the scaled closure Jacobian at or above which it is
    singular to float64: 1 / :data:`~distkin.indices.zonotope.RANK_TOL` (1e12), the
    rank tolerance of the indices (the ``jacobian`` query calls a pose singular at
    κ = σmin/σmax <= RANK_TOL); inf (an exactly rank-deficient matrix) included."""
    from ..indices.zonotope import RANK_TOL
    return 1.0 / RANK_TOL


def singular_cause(mech, condition) -> str:
    """The text naming a singular closure Jacobian as the reason the forward kinematics
    stopped (``condition`` at the pose it reached, :func:`singular_condition`), with the
    leg table's architecture singularity when it has one
    (:func:`.leg_architecture.line_span`); "" when the Jacobian is not singular there."""
    if not condition >= singular_condition():
        return ""
    from .leg_architecture import line_span
    text = (f"the closure Jacobian is singular at the pose reached (condition "
            f"{float(condition):.3g} >= {singular_condition():.3g}: rank-deficient in "
            f"float64), a singular configuration where Gauss-Newton cannot determine the "
            f"pose")
    desc = mech if hasattr(mech, "leg_table") else mech.leg_description()
    span = line_span(desc)
    if span is not None and span.architectural:
        text += (f"; the mechanism is architecturally singular: its leg lines span rank at "
                 f"most {max(span.rank, *span.probe_ranks)} of 6 at the home pose and at "
                 f"every pose tried: J is singular at every pose")
    return text


def unit_hint(mech, q, leg_length: float) -> str:
    """A likely unit slip in the joint values ``q`` (L,) (m for a prismatic leg, rad for
    a crank), or "": prismatic lengths whose median is more than
    :data:`~.presets.SLIP_RATIO` times off ``leg_length`` (m, the mechanism's typical leg
    length at home, :func:`.forward.leg_length`; the one test of a unit slip,
    :func:`~.presets.slip_ratio`), crank angles beyond one turn (degrees given as rad)."""
    from .presets import slip_ratio
    q = np.asarray(q, dtype=float).reshape(-1)
    pris = np.asarray(mech.leg_arrays()["prismatic"], dtype=bool)
    parts = []
    if pris.any():
        typical = float(np.median(np.abs(q[pris])))
        ratio = slip_ratio(typical, leg_length)
        if ratio is not None:
            parts.append(f"the prismatic leg lengths given (median {typical:.6g} m) are "
                         f"{typical / leg_length:.3g} x the mechanism's leg length at home "
                         f"({leg_length:.4g} m): lengths in another unit? (the engine works "
                         f"in m: lengths in mm are 1000 x too large)")
    if (~pris).any():
        big = float(np.max(np.abs(q[~pris])))
        if big > 2 * math.pi:
            parts.append(f"crank angles up to {big:.6g} rad given, beyond one turn: "
                         f"degrees? (the engine works in rad)")
    return "; ".join(parts)


def joint_values_text(mech, q) -> str:
    """The joint values ``q`` (L,) as text with their units (m for a prismatic leg, rad
    for a crank)."""
    pris = np.asarray(mech.leg_arrays()["prismatic"], dtype=bool)
    units = ("m" if pris.all() else "rad" if not pris.any()
             else "m for prismatic legs, rad for cranks")
    return f"[{', '.join(f'{v:.6g}' for v in np.asarray(q, dtype=float))}] ({units})"


def unreachable_error(mech, q, slip, condition, residual, max_iter, max_condition):
    """The :class:`~distkin.errors.NotFoundError` of the strict forward kinematics when
    Gauss-Newton did not converge for joint values ``q`` (L,) that :func:`unit_hint`
    finds in another unit (``slip``, its text): the values are likely out of the
    mechanism's reach, and an ill-conditioned last iterate (``condition`` above
    ``max_condition``) is where the iteration stranded, not a pose near a singularity
    (it was a :class:`~distkin.errors.SingularConfigurationError` saying so, QA).
    ``residual``: the rms closure residual there (m)."""
    from ..errors import NotFoundError
    stranded = (f", its last iterate ill-conditioned (condition {float(condition):.3g} > "
                f"{max_condition:g}: where the iteration stranded, not a pose near a "
                f"singularity)" if condition > max_condition else "")
    return NotFoundError(
        f"expected joint values within the mechanism's reach, got "
        f"{joint_values_text(mech, q)}, which look out of its reach: {slip}; Gauss-Newton "
        f"did not converge in {max_iter} iterations (rms closure residual "
        f"{float(residual):.3g} m){stranded}", field="q", margin=float(residual),
        hint="the joint values in the engine's units: m for prismatic legs, rad for cranks")


def warn_unsolved(mech, qa, single, solved, converged, verified, in_range, condition,
                  message, leg_length):
    """One :class:`~distkin.errors.ConditioningWarning` for the joint-value sets of
    ``qa`` (N, L) whose answer is not ``solved`` (converged and verified, (N,) bool):
    how many, the flags of the first, its joint values (m, rad), the legs outside their
    ranges (:func:`.joint_values.check_joint_ranges`'s words), :func:`singular_cause`,
    :func:`unit_hint`, and the result's ``message``.  Nothing when every set is solved."""
    bad = np.flatnonzero(~np.asarray(solved, dtype=bool))
    if not len(bad):
        return
    i = int(bad[0])
    q = qa[i]
    shown = joint_values_text(mech, q)
    head = ("forward kinematics: no verified pose for the joint values given" if single else
            f"forward kinematics: {len(bad)} of {len(qa)} joint-value sets without a "
            f"verified pose; the first, set {i}")
    parts = [f"{head}, {shown}: converged "
             f"{bool(converged[i])}, verified {bool(verified[i])}, in_range "
             f"{bool(in_range[i])}; the pose returned is no answer (fk.ok is False)"]
    if not in_range[i]:
        from .joint_values import check_joint_ranges
        try:
            check_joint_ranges(mech, q)
        except InfeasibleError as exc:
            parts.append(exc.message)
    cause = singular_cause(mech, condition[i]) if not converged[i] else ""
    if cause:
        parts.append(cause)
    hint = unit_hint(mech, q, leg_length)
    if hint:
        parts.append(hint)
    parts.append(message)
    _warn("; ".join(parts) + " (warn=False: the flags alone; strict=True raises)",
          ConditioningWarning)
