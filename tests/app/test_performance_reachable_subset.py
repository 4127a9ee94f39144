"""A ``performance`` study on a grid the device only partly reaches says that its Table
III/IV rows are over the reachable poses (QA IX 1): the rows, the notes, the findings
and the JSON, with the counts.  The reference is independent of the study's sweep: the
mechanism's own ``reachable`` on every grid pose, and the eq. (6) force capability
(``worst_case_output`` of Jᵀ sliced at zero torque) at those poses."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

HEAD = """title = "subset"
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "octopod"
[[query]]
type = "performance"
"""


def _run(tmp_path, body):
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    scene = loads_scene(HEAD + body, str(tmp_path / "s.toml"))
    records, texts, worst = run_scene(scene, progress=False)
    assert worst == 0, records[0].get("error")
    return records[0]["result"], texts[0]


@pytest.fixture(scope="module")
def partial(tmp_path_factory):
    """Octopod and Hunt-type on the 400 mm grid of the QA report (half 200 mm, ±10°)."""
    return _run(tmp_path_factory.mktemp("partial"),
                'devices = [{ label = "Hunt-type", preset = "hunt", rotation = 10 },\n'
                '           { label = "Octopod", preset = "octopod", rotation = 10 }]\n'
                "grid = { half = 200, step = 200, rotation = 10, rotation_step = 10 }\n")


def _grid_poses(g):
    pos = list(itertools.product(g["x_m"], g["y_m"], g["z_m"]))
    ori = list(itertools.product(g["rx_rad"], g["ry_rad"], g["rz_rad"]))
    return np.array([p + o for p in pos for o in ori])


def test_partial_grid_rows_say_reachable_only(partial):
    from distkin.indices import worst_case_output
    from distkin.mechanisms.rss import preset
    result, text = partial
    dev = next(d for d in result["devices"] if d["label"] == "Octopod")
    mech = preset("octopod")
    poses = _grid_poses(result["grid"]["Octopod"])
    ok = np.asarray(mech.reachable(poses), dtype=bool)
    n = int(ok.sum())
    assert 0 < n < len(poses)                          # the QA case: 44.86 %
    # the JSON says which poses every row and Table IV are over
    assert dev["reachable_only"] is True
    assert (dev["poses_used"], dev["poses_total"]) == (n, len(poses))
    for q, e in dev["table"].items():
        assert (e["reachable_only"], e["poses_used"], e["poses_total"]) == (True, n,
                                                                           len(poses)), q
    iso = dev["isotropy"]
    assert iso["reachable_only"] is True and iso["poses_used"] == n
    # the minimum is over those poses: eq. (6) at each reachable pose, a second route
    J = mech.jacobian(poses[ok])
    force = worst_case_output(np.swapaxes(J, 1, 2), -2.5, 2.5, keep=[0, 1, 2])
    assert dev["table"]["force"]["min"] == pytest.approx(float(np.min(force)), rel=1e-9)
    # the text: no "same def.: yes" row for the Octopod, the subset named on each row
    pct = f"over the {100 * n / len(poses):.3g} % reachable poses ({n:,} of {len(poses):,})"
    lines = [ln.strip() for ln in text.splitlines()]
    t3 = [ln.split("| Octopod (±10°) | ")[1].split(" | ")[0] for ln in lines
          if "| Octopod (±10°) | " in ln]
    t4 = [ln.split("|")[2].strip() for ln in lines if ln.startswith("| Octopod | ")
          and " / " not in ln.split("|")[2]]           # not the readings table
    assert (len(t3), len(t4)) == (12, 1)
    for same in t3 + t4:
        assert same != "yes" and same.startswith("no: " + pct), same
        assert "not like for like" in same
    notes = next(ln for ln in text.splitlines() if ln.strip().startswith("Notes:"))
    assert pct in notes and "reaches only" in notes
    assert "44.86 % reachable (every row below is over the reachable poses only)" in text


def test_partial_grid_findings_are_not_comparable(partial):
    """Octopod against Hunt-type over different subsets of their grids: not held, not
    NOT held, but not comparable, with the fractions."""
    result, _ = partial
    by = {d["label"]: d for d in result["devices"]}
    assert by["Hunt-type"]["reachable_only"] or by["Octopod"]["reachable_only"]
    f = next(f for f in result["findings"]
             if f["finding"].startswith("the Octopod beats the Hunt-type in minimum force"))
    assert f["status"] == "NOT COMPARABLE" and f["held"] is None
    assert "reachable poses only" in f["note"]


def test_full_reach_keeps_same_definition(tmp_path):
    """A grid the device reaches everywhere (25 mm about home, ±10°): no subset wording,
    reachable_only False with every pose counted; "no" rows all the same, for the grid
    is not the paper's."""
    result, text = _run(tmp_path, "grid = { half = 25, step = 25, rotation = 10, "
                                  "rotation_step = 10 }\n")
    dev = result["devices"][0]
    assert dev["reachable_fraction"] == 1.0
    assert dev["reachable_only"] is False and dev["poses_used"] == dev["poses_total"] == 729
    assert all(e["reachable_only"] is False for e in dev["table"].values())
    assert "reachable poses" not in text and "unreachable ones left out" not in text
    assert "| octopod | yes |" not in text
    # but not the paper's poses (27 = 3³ positions at ±25 mm, ±10° in steps of 10°), so
    # no Table III row says "yes" beside the paper's ±30° column (QA 2026-11-29)
    unlike = ("orientations over ±10° (the paper's column: ±30°); 27 positions, not Table "
              "II's 4,096 (±75 mm, step 10 mm); rotation steps of 10° (Table II: 5°)")
    assert dev["unlike_paper"] == unlike
    rows = [ln for ln in text.splitlines() if ln.startswith("| Continuous force [N] |")]
    assert rows and all(f"| no: {unlike}; ratio not like for like |" in r for r in rows)
    # nor Table IV's row beside the paper's GII, which is over Table II's ±20° in steps
    # of 5° (Kühne et al. Sec. III-B-2, Table II) for every device (QA 23: it said "yes")
    unlike4 = ("orientations over ±10° (Table IV: Table II's ±20°); 27 positions, not Table "
               "II's 4,096 (±75 mm, step 10 mm); rotation steps of 10° (Table II: 5°)")
    assert dev["isotropy"]["unlike_paper"] == unlike4
    assert f"| octopod | no: {unlike4}; ratio not like for like |" in text
    assert f"Not Table II's poses (Table IV's ratios not like for like): octopod: {unlike4}." \
        in text
    assert "Table IV over ±20°).  The geometry" in text


@pytest.mark.parametrize("L, rot", [(6, 20.0), (8, 30.0)])
def test_table2_grid_at_the_papers_rotation_is_like_for_like(L, rot):
    """Table II's grid (Kühne et al.: ±75 mm in steps of 10 mm about home, steps of 5°)
    over the paper's range of the column (±20° for L = 6, ±30° for L = 8): nothing to
    say; one step, one rotation or one position off: said."""
    from distkin.app.study_report import _unlike_paper
    from distkin.indices.workspace import table2_grid
    s = {"paper_column": "x", "L": L, "rotation_deg": rot, "positions": 16 ** 3}
    assert _unlike_paper(s, table2_grid(0.3, rot_deg=rot)) == ""
    assert "rotation steps of 10°" in _unlike_paper(
        s, table2_grid(0.3, rot_deg=rot, rot_step_deg=10.0))
    assert "positions, not Table II's" in _unlike_paper(s, table2_grid(0.3, rot_deg=rot,
                                                                      step=0.015))
    other = dict(s, rotation_deg=50.0 - rot)
    assert f"(the paper's column: ±{rot:.0f}°)" in _unlike_paper(other, table2_grid(
        0.3, rot_deg=50.0 - rot))


@pytest.mark.parametrize("L, rot", [(6, 20.0), (8, 30.0)])
def test_table4_row_is_like_for_like_only_on_table2(L, rot):
    """Table IV's GII is over Table II's grid, ±20° in steps of 5°, for every device
    (Kühne et al. Sec. III-B-2: "The rotations around each axis of the end effector are
    limited to ±20° with a step size of 5°"), so an Octopod whose Table III rows are over
    ±30° is like for like in Table IV over its inner ±20°; a coarser grid is not (QA 23:
    "same def. yes" on the coarse study's 343 positions and 10° steps)."""
    from distkin.app.study_report import _unlike_paper_table4
    from distkin.indices.workspace import table2_grid
    s = {"paper_column": "hunt" if L == 6 else "octopod", "L": L, "rotation_deg": rot,
         "positions": 16 ** 3, "isotropy": {"rotation_deg": 20.0}}
    assert _unlike_paper_table4(s, table2_grid(0.3, rot_deg=rot)) == ""
    assert "rotation steps of 10° (Table II: 5°)" in _unlike_paper_table4(
        s, table2_grid(0.3, rot_deg=rot, rot_step_deg=10.0))
    coarse = dict(s, positions=7 ** 3)
    assert "343 positions, not Table II's 4,096" in _unlike_paper_table4(
        coarse, table2_grid(0.3, rot_deg=rot, step=0.025))
    other = dict(s, isotropy={"rotation_deg": 15.0})
    assert "orientations over ±15° (Table IV: Table II's ±20°)" in _unlike_paper_table4(
        other, table2_grid(0.3, rot_deg=rot))
    # not the paper's device: nothing to compare
    assert _unlike_paper_table4(dict(s, paper_column=None), table2_grid(0.3, step=0.025)) == ""
    # a paper device without a Table IV value (the HEXA, Ergin's): its grid is still not
    # Table II's, as the rows beside it say (QA 25a F6: it said "yes")
    assert "343 positions, not Table II's 4,096" in _unlike_paper_table4(
        dict(coarse, paper_column="hexa"), table2_grid(0.3, rot_deg=rot, step=0.025))


def test_the_report_states_its_grid_resolution():
    """QA 25a F6: the text gave "343 positions" and Table II's step, never its own.  The
    words are checked against the grid's own axes (table2_grid's: ±75 mm about the home
    height, steps as asked; an axis of one value is "at" it)."""
    from distkin.app.study_report import _grid_text
    from distkin.indices.workspace import PoseGrid, table2_grid
    assert _grid_text(table2_grid(0.3, step=0.025, rot_step_deg=10.0), "mm") == (
        "positions x, y, z: ±75 mm in steps of 25 mm (7 values each) about z = 300 mm; "
        "orientations rx, ry, rz: ±20° in steps of 10° (5 values each)")
    assert "±7.5 cm in steps of 1 cm (16 values each) about z = 30 cm" in _grid_text(
        table2_grid(0.3), "cm")
    g = PoseGrid((0.0,), (-0.01, 0.0, 0.01), (0.25,), (0.0,), (0.0,), (-0.5, 0.5))
    assert _grid_text(g, "mm") == ("positions x, z: at 0 mm; y: ±10 mm in steps of 10 mm "
                                   "(3 values) about z = 250 mm; orientations rx, ry: at 0°; "
                                   "rz: ±28.65° in steps of 57.3° (2 values)")
