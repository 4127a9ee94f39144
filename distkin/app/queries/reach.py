"""Whether poses are reachable, leg by leg, in the words of the ``inverse_kinematics``
query (:mod:`.mechanisms`), for every query that must not answer at a pose the device
cannot take (``singularity`` on ``kind = "rss"`` and ``kind = "legs"``,
:mod:`.leg_singularity`).

A pose is reachable where every leg is valid
(:meth:`~distkin.mechanisms.kinematics.KernelMethods.inverse_kinematics`): it closes
(reach margin >= 0) and its joint lies in its declared range (a revolute leg's angle
range; a prismatic leg's stroke, part of its reach margin).  The certified
tier (:func:`~distkin.mechanisms.kinematics_tiers.ik_tier`) decides each leg with arb
balls or names it undecided; the fast and precise tiers name undecided a leg whose reach
margin is within its error estimate of 0 (``reach_undecided``: at its reach boundary
within rounding, where the sign of the margin decides nothing, QA 25a finding 2).
"""

from __future__ import annotations

import numpy as np

__all__ = ["reach_status", "reach_statuses", "reach_text"]


def reach_status(mech, res, i) -> dict:
    """Whether pose i of a tiered IK ``res`` of ``mech``
    (:func:`~distkin.mechanisms.kinematics_tiers.ik_tier`) is reachable, with the legs
    named (1-based), as the inverse_kinematics query states it and every query that needs
    a reachable pose reuses it:

    - ``reachable``: every leg is valid (it closes and its joint lies in its declared
      range; certified tier: certainly so) and none is undecided;
    - ``unreachable_legs``: the legs certainly not valid, and of them
      ``out_of_range_legs``, those whose joint is outside its declared range (a revolute
      leg that closes at an angle outside its ``range``; a prismatic leg whose length
      |P - B| is outside its stroke);
    - ``undecided_legs``: certified tier, legs neither certified nor certainly
      infeasible (a reach margin or a range end within the balls' width); fast and
      precise tiers, legs whose reach margin is within its error estimate of 0
      (``reach_undecided``; their ``valid`` flag is the margin's sign, which decides
      nothing there).
    """
    valid, margin = res.valid[i], np.asarray(res.reach_margin[i], dtype=float)
    undecided = (~res.certified[i] & ~res.infeasible[i] if res.method == "certified"
                 else np.asarray(res.reach_undecided[i], dtype=bool))
    bad = ~valid & ~undecided
    table = mech.leg_description().leg_table
    stroke = np.array([leg.prismatic and leg.range is not None for leg in table])
    pris = np.array([leg.prismatic for leg in table])
    outside = bad & (stroke | (~pris & (margin >= 0.0)))
    legs = lambda m: [int(j) + 1 for j in np.flatnonzero(m)]        # noqa: E731
    return {"reachable": bool(valid.all() and not undecided.any()),
            "unreachable_legs": legs(bad),
            "out_of_range_legs": legs(outside), "undecided_legs": legs(undecided)}


def reach_text(status) -> str:
    """The words of a :func:`reach_status`: "reachable", or "NOT reachable (legs [...])"
    and/or "undecided (legs [...])"."""
    if status["reachable"]:
        return "reachable"
    bad, open_ = status["unreachable_legs"], status["undecided_legs"]
    return "; ".join(([f"NOT reachable (legs {bad})"] if bad else [])
                     + ([f"undecided (legs {open_})"] if open_ else []))


def reach_statuses(mech, poses, method: str) -> list:
    """:func:`reach_status` of each pose (m, rad) of ``poses`` (N, 6), by the
    inverse kinematics at the query's tier (certified: every leg's closure and joint range
    certified, or the leg named undecided), as the inverse_kinematics query says it."""
    from ...mechanisms.kinematics_tiers import ik_tier
    if not len(poses):
        return []
    res = ik_tier(mech, np.array(poses, dtype=float), method)
    return [reach_status(mech, res, i) for i in range(len(poses))]
