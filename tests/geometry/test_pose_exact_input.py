"""triangle_frame / pose_from_points in the precise and certified tiers convert float and
string inputs exactly first (QA J 2, 8): the certified balls enclose the exact frame of
the binary inputs, computed independently with mpmath at 60 digits from exact mpf."""

import mpmath
import numpy as np
import pytest
from distkin.errors import InputError
from distkin.geometry import pose_from_points, triangle_frame


def _mp_frame(P):
    with mpmath.workdps(60):
        M = [[mpmath.mpf(float(x)) for x in r] for r in P]          # exact binary values
        d1 = [M[1][i] - M[0][i] for i in range(3)]
        d2 = [M[2][i] - M[0][i] for i in range(3)]
        n = [d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2],
             d1[0] * d2[1] - d1[1] * d2[0]]
        e1 = [x / mpmath.sqrt(sum(y * y for y in d1)) for x in d1]
        e3 = [x / mpmath.sqrt(sum(y * y for y in n)) for x in n]
        return e1, e3


def _inside(ball, ref):
    with mpmath.workdps(60):
        mid = mpmath.mpf(ball.mid().str(40, radius=False))
        rad = mpmath.mpf(ball.rad().str(40, radius=False))
        return abs(mid - ref) <= rad


def test_certified_frame_encloses_the_exact_frame_of_the_qa_floats():
    P = [[6.031005214236058, 16.38564246290394, -5.994362797971816],
         [6.671276319441174, 14.385300432790292, -6.756045820472858],
         [-182.10964974240602, 697.2954931117674, -73.2739426594721]]
    F = triangle_frame(P, method="certified")
    e1, e3 = _mp_frame(P)
    for r in range(3):
        assert _inside(F[r][0], e1[r]) and _inside(F[r][2], e3[r])
    assert float(F[2][2].rad()) < 1e-14


def test_certified_frame_encloses_exact_frames_of_random_floats():
    rng = np.random.default_rng(7)
    for _ in range(200):
        P = rng.normal(size=(3, 3)) * np.array([[1], [1e-3], [1e3]]) + rng.normal(size=(1, 3)) * 10
        F = triangle_frame(P.tolist(), method="certified")
        e1, e3 = _mp_frame(P)
        assert all(_inside(F[r][0], e1[r]) and _inside(F[r][2], e3[r]) for r in range(3))


def test_precise_frame_of_floats_is_accurate_to_its_digits():
    P = [[6.031005214236058, 16.38564246290394, -5.994362797971816],
         [6.671276319441174, 14.385300432790292, -6.756045820472858],
         [-182.10964974240602, 697.2954931117674, -73.2739426594721]]
    with mpmath.workdps(50):
        F = triangle_frame(P, method="precise")
    e1, e3 = _mp_frame(P)
    assert max(abs(F[r][2] - e3[r]) for r in range(3)) < 1e-45


@pytest.mark.parametrize("method", ["precise", "certified"])
def test_pose_from_numeric_strings_is_the_translation(method):
    q = [["0", "0", "0"], ["1", "0", "0"], ["0", "1", "0"]]
    p = [["1", "2", "3"], ["2", "2", "3"], ["1", "3", "3"]]
    R, t = pose_from_points(q, p, method=method)
    for i in range(3):
        assert abs(float(t[i].mid() if method == "certified" else t[i]) - (i + 1)) < 1e-14
        for j in range(3):
            v = R[i][j].mid() if hasattr(R[i][j], "mid") else R[i][j]
            assert abs(float(v) - (i == j)) < 1e-14


@pytest.mark.parametrize("method", ["precise", "certified"])
def test_malformed_pose_input_names_the_field(method):
    with pytest.raises(InputError, match="points"):
        pose_from_points([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 0, 0], [1, 0]], method=method)
    with pytest.raises(InputError, match=r"platform\[1\]\[0\]"):
        pose_from_points([[0, 0, 0], ["x", 0, 0], [0, 1, 0]], [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                         method=method)
