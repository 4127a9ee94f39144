"""Singularities: eq. (5), the Cayley-Menger pure condition, the four planes, det(AJ).

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*, Sec. IV.  Independent
routes: finite differences of leg lengths (eq. (5)), exact rational arithmetic for the
polynomial identities, arb balls for the signs, coordinates for the 6-6 platform.
"""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from distkin.delta import equivalent_platform
from distkin.errors import ConditioningWarning, UncertifiedError
from distkin.singularity import (RATIO_CONSTANT, PosePath, certified_sign, certify_crossing,
                                 cm_pure_condition, four_planes, jacobian_det,
                                 nearest_singularity, octahedral_joints, path_crossings,
                                 plucker_jacobian, pose_points, rotation_from_vector,
                                 signed_cm_condition, volume_factors)

GD = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
BASE = np.array([[0, 0, 0], [6, np.sqrt(108), 0], [12, 0, 0]])
PLAT = np.array([[0, 0, 0], [6, 0, 0], [3, np.sqrt(27), 0]])
RNG = np.random.default_rng(20261121)


def _random_poses(n, spread=0.6):
    """Platform above the base, flipped (the octahedral assembly), random tilt and twist."""
    flip = rotation_from_vector(np.array([np.pi, 0, 0]))
    R = rotation_from_vector(RNG.normal(size=(n, 3)) * spread) @ flip
    t = np.array([3, 5.196, 10]) + RNG.normal(size=(n, 3)) * [2, 2, 3]
    P = pose_points(PLAT, R, t)
    return np.concatenate([np.broadcast_to(BASE, P.shape), P], axis=-2), R, t


def test_eq5_against_finite_differences_of_leg_lengths():
    X, R, t = _random_poses(5)
    h = 1e-6
    for k in range(5):
        bj, pj = octahedral_joints(X[k])
        J = plucker_jacobian(bj, pj)                       # normalised: ldot = J (v, w)
        tw = RNG.normal(size=6)                            # v of the point at the origin, w

        def legs(e):
            # every platform point moves as p -> exp(w e) p + v e
            Rw = rotation_from_vector(tw[3:] * e)
            P = pose_points(PLAT, Rw @ R[k], Rw @ t[k] + tw[:3] * e)
            b2, p2 = octahedral_joints(np.concatenate([BASE, P]))
            return np.linalg.norm(p2 - b2, axis=1)
        fd = (legs(h) - legs(-h)) / (2 * h)
        np.testing.assert_allclose(J @ tw, fd, rtol=1e-7, atol=1e-7)
        # the unnormalised matrix is diag(l) J (eq. (5) as printed)
        Jh = plucker_jacobian(bj, pj, normalised=False)
        lens = np.linalg.norm(pj - bj, axis=1)
        np.testing.assert_allclose(Jh, lens[:, None] * J, rtol=1e-13)
        # the reference point changes J by a unimodular map: det unchanged
        Jc = plucker_jacobian(bj, pj, reference=np.array([1.0, -2.0, 3.0]))
        assert np.linalg.det(Jc) == pytest.approx(np.linalg.det(J), rel=1e-10)


def test_identities_exact_on_random_rational_configurations():
    for _ in range(6):
        X = np.vectorize(lambda v: Fraction(int(v), 37), otypes=[object])(
            RNG.integers(-400, 400, size=(6, 3)))
        dj = jacobian_det(*octahedral_joints(X), normalised=False)
        a, b = volume_factors(X)
        assert dj != 0
        assert dj == -216 * (a + b)
        assert four_planes(X).det == dj
        assert cm_pure_condition(X) == -RATIO_CONSTANT * (a - b) * dj
        assert signed_cm_condition(X) == -RATIO_CONSTANT * a * dj


def test_sign_and_zero_set_on_random_poses():
    X, _, _ = _random_poses(4000, spread=0.9)
    dj = jacobian_det(*octahedral_joints(X), normalised=False)
    a, b = volume_factors(X)
    K = signed_cm_condition(X)
    C = cm_pure_condition(X)
    ok = np.abs(a) > 1e-6 * np.max(np.abs(a))               # non-degenerate tetrahedra
    # the signed CM form: ratio K / det J = -110592 a, whose sign is that of -a
    ratio = K / dj
    np.testing.assert_allclose(ratio[ok] / (-RATIO_CONSTANT * a[ok]), 1.0, rtol=1e-6)
    assert np.all(np.sign(K[ok]) == -np.sign(a[ok]) * np.sign(dj[ok]))
    # the paper's form: ratio -110592 (a - b), which changes sign on these poses
    np.testing.assert_allclose((C / dj)[ok] / (-RATIO_CONSTANT * (a - b)[ok]), 1.0, rtol=1e-6)
    assert np.any(a - b > 0) and np.any(a - b < 0)


def test_paper_cm_form_vanishes_at_the_regular_home_pose():
    # exact: the symmetric home pose (P4 above the midpoint of P1P2), sympy arithmetic
    s3 = sp.sqrt(3)
    X = np.array([[0, 0, 0], [6, 6 * s3, 0], [12, 0, 0], [3, 3 * s3, 10], [9, 3 * s3, 10],
                  [6, 0, 10]], dtype=object)
    X = np.vectorize(sp.sympify, otypes=[object])(X)
    assert sp.simplify(cm_pure_condition(X)) == 0
    J = sp.zeros(6, 6)                     # det J by hand, independently of plucker_jacobian
    for k, (q, p) in enumerate(((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))):
        u = sp.Matrix(X[p - 1] - X[q - 1])
        J[k, :3] = u.T
        J[k, 3:] = sp.Matrix(X[q - 1]).cross(u).T
    dj = sp.simplify(J.det())
    assert dj == -279936000 * s3          # not zero: a regular pose
    assert sp.simplify(jacobian_det(*octahedral_joints(X), normalised=False) - dj) == 0
    assert sp.simplify(signed_cm_condition(X)) != 0


def _twist_path():
    """Flipped platform at height 10, rotation vectors of twist 60 and 120 deg."""
    return PosePath((3, sp.sqrt(3), 10), (90 * sp.sqrt(3), 90, 0),
                    (6, 0, 10), (90, 90 * sp.sqrt(3), 0), deg=True)


def _world(R, t):
    P = pose_points(PLAT, R, t)
    return np.concatenate([np.broadcast_to(BASE, P.shape), P], axis=-2)


def test_root_finding_along_a_path_all_tests_fire_and_arb_certifies():
    path = _twist_path()
    f = lambda s: jacobian_det(*octahedral_joints(_world(*path.at(s))), length_scale=6.0,  # noqa: E731
                                warn=False)
    roots, _, _ = path_crossings(f, 40)
    assert len(roots) == 1
    s = roots[0]
    X = _world(*path.at(np.array([s])))
    # all three characterisations fire at the root
    assert abs(f(np.array([s]))[0]) < 1e-12
    assert abs(cm_pure_condition(X, relative=True)[0]) < 1e-12
    with pytest.warns(ConditioningWarning, match="four-planes det F"):   # sign unresolved
        fp = four_planes(X, length_scale=6.0)
    assert abs(fp.relative[0]) < 1e-12 and fp.spread[0] < 1e-9
    assert fp.det_error[0] >= abs(fp.det[0])
    # the other tests, root-found independently, give the same s
    g = lambda s: cm_pure_condition(_world(*path.at(s)), relative=True)  # noqa: E731
    h = lambda s: four_planes(_world(*path.at(s)), warn=False).relative  # noqa: E731
    assert min(abs(r - s) for r in path_crossings(g, 40)[0]) < 1e-10
    assert min(abs(r - s) for r in path_crossings(h, 40)[0]) < 1e-10
    # arb: signs of det J on both sides of the root, on the exact path (pi, sqrt(3) as balls)
    import flint
    Ba = np.array([[flint.arb(0)] * 3, [flint.arb(6), flint.arb(108).sqrt(), flint.arb(0)],
                   [flint.arb(12), flint.arb(0), flint.arb(0)]], dtype=object)
    Pa = np.array([[flint.arb(0)] * 3, [flint.arb(6), flint.arb(0), flint.arb(0)],
                   [flint.arb(3), flint.arb(27).sqrt(), flint.arb(0)]], dtype=object)

    def f_arb(q):
        Rq, tq = path.at_certified(q)
        Xq = np.concatenate([Ba, pose_points(Pa, Rq, tq)])
        return jacobian_det(*octahedral_joints(Xq), normalised=False, method="certified")
    c = certify_crossing(f_arb, s)
    assert c.signs[0] == -c.signs[1]
    assert c.bracket[0] < s < c.bracket[1] and float(c.bracket[1] - c.bracket[0]) < 1e-6
    # the float sign agrees with the certified one on each side
    for q, sg in zip(c.bracket, c.signs):
        assert np.sign(f(np.array([float(q)]))[0]) == sg


def test_certified_sign_refuses_an_undecided_ball():
    import flint
    with pytest.raises(UncertifiedError):
        certified_sign(flint.arb(0, 1e-10))
    assert certified_sign(flint.fmpq(-1, 3)) == -1
    # an exactly singular pose evaluated in arb: the flipped platform twisted by 90 deg
    # about the vertical through the base centroid (irrational coordinates)
    s3 = sp.sqrt(3)
    path = PosePath((6 - s3, 2 * s3 - 3, 10), (90 * sp.sqrt(2), 90 * sp.sqrt(2), 0),
                    (6 - s3, 2 * s3 - 3, 10), (90 * sp.sqrt(2), 90 * sp.sqrt(2), 0), deg=True)
    Rf, tf = path.at(np.array([0.0]))
    assert abs(jacobian_det(*octahedral_joints(_world(Rf, tf)), length_scale=6.0,
                            warn=False)[0]) < 1e-13
    Rq, tq = path.at_certified(flint.fmpq(0))
    Ba = np.array([[flint.arb(0)] * 3, [flint.arb(6), flint.arb(108).sqrt(), flint.arb(0)],
                   [flint.arb(12), flint.arb(0), flint.arb(0)]], dtype=object)
    Pa = np.array([[flint.arb(0)] * 3, [flint.arb(6), flint.arb(0), flint.arb(0)],
                   [flint.arb(3), flint.arb(27).sqrt(), flint.arb(0)]], dtype=object)
    Xq = np.concatenate([Ba, pose_points(Pa, Rq, tq)])
    d = jacobian_det(*octahedral_joints(Xq), normalised=False, method="certified")
    assert d.contains(0)
    with pytest.raises(UncertifiedError):
        certified_sign(d)


def test_det_AJ_equals_det_A_det_J_on_the_built_platform():
    plat = equivalent_platform(GD, ["12/5", "6/5"] * 3)
    A = np.array(plat.transform.A.tolist(), dtype=float)
    detA = float(plat.transform.det)
    bj, qj = plat.joints("fast")
    X, R, t = _random_poses(50, spread=1.2)
    pj = pose_points(qj, R, t)
    J66 = plucker_jacobian(np.broadcast_to(bj, pj.shape), pj, normalised=False)
    Jo = plucker_jacobian(*octahedral_joints(X), normalised=False)
    # matrix identity Jhat66 = A Jhat (differentiate m^2 = A l^2 - b) ...
    np.testing.assert_allclose(J66, A @ Jo, rtol=1e-12, atol=1e-10)
    # ... hence the determinants
    np.testing.assert_allclose(np.linalg.det(J66), detA * np.linalg.det(Jo), rtol=1e-10)


def test_nearest_singularity_is_on_the_singular_surface_and_not_farther_than_the_path():
    path = _twist_path()
    L = 6 / np.sqrt(3)
    f = lambda R, t: jacobian_det(*octahedral_joints(_world(R, t)), length_scale=L,  # noqa: E731
                                  warn=False)
    R0, t0 = path.at(np.array([0.25]))
    ns = nearest_singularity(f, R0[0], t0[0], L)
    assert ns.converged and ns.residual < 1e-9
    assert abs(f(ns.rotation[None], ns.translation[None])[0]) < 1e-9
    # the crossing along the path is one singular pose: the nearest one is not farther
    s = path_crossings(lambda s: f(*path.at(s)), 40)[0][0]
    R1, t1 = path.at(np.array([s]))
    dR = R1[0] @ R0[0].T
    ang = np.arccos(np.clip((np.trace(dR) - 1) / 2, -1, 1))
    along = np.hypot(np.linalg.norm(t1[0] - t0[0]), L * ang)
    assert ns.distance <= along + 1e-9
    assert ns.first_order > 0


# near a flat tetrahedron the relative forms are 0/0 and say so (a CancellationWarning per
# sample, ~450 here: QA V 2, tested in test_cm_accuracy.py); this test counts zero sets
@pytest.mark.filterwarnings("ignore::distkin.geometry.cm_float.CancellationWarning")
def test_zero_sets_agree_along_random_paths():
    # every root of det J is a root of both CM forms and of the four-planes test; every
    # other root of the signed form is a root of its factor a (a flat tetrahedron)
    rng = np.random.default_rng(11)
    found = 0
    for _ in range(8):
        w0, w1 = rng.normal(size=3) * 1.5, rng.normal(size=3) * 1.5
        t0 = np.array([3, 5.196, 10]) + rng.normal(size=3) * 2
        t1 = np.array([3, 5.196, 10]) + rng.normal(size=3) * 2
        path = PosePath(tuple(t0), tuple(w0), tuple(t1), tuple(w1))
        X = lambda s: _world(*path.at(s))  # noqa: E731
        r_det = path_crossings(lambda s: jacobian_det(*octahedral_joints(X(s)), warn=False), 60)[0]
        r_k = path_crossings(lambda s: signed_cm_condition(X(s), relative=True), 60)[0]
        r_fp = path_crossings(lambda s: four_planes(X(s), warn=False).relative, 60)[0]
        r_a = path_crossings(lambda s: volume_factors(X(s))[0], 60)[0]
        near = lambda r, rs: min((abs(r - x) for x in rs), default=1.0)  # noqa: E731
        for r in r_det:
            # the tests fire at r (a sign change of K may be masked when a vanishes in
            # the same grid cell: K = -110592 a det Jhat then only touches zero)
            Xr = X(np.array([r]))
            assert abs(signed_cm_condition(Xr, relative=True)[0]) < 1e-9
            assert abs(cm_pure_condition(Xr, relative=True)[0]) < 1e-9
            assert near(r, r_fp) < 1e-9
        for r in r_k:
            assert near(r, r_det) < 1e-9 or near(r, r_a) < 1e-9
        found += len(r_det)
    assert found >= 3
