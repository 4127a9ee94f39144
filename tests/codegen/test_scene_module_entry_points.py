"""The scene modules of ``distkin codegen`` at their entry points, second round (QA X):
a scalar or None for a sequence, batch shapes that do not broadcast, a single pose to a
loop kernel and a prismatic leg's length <= 0 are ValueErrors naming what was expected
and received (not a raw TypeError, numpy's broadcast error, an IndexError, or inf/NaN);
what broadcasts in numpy now works; a declared crank range is in the reach margin.

Second routes: the scalar kernels row by row (and their numba compilation), numpy's
``(|P - B|^2 - q^2) / (2 q)`` of the leg table, and distkin's own inverse kinematics,
whose ``valid`` reads a crank's range from the angle of ``atan2``
(:func:`distkin.mechanisms.legs.in_revolute_range`)."""

from __future__ import annotations

import numpy as np
import pytest

from scene_modules import EX, SCENES

#: a pose of the Octopod and of the 6-UPS, inside their workspaces
OP_POSE = np.array([0.04, -0.03, 0.33, 0.26, -0.17, 0.35])
GS_POSE = np.array([0.01, -0.02, 0.45, 0.05, -0.04, 0.1])
#: Griffis-Duffy legs 20, 18, 18, 17, 15, 18 squared
GD_L2 = [400, 324, 324, 289, 225, 324]


def _refused(f, args, *words):
    with pytest.raises(ValueError) as e:
        f(*args)
    assert all(w in str(e.value) for w in words), str(e.value)


def test_a_scalar_for_a_sequence_is_refused_naming_it(mods):
    """ik_scalar(None) and ik_scalar(np.float64(1)) were raw TypeErrors of ``len``; now a
    ValueError naming the expected shape and what came; the batched twins name the type.
    Reference: the right input still gives the batched kernel's answer."""
    op, gd, cm, gs = mods["op"], mods["gd"], mods["cm"], mods["gs"]
    P = len(cm.PAIRS)
    for f, k, name in ((op.ik_scalar, 6, "pose"), (op.reach_scalar, 6, "pose"),
                       (gd.octic_scalar, 6, "legs2"), (cm.determinants_scalar, P, "sq")):
        want = f"expected {name} of shape ({k},): {k} numbers, got"
        _refused(f, (None,), want + " None")
        for x in (np.float64(1.0), 1, 2.5, np.int64(3), True):
            _refused(f, (x,), want + " a single number")
        _refused(f, (object(),), want + " an object without a length")
        _refused(f, ([1.0] * (k - 1),), want + f" length {k - 1}")
    q = op.ik(OP_POSE)
    _refused(op.closure_scalar, (1.0, OP_POSE), "expected q of shape (8,)", "a single number")
    _refused(op.closure_scalar, (q, None), "expected pose of shape (6,)", "got None")
    _refused(op.ik, (None,), "pose of shape (..., 6)", "got shape ()", "NoneType")
    _refused(op.ik, ("abc",), "pose of shape (..., 6): numbers", "got a str")
    _refused(op.ik, ({"x": 1},), "pose of shape (..., 6): numbers", "got a dict")
    np.testing.assert_allclose(op.ik_scalar(list(OP_POSE)), op.ik(OP_POSE), rtol=1e-14)
    np.testing.assert_allclose(np.array(gs.closure_scalar(gs.ik(GS_POSE), GS_POSE)),
                               gs.closure(gs.ik(GS_POSE), GS_POSE), rtol=1e-13, atol=1e-15)


def test_batch_shapes_are_broadcast_or_refused_naming_both(mods):
    """closure(q (5, L), pose (3, 6)) gave numpy's "operands could not be broadcast",
    naming neither input, and q (L,) beside poses (N, 6), which broadcast, failed too
    (the output took q's shape): now the first is refused naming both shapes (also past
    the 4096-row chunk) and the second gives N rows.  Reference: closure_scalar per row."""
    op = mods["op"]
    L = op.L
    poses = OP_POSE + np.linspace(-0.01, 0.01, 5)[:, None]
    qs = op.ik(poses)
    _refused(op.closure, (qs, poses[:3]), f"q {qs.shape}", "pose (3, 6)", "broadcast")
    big = np.repeat(poses[:1], 5000, axis=0)
    _refused(op.closure, (op.ik(big), big[:4999]), f"q (5000, {L})", "pose (4999, 6)")
    got = op.closure(qs[0], poses)                       # q (L,) beside poses (5, 6)
    assert got.shape == (5, L, 7)
    for i in range(5):
        np.testing.assert_allclose(got[i], np.array(op.closure_scalar(qs[0], poses[i])),
                                   rtol=1e-13, atol=1e-15)
    np.testing.assert_array_equal(op.closure(qs[:1], poses), got)    # q (1, L) alike
    many = np.repeat(poses, 1000, axis=0)                # 5000 rows: chunked by the poses
    wide = op.closure(qs[0], many)
    assert wide.shape == (5000, L, 7)
    np.testing.assert_array_equal(wide[::1000], got)


def test_loop_kernels_take_rows_or_refuse(mods):
    """reach_loop(pose (6,), out) was an IndexError: now a ValueError that says a single
    pose is pose[None]; a wrong ``_out`` is refused too.  Reference: the batched reach,
    and the loop kernel compiled by numba (what it is written for)."""
    import numba
    op = mods["op"]
    out = np.empty((1, op.L))
    _refused(op.reach_loop, (OP_POSE, out), "pose of shape (N, 6)", "pose[None]",
             "1-dimensional")
    _refused(op.reach_loop, (list(OP_POSE[None]), out), "not an array")
    X = np.repeat(OP_POSE[None], 3, axis=0)
    _refused(op.reach_loop, (X, np.empty((2, op.L))), f"_out of shape (N, {op.L}) with N = 3",
             f"got shape (2, {op.L})")
    _refused(op.reach_loop, (X[:, :5].copy(), np.empty((3, op.L))), "got shape (3, 5)")
    op.reach_loop(OP_POSE[None], out)
    np.testing.assert_allclose(out[0], op.reach(OP_POSE), rtol=1e-13)
    compiled = numba.njit(op.reach_loop)
    got = np.empty((3, op.L))
    compiled(X, got)
    np.testing.assert_allclose(got, op.reach(X), rtol=1e-13)
    with pytest.raises(ValueError, match=r"got shape \(2, 8\)"):
        compiled(X, np.empty((2, op.L)))


def test_prismatic_lengths_must_be_positive_alike(mods):
    """A 6-UPS closure at q = 0 gave inf/NaN (batched) or ZeroDivisionError (scalar), and
    a negative length passed as the positive one (its square): both flavours now refuse
    q <= 0 naming the leg, as the package's forward kinematics does; NaN passes as NaN;
    a crank angle (revolute table) may be negative.  Reference: numpy's
    (|x + R p - B|^2 - q^2) / (2 q) of the leg table."""
    import numba
    from scipy.spatial.transform import Rotation
    gs, op = mods["gs"], mods["op"]
    q = gs.ik(GS_POSE)
    for v, word in ((0.0, "= 0"), (-float(q[3]), "< 0")):
        bad = q.copy()
        bad[3] = v
        _refused(gs.closure, (bad, GS_POSE), f"q[3] = {v!r}", "prismatic leg 4", "q > 0")
        _refused(gs.closure, (np.array([q, bad]), GS_POSE), f"q[1, 3] = {v!r}")
        for f in (gs.closure_scalar, numba.njit(gs.closure_scalar)):
            _refused(f, (bad, GS_POSE), "q[3] > 0", "prismatic leg 4", f"got q[3] {word}")
    nan = q.copy()
    nan[2] = np.nan
    assert np.isnan(gs.closure(nan, GS_POSE)[2, 0])
    assert np.isnan(gs.closure_scalar(nan, GS_POSE)[2][0])
    R = Rotation.from_euler("xyz", GS_POSE[3:]).as_matrix()
    legs = [dict(leg) for leg in gs.LEGS]
    d2 = np.array([np.sum((GS_POSE[:3] + R @ np.array(g["platform"]) - np.array(g["base"]))
                          ** 2) for g in legs])
    ql = 1.05 * q
    np.testing.assert_allclose(gs.closure(ql, GS_POSE)[:, 0], (d2 - ql ** 2) / (2 * ql),
                               rtol=1e-12)
    qo = op.ik(OP_POSE)
    qo[0] = -abs(qo[0]) - 0.1                          # a crank angle: any sign
    np.testing.assert_allclose(op.closure(qo, OP_POSE),
                               np.array(op.closure_scalar(qo, OP_POSE)), rtol=1e-13,
                               atol=1e-15)


def test_positive_columns_only_in_a_mixed_table():
    """The check of ``positive`` columns (a mixed table's prismatic legs) leaves the other
    columns alone, batched and scalar.  Reference: the kernel's own expression."""
    import sympy as sp

    from distkin.codegen.emit import Kernel, module_source
    a, b, c = sp.symbols("a b c", real=True)
    extra = {"checked": True, "positive": {"q": (1,)}}
    src = module_source([Kernel("f", (("q", (a, b, c)),), [a * b - c], flavour=fl,
                                extra=extra) for fl in ("batched",)]
                        + [Kernel("f_scalar", (("q", (a, b, c)),), [a * b - c],
                                  flavour="scalar", extra=extra)],
                        generator="test", doc="test", source_hash="0")
    ns = {}
    exec(compile(src, "<mixed>", "exec"), ns)
    for f in (ns["f"], ns["f_scalar"]):
        np.testing.assert_allclose(np.ravel(f([-2.0, 3.0, -1.0])), [-2.0 * 3.0 + 1.0])
    _refused(ns["f"], ([[1.0, 2.0, 3.0], [-1.0, -0.5, 1.0]],), "q > 0 in the columns [1]",
             "q[1, 1] = -0.5")
    _refused(ns["f_scalar"], ([1.0, 0.0, 1.0],), "q[1] > 0", "got q[1] = 0")


def test_reach_holds_the_declared_crank_ranges(mods):
    """The reach of a scene with crank ranges (rus8: +-90 deg) held the closure only, so
    1495 of 160000 legs closing outside their range had a margin >= 0: now margin >= 0
    iff distkin's inverse kinematics calls the leg valid (it closes and atan2's angle is
    in its range), in the batched, scalar and loop kernels alike; the docstring says so."""
    from distkin.app.scene import load_scene
    ru = mods["ru"]
    mech = load_scene(EX / SCENES["ru"]).mechanism
    rng = np.random.default_rng(0)
    X = np.array([0, 0, 0.2, 0, 0, 0]) + rng.uniform(-1, 1, (20000, 6)) * [
        0.08, 0.08, 0.1, 0.6, 0.6, 0.6]
    q, valid = mech.inverse_kinematics(X)
    margin = mech.reach_margin(X)                      # rho^2 - C^2: the closure's only
    lo, hi = (np.array([leg.range[j] for leg in mech.leg_table]) for j in (0, 1))
    # clear of the range ends and of the reach boundary, where rounding decides
    clear = (np.minimum(np.abs(q - lo), np.abs(q - hi)) > 1e-9) & (np.abs(margin) > 1e-12)
    got = ru.reach(X)
    closes_out = (margin >= 0) & ~valid
    assert closes_out[clear].sum() > 100               # the case at stake is sampled
    np.testing.assert_array_equal((got >= 0)[clear], valid[clear])
    assert np.all(got <= margin + 1e-14)           # min(margin, range margin); m^2 ~ 0.05
    np.testing.assert_allclose(np.array(ru.reach_scalar(X[7])), got[7], rtol=1e-13)
    import numba
    for loop in (ru.reach_loop, numba.njit(ru.reach_loop)):     # min() compiled too
        out = np.empty((5, ru.L))
        loop(X[:5], out)
        np.testing.assert_allclose(out, got[:5], rtol=1e-13)
    assert "declare a joint range" in ru.reach.__doc__ and "[0, 1, 2, 3, 4, 5, 6, 7]" in \
        ru.reach.__doc__


def test_an_entry_that_is_not_a_number_is_refused_naming_it(mods):
    """ik_scalar([None] * 6) was float()'s raw TypeError: now a ValueError naming the
    expected (6 numbers and their units), the entry and its repr, in every scene module's
    scalar kernels.  Reference: the input itself (its entries' reprs), and numba's
    compilation of the same kernel still giving the batched answer."""
    import numba
    op, gd, cm, gs = mods["op"], mods["gd"], mods["cm"], mods["gs"]
    P = len(cm.PAIRS)
    cases = ((op.ik_scalar, 6, "pose", "x, y, z in m; rx, ry, rz in rad"),
             (op.jacobian_scalar, 6, "pose", "x, y, z in m; rx, ry, rz in rad"),
             (gd.octic_scalar, 6, "legs2", "squared length units"),
             (cm.determinants_scalar, P, "sq", "in m^2, the scene's unit"))
    for f, k, name, units in cases:
        for j, bad in ((0, None), (k - 1, "abc"), (2, [1.0, 2.0]), (1, object())):
            x = [1.0] * k
            x[j] = bad
            _refused(f, (x,), f"expected {name} of shape ({k},): {k} numbers ({units})",
                     f"got {name}[{j}] = {bad!r}")
    L = op.L
    _refused(op.closure_scalar, ([0.1] * (L - 1) + [None], OP_POSE),
             f"expected q of shape ({L},): {L} numbers (crank angles in rad)",
             f"got q[{L - 1}] = None")
    _refused(gs.closure_scalar, ([None] * 6, GS_POSE), "(leg lengths in m)", "q[0] = None")
    _refused(gs.closure_scalar, (gs.ik(GS_POSE), [0.0, None, 0, 0, 0, 0]),
             "(x, y, z in m; rx, ry, rz in rad)", "pose[1] = None")
    np.testing.assert_array_equal(gd.octic_scalar([str(v) for v in GD_L2]),  # float("400")
                                  gd.octic(np.array(GD_L2, float)))
    compiled = numba.njit(op.ik_scalar)
    np.testing.assert_allclose(compiled(OP_POSE), op.ik(OP_POSE), rtol=1e-13)
