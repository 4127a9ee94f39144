"""The ``forward_kinematics`` scene query for ``kind = "rss"`` and ``kind = "legs"``
(split from :mod:`.mechanisms`, whose docstring shows the query's fields).

The forward kinematics (:mod:`distkin.mechanisms.forward_tiers`) takes the same
``method`` and ``dps``: ``fast`` is Gauss-Newton in float64 (today's pose) with a
first-order error estimate; ``precise`` Newton on the generated kernel in mpmath from it;
``certified`` Krawczyk's test on arb balls, which proves a box of poses holding exactly
one solution (for L > 6: of six legs, ``legs`` or the best conditioned, with the other
legs' closure errors bounded over the box) or refuses (near a direct singularity).  The
JSON adds ``method``, ``pose_error`` (m, rad per coordinate: estimate or proved radius),
``certified``, ``legs`` and, certified, ``other_legs_closure_bound`` (m) and
``contraction``, and the fast answer's check (:mod:`distkin.mechanisms.forward`):
``verified`` (the round trip, the rms closure residual within ``residual_tol``, m, and
the joint values in range), ``round_trip`` (the closed-form IK at the pose gives back the
angles and no leg provably fails to close there), ``reach_undecided`` (the legs, 1-based,
at their reach boundary within the tier's rounding at the pose: whether they close is
undecided there, a warning, not a refusal; QA 25a finding 1), ``in_range`` (every joint
value within its leg's declared ``range``) and ``q_mismatch`` (the largest |IK(pose) - angle|, rad; m for
a prismatic leg).  Joint values outside their legs' declared ranges are no
configuration of the device: every tier refuses them before solving, an ``infeasible``
error naming ``angles[j]``, the leg, its value and its range in the scene's units
(:func:`distkin.mechanisms.joint_values.check_joint_ranges`).  A pose that fails the
round trip (another crank branch, or a least-squares minimum) is a ``not_found`` error
naming ``guess`` in every tier (below); measured, hence inconsistent, angles of an L > 6 mechanism
give their least-squares pose, reported with ``verified`` false unless the query's
``residual_tol`` (scene length unit; default 1024 eps times a leg length) admits their
rms closure residual (e.g. angles rounded to 0.01 deg on the Octopod leave ~0.005 mm).
``tol`` is relative (the step over the length scale: the same iterations at any scale);
``residual_tol`` is a length in the scene's unit.  ``angles`` are the joint values
(crank angles, or leg lengths of prismatic legs, each in its unit); the JSON gives them
also as ``joint_values`` (the name that fits both; ``angles`` stays for the contract).

Gauss-Newton is local: a pose that fails the round trip, or no convergence, is a
``not_found`` error naming ``guess`` (or ``angles`` when the start was the default home):
no pose was found from that start, which proves nothing about other starts.  A leg table
with the octahedral topology is solved by the exact octic first; when it proves that the
legs admit no assembly the answer is that (status ok, ``poses: []``, ``count`` 0 and the
``reason``; docs/design.md §4), as for ``kind = "octahedral"``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...argcheck import check_keys, positive_int, positive_number
from ...errors import DistkinError, InputError, NotFoundError, SingularConfigurationError
from ...exact import exact_to_float, parse_exact
from ..query import Outcome, register
from ..units import angle_factor, length_factor, warn_radians
from .mechanisms import (_fmt_pose, _joint_unit, _numbers, _plotter, _prismatic, _scale,
                         _tier_fields, _units, check_pose_units)

__all__ = ["ForwardKinematicsQuery"]


@dataclass(frozen=True)
class _FK:
    angles: tuple
    guess: tuple | None
    tol: float
    max_iter: int
    method: str = "fast"
    dps: int = 30
    bits: int | None = None
    legs: tuple | None = None
    residual_tol: float | None = None


def _mismatch_text(res, angles, mech, scene) -> str:
    """The fast answer's largest |IK(pose) - q| (``FKResult.q_mismatch``; ``angles`` (L,)
    the joint values, rad or m) in the scene's units: the crank's angle unit, a
    prismatic leg's length unit, and both (per leg,
    :func:`distkin.mechanisms.forward.round_trip`) for a mixed leg table."""
    lu, au, lf, af = _units(scene)
    pris = _prismatic(mech)
    if not pris.any():
        return f"{res.q_mismatch * af:.3g} {au}"
    if pris.all():
        return f"{res.q_mismatch * lf:.3g} {lu}"
    from ...mechanisms.forward import pose_error_estimate, round_trip
    mismatch, _ = round_trip(mech, np.asarray(angles, dtype=float)[None],
                             np.asarray(res.pose, dtype=float)[None],
                             pose_error_estimate(mech, res.condition, res.residual))
    return (f"{float(mismatch[0][~pris].max()) * af:.3g} {au} (cranks), "
            f"{float(mismatch[0][pris].max()) * lf:.3g} {lu} (prismatic legs)")


def _verified_line(res, angles, mech, scene, method: str) -> str:
    """Whether the fast answer ``res`` (:class:`~distkin.mechanisms.forward.FKResult`) of
    the joint values ``angles`` verifies: the round trip (the closed-form IK at the pose
    gives back the angles) and the rms closure residual within ``residual_tol``, with
    both numbers in the scene's units."""
    lu, au, lf, af = _units(scene)
    what = _joint_word(mech)
    open_ = ([] if res.reach_undecided is None else
             [int(j) + 1 for j in np.flatnonzero(res.reach_undecided)])
    trip = (f"round trip ok (the inverse kinematics at the pose gives back the {what}) "
            + (f"and every leg closes there" if not open_ else
               f"and no leg provably fails to close there (legs {open_} at their reach "
               f"boundary within rounding: undecided in float64)")
            if res.round_trip else
            f"round trip FAILED (the inverse kinematics at the pose does not give back "
            f"the {what}, or a leg does not close there)")
    small = res.residual <= res.residual_tol
    resid = (f"rms closure residual {res.residual * lf:.3g} {lu} "
             + ("<=" if small else "ABOVE") + f" residual_tol {res.residual_tol * lf:.3g} {lu}"
             + ("" if small else " (their least-squares pose: the angles are "
                                 "inconsistent, or Gauss-Newton stopped in a local minimum "
                                 "from this start; another guess tells them apart)"))
    other = ("" if method == "fast" else
             f"; the {method} pose passes the same round trip")
    if _ranged(mech):                      # (the query refuses values outside the ranges)
        other += (f"; {what} within the legs' declared ranges" if res.in_range else
                  f"; {what} OUTSIDE the legs' declared ranges")
    return (f"verified (fast tier): {'yes' if res.verified else 'no'}: {trip}, largest "
            f"|IK(pose) - {what[:-1]}| "
            f"{_mismatch_text(res, angles, mech, scene)}; {resid}{other}")


def _drawing_note(res, mech, scene) -> str:
    """The last title line of the forward kinematics' drawing: the legs are drawn at the
    closed-form IK of the solved pose, so a red leg is one that does not close there
    (the round trip's "every leg closes there"), and the joint values given are judged
    as the report judges them: their rms closure residual against ``residual_tol``, in
    the scene's length unit (QA: measured angles drawn as given left every distal link
    a few µm open, all red, beside "verified: yes")."""
    lu, _, lf, _ = _units(scene)
    small = res.residual <= res.residual_tol
    return (f"legs drawn at the IK of the solved pose; the {_joint_word(mech)} given: rms "
            f"closure residual {res.residual * lf:.3g} {lu} "
            + ("<=" if small else "ABOVE") + f" residual_tol {res.residual_tol * lf:.3g} {lu}"
            f" (verified: {'yes' if res.verified else 'no'})")


def _ranged(mech) -> bool:
    """Whether some leg of ``mech`` declares a joint range (a leg table's ``range``)."""
    from ...mechanisms.joint_values import joint_ranges
    return joint_ranges(mech) is not None


def _joint_word(mech) -> str:
    """What the joint values of ``mech`` are called: "angles" (every leg revolute), "leg
    lengths" (every leg prismatic) or "joint values" (a mixed table)."""
    pris = _prismatic(mech)
    if pris.size and pris.all():
        return "leg lengths"
    return "joint values" if pris.any() else "angles"


@register("forward_kinematics", mechanisms=("rss", "legs"),
          summary="numeric forward kinematics (Gauss-Newton, warm-started) from joint values")
class ForwardKinematicsQuery:
    @staticmethod
    def parse(table, mechanism, units, field):
        check_keys(table, {"type", "angles", "guess", "tol", "max_iter", "method", "dps",
                           "bits", "legs", "residual_tol"}, field)
        if "angles" not in table:
            raise InputError("missing required field 'angles'", field=f"{field}.angles")
        af = angle_factor(units)
        lf = length_factor(units, "units")
        raw = _numbers(table["angles"], f"{field}.angles", mechanism.L)
        for i, (a, p) in enumerate(zip(raw, _prismatic(mechanism))):
            if p and not a > 0:                # a zero length divides the closure (QA R 1)
                raise InputError(f"expected a positive leg length (prismatic leg {i + 1}, "
                                 f"{units.length}), got {a:g}", field=f"{field}.angles[{i}]",
                                 hint="a prismatic leg's joint value is its length from the "
                                      "base joint to the platform joint")
        # a prismatic leg's length as the leg table's stroke is read (an exact value times
        # the exact unit, rounded once, legs_scene): 563 mm against a stroke end of 563
        # mm was 1 ulp beyond it as 563 * 0.001 (review 2026-11-29)
        angles = tuple(exact_to_float(parse_exact(table["angles"][i], f"{field}.angles[{i}]"),
                                      f"{field}.angles[{i}]", units.length_factor)
                       if p else a * af for i, (a, p) in enumerate(zip(raw,
                                                                      _prismatic(mechanism))))
        guess = None
        if "guess" in table:
            raw_guess = _numbers(table["guess"], f"{field}.guess", 6)
            warn_radians(raw_guess[3:], units, f"{field}.guess")
            guess = tuple(np.array(raw_guess) * _scale(units))
            check_pose_units(np.array(guess)[None], units, [f"{field}.guess"],
                             mechanism.length_scale)
        from ...mechanisms.forward import TOL, check_step_tol
        tol = check_step_tol(positive_number(table.get("tol", TOL), f"{field}.tol"),
                             f"{field}.tol")                        # relative
        max_iter = positive_int(table.get("max_iter", 50), f"{field}.max_iter")
        tier = _tier_fields(table, field)
        legs = None
        if "legs" in table:
            from ...mechanisms.forward_tiers import six_legs
            six_legs(table["legs"], mechanism.L, f"{field}.legs")
            if tier["method"] == "fast":
                raise InputError("expected 'legs' with method 'precise' or 'certified' (the "
                                 "fast tier fits all legs), got method 'fast'",
                                 field=f"{field}.legs")
            legs = tuple(table["legs"])
        # measured (rounded) angles of an L > 6 mechanism close only in the least-squares
        # sense: the rms closure residual they may leave, in the scene's length unit
        rtol = (positive_number(table["residual_tol"], f"{field}.residual_tol") * lf
                if "residual_tol" in table else None)
        return _FK(angles, guess, tol, max_iter, legs=legs, residual_tol=rtol, **tier)

    @staticmethod
    def run(p, scene, ctx):
        mech = scene.mechanism
        guess = np.array(p.guess) if p.guess is not None else mech.home
        from ...mechanisms.joint_values import check_joint_ranges
        lu, au, lf, af = _units(scene)
        # outside their ranges the joint values are no configuration: refused in every
        # tier, in the scene's units (the tiers check again, with field "q")
        check_joint_ranges(mech, np.array(p.angles), field="angles",
                           units={"length": (lu, lf), "angle": (au, af)})
        # warn=False: an answer that is none is refused below, in the scene's units
        res = mech.forward_kinematics(np.array(p.angles), guess, tol=p.tol, max_iter=p.max_iter,
                                      residual_tol=p.residual_tol, warn=False)
        if res.modes is not None and len(res.modes) == 0:      # the octic proved it
            return _no_assembly(p, mech, scene, guess)
        start = ("the guess" if p.guess is not None else
                 "the mechanism's home, the default start (no guess given)")
        if not res.converged and p.method == "fast":
            lu, _, lf, _ = _units(scene)           # the residual in the scene's unit
            from ...mechanisms.fk_failure import singular_cause
            cause = singular_cause(mech, res.condition)
            if cause:        # not a matter of the start: the pose reached is singular
                raise SingularConfigurationError(
                    f"expected Gauss-Newton to converge from {start}, got no convergence "
                    f"in {p.max_iter} iterations (rms closure error {res.residual * lf:.3g} "
                    f"{lu}): {cause}", field="guess" if p.guess is not None else "angles",
                    hint="a start away from the singularity; an architecturally singular "
                         "leg table has no isolated pose: check the legs' geometry")
            raise NotFoundError(
                f"expected Gauss-Newton to converge from {start}, got no convergence in "
                f"{p.max_iter} iterations (rms closure error {res.residual * lf:.3g} {lu}): no pose "
                f"found from that start, not a proof that none exists",
                field="guess" if p.guess is not None else "angles", margin=res.residual,
                hint="another guess, near the device's pose")
        from ...mechanisms.forward_tiers import fast_tier, forward_tier
        from ...mechanisms.kinematics_tiers import BITS
        try:
            # fast: refused unless the answer passes the round trip; precise and
            # certified start from it (the exact octic's mode for an octahedral leg
            # table) and their pose must pass it too
            lu, au, lf, af = _units(scene)             # the refusal in scene units (QA R 10)
            shown = {"length": (lu, lf), "angle": (au, af)}
            tier = (fast_tier(mech, res, np.array(p.angles), shown) if p.method == "fast" else
                    forward_tier(mech, np.array(p.angles), method=p.method, dps=p.dps,
                                 bits=p.bits, legs=p.legs, fast=res, units=shown))
        except DistkinError as exc:         # the Python argument q is the scene's angles
            if exc.field == "q":
                exc.field = "angles"
            elif exc.field == "guess" and p.guess is None:     # the default start
                exc.field = "angles"
                exc.message += f" (the start: {start})"
                exc.args = (exc.one_line(),)
            raise
        pose = tier.pose
        lu, au, lf, af = _units(scene)
        err = tier.error
        what = {"fast": "error estimate (first order, not a bound)",
                "precise": f"error estimate ({p.dps} digits; the last Newton step)",
                "certified": f"proved radius (Krawczyk's test, arb balls at "
                             f"{p.bits or BITS} bits)"}[p.method]
        lines = [f"mechanism: {mech.name} (L = {mech.L})",
                 f"pose: {_fmt_pose(pose, scene, 6)}  [{p.method}]",
                 f"converged in {res.iterations} iterations (fast tier); rms closure error "
                 + ("at most " if tier.certified else "") + f"{tier.residual * lf:.3g} {lu}",
                 _verified_line(res, p.angles, mech, scene, p.method),
                 f"closure Jacobian (angular columns x length scale, dimensionless): "
                 f"sigma_min {res.sigma_min:.4g}, condition {res.condition:.4g}"
                 + ("  WARNING: near a singularity, the pose is ill-determined"
                    if res.near_singular else ""),
                 f"accuracy, {what}: position {float(err[:3].max()) * lf:.2g} {lu}, "
                 f"orientation {float(err[3:].max()) * af:.2g} {au}"]
        if p.method != "fast" and len(tier.legs) != mech.L:
            lines.append(f"legs defining the pose: {list(tier.legs)}")
        modes = None if res.modes is None else np.asarray(res.modes, dtype=float)
        if modes is not None:
            # an octahedral leg table: every assembly mode of the exact octic (Rojas et
            # al. Sec. III), the one nearest the guess polished above (QA 2026-11-29:
            # the API's fk.modes held 16, the report and the JSON none)
            lines.append(f"assembly modes (exact octic, Rojas et al. eq. (3)): "
                         f"{len(modes)}, the one nearest the start polished above")
            lines += [f"  mode {k}: {_fmt_pose(x, scene, 6)}" for k, x in enumerate(modes)]
        if tier.reach_undecided:
            lines.append(f"legs {list(tier.reach_undecided)}: at their reach boundary within "
                         f"rounding at the pose ({p.method} tier: reach margin within its "
                         f"error estimate of 0), whether they close is undecided")
        for leg, bound in tier.other_legs.items():
            lines.append(f"leg {leg}: closure error at most {bound * lf:.3g} {lu} over the "
                         f"proved box")
        result = {"pose": pose, "converged": res.converged, "iterations": res.iterations,
                  "residual": tier.residual, "sigma_min": res.sigma_min,
                  "condition": res.condition, "near_singular": res.near_singular,
                  "angles": np.array(p.angles), "joint_values": np.array(p.angles),
                  "guess": guess, "method": p.method,
                  "pose_error": err, "certified": tier.certified, "legs": list(tier.legs),
                  "verified": res.verified, "round_trip": res.round_trip,
                  "in_range": res.in_range, "reach_undecided": list(tier.reach_undecided),
                  **({} if modes is None else {"modes": modes}),
                  "q_mismatch": res.q_mismatch, "residual_tol": res.residual_tol,
                  "unit": {"pose": "m, rad", "residual": "m", "pose_error": "m, rad",
                           "angles": _joint_unit(mech), "joint_values": _joint_unit(mech),
                           "q_mismatch": _joint_unit(mech),
                           "residual_tol": "m", **_SOLVER_UNITS,
                           **({} if modes is None else {"modes": "m, rad"})}}
        if p.method == "certified":
            result["other_legs_closure_bound"] = {str(k): v for k, v in tier.other_legs.items()}
            result["contraction"] = tier.contraction
            result["unit"].update(_CERTIFIED_UNITS)
        if p.method == "precise":
            result["dps"] = p.dps
        return Outcome(result, "\n".join(lines),
                       _plotter(mech, pose[None], units=scene.units,
                                note=_drawing_note(res, mech, scene)))


def _no_assembly(p, mech, scene, guess):
    """The answer when the exact octic (Rojas et al. eq. (3)) proves that the legs of an
    octahedral leg table admit no assembly: status ok, no pose, and the reason
    (docs/design.md §4: a proved empty answer is an answer).  The octahedral solver's
    ``auto`` tier decided it (its fast tier only where it proves its roots); with
    ``method = "certified"`` the certified tier decides it again."""
    from ...octahedral import forward_kinematics as octahedral_fk
    topo = mech.octahedral()
    legs = np.array(p.angles)[topo["order"]]
    tier = "certified" if p.method == "certified" else "auto"
    oct_res = octahedral_fk(topo["base"], topo["platform"], legs, method=tier)
    if len(oct_res):                                  # not expected: the tiers disagree
        raise RuntimeError(f"the octic's {tier} tier found {len(oct_res)} assembly "
                           f"mode(s) where the first solve found none")
    answered = getattr(oct_res, "tier", tier)
    reason = (f"{oct_res.reason} (proved by the exact octic, Rojas et al. eq. (3), "
              f"{answered} tier)")
    lines = [f"mechanism: {mech.name} (L = {mech.L}, octahedral topology)",
             f"no assembly: 0 poses; {reason}"]
    result = {"pose": None, "poses": [], "count": 0, "reason": reason, "tier": answered,
              "method": p.method, "angles": np.array(p.angles),
              "joint_values": np.array(p.angles), "guess": guess,
              "unit": {"angles": _joint_unit(mech), "joint_values": _joint_unit(mech),
                       "guess": _SOLVER_UNITS["guess"]}}
    return Outcome(result, "\n".join(lines))


#: the ``unit`` entries of the solver's figures (QA 23 D6: they had none)
_SOLVER_UNITS = {
    "guess": "m, rad (SI, as pose: the scene's guess converted from its own units)",
    "sigma_min": "none (smallest singular value of the closure Jacobian, its rotation "
                 "columns divided by the length scale)",
    "condition": "none (sigma_max / sigma_min of that Jacobian)",
}

#: the certified tier's extra figures
_CERTIFIED_UNITS = {
    "other_legs_closure_bound": "m (per leg: the largest closure error over the proved "
                                "box)",
    "contraction": "none (Krawczyk's bound of |I - Y F'(X)|, below 1)",
}
