r"""The precise tier of the octahedral forward kinematics (mpmath at ``dps`` digits).

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III.
The octic's coefficients are computed exactly when the squared lengths are rational
(then rounded once to ``dps + 20`` digits), otherwise in ``mpf`` through the same
integer-coefficient kernel.  ``mpmath.polyroots`` gives every complex root; the real
and nearly real ones are polished by Newton's method on eq. (3) at the working
precision, and the poses come from the trilateration sequence of Sec. III in ``mpf``.
Not certified: the root count rests on ``polyroots``' convergence and on a tolerance
(:math:`10^{8-dps}` relative) for calling a root real or a residual zero.  A root's
multiplicity is the size of its cluster of ``polyroots`` roots (those within
:math:`10^{1-\lfloor w/4 \rfloor}` relative, :math:`w = dps + 20`), for assembly and
spurious roots alike; a cluster is said in the notes, and warned about where it may
hide assembly modes.
"""

from __future__ import annotations

from fractions import Fraction

from ..errors import ConditioningWarning, DegenerateGeometryError, InfeasibleError
from ..errors import warn as _warn
from ..exact import float_mpf
from .assembly import assemble_exact
from .closure import OCTIC, octic_data, part_values
from .problem import LEG_PAIRS, Problem

__all__ = ["solve_precise", "check_precise_dps", "MIN_DPS"]

#: fewest digits of this tier: its residual test is 10^(8 - dps) relative, and roots
#: closer than about 10^(-(dps + 20)/4) relative merge (a four-fold cluster's radius)
MIN_DPS = 15


def check_precise_dps(dps) -> int:
    """``dps`` for this tier, or :class:`InputError` (an integer >= :data:`MIN_DPS`)."""
    from ..errors import InputError
    from ..exact import default_dps
    dps = default_dps(dps)
    if dps < MIN_DPS:
        raise InputError(f"expected dps >= {MIN_DPS} for the precise tier of the octahedral "
                         f"forward kinematics (its root residual test is 10^(8 - dps) "
                         f"relative: fewer digits than float64's would; use "
                         f"method='fast' for float64), got {dps}", field="dps")
    return dps


def _mpf(v):
    import mpmath
    if isinstance(v, Fraction):
        return mpmath.mpf(v.numerator) / v.denominator
    if isinstance(v, (int, float)):
        return mpmath.mpf(v)
    return mpmath.mpf(v.evalf(mpmath.mp.dps + 10))


def _factored(d, x):
    val, der = part_values(d, x)
    G = val["u"] * val["E2"] + val["v"] * val["E1"] + 2 * val["b1"] * val["b2"]
    dG = (der["u"] * val["E2"] + val["u"] * der["E2"] + der["v"] * val["E1"]
          + val["v"] * der["E1"] + 2 * (der["b1"] * val["b2"] + val["b1"] * der["b2"]))
    a, b, c, e = val["T1a"], val["T1b"], val["T2a"], val["T2b"]
    R = a * b * c * e
    dR = (der["T1a"] * b * c * e + a * der["T1b"] * c * e + a * b * der["T2a"] * e
          + a * b * c * der["T2b"])
    return G * G - 4 * R, 2 * G * dG - 4 * dR, G * G + 4 * abs(R), val


def solve_precise(problem: Problem, dps: int, tol=None):
    """Every assembly mode at ``dps`` decimal digits; see :func:`.forward.forward_kinematics`."""
    import mpmath
    dps = check_precise_dps(dps)
    from ..geometry.poses import frame_fit
    from .result import AssemblyResult, Pose, RootInfo, _SPURIOUS_NOTE, _empty_reason
    work = dps + 20
    with mpmath.workdps(work):
        exact = problem.rational
        if exact:
            import flint
            q = lambda v: flint.fmpq(v.numerator, v.denominator)  # noqa: E731
            dq = octic_data([q(v) for v in problem.sides2], [q(v) for v in problem.legs2],
                            "exact")
            dq = [flint.fmpq(v) for v in dq]
            d = [mpmath.mpf(int(v.p)) / int(v.q) for v in dq]
            octic = tuple(Fraction(int(v.p), int(v.q)) for v in dq[OCTIC])
        else:
            d = octic_data([_mpf(v) for v in problem.sides2], [_mpf(v) for v in problem.legs2],
                           "exact")
            octic = tuple(d[OCTIC])
        coef = d[OCTIC]
        if all(c == 0 for c in coef):
            raise DegenerateGeometryError("expected an octic that does not vanish identically, "
                                          "got the zero polynomial (degenerate geometry)",
                                          field="legs")
        sides = [_mpf(v) for v in problem.sides2]
        legs2 = [_mpf(v) for v in problem.legs2]
        c = sum(sides) / 6 + sum(legs2) / 6
        while coef and coef[0] == 0:
            coef = coef[1:]
        deg = len(coef) - 1
        scaled = [coef[k] * c ** (deg - k) for k in range(deg + 1)]
        big = max(abs(v) for v in scaled)
        scaled = [v / big for v in scaled]
        roots = _polyroots(scaled, work) if deg > 0 else []
        eps_rel = mpmath.mpf(10) ** (8 - dps) if tol is None else mpmath.mpf(tol)
        # roots closer than this (relative) are one cluster: above the radius of a
        # four-fold root's cluster at the working precision, 10^(-work/4)
        near_exp = work // 4 - 1
        near = mpmath.mpf(10) ** (-near_exp)
        cands = []
        for z in roots:
            z = z * c
            if abs(mpmath.im(z)) <= 0.05 * max(abs(z), c):
                a, b = mpmath.re(z), abs(mpmath.im(z))
                cands.extend([a] if b <= near * c else [a - b, a + b])
        found = []
        for x in cands:
            step = mpmath.mpf(0)
            for _ in range(200):
                H, dH, Hs, _ = _factored(d, x)
                if dH == 0:
                    break
                step = H / dH
                if abs(step) > c:
                    step = c * mpmath.sign(step)
                x = x - step
                if abs(step) <= mpmath.mpf(10) ** (-work + 2) * max(abs(x), c):
                    break
            H, dH, Hs, val = _factored(d, x)
            if abs(H) > eps_rel * Hs and not _backward_small(coef, x, eps_rel):
                # neither H = G^2 - 4 R1 R2 small against its two parts, nor the octic
                # small against its terms (a root where G and R1 R2 both vanish, e.g. at
                # a flat tetrahedron of the bananas, passes only the second)
                continue
            if any(abs(x - y) <= near * max(abs(x), c) for y, _ in found):
                continue
            found.append((x, abs(step)))
        found.sort(key=lambda t: t[0])
        # the roots of polyroots within `near` of each root found: its multiplicity as
        # this precision sees it (a root of multiplicity m comes out as a cluster of
        # radius ~10^(-work/m), well inside `near` for m <= 4)
        mult, spread = [], []
        for x, step in found:
            near_x = [abs(z * c - x) for z in roots if abs(z * c - x) <= near * max(abs(x), c)]
            mult.append(max(1, len(near_x)))
            # how far the root may be from x: the last Newton step, or for a cluster
            # (a multiple root, where Newton converges linearly) its radius
            spread.append(max([10 * step] + (near_x if len(near_x) > 1 else [])))
        # a simple real root changes the octic's sign around it; a root found where it
        # does not is a complex pair next to the axis, or an even multiple root, that
        # this precision cannot tell apart
        unsure = [float(x) for k, ((x, step), m) in enumerate(zip(found, mult))
                  if m == 1 and not _changes_sign(d, x, step, c, work, found, k)]
        base = [[_mpf(v) for v in r] for r in problem.base]
        plat = [[_mpf(v) for v in r] for r in problem.platform]
        legs = [_mpf(v) for v in problem.legs]
        infos, poses, merged, outside = [], [], [], []
        for (x, step), m, dx in zip(found, mult, spread):
            val, der = part_values(d, x)
            tets = [val[k] for k in ("T1a", "T1b", "T2a", "T2b")]
            # the signs below are read with the root's uncertainty dx (a flat face or
            # tetrahedron of the bananas puts u, v or a T at 0 at the root itself)
            utol = {k: eps_rel * c ** 4 + abs(der[k]) * dx for k in ("u", "v")}
            tiny = eps_rel * c ** 3 + max(abs(der[k]) for k in ("T1a", "T1b", "T2a", "T2b")) * dx
            # a spurious root keeps its cluster's multiplicity m and radius dx, as the
            # assembly roots do (it said 1 for a triple root outside the feasible
            # interval, where the certified tier proves 3, QA); the note below says so
            if val["u"] > utol["u"] or val["v"] > utol["v"]:
                infos.append(RootInfo(float(x), _estimate(x, dx if m > 1 else step), m,
                                      "spurious", "spurious: a shared face of the bananas "
                                      "has no real triangle (D(5,4,1) or D(3,5,1) > 0)", x))
                if m > 1:
                    outside.append((float(x), m))
                continue
            if min(tets) < -tiny:
                infos.append(RootInfo(float(x), _estimate(x, dx if m > 1 else step), m,
                                      "spurious", "spurious: a tetrahedron of the bananas "
                                      "has negative squared volume (complex assembly)", x))
                if m > 1:
                    outside.append((float(x), m))
                continue
            try:
                # the trilaterations' tolerance: at least the root's relative uncertainty
                dx_rel = dx / max(abs(x), c)
                sets = assemble_exact(base, x, sides, legs2, method="precise", dps=work,
                                      every=near * max(c, abs(legs2[4])) if m > 1 else None,
                                      tol=_trilateration_tol(dx_rel, work))
            except (InfeasibleError, DegenerateGeometryError) as exc:
                infos.append(RootInfo(float(x), _estimate(x, step), m, "rejected",
                                      f"rejected: trilateration failed ({exc.message})", x))
                if m > 1:               # a cluster may hide assembly modes
                    merged.append((float(x), m, 0))
                continue
            modes = len(sets) // 2
            infos.append(RootInfo(float(x), _estimate(x, step), m, "assembly",
                                  "assembly mode" if modes == 1 else
                                  f"{modes} assembly modes at this root", x))
            if modes < m:
                merged.append((float(x), m, modes))
            if m == 1:
                sets = [(side, pts, res) for side, (pts, res) in zip((1, -1), sets)]
            kept = []
            for side, pts, _ in sets:
                # a flat platform lies in the base plane: a mode is its own mirror image
                # (within the heights' uncertainty, the square root of the root's)
                if any(max(abs(a - b) for ra, rb in zip(pts, q) for a, b in zip(ra, rb))
                       <= (near + mpmath.sqrt(1000 * dx_rel)) * mpmath.sqrt(c) for q in kept):
                    continue
                kept.append(pts)
                R, t = frame_fit(plat, pts, "precise")  # congruent by construction
                err, rel = _leg_errors(base, pts, legs)
                poses.append(Pose(float(x), side, _f(R), _f(t), _f(pts),
                                  float(err), float(rel),
                                  {"s15": +x, "points": pts, "rotation": R, "translation": t}))
        reason = "" if poses else _empty_reason(infos)
        notes = (_SPURIOUS_NOTE,)
        if unsure:
            what = ", ".join(f"{x:.10g}" for x in unsure)
            notes += (f"no sign change of the octic around s15 = {what} at {dps} digits: "
                      "a complex pair next to the real axis, or a double root",)
            _warn(f"precise tier: the octic does not change sign around s15 = "
                  f"{what} at {dps} digits (a complex pair next to the real axis "
                  "or a double root); the count may be wrong (use more digits or "
                  "method='certified')", ConditioningWarning)
        if outside:         # said, not warned: a spurious cluster hides no assembly mode
            what = "; ".join(f"s15 = {x:.10g}: {m} roots within 1e-{near_exp} relative"
                             for x, m in outside)
            notes += (f"spurious roots merged at {dps} digits ({what}): the multiplicity "
                      f"is the cluster's size at this precision, not proved (roots closer "
                      f"than that are not told apart; method='certified' proves it); no "
                      f"assembly mode is lost, every root of a cluster is spurious",)
        if merged:
            what = "; ".join(f"s15 = {x:.10g}: {m} roots within 1e-{near_exp} relative, "
                             f"{k} assembly mode{'s' if k != 1 else ''} separated"
                             for x, m, k in merged)
            notes += (f"not separated at {dps} digits ({what}): modes may be missing",)
            _warn(f"precise tier: roots of the octic closer than 1e-{near_exp} "
                  f"relative were merged ({what}); the count may be wrong (use "
                  "more digits or method='certified')", ConditioningWarning)
        return AssemblyResult(tuple(poses), "precise", octic, exact, tuple(infos), False,
                              reason, f"mpmath at {dps} digits (working {work}); root "
                              "residual below " + (f"1e-{dps - 8}" if tol is None else
                                                   f"{float(tol):.1e} (tol)") + " relative",
                              notes)


def _trilateration_tol(rel, work):
    """The trilaterations' relative tolerance at a root known to ``rel`` relative: their
    default 10^(8 - work) (None), or 1000 rel when larger (a multiple root's cluster; a
    float, so only when float64 holds it)."""
    import mpmath
    t = float(1000 * rel)
    return t if t > 0 and t > mpmath.mpf(10) ** (8 - work) else None


def _backward_small(coef, x, eps_rel) -> bool:
    """Whether x is a root of the octic ``coef`` (highest degree first) to relative
    backward error ``eps_rel``: ``|P(x)| <= eps_rel * sum |a_k| |x|^k``, i.e. an exact
    root of a polynomial whose coefficients differ by at most ``eps_rel`` relative."""
    import mpmath
    return abs(mpmath.polyval(coef, x)) <= eps_rel * mpmath.polyval([abs(a) for a in coef],
                                                                    abs(x))


def _changes_sign(d, x, step, c, work, found, k) -> bool:
    """Whether H = G^2 - 4 R1 R2 has opposite signs at x -+ delta, delta ten times the
    last Newton step (at least 10^(5 - work) of the scale) and below half the gaps to
    the neighbouring roots ``found[k -+ 1]``."""
    import mpmath
    delta = max(10 * step, mpmath.mpf(10) ** (5 - work) * max(abs(x), c))
    for j in (k - 1, k + 1):
        if 0 <= j < len(found):
            delta = min(delta, abs(found[j][0] - x) / 2)
    lo, hi = _factored(d, x - delta)[0], _factored(d, x + delta)[0]
    return lo * hi < 0


def _polyroots(coeffs, work):
    import mpmath
    last = None
    for extra, steps in ((2 * work, 100), (6 * work, 400)):
        try:
            return mpmath.polyroots(coeffs, maxsteps=steps, extraprec=extra)
        except mpmath.libmp.libhyper.NoConvergence as exc:
            last = exc
    raise DegenerateGeometryError(f"mpmath.polyroots did not converge on the octic ({last}); "
                                  "try method='certified'", field="legs")


def _f(a):
    import numpy as np
    return np.array(a, dtype=float)


def _estimate(x, step) -> float:
    """:attr:`.result.RootInfo.radius` of a precise root ``x`` (mpf) given as a float:
    the last Newton step plus the root's rounding to float64 (an estimate, as the
    precise tiers of :mod:`distkin.mechanisms` give theirs)."""
    return float(step) + float_mpf(x)[1]


def _leg_errors(base, pts, legs):
    import mpmath
    P = {1: base[0], 2: base[1], 3: base[2], 4: pts[0], 5: pts[1], 6: pts[2]}
    err, rel = mpmath.mpf(0), mpmath.mpf(0)
    for k, (i, j) in enumerate(LEG_PAIRS):
        d = mpmath.sqrt(sum((P[i][a] - P[j][a]) ** 2 for a in range(3)))
        e = abs(d - legs[k])
        err, rel = max(err, e), max(rel, e / legs[k])
    return err, rel
