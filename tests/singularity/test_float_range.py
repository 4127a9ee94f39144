"""The float64 range of the fast singularity tests (QA: defects 1-3, 7) and batches in the
precise tier (defect 4).

The Cayley-Menger conditions (Rojas, Borràs, Thomas, ICRA 2012, Sec. IV) are homogeneous
of degree 18 in the coordinates, det Jhat of degree 9, det J of degree 3: the fast tier
now scales the coordinates by a power of two.  At 1e-20 the fast conditions read an
exact-looking (0.0, 0.0); at 1e30 (nan, nan) with numpy RuntimeWarnings only; at 1e-30
the relative one raised a DegenerateGeometryError naming no tetrahedron.

References are independent of the fast tier: the certified tier (exact fmpq from the
float points' binary values), converted to Fractions.
"""

from __future__ import annotations

import warnings
from fractions import Fraction

import mpmath
import numpy as np
import pytest

from distkin.errors import InputError
from distkin.geometry.cm_float import FloatRangeWarning
from distkin.singularity import (certified_sign, cm_pure_condition, jacobian_det,
                                 octahedral_joints, signed_cm_condition, volume_factors)

P0 = np.random.default_rng(0).standard_normal((6, 3))
CONDITIONS = [signed_cm_condition, cm_pure_condition]


def _frac(q) -> Fraction:
    return Fraction(int(q.p), int(q.q))


def _exact(f, pts, **kw):
    return _frac(f(pts, method="certified", **kw))


@pytest.mark.parametrize("f", CONDITIONS)
@pytest.mark.parametrize("scale", [1e-17, 1e-15, 1e-10, 1.0, 1e10, 1e16])
def test_in_range_values_are_covered_by_their_estimate(f, scale):
    pts = P0 * scale
    with warnings.catch_warnings():
        warnings.simplefilter("error")               # no warning of any kind
        v, e = f(pts, with_error=True)
    exact = _exact(f, pts)
    assert exact != 0 and v != 0 and e > 0
    assert abs(Fraction(float(v)) - exact) <= Fraction(float(e))
    assert float(e) <= 1e-6 * abs(float(v))          # and it is useful, not huge


@pytest.mark.parametrize("f", CONDITIONS)
@pytest.mark.parametrize("scale", [1e-30, 1e-20, 1e30, 1e40])
def test_out_of_range_values_warn_and_never_claim_an_exact_zero(f, scale):
    pts = P0 * scale
    assert certified_sign(f(pts, method="certified")) == 1
    with pytest.warns(FloatRangeWarning) as rec:
        v, e = f(pts, with_error=True)
    exact = _exact(f, pts)
    value = mpmath.mpf(exact.numerator) / exact.denominator
    assert mpmath.nstr(value, 3) in rec[0].message.value.replace("e+", "e+") or \
        abs(mpmath.mpf(rec[0].message.value) / value - 1) < 1e-5
    assert not np.isnan(v) and not np.isnan(e)
    if scale < 1:
        assert v == 0.0 and e > 0                 # not an exact zero: an estimate > 0
        assert abs(exact) <= Fraction(float(e))
    else:
        assert v == np.inf and e == np.inf
    assert "below" in str(rec[0].message) if scale < 1 else "beyond" in str(rec[0].message)


@pytest.mark.parametrize("f", CONDITIONS)
@pytest.mark.parametrize("scale", [1e-30, 1e-20, 1e30, 1e100])
def test_relative_value_at_any_scale(f, scale):
    exact = _exact(f, P0 * scale, relative=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")               # no CancellationWarning, no overflow
        v, e = f(P0 * scale, relative=True, with_error=True)
    assert abs(Fraction(float(v)) - exact) <= Fraction(float(e))
    assert e < 1e-8


@pytest.mark.parametrize("f", CONDITIONS)
@pytest.mark.parametrize("scale", [1e-30, 1e30])
def test_precise_tier_at_extreme_scales(f, scale):
    pts = P0 * scale
    exact = _exact(f, pts)
    v, e = f(pts, method="precise", with_error=True)
    assert abs(Fraction(mpmath.nstr(v, 40)) - exact) <= Fraction(mpmath.nstr(2 * e, 5))
    assert e < 1e-20 * abs(v)


def test_batches_of_float_point_sets_scale_each_one():
    pts = np.stack([P0, P0 * 1e-30, P0 * 1e25])
    rel = signed_cm_condition(pts, relative=True)
    assert np.allclose(rel, float(_exact(signed_cm_condition, P0, relative=True)),
                       rtol=1e-12, atol=0)
    with pytest.warns(FloatRangeWarning, match=r"batch index \(1,\)"):
        v, e = signed_cm_condition(pts, with_error=True)
    assert v[0] == signed_cm_condition(P0) and e[1] > 0


@pytest.mark.parametrize("f", CONDITIONS)
@pytest.mark.parametrize("relative", [False, True])
def test_precise_and_certified_batches(f, relative):
    pts = np.stack([P0, 2 * P0[::-1]])
    v, e = f(pts, method="precise", relative=relative, with_error=True)
    assert v.shape == e.shape == (2,) and v.dtype == object
    c, r = f(pts, method="certified", relative=relative, with_error=True)
    assert c.shape == r.shape == (2,)
    for i in range(2):
        exact = _exact(f, pts[i], relative=relative)
        assert _frac(c[i]) == exact and r[i] == 0
        assert abs(Fraction(mpmath.nstr(v[i], 40)) - exact) <= Fraction(mpmath.nstr(2 * e[i], 5))
    assert np.array_equal(f(pts, method="precise", relative=relative), v)


def test_a_batched_degenerate_point_set_is_named_with_its_index():
    flat = P0.copy()
    flat[:, 2] = 0.0                                 # every tetrahedron flat
    from distkin.errors import DegenerateGeometryError
    with pytest.raises(DegenerateGeometryError, match=r"batch index \(1,\)"):
        cm_pure_condition(np.stack([P0, flat]), method="certified", relative=True)


@pytest.mark.parametrize("normalised", [False, True])
@pytest.mark.parametrize("scale", [1e-80, 1e-30, 1e30, 1e80])
def test_jacobian_det_at_extreme_scales(normalised, scale):
    b, p = octahedral_joints(P0 * scale)
    ref = jacobian_det(b, p, normalised=normalised, method="certified")
    ref = mpmath.mpf(_frac(ref).numerator) / _frac(ref).denominator if not normalised \
        else mpmath.mpf(ref.mid().str(30, radius=False))
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        v, e = jacobian_det(b, p, normalised=normalised, with_error=True)
    in_range = mpmath.mpf(2) ** -1022 < abs(ref) < mpmath.mpf(2) ** 1024
    if in_range:
        assert rec == []
        assert abs(mpmath.mpf(float(v)) - ref) <= e and e < 1e-9 * abs(v)
    else:
        assert [type(w.message) for w in rec] == [FloatRangeWarning]
        assert v in (0.0, np.inf) and e > 0
        assert abs(mpmath.mpf(rec[0].message.value) / ref - 1) < 1e-5
    if not normalised:
        return
    # dimensionless with a length scale: the value of the unit-scale points
    d = jacobian_det(b, p, normalised=normalised, length_scale=scale)
    assert d == pytest.approx(jacobian_det(*octahedral_joints(P0), normalised=normalised,
                                           length_scale=1.0), rel=1e-12)


def test_volume_factors_refuse_other_shapes():
    with pytest.raises(InputError, match=r"points: expected points P1..P6 of shape "
                                         r"\(\.\.\., 6, 3\), got \(4, 3\)"):
        volume_factors(P0[:4])
    a, b = volume_factors(P0)
    # det Jhat = -216 (a + b) (module docstring), exactly checked in the certified tier
    qa, qb = volume_factors(P0, method="certified")
    assert _frac(jacobian_det(*octahedral_joints(P0), normalised=False,
                              method="certified")) == -216 * (_frac(qa) + _frac(qb))
    assert a == pytest.approx(float(_frac(qa)), rel=1e-12)


def _near_singular_poses(n=200, seed=3):
    """Point sets at relative distances 1e-13..1e-5 from a root of det Jhat: P6 moved
    along a random direction to a sign change of det Jhat (bisection), then back off."""
    from near_singular import bisected_sign_change, moved
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        pts = rng.standard_normal((6, 3))
        d = rng.standard_normal(3)
        lo = bisected_sign_change(pts, d)
        if lo is None:
            continue
        for off in rng.choice([1e-13, 1e-11, 1e-9, 1e-7, 1e-5], size=4):
            out.append(moved(pts, d, lo + off * rng.choice([-1, 1])))
    return out[:n]


def test_jacobian_det_error_estimate_covers_the_exact_value_near_singularities():
    """QA 7: on near-singular poses the fast det J was off by more than 1e-6 relative
    with no accuracy statement; the estimate must cover the exact value (certified
    tier: fmpq for det Jhat, arb balls for det J) and flag the inaccurate ones."""
    bad = flagged = 0
    for pts in _near_singular_poses():
        b, p = octahedral_joints(pts)
        v, e = jacobian_det(b, p, normalised=False, with_error=True, warn=False)
        exact = _frac(jacobian_det(b, p, normalised=False, method="certified"))
        assert abs(Fraction(float(v)) - exact) <= Fraction(float(e))
        if abs(Fraction(float(v)) - exact) > Fraction(1, 10 ** 6) * abs(exact):
            bad += 1
        flagged += e > 1e-6 * abs(v)
        vn, en = jacobian_det(b, p, with_error=True, length_scale=2.0, warn=False)
        ball = jacobian_det(b, p, method="certified", length_scale=2.0)
        mid, rad = (mpmath.mpf(x.str(40, radius=False)) for x in (ball.mid(), ball.rad()))
        assert abs(mpmath.mpf(float(vn)) - mid) <= en + rad
    assert bad > 0                      # the poses do reach the inaccurate region
    assert flagged >= bad               # every inaccurate value says it may be
    # and at regular poses the estimate is small
    for pts in np.random.default_rng(5).standard_normal((20, 6, 3)):
        v, e = jacobian_det(*octahedral_joints(pts), with_error=True)
        assert e < 1e-8 * abs(v)


def test_jacobian_det_precise_error_estimate():
    b, p = octahedral_joints(_near_singular_poses(4)[0])
    with mpmath.workdps(15):           # the precise tier's own 30 digits, whatever mp.dps
        v, e = jacobian_det(b, p, normalised=False, method="precise", with_error=True)
    exact = _frac(jacobian_det(b, p, normalised=False, method="certified"))
    assert 0 < e < 1e-20
    assert abs(Fraction(mpmath.nstr(v, 45)) - exact) <= Fraction(mpmath.nstr(e, 10))
    assert jacobian_det(b, p, normalised=False, method="certified", with_error=True)[1] == 0
