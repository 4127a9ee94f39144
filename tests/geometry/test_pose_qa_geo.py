"""QA round: the fast tier of pose_from_points / triangle_frame read its input with
``np.asarray(..., float)``: numeric strings raised numpy's ValueError, a ragged list
numpy's inhomogeneous-shape ValueError, complex points lost their imaginary part with a
ComplexWarning only, booleans read as 1 and 0 (a "collinear" triangle).  Now they are
checked as in trilaterate's fast tier.

References: the certified tier on the same strings (exact parsing, arb balls), and a
rotation built exactly (a rotation about z by the angle of the 3-4-5 triangle).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from flint import arb

from distkin.errors import InputError
from distkin.geometry import points_from_pose, pose_from_points, triangle_frame, trilaterate

LOCAL = [["0", "0", "0"], ["sqrt(2)", "0", "0"], ["0", "1", "0"]]
# R = rotation about z with cos = 3/5, sin = 4/5 (exact), t = (1, 2, 3)
R_EXACT = np.array([[0.6, -0.8, 0], [0.8, 0.6, 0], [0, 0, 1]])


def test_numeric_strings_are_parsed_exactly_then_rounded():
    q = np.array([[0, 0, 0], [2 ** 0.5, 0, 0], [0, 1, 0]])
    world = q @ R_EXACT.T + [1, 2, 3]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        R, t = pose_from_points(LOCAL, world)
        F = triangle_frame(LOCAL)
    Rc, tc = pose_from_points(LOCAL, world, method="certified")
    for i in range(3):
        assert abs(float(t[i]) - float(arb(tc[i]).mid())) < 1e-12
        for j in range(3):
            assert abs(R[i, j] - float(arb(Rc[i][j]).mid())) < 1e-12
    np.testing.assert_allclose(R, R_EXACT, atol=1e-12)
    np.testing.assert_allclose(t, [1, 2, 3], atol=1e-12)
    Fc = triangle_frame(LOCAL, method="certified")
    np.testing.assert_allclose(F, [[float(arb(x).mid()) for x in r] for r in Fc], atol=1e-15)


def test_ragged_list_names_the_row_and_the_shape():
    with pytest.raises(InputError, match=r"\(\.\.\., 3, 3\).*a row of 2 entries") as e:
        pose_from_points([[0, 0], [1, 0, 0], [0, 1, 0]], np.eye(3))
    assert e.value.field == "platform[0]"
    with pytest.raises(InputError, match=r"\(\.\.\., 3, 3\).*4 entries") as e:
        triangle_frame([[0, 0, 0], [1, 0, 0, 0], [0, 1, 0]])
    assert e.value.field == "points[1]"
    with pytest.raises(InputError, match=r"shape \(\.\.\., 3, 3\), got shape \(2, 3\)"):
        triangle_frame([[0, 0, 0], [1, 0, 0]])


def test_complex_points_are_refused_not_truncated():
    for pts in (np.array([[0, 0, 1j], [1, 0, 0], [0, 1, 0]]), [[0, 0, 1j], [1, 0, 0], [0, 1, 0]]):
        with warnings.catch_warnings():
            warnings.simplefilter("error")             # no ComplexWarning either
            with pytest.raises(InputError, match="complex"):
                triangle_frame(pts)
            with pytest.raises(InputError, match="complex"):
                pose_from_points(np.eye(3), pts)


def test_booleans_are_refused_like_elsewhere():
    """True read as 1 made the platform triangle collinear (DegenerateGeometryError);
    trilaterate refuses a boolean with the same InputError."""
    q = [[True, 0, 0], [1, 0, 0], [0, 1, 0]]
    with pytest.raises(InputError, match="boolean True") as e:
        pose_from_points(q, np.eye(3))
    assert e.value.field == "platform[0][0]"
    with pytest.raises(InputError, match="boolean True"):
        triangle_frame(q)
    with pytest.raises(InputError, match="boolean True"):
        trilaterate(q, [1, 2, 2])


def test_exact_values_beyond_float64_are_refused_in_the_fast_tier():
    big = [[0, 0, 10 ** 400], [1, 0, 0], [0, 1, 0]]
    for f in (triangle_frame, lambda p: trilaterate(p, [1, 2, 2])):
        with pytest.raises(InputError, match=r"float64 range.*1\.0e\+400") as e:
            f(big)
        assert e.value.field == "points[0][2]"


def test_points_from_pose_fast_names_a_ragged_row_and_a_huge_value():
    """The same reader in points_from_pose: a ragged R or local names its row (it gave
    the whole value), an int beyond float64 the float64 range (it raised
    OverflowError); a proper call agrees with the certified tier (exact here)."""
    with pytest.raises(InputError, match="a row of 2 entries") as e:
        points_from_pose([[1, 0, 0], [0, 1], [0, 0, 1]], [0, 0, 0], [[1, 0, 0]])
    assert e.value.field == "R[1]"
    with pytest.raises(InputError, match="a row of 2 entries") as e:
        points_from_pose(np.eye(3), [0, 0, 0], [[1, 0, 0], [0, 1]])
    assert e.value.field == "local[1]"
    with pytest.raises(InputError, match=r"float64 range") as e:
        points_from_pose(np.eye(3), [0, 0, 10 ** 400], [[1, 0, 0]])
    assert e.value.field == "t[2]"
    got = points_from_pose(R_EXACT, ["1", "2", "3"], [["19.8", 0, 0]])
    ref = points_from_pose([["3/5", "-4/5", 0], ["4/5", "3/5", 0], [0, 0, 1]],
                           ["1", "2", "3"], [["19.8", 0, 0]], method="certified")
    np.testing.assert_allclose(got[0], [float(arb(x).mid()) for x in ref[0]], rtol=1e-15)


def _rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def test_nearly_collinear_frames_warn_where_the_fast_tier_cannot_vouch():
    """A nearly collinear triangle's normal is a difference of nearly equal products:
    the fast frame was off by ~eps/sin(angle) with no flag (3.8e-6 at sin 1e-11).
    Reference: the certified frame of the same floats at 256 bits.  Unwarned frames and
    poses are within FRAME_RTOL; warned ones exist."""
    import flint

    from distkin.errors import ConditioningWarning
    from distkin.geometry.poses import FRAME_RTOL
    rng = np.random.default_rng(4)
    n_warned = n_quiet = 0
    for _ in range(60):
        a, u = rng.normal(size=3), rng.normal(size=3)
        u /= np.linalg.norm(u)
        w = rng.normal(size=3)
        w -= (w @ u) * u
        w /= np.linalg.norm(w)
        q = np.array([a, a + u, a + rng.uniform(-1, 2) * u + 10 ** rng.uniform(-11.5, -7) * w])
        p = q @ _rotation(rng).T + rng.normal(size=3)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            F = triangle_frame(q)
            R, _ = pose_from_points(q, p, rtol=1e-6)
        warned = [c for c in caught if issubclass(c.category, ConditioningWarning)]
        assert len(warned) in (0, 2)                 # one per call
        with flint.ctx.workprec(256):
            Fc = triangle_frame(q, method="certified")
            Rc, _ = pose_from_points(q, p, method="certified", rtol=1e-6)
            errF = max(float(abs(arb(Fc[i][j]) - float(F[i, j])).upper())
                       for i in range(3) for j in range(3))
            errR = max(float(abs(arb(Rc[i][j]) - float(R[i, j])).upper())
                       for i in range(3) for j in range(3))
        if warned:
            n_warned += 1
            assert warned[0].message.estimate > FRAME_RTOL
        else:
            n_quiet += 1
            assert errF <= FRAME_RTOL and errR <= FRAME_RTOL
    assert n_warned > 5 and n_quiet > 5
