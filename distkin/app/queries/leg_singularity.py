"""Scene query ``singularity`` on a ``kind = "legs"`` or ``kind = "rss"`` mechanism (a
preset through its leg table, :meth:`~distkin.mechanisms.description.RSSDescription.leg_description`:
the same numbers as the table written out as ``kind = "legs"``): det J of the leg lines
(Rojas et al. eq. (5)), and the Cayley-Menger pure condition and the four-planes test
(Sec. IV) wherever they apply, at poses or along a path.

::

    [[query]]
    type = "singularity"
    poses = [[6, 3.4641, 17, 0, 0, 0], ...]     # x y z (length), rx ry rz (angle)
    # or pose = [...] (one pose), or
    path = { from = [...], to = [...], samples = 90 }   # linear in the pose coordinates
    method = "fast"                              # fast | precise | certified
    tolerance = 1e-9                             # optional: of the verdict `singular`

Where the tests apply (:func:`applicability`):

- det J: every six-leg table.  The lines are the legs (prismatic: base joint to
  platform joint) or the distal links (revolute: distal joint D to platform joint P, the
  rows of Jx in Kühne et al. eq. (1)); normalised, the moment columns divided by the
  mechanism's length scale (dimensionless).  L > 6: J is L x 6 and has no determinant;
  σmin of the normalised lines is reported instead (rank 6 or not).
- The Cayley-Menger pure condition (the paper's and the signed form, relative) and the
  four-planes test: only the octahedral topology (six prismatic legs on three base and
  three platform points, each on two legs; ``LegsDescription.octahedral``), whose
  P1..P6 they are written on.  A general 6-6 platform has them only through its
  Δ-transform (eq. (8)), which a leg table does not carry (``kind = "platform66"``,
  query ``singularity``, has it); on revolute legs the distal joints D move with the
  cranks and are six distinct points, not the shared vertices of an octahedron.

``method = "certified"`` evaluates det J, the signed condition and the four planes in
arb on the float64 joint positions (their exact binary values) and certifies the sign
of det J (or says that it cannot); ``precise`` in mpmath.  Every verdict is that of the
float64-rounded pose (``decided_at``; ``verdict``, the report's words): a path's
crossing is located by Brent's method on the float64 det J, and a certified sign at
its rounded pose is no verdict on the crossing itself (``near_singular`` says that
|det J| is below the tolerance there).

Every pose is first checked by the inverse kinematics at the query's tier
(:func:`~.reach.reach_statuses`, the inverse_kinematics query's own words).  Each row has
``reachable`` (every leg closes within its declared joint range or stroke; certified:
certainly), ``unreachable_legs`` (1-based), of them ``out_of_range_legs`` (a revolute
leg that closes outside its angle range, a prismatic leg outside its stroke) and
``undecided_legs`` (certified: a leg no ball decides; fast, precise: a reach margin
within its error estimate of 0).  At a pose with an unreachable
leg the device cannot be: every test is null (``sigma_min``, ``det_J``,
``det_sign_certified``, ...), ``singular`` is null and the verdict says why (text: "NOT
reachable (legs [...])", "undefined (pose not reachable)", as the jacobian query;
certified: no arb certificate is stated).  Where a leg is only undecided the tests are
evaluated but ``singular`` is null (regularity of a pose not proved reachable is not
proved).  Along a path, det J changes sign only between two reachable samples, and a
crossing located there at a pose that is not reachable goes to ``unreachable_crossings``
instead of ``crossings``; ``unreachable_parts`` lists the runs of samples that are not
reachable (``samples`` [first, last], 0-based, their poses ``from`` and ``to`` and the
legs), one report line each.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...argcheck import (as_table, check_keys, method_field, pose_list, positive_int,
                         require)
from ...errors import InputError, UncertifiedError
from ..query import Outcome, register
from ..units import angle_value, length_value
from .jacobian import UNDEFINED
from .reach import reach_statuses, reach_text

__all__ = ["LegSingularityQuery", "applicability", "leg_lines", "singularity_tests_at",
           "MAX_PATH_SAMPLES"]

#: Largest ``path.samples``: every sample is one pose evaluated in full, one at a time
#: (an unbounded count exhausted the memory and the time; QA F6).
MAX_PATH_SAMPLES = 10_000


@dataclass(frozen=True)
class _Params:
    poses: tuple | None
    path: tuple | None
    samples: int
    method: str
    tolerance: float = 1e-9


def _pose(value, units, fld):
    if not isinstance(value, list) or len(value) != 6:
        raise InputError(f"expected [x, y, z, rx, ry, rz], got {value!r}", field=fld)
    return tuple([length_value(v, units, f"{fld}[{i}]") for i, v in enumerate(value[:3])]
                 + [angle_value(v, units, f"{fld}[{i + 3}]") for i, v in enumerate(value[3:])])


def _table(mech):
    """The leg table of ``mech``: itself (kind "legs") or its leg description (kind
    "rss": every preset is a leg table, :meth:`~distkin.mechanisms.description.RSSDescription.leg_description`)."""
    return mech if hasattr(mech, "leg_table") else mech.leg_description()


def applicability(mech) -> dict:
    """Which tests apply to ``mech`` (a leg table, or an RSS mechanism through its leg
    table) and why (module docstring): ``det``, ``cm`` (bool) and ``reason`` (text)."""
    table = _table(mech)
    if mech.L != 6:
        return {"det": False, "cm": False,
                "reason": f"L = {mech.L}: J is {mech.L} x 6, singular where its rank drops "
                          "(σmin = 0), no determinant; the Cayley-Menger and four-planes "
                          "tests are written for six legs"}
    if table.octahedral() is not None:
        return {"det": True, "cm": True,
                "reason": "octahedral topology (Rojas et al. Fig. 4): det J of eq. (5), the "
                          "Cayley-Menger pure condition and the four-planes test (Sec. IV)"}
    if all(leg.prismatic for leg in table.leg_table):
        why = ("a 6-6 platform: the Cayley-Menger pure condition and the four-planes test "
               "are written on the six points of the octahedral topology; a 6-6 platform "
               "has them only through its Δ-transform (eq. (8)), which a leg table does not "
               "carry (kind = platform66, query singularity)")
    else:
        why = ("revolute legs: det J of the distal links' lines (Jx of Kühne et al. eq. (1)) "
               "applies; the Cayley-Menger and four-planes tests do not (the distal joints "
               "move with the cranks and are six distinct points, not the shared vertices "
               "of an octahedron)")
    return {"det": True, "cm": False, "reason": why}


def leg_lines(mech, pose):
    """The line ends of each leg at ``pose`` (m): base end (L, 3) (the base joint, or the
    distal joint D of a revolute leg) and platform joint (L, 3)."""
    pts = mech.points(np.asarray(pose, dtype=float))
    return pts["D"], pts["P"]


def _octa_points(mech, pose):
    """P1..P6 (6, 3) in the base frame (m) of an octahedral-topology table at ``pose``."""
    from ...spatial import rotation_matrix
    topo = _table(mech).octahedral()
    x = np.asarray(pose, dtype=float)
    plat = x[:3] + topo["platform"] @ rotation_matrix(x[3:]).T
    return np.vstack([topo["base"], plat])


def singularity_tests_at(mech, pose, method: str = "fast", tolerance: float = 1e-9) -> dict:
    """det J (normalised, moments / length scale), σmin of the normalised lines (moments
    about the end-effector origin, as the rows of the kernels' J), and
    for the octahedral topology the relative Cayley-Menger conditions and the four
    planes (relative, spread in m), at one pose (m, rad).

    ``singular``: the verdict, as the octahedral query's (QA V 5): fast and precise a
    tolerance test (|det J| < ``tolerance``, or σmin < ``tolerance`` where J has no
    determinant); certified the arb sign of det J (False where it is proven != 0, True
    where it is exactly 0, None where its ball contains 0 at 53, 256 and 2048 bits),
    with ``near_singular`` the tolerance test.  ``singular_test`` says which."""
    from ...singularity.conditions import (cm_pure_condition, four_planes, jacobian_det,
                                           signed_cm_condition)
    app = applicability(mech)
    s = mech.length_scale
    b, p = leg_lines(mech, pose)
    u = (p - b) / np.linalg.norm(p - b, axis=1)[:, None]
    J = np.hstack([u, np.cross(b - np.asarray(pose, dtype=float)[:3], u) / s])   # (L, 6)
    out = {"sigma_min": float(np.linalg.svd(J, compute_uv=False)[-1])}
    if app["det"]:
        tier = None if method == "fast" else method
        d = jacobian_det(b, p, length_scale=s, method=tier, warn=False)
        if method == "certified":      # det_J: the midpoint of the ball that decided
            out["det_sign_certified"], d = _certified_sign(d, b, p, s)
        out["det_J"] = _float(d)
    near = bool(abs(out["det_J"]) < tolerance) if app["det"] else \
        bool(out["sigma_min"] < tolerance)
    test = (f"tolerance test |det J| < {tolerance:g} ({method} tier; not a proof)" if app["det"]
            else f"tolerance test σmin < {tolerance:g} (float64; J is {mech.L} x 6: no "
                 f"determinant, nothing certified)")
    if method == "certified" and app["det"]:
        sgn = out["det_sign_certified"]
        out["singular"] = None if sgn is None else sgn == 0
        out["near_singular"] = near
        out["singular_test"] = "arb certificate of sign det J" + (
            " (undecided: its ball contains 0)" if sgn is None else "")
    else:
        out["singular"], out["singular_test"] = near, test
    if app["cm"]:
        P = _octa_points(mech, pose) / s
        tier = None if method == "fast" else method
        f = _float
        import warnings
        from ...geometry.cm_float import CancellationWarning
        with warnings.catch_warnings():     # undefined (NaN): said as None (QA V 2)
            warnings.simplefilter("ignore", CancellationWarning)
            for key, g in (("cm_relative", cm_pure_condition),
                           ("signed_cm_relative", signed_cm_condition)):
                v = f(g(P, relative=True, method=tier))
                out[key] = None if v != v else v
        fp = four_planes(P, method=tier, warn=False)      # said per pose instead (QA 24)
        out["four_planes_relative"] = f(fp.relative)
        out["four_planes_sign_resolved"] = bool(fp.det_error is None
                                                or fp.det_error < abs(fp.det))
        out["four_planes_spread"] = float(fp.spread) * s
    return out


def _certified_sign(d, b, p, s):
    """(the arb sign of det J or None, the ball it was read from).  The poses' floats
    are exact, so where the ball ``d`` contains 0 the normalisation's square roots are
    recomputed at 256, then 2048 bits (arb), until the sign is decided; the ball
    returned is the one that decided it (QA: the 128-bit ball's midpoint, 0, was
    reported beside "certified < 0" from the 256-bit ball, -2.7e-17)."""
    from ...exact_roots import working_precision
    from ...singularity.conditions import certified_sign, jacobian_det
    try:
        return certified_sign(d), d
    except UncertifiedError:
        pass
    for bits in (256, 2048):
        with working_precision(bits):
            ball = jacobian_det(b, p, length_scale=s, method="certified")
            try:
                return certified_sign(ball), ball
            except UncertifiedError:
                continue
    return None, d


#: the units of the result (QA W 10: the only query without a unit block)
_UNIT = {"pose": "m, rad", "length_scale_m": "m",
         "sigma_min": "none (of J: unit leg lines, moment columns divided by length_scale_m)",
         "det_J": "none (of that J)", "tolerance": "none (on det J, or on sigma_min)",
         "cm_relative": "none", "signed_cm_relative": "none",
         "four_planes_relative": "none", "four_planes_spread": "m",
         "four_planes_sign_resolved": "bool (fast: F's float64 rounding-error estimate is "
                                      "below |F|; the exact tiers: true)",
         "verdict": "text: what was decided and for which pose (decided_at)",
         "reachable": "bool: every leg closes within its declared joint range (certified: "
                      "certainly); false: every test null, no verdict",
         "unreachable_legs": "1-based legs", "out_of_range_legs": "1-based legs",
         "undecided_legs": "1-based legs",
         "unreachable_parts": "path: runs of samples not reachable, samples 0-based "
                              "[first, last], from/to m, rad"}


@register("singularity", mechanisms=("legs", "rss"),
          summary="det J of the leg lines (eq. 5), Cayley-Menger and four-planes tests where "
                  "they apply, at poses or along a path")
class LegSingularityQuery:
    @staticmethod
    def parse(table, mechanism, units, field):
        check_keys(table, {"type", "pose", "poses", "path", "method", "tolerance"}, field)
        given = [k for k in ("pose", "poses", "path") if k in table]
        if len(given) != 1:
            raise InputError("expected exactly one of pose, poses and path, got "
                             + (" and ".join(given) if given else "none"), field=field)
        poses = path = None
        samples = 90
        if "pose" in table:
            poses = (_pose(table["pose"], units, f"{field}.pose"),)
        elif "poses" in table:
            raw = pose_list(table["poses"], f"{field}.poses")
            poses = tuple(_pose(v, units, f"{field}.poses[{i}]") for i, v in enumerate(raw))
        else:
            pt = as_table(table["path"], f"{field}.path")
            check_keys(pt, {"from", "to", "samples"}, f"{field}.path")
            path = tuple(_pose(require(pt, k, f"{field}.path"), units, f"{field}.path.{k}")
                         for k in ("from", "to"))
            samples = positive_int(pt.get("samples", 90), f"{field}.path.samples", minimum=3)
            if samples > MAX_PATH_SAMPLES:
                raise InputError(f"expected at most {MAX_PATH_SAMPLES} samples, got {samples}",
                                 field=f"{field}.path.samples",
                                 hint="each sample is one pose evaluated in full; crossings "
                                      "between samples are located by Brent's method")
        from .mechanisms import check_pose_units      # float64-meaningless poses (QA R 8)
        names = ([f"{field}.pose"] if "pose" in table else
                 [f"{field}.poses[{i}]" for i in range(len(poses))] if poses else
                 [f"{field}.path.from", f"{field}.path.to"])
        check_pose_units(np.array(poses or path), units, names, mechanism.length_scale)
        from ...argcheck import relative_tol
        tol = relative_tol(table.get("tolerance", 1e-9), f"{field}.tolerance")
        return _Params(poses, path, samples, method_field(table, field), tol)

    @staticmethod
    def run(p, scene, ctx):
        mech = scene.mechanism
        app = applicability(mech)
        lu = scene.units.length if scene.units.length != "none" else "m"
        lf = 1.0 / float(scene.units.length_factor)
        deg = scene.units.angle == "deg"
        af = 180 / np.pi if deg else 1.0
        au = "deg" if deg else "rad"

        def fmt_pose(x, digits=10):
            # a pose the scene gives (or a path sample) to 10 digits, as the kinematics
            # queries echo them (two poses 40 nm apart, one unreachable, both read
            # 497.329 mm: review 2026-11-29); a computed crossing to 6
            return (f"({', '.join(f'{v * lf:.{digits}g}' for v in x[:3])}) {lu}, "
                    f"({', '.join(f'{v * af:.{digits}g}' for v in x[3:])}) {au}")

        lines = [f"  mechanism: {mech.name} (L = {mech.L}); tests: {app['reason']}",
                 ("  det J: normalised leg lines, moment columns / " if app["det"] else
                  "  σmin of the normalised leg lines, moment columns / ")
                 + f"{mech.length_scale * lf:.6g} {lu} (dimensionless)"
                 + ("; Cayley-Menger and four planes on P1..P6 / that length (relative, in "
                    f"[-1, 1]); spread in {lu}" if app["cm"] else "")]
        rows = []
        poses = p.poses
        if p.path is not None:
            a, b = (np.asarray(v) for v in p.path)
            s = np.linspace(0.0, 1.0, p.samples)
            poses = tuple(a + si * (b - a) for si in s)
        reach = reach_statuses(mech, poses, p.method)
        for i, x in enumerate(poses):
            r = _tests_if_reachable(mech, x, p, reach[i])
            rows.append(r)
            if p.path is None:
                lines.append(f"  pose {i}: {fmt_pose(x)}" + ("" if reach[i]["reachable"] else
                                                             "  -> " + _reach_words(reach[i])))
                lines.append("    " + _fmt(r, lf, lu))
        crossings, dropped = [], []
        if p.path is not None and app["det"]:
            # a sign change only between reachable samples: an unreachable sample has no
            # leg lines, so no det J (NaN: no sign, no local minimum of |det J|)
            det = np.array([r["det_J"] if reach[k]["reachable"] else np.nan
                            for k, r in enumerate(rows)], dtype=float)
            sg = np.sign(det)
            hits = [k for k in range(len(det)) if sg[k] == 0 and 0 < k < len(det) - 1]
            hits += [k for k in range(len(det) - 1) if sg[k] * sg[k + 1] < 0]
            found = [poses[k] if sg[k] == 0 else _crossing(mech, poses[k], poses[k + 1])
                     for k in sorted(hits)]
            found += _root_pairs_between(mech, a, b, s, det)     # QA F2
            found.sort(key=lambda c: float(np.linalg.norm(c - a)))
            for c, st in zip(found, reach_statuses(mech, found, p.method)):
                # between two reachable samples the path may still leave the workspace
                r = _tests_if_reachable(mech, c, p, st, crossing=True)
                (crossings if st["reachable"] else dropped).append(r)
            some = not all(st["reachable"] for st in reach)
            lines.append(f"  path: {p.samples} poses from {fmt_pose(poses[0])} to "
                         f"{fmt_pose(poses[-1])}; det J changes sign {len(crossings)} time(s)"
                         + (" between reachable samples" if some else "")
                         + " (a sample where det J is 0 counts as a crossing; a lower bound: "
                         "sign changes on the samples and root pairs searched at the local "
                         "minima of |det J|, not certified complete)")
            for r in crossings:
                lines.append(f"    crossing at {fmt_pose(r['pose'], 6)}: " + _fmt(r, lf, lu))
            for r in dropped:
                lines.append(f"    not a crossing of the device: det J of the leg lines "
                             f"changes sign at {fmt_pose(r['pose'], 6)}, between two reachable "
                             f"samples, but that pose is {_reach_words(r)}")
        if p.path is not None:
            lines += _unreachable_lines(_unreachable_parts(reach, poses), len(poses), fmt_pose)
        lines.append(f"  accuracy: {p.method} tier ("
                     + {"fast": "float64", "precise": "mpmath",
                        "certified": "arb balls on the float64 joint positions"}[p.method]
                     + "); crossings located by Brent's method on det J to 1e-12 of the path")
        result = {"mechanism": mech.name, "applicability": app, "method": p.method,
                  "tolerance": p.tolerance,
                  "length_scale_m": mech.length_scale, "poses": rows, "crossings": crossings,
                  "unit": _UNIT}
        if p.path is not None:
            result["unreachable_parts"] = _unreachable_parts(reach, poses)
            result["unreachable_crossings"] = dropped
        plot = _path_plotter(rows, crossings, result, p) if p.path and app["det"] else None
        return Outcome(result, "\n".join(lines), plot)


def _path_plotter(rows, crossings, result, p):
    """The ``--plots`` drawer of a path on a six-leg table: det J (null where a sample is
    not reachable), the CM conditions and the four planes where they apply, the
    crossings and the unreachable runs of samples (shaded), the result's own numbers,
    drawn by :func:`.singularity_path.plot_path` (s = 0 at ``from``, 1 at ``to``)."""
    from .singularity_path import plot_path
    s = np.linspace(0.0, 1.0, p.samples)
    a, b = (np.asarray(v, dtype=float) for v in p.path)
    col = lambda k: np.array([np.nan if r.get(k) is None else _float(r[k])  # noqa: E731
                              for r in rows], dtype=float)
    undefined = lambda k: [float(x) for x, r in zip(s, rows) if k in r  # noqa: E731
                           and r["reachable"] and r[k] is None]
    data = {"s": s, "det_J": col("det_J"), "roots": [
                float(np.dot(np.asarray(c["pose"]) - a, b - a) / np.dot(b - a, b - a))
                for c in crossings], "spurious": [],
            "unreachable": [(s[i], s[j]) for i, j in
                            (part["samples"] for part in result["unreachable_parts"])],
            "undefined": {"cm": undefined("cm_relative"),
                          "signed_cm": undefined("signed_cm_relative")}}
    if "cm_relative" in rows[0]:
        data.update(cm=col("cm_relative"), signed_cm=col("signed_cm_relative"),
                    four_planes=col("four_planes_relative"))
    return lambda stem: plot_path(data, stem)


def _reach_words(st) -> str:
    """:func:`~.reach.reach_text` of a reach status, with the legs whose joint is
    outside its declared range (angle range, stroke) named."""
    out = st["out_of_range_legs"]
    return reach_text(st) + (f", outside their declared joint range or stroke: legs {out}"
                             if out else "")


def _tests_if_reachable(mech, x, p, st, crossing=False) -> dict:
    """The row of pose ``x`` (m, rad) with its reach status ``st``: the tests of
    :func:`singularity_tests_at` and their verdict where every leg closes within its
    range.  Where a leg certainly does not (``unreachable_legs``) the leg lines do not
    exist: every test is null and there is no verdict (QA: "det J certified < 0,
    singular: no" 3 m above the Hunt preset, which no leg reaches).  Where the tier
    cannot decide a leg (``undecided_legs``) the tests are evaluated but
    ``singular`` is null: regularity of a pose not proved reachable is not proved."""
    if st["unreachable_legs"]:
        app = applicability(mech)
        keys = (["sigma_min"] + ["det_J"] * app["det"]
                + ["det_sign_certified", "near_singular"]
                * (app["det"] and p.method == "certified")
                + ["cm_relative", "signed_cm_relative", "four_planes_relative",
                   "four_planes_spread"] * app["cm"])
        r = {**dict.fromkeys(keys), "singular": None,
             "singular_test": "not evaluated: the pose is not reachable"}
    else:
        r = singularity_tests_at(mech, x, p.method, p.tolerance)
        if not st["reachable"]:
            r["singular"] = None
            r["singular_test"] += (f"; the pose's reachability is not decided (legs "
                                   f"{st['undecided_legs']} undecided): no verdict")
    r["pose"] = [float(v) for v in x]
    r.update(st)
    return _verdict(r, p.tolerance, crossing=crossing, method=p.method)


def _unreachable_parts(reach, poses) -> list:
    """The runs of consecutive path samples that are not reachable: ``samples`` [first,
    last] (0-based), their poses ``from`` and ``to`` (m, rad) and the legs named over the
    run (the union of each sample's :func:`~.reach.reach_status` lists)."""
    parts, k = [], 0
    while k < len(reach):
        if reach[k]["reachable"]:
            k += 1
            continue
        j = k
        while j + 1 < len(reach) and not reach[j + 1]["reachable"]:
            j += 1
        part = {"samples": [k, j], "from": [float(v) for v in poses[k]],
                "to": [float(v) for v in poses[j]]}
        for key in ("unreachable_legs", "out_of_range_legs", "undecided_legs"):
            part[key] = sorted({leg for st in reach[k:j + 1] for leg in st[key]})
        parts.append(part)
        k = j + 1
    return parts


def _unreachable_lines(parts, n, fmt_pose) -> list:
    """The report's lines of :func:`_unreachable_parts` of a path of ``n`` samples."""
    out = []
    for part in parts:
        i, j = part["samples"]
        words = _reach_words({**part, "reachable": False})
        out.append(f"  not reachable: samples {i}-{j} of 0-{n - 1}, from {fmt_pose(part['from'])} "
                   f"to {fmt_pose(part['to'])}: {words}; the device cannot take these poses: no "
                   "det J, no verdict and no crossing reported there")
    return out


def _float(v):
    """A float of a float, mpf, fmpq or arb (its midpoint)."""
    return float(v.mid()) if hasattr(v, "mid") else float(v)


def _fmt(r, lf, lu):
    if r.get("unreachable_legs"):
        return (("det J, σmin" if "det_J" in r else "σmin") + f": {UNDEFINED}; "
                + r["verdict"])
    parts = [f"σmin {r['sigma_min']:.6g}"]
    if "det_J" in r:
        parts.append(f"det J {r['det_J']:.6g}"
                     + (" (its arb ball's midpoint)" if "det_sign_certified" in r else ""))
    if "cm_relative" in r:
        g = lambda v: "undefined (0/0 within rounding)" if v is None else f"{v:.4g}"  # noqa: E731
        parts += [f"CM (paper) {g(r['cm_relative'])}", f"CM signed {g(r['signed_cm_relative'])}",
                  f"four planes {r['four_planes_relative']:.4g} "
                  f"(spread {r['four_planes_spread'] * lf:.4g} {lu})"]
    # the verdict last: it says for which pose it holds (the same words as the JSON's)
    return (", ".join(parts) + " (dimensionless unless a unit is given)"
            + (f"; {r['verdict']}" if "verdict" in r else ""))


#: where every verdict of this query is decided: the pose as float64 numbers (a pose
#: written "sqrt(12)", a crossing located by Brent's method), its joints in float64
DECIDED_AT = "the float64-rounded pose"


def _verdict(r, tolerance, crossing=False, method=None):
    """Say what was decided and for which pose (``r["verdict"]``, the same words in the
    text; ``r["decided_at"]``): the tiers evaluate det J at the float64-rounded pose, so
    a certified sign there says nothing of a singular pose within rounding of it (QA:
    "det J certified < 0, singular: no" at the 90° crossing of a twist whose exact
    pose is singular).  ``near_singular`` (|det J| < ``tolerance``, certified tier)
    says that; a ``crossing`` is where Brent's method located a sign change of the
    float64 det J, to 1e-12 of the path."""
    if "singular" not in r:
        return r
    if r.get("unreachable_legs"):       # no leg lines: nothing was evaluated
        text = (f"{_reach_words(r)}: the device cannot take this pose, so det J, σmin and "
                "the other tests are not evaluated (null) and there is no verdict "
                "(singular: undefined)")
        if method == "certified":
            text += ("; no arb certificate: a sign of det J at a pose the device cannot "
                     "take would certify nothing")
        r["decided_at"], r["verdict"] = DECIDED_AT, text
        return r
    v, s = r["singular"], r.get("det_sign_certified", "absent")
    sign = ("" if s == "absent" else
            "the sign of det J not certified (its ball contains 0), " if s is None else
            "det J certified " + {1: "> 0", -1: "< 0", 0: "= 0 exactly"}.get(s, str(s)) + ", ")
    there = ("undecided" if v is None else "yes" if v else "no")
    text = f"at {DECIDED_AT}: {sign}singular: {there} ({r['singular_test']})"
    near = r.get("near_singular")
    if near and v is not True:
        text += f"; |det J| < {tolerance:g} there: near-singular"
    if crossing:
        text += ("; the crossing itself (a sign change of the float64 det J, located by "
                 "Brent's method to 1e-12 of the path) lies within that of this pose: the "
                 "verdict is this pose's, not the crossing's")
    r["decided_at"], r["verdict"] = DECIDED_AT, text
    return r


def _root_pairs_between(mech, a, b, s, det):
    """Poses of the root pairs of det J inside one sample interval of the path a -> b
    (samples ``s``, float values ``det``), searched at the local minima of |det J|
    (:func:`distkin.singularity.paths.path_crossings`, QA F2)."""
    from ...singularity.conditions import jacobian_det
    from ...singularity.paths import _root_pairs

    def f(x):
        x = a + x * (b - a)
        return float(jacobian_det(*leg_lines(mech, x), length_scale=mech.length_scale,
                                   warn=False))
    vals = np.array([float(v) for v in det])
    return [a + r * (b - a) for r in _root_pairs(f, np.asarray(s), vals, 1e-12)]


def _crossing(mech, a, b):
    """The pose between ``a`` and ``b`` where det J = 0 (Brent's method)."""
    from scipy.optimize import brentq

    from ...singularity.conditions import jacobian_det

    def f(t):
        x = a + t * (b - a)
        return float(jacobian_det(*leg_lines(mech, x), length_scale=mech.length_scale,
                                   warn=False))
    t = brentq(f, 0.0, 1.0, xtol=1e-12)
    return a + t * (b - a)
