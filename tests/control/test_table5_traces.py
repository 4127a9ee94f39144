"""Table V emulated (distkin.control.table5): the time traces ``run_table5(traces=True)``
returns for the ``table5`` query's plot.  Asking for them changes no number of the
table (the sensor noise is drawn as without them), and they are the trials the rows
report: a free row's peak is the maximum of its trace, a blocked row's first trial the
mean of the F/T readings of its averaging window.

The grid is the Octo's four worst poses over the default 25 mm / 10° grid at ±30°
(:func:`table5.worst_cases`): the same rows as the full grid, at a fraction of its cost.
"""

import math

import numpy as np
import pytest

from distkin.control.table5 import ROWS, run_table5

D30, D10 = math.pi / 6, math.pi / 18
#: the Octo's worst poses of the six rows (m, rad; force and acceleration share one,
#: velocity and angular velocity another)
WORST_POSES = np.array([[0.075, -0.075, 0.375, -D30, D10, D30],
                        [-0.075, -0.075, 0.300, D30, 0.0, D30],
                        [-0.075, 0.075, 0.375, -D30, -D30, -D30],
                        [0.075, 0.075, 0.300, -D30, 0.0, D30]])


@pytest.fixture(scope="module")
def runs():
    kw = dict(poses=WORST_POSES, trials=2)
    return run_table5("octo", **kw), run_table5("octo", traces=True, **kw)


def test_traces_change_no_number_of_the_table(runs):
    plain, traced = runs
    assert list(plain) == [r[0] for r in ROWS]
    for row, r in plain.items():
        t = dict(traced[row])
        assert "trace" in t and "trace" not in r
        del t["trace"]
        assert t == r, row                              # bit for bit, every key
        # the mean is that of the trials listed (float64 mean, the same operation)
        assert r["emulated"] == float(np.mean(r["trial_values"]))
        assert len(r["trial_values"]) == (2 if r["kind"] == "blocked" else 1)


def test_the_traces_are_the_trials_the_rows_report(runs):
    _, traced = runs
    for row, r in traced.items():
        tr = r["trace"]
        t, v = tr["t"], tr["value"]
        assert t.shape == v.shape and t[0] == 0.0 and np.all(np.diff(t) > 0)
        if r["kind"] == "free":                 # 150 ms at 1 kHz; the peak is the row
            assert t.size == 150 and "reading" not in tr
            assert float(v.max()) == r["emulated"]
        else:                                   # 20 ms rise + 2 x 100 ms hold
            rd = tr["reading"]
            held = np.isfinite(rd)
            assert t.size == 220 and held.sum() == 100 and held[-100:].all()
            assert float(np.mean(rd[held])) == pytest.approx(r["trial_values"][0],
                                                             rel=1e-12)
            # the noise is small: the readings scatter about the wrench on the block
            assert np.abs(rd[held] - v[held]).max() < 0.05 * abs(r["emulated"])
