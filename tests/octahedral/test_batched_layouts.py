"""Batched solves whatever the layout of their inputs (QA: a batch with one thin triangle
and inputs that need rounding crashed with a numba TypingError in ``eta_rounded``).

The matrix: base and platform shared (3, 3) or per problem (N, 3, 3), a thin triangle in
the base, in the platform or nowhere, legs as floats or as strings (rounded), lengths
as given or 4096 times larger (normalised by :mod:`distkin.octahedral.scaling`), fast and
auto.  README: the thin problem alone gets verdict 11 (``auto``: it is handed to an
exact tier), the others keep their answers.  References: the single solve of each
problem (a second route: :func:`forward_kinematics`), and for the thin problem under
``auto`` the single ``auto`` solve."""

import itertools
import warnings

import numpy as np
import pytest

from distkin.errors import ConditioningWarning, DegenerateGeometryError
from distkin.octahedral import forward_kinematics, forward_kinematics_batched
from distkin.octahedral.descartes import THIN_TRIANGLE

# Rojas et al., ICRA 2012, Sec. VI (Griffis-Duffy legs), base and platform in floats
BASE = [[0, 0, 0], [6, 10.39, 0], [12, 0, 0]]
PLAT = [[0, 0, 0], [6, 0, 0], [3, 5.2, 0]]
THIN_BASE = [[0, 0, 0], [6, 1e-7, 0], [12, 0, 0]]
THIN_PLAT = [[0, 0, 0], [6, 0, 0], [3, 1e-7, 0]]
LEGS = [19.8, 18, 18, 17, 14.9, 17.8]
STR_LEGS = ["19.8", 18, 18, 17, "14.9", "17.8"]     # the same floats, parsed exactly

CASES = [(bp, pp, thin, s, sc) for bp, pp, thin, s, sc in itertools.product(
    (False, True), (False, True), (None, "base", "platform"), (False, True), (1, 4096))
    if not (thin == "base" and not bp) and not (thin == "platform" and not pp)]


def _scaled(rows, sc):
    return [[x * sc for x in r] for r in rows]


def _batch(base_per, plat_per, thin, strings, sc):
    """The batch (fat problem, second problem: thin where asked) and its problems."""
    b0, q0 = _scaled(BASE, sc), _scaled(PLAT, sc)
    b1 = _scaled(THIN_BASE, sc) if thin == "base" else b0
    q1 = _scaled(THIN_PLAT, sc) if thin == "platform" else q0
    legs = [str(float(l) * sc) if isinstance(l, str) else l * sc
            for l in (STR_LEGS if strings else LEGS)]
    base = np.array([b0, b1], float) if base_per else np.array(b0, float)
    plat = np.array([q0, q1], float) if plat_per else np.array(q0, float)
    return base, plat, [legs, legs], [(b0, q0), (b1, q1)]


@pytest.mark.parametrize("base_per, plat_per, thin, strings, sc", CASES)
def test_batched_layouts_thin_and_rounded(base_per, plat_per, thin, strings, sc):
    if strings:           # the strings give the same floats as the float legs
        assert [float(str(float(l) * sc)) for l in STR_LEGS] == [l * sc for l in LEGS]
    base, plat, legs, problems = _batch(base_per, plat_per, thin, strings, sc)
    assert [float(l) for l in legs[0]] == [l * sc for l in LEGS]
    for method in ("fast", "auto"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConditioningWarning)
            b = forward_kinematics_batched(base, plat, legs, method=method)
        for i, (bi, qi) in enumerate(problems):
            if thin is not None and i == 1:
                if method == "fast":
                    assert b.verdict[i] == THIN_TRIANGLE and b.count[i] == 0
                    with pytest.raises(DegenerateGeometryError):
                        forward_kinematics(bi, qi, legs[i])
                else:
                    one = forward_kinematics(bi, qi, legs[i], method="auto")
                    assert b.tier[i] == one.tier != "fast"
                    assert b.count[i] == len(one)
                continue
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConditioningWarning)
                one = forward_kinematics(bi, qi, legs[i], method=method)
            assert b.count[i] == len(one) == 12
            assert b.tier[i] == one.tier == "fast" and b.verdict[i] == 0
            np.testing.assert_allclose(b.s15[i][:6], [r.value for r in one.roots],
                                       rtol=1e-12)


@pytest.mark.parametrize("strings", (False, True))
def test_single_thin_with_rounded_inputs(strings):
    """The single solve of the thin problem: fast refuses it, auto solves it exactly;
    the precise tier (a second route) finds the same number of poses."""
    legs = STR_LEGS if strings else LEGS
    with pytest.raises(DegenerateGeometryError, match="hint: method='auto'"):
        forward_kinematics(THIN_BASE, PLAT, legs)
    auto = forward_kinematics(THIN_BASE, PLAT, legs, method="auto")
    prec = forward_kinematics(THIN_BASE, PLAT, legs, method="precise", dps=40)
    assert auto.tier == "certified" and len(auto) == len(prec)


def test_batched_arrays_are_read_only_as_single_poses_are():
    """QA: ``b.translation[0, 0, 0] = 5`` edited the pose of a problem marked proved.
    The arrays of a BatchResult (and of ``raw``) are read-only, as a single solve's
    Pose arrays are (QA T 8); the caller's input arrays stay writable; the answer
    still equals the single solve's."""
    base = np.array([BASE, THIN_BASE], float)
    plat = np.array([PLAT, PLAT], float)
    legs = np.array([LEGS, LEGS], float)
    single = forward_kinematics(BASE, PLAT, LEGS)
    assert not single[0].translation.flags.writeable
    for method in ("fast", "auto"):      # auto: problem 1 escalated, the arrays rebuilt
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConditioningWarning)
            b = forward_kinematics_batched(base, plat, legs, method=method)
        arrays = {name: getattr(b, name) for name in (
            "count", "s15", "points", "rotation", "translation", "max_leg_error",
            "max_leg_error_relative", "valid", "trusted", "verdict", "tier")}
        arrays.update({f"raw[{k!r}]": v for k, v in b.raw.items()
                       if isinstance(v, np.ndarray)})
        for name, a in arrays.items():
            assert not a.flags.writeable, (method, name)
        with pytest.raises(ValueError, match="read-only"):
            b.translation[0, 0, 0] = 5
        pose = b.result(0)[0]
        with pytest.raises(ValueError, match="read-only"):
            pose.translation[0] = 5
        np.testing.assert_allclose(pose.translation, single[0].translation, rtol=1e-12)
        assert b.trusted[0]
        assert all(a.flags.writeable for a in (base, plat, legs))


@pytest.mark.parametrize("where, value, got", [
    ("legs", np.array([[LEGS, LEGS], [LEGS, LEGS]]), "(2, 2, 6)"),      # two batch axes
    ("legs", np.array([LEGS[:5], LEGS[:5]]), "(2, 5)"),                 # a wrong last axis
    ("legs", 18.0, "()"),
    ("base", np.array([[BASE, BASE], [BASE, BASE]]), "(2, 2, 3, 3)"),
    ("platform", np.array(PLAT)[:, :2], "(3, 2)"),
])
def test_a_wrong_shape_names_the_accepted_shapes_and_the_one_received(where, value, got):
    """QA: legs of shape (2, 2, 6) said 'legs: expected at most one batch axis' (no shape;
    for base too, and blaming legs), and a wrong last axis 'expected shape (..., 6)', as
    if any number of batch axes would do: one batch axis at most, the field that is
    wrong, and the shape received."""
    from distkin.errors import InputError
    args = {"base": BASE, "platform": PLAT, "legs": LEGS, where: value}
    accepted = "(6,) or (N, 6)" if where == "legs" else "(3, 3) or (N, 3, 3)"
    with pytest.raises(InputError) as err:
        forward_kinematics_batched(args["base"], args["platform"], args["legs"])
    assert err.value.field == where
    assert err.value.message == f"expected shape {accepted}, got {got}"
