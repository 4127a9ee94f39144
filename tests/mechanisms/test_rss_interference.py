"""Link interference (distkin.mechanisms.interference): segment distances against brute
force, and the presets buildable at the centre pose (issue 15, finding 4)."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.mechanisms import preset
from distkin.mechanisms.interference import (CLEARANCE, interference, link_segments,
                                             segment_distance)

from rss_sampling import PRESET_NAMES


def _brute(p1, q1, p2, q2, n=401):
    s = np.linspace(0, 1, n)
    A = p1 + s[:, None] * (q1 - p1)
    B = p2 + s[:, None] * (q2 - p2)
    return np.min(np.linalg.norm(A[:, None] - B[None], axis=-1))


def test_segment_distance_against_dense_sampling():
    rng = np.random.default_rng(4)
    P = rng.normal(size=(60, 4, 3))
    # parallel, collinear-overlapping and point segments among them
    P[0, 3] = P[0, 2] + (P[0, 1] - P[0, 0])
    P[1, 2], P[1, 3] = P[1, 0] + 0.3 * (P[1, 1] - P[1, 0]), P[1, 0] + 2 * (P[1, 1] - P[1, 0])
    P[2, 1] = P[2, 0]
    d = segment_distance(P[:, 0], P[:, 1], P[:, 2], P[:, 3])
    ref = np.array([_brute(*p) for p in P])
    # the sampled minimum is an upper bound within a step of the exact one
    step = np.linalg.norm(P[:, 1] - P[:, 0], axis=1) + np.linalg.norm(P[:, 3] - P[:, 2], axis=1)
    assert np.all(d <= ref + 1e-12)
    assert np.all(ref - d <= step / 400)
    assert d[1] == 0.0


def test_segment_distance_analytic():
    # two skew perpendicular segments 1 apart (the z gap), and a clamped end point
    d = segment_distance([-1, 0, 0], [1, 0, 0], [0, -1, 1], [0, 1, 1])
    assert d == pytest.approx(1.0, abs=1e-15)
    d = segment_distance([0, 0, 0], [1, 0, 0], [3, 4, 0], [3, 5, 0])
    assert d == pytest.approx(np.hypot(2, 4), abs=1e-15)


@pytest.mark.parametrize("name", PRESET_NAMES)
def test_no_crossing_links_at_home(name):
    """Every preset can be assembled: at the workspace centre no two links (cranks,
    offsets, distal links, end-effector and base spokes) come within the clearance."""
    m = preset(name)
    r = interference(m, m.home)
    assert r.ok.all(), (r.distance, r.pair)
    assert r.distance[0] > 0.019                       # about ld = 20 mm apart


def test_radial_reading_octopod_cranks_cross():
    """The reading before issue 15 (radial axes, tangential cranks): with L = 8 the
    cranks of neighbouring pairs cross at the centre pose (its rule puts every crank at
    q = 0 there)."""
    for name in ("octopod", "octo"):
        m = preset(name, layout="radial")
        r = interference(m, m.home, q=np.zeros(m.L))
        assert r.distance[0] < 1e-3 and not r.ok[0]
    m = preset("hunt", layout="radial")
    assert interference(m, m.home, q=np.zeros(6)).ok[0]


def test_segments_are_the_links():
    m = preset("octo")
    st, en, leg, joint, kind = link_segments(m, m.home[None])
    lengths = np.linalg.norm(en - st, axis=-1)[0]
    for k, (kd, lg) in enumerate(zip(kind, leg)):
        want = {"crank": m.l1, "offset": m.l2, "distal": m.l3}.get(kd)
        if want is not None:
            assert lengths[k] == pytest.approx(want, rel=1e-14)
    assert kind.count("crank") == 8 and kind.count("effector spoke") == 8


def test_bad_clearance():
    m = preset("hunt")
    with pytest.raises(InputError, match="clearance"):
        interference(m, m.home, clearance=-1.0)
    assert CLEARANCE == 0.005
