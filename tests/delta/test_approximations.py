"""Approximations of the octahedral manipulator, Rojas et al. Fig. 2 (b)-(d), and what
their offsets cost (distkin.delta.approximations, distkin.delta.offset_study).

Independent routes: the joints measured against the rules documented in the module
docstring (distances, directions); the neglected-offset pose error against the
first-order twist J^-1 (m - l) of eq. (5) and against its own scaling in delta; the
exact Δ route against the octahedral solver called with the true l-legs; the Plücker
Jacobian against finite differences of the leg lengths; the singular zeros of Fig. 2(d)
against the identity J66 = A J (eq. (6)) and those of (b) against Fichter's 90° twist
singularity of platforms with joints on circles.
"""

import numpy as np
import pytest
import sympy as sp

from distkin.delta import (KINDS, PoseLine, approximation, compare_approximations,
                           equivalent_platform, neglected_offset_error, normal_line,
                           octahedral_as_66, singularity_shift, forward_kinematics66)
from distkin.delta.approximations import joint_offsets, stoughton_arai_approximation
from distkin.delta.offset_study import (det_along, leg_lengths, platform_frame,
                                        plucker_identity_residual)
from distkin.errors import InputError
from distkin.octahedral import forward_kinematics
from distkin.singularity import OCTAHEDRAL_LEGS, plucker_jacobian, rotation_from_vector
from distkin.spatial import axis_angle

GD = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
LEGS = ["19.8", "18", "18", "17", "14.9", "17.8"]


@pytest.fixture(scope="module")
def modes():
    """The six assembly modes of Sec. VI above the base."""
    res = forward_kinematics(*GD, LEGS)
    return [(p.rotation, p.translation) for p in res.poses if p.translation[2] > 0]


def _tri(v):
    pts = octahedral_as_66(GD).joints("fast")
    allp = np.vstack([pts[0][[0, 1, 3]], pts[1][[0, 2, 4]]])   # P1 P2 P3 P4 P5 P6
    tri = allp[:3] if v <= 3 else allp[3:]
    return allp, tri.mean(axis=0)


# ------------------------------------------------------------------ the constructions

@pytest.mark.parametrize("kind", KINDS)
def test_each_double_joint_becomes_two_joints_delta_apart(kind):
    delta = 0.37
    plat = approximation(GD, kind, "0.37")
    db, dp = joint_offsets(GD, plat)
    for end, disp in ((0, db), (1, dp)):
        for v in (1, 2, 3) if end == 0 else (4, 5, 6):
            ks = [k for k, leg in enumerate(OCTAHEDRAL_LEGS) if leg[end] == v]
            assert len(ks) == 2
            assert np.linalg.norm(disp[ks[0]] - disp[ks[1]]) == pytest.approx(delta, rel=1e-14)
            dist = sorted(np.linalg.norm(disp[ks], axis=1))
            if kind == "griffis_duffy":      # one stays, one moves delta along the edge
                assert dist[0] == 0 and dist[1] == pytest.approx(delta, rel=1e-14)
            else:                            # both delta/2 from the original centre
                np.testing.assert_allclose(dist, [delta / 2] * 2, rtol=1e-14)
    assert np.all(np.abs(db[:, 2]) < 1e-15) and np.all(np.abs(dp[:, 2]) < 1e-15)


def test_split_directions_follow_the_documented_rules():
    allp, _ = _tri(1)
    std = joint_offsets(GD, approximation(GD, "standard", 1))
    sa = joint_offsets(GD, approximation(GD, "stoughton_arai", 1))
    gd = joint_offsets(GD, approximation(GD, "griffis_duffy", 1))
    for k, (b, p) in enumerate(OCTAHEDRAL_LEGS):
        for end, v, far in ((0, b, p), (1, p, b)):
            _, G = _tri(v)
            radial = allp[v - 1] - G
            partner = next(x for leg in OCTAHEDRAL_LEGS for x in leg
                           if far in leg and x not in (v, far))
            toward = allp[partner - 1] - allp[v - 1]
            # (b): tangential, towards the neighbour joined to the same far vertex
            assert abs(std[end][k] @ radial) < 1e-12 and std[end][k] @ toward > 0
            # (c) "mixed": odd legs inwards at the base, outwards on the platform
            inward = (k % 2 == 0) == (end == 0)
            cosang = sa[end][k] @ radial / np.linalg.norm(radial) / 0.5
            assert cosang == pytest.approx(-1.0 if inward else 1.0, abs=1e-14)
            # (d): legs 1, 3, 5 move on the base, 2, 4, 6 on the platform, along the edge
            moved = (k % 2 == 0) == (end == 0)
            if moved:
                np.testing.assert_allclose(gd[end][k], toward / np.linalg.norm(toward),
                                           atol=1e-14)
            else:
                assert not gd[end][k].any()
    paired = joint_offsets(GD, stoughton_arai_approximation(GD, 1, pattern="paired"))
    _, G = _tri(4)
    assert paired[1][0] @ (allp[3] - G) < 0         # leg 1 inwards on the platform too


def test_joints_are_exact():
    plat = approximation(GD, "stoughton_arai", "1/10")
    b = [sp.Matrix(x) for x in plat.base_joints]
    # legs 1 and 6 share P1 = 0: one inward, one outward along the bisector, 1/10 apart
    assert sp.simplify((b[0] - b[5]).dot(b[0] - b[5]) - sp.Rational(1, 100)) == 0


def test_bad_input_is_named():
    with pytest.raises(InputError, match="delta"):
        approximation(GD, "standard", 0)
    with pytest.raises(InputError, match="kind"):
        approximation(GD, "radial", 1)
    with pytest.raises(InputError, match="pattern"):
        stoughton_arai_approximation(GD, 1, pattern="crossed")


# ------------------------------------------------------------- neglecting the offsets

@pytest.mark.parametrize("kind", KINDS)
def test_neglected_error_is_first_order_in_delta(kind, modes):
    R, t = modes[0]
    e1 = neglected_offset_error(GD, approximation(GD, kind, 1e-3), R, t)
    e2 = neglected_offset_error(GD, approximation(GD, kind, 2e-3), R, t)
    tiny = neglected_offset_error(GD, approximation(GD, kind, 1e-9), R, t)
    assert tiny.position < 1e-7 and tiny.orientation < 1e-8        # -> 0 with delta
    assert e2.position / e1.position == pytest.approx(2, rel=2e-3)  # linear
    assert e2.orientation / e1.orientation == pytest.approx(2, rel=2e-3)
    # the linearisation J^-1 (m - l) of eq. (5) predicts it to O(delta) relative
    assert e1.first_order_position == pytest.approx(e1.position, rel=1e-3)
    assert e1.first_order_orientation == pytest.approx(e1.orientation, rel=1e-3)
    assert e1.position > 1e-4 and e1.trusted


def test_leg_change_is_the_projected_joint_displacement(modes):
    R, t = modes[1]
    plat = approximation(GD, "standard", 1e-4)
    ob, oq = octahedral_as_66(GD).joints("fast")
    world = oq @ R.T + t
    u = (world - ob) / np.linalg.norm(world - ob, axis=1)[:, None]
    db, dq = joint_offsets(GD, plat)
    predicted = np.sum(u * (dq @ R.T - db), axis=1)
    actual = leg_lengths(plat, R, t) - leg_lengths(octahedral_as_66(GD), R, t)
    np.testing.assert_allclose(actual, predicted, atol=1e-9)


def test_exact_delta_route_recovers_the_pose(modes):
    plat = approximation(GD, "griffis_duffy", "0.6")
    for R, t in modes[:3]:
        e = neglected_offset_error(GD, plat, R, t)
        assert e.exact_position < 1e-10 and e.exact_orientation < 1e-10
        assert e.position > 1e-2                      # neglecting them does not
    # second route: the l-legs of the true pose give the same poses as the m-legs
    R, t = modes[2]
    m = leg_lengths(plat, R, t)
    res66 = forward_kinematics66(GD, ["0.6"] * 6, m)
    octa = forward_kinematics(*GD, leg_lengths(octahedral_as_66(GD), R, t))
    assert len(res66.poses) == len(octa.poses)
    for a, b in zip(res66.poses, octa.poses):
        np.testing.assert_allclose(a.translation, b.translation, atol=1e-9)


def test_precise_tier_agrees_and_certified_is_refused(modes):
    R, t = modes[0]
    plat = approximation(GD, "stoughton_arai", "0.12")
    f = neglected_offset_error(GD, plat, R, t, method="fast")
    p = neglected_offset_error(GD, plat, R, t, method="precise", dps=30)
    assert abs(f.position - p.position) < 1e-10 and abs(f.orientation - p.orientation) < 1e-10
    with pytest.raises(InputError, match="method"):
        neglected_offset_error(GD, plat, R, t, method="certified")


# ---------------------------------------------------------------------- singularities

@pytest.mark.parametrize("kind", ["octahedral", *KINDS])
def test_plucker_jacobian_against_finite_differences(kind, modes):
    R, t = modes[3]
    plat = octahedral_as_66(GD) if kind == "octahedral" else approximation(GD, kind, "0.5")
    c = np.array([6.0, 3.0, 10.0])                          # any reference point
    b, q = plat.joints("fast")
    J = plucker_jacobian(b, q @ R.T + t, reference=c)
    h, cols = 1e-6, []
    for i in range(6):
        e = np.zeros(6)
        e[i] = h
        legs = []
        for s in (1, -1):
            Rw = rotation_from_vector(s * e[3:])
            legs.append(leg_lengths(plat, Rw @ R, Rw @ (t - c) + c + s * e[:3]))
        cols.append((legs[0] - legs[1]) / (2 * h))
    fd = np.array(cols).T
    np.testing.assert_allclose(J, fd, atol=1e-8)
    assert np.linalg.det(J) == pytest.approx(np.linalg.det(fd), rel=1e-6)


def test_griffis_duffy_keeps_the_singular_set(modes):
    plat = equivalent_platform(GD, ["0.6"] * 6)
    rng = np.random.default_rng(3)
    for R, t in modes:
        Rr = rotation_from_vector(rng.normal(scale=0.3, size=3)) @ R
        assert plucker_identity_residual(GD, plat, Rr, t + rng.normal(size=3)) < 1e-14
    # on a scatter of poses, sign det J66 = sign det A * sign det J (same singular set)
    _, L = platform_frame(GD)
    R0, t0 = modes[2]                                   # the mode nearest a singularity
    R = rotation_from_vector(rng.normal(scale=0.4, size=(300, 3))) @ R0
    t = t0 + rng.normal(scale=2.0, size=(300, 3))
    ref = np.sign(det_along(octahedral_as_66(GD), R, t, L))
    assert 0 < np.sum(ref > 0) < 300                    # both sides of the locus are hit
    sgn = np.sign(float(plat.transform.det))
    assert np.array_equal(np.sign(det_along(plat, R, t, L)), sgn * ref)
    kinds = {k: approximation(GD, k, "0.12") for k in KINDS}
    line = normal_line(GD, *modes[0], 1.0)
    sh = singularity_shift(GD, kinds, line)
    assert len(sh.octahedral) == 1 and abs(sh.octahedral[0] - 0.5) < 1e-9
    assert sh.shift["griffis_duffy"][0] < 1e-12
    assert sh.shift["standard"][0] > 1e-3 and sh.shift["stoughton_arai"][0] > 1e-3


def _twist_line():
    R0 = axis_angle([0, 0, 1], np.pi / 2) @ axis_angle([1, 0, 0], np.pi)
    centre = np.array([6.0, 2 * np.sqrt(3), 10.0])
    return PoseLine(R0, centre - R0 @ np.array([3.0, np.sqrt(3), 0.0]), np.zeros(3),
                    np.array([0, 0, np.pi / 6]), tuple(centre))


def test_twist_singularity_moves_linearly_for_radial_splits_only():
    line = _twist_line()
    shifts = []
    for d in (0.01, 0.02):
        kinds = {k: approximation(GD, k, d) for k in KINDS}
        sh = singularity_shift(GD, kinds, line)
        assert sh.octahedral == pytest.approx((0.5,), abs=1e-12)      # 90 deg twist
        # (b): joints on two circles, so Fichter's 90 deg twist singularity stays
        assert sh.shift["standard"][0] < 1e-10
        assert sh.shift["griffis_duffy"][0] < 1e-10
        shifts.append(sh.shift["stoughton_arai"][0])
    assert shifts[1] / shifts[0] == pytest.approx(2, rel=2e-2)


def test_certified_shift_brackets_the_fast_one():
    kinds = {k: approximation(GD, k, "0.12") for k in KINDS}
    sh = singularity_shift(GD, kinds, _twist_line(), method="certified", samples=60)
    lo, hi = sh.bounds["stoughton_arai"][0]
    assert lo <= sh.shift["stoughton_arai"][0] <= hi and hi - lo < 1e-9 and lo > 0
    for k in ("standard", "griffis_duffy"):      # the zero provably stays within 1e-10
        assert sh.bounds[k][0][0] == 0.0 and sh.bounds[k][0][1] < 1e-10


def test_det_along_is_scale_free():
    line = _twist_line()
    _, L = platform_frame(GD)
    plat = approximation(GD, "standard", "0.3")
    d1 = det_along(plat, *line.at(np.array([0.3])), L)
    pl2 = approximation(([[2 * sp.sympify(x) for x in p] for p in GD[0]],
                         [[2 * sp.sympify(x) for x in p] for p in GD[1]]), "standard", "0.6")
    R, t = line.at(np.array([0.3]))
    d2 = det_along(pl2, R, 2 * t, 2 * L)
    assert d1 == pytest.approx(d2, rel=1e-12)     # dimensionless: twice the size, same


def test_compare_records_every_kind(modes):
    Rs = np.array([m[0] for m in modes[:2]])
    ts = np.array([m[1] for m in modes[:2]])
    cmp = compare_approximations(GD, Rs, ts, ["0.012", "0.024"], lines=[_twist_line()])
    for k in KINDS:
        assert cmp.position[k].shape == (2, 2) and np.all(cmp.position[k] > 0)
        ratio = cmp.position[k][1] / cmp.position[k][0]
        np.testing.assert_allclose(ratio, 2, rtol=2e-2)
    assert np.nanmax(cmp.exact_position) < 1e-10
    assert np.all(cmp.identity_residual < 1e-14) and cmp.untrusted == 0
    assert cmp.shift["stoughton_arai"].shape == (2, 1)


def test_negative_delta_message_shows_the_value_with_its_unit():
    """QA J 9, 12: the message showed Exact(value=Fraction(-1, 1), ...)."""
    from distkin.delta import approximation
    from distkin.errors import InputError
    from distkin.exact import parse_exact
    gd = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
    for delta in ("-1", parse_exact("-1")):
        with pytest.raises(InputError, match=r"got -1 \(length units\)") as exc:
            approximation(gd, "stoughton_arai", delta)
        assert "Exact(" not in str(exc.value)


def _grazing_line(modes, depth):
    """A line tangent to the octahedral singular locus at the singular pose nearest
    mode 0, moved ``depth`` (length units) along the locus normal to the side where it
    crosses the locus twice, a pair of zeros about 0.017 apart in s at depth 2e-5."""
    _, L = platform_frame(GD)
    nl = normal_line(GD, *modes[0], 1.0)
    n = np.concatenate([nl.dx, L * nl.dw])
    n /= np.linalg.norm(n)
    v = np.random.default_rng(0).normal(size=6)
    v -= v.dot(n) * n
    v /= np.linalg.norm(v)
    R0 = rotation_from_vector((depth * n[3:] / L)[None])[0] @ nl.rotation
    return PoseLine(R0, nl.translation + depth * n[:3], 3 * v[:3], 3 * v[3:] / L)


def test_shift_finds_both_zeros_where_a_line_grazes_the_locus(modes):
    """Both zeros of a grazing line, within one of 40 sample intervals, against a grid
    of 200000 samples (second route: the sign changes alone on the fine grid)."""
    from distkin.singularity.paths import path_crossings
    line = _grazing_line(modes, -2e-5)
    _, L = platform_frame(GD)
    oct66 = octahedral_as_66(GD)
    fine = path_crossings(lambda s: det_along(oct66, *line.at(s), L), 200000)[0]
    assert len(fine) == 2 and fine[1] - fine[0] < 1 / 39        # one coarse interval
    kinds = {"griffis_duffy": approximation(GD, "griffis_duffy", "0.12")}
    sh = singularity_shift(GD, kinds, line, samples=40)
    assert sh.octahedral == pytest.approx(fine, abs=1e-9)
    # Fig. 2(d) keeps the singular set: the same two zeros, no shift
    assert sh.zeros["griffis_duffy"] == pytest.approx(fine, abs=1e-9)
    assert np.all(sh.shift["griffis_duffy"] < 1e-8)
    cert = singularity_shift(GD, kinds, line, samples=40, method="certified")
    for (lo, hi), z in zip(cert.bounds["griffis_duffy"], fine):
        assert lo == 0.0 and hi < 1e-8
