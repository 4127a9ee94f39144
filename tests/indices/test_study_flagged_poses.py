"""QA Z2 follow-up: the zonotope kernel now answers NaN (with a ConditioningWarning) for
a near-flat pose whose value float64 cannot give.  A study chunk leaves such poses out
of its extremes and counts them (``n_flagged``); before, one NaN made the position's
minimum NaN, and the table's cell None.  Reference: the same chunk with the flagged
values removed by hand from the unflagged evaluation."""

import numpy as np

import distkin.indices.study as study
from distkin.indices.study import QUANTITIES, Device, study_chunk
from distkin.indices.workspace import table2_grid


def _spec(mech):
    grid = table2_grid(step=0.075, rot_step_deg=20)
    dev = Device("Octopod", mech, grid)
    return {"mech": dev.mech, "grid": grid, "lo": 0, "hi": 9,
            "actuators": {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51.0},
            "ST": (15, 15, 15, 1, 1, 1), "inner": None, "route": "kernels", "batch": 500}


def test_a_nan_pose_is_left_out_of_the_extremes_and_counted(monkeypatch, presets):
    spec = _spec(presets["octopod"])
    ref = study_chunk(spec)
    assert ref["n_flagged"].sum() == 0
    real = study.evaluate_poses
    seen = {}

    def flagging(mech, poses, **kw):
        ok, vals = real(mech, poses, **kw)
        vals = {q: np.array(v, float) for q, v in vals.items()}
        seen["ok"], seen["vals"] = ok.copy(), {q: v.copy() for q, v in vals.items()}
        vals["force"][0] = np.nan                   # the first reachable pose, flagged
        return ok, vals

    monkeypatch.setattr(study, "evaluate_poses", flagging)
    got = study_chunk(spec)
    no = spec["grid"].n_orientations
    first = int(np.flatnonzero(seen["ok"])[0])      # its position: first // no
    pos = first // no
    assert got["n_flagged"].sum() == 1 and got["n_flagged"][pos] == 1
    for q in QUANTITIES:
        for k in ("min", "max"):
            assert np.all(np.isfinite(got[f"{q}_{k}"]) | np.isinf(ref[f"{q}_{k}"]))
    # the flagged position's force extremes: over its other reachable orientations
    ok = seen["ok"][pos * no:(pos + 1) * no]
    idx = np.cumsum(seen["ok"]) - 1                 # index into vals of each reachable pose
    f = [seen["vals"]["force"][idx[pos * no + j]] for j in range(no)
         if ok[j] and pos * no + j != first]
    assert got["force_min"][pos] == min(f) and got["force_max"][pos] == max(f)
    other = np.arange(len(ref["force_min"])) != pos
    assert np.array_equal(got["force_min"][other], ref["force_min"][other])
    assert np.array_equal(got["torque_min"], ref["torque_min"])
