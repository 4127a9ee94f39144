"""The paper side of the study's findings and the reasons of its gaps (QA round 3).

Reference: the paper's own Table III (Kühne et al., as transcribed in
``PAPER_TABLE3``; the transcription is checked digit by digit against the seed text in
test_paper_tables_transcription.py), run through the same rules as our tables: the
paper side of a finding is computed from it, not written by hand (it said the
Hunt-type is best in all six maxima; the paper's table has it best in four), and a
reason never explains a gap in the wrong direction."""

from __future__ import annotations

import pytest

from distkin.indices.study import PAPER_TABLE3, PAPER_TABLE4
from distkin.indices.study_findings import findings, row_reason

CAPS = ("force", "torque", "velocity", "angular_velocity", "acceleration",
        "angular_acceleration")
SENS = ("sens_translational", "sens_rotational", "sens_force", "sens_torque")


def _as_ours(col, label):
    rows = CAPS + SENS
    return {"label": label, "paper_column": col, "L": 6,
            "table": {r: {"min": PAPER_TABLE3[col][r][0], "max": PAPER_TABLE3[col][r][1]}
                      for r in rows},
            "isotropy": {"gii": 1.0, "sigma_min": 1.0}}


def test_paper_side_is_the_papers_table_iii():
    devices = [_as_ours(c, l) for c, l in (("hunt", "Hunt-type"), ("hexa", "HEXA"),
                                           ("ergin", "Ergin's device"))]
    got = {f["finding"]: f for f in findings(devices)}
    best = next(f for k, f in got.items() if "best maximum" in k)
    want = [r for r in CAPS if all(PAPER_TABLE3["hunt"][r][1] >= PAPER_TABLE3[c][r][1]
                                   for c in ("hexa", "ergin"))]
    assert best["paper"]["rows where it is best"] == want
    assert best["ours"] == best["paper"]                # the same table, the same rule
    assert set(want) == {"force", "torque", "acceleration", "angular_acceleration"}
    assert "velocity, angular_velocity" in best["note"]  # the text's claim vs its table
    sens = next(f for k, f in got.items() if "systematically" in k)
    key = "rows where its largest sensitivity is the smallest"
    assert sens["paper"][key] == sens["ours"][key] == ["sens_rotational", "sens_force"]


def _summary(row, ours, paper):
    return {"label": "Hunt-type", "paper_column": "hunt",
            "table": {row: {"max": ours, "paper_max": paper, "ratio_max": ours / paper}},
            "diagnostics": {"sigma_min": 0.002},
            "isotropy": {"ratio_sigma_max": 0.16}}


def test_sensitivity_reasons_follow_the_map_and_the_direction():
    """{J# δq} grows like 1/σmin (translational, rotational); {Jᵀτ} is bounded by σmax
    (force, torque): the Hunt-type's torque sensitivity 0.28× the paper's was given the
    1/σmin reason, which explains a value too large."""
    torque = row_reason("sens_torque", "max", _summary("sens_torque", 0.6176, 2.18))
    assert "1/σmin" not in torque and "σmax" in torque
    big = row_reason("sens_rotational", "max", _summary("sens_rotational", 26.8, 6.13))
    assert "grows like 1/σmin" in big and "larger" in big
    small = row_reason("sens_rotational", "max", _summary("sens_rotational", 1.0, 6.13))
    assert "grows like" not in small and "smaller" in small


def test_design_sweep_says_why_its_optimum_differs(tmp_path, capsys):
    """The Table I optimum was marked NOT reproduced with no reason (QA): the report now
    names the parameters that moved and scores the paper's own design against the
    paper's GII (its ratio computed in the run: the sweep's GII of that design over
    Table I's 0.0006)."""
    import re

    from distkin.app.cli import main
    from distkin.app.design_report import PAPER_TABLE1
    scene = tmp_path / "ds.toml"
    scene.write_text(
        '[units]\nlength = "mm"\nangle = "deg"\n[mechanism]\nkind = "rss"\npreset = "hunt"\n'
        '[[query]]\ntype = "design_sweep"\nbase = "hunt"\nl2 = [0, 0, 5]\n'
        'beta = [0, 0, 10]\ngamma = [0, 30, 30]\nld = [20, 20, 5]\n'
        'leg_length = "constant_sum"\nbaseline = "ergin"\n'
        'grid = { half = 75, step = 75, rotation = 20, rotation_step = 20 }\n'
        'algorithm = "brute_force"\nunreachable = "skip"\n', encoding="utf-8")
    assert main(["run", str(scene), "--no-progress"]) == 0
    out = capsys.readouterr().out
    if "NOT reproduced" not in out:
        assert "why the optimum differs" not in out
        return
    g = float(re.search(r"the paper's design in this sweep: GII = ([0-9.e-]+)", out).group(1))
    why = next(line for line in out.splitlines() if "why the optimum differs" in line)
    assert f"{g / PAPER_TABLE1['gii']:.2g}× the paper's GII" in why
    # the paper's design's σ beside the paper's (QA 23: a GII within 2× was called "the
    # paper's design is reproduced" while σmin and σmax were ~6× off), recomputed here by
    # a second route: the hunt preset's σ of ST⁻¹Jᵀ over the same 27 × 27 poses
    m = re.search(r"σmin = ([0-9.e-]+) \(([0-9.e-]+)× the paper's\), σmax = ([0-9.e-]+) "
                  r"\(([0-9.e-]+)× the paper's\)", out)
    smin, smax = _hunt_sigma_range(75e-3, 20.0)
    assert float(m[1]) == pytest.approx(smin, rel=1e-3)
    assert float(m[3]) == pytest.approx(smax, rel=1e-3)
    assert float(m[2]) == pytest.approx(smin / PAPER_TABLE1["sigma_min"], rel=1e-2)
    assert float(m[4]) == pytest.approx(smax / PAPER_TABLE1["sigma_max"], rel=1e-2)
    rs = (smin / PAPER_TABLE1["sigma_min"], smax / PAPER_TABLE1["sigma_max"])
    if all(0.5 <= v <= 2 for v in (g / PAPER_TABLE1["gii"], *rs)):
        assert "each within 2×, so the difference lies in the designs that move" in why
    else:
        assert "so the difference lies in the designs that move" not in why
        if 0.5 <= g / PAPER_TABLE1["gii"] <= 2:          # today: 1.2×, σ 0.17× and 0.16×
            assert "the paper's design is not reproduced either" in why
    best = re.search(r"optimum: (.*);", out).group(1)
    moved = [k for k, v in (("gamma", "gamma = 0.0°"), ("beta", "beta = 0.0°"),
                            ("l2", "l2 = 0.0 mm"), ("ld", "ld = 20.0 mm")) if v not in best]
    assert moved and all(k in why for k in moved)


def _hunt_sigma_range(half, rot_deg):
    """min σmin and max σmax of ST⁻¹Jᵀ (ST = diag(15, 15, 15, 1, 1, 1), Kühne et al. Sec.
    III-B-2) for the hunt preset over 3 positions per axis at ±``half`` m about home and
    3 orientations per axis at ±``rot_deg``, the reachable poses only."""
    import itertools

    import numpy as np

    from distkin.indices.isotropy import scaled_singular_values
    from distkin.mechanisms.rss import preset
    mech = preset("hunt")
    h = np.asarray(mech.home, dtype=float)
    t, r = (-half, 0.0, half), np.radians((-rot_deg, 0.0, rot_deg))
    poses = np.array([h + np.array(p + o) for p in itertools.product(t, t, t)
                      for o in itertools.product(r, r, r)])
    ok = np.asarray(mech.reachable(poses), dtype=bool)
    lo, hi = scaled_singular_values(mech.jacobian(poses[ok]), (15, 15, 15, 1, 1, 1))
    return float(np.min(lo)), float(np.max(hi))


def test_the_force_reason_compares_like_with_like():
    """Table IV's σmin is over ±20°: the reason of a force gap quotes our σmin over the
    same inner range (isotropy, here 0.0611 over ±20°), not the full-range one (0.0547
    over ±30°, the diagnostics) as it did (QA round L 12)."""
    s = {"label": "Octopod", "paper_column": "octopod",
         "table": {"force": {"min": 6.0, "paper_min": 21.68, "ratio_min": 6.0 / 21.68}},
         "diagnostics": {"sigma_min": 0.0547},
         "isotropy": {"sigma_min": 0.0611, "rotation_deg": 20.0}}
    why = row_reason("force", "min", s)
    assert "ours 0.0611 1/(N·m) over ±20°" in why and "0.0547" not in why
    assert f"the paper's {PAPER_TABLE4['octopod'][1]:.3g} over ±20°" in why


def _wrench_min(col, label, row, ours_min, sigma_min):
    return {"label": label, "paper_column": col,
            "table": {row: {"min": ours_min, "paper_min": PAPER_TABLE3[col][row][0],
                            "ratio_min": ours_min / PAPER_TABLE3[col][row][0]}},
            "diagnostics": {"sigma_min": sigma_min},
            "isotropy": {"sigma_min": sigma_min, "rotation_deg": 20.0}}


def test_sigma_min_explains_a_minimum_only_where_the_ratios_agree():
    """QA 23: every Hunt-type wrench minimum was explained by its σmin, 0.00218 against
    Table IV's 0.0127 (0.172×), though the rows are 0.109× (force, acceleration) and
    0.23× / 0.22× (torque, angular acceleration).  The reason now says σmin explains a
    row only where the two ratios agree within 0.8-1.25×, computed here from the paper's
    Table III and IV and the full-grid values of docs/octopod_study_full.md."""
    for row, ours in (("force", 0.2054), ("acceleration", 16.53), ("torque", 0.0116),
                      ("angular_acceleration", 529.1)):
        s = _wrench_min("hunt", "Hunt-type", row, ours, 0.00218)
        ratio, rs = s["table"][row]["ratio_min"], 0.00218 / PAPER_TABLE4["hunt"][1]
        assert not 0.8 <= ratio / rs <= 1.25, row               # the premise, from the paper
        why = row_reason(row, "min", s)
        assert why.startswith("σmin of Jᵀ alone does not explain it: our σmin is 0.17× "
                              "Table IV's"), why
        assert f"this row's {ratio:.2g}× is not within 0.8-1.25× of that" in why
        assert "follows σmin" not in why
    s = _wrench_min("octopod", "Octopod", "force", 5.924, 0.0611)   # 0.273× against 0.274×
    why = row_reason("force", "min", s)
    assert why.startswith("the worst case follows σmin of Jᵀ: our σmin is 0.27× Table IV's")
    assert "as this row's 0.27× does" in why


def test_table4_factors_direction_held_magnitude_not():
    """QA 23: "[HELD] the Octopod raises the GII (×13) and σmin (×18)" was printed beside
    our ×37.7 and ×28.0.  Direction and magnitude are now two findings, each with its own
    verdict; the paper's factors come from its Table IV (0.0080 / 0.0006, 0.2230 /
    0.0127), ours are the full-grid values of docs/octopod_study_full.md."""
    hunt, octo = _as_ours("hunt", "Hunt-type"), _as_ours("octopod", "Octopod")
    octo["L"] = 8
    for s in (hunt, octo):
        s["table"]["velocity_true"] = dict(s["table"]["velocity"])
    hunt["isotropy"] = {"gii": 6.986e-4, "sigma_min": 0.00218}
    octo["isotropy"] = {"gii": 0.02633, "sigma_min": 0.0611}
    got = {f["finding"]: f for f in findings([hunt, octo])}
    d = got["the Octopod raises the GII and σmin over the Hunt-type (direction)"]
    m = got["the Octopod raises the GII ×13 and σmin ×18 over the Hunt-type (magnitude, "
            "each factor within 2×)"]
    pg = PAPER_TABLE4["octopod"][0] / PAPER_TABLE4["hunt"][0]
    ps = PAPER_TABLE4["octopod"][1] / PAPER_TABLE4["hunt"][1]
    assert (round(pg, 2), round(ps, 2)) == (13.33, 17.56)
    assert d["status"] == "HELD" and m["status"] == "NOT HELD"
    assert m["ours"]["gii_factor"] / pg > 2 and m["paper"] == {"gii_factor": pg,
                                                               "sigma_min_factor": ps}
    assert "σmin factor is 1.6× the paper's" in m["note"]
    # a factor within 2× of the paper's: the magnitude holds too
    octo["isotropy"] = {"gii": 0.0080 / 0.0006 * 6.986e-4, "sigma_min": 17.56 * 0.00218}
    m = next(f for f in findings([hunt, octo]) if "(magnitude" in f["finding"])
    assert m["status"] == "HELD" and m["note"] == ""
