"""Interval enclosures of the RSS kernels (distkin.certify.intervals) against
independent routes: the sympy model at 50 digits, the float kernels sampled inside the
box, finite differences, and analytic functions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from flint import arb

from distkin.certify.intervals import FORMS, Affine, Grad, enclose_box, point_values
from distkin.exact_roots import working_precision
from distkin.mechanisms import preset


def _upper(x) -> float:
    return float(x.upper())


def _lower(x) -> float:
    return float(x.lower())


def test_arb_kernel_encloses_the_sympy_model_at_50_digits():
    """Point values of the arb flavour contain the symbolic model it is generated from
    (the exact model, symbolic.ModelExprs) evaluated at 50 digits (an independent
    evaluation)."""
    import sympy as sp
    from distkin.mechanisms.symbolic import POSE, model_expressions
    mech = preset("hexa")
    pose = np.array([0.0123, -0.0311, 0.2875, 0.07, -0.05, 0.11])
    _, jq, jx = point_values(mech.kernels("arb"), pose)
    me = model_expressions(mech, exact=True)
    M = me.get("jq_jx")
    subs = {s: sp.Float(float(v), 60) for s, v in zip(POSE, pose)}
    for i in (0, 3):                                  # two legs keep it quick
        for j in range(7):
            exact = sp.N(M[i, j].xreplace(subs), 50)
            with working_precision(200):              # a 1e-50 ball, not a 53-bit one
                ref = arb(str(exact))
            ball = jq[i] if j == 0 else jx[i][j - 1]
            assert ball.contains(ref), (i, j)
            assert float(ball.rad()) < 1e-12


@pytest.mark.parametrize("name", ["hexa", "octo"])
@pytest.mark.parametrize("form", FORMS)
def test_box_enclosures_contain_sampled_values(name, form):
    """Every float kernel value at a random pose of the box lies in the enclosure
    (J0 + Σ T_k ε_k ± e), for every form; reach margins likewise."""
    mech = preset(name)
    ks = mech.kernels("arb")
    c = np.array([0.02, -0.01, 0.31, 0.05, -0.03, 0.04])
    h = np.array([0.006, 0.005, 0.004, 0.01, 0.008, 0.012])
    enc = enclose_box(ks, c - h, c + h, form=form)
    assert enc.jq is not None, "the box is well inside the workspace"
    rng = np.random.default_rng(3)
    P = c + h * rng.uniform(-1, 1, (300, 6))
    P = np.vstack([P, c - h, c + h])
    Jq, Jx = mech.jq_jx(P)
    R = mech.reach_margin(P)
    slack = 1e-12
    for i in range(mech.L):
        assert _lower(enc.reach[i]) - slack <= R[:, i].min()
        assert R[:, i].max() <= _upper(enc.reach[i]) + slack
        assert _lower(enc.jq[i]) - slack <= Jq[:, i].min()
        assert Jq[:, i].max() <= _upper(enc.jq[i]) + slack
        for j in range(6):
            mid = float(enc.jx0[i][j].mid())
            bound = float(enc.jx0[i][j].rad()) + sum(_upper(abs(T[i][j])) for T in enc.jx_terms)
            if enc.jx_err is not None:
                bound += _upper(abs(enc.jx_err[i][j]))
            assert np.abs(Jx[:, i, j] - mid).max() <= bound + slack


def test_affine_and_centred_are_tighter_than_plain():
    """The point of the centred forms: on a 6-D box they enclose Jx more tightly than the
    natural interval extension (widths compared, summed over the matrix)."""
    mech = preset("octo")
    ks = mech.kernels("arb")
    c = np.array([0.0, 0.0, 0.3, 0.0, 0.0, 0.0])
    h = np.array([0.01] * 3 + [0.02] * 3)

    def width(form):
        e = enclose_box(ks, c - h, c + h, form=form)
        w = 0.0
        for i in range(mech.L):
            for j in range(6):
                w += float(e.jx0[i][j].rad()) + sum(_upper(abs(T[i][j])) for T in e.jx_terms)
                if e.jx_err is not None:
                    w += _upper(abs(e.jx_err[i][j]))
        return w
    plain, centred, affine = width("plain"), width("centred"), width("affine")
    assert affine < plain and centred < plain


def test_grad_matches_finite_differences():
    """Forward-mode derivative balls of the arb kernel at a point against central
    differences of the float kernel."""
    mech = preset("ergin")
    ks = mech.kernels("arb")
    p = np.array([0.01, 0.02, 0.29, 0.03, -0.02, 0.05])
    G = [Grad(arb(float(v)), tuple(arb(1) if i == k else arb(0) for i in range(6)))
         for k, v in enumerate(p)]
    out = ks.jq_jx(G)
    eps = 1e-6
    for k in range(6):
        dp = np.zeros(6)
        dp[k] = eps
        fd = (mech.jq_jx(p + dp)[1] - mech.jq_jx(p - dp)[1]) / (2 * eps)
        for i in range(mech.L):
            for j in range(6):
                g = out[i][j + 1]
                d = float(g.d[k].mid()) if isinstance(g, Grad) else 0.0
                assert abs(d - fd[i, j]) <= 1e-6 * (1 + abs(fd[i, j]))


def test_affine_form_analytic():
    """f(x) = x*x - 2x + sqrt(x + 3) + sin(x)/cos(x) on [0.5, 0.7]: the affine range
    contains the exact range (f is increasing there) and is tighter than the plain
    interval evaluation (which pays for the dependency of x*x - 2x)."""
    def f(x):
        return x * x - 2 * x + (x + 3).sqrt() + x.sin() / x.cos()

    def fx(x):
        return x * x - 2 * x + math.sqrt(x + 3) + math.tan(x)
    x = Affine(arb(0.6), (arb(0.1),), arb(0))
    r = f(x).range()
    assert _lower(r) <= fx(0.5) and fx(0.7) <= _upper(r)
    assert _upper(r) - _lower(r) < 1.5 * (fx(0.7) - fx(0.5))
    plain = f(arb(0.6, 0.1))
    assert _upper(r) - _lower(r) < _upper(plain) - _lower(plain)


def test_affine_reports_non_smooth_operations():
    """sqrt and abs of a range containing 0 leave no finite remainder (nothing is
    certified from such a form)."""
    x = Affine(arb(0.0), (arb(0.1),), arb(0))
    assert not abs(x).e.is_finite()
    assert not (x * x).sqrt().e.is_finite() or not (x * x).sqrt().range().is_finite()
    g = Grad(arb(0, 0.1), (arb(1),))
    assert not abs(g).d[0].is_finite()


def test_quadratic_model_coefficients_and_range():
    """Second-order Taylor models: the coefficients of x*y are exact (analytic), and the
    range of a smooth function of two variables contains dense samples."""
    from distkin.certify.taylor import pairs, variable
    x = variable(0.5, arb(0.1), 0, 2)               # x = 0.5 + 0.1 e0
    y = variable(0.2, arb(0.3), 1, 2)               # y = 0.2 + 0.3 e1
    p = x * y
    assert float(p.c.mid()) == pytest.approx(0.1)
    assert [float(a.mid()) for a in p.a] == pytest.approx([0.02, 0.15])
    q = dict(zip(pairs(2), (float(v.mid()) for v in p.q)))
    assert q == pytest.approx({(0, 0): 0.0, (0, 1): 0.03, (1, 1): 0.0})
    assert float(p.e.upper()) == 0.0

    def f(u, v):
        return u * v - u * u + (u + 2).sqrt() / (v + 3) + v.cos()
    r = f(x, y).range()
    e0, e1 = np.meshgrid(np.linspace(-1, 1, 41), np.linspace(-1, 1, 41))
    U, V = 0.5 + 0.1 * e0, 0.2 + 0.3 * e1
    F = U * V - U * U + np.sqrt(U + 2) / (V + 3) + np.cos(V)
    assert _lower(r) <= F.min() and F.max() <= _upper(r)
    assert _upper(r) - _lower(r) < 1.5 * (F.max() - F.min())
    plain = f(arb(0.5, 0.1), arb(0.2, 0.3))
    assert _upper(r) - _lower(r) < _upper(plain) - _lower(plain)


@pytest.mark.parametrize("lo, hi", [(0.0064, 0.035), (3.0, 5.0), (0.1, 0.9)])
def test_chebyshev_enclosures_hold_and_are_tight(lo, hi):
    """sqrt(x) and 1/x lie within α x + ζ ± δ on a dense grid, and δ is attained to 1 %
    (the min-max line touches the function three times)."""
    from distkin.certify.linearize import chebyshev_recip, chebyshev_sqrt
    ball = arb(lo).union(arb(hi))
    xs = np.linspace(lo, hi, 20001)
    for fn, ref in ((chebyshev_sqrt, np.sqrt), (chebyshev_recip, lambda t: 1 / t)):
        al, zeta, delta = fn(ball)
        err = np.abs(ref(xs) - (float(al.mid()) * xs + float(zeta.mid())))
        assert err.max() <= float(delta.upper()) * (1 + 1e-9) + 1e-15
        assert err.max() >= 0.99 * float(delta.mid())
    assert chebyshev_sqrt(arb(0, 1)) is None and chebyshev_recip(arb(0, 1)) is None


def test_certified_path_does_not_import_sympy():
    """The certificate runs on the committed arb kernels only (no symbolic work)."""
    import subprocess
    import sys
    code = ("import sys, numpy as np\n"
            "from distkin.mechanisms import preset\n"
            "from distkin.certify import certify_box\n"
            "m = preset('octo')\n"
            "v = certify_box(m, m.kernels('arb'), np.array([0, 0, 0.29, 0, 0, 0]),"
            " np.array([0.01, 0.01, 0.3, 0.01, 0.01, 0.01]))\n"
            "print(v.status, 'sympy' in sys.modules)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       check=True)
    assert r.stdout.split() == ["1", "False"]


def test_arb_flavour_of_emit_matches_sympy():
    """The arb printer (distkin.codegen.emit): a kernel with every construct it supports
    (rationals, exact doubles, integer and half powers, abs, sin, cos; numbers under
    sqrt and sin, big rationals) encloses sympy's 50-digit value; unsupported constructs
    are refused."""
    import sympy as sp
    from distkin.codegen.emit import Kernel, module_source
    x, y = sp.symbols("x y", real=True)
    expr = [sp.sqrt(sp.Abs(x - 3)) * sp.sin(y) + sp.Rational(1, 3) / x ** 2
            + sp.Float(0.1) * sp.cos(y) ** 3 - 1 / sp.sqrt(x + y ** 2) + (x * y) ** 5
            + sp.sqrt(2) * x + sp.sin(sp.Rational(1, 7)) * y
            + sp.Rational(10 ** 30 + 1, 3 * 10 ** 30) * y]
    src = module_source([Kernel("f_arb", (("p", (x, y)),), expr, flavour="arb")],
                        generator="test", doc="test", source_hash="0")
    # numbers are balls before a method call; big rationals come from exact integers
    assert "_A(2).sqrt()" in src and f"_A({10 ** 30 + 1})," in src
    ns: dict = {}
    exec(compile(src, "<arb kernel>", "exec"), ns)
    out = ns["f_arb"]([arb(1.25), arb(-0.5)])[0]
    ref = sp.N(expr[0].subs({x: sp.Rational(5, 4), y: sp.Rational(-1, 2)}), 50)
    with working_precision(200):                      # a 1e-50 ball, not a 53-bit one
        ref = arb(str(ref))
    assert out.contains(ref)
    assert float(out.rad()) < 1e-13
    with pytest.raises(ValueError, match="arb flavour"):
        module_source([Kernel("g", (("p", (x, y)),), [sp.exp(x)], flavour="arb")],
                      generator="test", doc="test", source_hash="0")


def test_committed_arb_modules_are_current():
    """``python -m distkin.codegen --check`` for the arb modules (regenerate, compare)."""
    import subprocess
    import sys
    from pathlib import Path
    from distkin.mechanisms.presets import PRESETS
    names = [f"rss_{n}_arb" for n in PRESETS]
    r = subprocess.run([sys.executable, "-m", "distkin.codegen", "--check", *names],
                       capture_output=True, text=True, timeout=600,
                       cwd=Path(__file__).resolve().parents[2])
    assert r.returncode == 0, r.stdout + r.stderr
    assert all(f"{n}: ok" in r.stdout for n in names)
