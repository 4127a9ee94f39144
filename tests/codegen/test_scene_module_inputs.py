"""The scene modules of ``distkin codegen`` at their entry points (QA U): integer and list
inputs give the float64 answer, wrong shapes and negative squared lengths are refused
naming what was expected and received (batched and scalar alike), the docstrings of a
prismatic leg table speak of lengths, and every header names its generator module.

Second routes: the float64 input's answer, distkin's exact octic (fmpq) and exact
Cayley-Menger determinants, and numpy's |x + R p - B| for prismatic legs."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from scene_modules import SCENES

#: Griffis-Duffy legs 20, 18, 18, 17, 15, 18 squared (exact integers)
GD_L2 = [400, 324, 324, 289, 225, 324]


def test_integer_inputs_give_the_float_answer(mods):
    """int64 squared legs (mm^2-sized) overflowed in the batched octic (6.85e9 ...
    -6.08e18 instead of ... 2.859e30) and Cayley-Menger determinants: now the int64,
    the list and the float64 inputs give one answer, which is distkin's exact one."""
    from flint import fmpq

    from distkin.geometry.cayley_menger import cayley_menger, parse_label, squared_distances
    from distkin.octahedral.closure import octic_data
    gd, cm = mods["gd"], mods["cm"]
    li = np.array([GD_L2])
    want = gd.octic(li.astype(float))
    np.testing.assert_array_equal(gd.octic(li), want)
    np.testing.assert_array_equal(gd.octic([GD_L2]), want)
    np.testing.assert_array_equal(gd.parts(li), gd.parts(li.astype(float)))
    np.testing.assert_allclose(gd.octic_scalar(li[0]), want[0], rtol=1e-14)  # numpy ints
    sides = [fmpq(144)] * 3 + [fmpq(36)] * 3            # the scene's exact squared sides
    exact = octic_data(sides, [fmpq(v) for v in GD_L2], "exact")[30:]
    exact = np.array([float(Fraction(int(c.p), int(c.q)) / Fraction(int(exact[0].p),
                                                                   int(exact[0].q)))
                      for c in exact])
    np.testing.assert_allclose(want[0] / want[0][0], exact, rtol=1e-12, atol=0)
    assert want[0][-1] > 2.8e30                        # the answer the int input lost

    P = np.array([[0, 0, 0], [6, 0, 0], [2, 5, 0], [1, 1, 4], [3, -2, 2], [-1, 3, 2]]) * 300
    idx = np.array(cm.PAIRS) - 1
    sq = ((P[idx[:, 0]] - P[idx[:, 1]]) ** 2).sum(-1)[None]    # int64 mm^2, exact
    got = cm.determinants(sq)
    np.testing.assert_array_equal(got, cm.determinants(sq.astype(float)))
    np.testing.assert_allclose(cm.determinants_scalar(sq[0]), got[0], rtol=1e-14)
    S = squared_distances(np.array(P.tolist(), dtype=object))
    for m, name in enumerate(cm.DETERMINANTS):
        rows, cols = parse_label(name)
        ref = float(cayley_menger(S, rows, cols))
        # a vanishing determinant (5 points in 3-D) against the size of its terms
        scale = max(abs(ref), float(sq.max()) ** (len(rows) - 1))
        assert abs(got[0][m] - ref) <= 1e-12 * scale, (name, got[0][m], ref)


def _refused(f, x, *words):
    with pytest.raises(ValueError) as e:
        f(*x) if isinstance(x, tuple) else f(x)
    assert all(w in str(e.value) for w in words), str(e.value)


def test_wrong_shapes_are_refused_naming_both(mods):
    """7 values were taken as 6 (the seventh ignored), 5 gave an IndexError: now a
    ValueError naming the expected shape (and, batched, the received one)."""
    gd, cm, op = mods["gd"], mods["cm"], mods["op"]
    L2 = np.array(GD_L2, float)
    for f in (gd.octic, gd.parts, gd.s15_interval):
        _refused(f, np.append(L2, 1e9)[None], "legs2", "(..., 6)", "got shape (1, 7)")
        _refused(f, L2[None, :5], "(..., 6)", "got shape (1, 5)")
    for f in (gd.octic_scalar, gd.s15_interval_scalar):     # (numba: constant messages)
        _refused(f, list(L2) + [1e9], "legs2 of shape (6,): 6 numbers")
        _refused(f, L2[None], "legs2 of shape (6,)")
    P = len(cm.PAIRS)
    _refused(cm.determinants, np.ones((2, P + 1)), "sq", f"(..., {P})", f"(2, {P + 1})")
    _refused(cm.determinants_scalar, [1.0] * (P - 1), f"sq of shape ({P},)")
    pose = np.array([0.04, -0.03, 0.33, 0.26, -0.17, 0.35])
    for f in (op.ik, op.jacobian, op.reach):
        _refused(f, pose[:5], "pose", "(..., 6)", "got shape (5,)")
        _refused(f, np.append(pose, 9.0), "pose", "(..., 6)", "got shape (7,)")
    for f in (op.ik_scalar, op.jacobian_scalar):
        _refused(f, list(pose) + [9.0], "pose of shape (6,)")
    q = op.ik(pose)
    _refused(op.closure, (q[:-1], pose), "q", f"(..., {op.L})", f"got shape ({op.L - 1},)")
    _refused(op.closure_scalar, (list(q), list(pose[:5])), "pose", "(6,)")
    # the right shapes as lists: what float64 arrays give (a list was a TypeError)
    np.testing.assert_array_equal(op.jacobian(list(pose)), op.jacobian(pose))
    np.testing.assert_allclose(op.jacobian_scalar(pose), op.jacobian(pose), rtol=1e-14)


def test_negative_squared_legs_are_refused_alike(mods):
    """s15_interval_scalar of negative squared legs was a bare 'math domain error' and
    the batched twin a NaN: both now refuse it, naming the entry; NaN passes as NaN."""
    gd = mods["gd"]
    bad = np.array(GD_L2, float)
    bad[4] = -225.0
    _refused(gd.s15_interval_scalar, list(bad), "legs2 >= 0", "negative entry")
    _refused(gd.s15_interval, bad[None], "legs2[0, 4] = -225.0", ">= 0")
    _refused(gd.octic, bad, "legs2[4] = -225.0")
    nan = np.array(GD_L2, float)
    nan[0] = np.nan
    assert np.isnan(gd.s15_interval(nan)).any() and np.isnan(gd.s15_interval_scalar(nan)).any()


def test_prismatic_docstrings_speak_of_lengths(mods):
    """A UPS table's ik returns leg lengths in m (= |x + R p - B| by numpy), its reach
    the stroke margin, its closure has no l3; a revolute table keeps the crank angles."""
    from scipy.spatial.transform import Rotation
    gs, op = mods["gs"], mods["op"]
    assert "leg" in gs.ik.__doc__ and "lengths" in gs.ik.__doc__ and "(m)" in gs.ik.__doc__
    assert "crank" not in gs.ik.__doc__ + gs.ik_scalar.__doc__
    assert "(q - qmin)(qmax - q)" in gs.reach.__doc__ and "rho" not in gs.reach.__doc__
    assert "l3" not in gs.closure.__doc__ and "q_i the leg length (m)" in gs.closure.__doc__
    assert "crank" in op.ik.__doc__ and "rad" in op.ik.__doc__ and "l3" in op.closure.__doc__
    pose = np.array([0.01, -0.02, 0.45, 0.05, -0.04, 0.1])
    R = Rotation.from_euler("xyz", pose[3:]).as_matrix()
    legs = [dict(leg) for leg in gs.LEGS]
    ref = [np.linalg.norm(pose[:3] + R @ np.array(g["platform"]) - np.array(g["base"]))
           for g in legs]
    np.testing.assert_allclose(gs.ik(pose), ref, rtol=1e-13)
    lo, hi = np.array([g["range"] for g in legs]).T
    np.testing.assert_allclose(gs.reach(pose), (np.array(ref) - lo) * (hi - np.array(ref)),
                               rtol=1e-12)


def test_mixed_table_docstrings_name_the_legs():
    """A table of revolute and prismatic legs: each docstring says which legs it is for."""
    from distkin.codegen.rss import _docs
    desc = SimpleNamespace(L=3, leg_table=[SimpleNamespace(prismatic=p)
                                           for p in (False, True, False)])
    docs = _docs(desc)
    assert "Revolute legs [0, 2]" in docs["ik"] and "Prismatic legs [1]" in docs["ik"]
    assert "crank" in docs["ik"] and "lengths q_i = |P_i - B_i| (m)" in docs["ik"]
    assert "(q - qmin)(qmax - q)" in docs["reach"] and "rho^2 - C^2" in docs["reach"]


def test_scene_headers_name_their_generator_module(mods):
    """Every scene module's header names the generator module (the rss/legs one named
    only the scene) and its symbolic hash is SOURCE_SHA256."""
    gens = {"gd": "(distkin.codegen.octahedral_scene; derivation: "
                  "derivations/octahedral_octic.py)",
            "cm": "(distkin.codegen.cayley_menger_scene)",
            "op": "(distkin.codegen.rss; derivation: derivations/rss_model.py)",
            # a 6-UPS table: the RSS script is not its derivation (QA W 12)
            "gs": "(distkin.codegen.rss; derivation: distkin.mechanisms.symbolic, "
                  "prismatic legs)"}
    for key, gen in gens.items():
        head = Path(mods[key].__file__).read_text(encoding="utf-8").splitlines()[:3]
        assert head[0] == f"# GENERATED BY distkin codegen {SCENES[key]} {gen} -- DO NOT EDIT"
        assert head[2] == f"# symbolic source sha256: {mods[key].SOURCE_SHA256}"


def test_scalar_kernels_still_compile_with_numba(mods):
    """QA W 1: the scalar twins' check was a call of a Python class, and
    ``numba.njit(m.reach_scalar)`` failed to type it; the check is now written out in
    what numba compiles.  Reference: the same kernel uncompiled, and the batched twin."""
    import numba
    op, gd = mods["op"], mods["gd"]
    pose = np.array([0.04, -0.03, 0.33, 0.26, -0.17, 0.35])
    for name in ("reach_scalar", "ik_scalar", "jacobian_scalar"):
        compiled = numba.njit(getattr(op, name))
        np.testing.assert_allclose(compiled(pose), getattr(op, name)(pose), rtol=1e-13)
    np.testing.assert_allclose(numba.njit(op.reach_scalar)(pose), op.reach(pose), rtol=1e-13)
    L2 = np.array(GD_L2, float)
    np.testing.assert_allclose(numba.njit(gd.octic_scalar)(L2), gd.octic(L2), rtol=1e-13)
    with pytest.raises(ValueError, match="pose of shape"):
        numba.njit(op.ik_scalar)(pose[:5])


def test_a_broadcast_input_survives_the_chunks(mods):
    """QA W 4: closure(q (4097, L), pose (6,)) failed past the 4096-row chunk (every input
    was sliced by rows, the pose came out empty), and pose (1, 6) failed to broadcast.
    Reference: the same rows below the chunk size, unchunked, and the closure's own
    zero at the IK angles of that pose."""
    op = mods["op"]
    pose = np.array([0.04, -0.03, 0.33, 0.26, -0.17, 0.35])
    q = np.repeat(op.ik(pose)[None], 4097, axis=0)
    small = op.closure(q[:10], pose)
    assert np.max(np.abs(small[..., 0])) < 1e-12          # Phi = 0 at the IK angles
    for p in (pose, pose[None]):
        big = op.closure(q, p)
        assert big.shape[0] == 4097
        np.testing.assert_array_equal(big[:10], small)
        np.testing.assert_array_equal(big[-1], small[0])
