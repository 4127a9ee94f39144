"""Table V's worst cases (:func:`distkin.control.table5.worst_cases`) skip the poses the
study skips: a NaN value (np.argmin picked the first NaN, and the row's analysis came
out NaN) and a pose whose J float64 does not resolve (``J_unresolved``, QA 25a F4).

Reference: the same selection done by hand on the study's own values
(:func:`distkin.indices.study.evaluate_poses` on the same poses), with the spoiled poses
removed."""

import math

import numpy as np
import pytest

import distkin.indices.study as study
from distkin.control.table5 import ROWS, worst_cases
from distkin.indices.study import ACTUATORS
from distkin.errors import NotFoundError
from distkin.mechanisms import preset

D30, D10 = math.pi / 6, math.pi / 18
POSES = np.array([[0.075, -0.075, 0.375, -D30, D10, D30],
                  [-0.075, -0.075, 0.300, D30, 0.0, D30],
                  [-0.075, 0.075, 0.375, -D30, -D30, -D30],
                  [0.075, 0.075, 0.300, -D30, 0.0, D30],
                  [0.0, 0.0, 0.330, 0.0, 0.0, 0.0]])


def _spoiled(monkeypatch, spoil):
    """evaluate_poses as the study's, then ``spoil(values)`` applied to its output."""
    real = study.evaluate_poses

    def wrapped(*a, **kw):
        ok, vals = real(*a, **kw)
        vals = {k: np.array(v, copy=True) for k, v in vals.items()}
        spoil(vals)
        return ok, vals
    monkeypatch.setattr(study, "evaluate_poses", wrapped)


def test_a_nan_or_unresolved_pose_is_no_worst_case(monkeypatch):
    mech = preset("octo")
    ok, vals = study.evaluate_poses(mech, POSES, actuators=dict(ACTUATORS), warn=False)
    assert ok.all()
    rows = [r[0] for r in ROWS]
    first = {row: int(np.argmin(vals[row])) for row in rows}     # the unspoiled answer

    def spoil(v):
        for row in rows:
            v[row][first[row]] = np.nan                        # the true worst is NaN
        v["J_unresolved"][:] = False
        v["J_unresolved"][0] = True                            # pose 0 not resolved
    _spoiled(monkeypatch, spoil)
    got = worst_cases(mech, POSES, dict(ACTUATORS))
    for row in rows:
        keep = np.ones(len(POSES), bool)
        keep[[0, first[row]]] = False
        want = np.flatnonzero(keep)[np.argmin(vals[row][keep])]
        assert np.array_equal(got[row]["pose"], POSES[want]), row
        assert got[row]["analysis"] == vals[row][want], row
        assert math.isfinite(got[row]["analysis"])


def test_no_usable_pose_is_refused_naming_the_row(monkeypatch):
    def spoil(v):
        v["J_unresolved"][:] = True
    _spoiled(monkeypatch, spoil)
    with pytest.raises(NotFoundError, match="got none of 5 reachable poses"):
        worst_cases(preset("octo"), POSES, dict(ACTUATORS))
