"""Trilateration round trips (hypothesis), tiers, and its failure modes.

Independent route: the point that generated the distances is known, so the answer is
compared with it; the certified tier is compared with exact rational geometry.
"""

import mpmath
import numpy as np
import pytest
from flint import fmpq
from hypothesis import given, settings
from hypothesis import strategies as st

from distkin.errors import DegenerateGeometryError, InfeasibleError, InputError, UncertifiedError
from distkin.geometry import squared_distances, trilaterate, trilaterate_both

EPS = np.finfo(float).eps


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), log_scale=st.floats(-6, 6))
def test_round_trip_scales(seed, log_scale):
    """Scales 1e-6..1e6: the generating point comes back to a relative error bounded by a
    conditioning factor (largest distance / height, and / triangle 'fatness')."""
    rng = np.random.default_rng(seed)
    scale = 10.0 ** log_scale
    A = rng.normal(size=(3, 3))
    n = np.cross(A[1] - A[0], A[2] - A[0])
    # keep the reference triangle non-degenerate and the point off its plane
    lengths = np.linalg.norm(A[[1, 2, 2]] - A[[0, 0, 1]], axis=1)
    fat = np.linalg.norm(n) / lengths.max() ** 2
    if fat < 1e-2:
        return
    p = rng.normal(size=3)
    h = abs((p - A[0]) @ n) / np.linalg.norm(n)
    size = max(np.abs(A).max(), np.abs(p).max(), lengths.max())
    if h < 1e-2 * size:
        return
    A, p = A * scale, p * scale
    s = ((A - p) ** 2).sum(axis=1)
    side = 1 if (p - A[0]) @ n >= 0 else -1
    got = trilaterate(A, s, side)
    rel = np.linalg.norm(got - p) / (scale * size)
    # bound: eps times a conditioning factor (size/h)^2 / fatness, generous constant
    bound = 1e3 * EPS * (size * scale / (h * scale)) ** 2 / fat
    assert rel <= bound, (rel, bound)
    assert rel < 1e-9


def test_round_trip_error_report():
    """Report the relative errors seen by the property test (and bound them)."""
    rng = np.random.default_rng(3)
    errs = []
    for scale in 10.0 ** np.arange(-6, 7):
        A = rng.normal(size=(200, 3, 3)) * scale
        p = rng.normal(size=(200, 3)) * scale
        s = ((A - p[:, None, :]) ** 2).sum(axis=2)
        n = np.cross(A[:, 1] - A[:, 0], A[:, 2] - A[:, 0])
        side = np.where(np.einsum("ij,ij->i", p - A[:, 0], n) >= 0, 1.0, -1.0)
        h = np.abs(np.einsum("ij,ij->i", p - A[:, 0], n)) / np.linalg.norm(n, axis=1)
        keep = h > 0.05 * scale
        got = trilaterate(A[keep], s[keep], side[keep])
        rel = np.linalg.norm(got - p[keep], axis=1) / scale
        errs.append((scale, np.median(rel), rel.max()))
    print("\nscale      median rel err   max rel err")
    for scale, med, mx in errs:
        print(f"{scale:8.0e}   {med:12.2e}   {mx:12.2e}")
    worst = max(e[2] for e in errs)
    assert worst < 1e-8
    # the errors are scale-invariant: the same inputs scaled by 2^k (exact in binary)
    # give the same points scaled by 2^k, bit for bit
    A = rng.normal(size=(200, 3, 3))
    p = rng.normal(size=(200, 3))
    s = ((A - p[:, None, :]) ** 2).sum(axis=2)
    n = np.cross(A[:, 1] - A[:, 0], A[:, 2] - A[:, 0])
    side = np.where(np.einsum("ij,ij->i", p - A[:, 0], n) >= 0, 1.0, -1.0)
    ref = trilaterate(A, s, side)
    for k in (-40, -7, 5, 40):
        f = 2.0 ** k
        assert np.array_equal(trilaterate(A * f, s * f * f, side) / f, ref), k


def test_mirror_pair_and_side_convention():
    P = np.array([[0, 0, 0], [2, 0, 0], [0, 3, 0]], float)
    up, down = trilaterate_both(P, [3, 3, 6])
    # analytic: (1, 1, 1) and its mirror (1, 1, -1); normal (2,0,0)x(0,3,0) = +z
    np.testing.assert_allclose(up, [1, 1, 1], atol=1e-14)
    np.testing.assert_allclose(down, [1, 1, -1], atol=1e-14)


def test_precise_tier_many_digits():
    with mpmath.workdps(60):
        P = [[0, 0, 0], [2, 0, 0], [0, 3, 0]]
        p = trilaterate(P, [2, 2, 7], 1, method="precise", dps=60)
        # analytic: (1, 1, 0)? No: s_a=2 -> x^2+y^2+z^2=2, (x-2)^2+..=2 -> x=1; y: 9-6y=5 -> y=2/3
        x, y = mpmath.mpf(1), mpmath.mpf(2) / 3
        z = mpmath.sqrt(2 - x**2 - y**2)
        assert abs(p[0] - x) < mpmath.mpf(10) ** -55
        assert abs(p[1] - y) < mpmath.mpf(10) ** -55
        assert abs(p[2] - z) < mpmath.mpf(10) ** -55


def test_certified_tier_encloses_exact_point():
    P = [[0, 0, 0], [2, 0, 0], [0, 3, 0]]
    p = trilaterate(P, [2, 2, 7], 1, method="certified")
    assert p[0].contains(fmpq(1)) and p[1].contains(fmpq(2, 3))
    # z^2 = 2 - 1 - 4/9 = 5/9 exactly
    assert (p[2] * p[2]).contains(fmpq(5, 9))
    assert float(p[2].rad()) < 1e-14


def test_certified_in_plane_is_exact_zero_height():
    p = trilaterate([[0, 0, 0], [2, 0, 0], [0, 2, 0]], [2, 2, 2], 1, method="certified")
    # analytic: (1, 1, 0), returned exactly
    assert [type(x).__name__ for x in p] == ["fmpq"] * 3
    assert p == [1, 1, 0]


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
def test_collinear_raises_degenerate(method):
    P = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]
    with pytest.raises(DegenerateGeometryError, match="collinear"):
        trilaterate(P, [1, 1, 1], method=method)


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
def test_coincident_raises_degenerate(method):
    P = [[0, 0, 0], [0, 0, 0], [1, 0, 0]]
    with pytest.raises(DegenerateGeometryError):
        trilaterate(P, [1, 1, 1], method=method)


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
def test_infeasible_reports_margin(method):
    # spheres of radius 1 about (0,0,0) and (5,0,0) never meet: h^2 < 0
    P = [[0, 0, 0], [5, 0, 0], [0, 5, 0]]
    with pytest.raises(InfeasibleError) as info:
        trilaterate(P, [1, 1, 1], method=method)
    assert info.value.margin < 0
    # analytic margin: x = (1 + 25 - 1)/10 = 5/2, y = 5/2; h^2 = 1 - 25/4 - 25/4 = -23/2
    assert info.value.margin == pytest.approx(-11.5, rel=1e-12)


def test_certified_undecidable_raises():
    from flint import arb
    P = [[0, 0, 0], [2, 0, 0], [0, 2, 0]]
    # h^2 is a ball around 0: cannot decide whether the point exists
    s = [arb(2) + arb(0, 1e-12), 2, 2]
    with pytest.raises(UncertifiedError):
        trilaterate(P, s, method="certified")


def test_bad_shapes_and_values():
    with pytest.raises(InputError, match="shape"):
        trilaterate(np.zeros((2, 3)), [1, 1, 1])
    with pytest.raises(InputError, match="finite"):
        trilaterate(np.eye(3), [1, np.nan, 1])
    with pytest.raises(InputError, match="side"):
        trilaterate(np.eye(3), [1, 1, 1], side=0)
    with pytest.raises(InputError, match="method"):
        trilaterate(np.eye(3), [1, 1, 1], method="exact")


def test_batched_matches_single():
    rng = np.random.default_rng(5)
    A = rng.normal(size=(20, 3, 3))
    p = rng.normal(size=(20, 3))
    s = squared_distances(np.concatenate([A, p[:, None]], axis=1))[:, 3, :3]
    both = trilaterate(A, s, 1)
    for i in range(20):
        np.testing.assert_allclose(both[i], trilaterate(A[i], s[i], 1), rtol=1e-14, atol=1e-14)


@pytest.mark.parametrize("scale", [1e-200, 1e-150, 1e-9, 1e120])
def test_certified_infeasible_gives_decimal_margin_at_every_scale(scale):
    """QA J 6: float(p) / float(q) of the exact h^2 overflowed (OverflowError) beyond
    1e308 digits' worth, and the message printed the whole fraction.  The margin now
    agrees with the precise tier's (an independent route, mpmath at 40 digits)."""
    pts = [[0, 0, 0], [scale, 0, 0], [0, scale, 0]]
    sq = [0.0, 4 * scale * scale, 4 * scale * scale]       # at P1, but 2 s from P2 and P3
    with pytest.raises(InfeasibleError) as cert:
        trilaterate(pts, sq, method="certified")
    with mpmath.workdps(40), pytest.raises(InfeasibleError) as prec:
        trilaterate(pts, sq, method="precise", dps=40)
    assert cert.value.field == "sq"
    assert "squared length units" in str(cert.value) and len(str(cert.value)) < 200
    assert cert.value.margin == pytest.approx(prec.value.margin, rel=1e-12)
    shown = str(cert.value).split("h^2 = ")[1].split(" ")[0]           # the decimal, any scale
    want = str(prec.value).split("h^2 = ")[1].split(" ")[0]
    assert mpmath.mpf(shown) < 0 and mpmath.almosteq(mpmath.mpf(shown), mpmath.mpf(want), 1e-6)
