"""Scene queries for ``kind = "rss"`` and ``kind = "legs"``: inverse kinematics,
Jacobian, forward kinematics.

Joint coordinates are angles (rad in the JSON, the scene's angle unit in the text and
in ``angles``) for revolute legs and lengths (m; the scene's length unit) for prismatic
ones.

Poses are written in the scene's units, ``[x, y, z, rx, ry, rz]`` (length units, then
angle units; rotation R = Rz(rz) Ry(ry) Rx(rx), :mod:`distkin.spatial`)::

    [[query]]
    type = "inverse_kinematics"
    poses = [[0, 0, 300, 0, 0, 0], [20, -10, 320, 10, 0, 5]]
    method = "certified"               # optional: fast (default) | precise | certified
    dps = 30                           # optional, precise tier only

    [[query]]
    type = "jacobian"
    pose = [0, 0, 300, 0, 0, 0]        # one pose, or poses = [...]
    mass_matrix = true                 # optional: Mq and the acceleration map (eq. (7))
    method = "precise"                 # optional, as above (and dps)

    [[query]]
    type = "forward_kinematics"
    angles = [1.2, -3.4, ...]          # L crank angles, angle units
    guess = [0, 0, 300, 0, 0, 0]       # optional warm start (default: workspace centre)
    tol = 2e-12                        # optional, dimensionless: the last Gauss-Newton step
                                       # over the mechanism's length scale
    residual_tol = 0.01                # optional, scene length unit: measured angles
    max_iter = 50
    method = "certified"               # optional: fast (default) | precise | certified
    legs = [1, 2, 3, 4, 6, 7]          # optional (L > 6, precise/certified): six legs
    bits = 128                         # optional (certified): the balls' precision

Every result is in SI in the JSON (m, rad), with the scene's units in the text; each
result's ``unit`` block names the units of its arrays.  The jacobian query (its
``kappa`` and singular values) is :mod:`.jacobian`; it shares this module's pose and
tier helpers.

``method`` (:mod:`distkin.mechanisms.kinematics_tiers`): ``fast`` is the float64 kernels
(today's numbers) with a first-order error estimate; ``precise`` runs the generated
kernels in mpmath at ``dps`` digits (error estimate: a second run at dps + 15 digits);
``certified`` runs them on python-flint balls from the pose's exact binary value (the
scene pose converted to SI and rounded once to float64), and marks every leg it cannot
certify (reach margin ball containing 0 or negative, angle on the ±π cut, joint-range
end undecided, Jacobian: Jq_ii ball containing 0) with the reason.  Each pose row has
``method``, ``q_error`` (IK; rad or m per leg) or ``J_error``, ``Jq_error``,
``Jx_error`` (Jacobian), and for ``certified`` ``certified`` (per leg) and
``uncertified`` ([{leg, reason}], legs 1-based); the text states the largest error.
The fast Jacobian's estimate propagates the IK's error and the rounding to first order
through Jq, Jx and J = Jx/Jq; next to a leg's reach boundary (Jq_ii -> 0) float64 loses
J: a row whose estimate exceeds 1e-6 of the row flags the pose (``inaccurate``, true
only in the fast tier; the text says to use ``method = "precise"``), and where first
order fails the error is ``inf`` ("inf" in the JSON, as every non-finite number; "not
resolved in float64" in the text).

The forward kinematics (:mod:`distkin.mechanisms.forward_tiers`) takes the same
``method`` and ``dps``: ``fast`` is Gauss-Newton in float64 (today's pose) with a
first-order error estimate; ``precise`` Newton on the generated kernel in mpmath from it;
``certified`` Krawczyk's test on arb balls, which proves a box of poses holding exactly
one solution (for L > 6: of six legs, ``legs`` or the best conditioned, with the other
legs' closure errors bounded over the box) or refuses (near a direct singularity).  The
JSON adds ``method``, ``pose_error`` (m, rad per coordinate: estimate or proved radius),
``certified``, ``legs`` and, certified, ``other_legs_closure_bound`` (m) and
``contraction``, and the fast answer's check (:mod:`distkin.mechanisms.forward`):
``verified`` (the round trip and the rms closure residual within ``residual_tol``, m),
``round_trip`` (the closed-form IK at the pose gives back the angles) and ``q_mismatch``
(the largest |IK(pose) - angle|, rad; m for a prismatic leg).  A pose that fails the
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

from ...argcheck import (check_keys, dps_field, method_field, pose_list, positive_int,
                          positive_number)
from ...errors import DistkinError, InputError, NotFoundError
from ...exact import parse_float
from ..query import Outcome, register
from ..units import angle_factor, length_factor
from .reach import reach_status, reach_text

__all__ = ["InverseKinematicsQuery", "ForwardKinematicsQuery", "parse_poses",
           "check_pose_units"]


def _numbers(value, field, length=None):
    if not isinstance(value, (list, tuple)):
        raise InputError(f"expected a list of {length or 'some'} numbers, got "
                         f"{type(value).__name__} {value!r}", field=field)
    if length is not None and len(value) != length:
        raise InputError(f"expected {length} numbers, got {len(value)}", field=field)
    return [parse_float(v, f"{field}[{i}]") for i, v in enumerate(value)]


def _scale(units):
    lf, af = length_factor(units, "units"), angle_factor(units)
    return np.array([lf] * 3 + [af] * 3)


def parse_poses(table, units, field, *, required=True, mechanism=None):
    """``pose = [...]`` or ``poses = [[...], ...]`` in scene units -> (N, 6) SI array.

    Given the ``mechanism``, a pose whose numbers mean nothing in float64 is refused here,
    in the scene's units (:func:`check_pose_units`)."""
    if "pose" in table and "poses" in table:
        raise InputError("expected either 'pose' or 'poses', got both", field=field)
    if "pose" in table:
        rows = [_numbers(table["pose"], f"{field}.pose", 6)]
        names = [f"{field}.pose"]
    elif "poses" in table:
        raw = pose_list(table["poses"], f"{field}.poses")
        rows = [_numbers(r, f"{field}.poses[{i}]", 6) for i, r in enumerate(raw)]
        names = [f"{field}.poses[{i}]" for i in range(len(rows))]
    elif required:
        raise InputError("missing required field 'poses' (or 'pose')", field=f"{field}.poses")
    else:
        return None
    X = np.array(rows) * _scale(units)
    if mechanism is not None:
        check_pose_units(X, units, names, mechanism.length_scale)
    return tuple(map(tuple, X))


def check_pose_units(X, units, names, scale):
    """:func:`distkin.mechanisms.description.check_pose_range` on poses (N, 6) (SI) of a
    scene, its error naming ``names[i]`` and stating the values and the bound in the
    scene's units (QA R 3, R 8: a pose of 1e300 mm, an angle of 1e20 deg)."""
    from ...mechanisms.description import MAX_REACH, MAX_ROTATION, check_pose_range
    try:
        check_pose_range(X, "", scale)
    except InputError:
        lf, af = 1.0 / length_factor(units, "units"), 1.0 / angle_factor(units)
        Y = np.abs(np.asarray(X, dtype=float))
        bad = np.concatenate([Y[:, :3] > MAX_REACH * scale, Y[:, 3:] > MAX_ROTATION], axis=1)
        i, k = (int(v) for v in np.argwhere(bad)[0])
        if k >= 3:
            raise InputError(
                f"expected a rotation component of magnitude at most {MAX_ROTATION * af:.3g} "
                f"{units.angle} ({MAX_ROTATION:g} rad: float64 keeps no digit of a larger "
                f"angle modulo 2π), got {X[i, k] * af:.6g} {units.angle}",
                field=f"{names[i]}[{k}]",
                hint=f"a unit slip? the scene's [units] angle is \"{units.angle}\"") from None
        raise InputError(
            f"expected a translation component of magnitude at most "
            f"{MAX_REACH * scale * lf:.3g} {units.length} ({MAX_REACH:g} x the mechanism's "
            f"length scale; no pose of the device lies farther), got {X[i, k] * lf:.6g} "
            f"{units.length}", field=f"{names[i]}[{k}]",
            hint=f"a unit slip? the scene's [units] length is \"{units.length}\"") from None


def _units(scene):
    u = scene.units
    return u.length, u.angle, 1.0 / length_factor(u, "units"), 1.0 / angle_factor(u)


def _fmt_pose(pose, scene):
    lu, au, lf, af = _units(scene)
    p = np.asarray(pose)
    return (f"({p[0] * lf:.6g}, {p[1] * lf:.6g}, {p[2] * lf:.6g}) {lu}, "
            f"({p[3] * af:.6g}, {p[4] * af:.6g}, {p[5] * af:.6g}) {au}")


def _prismatic(mech) -> np.ndarray:
    """(L,) bool: prismatic legs (none for an RSS mechanism)."""
    desc = mech.leg_description() if mech.kind == "legs" else None
    return (np.array([leg.prismatic for leg in desc.leg_table]) if desc is not None
            else np.zeros(mech.L, dtype=bool))


def _mechanism_unit(mech) -> dict | str:
    """The units of the JSON's ``mechanism`` block (SI): per parameter, or in words."""
    from ...mechanisms.description import SI_UNITS
    params = mech.parameters()
    if "legs" in params and isinstance(params["legs"], list):
        return ("SI: the legs' points and lengths m, axes and directions unitless, range "
                "rad (revolute) or m (prismatic), limit N m (revolute) or N (prismatic); "
                "home m, rad; mass kg; inertia kg m^2")
    return {k: SI_UNITS[k] for k in params if k in SI_UNITS}


def _joint_unit(mech) -> str:
    """The SI unit of the joint coordinates q in the JSON: rad for revolute legs, m for
    prismatic ones (each leg's, when they are mixed)."""
    pris = _prismatic(mech)
    if not pris.any():
        return "rad"
    if pris.all():
        return "m"
    return (f"rad (revolute legs), m (prismatic legs "
            f"{[int(j) + 1 for j in np.flatnonzero(pris)]})")


def _joint_text(q, mech, scene):
    """Joint coordinates in the scene's units, each with its unit."""
    lu, au, lf, af = _units(scene)
    pris = _prismatic(mech)
    if not pris.any():
        return "[" + ", ".join(f"{v * af:.6g}" for v in q) + f"] {au}"
    return "[" + ", ".join(f"{v * lf:.6g} {lu}" if p else f"{v * af:.6g} {au}"
                           for v, p in zip(q, pris)) + "]"


def _describe(mech, lf, lu) -> str:
    if mech.kind == "rss":
        return f"mechanism: {mech.name} (L = {mech.L}, l3 = {mech.l3 * lf:.6g} {lu})"
    types = ", ".join(sorted({leg.type for leg in mech.leg_table}))
    return f"mechanism: {mech.name} (L = {mech.L} legs: {types})"


def _plotter(mech, poses, qs=None):
    if mech.kind != "rss":
        def plot_legs(stem):
            from ...mechanisms.plot import plot_legs_poses
            return plot_legs_poses(mech, poses, stem, q=qs)
        return plot_legs

    def plot(stem):
        from ...mechanisms.plot import plot_poses
        return plot_poses(mech, poses, stem, q=qs)
    return plot


@dataclass(frozen=True)
class _Poses:
    poses: tuple
    mass_matrix: bool = False
    method: str = "fast"
    dps: int = 30
    bits: int | None = None


def _tier_fields(table, field):
    """``method``, ``dps`` (precise only, else None) and ``bits`` (certified only: the
    balls' working precision, 53..4096; default
    :data:`~distkin.mechanisms.kinematics_tiers.BITS`) of an inverse_kinematics,
    jacobian or forward_kinematics query."""
    from ...mechanisms.kinematics_tiers import check_bits
    method = method_field(table, field)
    bits = check_bits(table["bits"], method, f"{field}.bits") if "bits" in table else None
    dps = dps_field(table, method, field)
    return {"method": method, "dps": dps if method == "precise" else None, "bits": bits}


def _uncertified(res, i):
    """[{leg (1-based), reason}] of pose i of a tiered result."""
    return [{"leg": j + 1, "reason": why} for k, j, why in res.reasons if k == i]


def _tier_rows(res, i, row, *fields):
    """Add the tier's fields of pose i to a JSON row: method, the errors, and for the
    certified tier the per-leg flags and reasons."""
    row["method"] = res.method
    for name in fields:
        row[name] = getattr(res, name)[i]
    if res.method == "certified":
        row["certified"] = res.certified[i]
        row["uncertified"] = _uncertified(res, i)
    return row


def _tier_lines(res, i):
    return [f"  NOT certified: leg {u['leg']}: {u['reason']}" for u in _uncertified(res, i)]


#: the text of an error the fast tier cannot state (``inf``: its first-order estimate
#: fails, at a leg's reach boundary)
NOT_RESOLVED = 'not resolved in float64 (use method = "precise")'
#: the JSON unit of an IK pose's ``reach_margin`` (``KernelMethods.reach_margin`` of
#: :mod:`distkin.mechanisms.kinematics`; QA U 4: the number had none)
REACH_UNIT = ("m^2 per leg (revolute: rho^2 - C^2 of A cos q + B sin q = C; prismatic: "
              "(q - qmin)(qmax - q) within its range, else q^2); >= 0: the leg closes")


def _amount(err, mask, factor: float = 1.0, unit: str = "", method: str = "fast") -> str:
    """The largest error over ``mask`` as text with its unit; "no valid leg" when
    ``mask`` is empty, and where an error is not finite (the fast tier's first-order
    estimate fails: ``inf``) :data:`NOT_RESOLVED` (another tier: "unbounded") rather
    than the largest finite one, which would understate it."""
    vals = err[mask]
    if not vals.size:
        return "no valid leg"
    if not np.all(np.isfinite(vals)):
        return NOT_RESOLVED if method == "fast" else "unbounded"
    return f"{float(vals.max()) * factor:.2g}{unit}"


def _accuracy(res, what, amounts, fast_how) -> str:
    """The accuracy line of a tiered result: ``amounts`` the measured largest errors (or
    radii) as text with units; ``fast_how`` the fast tier's estimate."""
    how = {"fast": f"first-order estimate, not a bound: {fast_how}",
           "precise": "error estimate of the float64 values given: the difference from a "
                      "second run with 15 more digits, plus their rounding to float64",
           "certified": "certified radii about the float64 values given (the ball's radius "
                        "plus the rounding of its midpoint); the pose taken as the exact "
                        "binary value of its float64 SI coordinates"}[res.method]
    legs = (f"; {int(res.certified.sum())} of {res.certified.size} legs certified"
            if res.method == "certified" else "")
    kind = "radius" if res.method == "certified" else "error"
    return (f"accuracy ({res.method}, {res.precision}; {how}): largest {kind} of {what}: "
            f"{amounts}{legs}")


@register("inverse_kinematics", mechanisms=("rss", "legs"),
          summary="closed-form joint coordinates (crank angles, leg lengths) at given poses")
class InverseKinematicsQuery:
    @staticmethod
    def parse(table, mechanism, units, field):
        check_keys(table, {"type", "pose", "poses", "method", "dps", "bits"}, field)
        return _Poses(parse_poses(table, units, field, mechanism=mechanism),
                      **_tier_fields(table, field))

    @staticmethod
    def run(p, scene, ctx):
        from ...mechanisms.kinematics_tiers import ik_tier
        mech = scene.mechanism
        X = np.array(p.poses)
        res = ik_tier(mech, X, p.method, p.dps, p.bits)
        q, valid, margin = res.q, res.valid, res.reach_margin
        lu, au, lf, af = _units(scene)
        rows, lines = [], [_describe(mech, lf, lu)]
        for i in range(len(X)):
            ok = bool(valid[i].all())
            rows.append(_tier_rows(res, i, {"pose": X[i], "q": q[i], "valid": valid[i],
                                            "reachable": ok, "reach_margin": margin[i]},
                                   "q_error"))
            # certified: a leg that is neither certified nor certainly infeasible is
            # undecided (at its reach boundary, ...), not unreachable
            verdict = reach_text(reach_status(mech, res, i))
            lines.append(f"pose {i}: {_fmt_pose(X[i], scene)}  -> " + verdict)
            lines.append("  q = " + _joint_text(q[i], mech, scene))
            lines += _tier_lines(res, i)
        closes = np.asarray(margin) >= 0
        if not valid.any() and closes.any():   # the joint ranges exclude them (QA Q 5)
            lines.append("note: no leg is valid at any of these poses, yet legs close "
                         "there: their angles are outside the legs' joint ranges "
                         "(mechanism.leg range)")
        elif not valid.any():                  # not one leg closes anywhere: units?
            lines.append(f"note: no leg reaches any of these poses; the mechanism's home is "
                         f"{_fmt_pose(mech.home, scene)} in this scene's units "
                         f"([units] length = \"{scene.units.length}\", angle = "
                         f"\"{scene.units.angle}\")")
        pris = _prismatic(mech)[None] & np.ones_like(valid)
        ok = valid | res.certified
        amounts = ([_amount(res.q_error, ok & ~pris, 1.0, " rad", p.method)]
                   if (~pris).any() else [])
        if pris.any():
            amounts.append(_amount(res.q_error, ok & pris, lf, f" {lu}", p.method))
        lines.append(_accuracy(res, "q over the valid legs", ", ".join(amounts),
                               "closure residual |Phi_i(q)|/|Jq_ii| + 2 eps max(|q|, 1)"))
        if not _prismatic(mech).all():         # (a prismatic leg's length has no branch)
            lines.append("branch: the crank angle nearer 0 at the workspace centre "
                         "(distkin.mechanisms.presets) or the leg's own "
                         "(distkin.mechanisms.legs)")
        return Outcome({"mechanism": mech.parameters(), "method": p.method,
                        "precision": res.precision,
                        "unit": {"q": _joint_unit(mech), "pose": "m, rad",
                                 "q_error": _joint_unit(mech), "reach_margin": REACH_UNIT,
                                 "mechanism": _mechanism_unit(mech)},
                        "poses": rows}, "\n".join(lines), _plotter(mech, X, q))


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
    trip = (f"round trip ok (the inverse kinematics at the pose gives back the {what})"
            if res.round_trip else
            f"round trip FAILED (the inverse kinematics at the pose does not give back "
            f"the {what})")
    small = res.residual <= res.residual_tol
    resid = (f"rms closure residual {res.residual * lf:.3g} {lu} "
             + ("<=" if small else "ABOVE") + f" residual_tol {res.residual_tol * lf:.3g} {lu}"
             + ("" if small else " (their least-squares pose: the angles are "
                                 "inconsistent, or Gauss-Newton stopped in a local minimum "
                                 "from this start; another guess tells them apart)"))
    other = ("" if method == "fast" else
             f"; the {method} pose passes the same round trip")
    return (f"verified (fast tier): {'yes' if res.verified else 'no'}: {trip}, largest "
            f"|IK(pose) - {what[:-1]}| "
            f"{_mismatch_text(res, angles, mech, scene)}; {resid}{other}")


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
        angles = tuple(a * (lf if p else af) for a, p in zip(raw, _prismatic(mechanism)))
        guess = None
        if "guess" in table:
            guess = tuple(np.array(_numbers(table["guess"], f"{field}.guess", 6)) * _scale(units))
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
        res = mech.forward_kinematics(np.array(p.angles), guess, tol=p.tol, max_iter=p.max_iter,
                                      residual_tol=p.residual_tol)
        if res.modes is not None and len(res.modes) == 0:      # the octic proved it
            return _no_assembly(p, mech, scene, guess)
        start = ("the guess" if p.guess is not None else
                 "the mechanism's home, the default start (no guess given)")
        if not res.converged and p.method == "fast":
            lu, _, lf, _ = _units(scene)           # the residual in the scene's unit
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
                 f"pose: {_fmt_pose(pose, scene)}  [{p.method}]",
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
                  "q_mismatch": res.q_mismatch, "residual_tol": res.residual_tol,
                  "unit": {"pose": "m, rad", "residual": "m", "pose_error": "m, rad",
                           "angles": _joint_unit(mech), "joint_values": _joint_unit(mech),
                           "q_mismatch": _joint_unit(mech),
                           "residual_tol": "m"}}
        if p.method == "certified":
            result["other_legs_closure_bound"] = {str(k): v for k, v in tier.other_legs.items()}
            result["contraction"] = tier.contraction
        if p.method == "precise":
            result["dps"] = p.dps
        return Outcome(result, "\n".join(lines),
                       _plotter(mech, pose[None], np.array(p.angles)[None]))


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
                       "guess": "m, rad"}}
    return Outcome(result, "\n".join(lines))
