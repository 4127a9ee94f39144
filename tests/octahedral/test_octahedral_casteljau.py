"""The subdivision route of the fast tier's proof (:mod:`distkin.octahedral.casteljau`,
``descartes._vouch_split``; issue 17).

Independent references: exact rational arithmetic (``fractions.Fraction``) for the
de Casteljau splits and their bounds, and the Bernstein coefficients on the
sub-interval computed another way (from the power form, exactly); a polynomial with
known roots for the counts; the rebuild route (``descartes._vouch_bisect``) and the
certified tier for the verdicts on octahedra.
"""

from __future__ import annotations

from fractions import Fraction
from math import comb

import numpy as np
import pytest

from distkin.octahedral import casteljau as cj
from distkin.octahedral import descartes as dc
from distkin.octahedral.error_bounds import (ETA_FLOAT, U, error_cache, part_bounds_into,
                                             part_errors, part_errors_into)


def _split_exact(b, tau):
    """de Casteljau in rationals: (left, right) coefficients."""
    w = list(b)
    left, right = [w[0]], [None] * 9
    right[8] = w[8]
    for r in range(1, 9):
        w = [(1 - tau) * w[i] + tau * w[i + 1] for i in range(9 - r)]
        left.append(w[0])
        right[8 - r] = w[-1]
    return left, right


def _bernstein_on(poly, a, b):
    """Exact Bernstein coefficients (degree 8) on [a, b] of the polynomial with power
    coefficients ``poly`` (ascending, rationals): substitute x = a + (b - a) t, then
    b_i = sum_{j <= i} C(i, j) / C(8, j) h_j."""
    h = [Fraction(0)] * 9
    w = b - a
    for k, c in enumerate(poly):          # c (a + w t)^k
        for j in range(k + 1):
            h[j] += c * comb(k, j) * a ** (k - j) * w ** j
    return [sum(Fraction(comb(i, j), comb(8, j)) * h[j] for j in range(i + 1))
            for i in range(9)]


def _value(poly, x):
    return sum(c * x ** k for k, c in enumerate(poly))


@pytest.mark.parametrize("seed", range(6))
def test_split_encloses_the_exact_sub_interval_coefficients(seed):
    """Random octics (coefficients spanning 12 decades, signs mixed) on a random
    interval, Bernstein coefficients rounded to floats with bounds; a split at a random
    t: every float coefficient of both parts lies within its bound of the exact
    Bernstein coefficient on the exact sub-interval, computed from the power form
    (another route than de Casteljau's), and the last coefficient of the left part is
    the octic's value at the exact cut point; the cut point's float lies within its
    bound."""
    rng = np.random.default_rng(seed)
    poly = [Fraction(float(rng.normal() * 10.0 ** rng.integers(-6, 6))) for _ in range(9)]
    a, b = sorted(Fraction(float(v)) for v in rng.uniform(-3, 3, 2))
    exact = _bernstein_on(poly, a, b)
    P = np.array([float(v) for v in exact])
    EP = np.array([abs(float(Fraction(float(p)) - v)) * 2 + 1e-300 for p, v in zip(P, exact)])
    sigma, tau = cj.weights(float(rng.uniform(0.02, 0.98)))
    assert sigma + tau == 1.0 and 0 < tau < 1
    L, EL, R, ER, w, ew = (np.empty(9) for _ in range(6))
    cj.split(P, EP, sigma, tau, L, EL, R, ER, w, ew)
    cut = a + Fraction(tau) * (b - a)
    for got, bound, want in ((L, EL, _bernstein_on(poly, a, cut)),
                             (R, ER, _bernstein_on(poly, cut, b))):
        for i in range(9):
            assert abs(Fraction(float(got[i])) - want[i]) <= Fraction(float(bound[i])), i
    assert abs(Fraction(float(L[8])) - _value(poly, cut)) <= Fraction(float(EL[8]))
    assert L[8] == R[0] and EL[8] == ER[0]
    x, ex = cj.cut_point(float(a), 0.0, float(b), 0.0, sigma, tau)
    assert abs(Fraction(x) - cut) <= Fraction(ex)
    # the exact reference of the test itself: de Casteljau in rationals agrees
    le, ri = _split_exact(exact, Fraction(tau))
    assert le == _bernstein_on(poly, a, cut) and ri == _bernstein_on(poly, cut, b)


def test_unscale_and_weights():
    """Scaled -> unscaled coefficients within their bounds (exact division as the
    reference); weights sum to one exactly on both sides of 1/2."""
    rng = np.random.default_rng(3)
    Bs = rng.normal(size=9) * 1e3
    EBs = np.abs(Bs) * 4 * U
    P, EP = np.empty(9), np.empty(9)
    cj.unscale(Bs, EBs, P, EP)
    for i in range(9):
        want = Fraction(float(Bs[i])) / comb(8, i)
        assert abs(Fraction(float(P[i])) - want) + Fraction(float(EBs[i])) / comb(8, i) \
            <= Fraction(float(EP[i]))
    for t in (1e-9, 0.1, 0.3, 0.5, 0.7, 0.999999):
        s, tt = cj.weights(t)
        assert Fraction(s) + Fraction(tt) == 1 and abs(tt - t) <= 2 * U


def test_count_finds_the_real_roots_of_a_known_octic():
    """(x - 0.1)(x - 0.35)(x - 0.36)(x - 0.8)(x^2 - x + 0.2525)(x^2 + 1) on [0, 1]:
    four real roots in (0, 1) and a complex pair 0.5 +- 0.05i right above the interval
    (its sign changes must be split away).  The count is 4, and the four isolating
    pieces hold one root each, from left to right.  Also: no root for (x^2 - x + 0.2525) on
    [0, 1] alone (0 or undecided, never a wrong number)."""
    roots = [Fraction(1, 10), Fraction(35, 100), Fraction(36, 100), Fraction(8, 10)]
    poly = [Fraction(1)]
    for f in [[-r, 1] for r in roots] + [[Fraction(2525, 10000), -1, 1], [1, 0, 1]]:
        out = [Fraction(0)] * (len(poly) + len(f) - 1)
        for i, p in enumerate(poly):
            for j, q in enumerate(f):
                out[i + j] += p * q
        poly = out
    exact = _bernstein_on(poly, Fraction(0), Fraction(1))
    P = np.array([float(v) for v in exact])
    EP = np.array([abs(float(Fraction(float(p)) - v)) + 4 * U * abs(p) for p, v in zip(P, exact)])
    S, X = np.empty((cj.STACK, 18)), np.empty((cj.STACK, 4))
    work = [np.empty(9) for _ in range(4)]
    found = np.empty((8, 4))
    n, used = cj.count(P, EP, 0.0, 0.0, 1.0, 0.0, 64, S, X, *work, found)
    assert n == 4 and used > 0
    for (ia, iea, ib, ieb), r in zip(found[:4], roots):   # left to right, one root each
        assert sum(ia - iea < float(q) < ib + ieb for q in roots) == 1
        assert ia - iea < float(r) < ib + ieb
    pair = _bernstein_on([Fraction(2525, 10000), -1, 1] + [0] * 6, Fraction(0), Fraction(1))
    P2 = np.array([float(v) for v in pair])
    n2 = cj.count(P2, np.abs(P2) * 4 * U, 0.0, 0.0, 1.0, 0.0, 64, S, X, *work, found)[0]
    assert n2 in (0, -1)


def test_part_errors_into_reuses_its_factors_rightly():
    """The cached factors (one division per eta, not per problem) give the bounds of a
    fresh cache, eta by eta, also when eta changes between calls."""
    from distkin.octahedral.problem import float_problem
    from distkin.octahedral.reference import random_octahedron
    from distkin.octahedral.single import octic_array
    rng = np.random.default_rng(5)
    cache, out = error_cache(), np.empty(30)
    for k in range(20):
        _, _, _, s2, l2, _, _ = float_problem(*random_octahedron(rng)[:3])
        d = octic_array(s2[0], l2[0])
        eta = ETA_FLOAT if k % 3 else 1e-12
        part_errors_into(d, s2[0], l2[0], eta, out, cache)
        assert np.array_equal(out, part_errors(d, s2[0], l2[0], eta))


def _solved(n, seed, scale=1.0):
    """n random octahedra (lengths times ``scale``), the batched fast tier's raw answer
    on the normalised problems, and the normalising exponents k (lengths / 2^k)."""
    from distkin.octahedral.batched import solve_fast
    from distkin.octahedral.problem import float_problem
    from distkin.octahedral.reference import random_octahedron
    rng = np.random.default_rng(seed)
    probs = [random_octahedron(rng) for _ in range(n)]
    B, Q, L = (np.array([p[k] for p in probs]) * scale for k in range(3))
    B, Q, L, s2, l2, k, _ = float_problem(B, Q, L)
    return probs, s2, l2, k, solve_fast(B, Q, L, s2, l2)


def _routes(raw, s2, l2, i, tight, ws):
    """Verdicts and radii of both routes on problem i of a raw batched answer (the
    subdivision route's verdict -1 where the interval alone decides)."""
    n = int(np.sum(raw["status"][i] >= 0))
    x, codes = raw["roots"][i, :n], raw["status"][i, :n]
    e = np.empty(60)
    part_bounds_into(raw["data"][i], s2[i], l2[i], ETA_FLOAT, e, error_cache())
    r1, r2 = np.full(n, np.inf), np.full(n, np.inf)
    v, a, b, first, m = dc._interval(e, s2[i], l2[i], ETA_FLOAT, raw["lo"][i], raw["hi"][i],
                                     x, codes)
    if v >= 0:
        return -1, v, r1, r2
    args = (raw["data"][i], e, a, b, first, m, x, codes)
    v1 = dc._vouch_split(*args, r1, tight, ws)
    v2 = dc._vouch_bisect(*args, r2, tight, ws)
    return v1, v2, r1, r2


@pytest.mark.parametrize("scale", [1.0, 1e-3])
def test_split_route_agrees_with_the_rebuild_route(scale):
    """400 random octahedra (two scales), in the batched form (pieces) and the single
    form (tight radii): the subdivision route proves at least 95 % of them alone (it
    leaves the rest to the rebuild route, which gives the verdict); every problem it
    proves, the rebuild route proves too, with proved radii around the same roots."""
    _, s2, l2, _, raw = _solved(400, 17, scale)
    ws = dc._workspace()
    proved = 0
    for i in range(len(s2)):
        for tight in (False, True):
            v1, v2, r1, r2 = _routes(raw, s2, l2, i, tight, ws)
            assert v1 in (-1, 0) or v1 in dc.SPLIT_STEPS
            if v1 <= 0:
                proved += 1
                assert v2 == 0, (i, tight)
                assert np.array_equal(np.isfinite(r1), np.isfinite(r2))
    assert proved >= 0.95 * 2 * len(s2)


def test_split_route_answers_are_the_certified_ones():
    """60 random octahedra proved by the subdivision route alone: the number of poses
    is the certified tier's (FLINT's root isolation on the exact octic), and every
    assembly root lies within its proved radius of a certified assembly root, in the
    batched form (pieces) and the single form (tight radii)."""
    from distkin.octahedral import forward_kinematics
    probs, s2, l2, k, raw = _solved(60, 29)
    ws = dc._workspace()
    checked = 0
    for i, prob in enumerate(probs):
        b, p, legs = prob[:3]
        verdicts = [_routes(raw, s2, l2, i, tight, ws) for tight in (False, True)]
        if max(verdicts[0][0], verdicts[1][0]) > 0 or verdicts[0][1] != 0:
            continue
        cert = forward_kinematics(b, p, legs, method="certified", tol=1e-3)
        assert raw["count"][i] == len(cert), i
        exact = np.array([float(r.value) for r in cert.assembly_roots])
        n = len(verdicts[0][2])
        for j in np.flatnonzero(raw["status"][i, :n] == 0):
            x = np.ldexp(raw["roots"][i, j], 2 * k[i])
            for _, _, radii, _ in verdicts:
                assert np.min(np.abs(exact - x)) <= np.ldexp(radii[j], 2 * k[i]), (i, j)
        checked += 1
    assert checked >= 55


def test_recovery_solves_the_missed_pair_again():
    """Random octahedron 1678 of seed 17 (the benchmark's batch): the sign scan sees
    three of its four assembly roots (two within 3.4e-4 of each other and of a third, in
    one grid cell), the bare tier gives 6 poses and the proof refuses them.  The
    recovery (:func:`.batched.recover_flagged`) isolates the four roots with the proof's
    subdivision and the proof then vouches for them: 8 poses, the certified tier's, to
    1e-9 of the mechanism's size."""
    import warnings

    from distkin.octahedral import forward_kinematics, forward_kinematics_batched
    from distkin.octahedral.reference import random_octahedron
    rng = np.random.default_rng(17)
    probs = [random_octahedron(rng)[:3] for _ in range(1679)][1670:]
    B, Q, L = (np.array([p[k] for p in probs]) for k in range(3))
    bare = forward_kinematics_batched(B, Q, L, prove=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")              # nothing left unproved: no warning
        fast = forward_kinematics_batched(B, Q, L)
    assert list(fast.raw["recovered"]) == [8] and fast.trusted.all()
    cert = forward_kinematics(*probs[8], method="certified")
    assert bare.count[8] == 6 and fast.count[8] == len(cert) == 8
    size = np.abs(np.asarray(probs[8][2])).max()
    want = np.array([p.points for p in cert.poses])
    for got in fast.points[8, :8]:
        assert np.min(np.abs(want - got).max(axis=(1, 2))) <= 1e-9 * size
    assert np.array_equal(fast.count[:8], bare.count[:8])


def test_recovery_never_replaces_with_an_unproved_answer():
    """The 240 family problems of ``hard_families()`` (near-coplanar, near-line,
    clustered, three scales): every problem the recovery replaced is proved and has the
    truth's number of poses (the family's exact count); every other problem keeps the
    scan's answer, and a flagged one stays flagged.  (Today it replaces none of them:
    their refusals are flat tetrahedra (verdict 6, where the recovery is not tried) or
    clusters the float64 subdivision cannot split; the positive case is the test
    above.)"""
    import warnings

    from distkin.octahedral import forward_kinematics_batched
    from distkin.octahedral.hardset import hard_families
    fam = hard_families()
    B, Q, L = (np.array([getattr(c, k) for c in fam], dtype=float)
               for k in ("base", "platform", "legs"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fast = forward_kinematics_batched(B, Q, L)
    bare = forward_kinematics_batched(B, Q, L, prove=False)
    rec = fast.raw["recovered"]
    for i in rec:
        assert fast.trusted[i] and fast.count[i] == fam[i].poses, fam[i].name
    other = np.setdiff1d(np.arange(len(fam)), rec)
    assert np.array_equal(fast.count[other], bare.count[other])
    assert (fast.verdict[other][~fast.trusted[other]] != 0).all()
    assert (~fast.trusted).sum() >= 100


def test_single_solve_recovers_as_the_batched_tier_does():
    """The single solve's default call on random octahedron 1678 of seed 17 (the pair
    its sign scan misses): no warning, proved, the batched tier's 8 poses bit for bit;
    ``auto`` keeps it in the fast tier; the bare call (``warn=False``, no proof) still
    gives the scan's 6 poses."""
    import warnings

    from distkin.octahedral import forward_kinematics, forward_kinematics_batched
    from distkin.octahedral.reference import random_octahedron
    rng = np.random.default_rng(17)
    probs = [random_octahedron(rng)[:3] for _ in range(1679)]
    b, p, legs = (np.asarray(v, dtype=float) for v in probs[1678])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        one = forward_kinematics(b, p, legs)
    assert one.conditioning.trusted and len(one) == 8
    batch = forward_kinematics_batched(b[None], p[None], legs[None]).result(0)
    assert [q.s15 for q in one.poses] == [q.s15 for q in batch.poses]
    assert all(np.array_equal(q.points, r.points) for q, r in zip(one.poses, batch.poses))
    assert forward_kinematics(b, p, legs, method="auto").tier == "fast"
    assert len(forward_kinematics(b, p, legs, warn=False)) == 6
