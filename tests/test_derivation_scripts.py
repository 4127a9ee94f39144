"""The checks of ``derivations/*.py`` check (QA U): each one fails on a wrong intermediate.

The old scripts printed "ok" after checks that could not fail: eq. (3) "built with
radicals" passed for any expression with a power, the coefficient of s26 was compared
with itself, F = -u v G was printed unchecked, ``--full`` asserted nothing, and any
argument was accepted.  Here each step is fed a wrong intermediate and must exit with
"CHECK FAILED"; the references are independent routes (the bordered Cayley-Menger
determinant of the paper's definition, Heron's formula, the printed eq. (10) of Rojas et
al., the generated kernel) inside the scripts.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

sp = pytest.importorskip("sympy")

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = ("octahedral_octic", "delta_transform", "rss_model")


def _load(name):
    spec = importlib.util.spec_from_file_location(f"_derivation_{name}",
                                                  ROOT / "derivations" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def octic():
    return _load("octahedral_octic")


def _fails(fn, *args, match, **kw):
    with pytest.raises(SystemExit) as exc:
        fn(*args, **kw)
    assert str(exc.value).startswith("CHECK FAILED") and match in str(exc.value), exc.value


def test_step1_compares_the_coefficient_with_the_face_determinant(octic, capsys):
    """A banana whose s26 coefficient is 2 D(face) (pentad halved, so linearity, the
    Jacobi identity and the branch symmetry all still hold) is refused: the coefficient
    is compared with the bordered determinant D(5,4,1) built from the definition."""
    octic.step_bananas()
    assert "ok: c1 = D(5,4,1)" in capsys.readouterr().out

    def doubled(k):
        b = octic.banana(k)
        c = 2 * b.coefficient
        return dataclasses.replace(b, coefficient=c, pentad=b.pentad / 2,
                                   bideterminant=sp.expand(c * octic.S[(2, 6)] + b.constant))
    _fails(octic.step_bananas, doubled, match="c1 = D(5,4,1)")


def test_step2_checks_f_equals_minus_uvg_on_the_parts(octic):
    p = octic.octic_parts()
    octic.step_closure(p)
    wrong = dataclasses.replace(p, E1=p.E1 + octic.S[(1, 2)])
    _fails(octic.step_closure, wrong, match="F + u v G = 0 on the parts")


def test_eq3_is_compared_with_the_printed_eq10(octic):
    """Rojas et al. eq. (10): the tester's vacuous x**2 and an eq. (3) with u and v
    exchanged in its radical terms are both refused; the real one passes."""
    octic.check_eq3_against_eq10()
    _fails(octic.check_eq3_against_eq10, lambda *a, **k: octic.X ** 2,
           match="one square root")

    def swapped(signs, values=None, *, cleared=False):
        p = octic.octic_parts(values)
        return (p.u * p.b2 - p.v * p.b1 + p.u * sp.sqrt(p.R1) - p.v * sp.sqrt(p.R2))
    _fails(octic.check_eq3_against_eq10, swapped, match="radical terms are eq. (10)")


def test_step9_compares_the_full_octic_with_the_kernel(octic):
    """``--full``'s check, fed the octic in the legs (sides of the example fixed; the
    same numbers at the example's legs, seconds instead of a minute) passes; one wrong
    coefficient fails against the generated kernel."""
    values = {**octic.GD_SIDES, **octic.GD_LEGS2}
    coeffs = [sp.Rational(c) for c in octic.octic_polynomial(values).all_coeffs()]
    legs = octic.octic_in_legs(octic.GD_SIDES)
    octic.step_full(coeffs, full_octic=legs)
    bad = list(legs)
    bad[3] = bad[3] + octic.S[(1, 4)]
    _fails(octic.step_full, coeffs, full_octic=bad, match="generated kernel")


@pytest.mark.parametrize("name", SCRIPTS)
def test_help_prints_the_paper_and_runs_nothing(name, capsys):
    mod = _load(name)
    with pytest.raises(SystemExit) as exc:
        mod.main(["--help"])
    out = capsys.readouterr().out
    assert exc.value.code == 0 and out.startswith("usage:")
    assert ("Rojas" if name != "rss_model" else "Kühne") in out
    assert "ok:" not in out and "all checks passed" not in out


@pytest.mark.parametrize("name", SCRIPTS)
def test_unknown_option_exits_2_with_usage(name):
    """``octahedral_octic.py --fulll`` ran the default checks and said "all checks
    passed" (exit 0) without step 9."""
    r = subprocess.run([sys.executable, str(ROOT / "derivations" / f"{name}.py"), "--fulll"],
                       capture_output=True, text=True, timeout=600,
                       env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert r.returncode == 2, r.stdout[-2000:] + r.stderr[-2000:]
    assert r.stderr.startswith("usage:") and "unrecognized arguments: --fulll" in r.stderr
    assert r.stdout == ""


@pytest.mark.slow
def test_full_run_passes_and_checks_step9():
    """About a minute: ``--full`` expands F + u v G and the octic and compares them."""
    r = subprocess.run([sys.executable, str(ROOT / "derivations" / "octahedral_octic.py"),
                        "--full"], capture_output=True, text=True, timeout=900,
                       env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    step9 = r.stdout.split("== 9.")[1]
    assert step9.count("ok:") == 4 and "all checks passed" in step9


def test_rss_step6_refuses_a_range_margin_of_the_other_branch(capsys):
    """Item 6 compares the exact ``ranges`` kernel with rho^2 (cos(q - m) - cos w) at the
    leg's own IK angle (atan2, 60 digits): a margin written with the other branch's
    cos q and sin q (sigma flipped) is refused."""
    rss = _load("rss_model")
    rss.check_range_margin()                     # the model's own kernel passes

    def flipped(leg):
        A, Bz, C, s = leg["A"], leg["Bz"], leg["C"], -leg["branch"]
        h = sp.sqrt(sp.Abs(A ** 2 + Bz ** 2 - C ** 2))
        lo, hi = (sp.Rational(v) for v in leg["range"])
        m, w = (lo + hi) / 2, (hi - lo) / 2
        return ((A * C + s * Bz * h) * sp.cos(m) + (Bz * C - s * A * h) * sp.sin(m)
                - (A ** 2 + Bz ** 2) * sp.cos(w))
    _fails(rss.check_range_margin, flipped, match="(c) the exact ranges kernel")
