"""The binary64 Taylor models (distkin.certify.fptaylor) and the batched ``quadratic64``
route (distkin.certify.batch), against independent references: exact rational
arithmetic, mpmath at 50 digits, arb point evaluations of the generated kernels, the
arb ``quadratic`` route on the same boxes, and sampled poses inside certified boxes."""

import math
from fractions import Fraction

import mpmath
import numpy as np
import pytest

from distkin.certify.batch import branch_and_prune_batched, certify_batch
from distkin.certify.boxes import REGULAR, SINGULAR, UNDECIDED, UNREACHABLE, certify_box
from distkin.certify.fptaylor import Quadratics, sum_up
from distkin.certify.intervals import point_values
from distkin.mechanisms import preset


def _random_models(rng, B, n, scale=1.0, centre=0.0):
    a = rng.normal(size=(B, n)) * scale * 0.1
    q = rng.normal(size=(B, n, n)) * scale * 0.01
    q = 0.5 * (q + np.transpose(q, (0, 2, 1)))
    return Quadratics(centre + rng.normal(size=B) * scale, a, q,
                      np.abs(rng.normal(size=B)) * 1e-9)


def _value(m, b, eps, delta):
    """The exact value (Fraction) of model ``m`` of box ``b`` at ``eps`` with remainder
    ``delta * e``."""
    n = len(eps)
    v = Fraction(m.c[b])
    for k in range(n):
        v += Fraction(m.a[b, k]) * eps[k]
        for l in range(n):
            v += Fraction(m.q[b, k, l]) * eps[k] * eps[l]
    return v + delta * Fraction(m.e[b])


def _inside(m, b, eps, exact):
    """|exact - m(eps)| <= e_m (exact rationals)."""
    return abs(exact - _value(m, b, eps, 0)) <= Fraction(m.e[b])


def test_sum_up_bounds_the_exact_sum():
    rng = np.random.default_rng(0)
    x = np.abs(rng.normal(size=(50, 37))) * 10.0 ** rng.integers(-300, 300, size=(50, 37))
    s = sum_up(x, 1)
    for i in range(50):
        assert sum(Fraction(v) for v in x[i]) <= Fraction(s[i])


def test_sums_and_products_contain_the_exact_values():
    """x + y, x * y, 3.1 x, x / 7 and x * x at random ε and δ, in exact rationals."""
    rng = np.random.default_rng(1)
    B, n = 6, 3
    x = _random_models(rng, B, n)
    y = _random_models(rng, B, n, scale=3.0)
    ops = {"add": (x + y, lambda u, v: u + v), "mul": (x * y, lambda u, v: u * v),
           "scale": (x * 3.1, lambda u, v: u * Fraction(3.1)),
           "div": (x / 7.0, lambda u, v: u / 7), "square": (x * x, lambda u, v: u * u),
           "sub": (1.5 - y, lambda u, v: Fraction(1.5) - v)}
    for _ in range(4):
        eps = [Fraction(float(t)) for t in rng.uniform(-1, 1, n)]
        dx, dy = (Fraction(float(t)) for t in rng.choice([-1.0, 1.0], 2))
        for b in range(B):
            u, v = _value(x, b, eps, dx), _value(y, b, eps, dy)
            for name, (z, f) in ops.items():
                assert _inside(z, b, eps, f(u, v)), name


@pytest.mark.parametrize("name", ["sqrt", "recip", "sin", "cos"])
def test_functions_contain_the_values_at_50_digits(name):
    rng = np.random.default_rng(2)
    B, n = 5, 2
    x = _random_models(rng, B, n, scale=0.3, centre=2.0 if name in ("sqrt", "recip") else 0.0)
    z = {"sqrt": lambda m: m.sqrt(), "recip": lambda m: 1.0 / m,
         "sin": lambda m: m.sin(), "cos": lambda m: m.cos()}[name](x)
    f = {"sqrt": mpmath.sqrt, "recip": lambda t: 1 / t, "sin": mpmath.sin,
         "cos": mpmath.cos}[name]
    assert np.all(np.isfinite(z.e))
    with mpmath.workdps(50):
        for _ in range(4):
            eps = [Fraction(float(t)) for t in rng.uniform(-1, 1, n)]
            for b in range(B):
                u = _value(x, b, eps, Fraction(float(rng.choice([-1.0, 1.0]))))
                fu = f(mpmath.mpf(u.numerator) / u.denominator)
                zv = _value(z, b, eps, 0)
                err = abs(fu - mpmath.mpf(zv.numerator) / zv.denominator)
                assert err <= mpmath.mpf(z.e[b]), name


def test_not_smooth_or_huge_models_certify_nothing():
    B, n = 2, 1
    x = Quadratics(np.array([0.0, 1e-3]), np.array([[1.0], [1.0]]), np.zeros((B, n, n)),
                   np.zeros(B))
    for z in (x.sqrt(), 1.0 / x, abs(x)):
        assert not np.any(np.isfinite(z.e))
    big = Quadratics(np.array([1e300]), np.array([[1e300]]), np.zeros((1, 1, 1)), np.zeros(1))
    with np.errstate(all="ignore"):
        assert not np.isfinite((big * big * big).e[0])


def _boxes(mech, B, rng, rot):
    c = np.column_stack([rng.uniform(-0.07, 0.07, (B, 3)) + [0, 0, mech.z0],
                         rng.uniform(-rot, rot, (B, 3))])
    h = np.array([0.01] * 3 + [math.radians(2.5)] * 3) * rng.uniform(0.5, 2.5, (B, 1))
    return c - h, c + h


def test_kernel_models_contain_arb_point_values():
    """The reach margins and Jx entries over a box contain the arb point values of the
    generated kernel at poses sampled in the box."""
    from distkin.certify.batch import _inputs, _stack
    mech = preset("octo")
    ks = mech.kernels("arb")
    rng = np.random.default_rng(3)
    lo, hi = _boxes(mech, 4, rng, math.radians(20))
    _, X = _inputs(lo, hi, tuple(range(6)))
    rc, ra, rq, re = _stack(ks.reach(X), X[0])
    reach = Quadratics(rc.reshape(-1), ra.reshape(-1, 6), rq.reshape(-1, 6, 6), re.reshape(-1))
    rlo, rhi = (b.reshape(4, -1) for b in reach.bounds())
    rows = ks.jq_jx(X)
    jx = Quadratics(*(np.stack([getattr(g, f) for row in rows for g in row[1:]], axis=1)
                      .reshape((-1,) + getattr(rows[0][1], f).shape[1:])
                      for f in ("c", "a", "q", "e")))
    jlo, jhi = (b.reshape(4, -1) for b in jx.bounds())
    for b in range(4):
        for t in rng.uniform(0, 1, (5, 6)):
            p = lo[b] + t * (hi[b] - lo[b])
            r, _, j = point_values(ks, p)
            assert all(rlo[b, i] <= float(v.mid()) <= rhi[b, i] for i, v in enumerate(r))
            flat = [float(v.mid()) for row in j for v in row]
            assert all(jlo[b, i] <= v <= jhi[b, i] for i, v in enumerate(flat))


def test_a_box_wider_than_its_varying_coordinates_is_refused():
    mech = preset("octo")
    lo = np.array([[0.0, 0.0, 0.3, 0.0, 0.0, 0.0]])
    hi = np.array([[0.01, 0.01, 0.31, 0.01, 0.0, 0.0]])
    with pytest.raises(ValueError, match="zero width outside"):
        certify_batch(mech, mech.kernels("arb"), lo, hi, (0, 1, 2))


def test_verdicts_agree_with_the_arb_route():
    """Same boxes, both routes: no contradiction, contraction bounds within 5 % where
    both certify, and both σ bounds below the float σmin(Jx) at the box's corners and
    midpoint (the bounds themselves differ with the Perron vector of each route)."""
    mech = preset("octo")
    ks = mech.kernels("arb")
    rng = np.random.default_rng(4)
    lo, hi = _boxes(mech, 24, rng, math.radians(30))
    r = certify_batch(mech, ks, lo, hi, tuple(range(6)))
    both = 0
    for i in range(24):
        v = certify_box(mech, ks, lo[i], hi[i], form="quadratic")
        s64 = int(r["status"][i])
        assert {v.status, s64} <= {UNDECIDED, REGULAR} or v.status == s64
        if v.status == s64 == REGULAR:
            both += 1
            assert r["contraction"][i] == pytest.approx(v.contraction, rel=0.05)
            P = np.vstack([lo[i] + np.array([(j >> k) & 1 for k in range(6)])
                           * (hi[i] - lo[i]) for j in range(64)] + [0.5 * (lo[i] + hi[i])])
            smin = np.linalg.svd(mech.jq_jx(P)[1], compute_uv=False)[:, -1].min()
            assert 0 < r["sigma"][i] <= smin and 0 < v.sigma_lower <= smin
    assert both >= 8


@pytest.mark.parametrize("name,rot", [("octo", 30.0), ("hexa", 20.0)])
def test_sampled_poses_in_regular_boxes(name, rot):
    """Branch-and-prune over a 6-D corner; at poses sampled in every regular box the
    float σmin(Jx) is at least the certified bound and (L = 6) det Jx has the certified
    sign."""
    mech = preset(name)
    a = math.radians(rot)
    lo = np.array([0.0375, 0.0375, mech.z0 + 0.0375, a / 2, a / 2, a / 2])
    hi = np.array([0.075, 0.075, mech.z0 + 0.075, a, a, a])
    r = branch_and_prune_batched(mech, lo, hi, [0.15 / 8] * 3 + [a / 4] * 3)
    reg = np.flatnonzero(r["status"] == REGULAR)
    assert len(reg) > 0
    rng = np.random.default_rng(5)
    for b in reg:
        P = r["lo"][b] + rng.uniform(0, 1, (6, 6)) * (r["hi"][b] - r["lo"][b])
        _, Jx = mech.jq_jx(P)
        s = np.linalg.svd(Jx, compute_uv=False)[:, -1]
        assert np.all(s >= r["sigma_lower"][b] * (1 - 1e-9))
        if mech.L == 6:
            assert np.all(np.sign(np.linalg.det(Jx)) == r["det_sign"][b])


def test_singular_boxes_of_the_radial_hexa():
    """The HEXA under the radial reading has singular regions at zero rotation
    (BENCHMARKS.md): the binary64 route certifies singular boxes there, each with a
    sign change of det Jx at its corners, and no regular box holds a sampled pose of
    the opposite sign."""
    mech = preset("hexa", layout="radial")
    lo = np.array([-0.075, -0.075, mech.z0 - 0.075, 0, 0, 0])
    hi = np.array([0.075, 0.075, mech.z0 + 0.075, 0, 0, 0])
    r = branch_and_prune_batched(mech, lo, hi, [0.15 / 8] * 3 + [1] * 3)
    st = r["status"]
    assert np.any(st == SINGULAR) and np.any(st == REGULAR)
    assert not np.any(st == UNREACHABLE)
    rng = np.random.default_rng(6)
    for b in np.flatnonzero(st == REGULAR)[:40]:
        P = r["lo"][b] + rng.uniform(0, 1, (4, 6)) * (r["hi"][b] - r["lo"][b])
        assert np.all(np.sign(np.linalg.det(mech.jq_jx(P)[1])) == r["det_sign"][b])
