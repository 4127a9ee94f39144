r"""``method="auto"``: the fast tier when it can be trusted, a slower one when not.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III.
The fast tier's answer is kept when

1. its conditioning estimate (:func:`.conditioning.estimate`) trusts the real-root
   count: every root that can lie in the feasible interval is isolated by more than its
   first-order error radius, and
2. every pose reproduces the six legs to :data:`LEG_TOL` relative.

Otherwise the problem is solved again by the ``certified`` tier (exact ``fmpq`` octic,
FLINT's root isolation), whose count is proved.  Data that cannot be made exact
(irrational squared lengths) go to the ``precise`` tier at :data:`PRECISE_DPS` digits
instead, and the result says that its count is not certified.  An
:class:`~distkin.errors.UncertifiedError` of the certified tier is raised, never turned
into a guess.  The result's ``tier`` names the tier that answered and ``tier_reason``
says why; ``conditioning`` keeps the fast tier's estimate.
"""

from __future__ import annotations

from dataclasses import replace

from ..errors import InputError

__all__ = ["escalate", "LEG_TOL", "PRECISE_DPS"]

#: relative leg residual under which a fast pose is accepted
LEG_TOL = 1e-9
#: digits of the precise tier when the data cannot be made exact
PRECISE_DPS = 50


def escalate(fast, base, platform, legs, *, dps=None, tol=None):
    """Keep the fast result ``fast`` or solve again in a slower tier (see module doc).

    Parameters
    ----------
    fast : AssemblyResult
        The fast tier's answer, with its ``conditioning``.
    base, platform, legs, dps, tol
        As for :func:`.forward.forward_kinematics`.

    Returns
    -------
    AssemblyResult with ``method="auto"`` and ``tier``/``tier_reason`` set.
    """
    cond = fast.conditioning
    worst = max((p.max_leg_error_relative for p in fast.poses), default=0.0)
    if cond.trusted and worst <= LEG_TOL:
        return replace(fast, method="auto", tier="fast",
                       tier_reason=f"conditioning estimate trusts the count (largest relative "
                                   f"root error radius {cond.root_condition:.2g} eps); legs "
                                   f"reproduced to {worst:.1e} <= {LEG_TOL:g} relative")
    why = (f"fast tier not trusted: {cond.reason}" if not cond.trusted else
           f"fast tier reproduces a leg only to {worst:.1e} relative (> {LEG_TOL:g})")
    from .certified import solve_certified
    from .problem import exact_problem
    problem = exact_problem(base, platform, legs)
    try:
        res = solve_certified(problem, 1e-15 if tol is None else float(tol))
    except InputError as exc:          # irrational squared lengths: no exact octic
        from .precise import solve_precise
        digits = PRECISE_DPS if dps is None else dps
        res = solve_precise(problem, digits, tol)
        return replace(res, method="auto", tier="precise", conditioning=cond,
                       tier_reason=f"{why}; the data cannot be made exact ({exc}), so the "
                                   f"precise tier at {digits} digits answered: its count is "
                                   "not certified")
    return replace(res, method="auto", tier="certified", conditioning=cond,
                   tier_reason=f"{why}; escalated to the certified tier (count proved)")
