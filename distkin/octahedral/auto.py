r"""``method="auto"``: the fast tier when it proves its answer, the certified one when not.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III.
The fast tier's answer is kept when

1. its assembly roots are proved to be those of the exact problem (:mod:`.descartes`,
   through :func:`.conditioning.assess`: a proof in float64 with rigorous rounding
   bounds, not an estimate), and
2. every pose reproduces the six legs to :data:`LEG_TOL` relative.

Otherwise the problem is solved again by the ``certified`` tier (exact ``fmpq`` octic,
FLINT's root isolation), whose count is proved too.  Data that cannot be made exact
(irrational squared lengths), and problems the certified tier cannot decide (an
:class:`~distkin.errors.UncertifiedError`: a multiple root of the exact octic where
several modes meet, e.g. the symmetric home pose of the equilateral pair, whose balls
cannot single out the placements) go to the ``precise`` tier at :data:`PRECISE_DPS`
digits instead, and the result says that its count is not certified (``certified``
False; ``tier_reason`` says why; QA R 2: ``auto`` raised there, while README promises
"escalated to certified (or precise)").  The result's ``tier`` names the tier that
answered and ``tier_reason`` says why; ``conditioning`` keeps the fast tier's verdict.

:func:`escalate_batch` does the same for the problems of a batched solve, one by one:
only the problems the fast tier did not prove are solved again.  There an error of the
slower tiers (a collinear triangle: :class:`~distkin.errors.DegenerateGeometryError`,
or an :class:`~distkin.errors.UncertifiedError` of the precise tier) concerns one
problem: it keeps the fast answer, flagged, the reason goes to ``.unresolved`` and the
call warns, so that the other problems' answers are not lost.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import DegenerateGeometryError, InputError, UncertifiedError
from ..errors import warn as _warn
from .result import _evolve, _worst_leg_error, blank_row

__all__ = ["escalate", "escalate_batch", "escalate_thin", "solve_exact", "LEG_TOL",
           "PRECISE_DPS"]

#: relative leg residual under which a fast pose is accepted
LEG_TOL = 1e-9
#: digits of the precise tier when the data cannot be made exact
PRECISE_DPS = 50


def solve_exact(base, platform, legs, *, dps=None, tol=None):
    """The certified tier's answer (in the given units), or the precise tier's when the
    squared lengths are irrational.  Returns ``(result, tier, note)``."""
    from .certified import solve_certified
    from .problem import exact_problem
    from .scaling import in_units, rescale_result
    problem = exact_problem(base, platform, legs)
    try:
        with in_units(problem.exponent):
            res = solve_certified(problem, 1e-15 if tol is None else float(tol))
    except InputError as exc:          # irrational squared lengths: no exact octic
        why = f"the data cannot be made exact ({exc})"
    except UncertifiedError as exc:    # a multiple root: the balls cannot place its modes
        why = f"the certified tier cannot decide it ({exc.message})"
    else:
        return (replace(rescale_result(res, problem.exponent),
                        accuracy=res.accuracy + problem.float_note()), "certified",
                "escalated to the certified tier (count proved)")
    from .precise import solve_precise
    digits = PRECISE_DPS if dps is None else dps
    with in_units(problem.exponent):
        res = solve_precise(problem, digits, tol)
    return (replace(rescale_result(res, problem.exponent),
                    accuracy=res.accuracy + problem.float_note()), "precise",
            f"{why}, so the precise tier at {digits} digits answered: its count is not "
            "certified")


def escalate_thin(exc, base, platform, legs, *, dps=None, tol=None):
    """``auto`` on a problem whose triangle the fast tier refuses as thinner than float64
    resolves (``exc``): the certified tier (or precise) answers, or refuses it as
    collinear (QA N 2)."""
    res, tier, note = solve_exact(base, platform, legs, dps=dps, tol=tol)
    return replace(res, method="auto", tier=tier,
                   tier_reason=f"the fast tier refused the data ({exc.message}); {note}")


def _why(cond, worst):
    """Why the fast answer is not kept, or "" when it is."""
    if not cond.trusted:
        return f"fast tier not proved: {cond.reason}"
    if not worst <= LEG_TOL:
        return f"fast tier reproduces a leg only to {worst:.1e} relative (> {LEG_TOL:g})"
    return ""


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
    worst = _worst_leg_error(fast)
    why = _why(cond, worst)
    if not why:
        return _evolve(fast, method="auto", tier="fast",
                       tier_reason=f"the fast tier proved its assembly roots (largest "
                                   f"relative root radius {cond.root_condition:.2g} eps); "
                                   f"legs reproduced to {worst:.1e} <= {LEG_TOL:g} relative")
    res, tier, note = solve_exact(base, platform, legs, dps=dps, tol=tol)
    return replace(res, method="auto", tier=tier, conditioning=cond,
                   tier_reason=f"{why}; {note}")


def _row(value, i, ndim):
    """Problem i's rows of a batched input (broadcast when it has no batch axis)."""
    a = np.asarray(value, dtype=object)
    return (a[i] if a.ndim == ndim + 1 else a).tolist()


def escalate_batch(batch, base, platform, legs, *, dps=None, tol=None):
    """:func:`escalate` for the problems of a batched fast solve
    (:class:`~.forward.BatchResult`): each problem the fast tier did not prove, or whose
    poses reproduce a leg worse than :data:`LEG_TOL`, is solved by :func:`solve_exact`;
    its answer replaces the fast one in the arrays and in ``.escalated``, and ``.tier``
    names the tier.  Returns a new BatchResult."""
    worst = np.where(batch.valid, batch.max_leg_error_relative, 0.0).max(axis=1)
    todo = np.flatnonzero(~batch.trusted | ~(worst <= LEG_TOL))
    if not todo.size:                   # (no copies of the ~3 KiB per problem: issue 17)
        return replace(batch, escalated={})
    raw = dict(batch.raw)
    for name in ("count", "s15", "points", "rotation", "translation", "leg_error",
                 "leg_error_rel", "valid", "roots", "status", "step", "slot"):
        raw[name] = raw[name].copy()
    tier = batch.tier.copy()
    escalated, unresolved = {}, {}
    for i in todo:
        try:
            res, t, note = solve_exact(_row(base, i, 2), _row(platform, i, 2),
                                       _row(legs, i, 1), dps=dps, tol=tol)
        except (UncertifiedError, DegenerateGeometryError) as exc:  # this problem only:
            unresolved[int(i)] = exc.message                        # flagged, not guessed
            continue
        cond = batch.result(i).conditioning
        why = _why(cond, worst[i])
        escalated[int(i)] = replace(res, method="auto", tier=t, conditioning=cond,
                                    tier_reason=f"{why}; {note}")
        tier[i] = t
        _put(raw, i, res)
    if unresolved:
        from ..errors import ConditioningWarning
        first = min(unresolved)
        _warn(f"auto: the certified tier could not decide {len(unresolved)} of "
              f"{len(batch)} problems (first: problem {first}: {unresolved[first]}); "
              "they keep the fast answer, flagged (trusted False; .unresolved "
              "says why)", ConditioningWarning)
    return replace(batch, count=raw["count"], s15=raw["s15"], points=raw["points"],
                   rotation=raw["rotation"], translation=raw["translation"],
                   max_leg_error=raw["leg_error"], max_leg_error_relative=raw["leg_error_rel"],
                   valid=raw["valid"], raw=raw, tier=tier, escalated=escalated,
                   unresolved=unresolved)


_CODES = {"assembly": 0, "rejected": 3}


def _put(raw, i, res):
    """Write the AssemblyResult ``res`` into row i of the batched arrays."""
    blank_row(raw, i)
    poses = res.poses[:16]
    raw["count"][i] = len(poses)
    modes = sorted({p.s15 for p in poses})[:8]
    raw["s15"][i, :len(modes)] = modes
    for j, p in enumerate(poses):
        raw["points"][i, j] = p.points
        raw["rotation"][i, j] = p.rotation
        raw["translation"][i, j] = p.translation
        raw["leg_error"][i, j] = p.max_leg_error
        raw["leg_error_rel"][i, j] = p.max_leg_error_relative
        raw["valid"][i, j] = True
    for j, r in enumerate(res.roots[:8]):
        raw["roots"][i, j] = r.value
        raw["step"][i, j] = r.radius
        raw["status"][i, j] = _CODES.get(r.status, 1 if "triangle" in r.reason else 2)
