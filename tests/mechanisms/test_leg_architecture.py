"""A leg table whose lines cannot span the platform's 6 DOF is said at load time
(QA 2026-12: six parallel legs loaded silently; :mod:`distkin.mechanisms.leg_architecture`).

References: the analytic Plücker lines of the legs (Rojas et al. eq. (5)) and their
rank, and the mechanism's own J (the kernels, a second route) at the home pose and at
random poses; a healthy table (the 6-UPS example's geometry) stays silent."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from distkin.errors import GeometryWarning
from distkin.mechanisms import LegMechanism
from distkin.mechanisms.leg_architecture import LINE_SPAN_TOL, line_span
from distkin.spatial import rotation_matrix

#: platform joints (m) of a 6-6 hexapod: three pairs on a 0.15 m circle
P6 = np.array([[0.15 * np.cos(a), 0.15 * np.sin(a), 0.0]
               for c in (0, 120, 240) for a in np.radians([c - 50, c + 50])])
#: base joints of a healthy table: three pairs on a 0.3 m circle
B6 = np.array([[0.3 * np.cos(a), 0.3 * np.sin(a), 0.0]
               for c in (0, 120, 240) for a in np.radians([c - 10, c + 10])])


def _table(base, platform, home, scale=1.0, name="t"):
    legs = tuple(dict(type="UPS", base=tuple(b * scale), platform=tuple(p * scale))
                 for b, p in zip(base, platform))
    return LegMechanism(name, legs, tuple(_scaled(home, scale)), route="numpy")


def _scaled(pose, scale):
    """``pose`` with its translation times ``scale`` (the table drawn in another unit)."""
    return np.array(list(np.array(pose[:3]) * scale) + list(pose[3:]))


def _lines(base, platform, X):
    """The analytic normalised Plücker lines (unit direction, moment about the
    end-effector centre) of UPS legs at pose X."""
    Rp = (rotation_matrix(np.asarray(X[3:], dtype=float)) @ platform.T).T
    d = X[:3] + Rp - base
    n = d / np.linalg.norm(d, axis=1)[:, None]
    return np.concatenate([n, np.cross(Rp, n)], axis=1)


@pytest.mark.parametrize("scale", [1.0, 1e-3, 1e3])
def test_six_parallel_legs_warn_at_load_at_any_scale(scale):
    """Base joints right below the platform joints (a platform congruent to its base,
    legs parallel): rank 3 at home, singular at every pose (the platform translates
    with the legs locked).  Before: no warning."""
    home = (0.0, 0.0, 0.4, 0.0, 0.0, 0.0)
    with pytest.warns(GeometryWarning, match=r"architecturally singular.*rank 3 at the "
                      r"home pose|rank 3 at the home pose.*architecturally singular") as rec:
        m = _table(P6, P6, home, scale)
    assert len([w for w in rec if issubclass(w.category, GeometryWarning)]) == 1
    # independent: the analytic lines at home are rank 3 (all directions along z)
    X = _scaled(home, scale)
    assert np.linalg.matrix_rank(_lines(P6 * scale, P6 * scale, X), tol=1e-12) == 3
    # the mechanism's J (a second route) is singular at random poses too
    rng = np.random.default_rng(3)
    for _ in range(5):
        Y = X + np.concatenate([rng.uniform(-0.05, 0.05, 3) * scale, rng.uniform(-0.2, 0.2, 3)])
        s = np.linalg.svd(m.jacobian(Y) * [1, 1, 1, 1 / scale, 1 / scale, 1 / scale],
                          compute_uv=False)
        assert s[-1] / s[0] < 1e-12
    span = line_span(m)
    assert span.architectural and span.rank == 3
    assert span.ratio <= LINE_SPAN_TOL


def test_the_span_ratio_is_scale_invariant():
    """The same healthy table in mm, m and km: the same σ6/σ1 (the test's unit-free
    normalisation), equal to the analytic lines' own ratio."""
    home = (0.0, 0.0, 0.4, 0.0, 0.0, 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", GeometryWarning)        # a healthy table: silent
        spans = [line_span(_table(B6, P6, home, s)) for s in (1e-3, 1.0, 1e3)]
    L = _lines(B6, P6, np.array(home))
    ls = np.mean(np.linalg.norm(P6, axis=1))
    sv = np.linalg.svd(L * [1, 1, 1, 1 / ls, 1 / ls, 1 / ls], compute_uv=False)
    for span in spans:
        assert span.rank == 6 and not span.singular_home
        assert span.ratio == pytest.approx(sv[-1] / sv[0], rel=1e-9)


def test_a_singular_home_alone_is_said_as_such():
    """An octahedral (3-3) table whose home lies in the base plane: every leg line in
    the plane z = 0, rank 3 there, but regular off the plane (not an architecture
    singularity)."""
    base = np.array([[0, 0, 0], [6, np.sqrt(108), 0], [12, 0, 0]], dtype=float)
    plat = np.array([[0, 0, 0], [6, 0, 0], [3, np.sqrt(27), 0]], dtype=float)
    pairs = [(0, 0), (1, 0), (1, 1), (2, 1), (2, 2), (0, 2)]      # P1P4, P2P4, ...
    legs = tuple(dict(type="SPS", base=tuple(base[b]), platform=tuple(plat[p]))
                 for b, p in pairs)
    home = (3.0, 2.0, 0.0, 0.0, 0.0, 0.0)
    with pytest.warns(GeometryWarning, match="home is a singular pose") as rec:
        m = LegMechanism("flat", legs, home, route="numpy")
    assert not any("architecturally" in str(w.message) for w in rec)
    B = np.array([base[b] for b, _ in pairs])
    P = np.array([plat[p] for _, p in pairs])
    assert np.linalg.matrix_rank(_lines(B, P, np.array(home)), tol=1e-12) == 3
    up = np.array([3.0, 2.0, 10.0, 0.1, -0.1, 0.2])
    assert np.linalg.matrix_rank(_lines(B, P, up), tol=1e-9) == 6
    assert np.linalg.matrix_rank(m.jacobian(up), tol=1e-9) == 6       # the kernels agree


def test_the_gough_example_is_silent():
    from pathlib import Path
    from distkin.app.scene import load_scene
    path = Path(__file__).parents[2] / "examples" / "gough_stewart_6ups.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("error", GeometryWarning)
        m = load_scene(path).mechanism
    span = line_span(m)
    assert span.rank == 6 and not span.singular_home and not span.architectural
    assert all(r > 0.1 for r in span.probe_ratios)
