"""Bad input to the offset study (distkin.delta.offset_study, .singular_locus,
.approximations) raises InputError naming the field, what was expected and what was
received; a pose that is not a rigid motion (a scaled rotation, a reflection) is refused
instead of measured (QA: 2R gave an error of 0.25 "trusted", a reflection a first-order
error of 2e11).  Geometry: the Griffis-Duffy example of Rojas et al., Sec. VI."""

import numpy as np
import pytest

from distkin.delta import (approximation, compare_approximations, neglected_offset_error,
                           normal_line)
from distkin.delta.offset_study import plucker_identity_residual
from distkin.delta.pose_input import ROTATION_TOL, check_rotation
from distkin.errors import InputError
from distkin.singularity import rotation_from_vector

GD = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
R0 = np.diag([1.0, -1.0, -1.0])
T0 = np.array([6.0, 3.46, 15.0])

BAD_ROTATIONS = [
    (2 * R0, r"max\|R\^T R - I\| = 3 and det R = 8"),
    (np.diag([1.0, 1.0, -1.0]), r"det R = -1"),                       # a reflection
    (R0 + 1e-6, r"orthonormal within 1e-09"),
    (R0[:2], r"expected shape \(3, 3\), got \(2, 3\)"),
    ([[1, 0, 0], [0, np.nan, 0], [0, 0, 1]], r"expected finite numbers"),
    ("identity", r"expected numbers of shape \(3, 3\), got 'identity'"),
]


@pytest.fixture(scope="module")
def plats():
    return {k: approximation(GD, k, "0.1") for k in ("standard", "griffis_duffy")}


@pytest.mark.parametrize("bad, message", BAD_ROTATIONS)
def test_rotation_that_is_not_one_is_named(bad, message, plats):
    with pytest.raises(InputError, match=message) as err:
        neglected_offset_error(GD, plats["standard"], bad, T0)
    assert err.value.field == "rotation"
    with pytest.raises(InputError, match=message) as err:
        plucker_identity_residual(GD, plats["griffis_duffy"], bad, T0)
    assert err.value.field == "rotation"


def test_boolean_in_a_rotation_is_named(plats):
    bad = [[True, 0, 0], [0, -1, 0], [0, 0, -1]]
    with pytest.raises(InputError, match="boolean True") as err:
        neglected_offset_error(GD, plats["standard"], bad, T0)
    assert err.value.field == "rotation[0][0]"


@pytest.mark.parametrize("bad, field, message", [
    (T0[:2], "translation", r"expected shape \(3,\), got \(2,\)"),
    ([6.0, np.inf, 15.0], "translation", "expected finite numbers"),
    ([6.0, True, 15.0], "translation[1]", "boolean True"),
])
def test_translation_that_is_not_one_is_named(bad, field, message, plats):
    with pytest.raises(InputError, match=message) as err:
        neglected_offset_error(GD, plats["standard"], R0, bad)
    assert err.value.field == field


def test_rounded_rotations_are_accepted():
    # a computed rotation (round-off ~1e-16) passes and is returned unchanged
    R = rotation_from_vector(np.array([0.3, -0.2, 1.1]))
    assert np.array_equal(check_rotation(R), R)
    # the tolerance is on R^T R - I: a perturbation well inside it passes
    check_rotation(R + ROTATION_TOL / 100)


def test_platform_and_method_are_named(plats):
    with pytest.raises(InputError, match=r"expected a Platform66 .*got tuple") as err:
        neglected_offset_error(GD, GD, R0, T0)
    assert err.value.field == "platform"
    with pytest.raises(InputError, match="certified") as err:
        neglected_offset_error(GD, plats["standard"], R0, T0, method="certified")
    assert err.value.field == "method"


def test_compare_names_the_pose(plats):
    Rs = np.array([R0, np.diag([1.0, 1.0, -1.0])])
    with pytest.raises(InputError, match="det R = -1") as err:
        compare_approximations(GD, Rs, [T0, T0], ["0.1"], kinds=("standard",))
    assert err.value.field == "rotations[1]"
    with pytest.raises(InputError, match=r"as many translations as rotations \(2\), got 1") \
            as err:
        compare_approximations(GD, [R0, R0], [T0], ["0.1"], kinds=("standard",))
    assert err.value.field == "translations"


def test_normal_line_checks_its_pose():
    with pytest.raises(InputError, match="det R = -1") as err:
        normal_line(GD, np.diag([1.0, 1.0, -1.0]), T0, 1.0)
    assert err.value.field == "rotation"


@pytest.mark.parametrize("kind", ["standard", "griffis_duffy"])
def test_pattern_with_a_kind_that_has_none_is_named(kind):
    with pytest.raises(InputError, match=rf"expected no pattern for kind '{kind}'.*got "
                                         r"'paired'") as err:
        approximation(GD, kind, "0.1", pattern="paired")
    assert err.value.field == "pattern"


def test_pattern_reaches_stoughton_arai():
    from distkin.delta import stoughton_arai_approximation
    paired = approximation(GD, "stoughton_arai", "0.1", pattern="paired")
    assert paired == stoughton_arai_approximation(GD, "0.1", pattern="paired")
    assert paired != approximation(GD, "stoughton_arai", "0.1")          # "mixed"
    with pytest.raises(InputError, match="got 3") as err:
        approximation(GD, "stoughton_arai", "0.1", pattern=3)
    assert err.value.field == "pattern"


def _own_rcond(R, t):
    """sigma_min / sigma_max of the octahedral manipulator's Plücker matrix at (R, t),
    built here from the joints (rows: unit leg direction, moment about the origin)."""
    s108, s27 = np.sqrt(108.0), np.sqrt(27.0)
    P = np.array([[0, 0, 0], [6, s108, 0], [12, 0, 0], [0, 0, 0], [6, 0, 0], [3, s27, 0]])
    legs = [(1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6)]
    rows = []
    for b, p in legs:
        a, w = P[b - 1], R @ P[p - 1] + t
        u = (w - a) / np.linalg.norm(w - a)
        rows.append(np.r_[u, np.cross(a, u)])
    sv = np.linalg.svd(np.array(rows), compute_uv=False)
    return sv[-1] / sv[0]


@pytest.mark.parametrize("z", [0.0, 0.001, 0.1, 5.0])
def test_neglected_offset_error_refuses_singular_true_poses(z):
    """QA J 7: identity rotation at t = (5, 3, z) (a platform parallel to the base with
    the same orientation: singular at every height, by the Plücker matrix built here)
    gave numpy's LinAlgError or a first-order error of 1e13; now a
    SingularConfigurationError naming the pose."""
    from distkin.delta import approximation, neglected_offset_error
    from distkin.errors import SingularConfigurationError
    gd = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
    t = np.array([5.0, 3.0, z])
    assert _own_rcond(np.eye(3), t) < 1e-10
    pl = approximation(gd, "standard", "0.12")
    with pytest.raises(SingularConfigurationError, match="translation"):
        neglected_offset_error(gd, pl, np.eye(3), t)


def test_neglected_offset_error_refuses_the_90_degree_twist_and_keeps_regular_poses():
    from scipy.spatial.transform import Rotation
    from distkin.delta import approximation, neglected_offset_error
    from distkin.errors import SingularConfigurationError
    gd = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
    pl = approximation(gd, "standard", "0.12")
    R = Rotation.from_euler("zx", [90, 180], degrees=True).as_matrix()
    c = np.array([3.0, np.sqrt(3.0), 0.0])
    t = np.array([6.0, 2 * np.sqrt(3.0), 10.0]) - R @ c
    assert _own_rcond(R, t) < 1e-10
    with pytest.raises(SingularConfigurationError):
        neglected_offset_error(gd, pl, R, t)
    R2 = Rotation.from_euler("zx", [60, 180], degrees=True).as_matrix()   # 60 degrees: regular
    t2 = np.array([6.0, 2 * np.sqrt(3.0), 10.0]) - R2 @ c
    assert _own_rcond(R2, t2) > 1e-3
    err = neglected_offset_error(gd, pl, R2, t2)
    assert np.isfinite(err.first_order_position)
