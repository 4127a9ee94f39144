"""Presets and parametrisation of the RSS mechanisms (Kühne et al., Sec. III, Table I)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from distkin.errors import ConditioningWarning, InputError
from distkin.mechanisms import PRESETS, RSSMechanism, preset

from rss_sampling import PRESET_NAMES


def test_paper_values():
    # Sec. III-B.2: l1 = 157 mm, l0 = 152 mm, lp = 55 mm, z0 = 0.30 m
    for name in ("hunt", "hexa", "ergin", "octopod"):
        m = preset(name)
        assert (m.l0, m.l1, m.lp, m.z0) == (0.152, 0.157, 0.055, 0.30)
    # Sec. III-D: the Octo
    o = preset("octo")
    assert o.L == 8 and o.l0 == 0.160 and o.l2 == pytest.approx(0.0256, abs=1e-15)
    assert o.beta == 0.0 and math.degrees(o.gamma) == pytest.approx(13.18, abs=1e-12)
    assert o.ld == 0.020
    # Table I optimum (Hunt-type): l2 = beta = gamma = 0, ld = 20 mm
    h = preset("hunt")
    assert (h.l2, h.beta, h.gamma, h.ld, h.L) == (0.0, 0.0, 0.0, 0.020, 6)
    assert preset("octopod").L == 8
    # Sec. III-B.3: the Cartesian mass matrix
    np.testing.assert_array_equal(o.cartesian_mass_matrix(),
                                  np.diag([0.17, 0.17, 0.17, 3e-4, 3e-4, 3e-4]))
    assert set(PRESETS) == set(PRESET_NAMES)


def test_leg_length_rule_analytic():
    # presets.py, "tangential" reading: l2 + l3 = LEG_LENGTH for every preset.  Hunt-type,
    # pair 0 (theta = 0), leg side s: pivot (l0, s ld/2, 0), axis along y, crank in the
    # plane y = s ld/2, tip (l0 + l1 cos q, s ld/2, l1 sin q); spherical joint at
    # (lp, s ld/2, z0) at the centre.  So l3^2 = (l0 + l1 cos q - lp)^2 + (z0 - l1 sin q)^2;
    # solved for q independently (bisection on the branch nearer 0).
    from scipy.optimize import brentq
    from distkin.mechanisms.rss import LEG_LENGTH
    for name in PRESETS:
        m = preset(name)
        assert m.l2 + m.l3 == pytest.approx(LEG_LENGTH, abs=1e-15)
    for name in ("hunt", "octopod"):
        m = preset(name)
        f = lambda q: (m.l0 + m.l1 * math.cos(q) - m.lp) ** 2 + (m.z0 - m.l1 * math.sin(q)) ** 2 \
            - m.l3 ** 2
        q0 = brentq(f, -math.pi / 4, math.pi / 2)
        q, valid = m.inverse_kinematics(m.home)
        assert valid.all()
        np.testing.assert_allclose(q, q0, rtol=0, atol=1e-13)
        # the crank elevation at the centre stated in presets.py's docstring (18.9°)
        assert math.degrees(q0) == pytest.approx(18.9, abs=0.05)


def test_leg_length_rule_is_the_centre_of_the_closing_interval():
    # LEG_LENGTH is the centre, rounded to 0.1 mm, of the intersection of the intervals
    # of l2 + l3 that close every leg of every preset over its study box (Table II
    # positions, +-20 deg for L = 6, +-30 deg for L = 8); recomputed here on a 25 mm /
    # 10 deg grid (the full 10 mm / 5 deg grid gives 349.66 mm: slow test below).
    from distkin.mechanisms.presets import leg_length_rule
    from distkin.mechanisms.rss import LEG_LENGTH
    r = leg_length_rule(step=0.025, rot_step_deg=10.0)
    lo, hi = r["interval"]
    assert lo < LEG_LENGTH < hi
    assert abs(r["K"] - LEG_LENGTH) < 1.5e-3


@pytest.mark.slow
def test_leg_length_rule_full_grid():
    from distkin.mechanisms.presets import leg_length_rule
    from distkin.mechanisms.rss import LEG_LENGTH
    r = leg_length_rule()
    assert round(r["K"], 4) == LEG_LENGTH


def test_reading_of_fig2():
    # presets.py: actuator axes of a pair on one tangential line (turned by s beta),
    # cranks horizontal at q = 0 and radially outwards, RRRS offset l2 along the axis away
    # from the pair's centre.
    m = preset("ergin")
    g = m.geometry()
    z = np.array([0.0, 0.0, 1.0])
    for i in range(m.L):
        th, s = g["theta"][i], g["side"][i]
        e = np.array([math.cos(th), math.sin(th), 0.0])
        t = np.array([-math.sin(th), math.cos(th), 0.0])
        a = math.cos(s * m.beta) * t + math.sin(s * m.beta) * np.cross(z, t)
        np.testing.assert_allclose(g["a"][i], a, atol=1e-15)
        np.testing.assert_allclose(g["u"][i], np.cross(a, z), atol=1e-15)
        assert np.dot(g["u"][i], e) > 0.9                  # radially outwards
        np.testing.assert_allclose(g["offset"][i], s * m.l2 * a, atol=1e-15)
        # the offset moves the universal joint away from the pair's other pivot
        mate = i + 1 if i % 2 == 0 else i - 1
        assert np.dot(g["offset"][i], g["B"][i] - g["B"][mate]) > 0
    # the pre-issue-15 reading stays available: radial axes, tangential cranks
    r = preset("ergin", layout="radial").geometry()
    np.testing.assert_allclose(r["u"], r["side"][:, None] * np.cross(z, r["a"]), atol=1e-15)


def test_table2_grid_reachable(any_preset):
    # Sec. II-A / Table II: every pose of the grid's corners and faces (the extreme
    # positions, +-75 mm about z0, with every +-20 deg orientation corner) closes.
    import itertools
    m = any_preset
    c = [-0.075, 0.0, 0.075]
    r = np.radians([-20.0, 0.0, 20.0])
    P = np.array([(x, y, m.z0 + zz, a, b, d) for x, y, zz in itertools.product(c, c, c)
                  for a, b, d in itertools.product(r, r, r)])
    assert m.reachable(P).all()


def test_home_cranks_symmetric(any_preset):
    # at the centre every crank has the same elevation (the legs are congruent), on the
    # branch nearer 0
    q, valid = any_preset.inverse_kinematics(any_preset.home)
    assert valid.all()
    assert np.ptp(q) < 1e-13 and 0 < q[0] < math.radians(45)


def test_overrides_recompute_l3():
    from distkin.mechanisms.rss import LEG_LENGTH
    m = preset("octopod", l2=0.010)
    assert m.name == "octopod*" and m.l3 == pytest.approx(LEG_LENGTH - 0.010, abs=1e-15)
    m2 = preset("octopod", l3=0.40)
    assert m2.l3 == 0.40
    # the radial reading keeps its horizontal-crank rule: q = 0 at the centre
    m3 = preset("octopod", layout="radial", l0=0.170)
    assert m3.l3 == pytest.approx(math.sqrt((0.170 - 0.055) ** 2 + 0.157 ** 2 + 0.3 ** 2))
    q3, _ = m3.inverse_kinematics(m3.home)
    assert np.abs(q3).max() < 1e-13


@pytest.mark.parametrize("kwargs, field", [
    ({"legs": 7}, "legs"), ({"l1": -0.1}, "l1"), ({"gamma": math.pi}, "beta"),
    ({"ld": float("nan")}, "ld"), ({"bogus": 1.0}, "preset"), ({"layout": "spiral"}, "layout"),
    ({"l2": 0.4}, "l2"),
])
def test_bad_parameters(kwargs, field):
    with pytest.raises(InputError) as info:
        preset("hexa", **kwargs)
    assert info.value.field == field
    assert "expected" in str(info.value)


def test_unknown_preset():
    with pytest.raises(InputError, match="expected a preset in"):
        preset("tripod")


def test_frozen():
    m = preset("octo")
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.l0 = 1.0
    assert isinstance(m, RSSMechanism)


def test_leg_lengths_at_ik(any_preset):
    """Independent numpy geometry (points) vs the generated IK: every link has its length."""
    from rss_sampling import reachable_poses
    m = any_preset
    P = reachable_poses(m, 200, seed=3)
    pts = m.points(P)
    assert np.abs(np.linalg.norm(pts["C"] - pts["B"], axis=-1) - m.l1).max() < 1e-15
    assert np.abs(np.linalg.norm(pts["D"] - pts["C"], axis=-1) - m.l2).max() < 1e-15
    assert np.abs(np.linalg.norm(pts["P"] - pts["D"], axis=-1) - m.l3).max() < 1e-14
    # the spherical joints lie on a circle of radius lp about the end-effector centre
    r = np.linalg.norm(pts["P"] - P[:, None, :3], axis=-1)
    assert np.abs(r - math.hypot(m.lp, m.ld / 2)).max() < 1e-15


def test_mirror_symmetry(any_preset):
    """Reflection in the xz plane maps leg (pair k, side s) to (pair -k, side -s)."""
    from rss_sampling import reachable_poses
    m = any_preset
    P = reachable_poses(m, 50, seed=5)
    M = P * np.array([1, -1, 1, -1, 1, -1])          # mirrored pose
    q, _ = m.inverse_kinematics(P)
    qm, _ = m.inverse_kinematics(M)
    n = m.L // 2
    perm = [2 * ((-(i // 2)) % n) + (1 - i % 2) for i in range(m.L)]
    np.testing.assert_allclose(qm, q[:, perm], atol=1e-13)


def test_unreachable_is_flagged_not_nan(any_preset):
    m = any_preset
    P = np.array([[0, 0, 1.0, 0, 0, 0], [0.7, 0, 0.3, 0, 0, 0], m.home])
    q, valid = m.inverse_kinematics(P)
    assert np.all(np.isfinite(q))
    assert not valid[0].any() and not valid[1].all() and valid[2].all()
    assert list(m.reachable(P)) == [False, False, True]
    with pytest.warns(ConditioningWarning, match="at 2 of 3 pose"):  # finite, and said
        assert np.all(np.isfinite(m.jacobian(P)))


def test_bad_pose_shape():
    with pytest.raises(InputError, match="expected shape"):
        preset("hunt").inverse_kinematics(np.zeros((3, 5)))
    with pytest.raises(InputError, match="finite"):
        preset("hunt").jacobian([0, 0, np.nan, 0, 0, 0])


def test_plot_draws(tmp_path):
    from distkin.mechanisms.plot import plot_poses
    m = preset("octo")
    paths = plot_poses(m, [m.home, m.home + [0.02, 0, 0.01, 0.2, 0, 0]], tmp_path / "octo")
    assert len(paths) == 2 and all(p.stat().st_size > 10_000 for p in paths)


def test_pickle_keeps_description_only():
    import pickle
    m = preset("octo", l0=0.165)
    m.jacobian(m.home)                                    # loads kernels (a work buffer)
    m2 = pickle.loads(pickle.dumps(m))
    assert m2 == m and hash(m2) == hash(m)
    np.testing.assert_array_equal(m2.jacobian(m2.home), m.jacobian(m.home))
