"""Inputs of the singular-locus study and of the approximations (QA defects 11-13):
bad input is an InputError naming the field (not a TypeError from deep inside, an empty
answer, or a float64 answer under another tier's name); offsets that are no small
offset of Fig. 2 (b), (c) (Rojas, Borràs, Thomas, ICRA 2012, Sec. I) are refused.

References: the analytic shortest side of the triangles (numpy on the float joints, not
the code's sympy), the analytic split (each joint delta/2 from its centre), and
normal_line's construction (the singular pose is at the middle of the line, s = 1/2,
where the octahedral det J is 0: checked with the certified tier).
"""

from __future__ import annotations

import numpy as np
import pytest

from distkin.delta import (PoseLine, normal_line, octahedral_as_66, singularity_shift,
                           standard_approximation, stoughton_arai_approximation)
from distkin.delta.approximations import joint_offsets
from distkin.delta.offset_study import det_along, platform_frame
from distkin.errors import InputError
from distkin.singularity import certified_sign, jacobian_det

GD = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
R0, T0 = np.eye(3), np.array([3.0, 1.7, 8.0])


@pytest.fixture(scope="module")
def line():
    return normal_line(GD, R0, T0, 1.0)


@pytest.fixture(scope="module")
def plat():
    return standard_approximation(GD, "0.5")


# ------------------------------------------------------------------- singularity_shift

@pytest.mark.parametrize("platforms, what", [
    ("LIST", "got list"), ({"standard": "x"}, None), ({1: "PLAT"}, "names"), (None, "got NoneType"),
])
def test_platforms_must_map_names_to_platforms(platforms, what, line, plat):
    if platforms == "LIST":
        platforms = [plat]
    elif platforms and 1 in platforms:
        platforms = {1: plat}
    with pytest.raises(InputError) as exc:
        singularity_shift(GD, platforms, line)
    assert exc.value.field.startswith("platforms")
    assert "expected" in exc.value.message and (what is None or what in exc.value.message)


@pytest.mark.parametrize("samples", [0, 1, -3, 2.5, "400", True])
def test_samples_must_be_an_integer_of_at_least_two(samples, line, plat):
    with pytest.raises(InputError, match=r"^samples: expected an integer >= 2"):
        singularity_shift(GD, {"standard": plat}, line, samples=samples)


def test_line_must_be_a_pose_line(plat):
    with pytest.raises(InputError, match=r"^line: expected a PoseLine"):
        singularity_shift(GD, {"standard": plat}, (R0, T0))


def test_the_octahedral_zero_is_the_middle_of_the_normal_line(line, plat):
    sh = singularity_shift(GD, {"standard": plat}, line, samples=40)
    # the line is centred on the singular pose found: certified sign change around 1/2
    _, L = platform_frame(GD)
    b, q = octahedral_as_66(GD).joints("fast")
    signs = []
    for s in (0.5 - 1e-6, 0.5 + 1e-6):
        R, t = line.at(np.array([s]))
        world = np.einsum("ij,nj->ni", R[0], q) + t[0]
        signs.append(certified_sign(jacobian_det(b, world, length_scale=L,
                                                 method="certified")))
    assert signs[0] * signs[1] == -1
    assert any(abs(z - 0.5) < 1e-6 for z in sh.octahedral)


# -------------------------------------------------------------------------- normal_line

@pytest.mark.parametrize("half", [float("nan"), float("inf"), -1, 0, "a", True])
def test_half_length_must_be_positive_and_finite(half):
    with pytest.raises(InputError) as exc:
        normal_line(GD, R0, T0, half)
    assert exc.value.field == "half_length"


def test_normal_line_reaches_half_length(line):
    _, L = platform_frame(GD)
    assert isinstance(line, PoseLine)
    assert line.length(L) == pytest.approx(2.0, rel=1e-12)      # 2 half_length


# ---------------------------------------------------------------------------- det_along

@pytest.mark.parametrize("method", ["precise", "exact", None])
def test_det_along_refuses_tiers_it_does_not_implement(method, plat):
    with pytest.raises(InputError) as exc:
        det_along(plat, R0, T0, 1.0, method=method)
    assert exc.value.field == "method"


def test_det_along_fast_against_certified(plat):
    b, q = plat.joints("fast")
    fast = det_along(plat, R0, T0, 2.0)
    ball = jacobian_det(b, q @ R0.T + T0, length_scale=2.0, method="certified")
    # within the fast value's own rounding-error estimate (a pose near the singular
    # locus has det J ~1e-15, where float64 keeps no digit) and the ball's radius: the
    # ball is tight since the certified tier works at 128 bits, not flint's global 53
    _, err = jacobian_det(b, q @ R0.T + T0, length_scale=2.0, with_error=True, warn=False)
    assert abs(fast - float(ball.mid())) <= 1e-12 * abs(fast) + float(err) + float(ball.rad())


def test_det_along_refuses_a_non_platform():
    with pytest.raises(InputError, match=r"^platform: expected a Platform66"):
        det_along(GD, R0, T0, 1.0)


# ------------------------------------------------------------------- the approximations

def _shortest_side():
    b, q = octahedral_as_66(GD).joints("fast")
    pts = np.vstack([b[[0, 1, 4]], q[[0, 2, 4]]])            # P1 P2 P3, P4 P5 P6
    return min(np.linalg.norm(pts[i] - pts[j]) for i, j in
               ((0, 1), (1, 2), (0, 2), (3, 4), (4, 5), (3, 5)))


@pytest.mark.parametrize("maker", [standard_approximation, stoughton_arai_approximation])
@pytest.mark.parametrize("delta", [100, 6, "6", "sqrt(36)", 6.000001])
def test_offsets_of_a_side_or_more_are_refused(maker, delta):
    assert _shortest_side() == pytest.approx(6.0, rel=1e-15)
    with pytest.raises(InputError, match=r"^delta: expected 0 < delta < 6 \(the shortest "
                                         r"triangle side, P4P5"):
        maker(GD, delta)


@pytest.mark.parametrize("maker", [standard_approximation, stoughton_arai_approximation])
@pytest.mark.parametrize("delta", ["5.99", "0.5"])
def test_smaller_offsets_split_each_joint_by_half_of_delta(maker, delta):
    db, dp = joint_offsets(GD, maker(GD, delta))
    half = float(delta) / 2
    assert np.allclose(np.linalg.norm(db, axis=1), half, rtol=1e-13)
    assert np.allclose(np.linalg.norm(dp, axis=1), half, rtol=1e-13)
    # the inward joints of (c) stay short of the centroid: circumradius 6/sqrt(3) > half
    assert half < _shortest_side() / np.sqrt(3)


def test_the_bound_follows_the_geometry():
    small = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [2, 0, 0], [1, "sqrt(3)", 0]])
    with pytest.raises(InputError, match=r"delta < 2 "):
        standard_approximation(small, "2.5")
    db, _ = joint_offsets(small, standard_approximation(small, "1.9"))
    assert np.allclose(np.linalg.norm(db, axis=1), 0.95, rtol=1e-13)
