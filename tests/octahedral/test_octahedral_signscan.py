"""The compiled routes of the batched fast tier (issue 17) against the numpy routes they
replace, and the light result objects against the dataclass constructors.

* :func:`distkin.octahedral.signscan.scan_many` (one compiled loop per problem) against
  :func:`distkin.octahedral.rootscan.real_roots` (numpy, the previous route): the same
  problems doubted, the same number of roots per problem, the roots within 1e-9
  relative (the grid values differ in the last bits, BLAS against a plain sum; the
  refinement stops at 1e-11 in u);
* the whole batched tier with either scan: the same counts, statuses and verdicts of
  the proof, and every assembly root of a proved problem within the sum of both routes'
  proved radii of the other's (both lie within their radius of the same exact root);
  poses within 1e-9 of the size of the mechanism;
* the compiled scalar kernel over rows against the batched numpy kernel: equal bits;
* the compiled input checks of float64 arrays (:func:`.problem.float_problem`'s fast
  path) against its general numpy path, and the compiled scan window against the numpy
  formulas it replaced (:func:`.closure.feasible_interval`): equal bits, and the same
  errors;
* the fast result objects (built without ``__init__``) equal to, and printed as, those
  built by the dataclass constructors;
* a batched row and the single solve of the same problem: equal bits (one formula for
  the squared lengths, :func:`.problem.sides_into`), on generic floats and on the hard
  families.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from distkin.errors import ConditioningWarning
from distkin.octahedral import batched, forward_kinematics, forward_kinematics_batched
from distkin.octahedral.closure import octic_data, shifted_octic
from distkin.octahedral.companion import octic_rows
from distkin.octahedral.problem import float_problem
from distkin.octahedral.reference import random_octahedron
from distkin.octahedral.result import AssemblyResult, Pose, RootInfo
from distkin.octahedral.rootscan import real_roots
from distkin.octahedral.signscan import scan_many


@pytest.fixture(scope="module")
def problems():
    rng = np.random.default_rng(1717)
    probs = [random_octahedron(rng) for _ in range(400)]
    return (np.array([p[0] for p in probs]), np.array([p[1] for p in probs]),
            np.array([p[2] for p in probs]))


def _numpy_scan(data, x0, h):
    return real_roots(shifted_octic(data, x0, h),
                      lambda r: shifted_octic(data[r], x0[r], h[r], absolute=True), x0, h)


def _window(s2, l2):
    """Centre, half-width and scale of the scan, as :func:`.batched.solve_fast` chooses
    them."""
    _, _, x0, h, c = batched.scan_window(s2, l2)
    return x0, h, c


def test_compiled_kernel_rows_equal_the_numpy_kernel(problems):
    _, _, _, s2, l2, _, _ = float_problem(*problems)
    s2, l2 = np.ascontiguousarray(s2), np.ascontiguousarray(l2)
    assert np.array_equal(octic_rows(s2, l2), octic_data(s2, l2, "fast"))


def test_compiled_scan_matches_the_numpy_scan(problems):
    _, _, _, s2, l2, _, _ = float_problem(*problems)
    data = octic_data(s2, l2, "fast")
    x0, h, c = _window(s2, l2)
    r1, x1, _, d1 = _numpy_scan(data, x0, h)
    r2, x2, _, d2 = scan_many(data, x0, h, False)
    assert np.array_equal(d1, d2)
    assert d1.sum() > 0                       # the doubt path is exercised
    assert np.array_equal(np.bincount(r1, minlength=len(x0)), np.bincount(r2, minlength=len(x0)))
    o1, o2 = np.lexsort((x1, r1)), np.lexsort((x2, r2))
    assert np.array_equal(r1[o1], r2[o2])
    rel = np.abs(x1[o1] - x2[o2]) / np.maximum(np.abs(x1[o1]), c[r1[o1]])
    assert rel.max() <= 1e-9


def test_batched_tier_with_either_scan_agrees(problems, monkeypatch):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConditioningWarning)
        monkeypatch.setattr(batched, "scan_many", lambda d, x0, h: scan_many(d, x0, h, False))
        new = forward_kinematics_batched(*problems)
        monkeypatch.setattr(batched, "scan_many", _numpy_scan)
        old = forward_kinematics_batched(*problems)
    assert np.array_equal(new.count, old.count)
    assert np.array_equal(new.raw["status"], old.raw["status"])
    assert np.array_equal(new.verdict, old.verdict)
    proved = new.trusted[:, None] & (new.raw["status"] == 0)
    gap = np.abs(new.raw["roots"] - old.raw["roots"])[proved]
    assert np.all(gap <= (new.raw["radii"] + old.raw["radii"])[proved])
    scale = np.abs(problems[0]).max(axis=(1, 2)) + problems[2].max(axis=1)
    dp = np.nan_to_num(np.abs(new.points - old.points)).max(axis=(1, 2, 3))
    assert np.all(dp <= 1e-9 * scale)


def test_second_scan_on_the_finer_grid():
    """The problems the grid of rootscan doubts are scanned again on a grid four times
    finer; most are then resolved without eigenvalues.  Where the answer differs from
    the careful way's, the one the proof vouches for has the certified count (on these
    3000 random octahedra: one problem with four roots within 1.5e-3 relative, where
    the eigenvalue route found two and was flagged, and the finer grid finds four)."""
    rng = np.random.default_rng(17)
    probs = [random_octahedron(rng) for _ in range(4000)][3000:]
    B, Q, L = (np.array([p[k] for p in probs]) for k in range(3))
    _, _, _, s2, l2, _, _ = float_problem(B, Q, L)
    data = octic_data(s2, l2, "fast")
    x0, h, _ = _window(s2, l2)
    coarse, fine = scan_many(data, x0, h, False)[3], scan_many(data, x0, h)[3]
    assert not (fine & ~coarse).any() and fine.sum() < 0.5 * coarse.sum()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConditioningWarning)
        new = forward_kinematics_batched(B, Q, L)
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(batched, "scan_many", lambda d, x0, h: scan_many(d, x0, h, False))
            old = forward_kinematics_batched(B, Q, L)
    differ = np.flatnonzero((new.count != old.count) | (new.trusted != old.trusted))
    assert np.array_equal(new.count[~coarse], old.count[~coarse])
    for i in differ:
        cert = forward_kinematics(B[i], Q[i], L[i], method="certified")
        for res in (new, old):
            if res.trusted[i]:
                assert res.count[i] == len(cert), i
    assert new.trusted.sum() >= old.trusted.sum()


def _full(r):
    """Every field of an :class:`AssemblyResult` as its repr (its own repr is a summary)."""
    import dataclasses
    return tuple(repr(getattr(r, f.name)) for f in dataclasses.fields(r))


def test_light_result_objects_equal_the_constructed_ones(problems):
    res = forward_kinematics(problems[0][0], problems[1][0], problems[2][0], warn=False)
    batch = forward_kinematics_batched(*(a[:5] for a in problems), warn=False).result(0)
    for r in (res, batch):
        assert r.roots and r.poses
        for p in r.poses:
            q = Pose(p.s15, p.side, p.rotation, p.translation, p.points, p.max_leg_error,
                     p.max_leg_error_relative)
            assert type(p) is Pose and repr(p) == repr(q)
            assert all(np.array_equal(getattr(p, f), getattr(q, f)) for f in
                       ("s15", "side", "rotation", "translation", "points", "native",
                        "radius", "max_leg_error", "max_leg_error_relative"))
        built = AssemblyResult(r.poses, "fast", r.octic, False, r.roots, False, r.reason,
                               r.accuracy, r.notes, tier="fast",
                               conditioning=r.conditioning)
        assert type(r) is AssemblyResult and r == built and _full(r) == _full(built)
        assert len(r) == len(r.poses) and list(r) == list(r.poses) and r[0] is r.poses[0]
        for x in r.roots:
            y = RootInfo(x.value, x.radius, 1, x.status, x.reason, x.value, x.radius_kind)
            assert type(x) is RootInfo and x == y and repr(x) == repr(y)
            assert hash(x.native) == hash(y.native)


def test_lazy_single_result_equals_the_eager_route():
    """The bare and the default single solve read the compiled solver's buffer and
    build their roots and poses when first read (:func:`.result._buffer_result`);
    the eager route (:func:`.batched.solve_scan_single`, then
    :func:`.result._single_result`, main's construction) gives equal objects, bit for
    bit: on 300 random octahedra at three scales (one rescaled by a power of two),
    before and after a pickle, and ``len`` agrees before anything is built; so does
    ``method="auto"`` against :func:`.auto.escalate` of the eager result."""
    import copy
    import pickle

    from distkin.octahedral.batched import solve_scan_single
    from distkin.octahedral.conditioning import assess, eta_of
    from distkin.octahedral.problem import float_single
    from distkin.octahedral.result import _single_result
    rng = np.random.default_rng(11)
    lazy_seen = 0
    for i in range(300):
        B, Q, L = random_octahedron(rng)[:3]
        scale = (1.0, 2.0 ** -30, 1e100)[i % 3]
        B, Q, L = B * scale, Q * scale, L * scale
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConditioningWarning)
            bare = forward_kinematics(B, Q, L, warn=False)
            proved = forward_kinematics(B, Q, L)
        lazy_seen += "_lazy" in bare.__dict__
        n = len(bare)                               # before the poses are built
        b2, q2, l2, k, rounded = float_single(B, Q, L)
        raw = solve_scan_single(b2, q2, l2)
        cond = assess(raw.sides2, raw.legs2, raw.data, raw.lo, raw.hi, raw.roots,
                      eta_of(b2, q2, l2, rounded))
        eager = _single_result(raw, k=k)
        eager_proved = _single_result(raw, conditioning=cond, k=k)
        again = pickle.loads(pickle.dumps(proved))
        copied = copy.deepcopy(bare)
        assert n == len(eager)
        if i % 3 == 0:              # auto keeps the lazy result (its leg check reads the buffer)
            from distkin.octahedral.auto import escalate
            auto = forward_kinematics(B, Q, L, method="auto")
            assert _full(auto) == _full(escalate(eager_proved, B, Q, L))
        for got, want in ((bare, eager), (proved, eager_proved), (again, eager_proved),
                          (copied, eager)):
            assert _full(got) == _full(want)
            assert got.roots == want.roots
            for p, q in zip(got.poses, want.poses):
                for f in ("rotation", "translation", "points"):
                    assert np.array_equal(getattr(p, f), getattr(q, f))
    assert lazy_seen >= 80              # the lean path was tested (scale 1: not rescaled)


def test_single_solve_scan_route_against_the_eigenvalue_route():
    """The public single solve takes the batched tier's compiled scan
    (:func:`.batched.solve_scan_single`); the eigenvalue route
    (:func:`.single.solve_fast_single`: LAPACK, direct and careful paths) remains the
    careful way and a second route: the same statuses and poses (s15 within 1e-9
    relative, points within 1e-8 of the size of the mechanism, the tolerances of
    test_octahedral_fast_paths) on 2000 random octahedra at scales 1e-2..1e2."""
    from distkin.octahedral.problem import float_single
    from distkin.octahedral.result import _single_result
    from distkin.octahedral.single import solve_fast_single
    rng = np.random.default_rng(7)
    cases = [random_octahedron(rng, scale=10 ** rng.uniform(-2, 2))[:3] for _ in range(2000)]
    doubted = 0
    for b, q, l in cases:
        B, Q, L, k, _ = float_single(b, q, l)
        scan = batched.solve_scan_single(B, Q, L)
        doubted += scan.eigenvalues is not None          # went the careful way
        new = _single_result(scan, k=k)
        old = _single_result(solve_fast_single(B, Q, L), k=k)
        assert [r.status for r in new.roots] == [r.status for r in old.roots]
        size = np.abs(b).max() + np.abs(q).max()
        for pn, po in zip(new, old):
            assert pn.side == po.side
            assert abs(pn.s15 - po.s15) <= 1e-9 * max(po.s15, size ** 2)
            assert np.abs(pn.points - po.points).max() <= 1e-8 * size
    assert 0 < doubted < 400


def test_compiled_checks_and_window_equal_the_numpy_routes(problems):
    """float64 arrays take the compiled checks of :func:`.problem.float_problem` (issue
    17); nested lists of the same floats take the general numpy path: every returned
    array is the same, bit for bit, also where the lengths are rescaled; a NaN or a
    degenerate triangle in one problem of the arrays raises the general path's error.
    :func:`.batched.scan_window` (compiled) against the numpy formulas it replaced."""
    from distkin.errors import DegenerateGeometryError, InputError
    from distkin.octahedral import problem
    from distkin.octahedral.closure import feasible_interval
    B, Q, L = problems
    for f in (1.0, 2.0 ** 20, 2.0 ** -20):
        fast = float_problem(B * f, Q * f, L * f)
        general = float_problem((B * f).tolist(), (Q * f).tolist(), (L * f).tolist())
        assert len(fast) == len(general) == 7
        for a, b in zip(fast, general):
            assert a.dtype == b.dtype and np.array_equal(a, b)
        assert fast[5].any() == (f != 1.0)              # rescaled: the general path
    assert problem._batch_ok(B, Q, L, np.empty((len(L), 6)), np.empty((len(L), 6)))  # (f = 1: compiled)
    bad = L.copy()
    bad[7, 2] = np.nan
    with pytest.raises(InputError, match="finite"):
        float_problem(B, Q, bad)
    flat = Q.copy()
    flat[3, 2] = flat[3, 0] + 2 * (flat[3, 1] - flat[3, 0])      # P6 on the line P4 P5
    with pytest.raises(DegenerateGeometryError) as err:
        float_problem(B, flat, L)
    assert err.value.field == "platform[3]"          # (the problem at fault)
    _, _, _, s2, l2, _, _ = float_problem(B, Q, L)
    far = l2.copy()
    far[:, 2] *= 100.0                                  # P2P5 too long: no assembly
    s2, l2 = np.concatenate([s2, s2]), np.concatenate([l2, far])
    lo, hi, x0, h, c = batched.scan_window(s2, l2)
    lo_np, hi_np, _ = feasible_interval(s2, l2)
    lo0 = np.maximum(lo_np, 0.0)
    c_np = np.where(hi_np > 0, 0.5 * (lo0 + hi_np), np.mean(s2, axis=1))
    wide = hi_np > lo0
    x0_np = np.where(wide, 0.5 * (lo0 + hi_np), c_np)
    h_np = np.maximum(np.where(wide, 0.5 * (hi_np - lo0), 0.5 * c_np), 1e-3 * c_np)
    assert wide.any() and (~wide).any()                 # both branches
    for a, b in ((lo, lo_np), (hi, hi_np), (x0, x0_np), (h, h_np), (c, c_np)):
        assert np.array_equal(a, b)


def test_batched_rows_equal_single_solves_bit_for_bit():
    """The batched tier and the single solve share one formula for the squared sides
    (:func:`.problem.sides_into`; the batched input checks used numpy's ``einsum``
    before, which sums in another order: on generic floats about a quarter of the
    squared sides differed in the last bit, and with them the answers of problems near
    a double root).  Now a batched row and the single solve of the same problem agree
    bit for bit: squared lengths, kernel output, roots, poses and leg residuals, on 600
    random octahedra whose coordinates and legs carry full-width mantissas (each value
    times 1 + 1e-3 noise; the reference data alone have short mantissas that every
    order of summation rounds alike).  The problems the scan doubts go the careful way
    in both (eigenvalues, compared elsewhere) and are skipped here."""
    from distkin.octahedral.companion import _squares
    rng = np.random.default_rng(2026)
    cases = [random_octahedron(rng, scale=10 ** rng.uniform(-2, 2))[:3] for _ in range(600)]
    B, Q, L = (np.array([c[j] for c in cases]) for j in range(3))
    size = np.abs(B).max(axis=(1, 2))[:, None, None]
    B = B + 1e-3 * size * rng.standard_normal(B.shape)     # (z too: out of the xy plane)
    Q = Q + 1e-3 * size * rng.standard_normal(Q.shape)
    L = L * (1 + 1e-3 * rng.standard_normal(L.shape))
    pts = np.concatenate([B, Q], axis=1)
    einsum = np.stack([np.einsum("nk,nk->n", pts[:, i] - pts[:, j], pts[:, i] - pts[:, j])
                       for i, j in ((0, 1), (0, 2), (1, 2), (3, 4), (3, 5), (4, 5))], -1)
    single = np.array([_squares(B[i], Q[i], L[i])[0] for i in range(len(L))])
    assert (einsum != single).mean() > 0.05               # the data separate the orders
    assert np.allclose(einsum, single, rtol=4e-16, atol=0)
    b, q, l, s2, l2, k, _ = float_problem(B, Q, L)
    assert not k.any()                                     # (no rescaling: the same floats)
    raw = batched.solve_fast(b, q, l, s2, l2)
    checked = 0
    for i in range(len(L)):
        one = batched.solve_scan_single(b[i], q[i], l[i])
        if one.eigenvalues is not None:
            continue
        checked += 1
        m = raw["count"][i]
        assert np.array_equal(one.sides2, s2[i]) and np.array_equal(one.legs2, l2[i])
        assert np.array_equal(one.data, raw["data"][i])
        n = one.roots.shape[0]
        assert np.array_equal(one.roots[:, 0], raw["roots"][i, :n])
        assert np.array_equal(one.roots[:, 2], raw["status"][i, :n])
        assert np.isnan(raw["roots"][i, n:]).all()
        s15, _, points, rotation, translation, err, _ = one.poses
        assert s15.size == m
        for got, want in ((points, raw["points"]), (rotation, raw["rotation"]),
                          (translation, raw["translation"]), (err, raw["leg_error"])):
            assert np.array_equal(got, want[i, :m])
    assert checked > 500


def test_bare_single_and_batched_agree_on_the_hard_families():
    """The same agreement through the public entry points on the 240 problems of
    :func:`.hardset.hard_families` (near-coplanar, near-line, clustered; at 1e-3, 1 and
    1e3, rescaled by powers of two where needed), the doubted ones included: the bare
    single solve and the bare batched row give the same poses bit for bit.  (With the
    two orders of summation, 22 of the 240 differed in their last bits, one of them in
    its count: 4 poses single, 0 batched.)"""
    from distkin.octahedral.hardset import hard_families
    cases = hard_families()
    B, Q, L = (np.array([getattr(c, f) for c in cases]) for f in ("base", "platform", "legs"))
    bat = forward_kinematics_batched(B, Q, L, prove=False)
    for i, c in enumerate(cases):
        one = forward_kinematics(c.base, c.platform, c.legs, warn=False)
        assert len(one) == bat.count[i], c.name
        for j, pose in enumerate(one):
            assert pose.s15 == bat.s15[i, j // 2], c.name
            assert np.array_equal(pose.points, bat.points[i, j]), c.name
            assert np.array_equal(pose.rotation, bat.rotation[i, j]), c.name
