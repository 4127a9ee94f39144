"""points_from_pose in every tier, its input checks, and the congruence test of
pose_from_points (QA T 1, T 7).  References: exact Fractions of the binary inputs, and
coordinates written out by hand."""

from fractions import Fraction

import flint
import mpmath
import numpy as np
import pytest
from distkin.errors import InputError
from distkin.geometry import points_from_pose, pose_from_points
from scipy.spatial.transform import Rotation

R = Rotation.from_euler("xyz", [0.3, -0.2, 1.1]).as_matrix()
T = np.array([1.0, 2, 3])
LOCAL = np.array([[0, 0, 0], [6, 0, 0], [3, np.sqrt(27), 0]])
WORLD = LOCAL @ R.T + T


def _exact_image():
    """R q + t of the binary values, in Fractions."""
    return [[sum(Fraction(R[i][k]) * Fraction(q[k]) for k in range(3)) + Fraction(T[i])
             for i in range(3)] for q in LOCAL]


def test_certified_points_are_exact_images_of_the_binary_inputs():
    out = points_from_pose(R, T, LOCAL, method="certified")
    ref = _exact_image()
    assert all(type(c).__name__ == "fmpq" for row in out for c in row)
    assert all(Fraction(int(c.p), int(c.q)) == r for row, rr in zip(out, ref)
               for c, r in zip(row, rr))


def test_certified_points_of_irrational_strings_are_balls_holding_the_value():
    Rq = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    out = points_from_pose(Rq, ["1", "2", "3"], [["19.8", "sqrt(2)", 0]], method="certified")
    assert str(out[0][1]) == "109/5"                       # 19.8 + 2, exact
    assert isinstance(out[0][0], flint.arb) and out[0][0].contains(1 - flint.arb(2).sqrt())
    assert float(out[0][0].rad()) < 1e-14


def test_precise_points_at_the_requested_digits():
    out = points_from_pose(R, T, LOCAL, method="precise", dps=50)
    ref = _exact_image()
    assert all(isinstance(c, mpmath.mpf) for row in out for c in row)
    with mpmath.workdps(60):
        err = max(abs(c - mpmath.mpf(r.numerator) / r.denominator)
                  for row, rr in zip(out, ref) for c, r in zip(row, rr))
    assert err < 1e-48


def test_fast_batched_matches_the_exact_image():
    out = points_from_pose(np.stack([R, R]), T, LOCAL)
    assert out.shape == (2, 3, 3)
    ref = np.array([[float(x) for x in r] for r in _exact_image()])
    assert np.abs(out - ref).max() < 1e-14


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
@pytest.mark.parametrize("args, field", [
    ((R[:2], T, LOCAL), "R"), ((R, T[:2], LOCAL), "t"), ((R, T, LOCAL[:, :2]), "local"),
    ((R, T, [[np.nan, 0, 0]]), "local"), ((R, T, [["x", 0, 0]]), "local"),
])
def test_malformed_input_names_its_field(method, args, field):
    with pytest.raises(InputError) as exc:
        points_from_pose(*args, method=method)
    assert exc.value.field.startswith(field)


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
def test_scaled_rotation_and_reflection_are_refused(method):
    with pytest.raises(InputError, match=r"max\|R\^T R - I\| = 3 and det R = 8"):
        points_from_pose(2 * R, T, LOCAL, method=method)
    with pytest.raises(InputError, match="det R = -1 .a reflection"):
        points_from_pose(np.diag([1.0, 1, -1]), T, LOCAL, method=method)


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
def test_pose_from_points_refuses_triangles_that_are_not_congruent(method):
    with pytest.raises(InputError, match=r"s\(1,2\) = 144 against 36"):
        pose_from_points(LOCAL, 2 * WORLD, method=method)
    moved = WORLD + [[0, 0, 0.1], [0, 0, 0], [0, 0, 0]]
    with pytest.raises(InputError, match="relative mismatch"):
        pose_from_points(LOCAL, moved, method=method)


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
def test_pose_from_points_accepts_rounded_data_and_a_given_tolerance(method):
    Rf, tf = pose_from_points(LOCAL, WORLD, method=method)
    assert abs(float(Rf[0][0] if method == "fast" else Rf[0][0].mid() if method ==
                     "certified" else Rf[0][0]) - R[0][0]) < 1e-12
    noisy = WORLD + 1e-6 * np.array([[1, -1, 0], [0, 1, 1], [-1, 0, 1]])
    with pytest.raises(InputError), mpmath.workdps(30):     # precise: rtol 1e-9 at 30 digits
        pose_from_points(LOCAL, noisy, method=method)
    Rn, tn = pose_from_points(LOCAL, noisy, method=method, rtol=1e-4)
    assert abs(float(tn[0] if method != "certified" else tn[0].mid()) - 1.0) < 1e-5


def test_fast_congruence_test_is_batched_and_scale_free():
    with pytest.raises(InputError, match=r"batch index \(2,\)"):
        pose_from_points(LOCAL, np.stack([WORLD, WORLD, 2 * WORLD]))
    for f in (1e-200, 1e200):
        Rf, tf = pose_from_points(LOCAL * f, WORLD * f)
        assert np.allclose(Rf, R, atol=1e-14) and np.allclose(tf / f, T, rtol=1e-13)


def test_certified_exact_congruence_with_rtol_zero():
    q = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
    p = [[0, 0, 0], [0, 6, 0], ["-sqrt(27)", 3, 0]]
    Rc, tc = pose_from_points(q, p, method="certified", rtol=0)
    assert Rc[1][0] == 1 and Rc[0][1].contains(-1)
    with pytest.raises(InputError):
        pose_from_points([[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                         [[0, 0, 0], ["1+1/10**30", 0, 0], [0, 1, 0]], method="certified", rtol=0)
    pose_from_points([[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                     [[0, 0, 0], ["1+1/10**30", 0, 0], [0, 1, 0]], method="certified")


def test_precise_points_do_not_follow_mpmaths_global_precision():
    """QA 23b: without ``dps`` the precise tier worked at ``mp.dps`` (15 unless set, so
    float64-grade).  Now 30 digits whatever the global setting: p = R q + t with R a
    rotation by 1/3 rad about z, against the same sum at 60 digits."""
    import mpmath
    c, s = mpmath.cos(mpmath.mpf(1) / 3), mpmath.sin(mpmath.mpf(1) / 3)
    R = [[str(c), str(-s), "0"], [str(s), str(c), "0"], ["0", "0", "1"]]
    outs = []
    for global_dps in (15, 50):
        with mpmath.workdps(global_dps):
            outs.append(points_from_pose(R, ["0.1", "0", "0"], [["1", "2", "3"]],
                                         method="precise", atol=1e-12)[0][0])
    with mpmath.workdps(60):
        ref = mpmath.mpf(R[0][0]) + 2 * mpmath.mpf(R[0][1]) + mpmath.mpf("0.1")
    assert outs[0] == outs[1]
    assert abs(outs[0] - ref) < mpmath.mpf(10) ** -28
