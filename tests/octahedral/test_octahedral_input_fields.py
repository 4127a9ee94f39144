"""Input errors name the field and the value in every tier (QA: the certified tier named
``legs`` for an irrational base coordinate; ``"10**400"`` had no field in the exact
tiers; ``"1e-400"`` was "not positive"; batched fields had two forms; ``tol`` was
silently ignored by the fast tier).

References: which squared lengths are irrational is decided independently with sympy
from the coordinates (Rojas et al., ICRA 2012: eq. (3) has the squared sides and legs
as coefficients, so the certified tier needs them rational); the other messages are
compared across tiers (single fast, auto, precise, certified, batched)."""

import re
import warnings

import pytest
import sympy as sp

from distkin.errors import ConditioningWarning, InputError
from distkin.octahedral import forward_kinematics, forward_kinematics_batched

PLAT = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
GD_BASE = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
LEGS = ["19.8", 18, 18, 17, "14.9", "17.8"]
TIERS = ("fast", "auto", "precise", "certified")
SIDES = ((1, 2), (1, 3), (2, 3), (4, 5), (4, 6), (5, 6))


def _irrational_sides(base, plat):
    """The squared sides |PiPj|^2 that are irrational, by sympy, from the data."""
    pts = [[sp.sympify(v) for v in r] for r in list(base) + list(plat)]
    out = []
    for a, b in SIDES:
        d = sp.nsimplify(sp.expand(sum((x - y) ** 2 for x, y in zip(pts[a - 1], pts[b - 1]))))
        if not d.is_Rational:
            out.append(f"|P{a}P{b}|^2")
    return out


@pytest.mark.parametrize("base, plat, legs, culprits", [
    ([[0, 0, 0], [6, "pi*3", 0], [12, 0, 0]], PLAT, LEGS, {"base[1][1]": "pi*3"}),
    # P2 = (sqrt 37, sqrt 107): |P1P2|^2 = 144 is rational, |P2P3|^2 is not, by x only
    ([[0, 0, 0], ["sqrt(37)", "sqrt(107)", 0], [12, 0, 0]], PLAT, LEGS,
     {"base[1][0]": "sqrt(37)"}),
    (GD_BASE, [[0, 0, 0], [6, 0, 0], ["sqrt(2)", "sqrt(26)", 0]], LEGS,
     {"platform[2][0]": "sqrt(2)"}),
    (GD_BASE, PLAT, LEGS[:5] + ["17.8+sqrt(2)/1000"], {"legs[5]": "17.8+sqrt(2)/1000"}),
    # two culprits: the field is the first, the message names both
    ([["sqrt(2)", 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], PLAT,
     LEGS[:5] + ["17.8+sqrt(2)/1000"],
     {"base[0][0]": "sqrt(2)", "legs[5]": "17.8+sqrt(2)/1000"}),
])
def test_certified_names_the_irrational_inputs(base, plat, legs, culprits):
    with pytest.raises(InputError) as e:
        forward_kinematics(base, plat, legs, method="certified")
    err = e.value
    assert err.field == next(iter(culprits))
    for field, text in culprits.items():
        assert f"{field} = {text}" in err.message
    squares = _irrational_sides(base, plat)
    if any(f.startswith("legs") for f in culprits):
        squares.append("l6^2")
    got = re.search(r"got (\d+) irrational one\(s\), (.*), from", err.message)
    assert int(got.group(1)) == len(squares) and got.group(2) == ", ".join(squares)
    # auto falls back to the precise tier, which solves it
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConditioningWarning)
        res = forward_kinematics(base, plat, legs, method="auto")
    assert res.tier in ("fast", "precise")


@pytest.mark.parametrize("where", ["legs", "base", "platform"])
def test_beyond_float64_names_the_field_in_every_tier(where):
    base, plat, legs = [list(r) for r in GD_BASE], [list(r) for r in PLAT], list(LEGS)
    field = {"legs": "legs[0]", "base": "base[1][0]", "platform": "platform[2][0]"}[where]
    if where == "legs":
        legs[0] = "10**400"
    elif where == "base":
        base[1][0] = "10**400"
    else:
        plat[2][0] = "10**400"
    for m in TIERS:
        with pytest.raises(InputError, match="float64 range") as e:
            forward_kinematics(base, plat, legs, method=m)
        assert e.value.field == field and "'10**400'" in e.value.message, m


@pytest.mark.parametrize("value, kind", [("1e-400", "range"), ("10**-400", "range"),
                                         ("-1e-400", "positive"), ("0", "positive")])
def test_a_leg_below_float64_gets_one_message_in_every_tier(value, kind):
    legs = [value] + LEGS[1:]
    msgs = set()
    for m in TIERS:
        with pytest.raises(InputError) as e:
            forward_kinematics(GD_BASE, PLAT, legs, method=m)
        assert e.value.field == "legs[0]", m
        msgs.add(e.value.message)
    for m in ("fast", "auto"):
        with pytest.raises(InputError) as e:
            forward_kinematics_batched(GD_BASE, PLAT, [LEGS, legs], method=m)
        assert e.value.field == "legs[1][0]", m
        msgs.add(e.value.message)
    if kind == "range":
        assert len(msgs) == 1, msgs
        msg = msgs.pop()
        assert f"got {value}" in msg
        assert "2^-500" in msg and "rounds to 0" in msg and "expected a positive" not in msg
    else:           # (the float tiers print the float: 0.0 for "0")
        assert all(m.startswith("expected a positive leg length, got ") for m in msgs)


def test_tol_with_the_fast_tier_is_refused_as_dps_is():
    """``tol`` has no effect on the fast tier: refused there, single and batched, as
    ``dps`` is (QA T 9) and as the CLI refuses it; accepted by the tiers that use it."""
    for call in (lambda **kw: forward_kinematics(GD_BASE, PLAT, LEGS, **kw),
                 lambda **kw: forward_kinematics_batched(GD_BASE, PLAT, [LEGS], **kw)):
        for name, value in (("tol", 1e-3), ("dps", 30)):
            with pytest.raises(InputError, match="got method 'fast'") as e:
                call(method="fast", **{name: value})
            assert e.value.field == name
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConditioningWarning)
            call(method="auto", tol=1e-3)
    for m in ("precise", "certified"):
        assert len(forward_kinematics(GD_BASE, PLAT, LEGS, method=m, tol=1e-12)) == 12


@pytest.mark.parametrize("bad, kind", [(float("nan"), "finite"), (1e300, "range"),
                                       (-1.0, "positive"), ("1e-400", "range"),
                                       ("10**400", "float64")])
def test_batched_fields_name_problem_then_leg(bad, kind):
    """One form in every batched input check (QA: ``legs[1][0]`` for a NaN but
    ``legs[1] (legs[0] of problem 1)`` for an over-range length): problem, then leg,
    the index path of the value in the array as given; the single solve of the same
    problem names ``legs[0]`` (a second route)."""
    legs = [list(LEGS), [bad] + LEGS[1:]]
    with pytest.raises(InputError) as single:
        forward_kinematics(GD_BASE, PLAT, legs[1])
    assert single.value.field == "legs[0]"
    for m in ("fast", "auto"):
        with pytest.raises(InputError) as e:
            forward_kinematics_batched(GD_BASE, PLAT, legs, method=m)
        assert e.value.field == "legs[1][0]", (m, e.value)
        assert "of problem" not in e.value.message
    # a coordinate of a per-problem base: base[problem][point][coordinate]; of a shared
    # base: base[point][coordinate]
    if kind in ("range", "float64") and bad != "1e-400":
        bases = [[list(r) for r in GD_BASE] for _ in range(2)]
        bases[1][2][0] = bad
        with pytest.raises(InputError) as e:
            forward_kinematics_batched(bases, PLAT, [LEGS, LEGS])
        assert e.value.field == "base[1][2][0]"
        shared = [list(r) for r in GD_BASE]
        shared[2][0] = bad
        with pytest.raises(InputError) as e:
            forward_kinematics_batched(shared, PLAT, [LEGS, LEGS])
        assert e.value.field == "base[2][0]"
