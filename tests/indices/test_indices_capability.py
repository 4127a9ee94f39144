"""Worst/best-case output capabilities: the zonotope kernel against Ueberle's method
(L = d) and the paper's polytope algorithm (Qhull), on preset Jacobians, near
singularities and at the edge cases of docs/design.md §6."""

import warnings

import numpy as np
import pytest
from indices_helpers import random_reachable_poses, rel_err

from distkin.errors import ConditioningWarning, InputError, SingularConfigurationError
from distkin.indices import best_case_output, output_generators, worst_case_output
from distkin.indices.capability import UEBERLE_KAPPA, hull_multi
from distkin.indices.study import ACTUATORS

SLICES = (None, [0, 1, 2], [3, 4, 5])


def _generators(mech, poses):
    J = mech.jacobian(poses)
    return output_generators(J, mass=np.diag(mech.cartesian_mass_matrix()))


@pytest.mark.parametrize("name", ["ergin", "hexa", "hunt"])
def test_ueberle_equals_zonotope_on_1000_poses(presets, name):
    """Acceptance: L = d, 1000 random poses, every output and slice, 1e-9 relative."""
    mech = presets[name]
    poses = random_reachable_poses(mech, 1000, 20, seed=1)
    gens = _generators(mech, poses)
    for gen, lim in (("wrench", ACTUATORS["nominal_torque"]),
                     ("twist", ACTUATORS["velocity"]),
                     ("acceleration", ACTUATORS["stall_torque"])):
        for keep in SLICES:
            z = worst_case_output(gens[gen], -lim, lim, keep)
            u = worst_case_output(gens[gen], -lim, lim, keep, method="ueberle")
            assert z.shape == (1000,)
            assert np.all(z > 0)
            assert rel_err(z, u) < 1e-9, (gen, keep)


@pytest.mark.parametrize("name", ["octopod", "octo"])
def test_hull_equals_zonotope_on_preset_poses(presets, name):
    """L = 8: the paper's polytope algorithm (Qhull) on 25 poses per preset (the 1000-pose
    run is the slow test below), every slice, worst and best case."""
    _hull_vs_zonotope(presets[name], 25, seed=2)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["octopod", "octo"])
def test_hull_equals_zonotope_on_1000_poses(presets, name):
    """Acceptance: L = 8, 1000 random poses (about 3 minutes per preset)."""
    _hull_vs_zonotope(presets[name], 1000, seed=3)


def _hull_vs_zonotope(mech, n, seed):
    poses = random_reachable_poses(mech, n, 30, seed=seed)
    G = _generators(mech, poses)["wrench"]
    lim = ACTUATORS["nominal_torque"]
    lo, hi = np.full(8, -lim), np.full(8, lim)
    ref = np.array([[w for w, _ in hull_multi(g, lo, hi, [range(6), (0, 1, 2), (3, 4, 5)])]
                    for g in G])
    for k, keep in enumerate(SLICES):
        z = worst_case_output(G, -lim, lim, keep)
        assert rel_err(z, ref[:, k]) < 1e-9, keep
    bz = best_case_output(G[:10], -lim, lim, [0, 1, 2])
    bh = best_case_output(G[:10], -lim, lim, [0, 1, 2], method="hull")
    assert rel_err(bz, bh) < 1e-9


def test_random_generators_all_methods_and_asymmetric_limits():
    rng = np.random.default_rng(0)
    keeps = SLICES + ([0],)
    for L in (6, 7, 8):
        G = rng.normal(size=(6, 6, L))
        lo, hi = rng.uniform(-3, -0.1, L), rng.uniform(0.1, 3, L)
        ref = np.array([hull_multi(g, lo, hi, [range(6) if k is None else k for k in keeps])
                        for g in G])                          # (6, keeps, 2)
        for k, keep in enumerate(keeps):
            assert rel_err(worst_case_output(G, lo, hi, keep), ref[:, k, 0]) < 1e-9
            assert rel_err(best_case_output(G, lo, hi, keep), ref[:, k, 1]) < 1e-9
            if L == 6:
                u = worst_case_output(G, lo, hi, keep, method="ueberle")
                assert rel_err(u, ref[:, k, 0]) < 1e-9


def test_analytic_box():
    """G = I: the set is the box itself; the worst case is the nearest face, the best the
    farthest corner; slices are sub-boxes."""
    lo, hi = np.array([-1.0, -2, -3]), np.array([4.0, 5, 0.5])
    assert worst_case_output(np.eye(3), lo, hi) == pytest.approx(0.5, rel=1e-15)
    assert worst_case_output(np.eye(3), lo, hi, [0, 1]) == pytest.approx(1.0, rel=1e-15)
    assert best_case_output(np.eye(3), lo, hi) == pytest.approx(np.sqrt(16 + 25 + 9))
    assert best_case_output(np.eye(3), lo, hi, [0, 1]) == pytest.approx(np.sqrt(41))


def test_facet_count_matches_qhull():
    """docs/design.md §6: 2·C(8, 5) = 112 facet hyperplanes for L = 8, d = 6."""
    from scipy.spatial import ConvexHull

    from distkin.indices.capability import _box_vertices
    from distkin.indices.zonotope import facet_normals
    G = np.random.default_rng(5).normal(size=(6, 8))
    n, P, regular = facet_normals(G[None])
    assert n.shape == (1, 56, 6) and regular[0]
    assert np.allclose(P[0], n[0] @ G)
    hull = ConvexHull(_box_vertices(-np.ones(8), np.ones(8)) @ G.T)
    planes = np.unique(np.round(hull.equations, 9), axis=0)
    assert len(planes) == 112
    unit = n[0] / np.linalg.norm(n[0], axis=1)[:, None]
    both = np.vstack([unit, -unit])
    for eq in planes:                       # every Qhull facet is one of ours
        assert np.min(np.linalg.norm(both - eq[:6], axis=1)) < 1e-9


@pytest.mark.parametrize("L", [6, 8])
def test_near_singularity_all_methods_go_to_zero_together(L):
    rng = np.random.default_rng(1)
    U, _ = np.linalg.qr(rng.normal(size=(6, 6)))
    V, _ = np.linalg.qr(rng.normal(size=(L, L)))
    prev = None
    for t in (1e-2, 1e-4, 1e-6, 1e-8):
        S = np.zeros((6, L))
        np.fill_diagonal(S, [3, 2, 1.5, 1, 0.7, t])
        G = U @ S @ V.T
        for keep in SLICES:
            z = worst_case_output(G, -1, 1, keep)
            h = worst_case_output(G, -1, 1, keep, method="hull")
            assert z == pytest.approx(h, rel=1e-6)
            if L == 6:
                # below UEBERLE_KAPPA it hands the pose to the zonotope kernel, saying so
                with warnings.catch_warnings(record=True) as rec:
                    warnings.simplefilter("always", ConditioningWarning)
                    u = worst_case_output(G, -1, 1, keep, method="ueberle")
                assert bool(rec) == (t / 3 <= UEBERLE_KAPPA), (t, rec)
                assert z == pytest.approx(u, rel=1e-6)
            assert z < 10 * t                 # proportional to the vanishing singular value
        whole = worst_case_output(G, -1, 1)
        if prev is not None:
            assert whole == pytest.approx(prev / 100, rel=1e-3)
        prev = whole
    S = np.zeros((6, L))
    np.fill_diagonal(S, [3, 2, 1.5, 1, 0.7, 0.0])
    G = U @ S @ V.T
    assert worst_case_output(G, -1, 1) == 0.0
    assert worst_case_output(G, -1, 1, [0, 1, 2]) == 0.0
    with pytest.raises(SingularConfigurationError, match="zonotope"):
        worst_case_output(G, -1, 1, method="hull")


def test_origin_outside_gives_a_negative_flag_in_every_method():
    rng = np.random.default_rng(2)
    G = rng.normal(size=(10, 6, 6))
    lo = rng.uniform(0.1, 1, 6)
    hi = lo + 1
    z = worst_case_output(G, lo, hi)
    assert np.all(z < 0)
    assert rel_err(z, worst_case_output(G, lo, hi, method="hull")) < 1e-9
    assert rel_err(z, worst_case_output(G, lo, hi, method="ueberle")) < 1e-9


def test_pure_torque_null_wrench_gives_the_finite_force_slice():
    """At an exact singularity whose null wrench is a pure torque the plain formula gives
    ∞ for the force slice; the flat route returns the true inradius, checked against the
    slice polytope's vertices found by linear programs and its Qhull hull."""
    from scipy.optimize import linprog
    from scipy.spatial import ConvexHull
    rng = np.random.default_rng(3)
    w = np.r_[0, 0, 0, rng.normal(size=3)]
    w /= np.linalg.norm(w)
    G0 = rng.normal(size=(6, 8))
    G = G0 - np.outer(w, w @ G0)
    f = worst_case_output(G, -1, 1, [0, 1, 2])
    assert np.isfinite(f) and f > 0
    assert worst_case_output(G, -1, 1, [3, 4, 5]) == 0.0   # this slice leaves the span
    # the slice polytope {f : (f, 0) = G p, |p| <= 1} by the iterative hull method: LPs
    # in the normal direction of every facet until no facet can be pushed out (exact)
    A_eq = np.vstack([np.hstack([G[3:], np.zeros((3, 3))]),
                      np.hstack([G[:3], -np.eye(3)])])

    def extreme(d):
        res = linprog(np.r_[np.zeros(8), -d], A_eq=A_eq, b_eq=np.zeros(6),
                      bounds=[(-1, 1)] * 8 + [(None, None)] * 3, method="highs")
        return res.x[8:]
    verts = [extreme(d) for d in np.vstack([np.eye(3), -np.eye(3), rng.normal(size=(20, 3))])]
    for _ in range(50):
        hull = ConvexHull(np.array(verts))
        new = [v for eq in hull.equations
               for v in [extreme(eq[:3])] if eq[:3] @ v + eq[3] > 1e-9]
        if not new:
            break
        verts += new
    assert not new
    assert f == pytest.approx(np.min(-hull.equations[:, -1]), rel=1e-9)


def test_acceleration_slice_is_the_force_slice_scaled(presets):
    """With M̂ = diag(m, m, m, I, I, I) the zero-angular-acceleration slice of M̂⁻¹Jᵀτ
    is the zero-torque force slice divided by m (stall instead of nominal torque).  The
    paper's Table III obeys the same relation: 21.68 N · 34.2/2.5 / 0.17 kg = 1744.6 m/s²
    against the printed 1744.46 m/s² (Octopod)."""
    assert 21.68 * 34.2 / 2.5 / 0.17 == pytest.approx(1744.46, rel=2e-4)
    mech = presets["octopod"]
    poses = random_reachable_poses(mech, 50, 30, seed=4)
    g = _generators(mech, poses)
    f = worst_case_output(g["wrench"], -2.5, 2.5, [0, 1, 2])
    a = worst_case_output(g["acceleration"], -34.2, 34.2, [0, 1, 2])
    assert rel_err(a, f * 34.2 / 2.5 / mech.mass) < 1e-12


def test_bad_input_is_reported_with_field():
    G = np.ones((6, 8))
    with pytest.raises(InputError, match="L = d"):
        worst_case_output(G, -1, 1, method="ueberle")
    with pytest.raises(InputError, match="method"):
        worst_case_output(G, -1, 1, method="lp")
    with pytest.raises(InputError, match="pmin <= pmax"):
        worst_case_output(G, 1, -1)
    with pytest.raises(InputError, match="distinct indices"):
        worst_case_output(G, -1, 1, keep=[0, 0])
    with pytest.raises(InputError, match="distinct indices"):
        worst_case_output(G, -1, 1, keep=[6])
    with pytest.raises(InputError, match=r"L >= d"):
        worst_case_output(np.ones((6, 3)), -1, 1)
    with pytest.raises(InputError, match="shape"):
        worst_case_output(G, np.ones(3), 1)
    with pytest.raises(InputError, match="finite"):
        worst_case_output(np.full((6, 6), np.nan), -1, 1)
    with pytest.raises(InputError, match="method"):
        best_case_output(G, -1, 1, method="ueberle")


def test_sensitivities_are_box_vertex_maxima(presets):
    """Cardou's sensitivities (projection) equal a brute-force maximum over all 2^L
    actuator sign vectors; the paper's slice (the default) is bounded by the projection."""
    from itertools import product

    from distkin.indices.sensitivity import max_sensitivities
    mech = presets["hunt"]
    poses = random_reachable_poses(mech, 20, 20, seed=6)
    J = mech.jacobian(poses)
    s = max_sensitivities(J, mode="projection")
    sl = max_sensitivities(J)
    signs = np.array(list(product((-1.0, 1.0), repeat=6))).T
    Jp = np.linalg.pinv(J)
    ref = np.linalg.norm((Jp[:, :3, :] @ signs), axis=1).max(axis=1)
    assert rel_err(s["translational"], ref) < 1e-12
    ref = np.linalg.norm((np.swapaxes(J, 1, 2)[:, 3:, :] @ signs), axis=1).max(axis=1)
    assert rel_err(s["torque"], ref) < 1e-12
    for k in s:
        assert np.all(sl[k] <= s[k] * (1 + 1e-12))


@pytest.mark.parametrize("name", ["hunt", "octopod", "octo"])
def test_slice_sensitivities_against_the_hull_route(presets, name):
    """The paper's sensitivities (eq. (14) slice, eq. (16) farthest point; compiled vertex
    enumeration of distkin.indices.slice_farthest) against the paper's polytope
    algorithm as written: Qhull hull of all 2^L vertices, half-space intersection with
    the slice, farthest vertex (capability.hull_worst_best), with unit limits."""
    from distkin.indices.capability import hull_multi
    from distkin.indices.sensitivity import max_sensitivities
    mech = presets[name]
    poses = random_reachable_poses(mech, 6, 30 if mech.L == 8 else 20, seed=12)
    J = mech.jacobian(poses)
    sl = max_sensitivities(J)
    Jp = np.linalg.pinv(J)
    one = np.ones(mech.L)
    for i in range(len(poses)):
        (_, t), (_, r) = hull_multi(Jp[i], -one, one, [(0, 1, 2), (3, 4, 5)])
        (_, f), (_, m) = hull_multi(J[i].T, -one, one, [(0, 1, 2), (3, 4, 5)])
        assert sl["translational"][i] == pytest.approx(t, rel=1e-10)
        assert sl["rotational"][i] == pytest.approx(r, rel=1e-10)
        assert sl["force"][i] == pytest.approx(f, rel=1e-10)
        assert sl["torque"][i] == pytest.approx(m, rel=1e-10)


def test_preset_approaching_a_singularity(presets):
    """The ergin preset has direct singularities inside its ±20° workspace (as the paper's
    Ergin device, Sec. III-B.1, Table III's 0.00 N; the tangential reading of Fig. 2,
    presets.py): bisect a segment between two poses whose det J differs in sign; along
    the way Ueberle's method and the kernel agree and both go to 0 with σmin."""
    mech = presets["ergin"]
    P = random_reachable_poses(mech, 3000, 20, seed=11)  # ±20°
    det = np.linalg.det(mech.jacobian(P))
    i = int(np.flatnonzero(det > 0)[0])
    j = next(k for k in np.flatnonzero(det < 0)
             if mech.reachable(np.linspace(P[i], P[k], 50)).all())
    a, b = P[i], P[j]
    vals = []
    for _ in range(45):
        m = (a + b) / 2
        Jm = mech.jacobian(m[None])
        if np.linalg.det(Jm[0]) > 0:
            a = m
        else:
            b = m
        G = np.swapaxes(Jm, 1, 2)
        z = worst_case_output(G, -2.5, 2.5)[0]
        with warnings.catch_warnings(record=True) as rec:
            warnings.simplefilter("always")
            u = worst_case_output(G, -2.5, 2.5, method="ueberle")[0]
        sv = np.linalg.svd(G[0], compute_uv=False)
        smin = sv[-1]
        # QA Z2: Ueberle's method hands (nearly) singular poses to the kernel, saying so
        assert all(issubclass(w.category, ConditioningWarning) for w in rec), rec
        # (below UEBERLE_KAPPA = 1e-6, where its least squares lose accuracy; QA 24)
        assert bool(rec) == (smin / sv[0] <= UEBERLE_KAPPA), (smin / sv[0], rec)
        vals.append((smin, z, u))
        if smin > 1e-9:
            assert z == pytest.approx(u, rel=1e-6)
        assert abs(z - u) <= 1e-9 + 1e-6 * u
    smin, z, u = vals[-1]
    assert smin < 1e-10 and z < 1e-9 and u < 1e-9
    first = vals[0]
    assert z < first[1] * 1e-6


@pytest.mark.parametrize("name", ["octopod", "octo", "hunt"])
def test_true_velocity_set_against_linear_programming(presets, name):
    """The true velocity set {ẋ : |J ẋ|∞ <= q̇max} (velocity_set), sliced at zero angular
    (resp. translational) velocity: its worst case min_i q̇max/||J_i,S|| against
    scipy.optimize.linprog.  The LP computes the support h(n) of the slice for every
    slab normal n = J_i,S and for 200 random directions; the inradius about the origin
    is min h(n)/||n|| over the facet normals, and no random direction reaches a boundary
    point closer than it.  For L = 6 it equals the J# zonotope of eq. (5); for L = 8 the
    zonotope contains it (J# overstates)."""
    from scipy.optimize import linprog

    from distkin.indices.velocity_set import true_velocity_worst
    mech = presets[name]
    qmax = 51.0
    rng = np.random.default_rng(3)
    poses = random_reachable_poses(mech, 3, 30 if mech.L == 8 else 20, seed=14)
    J = mech.jacobian(poses)
    for keep in ((0, 1, 2), (3, 4, 5)):
        w = true_velocity_worst(J, qmax, keep)
        zon = worst_case_output(np.linalg.pinv(J), -qmax, qmax, keep=keep)
        for i in range(len(poses)):
            A = J[i][:, list(keep)]
            A_ub, b_ub = np.vstack([A, -A]), np.full(2 * mech.L, qmax)

            def support(n):
                res = linprog(-n, A_ub=A_ub, b_ub=b_ub, bounds=[(None, None)] * 3,
                              method="highs")
                assert res.success
                return -res.fun
            h = min(support(n) / np.linalg.norm(n) for n in A)
            assert w[i] == pytest.approx(h, rel=1e-9)
            for d in rng.normal(size=(200, 3)):
                d /= np.linalg.norm(d)
                # the boundary point along d lies at t = min_i qmax / |J_i,S d|
                t = qmax / np.abs(A @ d).max()
                assert t >= w[i] * (1 - 1e-12)
            if mech.L == 6:
                assert zon[i] == pytest.approx(w[i], rel=1e-9)
            else:
                assert zon[i] >= w[i] * (1 - 1e-12)
