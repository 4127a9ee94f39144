r"""The certified tier of the octahedral forward kinematics (python-flint).

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III.

1. The octic and the quadratic parts of eq. (3) are computed **exactly** in ``fmpq``
   by the generated kernel (the squared lengths must be rational).
2. Its distinct real roots are isolated with certainty
   (:func:`distkin.exact_roots.real_roots`, FLINT's ``complex_roots``): the count is
   proved, and so are the multiplicities.
3. Each root is classified with certified signs
   (:func:`distkin.exact_roots.sign_at_root`): it is an assembly mode iff the shared
   faces are real triangles (:math:`D(5,4,1), D(3,5,1) < 0`) and the four tetrahedra of
   the bananas have non-negative squared volume; otherwise it is spurious.  A sign that
   is exactly 0 is found exactly (common factor with the octic).
4. The trilateration sequence runs in ``arb`` balls around the root; the one
   placement of (P4, P6) compatible with leg 5 is identified by balls (the others'
   leg-5 residual balls exclude 0).  The root enclosure is refined (doubling the
   working precision) until every point's radius is below ``tol`` times the size of
   the mechanism.

Whatever cannot be decided raises :class:`~distkin.errors.UncertifiedError`: a flat
face or flat tetrahedron at a root (a pose at the edge of assemblability), or a
placement that the balls cannot single out.  The count is never guessed.
"""

from __future__ import annotations

from fractions import Fraction

from ..exact import float_ball
from ..exact_roots import MAX_BITS, ball_ends, real_roots, sign_at_root, working_precision
from ..errors import (DegenerateGeometryError, InfeasibleError, InputError,
                      UncertifiedError)
from .assembly import assemble_exact
from .closure import OCTIC, PART_NAMES, octic_data
from .problem import LEG_PAIRS, SIDE_PAIRS, Problem

__all__ = ["solve_certified", "leg_error_bounds", "segment_error_bounds"]


def _q(v):
    import flint
    return flint.fmpq(v.numerator, v.denominator)


def _refuse_irrational(problem: Problem):
    """The certified tier needs the exact octic over the rationals: squared sides and
    legs rational (Rojas et al., ICRA 2012, eq. (3) has them as coefficients).  An
    :class:`InputError` naming the inputs that make some irrational, and their values
    (QA: it named ``legs`` for an irrational base coordinate, without its value); its
    ``field`` is the first of them."""
    bad = problem.irrational
    names = [f"|P{a}P{b}|^2" for (a, b), v in zip(SIDE_PAIRS, problem.sides2)
             if not isinstance(v, Fraction)]
    names += [f"l{i + 1}^2" for i, v in enumerate(problem.legs2) if not isinstance(v, Fraction)]
    got = ", ".join(f"{f} = {t}" for f, t, _ in bad[:4])
    if len(bad) > 4:
        got += f" and {len(bad) - 4} more"
    raise InputError(
        f"expected rational squared lengths for the certified tier (squared sides "
        f"|PiPj|^2 and legs li^2), got {len(names)} irrational one(s), "
        f"{', '.join(names)}, from {got or 'the data'}",
        field=bad[0][0] if bad else "legs",       # (the message names them all)
        hint="give coordinates whose squared differences sum to rationals (sqrt(108) "
             "against 0 does) and legs whose squares are rational, or use "
             "method='precise' (or 'auto', which falls back to it)")


def solve_certified(problem: Problem, tol: float):
    """Every assembly mode, certified; see :func:`.forward.forward_kinematics`."""
    import flint
    from .result import AssemblyResult, RootInfo, _SPURIOUS_NOTE, _empty_reason
    if not problem.rational:
        _refuse_irrational(problem)
    sides = [_q(v) for v in problem.sides2]
    legs2 = [_q(v) for v in problem.legs2]
    d = [flint.fmpq(v) for v in octic_data(sides, legs2, "exact")]
    octic = d[OCTIC]
    if all(c == 0 for c in octic):
        raise DegenerateGeometryError("expected an octic that does not vanish identically, got "
                                      "the zero polynomial (degenerate geometry)", field="legs")
    poly = flint.fmpq_poly(list(reversed(octic)))
    parts = {name: flint.fmpq_poly([d[3 * i], d[3 * i + 1], d[3 * i + 2]])
             for i, name in enumerate(PART_NAMES)}
    roots = real_roots(poly, bits=64)
    infos, feasible = [], []
    open_face = _open_face(problem)
    for r in roots:
        status, reason = ("spurious", open_face) if open_face else _classify(poly, parts, r)
        infos.append([r, status, reason])
        if status == "assembly":
            feasible.append(r)
    size = max(float(v) for v in problem.sides2 + problem.legs2) ** 0.5
    flat = {r.index for r, status, reason in infos if "flat" in reason}
    poses, radii = _poses(problem, poly, feasible, sides, legs2, tol, size, flat)
    out = []
    for r, status, reason in infos:
        ball = radii.get(r.index, r.ball)
        value, radius = float_ball(ball)
        out.append(RootInfo(value, radius, r.multiplicity, status, reason, ball, "certified"))
    reason = "" if poses else _empty_reason(out)
    return AssemblyResult(tuple(poses), "certified",
                          tuple(Fraction(int(c.p), int(c.q)) for c in octic), True,
                          tuple(out), True, reason,
                          f"certified: exact octic, FLINT root isolation, arb balls; point "
                          f"radii <= {tol:.1e} x size", (_SPURIOUS_NOTE,))


#: the six side faces of the octahedron (Sec. II), each by its three vertices
_FACES = ((1, 2, 4), (2, 4, 5), (2, 3, 5), (3, 5, 6), (1, 3, 6), (1, 4, 6))


def _open_face(problem: Problem) -> str:
    """Why no assembly exists, decided exactly from the squared lengths alone, or "":
    a side face of the octahedron whose squared area (the Cayley-Menger determinant of
    the triangle, :func:`~distkin.geometry.cayley_menger.triangle_area_squared`) is
    negative: its lengths violate the triangle inequality.  Then every real root of the
    octic is spurious, flat faces at a root included (the classification would stop
    there)."""
    from ..geometry.cayley_menger import triangle_area_squared
    sq = dict(zip(SIDE_PAIRS + LEG_PAIRS, problem.sides2 + problem.legs2))
    for face in _FACES:
        if triangle_area_squared(sq, *face) < 0:
            name = " ".join(f"P{i}" for i in face)
            return (f"spurious: the face {name} of the octahedron is not a real triangle "
                    "(its lengths violate the triangle inequality): no assembly exists")
    return ""


def _classify(poly, parts, r):
    flat = False
    for name, want, text in (("u", -1, "D(5,4,1)"), ("v", -1, "D(3,5,1)")):
        s = sign_at_root(poly, parts[name], r)
        if s == 0:
            raise UncertifiedError(f"the face {text} of a banana is flat at the root "
                                   f"s15 = {r.ball}; the trilateration sequence cannot place "
                                   "the platform there")
        if s != want:
            return "spurious", (f"spurious: the face {text} is not a real triangle at this "
                                "root (outside the triangle bounds of s15)")
    for name, text in (("T1a", "D(5,4,1,2)"), ("T1b", "D(5,4,1,6)"),
                       ("T2a", "D(3,5,1,2)"), ("T2b", "D(3,5,1,6)")):
        s = sign_at_root(poly, parts[name], r)
        if s < 0:
            return "spurious", (f"spurious: {text} < 0 at this root (a tetrahedron with "
                                "negative squared volume: complex assembly)")
        if s == 0:
            flat = True
    if flat:
        return "assembly", ("assembly mode with a flat tetrahedron (edge of "
                            "assemblability: two placements coincide)")
    return "assembly", "assembly mode"


def _poses(problem, poly, feasible, sides, legs2, tol, size, flat=()):
    import flint
    import numpy as np
    from ..geometry.poses import frame_fit
    from .result import Pose
    out, radii = [], {}
    base0 = [[_q(v) if isinstance(v, Fraction) else v for v in r] for r in problem.base]
    plat0 = [[_q(v) if isinstance(v, Fraction) else v for v in r] for r in problem.platform]
    rational = {}
    if flat:  # a zero height: try the exact path, which needs the root to be rational
        for q, _m in flint.fmpq_poly(poly).roots():
            rational[float(q)] = q
    for r in feasible:
        bits, ball = 64, r.ball
        lower, upper = ball_ends(r.ball)
        exact = [q for q in rational.values() if lower <= q <= upper]
        if exact and all(type(v).__name__ == "fmpq" for row in base0 + plat0 for v in row):
            try:
                built = _exact_poses(base0, plat0, exact[0], sides, legs2, problem,
                                     tol * size)
            except (InfeasibleError, DegenerateGeometryError) as exc:  # as the balls' path:
                raise UncertifiedError(       # auto then asks the precise tier (review)
                    f"trilateration at the certified root s15 = {exact[0]} failed: "
                    f"{exc.message}") from None
            radii[r.index] = flint.arb(exact[0])
            out.extend(built)
            continue
        while True:
            with working_precision(bits + 30):
                # irrational data are re-enclosed at the working precision
                base, plat = _enclose(base0), _enclose(plat0)
                legs = [_enclose_one(v) for v in problem.legs]
                try:
                    pairs = assemble_exact(base, ball, sides, legs2, method="certified")
                except (InfeasibleError, DegenerateGeometryError) as exc:
                    raise UncertifiedError(f"trilateration at the certified root s15 = "
                                           f"{ball} failed: {exc.message}") from None
                except UncertifiedError:
                    pairs = None
                if pairs is not None:
                    built = []
                    try:
                        for side, (pts, _) in zip((1, -1), pairs):
                            R, t = frame_fit(plat, pts, "certified")  # congruent: built so
                            err, rel = leg_error_bounds(base, pts, legs)
                            rad = max(float(c.rad()) for row in pts for c in row)
                            built.append((side, pts, R, t, err, rel, rad))
                    except UncertifiedError:
                        # the placed triangle's balls too wide to prove it a triangle (a
                        # platform 1e-4 of the base: QA 23d 1): more bits, as for
                        # the trilateration
                        built = None
                    if built is not None and max(b[-1] for b in built) <= tol * size:
                        break
            if bits >= MAX_BITS and r.multiplicity > 1:
                raise UncertifiedError(
                    f"s15 = {r.ball} is a root of multiplicity {r.multiplicity}, where "
                    "several assembly modes can meet (a symmetric configuration: e.g. "
                    "equilateral base and platform with six equal legs); the balls cannot "
                    f"single out its placements within {MAX_BITS} bits",
                    hint="method='precise' gives every mode at a multiple root, each with "
                         "its leg residual (not certified)")
            if bits >= MAX_BITS:
                raise UncertifiedError(f"cannot enclose the poses of root s15 = {r.ball} to "
                                       f"{tol:.1e} within {MAX_BITS} bits")
            bits *= 2
            ball = real_roots(poly, bits=bits)[r.index].ball
        radii[r.index] = ball
        mid = lambda a: np.array([[float(c.mid()) for c in row] for row in a])  # noqa: E731
        for side, pts, R, t, err, rel, _ in built:
            out.append(Pose(float(ball.mid()), side, mid(R), np.array([float(c.mid()) for c in t]),
                            mid(pts), err, rel,
                            {"s15": ball, "points": pts, "rotation": R, "translation": t},
                            _points_radius(pts)))
    return out, radii


def _exact_poses(base, plat, x, sides, legs2, problem, limit):
    """Poses at an exactly rational root with rational data: exact arithmetic throughout
    (a zero height is exactly zero, e.g. a flat configuration at the edge of
    assemblability, where the two mirror images coincide and count once).  A point
    that is irrational all the same (the square root of a rational height) is an arb
    ball, and the working precision is doubled until every point's radius is at most
    ``limit`` (``tol`` times the size of the mechanism), as for an irrational root
    (QA: computed at the context's 53 bits, such poses had radii of 2e-12 under an
    accuracy statement of 1e-15 x size)."""
    bits = 64
    while True:
        with working_precision(bits + 30):
            out = _exact_poses_at(base, plat, x, sides, legs2, problem)
        rad = max((float(c.rad()) for p in out for row in p.native["points"] for c in row
                   if type(c).__name__ == "arb"), default=0.0)  # (the balls', as _poses)
        if rad <= limit:
            return out
        if bits >= MAX_BITS:
            raise UncertifiedError(f"cannot enclose the poses of root s15 = {x} to "
                                   f"{limit:.1e} within {MAX_BITS} bits")
        bits *= 2


def _exact_poses_at(base, plat, x, sides, legs2, problem):
    """:func:`_exact_poses` at the working precision in force."""
    import flint
    import numpy as np
    from ..geometry.poses import frame_fit
    from .result import Pose
    pairs = assemble_exact(base, x, sides, legs2, method="certified")
    legs = [_enclose_one(v) for v in problem.legs]
    out, seen = [], []
    for side, (pts, _) in zip((1, -1), pairs):
        key = [[flint.fmpq(c) if type(c).__name__ == "fmpq" else c for c in row] for row in pts]
        if any(all(a == b for ra, rb in zip(key, k2) for a, b in zip(ra, rb)) for k2 in seen):
            continue
        seen.append(key)
        R, t = frame_fit(plat, pts, "certified")  # congruent: built so
        err, rel = leg_error_bounds(base, pts, legs)
        out.append(Pose(float(x.p) / float(x.q), side, _mids(R),
                        np.array([float(flint.arb(c).mid()) for c in t]), _mids(pts), err, rel,
                        {"s15": x, "points": pts, "rotation": R, "translation": t},
                        _points_radius(pts)))
    return out


def _points_radius(pts) -> float:
    """:attr:`.result.Pose.radius`: the largest radius about the float points that
    encloses their balls (:func:`~distkin.exact.float_ball`)."""
    return max(float_ball(c)[1] for row in pts for c in row)


def _mids(rows):
    import flint
    import numpy as np
    return np.array([[float(flint.arb(c).mid()) for c in row] for row in rows])


def _enclose_one(v):
    import flint
    from ..exact import sympy_to_arb
    if isinstance(v, Fraction):
        return flint.arb(_q(v))
    if type(v).__name__ in ("fmpq", "arb"):
        return flint.arb(v)
    return sympy_to_arb(v)


def _enclose(rows):
    return [[v if type(v).__name__ == "fmpq" else _enclose_one(v) for v in r] for r in rows]


def leg_error_bounds(base, pts, legs):
    """Rigorous upper bounds (float64, rounded up) of ``max_k | |P_i P_j| - l_k |``,
    absolute and relative to ``l_k``, over the six legs (:data:`.problem.LEG_PAIRS`):
    ``base`` P1 P2 P3 and ``pts`` P4 P5 P6 rows of arb balls or exact numbers, ``legs``
    arb balls.  Also the JSON's bound for the printed float64 points
    (:func:`distkin.app.queries.octahedral.floats_leg_error`)."""
    P = {1: base[0], 2: base[1], 3: base[2], 4: pts[0], 5: pts[1], 6: pts[2]}
    return segment_error_bounds([P[i] for i, _ in LEG_PAIRS], [P[j] for _, j in LEG_PAIRS],
                                legs)


def segment_error_bounds(ends_a, ends_b, legs):
    """Rigorous upper bounds (float64, rounded up) of ``max_k | |A_k B_k| - l_k |``,
    absolute and relative to ``l_k``: ``ends_a``, ``ends_b`` rows (3 coordinates) of arb
    balls or exact numbers, ``legs`` arb balls, one per row.  The six legs of an
    octahedron (:func:`leg_error_bounds`) or of a 6-6 platform (the JSON's bound for its
    printed joints, :func:`distkin.app.queries.octahedral.floats_segment_error`)."""
    import flint
    err = rel = 0.0
    for a, b, leg in zip(ends_a, ends_b, legs):
        d2 = sum((flint.arb(a[c]) - b[c]) ** 2 for c in range(3))
        e = abs(d2.sqrt() - leg)
        err = max(err, _float_up(e))
        rel = max(rel, _float_up(e / leg))
    return err, rel


def _float_up(ball) -> float:
    """The smallest float64 at or above every point of the arb ``ball`` (absolute):
    ``float()`` of its upper end rounds to nearest, which may be below it."""
    import math

    import flint
    up = flint.arb(ball.abs_upper())
    x = float(up)
    return x if flint.arb(x) >= up else math.nextafter(x, math.inf)
