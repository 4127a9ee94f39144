"""Round trip: random assembled octahedra (seeded; regular and arbitrary triangles; sizes
1e-3 to 1e3) -> legs -> forward kinematics; the generating pose must be among the poses.

* fast tier: all 2000 problems, batched and one by one; the miss rate is reported (``-s`` prints it,
  and it is recorded as a test property) and every miss must be explained by the
  certified tier as a near-double root (another real root of the octic within 1e-3
  relative: two assembly modes about to merge, which float64 cannot always separate);
* certified tier: all 2000 problems (about 6 ms each), in the default suite; it must
  miss none.
"""

from __future__ import annotations

import numpy as np
import pytest

from distkin.octahedral import forward_kinematics, forward_kinematics_batched
from distkin.octahedral.reference import random_octahedron

N = 2000
MATCH = 1e-7   # generating pose found: max point distance / size


@pytest.fixture(scope="module")
def cases():
    rng = np.random.default_rng(2012)
    out = []
    for i in range(N):
        scale = 10 ** rng.uniform(-3, 3)
        out.append(random_octahedron(rng, scale=scale, shape="regular" if i % 4 == 0 else "random"))
    return out


def _size(c):
    return np.abs(c[0]).max() + np.abs(c[3]).max()


def _distance(points_list, truth, size):
    if len(points_list) == 0:
        return np.inf
    return float(np.min(np.abs(np.asarray(points_list) - truth).max(axis=(-2, -1)))) / size


def test_fast_tier_round_trip(cases, record_property):
    B = np.array([c[0] for c in cases])
    Q = np.array([c[1] for c in cases])
    L = np.array([c[2] for c in cases])
    br = forward_kinematics_batched(B, Q, L)
    misses = []
    for i, c in enumerate(cases):
        single = forward_kinematics(*c[:3], warn=False)
        for pts, rel in ((br.points[i][br.valid[i]], br.max_leg_error_relative[i]),
                         ([p.points for p in single],
                          [p.max_leg_error_relative for p in single])):
            if _distance(pts, c[3], _size(c)) > MATCH:
                misses.append(i)
            else:
                # the returned poses all reproduce the legs
                assert np.nanmax(rel) < 1e-6
    misses = sorted(set(misses))
    rate = len(misses) / N
    record_property("fast_miss_rate", rate)
    print(f"\nfast tier: {len(misses)} misses in {N} ({100 * rate:.3f} %), batched or single")
    assert rate <= 0.005
    for i in misses:
        b, q, l, pts, _, _ = cases[i]
        res = forward_kinematics(b, q, l, method="certified", tol=1e-12)
        true_s15 = float(np.sum((pts[1] - b[0]) ** 2))
        vals = np.array([r.value for r in res.roots])
        k = int(np.argmin(np.abs(vals - true_s15)))
        gaps = np.abs(np.delete(vals, k) - vals[k]) / vals[k]
        print(f"  miss {i}: s15 = {true_s15:.6g}, nearest other real root at relative "
              f"{gaps.min():.2e} (near-double root)")
        assert gaps.min() < 1e-3, "a fast-tier miss that is not a near-double root"
        assert _distance([p.points for p in res], pts, _size(cases[i])) <= MATCH


def _certified_round_trip(cases, n):
    misses = []
    for c in cases[:n]:
        b, q, l, pts, _, _ = c
        res = forward_kinematics(b, q, l, method="certified", tol=1e-12)
        assert res.certified
        if _distance([p.points for p in res], pts, _size(c)) > 1e-9:
            misses.append(c)
    return misses


def test_certified_tier_round_trip(cases):
    assert _certified_round_trip(cases, N) == []
