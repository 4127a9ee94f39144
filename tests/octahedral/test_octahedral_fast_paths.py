"""The fast tier's internals against independent routes.

* the trilateration sequence in the base-adapted frame (closed forms, compiled:
  :func:`distkin.octahedral.placement.assemble_many`) against the foundation's Gram-form
  trilateration (:func:`distkin.geometry.trilateration.trilaterate`) run step by step as
  in Sec. III of Rojas et al. (ICRA 2012), on octahedra in general position (base not in
  z = 0), and against the generating pose;
* the single-solve tier and the batched tier against each other and against the
  certified roots (since issue 17 the single solve takes the batched tier's sign scan
  first and the eigenvalues only for the problems the scan doubts; the eigenvalue
  route on its own is compared with the scan in test_octahedral_signscan.py);
* every returned pose is a proper rigid motion that carries the platform triangle onto
  the returned points (this checks the mirror-image shortcut for side -1).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from distkin.errors import ConditioningWarning

from distkin.geometry.trilateration import trilaterate
from distkin.octahedral import forward_kinematics, forward_kinematics_batched
from distkin.octahedral.placement import assemble_many
from distkin.octahedral.problem import LEG_PAIRS, float_problem
from distkin.octahedral.reference import random_octahedron


def _general_position(rng, n, shape="random"):
    """Random assembled octahedra, then moved by a random rigid motion (base anywhere)."""
    out = []
    for _ in range(n):
        b, q, l, pts, _, _ = random_octahedron(rng, scale=10 ** rng.uniform(-2, 2), shape=shape)
        M, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        M = M * np.sign(np.linalg.det(M))
        shift = rng.normal(size=3) * np.abs(b).max()
        out.append((b @ M.T + shift, q, l, pts @ M.T + shift))
    return out


def _sequence_by_trilateration(base, s15, sides2, legs2, side):
    """Sec. III step by step with the foundation's trilateration; P6 chosen by leg 5."""
    s45, s46, s56 = sides2[3:]
    s14, s24, s25, s35, s36, s16 = legs2
    P1, P2, P3 = base
    P5 = trilaterate(np.array([P1, P2, P3]), [s15, s25, s35], side)
    best = None
    for tau in (1, -1):
        P4 = trilaterate(np.array([P1, P2, P5]), [s14, s24, s45], tau)
        for rho in (1, -1):
            P6 = trilaterate(np.array([P1, P4, P5]), [s16, s46, s56], rho)
            r = abs(np.sum((P6 - P3) ** 2) - s36)
            if best is None or r < best[0]:
                best = (r, np.array([P4, P5, P6]))
    return best[1]


def test_adapted_frame_sequence_matches_gram_trilateration():
    rng = np.random.default_rng(31)
    cases = _general_position(rng, 150)
    B = np.array([c[0] for c in cases])
    Q = np.array([c[1] for c in cases])
    L = np.array([c[2] for c in cases])
    B, Q, L, s2, l2, _, _ = float_problem(B, Q, L)
    x = np.array([np.sum((c[3][1] - c[0][0]) ** 2) for c in cases])    # true s15
    pts, h2min, r36 = assemble_many(B, x, s2, l2)
    assert pts.shape == (150, 2, 3, 3) and h2min.shape == r36.shape == (150,)
    size = np.abs(B).max(axis=(1, 2)) + np.abs(Q).max(axis=(1, 2))
    for i, c in enumerate(cases):
        for s, side in enumerate((1, -1)):
            ref = _sequence_by_trilateration(B[i], x[i], s2[i], l2[i], side)
            assert np.abs(pts[i, s] - ref).max() <= 1e-9 * size[i]
        # the generating pose is one of the two mirror placements
        assert min(np.abs(pts[i, s] - c[3]).max() for s in range(2)) <= 1e-9 * size[i]
        assert np.all(h2min[i] > -1e-12) and np.all(r36[i] < 1e-9)


def test_single_and_batched_tiers_agree_with_each_other_and_the_certified_roots():
    rng = np.random.default_rng(32)
    cases = _general_position(rng, 60) + _general_position(rng, 20, shape="regular")
    B = np.array([c[0] for c in cases])
    Q = np.array([c[1] for c in cases])
    L = np.array([c[2] for c in cases])
    br = forward_kinematics_batched(B, Q, L)
    for i, (b, q, l, truth) in enumerate(cases):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ConditioningWarning)
            single = forward_kinematics(b, q, l)
        batched = br.result(i)
        assert [r.status for r in single.roots] == [r.status for r in batched.roots]
        assert len(single) == len(batched) == br.count[i]
        size = np.abs(b).max() + np.abs(q).max()
        for ps, pb in zip(single, batched):
            assert ps.side == pb.side
            assert abs(ps.s15 - pb.s15) <= 1e-9 * max(ps.s15, size ** 2)
            assert np.abs(ps.points - pb.points).max() <= 1e-8 * size
        # floats are taken as their exact binary values by the certified tier
        cert = forward_kinematics(b, q, l, method="certified", tol=1e-12)
        exact = np.array([r.value for r in cert.assembly_roots])
        for r in single.assembly_roots:
            assert np.min(np.abs(exact - r.value)) <= 1e-9 * r.value
        if len(single.assembly_roots) != len(exact):
            assert caught, i                   # a miscount is announced (not proved)
        true_s15 = np.sum((truth[1] - b[0]) ** 2)
        assert np.min(np.abs(exact - true_s15)) <= 1e-8 * true_s15


@pytest.mark.parametrize("batched", [False, True])
def test_every_pose_is_a_proper_rigid_motion_onto_its_points(batched):
    rng = np.random.default_rng(33)
    cases = _general_position(rng, 40)
    B = np.array([c[0] for c in cases])
    Q = np.array([c[1] for c in cases])
    L = np.array([c[2] for c in cases])
    results = ([forward_kinematics_batched(B, Q, L).result(i) for i in range(len(cases))]
               if batched else [forward_kinematics(*c[:3], warn=False) for c in cases])
    n_poses = 0
    for (b, q, l, _), res in zip(cases, results):
        size = np.abs(b).max() + np.abs(q).max()
        sides = [p.side for p in res]
        assert sides == [1, -1] * (len(res) // 2)
        for p in res:
            R = p.rotation
            assert np.allclose(R @ R.T, np.eye(3), atol=1e-12)
            assert abs(np.linalg.det(R) - 1) <= 1e-12
            assert np.abs(q @ R.T + p.translation - p.points).max() <= 1e-9 * size
            full = np.vstack([b, p.points])
            lengths = [np.linalg.norm(full[i - 1] - full[j - 1]) for i, j in LEG_PAIRS]
            err = np.max(np.abs(np.array(lengths) - l))
            assert err <= p.max_leg_error * (1 + 1e-9) + 1e-15 * size
            n_poses += 1
        # the two poses of one root are mirror images in the base plane
        n = np.cross(b[1] - b[0], b[2] - b[0])
        n /= np.linalg.norm(n)
        for p, m in zip(res.poses[::2], res.poses[1::2]):
            mirrored = p.points - 2 * ((p.points - b[0]) @ n)[:, None] * n
            assert np.abs(mirrored - m.points).max() <= 1e-9 * size
    assert n_poses > 100


def test_no_phantom_close_roots_and_the_two_fast_paths_agree():
    """Two starts from a nearly real complex pair next to one simple root used to stall
    on its two sides, 1e-9..1e-8 apart, and the single solve reported the root twice
    (8 of these 2000 octahedra, two with duplicated assembly poses).  Reference: the
    certified tier (exact fmpq octic of the same floats, FLINT isolation); a pair of fast
    roots closer than 1e-7 relative must be two certified roots."""
    rng = np.random.default_rng(7)
    cases = [random_octahedron(rng, scale=10 ** rng.uniform(-2, 2))[:3] for _ in range(2000)]
    B, Q, L = (np.array([c[k] for c in cases]) for k in range(3))
    br = forward_kinematics_batched(B, Q, L, warn=False)
    assert br.trusted.sum() >= 1990       # proved (the others are flagged: see test_auto)
    close = 0
    for i, c in enumerate(cases):
        single = forward_kinematics(*c, warn=False)
        assert [r.status for r in single.roots] == [r.status for r in br.result(i).roots], i
        v = [r.value for r in single.roots]
        for a, b in zip(v, v[1:]):
            if b - a <= 1e-7 * max(abs(b), 1e-300):
                close += 1
                cert = forward_kinematics(*c, method="certified", tol=1e-12)
                near = [r.value for r in cert.roots if a - (b - a) <= r.value <= b + (b - a)]
                assert len(near) >= 2, (i, a, b, near)
    assert close <= 2    # genuinely close pairs are rare among random octahedra


def test_single_solve_next_to_a_nearly_flat_banana_tetrahedron():
    """Two random octahedra whose generating pose has a banana tetrahedron flat to
    ~1e-10 of c^3 (c: the middle of the feasible interval): there eq. (3) has a square
    root singularity, a first Newton step below 1e-9 relative proved nothing, and the
    single solve used to stop there; its pose was 2.6e-6 and 1.6e-7 (relative) from the
    generating one (the batched tier, starting from the more accurate scanned roots, was
    at 1e-11).  Reference: the generating pose; now within 1e-9."""
    from distkin.octahedral.single import bounds, octic_array, tet_min
    rng = np.random.default_rng(102)
    cases = [random_octahedron(rng, scale=10 ** rng.uniform(-3, 3),
                               shape="regular" if i % 4 == 0 else "random")
             for i in range(2000)]
    for i in (1597, 1998):
        b, q, l, pts, _, _ = cases[i]
        _, _, _, s2, l2, k, _ = float_problem(b, q, l)        # lengths / 2^k
        d = octic_array(s2[0], l2[0])
        lo, hi = bounds(s2[0], l2[0])
        c = 0.5 * (max(lo, 0.0) + hi)
        s15 = np.ldexp(np.sum((pts[1] - b[0]) ** 2), -2 * int(k[0]))
        assert abs(tet_min(d, s15)) < 1e-9 * c ** 3   # the case
        size = np.abs(b).max() + np.abs(pts).max()
        res = forward_kinematics(b, q, l, warn=False)
        assert min(np.abs(p.points - pts).max() for p in res) <= 1e-9 * size


def test_compile_notice_only_before_the_first_solve_on_a_machine(tmp_path, capsys):
    """A scene run says why its first fast solve on a machine is slow (numba compiles,
    20-60 s), and says it once; with the machine code in numba's cache it says nothing."""
    import os
    import subprocess
    import sys

    from distkin.octahedral.single import compile_notice
    from distkin.app.registry import RunContext
    forward_kinematics(*_general_position(np.random.default_rng(1), 1)[0][:3], warn=False)
    assert compile_notice() == ""                   # this process has used the cache
    code = ("from distkin.octahedral.single import compile_notice; "
            "print(compile_notice())")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))   # a machine with no cache
    msg = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, check=True).stdout.strip()
    assert msg.startswith("compiling the fast octahedral tier")
    ctx = RunContext(progress=True)
    ctx.notice(msg)
    ctx.notice(msg)
    ctx.notice("")
    RunContext(progress=False).notice(msg)
    assert capsys.readouterr().err == f"distkin: {msg}\n"


def test_placement_arrays_are_disjoint_contiguous_views():
    """:func:`distkin.octahedral.placement.place_many` returns its eleven arrays as views
    of two blocks (issue 17: one allocation instead of eleven); each must have its own
    memory (no two overlap: writing one cannot change another), be C-contiguous with
    the documented shape and dtype, and hold what the batched tier reports."""
    from distkin.octahedral import batched
    from distkin.octahedral.placement import place_many
    rng = np.random.default_rng(5)
    cases = [random_octahedron(rng)[:3] for _ in range(50)]
    B, Q, L, s2, l2, _, _ = float_problem(*(np.array([c[k] for c in cases]) for k in range(3)))
    raw = batched.solve_fast(B, Q, L, s2, l2)
    lo, hi, x0, h, c = batched.scan_window(s2, l2)
    rows = np.flatnonzero(raw["status"].ravel() >= 0)
    row, col = np.divmod(rows, 8)
    out = place_many(B, Q, L, s2, l2, lo, hi, c, row, raw["roots"][row, col],
                     raw["step"][row, col], raw["status"][row, col].copy())
    n = len(cases)
    shapes = [(n, 8), (n, 8), (n, 8), (n, 8), (n,), (n, 8), (n, 16, 3, 3), (n, 16, 3, 3),
              (n, 16, 3), (n, 16), (n, 16)]
    kinds = "ffiiiffffff"
    spans = []
    for a, shape, kind in zip(out, shapes, kinds):
        assert a.shape == shape and a.dtype.kind == kind and a.flags.c_contiguous
        start = a.__array_interface__["data"][0]
        spans.append((start, start + a.nbytes))
    spans.sort()
    assert all(e0 <= s1 for (_, e0), (s1, _) in zip(spans, spans[1:]))
    for name, a in zip(("roots", "step", "status", "slot", "count", "s15", "points",
                        "rotation", "translation", "leg_error", "leg_error_rel"), out):
        assert np.array_equal(a, raw[name], equal_nan=True), name
