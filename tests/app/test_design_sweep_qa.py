"""The design_sweep query after QA's scratch scenes (defects 1-6 of the design-sweep
round): the swept mechanism is said (the scene's [mechanism] is not it), the design
count is limited before anything is allocated, Table I's verdict only where it applies,
a degenerate design named, ``scaling`` under its own key, the grid printed as given.

Every expected value is derived from the scene text the test writes (its ranges, its
grid, its units), from the presets (:func:`distkin.mechanisms.preset`), from Table I's
design (l2 = β = γ = 0, ld = 20 mm) or from a second route (a direct
:func:`~distkin.indices.design.sweep_designs`, the generated kernels' J); never copied
from the output.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from distkin.app.cli import main
from distkin.app.scene import loads_scene
from distkin.errors import InfeasibleError, InputError

HEAD = '[units]\nlength = "mm"\nangle = "deg"\n[mechanism]\nkind = "rss"\npreset = "{preset}"\n'
QUERY = ('[[query]]\ntype = "design_sweep"\nbase = "{base}"\nl2 = [{l2}]\nbeta = [0, 0, 10]\n'
         'gamma = [0, 0, 10]\nld = [{ld}]\nworkers = 1\n')
SMALL = "grid = { half = 25, step = 25, rotation = 10, rotation_step = 10 }\n"


def _scene(preset="hunt", base="hunt", l2="0, 10, 5", ld="20, 20, 5", grid=SMALL, mech="",
           extra=""):
    return (HEAD.format(preset=preset) + mech + QUERY.format(base=base, l2=l2, ld=ld) + grid
            + extra)


def _run(tmp_path, capsys, text, *, code=0):
    f = tmp_path / "s.toml"
    f.write_text(text, encoding="utf-8")
    js = tmp_path / "s.json"
    got = main(["run", str(f), "--no-progress", "--json", str(js)])
    out, err = capsys.readouterr()
    assert got == code, out + err
    result = json.loads(js.read_text())["queries"][0].get("result") if code == 0 else None
    return out, err, result


def _error_line(tmp_path, capsys, text):
    _, err, _ = _run(tmp_path, capsys, text, code=2)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("distkin: error: "), err
    return lines[0]


# ------------------------------------------------------------ 1. the swept mechanism
def test_the_scenes_mechanism_overrides_are_said_not_swept(tmp_path, capsys):
    """[mechanism] octo with l0 = 170, l1 = 100 beside base = "hunt": the sweep sweeps the
    hunt preset (its GII is a direct sweep's over DesignSpace("hunt")), and now says so in
    a warning, in the text and in the JSON; before, nothing said the overrides were
    dropped."""
    from distkin.indices.design import DesignSpace, sweep_designs
    from distkin.mechanisms import preset
    out, err, res = _run(tmp_path, capsys, _scene(preset="octo", mech="l0 = 170\nl1 = 100\n"))
    warn = [ln for ln in err.splitlines() if ln.startswith("distkin: warning:")]
    assert len(warn) == 1
    for words in ("[mechanism]", "octo*", "l0 = 170 mm", "l1 = 100 mm", "'hunt'",
                  "does not use the [mechanism] table"):
        assert words in warn[0]
    assert "swept mechanism: the 'hunt' preset" in out
    hunt = preset("hunt")
    m = res["mechanism"]
    assert m["base"] == "hunt" and m["scene_mechanism_is_base"] is False
    assert (m["legs"], m["l0"], m["l1"]) == (hunt.legs, hunt.l0, hunt.l1)
    assert m["unit"]["l0"] == "m" and "l0 = 170 mm" in m["scene_mechanism_note"]
    # a second route: the same sweep run directly on the hunt preset
    g = loads_scene(_scene()).queries[0].params.grid
    space = DesignSpace("hunt", (("l2", (0.0, 0.005, 0.010)), ("beta", (0.0,)),
                                 ("gamma", (0.0,)), ("ld", (0.020,))))
    direct = sweep_designs(space, g.poses(np.arange(g.n_positions)), algorithm="culling",
                           progress=False)
    assert res["gii"] == direct["gii"]


def test_a_scene_whose_mechanism_is_the_base_has_no_warning(tmp_path, capsys):
    out, err, res = _run(tmp_path, capsys, _scene())
    assert "warning" not in err
    assert res["mechanism"]["scene_mechanism_is_base"] is True
    assert "the scene's [mechanism] is the same preset" in out


# ------------------------------------------------------------------ 2. the limits
def test_a_tiny_step_is_refused_before_anything_is_allocated(tmp_path, capsys):
    """l2 = [0, 30, 0.0001] mm: (30 - 0) / 0.0001 + 1 designs ran > 10 minutes silently."""
    import tracemalloc

    from distkin.app.design_report import MAX_SWEEP_DESIGNS
    n = round(30 / 0.0001) + 1
    tracemalloc.start()
    try:
        line = _error_line(tmp_path, capsys, _scene(l2="0, 30, 0.0001"))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50e6
    assert line.startswith(f"distkin: error: query[0].l2: expected at most "
                           f"{MAX_SWEEP_DESIGNS:,} designs")
    assert f"got {n:,} l2 × 1 beta × 1 gamma × 1 ld = {n:,} designs" in line
    assert "0.0001 mm" in line


def test_designs_times_poses_is_limited_and_the_limit_can_be_lifted(tmp_path, capsys):
    """3001 designs (l2 = [0, 30, 0.01]) × Table II's 16³ positions × 9³ orientations:
    above MAX_SWEEP_EVALUATIONS; refused naming both counts and max_evaluations, which
    lifts it (the scene then loads).  The paper's own sweep (Table I × Table II, the
    default) stays below the limit."""
    from distkin.app.design_report import MAX_SWEEP_EVALUATIONS
    grid = "grid = { half = 75, step = 10, rotation = 20, rotation_step = 5 }\n"
    designs, poses = 3001, 16 ** 3 * 9 ** 3
    assert designs * poses > MAX_SWEEP_EVALUATIONS >= 7 * 4 * 4 * 5 * poses
    line = _error_line(tmp_path, capsys, _scene(l2="0, 30, 0.01", grid=grid))
    assert line.startswith(f"distkin: error: query[0]: expected at most "
                           f"{MAX_SWEEP_EVALUATIONS:,} (design, pose) evaluations")
    assert f"got {designs:,} designs × {poses:,} poses = {designs * poses:,}" in line
    assert f"max_evaluations = {designs * poses}" in line
    scene = loads_scene(_scene(l2="0, 30, 0.01", grid=grid,
                               extra=f"max_evaluations = {designs * poses}\n"))
    assert len(scene.queries[0].params.space.designs()) == designs


def test_the_culling_shows_a_progress_bar(capsys):
    """With progress on, the culling (which ran silent before the brute force's chunk
    bar) draws its bar on stderr; with progress off, nothing."""
    from distkin.indices.design import DesignSpace, sweep_designs
    from distkin.mechanisms import preset
    space = DesignSpace("hunt", (("l2", (0.0, 0.005)), ("beta", (0.0,)), ("gamma", (0.0,)),
                                 ("ld", (0.020,))))
    poses = np.tile(preset("hunt").home, (4, 1))
    sweep_designs(space, poses, algorithm="culling", progress=True)
    assert "design sweep, culling" in capsys.readouterr().err
    sweep_designs(space, poses, algorithm="culling", progress=False)
    assert "culling" not in capsys.readouterr().err


# ------------------------------------------------------------ 3. Table I's verdict
@pytest.mark.parametrize("kw, reason", [
    (dict(l2="0, 0, 5"), "a sweep of one design"),
    (dict(l2="10, 10, 5"), "is not in the sweep's grid"),
    (dict(base="octo"), "another base"),
])
def test_table1_verdict_only_where_it_applies(tmp_path, capsys, kw, reason):
    """One design, a grid without Table I's design (l2 = 0 not in [10, 10]), or a base
    whose (0, 0°, 0°, 20 mm) design is not the hunt preset: "not applicable" with the
    reason, in text and JSON (null); the old code said "reproduced" for the first and
    last, "NOT reproduced" for the second."""
    out, _, res = _run(tmp_path, capsys, _scene(**kw))
    assert res["optimum_reproduced"] is None
    assert reason in res["optimum_reproduced_reason"]
    assert f"Table I optimum: not applicable ({res['optimum_reproduced_reason']})" in out


def test_table1_verdict_where_it_applies(tmp_path, capsys):
    """Base hunt, a grid holding Table I's design among others: the verdict follows the
    optimum against Table I's parameters (the JSON's own optimum, compared here)."""
    out, _, res = _run(tmp_path, capsys, _scene())
    p = res["parameters"]
    paper = (p["l2_m"], p["beta_rad"], p["gamma_rad"], p["ld_m"]) == (0.0, 0.0, 0.0, 0.020)
    assert len(res["ties"]) == 1 and res["optimum_reproduced_reason"] is None
    assert res["optimum_reproduced"] is paper
    assert ("Table I optimum: reproduced" in out) is paper


# --------------------------------------------------------- 4. a degenerate design
def test_coincident_legs_are_named(tmp_path, capsys):
    """l2 = ld = β = γ = 0 with unreachable = "skip": the legs of each pair coincide.  The
    preset refuses ld = 0 when built (naming ld); the sweep refuses the scene at load,
    naming the design and its parameters in the scene's units, and suggests nothing
    already set.  Independent: the presets' pairs are ld apart (20 mm in Table I)."""
    from distkin.indices.design import DesignSpace
    from distkin.mechanisms import preset
    g = preset("hunt").geometry()
    assert np.linalg.norm(g["B"][0] - g["B"][1]) > 0             # ld = 20 mm apart
    space = DesignSpace("hunt", (("l2", (0.0,)), ("beta", (0.0,)), ("gamma", (0.0,)),
                                 ("ld", (0.0,))))
    with pytest.raises(InputError, match="legs of each pair coincide") as e:
        space.mechanism({"l2": 0.0, "beta": 0.0, "gamma": 0.0, "ld": 0.0})
    assert e.value.field == "ld"
    line = _error_line(tmp_path, capsys, _scene(l2="0, 0, 5", ld="0, 0, 5",
                                                extra='unreachable = "skip"\n'))
    assert line.startswith("distkin: error: query[0].ld: expected every design of the sweep "
                           "to be a valid hunt mechanism, got one that is not")
    assert "l2 = 0 mm, beta = 0 deg, gamma = 0 deg, ld = 0 mm" in line
    assert "legs of each pair coincide" in line
    assert "unreachable" not in line


def test_an_all_zero_skip_sweep_does_not_suggest_skip(monkeypatch):
    """The sweep's own refusal (every design GII 0) with unreachable = "skip" no longer
    hints at "skip"; with "zero" it still does.  Every design is made singular at every
    pose it reaches (σmin 0, σmax 1: the case the wording is for) by replacing the
    per-design σ's."""
    import distkin.indices.design as design
    space = design.DesignSpace("hunt", (("l2", (0.0, 0.01)),))
    g = loads_scene(_scene()).queries[0].params.grid
    poses = g.poses(np.arange(g.n_positions))
    monkeypatch.setattr(design, "design_sigmas",
                        lambda mech, P, *a, **k: (np.zeros(len(P)), np.ones(len(P))))
    for mode in ("skip", "zero"):
        with pytest.raises(InfeasibleError, match="scores GII 0") as e:
            design.sweep_designs(space, poses, algorithm="culling", unreachable=mode,
                                 progress=False)
        assert ("unreachable = 'skip'" in (e.value.hint or "")) is (mode == "zero")


# ------------------------------------------------------------------- 5. scaling
@pytest.mark.parametrize("scaling, index, words", [
    ("[0,0,0,0,0,0]", 0, "expected a positive number, got 0"),
    ("[15,-15,15,1,1,1]", 1, "expected a positive number, got -15"),
    ("[15,15,15,1,1,inf]", 5, "expected a finite number, got inf"),
])
def test_scaling_is_named_as_the_scene_spells_it(tmp_path, capsys, scaling, index, words):
    """The kernel's check named its argument, "query[0].ST"."""
    line = _error_line(tmp_path, capsys, _scene(extra=f"scaling = {scaling}\n"))
    assert line == f"distkin: error: query[0].scaling[{index}]: {words}"


def test_scaling_of_the_wrong_length(tmp_path, capsys):
    line = _error_line(tmp_path, capsys, _scene(extra="scaling = [15, 15]\n"))
    assert line.startswith("distkin: error: query[0].scaling: expected 6 scaling factors")


# ------------------------------------------------------------------- 6. the grid
@pytest.mark.parametrize("half, step, rot, rstep", [
    (0.001, 0.001, 0.001, 0.001),        # printed "±0°, step 0 mm"
    (0, 25, 0, 10),                      # one pose: printed "step 0 mm"
    (25, 12.5, 10, 5),
])
def test_the_grid_is_printed_and_stored_as_given(tmp_path, capsys, half, step, rot, rstep):
    grid = (f"grid = {{ half = {half}, step = {step}, rotation = {rot}, "
            f"rotation_step = {rstep} }}\n")
    out, _, res = _run(tmp_path, capsys, _scene(l2="0, 0, 5", grid=grid))
    assert (f"±{half:.4g} mm by {step:.4g} mm about the home pose, ±{rot:.4g}° by "
            f"{rstep:.4g}°") in out
    g = res["grid"]
    assert g["half"] == pytest.approx(half * 1e-3) and g["step"] == pytest.approx(step * 1e-3)
    assert g["rotation"] == pytest.approx(math.radians(rot))
    assert g["rotation_step"] == pytest.approx(math.radians(rstep))
    assert g["unit"] == {"half": "m", "step": "m", "rotation": "rad", "rotation_step": "rad",
                         "centre": "m, m, m, rad, rad, rad"}
    n = round(2 * half / step) + 1
    nr = round(2 * rot / rstep) + 1 if rot else 1
    assert (g["positions"], g["orientations"]) == (n ** 3, nr ** 3)


def test_input_error_is_raised_by_the_parser():
    """The scene loader (no run) refuses the same inputs (for callers of loads_scene)."""
    with pytest.raises(InputError, match=r"query\[0\]\.scaling\[0\]"):
        loads_scene(_scene(extra="scaling = [0,1,1,1,1,1]\n"))


def test_the_grid_json_without_the_scenes_spec_reads_the_grid_itself():
    """A query built without the scene's grid spec (grid_spec None, e.g. from Python)
    gave the full width as "half" and the middle element as "centre" (review).
    Reference: the scene's own spec and home pose, read from the same grid."""
    import dataclasses

    from distkin.app.design_report import _grid_json
    from distkin.mechanisms import preset
    p = loads_scene(_scene()).queries[0].params
    grid = p.grid
    from_spec = _grid_json(p, grid)
    bare = _grid_json(dataclasses.replace(p, grid_spec=None), grid)
    for k in ("half", "step"):
        assert bare[k] == pytest.approx(from_spec[k], rel=1e-12, abs=1e-15), k
    assert bare["centre"] == pytest.approx([0, 0, preset("hunt").z0, 0, 0, 0], abs=1e-12)
