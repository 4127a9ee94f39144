"""Bounds of the precision fields (QA G 3): ``dps`` had only a lower bound, so
``method = "precise", dps = 1000000`` ran without end.  It is now an integer 5..1233,
the decimal digits of 4096 bits, the bound of the certified tier's ``bits`` (53..4096)
and of an exact scene value; refused in one line naming the field and the range, before
any work, in scenes and in the Python API.

References: the digits of 2**4096 (Python's integers), and for the largest dps the
certified tier's arb balls on the same exact octic (FLINT), refined to 1e-300.
"""

from __future__ import annotations

import time

import mpmath
import pytest

from distkin.app.cli import main
from distkin.errors import InputError
from distkin.exact import MAX_BITS, MAX_DPS, default_dps
from distkin.octahedral import forward_kinematics
from distkin.octahedral.reference import GD_BASE, GD_LEGS, GD_PLATFORM, GD_ROOTS

OCTA = """
[mechanism]
kind = "octahedral"
base = [[0,0,0], [6,"sqrt(108)",0], [12,0,0]]
platform = [[0,0,0], [6,0,0], [3,"sqrt(27)",0]]

[[query]]
type = "forward_kinematics"
legs = ["19.8", "18", "18", "17", "14.9", "17.8"]
method = "{method}"
{extra}
"""


def _run(capsys, tmp_path, text, *args):
    f = tmp_path / "s.toml"
    f.write_text(text)
    code = main(["run", str(f), "--no-progress", *args])
    out, err = capsys.readouterr()
    return code, out, err


def test_max_dps_is_the_digits_of_4096_bits():
    # 2**4096 has 1234 decimal digits: 4096 bits carry 1233 whole decimal digits
    assert MAX_BITS == 4096 and MAX_DPS == len(str(2 ** 4096)) - 1 == 1233
    assert default_dps(None) == 30 and default_dps(5) == 5 and default_dps(1233) == 1233
    for bad in (4, 1234, 10 ** 6, True, 30.0, "30"):
        with pytest.raises(InputError) as exc:
            default_dps(bad)
        assert exc.value.field == "dps"
        assert exc.value.message == (f"expected dps as an integer 5..1233 (decimal digits, "
                                     f"at most 4096 bits), got {bad!r}")


@pytest.mark.parametrize("dps", [1234, 1000000])
def test_scene_dps_beyond_the_bound_is_refused_at_once(tmp_path, capsys, dps):
    t0 = time.perf_counter()
    code, out, err = _run(capsys, tmp_path, OCTA.format(method="precise", extra=f"dps = {dps}"))
    assert time.perf_counter() - t0 < 10                 # it used to run for hours
    assert code == 2 and out == ""
    assert err.strip() == (f"distkin: error: query[0].dps: expected dps as an integer "
                           f"5..1233 (decimal digits, at most 4096 bits), got {dps}")


def test_python_api_dps_beyond_the_bound_is_refused():
    """auto escalates to the precise tier only when the data cannot be made exact, so its
    dps was passed on unchecked; the IK tiers and trilateration share the bound."""
    from distkin.geometry import trilaterate
    from distkin.mechanisms import preset
    for method in ("precise", "auto"):
        with pytest.raises(InputError, match=r"5\.\.1233") as exc:
            forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method=method, dps=10 ** 6)
        assert exc.value.field == "dps"
    with pytest.raises(InputError, match=r"5\.\.1233"):
        trilaterate([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [1, 1, 1], method="precise",
                    dps=10 ** 6)
    m = preset("hunt")
    with pytest.raises(InputError, match=r"5\.\.1233"):
        m.inverse_kinematics(m.home, method="precise", dps=1234)


def test_largest_dps_runs_and_its_digits_are_right():
    """dps = 1233 is accepted (the solver works at dps + 20 digits internally) and the
    roots agree with the certified balls to far more than the default 30 digits."""
    res = forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="precise", dps=MAX_DPS)
    cert = forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="certified", tol=1e-300)
    assert len(res) == 12 and res.real_root_count == cert.real_root_count == 6
    assert [f"{float(r.value):.1f}" for r in res.roots] == list(GD_ROOTS)
    with mpmath.workdps(MAX_DPS + 20):
        for r, c in zip(res.roots, cert.roots):
            mid = mpmath.mpf(c.native.mid().str(700, radius=False))
            rad = mpmath.mpf(c.native.rad().str(5, radius=False))
            assert rad < mpmath.mpf(10) ** -600 * mid          # the reference is sharp
            assert abs(r.native - mid) <= rad + mpmath.mpf(10) ** -650 * mid


# ---- tol of the octahedral forward kinematics (QA G 6) ----------------------------------


@pytest.mark.parametrize("method, ok", [("fast", False), ("precise", True),
                                        ("certified", True), ("auto", True)])
def test_scene_tol_only_with_a_tier_that_reads_it(tmp_path, capsys, method, ok):
    """The fast tier has no tolerance to refine to: 'tol' was accepted and ignored; it is
    refused as dps is with a method that does not use it."""
    code, out, err = _run(capsys, tmp_path, OCTA.format(method=method, extra="tol = 1e-6"))
    if ok:
        assert code == 0, err
        return
    assert code == 2 and out == ""
    assert err.strip() == ("distkin: error: query[0].tol: expected 'tol' only with method "
                           "'precise', 'certified' or 'auto' (the tiers that refine to it), "
                           "got method 'fast'")


@pytest.mark.parametrize("tol, got", [("5", "5"), ("1", "1"), ("0", "0"),
                                     ("-1e-3", "-0.001")])
def test_scene_tol_is_a_relative_tolerance_below_one(tmp_path, capsys, tol, got):
    """tol = 5 (a radius of 500 % of the size) was accepted for certified and printed
    'point radii <= 5.0e+00 x size'."""
    code, out, err = _run(capsys, tmp_path, OCTA.format(method="certified", extra=f"tol = {tol}"))
    assert code == 2 and out == ""
    assert err.strip() == ("distkin: error: query[0].tol: expected tol as a relative "
                           f"tolerance, a number 0 < tol < 1, got {got}")


def test_precise_tol_below_its_digits_is_refused_not_an_empty_answer():
    """At 30 digits (working 50) a root residual of 1e-52 cannot be reached: every root
    was rejected and the answer was 'no assembly mode', silently.  Reference: the
    certified count (6 real roots) and the printed roots of Rojas et al., Sec. VI."""
    with pytest.raises(InputError) as exc:
        forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="precise", tol=1e-52)
    assert exc.value.field == "tol"
    assert exc.value.message == ("expected tol >= 1e-30 at 30 digits (the precise tier's "
                                 "dps), got 1e-52")
    assert exc.value.hint == "raise dps to at least 52 for it"
    # auto's precise fallback works at dps (default 50) digits: the same bound
    with pytest.raises(InputError, match="at 50 digits"):
        forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="auto", tol=1e-60)
    for method in ("certified", "precise", "auto"):
        with pytest.raises(InputError, match="0 < tol < 1"):
            forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method=method, tol=5)
    # with the digits to reach it, the same tolerance gives every mode
    cert = forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="certified")
    res = forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="precise", dps=52,
                             tol=1e-52)
    assert len(res) == 12 and res.real_root_count == cert.real_root_count == 6
    assert [f"{float(r.value):.1f}" for r in res.roots] == list(GD_ROOTS)
    assert "root residual below 1.0e-52 (tol) relative" in res.accuracy
    assert len(forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="auto", dps=60,
                                  tol=1e-60)) == 12
