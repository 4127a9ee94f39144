"""Leg tables refused at load time (QA report M, findings 4, 5, 8).

* every platform joint at one point (a "star"), or every base joint of an all-prismatic
  table at one point: J has rank at most 3 at every pose (checked here by the rank of
  the numpy reference J, an independent route), so the table is refused with a
  DegenerateGeometryError naming ``leg`` instead of a ZeroDivisionError in FK;
* a home pose at which a revolute leg does not close: refused naming ``home``, the leg
  and its reach margin (compared with the margin computed here from the geometry);
* a leg without ``platform``: named as a missing field, not Python's TypeError.
"""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import DegenerateGeometryError, InputError
from distkin.mechanisms import LegMechanism
from distkin.mechanisms.legs import LegsDescription
from distkin.spatial import rotation_matrix

from legs_sampling import random_legs

_RING = [(np.cos(a), np.sin(a), 0.0) for a in np.linspace(0, 2 * np.pi, 7)[:-1]]


def _rank_of_lines(B, P):
    """Rank of the six Plücker lines (n, P x n) through B_i and P_i (analytic J rows)."""
    rows = []
    for b, p in zip(np.array(B), np.array(P)):
        n = (p - b) / np.linalg.norm(p - b)
        rows.append(np.r_[n, np.cross(p, n)])
    return np.linalg.matrix_rank(np.array(rows), tol=1e-9)


def test_star_platform_is_refused_not_a_crash():
    legs = [dict(type="SPS", base=b, platform=(0.0, 0.0, 0.0)) for b in _RING]
    P = np.tile([0.0, 0.0, 1.0], (6, 1))                  # at the pose (0, 0, 1)
    assert _rank_of_lines(_RING, P) == 3                  # singular at any pose
    with pytest.raises(DegenerateGeometryError, match="platform joints") as exc:
        LegMechanism("star", tuple(legs), (0, 0, 1, 0, 0, 0), route="numpy")
    assert exc.value.field == "leg" and "rank at most 3" in exc.value.message


def test_star_base_is_refused_for_prismatic_legs():
    legs = [dict(type="UPS", base=(0.0, 0.0, 0.0), platform=p) for p in _RING]
    P = np.array(_RING) + [0.0, 0.0, 1.0]
    assert _rank_of_lines(np.zeros((6, 3)), P) == 3
    with pytest.raises(DegenerateGeometryError, match="base joints"):
        LegsDescription("star", tuple(legs), (0, 0, 1, 0, 0, 0))


def test_star_scene_exits_2_with_the_field(tmp_path):
    import subprocess
    import sys
    rows = "\n".join(f'[[mechanism.leg]]\ntype = "SPS"\nbase = [{b[0]:.6f}, {b[1]:.6f}, 0]\n'
                     f'platform = [0, 0, 0]' for b in _RING)
    (tmp_path / "s.toml").write_text(
        f'[mechanism]\nkind = "legs"\nhome = [0, 0, 1, 0, 0, 0]\n{rows}\n'
        f'[[query]]\ntype = "forward_kinematics"\nangles = [1.4142, 1.4142, 1.4142, 1.4142, '
        f'1.4142, 1.4142]\n')
    r = subprocess.run([sys.executable, "-m", "distkin", "run", str(tmp_path / "s.toml")],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "mechanism.leg:" in r.stderr and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def _margin(leg, X):
    """rho^2 - C^2 of a revolute leg at pose X, written out from the closure
    |P - D(q)| = l3 (legs module docstring)."""
    P = X[:3] + rotation_matrix(X[3:]) @ np.array(leg.platform)
    w = P - np.array(leg.base) - np.array(leg.offset)
    A, B = w @ np.array(leg.crank0), w @ np.array(leg.crank90)
    C = (w @ w + leg.crank ** 2 - leg.distal ** 2) / (2 * leg.crank)
    return A * A + B * B - C * C


def test_unreachable_home_is_refused_with_the_margins():
    desc = random_legs(11)
    legs = [leg.as_dict() for leg in desc.leg_table]
    for d in legs:
        d.pop("branch", None)
    far = np.array(desc.home) + [0, 0, 3.0, 0, 0, 0]
    want = [(i + 1, _margin(leg, far)) for i, leg in enumerate(desc.leg_table)
            if not leg.prismatic]
    assert all(m < 0 for _, m in want)
    with pytest.raises(InputError) as exc:
        LegsDescription("far", tuple(legs), tuple(far))
    assert exc.value.field == "home"
    for i, m in want[:6]:
        assert f"leg {i} margin {m:.3g} m^2" in exc.value.message
    LegsDescription("near", tuple(legs), desc.home_pose)     # the reachable home loads


def test_missing_platform_is_named():
    legs = [dict(type="SPS", base=b, platform=(0.1 * b[0], 0.1 * b[1], 0.0)) for b in _RING]
    del legs[2]["platform"]
    with pytest.raises(InputError) as exc:
        LegsDescription("x", tuple(legs), (0, 0, 1, 0, 0, 0))
    assert exc.value.field == "leg[2].platform"
    assert "expected platform on every leg, got nothing" in exc.value.message
    assert "__init__" not in exc.value.message
