"""Findings and reasons on studies that do not cover what a claim is about (QA round H
4, 7, 10, 11): an unbounded maximum sensitivity counts as the largest (it counted as the
smallest), a "±30°" claim on a grid that does not reach ±30° or has unreachable poses is
NOT COMPARABLE (it was HELD), a device that reaches no pose makes its comparisons NOT
COMPARABLE (σmin = 0 raised ZeroDivisionError), and a reason with a missing value of ours
says so (it raised TypeError).  The expected statuses follow from the synthetic tables."""

from __future__ import annotations

import math

import numpy as np
import pytest

from distkin.indices import study
from distkin.indices.study_findings import findings, row_reason
from distkin.indices.workspace import PoseGrid

BASE = {"force": 5, "torque": 0.5, "acceleration": 500, "velocity": 3, "velocity_true": 2.5,
        "angular_velocity": 80, "angular_acceleration": 1e4, "sigma_min": 0.1,
        "sigma_max": 2, "sens_translational": 0.3, "sens_rotational": 8, "sens_force": 30,
        "sens_torque": 1.5}


def _grid(rot_deg):
    r = tuple(np.deg2rad([-rot_deg, 0.0, rot_deg]))
    return PoseGrid((0.0, 0.01), (0.0,), (0.3,), r, r, r)


def _summary(presets, col, label, grid, vals=None, n_ok=None):
    n_ok = [grid.n_orientations] * 2 if n_ok is None else n_ok
    per = {"n_ok": np.array(n_ok), "n_ok_in": np.array(n_ok)}
    for q in study.QUANTITIES:
        v = np.full(2, float({**BASE, **(vals or {})}.get(q, 1.0)))
        for suf in ("_min", "_max", "_min_in", "_max_in"):
            per[q + suf] = v.copy()
    for q in study._ARGMIN:
        per[q + "_argmin"] = np.zeros(2, np.int64)
    return study.summarise(study.Device(label, presets[col], grid, col), per)


def _by_name(out):
    return {f["finding"]: f for f in out}


def test_an_unbounded_sensitivity_counts_as_the_largest(presets):
    g = _grid(30)
    S = [_summary(presets, "hunt", "Hunt-type", g, {"sens_rotational": math.inf}),
         _summary(presets, "hexa", "HEXA", g), _summary(presets, "ergin", "Ergin", g),
         _summary(presets, "octopod", "Octopod", g, {"force": 20})]
    assert S[0]["table"]["sens_rotational"]["max"] is None           # JSON
    assert S[0]["table"]["sens_rotational"]["max_unbounded"]
    got = _by_name(findings(S))
    sens = next(f for k, f in got.items() if "systematically" in k)
    rows = sens["ours"]["rows where its largest sensitivity is the smallest"]
    assert "sens_rotational" not in rows                            # inf is not smallest
    ratio = next(f for k, f in got.items() if "force sensitivity increases" in k)
    assert ratio["ours"]["sens_rotational"] == 0.0                  # 8 / inf


@pytest.mark.parametrize("rot, n_ok, why", [(10, None, "covers ±10°"),
                                            (30, [27, 9], "unreachable")])
def test_the_30_degree_claims_need_the_range_and_every_pose(presets, rot, n_ok, why):
    g = _grid(rot)
    S = [_summary(presets, "hunt", "Hunt-type", g),
         _summary(presets, "octopod", "Octopod", g, {"force": 20}, n_ok),
         _summary(presets, "octo", "Octo", g, None, n_ok)]
    thirty = [f for f in findings(S) if "30°" in f["finding"]]
    assert len(thirty) == 3
    for f in thirty:
        assert f["status"] == "NOT COMPARABLE" and f["held"] is None and why in f["note"]
    # the same values on a full ±30° grid are held
    g = _grid(30)
    S = [_summary(presets, "hunt", "Hunt-type", g),
         _summary(presets, "octopod", "Octopod", g, {"force": 20}),
         _summary(presets, "octo", "Octo", g)]
    assert [f["status"] for f in findings(S) if "30°" in f["finding"]] == ["HELD"] * 3


def test_a_device_without_a_reachable_pose_is_not_compared(presets):
    g = _grid(30)
    S = [_summary(presets, "hunt", "Hunt-type", g, n_ok=[0, 0]),
         _summary(presets, "octopod", "Octopod", g, {"force": 20})]
    assert S[0]["isotropy"]["sigma_min"] is None        # no reachable pose: no σ (QA L 4)
    out = findings(S)                                  # ZeroDivisionError before
    hunt = [f for f in out if "Hunt-type" in f["finding"]]
    assert hunt and all(f["status"] == "NOT COMPARABLE" for f in hunt)
    assert all("Hunt-type reaches no pose" in f["note"] for f in hunt)


def test_reasons_with_a_missing_value_of_ours():
    for det in (False, True):
        s = {"paper_column": "ergin", "label": "Ergin",
             "table": {"force": {"min": None, "max": 12.0, "paper_min": 0.0,
                                 "paper_max": 12.72, "ratio_min": None, "ratio_max": 0.94}},
             "diagnostics": {"det_sign_changes": det, "sigma_min": None}, "isotropy": {}}
        assert "ours is not available" in row_reason("force", "min", s)
    s = {"paper_column": "hunt", "label": "Hunt",
         "table": {"sens_translational": {"min": 0.1, "max": 5.0, "paper_min": 0.18,
                                          "paper_max": 0.34, "ratio_min": 0.5,
                                          "ratio_max": 14.7}},
         "diagnostics": {"sigma_min": None}, "isotropy": {}}
    assert "our σmin not available" in row_reason("sens_translational", "max", s)


def test_a_velocity_at_the_threshold_within_rounding_is_not_decided(presets):
    """The exact 1 m/s of unit Plücker rows, computed as 1 - 1 ulp, on a full ±30° grid:
    the "minimum velocity >= 1 m/s" claim is undecided (QA round L 2), not NOT HELD; a
    real shortfall (0.9 m/s) still is."""
    g = _grid(30)
    one = float(np.nextafter(1.0, 0.0))

    def claim(v):
        S = [_summary(presets, "hunt", "Hunt-type", g),
             _summary(presets, "octopod", "Octopod", g,
                      {"force": 20, "velocity": v, "velocity_true": v})]
        return next(f for f in findings(S) if "minimum velocity" in f["finding"])
    f = claim(one)
    assert f["held"] is None and "at the threshold within float64 rounding" in f["note"]
    assert claim(0.9)["status"] == "NOT HELD"
