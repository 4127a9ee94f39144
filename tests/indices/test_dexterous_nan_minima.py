"""``dexterous_workspace`` refuses a NaN minimum (QA IX 4): a NaN compares below every
threshold, so a NaN-filled velocity emptied the workspace silently while a NaN threshold
was refused.  The reference is the analytic count of a 3 × 3 × 3 grid: 27 positions,
8 cells of (50 mm)³."""

from __future__ import annotations

import re

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.indices.workspace import PoseGrid, axis_values, dexterous_workspace


def _grid():
    t = tuple(axis_values(-0.05, 0.05, 0.05))
    r = (0.0,)
    return PoseGrid(t, t, tuple(0.3 + np.array(t)), r, r, r)


def test_every_position_above_threshold_is_the_whole_grid():
    g = _grid()
    dex = dexterous_workspace(g, np.ones(27, bool), {"velocity": np.full(27, 2.0)},
                              {"velocity": 1.0})
    assert (dex["count"], dex["cells"], dex["cells_total"]) == (27, 8, 8)
    assert dex["volume_m3"] == pytest.approx(8 * 0.05 ** 3, rel=1e-12)


@pytest.mark.parametrize("values, where", [(np.full(27, np.nan), "position 0 (and 26 more)"),
                                           (np.r_[np.full(4, 2.0), np.nan, np.full(22, 2.0)],
                                            "position 4")])
def test_a_nan_minimum_is_refused_by_name(values, where):
    with pytest.raises(InputError, match=re.escape(f"got NaN at {where}")) as err:
        dexterous_workspace(_grid(), np.ones(27, bool), {"velocity": values},
                            {"velocity": 1.0})
    assert err.value.field == "minima.velocity"


def test_infinite_minima_stay_allowed():
    """+inf (no reachable orientation at a position) is a number, not refused."""
    v = np.full(27, 2.0)
    v[0] = np.inf
    dex = dexterous_workspace(_grid(), np.ones(27, bool), {"velocity": v}, {"velocity": 1.0})
    assert dex["count"] == 27
