"""Stability at the extremes (issue 8): the same device at mm, m and km scale.

The extreme: every length of a device multiplied by k = 1e-3 or 1e3 (angles, actuator
limits, mass and inertia unchanged).  Dimensional analysis fixes how each result
scales, with no reference output of our own code:

* angles (crank angles, rotations): k⁰; positions and translations: k¹;
* the Jacobian q̇ = J·(v, ω): the columns of v scale as k⁻¹, those of ω as k⁰;
* with the same actuator torques, force ∝ k⁻¹ and torque ∝ k⁰; with the same actuator
  rates, velocity ∝ k¹ and angular velocity ∝ k⁰; with the same mass, acceleration
  ∝ k⁻¹ and angular acceleration ∝ k⁰; Cardou's sensitivities: translational (m/rad)
  ∝ k¹, force (N/(N·m)) ∝ k⁻¹, rotational and torque ∝ k⁰;
* the scaled singular values of W = ST⁻¹Jᵀ are invariant when the intended forces of
  ST scale with the forces (ST = diag(15/k N ×3, 1 N·m ×3));
* the octahedral octic's unknown s15 is a squared length: its roots scale as k².
"""

from fractions import Fraction

import numpy as np
import pytest

SCALES = (1e-3, 1e3)
#: length exponent of every per-pose quantity of the study (module docstring)
EXPONENTS = {"force": -1, "torque": 0, "velocity": 1, "angular_velocity": 0,
             "acceleration": -1, "angular_acceleration": 0, "sens_translational": 1,
             "sens_rotational": 0, "sens_force": -1, "sens_torque": 0,
             "sigma_min": 0, "sigma_max": 0}
_LENGTHS = ("l0", "l1", "l3", "lp", "ld", "z0")    # the octopod's non-zero lengths


@pytest.fixture(scope="module")
def octopod_poses():
    from distkin.mechanisms import preset
    mech = preset("octopod")
    rng = np.random.default_rng(8)
    poses = np.c_[rng.uniform(-0.075, 0.075, (64, 3)) + [0, 0, mech.z0],
                  np.deg2rad(rng.uniform(-20, 20, (64, 3)))]     # Table II box, ±20°
    assert mech.reachable(poses).all()
    return mech, poses


def _scaled(mech, k):
    import warnings

    from distkin.mechanisms import GeometryWarning, preset
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", GeometryWarning)
        out = preset("octopod", **{n: getattr(mech, n) * k for n in _LENGTHS})
    # scaled on purpose: at k = 1e-3 or 1e3 every length is 1000x off the preset's, what
    # the unit-slip rule (100x either way) warns about
    assert all("x the preset's" in str(w.message) for w in caught)
    assert bool(caught) is (not 1e-2 <= k <= 1e2)
    return out


@pytest.mark.parametrize("k", SCALES)
def test_octopod_kinematics_scale_exactly(octopod_poses, k):
    """Extreme: the Octopod with every length ×k (k = 1e-3, 1e3), its own generated
    kernels, at the same poses scaled (positions ×k, rotations unchanged).

    Expected: (l3 = LEG_LENGTH - l2 is a device constant, so it is scaled explicitly)
    crank angles identical
    (abs 1e-13 rad); the v-columns of J scale as 1/k and the ω-columns are unchanged
    (relative 1e-13 of the largest entry).  float64 scaling by a non-power of two
    costs a few ulps, so 1e-13 leaves a margin of about 100.
    """
    mech, poses = octopod_poses
    ms = _scaled(mech, k)
    assert ms.l3 == pytest.approx(mech.l3 * k, rel=1e-14)
    ps = poses.copy()
    ps[:, :3] *= k
    q, ok = mech.inverse_kinematics(poses)
    qs, oks = ms.inverse_kinematics(ps)
    assert oks.all() and ok.all()
    np.testing.assert_allclose(qs, q, rtol=0, atol=1e-13)
    J, Js = mech.jacobian(poses), ms.jacobian(ps)
    np.testing.assert_allclose(Js[..., :3] * k, J[..., :3], rtol=0,
                               atol=1e-13 * np.abs(J[..., :3]).max())
    np.testing.assert_allclose(Js[..., 3:], J[..., 3:], rtol=0,
                               atol=1e-13 * np.abs(J[..., 3:]).max())


@pytest.mark.parametrize("k", SCALES)
def test_octopod_capabilities_scale_as_dimensional_analysis_says(octopod_poses, k):
    """Extreme: as above; every index of the study (:func:`evaluate_poses`: six
    worst-case capabilities, four maximum sensitivities, scaled σmin/σmax).

    Expected: value(k) = k^e · value(1) with the exponent e of the module docstring,
    relative tolerance 1e-12 for the capabilities and singular values (zonotope facet
    ratios, a handful of roundings each) and 1e-11 for the four sensitivities (their
    vertex enumeration solves small systems and the twist map is a pseudo-inverse,
    so κ·eps-sized differences appear).
    """
    from distkin.indices.study import evaluate_poses
    mech, poses = octopod_poses
    ms = _scaled(mech, k)
    ps = poses.copy()
    ps[:, :3] *= k
    ok, v = evaluate_poses(mech, poses)
    oks, vs = evaluate_poses(ms, ps, ST=(15 / k,) * 3 + (1.0,) * 3)
    assert ok.all() and oks.all()
    for name, e in EXPONENTS.items():
        tol = 1e-11 if name.startswith("sens_") else 1e-12
        np.testing.assert_allclose(vs[name], v[name] * k ** e, rtol=tol, err_msg=name)


def _scene(unit, factor):
    """The Octopod with l0 = 160 mm and one IK pose, written in ``unit``."""
    def num(mm):
        return f'"{Fraction(mm) * factor}"'
    pose = ", ".join([num(40), num(-30), num(330), "15", "-10", "20"])
    return (f'[units]\nlength = "{unit}"\nangle = "deg"\n\n[mechanism]\nkind = "rss"\n'
            f'preset = "octopod"\nl0 = {num(160)}\n\n'
            f'[[query]]\ntype = "inverse_kinematics"\npose = [{pose}]\n')


def test_scene_units_mm_m_km_describe_the_same_device():
    """Extreme: one device written with lengths in mm, m and km (values like
    "0.00016" km), through the scene parser.

    Expected: the same SI mechanism (every length within 4e-16 relative: the exact
    decimal is rounded once to float and multiplied by the unit's factor) and the same
    query pose, and crank angles equal within 1e-14 rad.
    """
    from distkin.app.scene import loads_scene
    scenes = [loads_scene(_scene(u, f)) for u, f in
              (("mm", 1), ("m", Fraction(1, 1000)), ("km", Fraction(1, 10 ** 6)))]
    ref = scenes[0]
    for sc in scenes[1:]:
        for n in ("l0", "l1", "l3", "lp", "ld", "z0"):
            assert getattr(sc.mechanism, n) == pytest.approx(getattr(ref.mechanism, n),
                                                              rel=4e-16, abs=0), n
        np.testing.assert_allclose(sc.queries[0].params.poses, ref.queries[0].params.poses,
                                   rtol=4e-16, atol=0)
        X = np.array(ref.queries[0].params.poses)
        np.testing.assert_allclose(sc.mechanism.inverse_kinematics(X)[0],
                                   ref.mechanism.inverse_kinematics(X)[0], rtol=0, atol=1e-14)


# ------------------------------------------------------------------- octahedral
_GD_LEGS = ("19.8", "18", "18", "17", "14.9", "17.8")


def _gd(k: Fraction):
    """Griffis-Duffy example (Rojas et al., Sec. VI) with every length ×k, exact."""
    def s(x):
        return str(Fraction(x) * k)
    base = [[0, 0, 0], [s(6), f"sqrt(108)*{k}", 0], [s(12), 0, 0]]
    plat = [[0, 0, 0], [s(6), 0, 0], [s(3), f"sqrt(27)*{k}", 0]]
    return base, plat, [s(Fraction(x)) for x in _GD_LEGS]


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
@pytest.mark.parametrize("k", [Fraction(1, 1000), Fraction(1000)])
def test_octahedral_fast_tier_scales_within_its_own_error_estimate(k):
    """Extreme: the Griffis-Duffy example ×1e-3 and ×1e3, fast tier.

    Expected: the same six real roots, each scaled by k² within the sum of the two
    error estimates the tier reports (root ``radius``); the same twelve poses:
    rotations equal (abs 1e-11) and translations scaled by k (1e-11 relative to the
    platform's size; the tier reproduces legs to about 1e-12 relative).
    """
    from distkin.octahedral import forward_kinematics
    r1 = forward_kinematics(*_gd(Fraction(1)), method="fast")
    rk = forward_kinematics(*_gd(k), method="fast")
    kf = float(k)
    assert rk.real_root_count == r1.real_root_count == 6
    assert len(rk) == len(r1) == 12
    for a, b in zip(rk.roots, r1.roots):
        assert abs(a.value - kf ** 2 * b.value) <= a.radius + kf ** 2 * b.radius
    size = 20.0
    for p, p1 in zip(rk, r1):
        np.testing.assert_allclose(p.rotation, p1.rotation, rtol=0, atol=1e-11)
        np.testing.assert_allclose(p.translation / kf, p1.translation, rtol=0,
                                   atol=1e-11 * size)


@pytest.mark.parametrize("k", [Fraction(1, 1000), Fraction(1000)])
def test_octahedral_certified_tier_scales_exactly(k):
    """Extreme: as above, certified tier (exact octic, arb balls).

    Expected: the enclosure of every root at scale k and k² times the enclosure at
    scale 1 overlap (their difference contains 0: the same exact number, rigorously);
    the same for every coordinate of every pose translation (scaled by k); rotations
    equal within the balls' radii (checked by overlap as well).
    """
    import flint

    from distkin.octahedral import forward_kinematics
    r1 = forward_kinematics(*_gd(Fraction(1)), method="certified")
    rk = forward_kinematics(*_gd(k), method="certified")
    kq = flint.fmpq(k.numerator, k.denominator)
    assert rk.certified and r1.certified
    assert rk.real_root_count == r1.real_root_count == 6 and len(rk) == len(r1) == 12
    for a, b in zip(rk.roots, r1.roots):
        assert (a.native - b.native * kq * kq).contains(0)
    for p, p1 in zip(rk, r1):
        for x, y in zip(p.native["translation"], p1.native["translation"]):
            assert (x - y * kq).contains(0)
        for x, y in zip(np.ravel(p.native["rotation"]), np.ravel(p1.native["rotation"])):
            assert (x - y).contains(0)
