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

The forward kinematics query, which takes the same ``method`` and ``dps``, is
:mod:`.forward_kinematics`; it shares this module's pose and unit helpers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...argcheck import check_keys, dps_field, method_field, pose_list
from ...errors import InputError
from ...exact import parse_float
from ..query import Outcome, register
from ..units import angle_factor, length_factor, warn_radians
from .reach import reach_status, reach_text

__all__ = ["InverseKinematicsQuery", "parse_poses", "check_pose_units"]


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
    warn_radians([a for r in rows for a in r[3:]], units,
                 f"{field}.pose" if "pose" in table else f"{field}.poses")
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


def _fmt_pose(pose, scene, digits: int = 10):
    """A pose in the scene's units, to ``digits`` significant digits.  A pose the scene
    gives takes 10: with 6, the poses of one query at z = 497.3287, 497.32875 and
    497.3287549 mm all read 497.329, one of them unreachable (QA 2026-11-29); 10 keep what
    a scene writes and hide the unit conversion's last bits (497.32875490000003 reads
    497.3287549).  A computed pose (forward kinematics) keeps 6: its accuracy is stated
    beside it."""
    lu, au, lf, af = _units(scene)
    p = np.asarray(pose)
    return (f"({', '.join(f'{v * lf:.{digits}g}' for v in p[:3])}) {lu}, "
            f"({', '.join(f'{v * af:.{digits}g}' for v in p[3:])}) {au}")


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


def _plotter(mech, poses, qs=None, *, units=None, note=None):
    """The ``--plots`` drawer of poses (N, 6) (m, rad) of ``mech``, in the scene's
    ``units`` (:mod:`distkin.mechanisms.plot`); ``qs`` (N, L) the joint values drawn
    (default the inverse kinematics), ``note`` a last title line."""
    def plot(stem):
        from ...mechanisms.plot import plot_legs_poses, plot_poses
        return (plot_poses if mech.kind == "rss" else plot_legs_poses)(
            mech, poses, stem, q=qs, units=units, note=note)
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
            # certified: a leg that is neither certified nor certainly infeasible is
            # undecided (at its reach boundary, ...), not unreachable; fast, precise: a
            # reach margin within its error estimate of 0 (QA 25a finding 2)
            status = reach_status(mech, res, i)
            rows.append(_tier_rows(res, i, {"pose": X[i], "q": q[i], "valid": valid[i],
                                            "reachable": status["reachable"],
                                            "reach_margin": margin[i]},
                                   "q_error", "reach_undecided"))
            lines.append(f"pose {i}: {_fmt_pose(X[i], scene)}  -> " + reach_text(status))
            lines.append("  q = " + _joint_text(q[i], mech, scene))
            lines += _tier_lines(res, i)
            if res.method != "certified" and res.reach_undecided[i].any():
                lines.append(f"  undecided in {res.precision}: legs "
                             f"{status['undecided_legs']}: the reach margin is within its "
                             f"error estimate of 0 (at the reach boundary within rounding; "
                             f"valid is the sign's guess); method = \"certified\" decides")
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
                        "poses": rows}, "\n".join(lines), _plotter(mech, X, q, units=scene.units))
