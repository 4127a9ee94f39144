"""The fast trilateration's error estimate and warning (QA: on nearly collinear bases
it was off by 1e-4 .. 3.6e-2 of the problem's scale with no flag, and raised a false
InfeasibleError for configurations that exist).

Reference: the certified tier on the same float64 inputs (exact rational arithmetic of
their binary values; arb balls only for the final square root), i.e. the exact
trilateration of what the fast tier was given.  Claims checked on sampled bases:
every unwarned fast point is within TRILATERATION_RTOL of the length scale
Lambda = sqrt(|sa| + |sb| + |sc| + |v2|^2 + |v3|^2) of the certified one; every fast
point is within its own error estimate; a fast InfeasibleError only where the certified
tier proves h^2 < 0.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from flint import arb

from distkin.errors import ConditioningWarning, DegenerateGeometryError, InfeasibleError
from distkin.geometry import trilaterate, trilaterate_both, trilateration_parts
from distkin.geometry.trilateration import TRILATERATION_RTOL


def _scale(P, s):
    v2, v3 = P[1] - P[0], P[2] - P[0]
    return float(np.sqrt(np.abs(s).sum() + v2 @ v2 + v3 @ v3))


def _dist(fast, cert):
    """max |fast - cert| over the coordinates, the ball's radius added (an upper bound
    on the distance to the exact point)."""
    out = 0.0
    for f, c in zip(fast, cert):
        b = arb(c)
        out = max(out, float(abs(b - float(f)).upper()))
    return out


def _fast(P, s):
    """(parts, (p+, p-), warned) of the fast tier, or None on InfeasibleError."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            parts = trilateration_parts(P, s)
        except InfeasibleError:
            return None
    warned = [w for w in caught if issubclass(w.category, ConditioningWarning)]
    return parts, (parts.point(1), parts.point(-1)), bool(warned)


def _cases(n, seed):
    """Nearly collinear bases (sin of the angle at P_a from 1e-7 to 1e-2: below ~1e-7
    the fast tier refuses them as collinear), points off
    the plane, near it and in it (up to rounding), up to 100 base sizes away."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        a = rng.normal(size=3)
        u = rng.normal(size=3)
        u /= np.linalg.norm(u)
        w = rng.normal(size=3)
        w -= (w @ u) * u
        w /= np.linalg.norm(w)
        L = 10 ** rng.uniform(-1, 1)
        P = np.array([a, a + L * rng.uniform(0.5, 2) * u,
                      a + L * rng.uniform(-1, 2) * u + L * 10 ** rng.uniform(-6.5, -2) * w])
        X = a + rng.normal(size=3) * L * 10 ** rng.uniform(-1, 2)
        kind = rng.integers(3)
        if kind:                                   # near the plane, or in it
            nrm = np.cross(P[1] - a, P[2] - a)
            nrm /= np.linalg.norm(nrm)
            X = X - ((X - a) @ nrm) * nrm
            if kind == 1:
                X = X + nrm * L * 10 ** rng.uniform(-12, -3)
        s = ((P - X) ** 2).sum(1)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                trilateration_parts(P, s)
            except DegenerateGeometryError:        # refused as collinear: not sampled
                continue
            except InfeasibleError:
                pass
        yield P, s


def test_the_qa_case_warns_and_its_estimate_covers_the_error():
    P = np.array([[0, 0, 0], [1, 0, 0], [0.3, 1e-7, 0]])
    X = np.array([.2, .5, .7])
    s = ((P - X) ** 2).sum(1)
    with pytest.warns(ConditioningWarning, match="cannot vouch") as rec:
        got = trilaterate(P, s)
    assert len([w for w in rec if issubclass(w.category, ConditioningWarning)]) == 1
    ref = trilaterate(P, s, method="certified")
    err = _dist(got, ref)
    assert err > TRILATERATION_RTOL * _scale(P, s)         # it was right to warn
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert err <= float(trilateration_parts(P, s).error)


@pytest.mark.parametrize("seed", [0, 1])
def test_sampled_nearly_collinear_bases_against_the_certified_tier(seed):
    n_warned = n_quiet = n_clamped = 0
    for P, s in _cases(150, seed):
        try:
            cert = trilaterate_both(P, s, method="certified")
        except InfeasibleError:
            cert = None                            # h^2 < 0 exactly for these floats
        fast = _fast(P, s)
        if fast is None:                           # no false InfeasibleError
            assert cert is None, (P.tolist(), s.tolist())
            continue
        if cert is None:                           # clamped within the estimate
            n_clamped += 1
            continue
        parts, points, warned = fast
        lam = _scale(P, s)
        for f, c in zip(points, cert):
            err = _dist(f, c)
            assert err <= float(parts.error), (P.tolist(), s.tolist(), err, parts.error)
            if not warned:
                assert err <= TRILATERATION_RTOL * lam, (P.tolist(), s.tolist(), err)
        n_warned += warned
        n_quiet += not warned
    assert n_warned > 20 and n_quiet > 20          # both branches exercised


def test_batched_warns_once_and_matches_one_by_one():
    cases = list(_cases(60, 3))
    P = np.array([c[0] for c in cases])
    S = np.array([c[1] for c in cases])
    one = []
    for p, s in cases:
        f = _fast(p, s)
        one.append(None if f is None else f)
    keep = [i for i, f in enumerate(one) if f is not None]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        plus, minus = trilaterate_both(P[keep], S[keep])
        parts = trilateration_parts(P[keep], S[keep])
    cw = [w for w in caught if issubclass(w.category, ConditioningWarning)
          and "cannot vouch" in str(w.message)]
    assert len(cw) == 2                            # one per call
    # and at most one per call saying that a clamped configuration may not exist
    assert len(caught) - len(cw) <= 2
    assert all("may not exist" in str(w.message) for w in caught if w not in cw)
    flagged = [one[i][2] for i in keep]
    assert f"{sum(flagged)} of {len(keep)} flagged" in str(cw[0].message)
    for j, i in enumerate(keep):
        np.testing.assert_array_equal(plus[j], one[i][1][0])
        np.testing.assert_array_equal(minus[j], one[i][1][1])
        assert parts.error[j] == pytest.approx(float(one[i][0].error), rel=1e-12)


def test_well_conditioned_bases_do_not_warn():
    rng = np.random.default_rng(11)
    P = rng.normal(size=(500, 3, 3))
    X = rng.normal(size=(500, 3)) * 3
    S = ((P - X[:, None, :]) ** 2).sum(-1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = trilaterate(P, S)
    for i in range(0, 500, 50):                    # and they are right
        ref = trilaterate(P[i], S[i], method="certified")
        assert _dist(got[i], ref) <= 1e-12 * _scale(P[i], S[i])


def _precise_cases(n, seed):
    """Bases nearly collinear beyond float64's reach (sin from 1e-10.5 to 1e-4: the
    precise tier at 30 digits refuses below ~1e-11), points off and near the plane."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        a, u = rng.normal(size=3), rng.normal(size=3)
        u /= np.linalg.norm(u)
        w = rng.normal(size=3)
        w -= (w @ u) * u
        w /= np.linalg.norm(w)
        P = np.array([a, a + rng.uniform(0.5, 2) * u,
                      a + rng.uniform(-1, 2) * u + 10 ** rng.uniform(-10.5, -4) * w])
        X = a + rng.normal(size=3) * 10 ** rng.uniform(-1, 1)
        if rng.integers(2):
            nrm = np.cross(P[1] - a, P[2] - a)
            nrm /= np.linalg.norm(nrm)
            X = X - ((X - a) @ nrm) * nrm + nrm * 10 ** rng.uniform(-9, -3)
        yield P, ((P - X) ** 2).sum(1)


def test_precise_tier_warns_where_it_cannot_vouch():
    """The same estimate in mpmath (it lost up to ~20 of its 30 digits silently on such
    bases): unwarned answers within precise_rtol(30) of the scale of the certified
    point, every answer within its estimate, no false InfeasibleError."""
    import flint
    import mpmath

    from distkin.geometry.trilat_error import precise_rtol
    rtol = float(precise_rtol(30))
    n_warned = n_quiet = 0
    for P, s in _precise_cases(60, 5):
        old_prec, flint.ctx.prec = flint.ctx.prec, 256   # balls far below 1e-30
        try:
            cert = trilaterate_both(P, s, method="certified")
        except InfeasibleError:
            cert = None
        finally:
            flint.ctx.prec = old_prec
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                parts = trilateration_parts(P, s, method="precise")
            except InfeasibleError:
                assert cert is None
                continue
            with mpmath.workdps(30):
                points = (parts.point(1), parts.point(-1))
        if cert is None:
            continue
        warned = any(issubclass(w.category, ConditioningWarning) for w in caught)
        lam = _scale(P, s)
        for p, c in zip(points, cert):
            with flint.ctx.workprec(256):
                err = max(float(abs(arb(cc) - arb(mpmath.nstr(pp, 45))).upper())
                          for pp, cc in zip(p, c))
            assert err <= float(parts.error)
            if not warned:
                assert err <= rtol * lam
        n_warned += warned
        n_quiet += not warned
    assert n_warned > 5 and n_quiet > 5
