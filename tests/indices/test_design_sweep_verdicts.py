"""Design sweeps (Kühne et al., Sec. III-B-2, Table I): no optimum without a reachable
pose, ties stated, the same workspace for every design, units in the JSON, resumed
chunks said (QA round L, items 1, 5, 10, 11).  Every check is against an independent
count: the grid and design counts from the scene's ranges, reachability by the
generated kernels (``mech.reachable``, not the numpy reference the sweep uses), or
identical mechanisms, which must tie exactly."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

from distkin.errors import InfeasibleError, InputError
from distkin.indices.design import DesignSpace, sweep_designs
from distkin.indices.workspace import PoseGrid, axis_values

D = math.radians

SCENE = """[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "hunt"
[[query]]
type = "design_sweep"
base = "hunt"
l2 = [0, 15, 15]
beta = [0, 0, 10]
gamma = [0, 30, 30]
ld = [20, 40, 20]
GRID
algorithm = "both"
workers = 1
EXTRA
"""


def _grid(half, step, rot, rstep, z0):
    t = axis_values(-half, half, step)
    r = axis_values(-rot, rot, rstep)
    return PoseGrid(tuple(t), tuple(t), tuple(z0 + t), tuple(r), tuple(r), tuple(r))


@pytest.fixture(scope="module")
def partial():
    """8 designs on a grid (±150 mm, ±30°) that each reaches only in part."""
    from distkin.mechanisms import preset
    g = _grid(0.15, 0.15, D(30), D(30), preset("hunt").z0)
    space = DesignSpace("hunt", (("l2", (0.0, 0.015)), ("beta", (0.0,)),
                                 ("gamma", (0.0, D(30))), ("ld", (0.02, 0.04))))
    return space, g.poses(np.arange(g.n_positions))


def test_no_reachable_pose_is_no_optimum(tmp_path, capsys):
    """A ±5 m grid that no design reaches: exit 2, one line with the counts (2 × 2 × 2
    designs from the ranges, 2³ positions × 3³ orientations = 216 poses), no numpy
    warning, and no "reproduced" (the old code: exit 0, "Table I optimum: reproduced"
    by the order of an all-zero tie, σmin "inf")."""
    from distkin.app.cli import main
    scene = tmp_path / "empty.toml"
    scene.write_text(SCENE.replace("GRID", "grid = { half = 5000, step = 10000, rotation = 20,"
                                           " rotation_step = 20 }").replace("EXTRA", ""))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code = main(["run", str(scene), "--no-progress"])
    cap = capsys.readouterr()
    assert code == 2
    err = [ln for ln in cap.err.splitlines() if ln.strip()]
    # first the 10 m step on a 55 mm device, a likely unit slip (QA r06), then the error
    assert len(err) == 2
    assert err[0].startswith("distkin: warning: query[0].grid.step: 10000 mm is 182 x ")
    assert "no design of the sweep reaches any pose of the grid (8 designs × 216 poses)" \
        in err[1]
    assert "reproduced" not in cap.out and "RuntimeWarning" not in cap.err


def test_identical_designs_tie_and_the_tie_is_stated(partial):
    """Two designs with the same geometry must have the same GII bit for bit: both are
    the optimum's tie, by culling and by brute force (the old result named only the
    first, by its index)."""
    space, poses = partial

    class Twice(DesignSpace):
        def designs(self):
            return [{"l2": 0.0}, {"l2": 0.0}]
    twice = Twice("hunt", (("l2", (0.0,)),))
    out = sweep_designs(twice, poses, algorithm="both", unreachable="skip", progress=False)
    assert out["ties"] == [0, 1]
    assert out["culling"]["ties"] == out["brute_force"]["ties"] == [0, 1]
    assert out["agree"] is True


def test_default_scores_every_design_on_the_whole_grid(partial):
    """Sec. III-B-2 scores the GII over "the chosen ... workspace": by default a design
    that misses a pose (counted by the generated reach kernel) scores 0 there, so on
    this grid, where every design misses some, there is no optimum to report (the old
    default, "skip", ranked the designs on different subsets)."""
    space, poses = partial
    cover = [float(np.mean(space.mechanism(d).reachable(poses))) for d in space.designs()]
    assert max(cover) < 1
    with pytest.raises(InfeasibleError, match=r"every design of the sweep scores GII 0 "
                                              r"\(8 designs × 729 poses\)"):
        sweep_designs(space, poses, algorithm="culling", progress=False)


def test_skip_flags_an_optimum_that_covers_less(partial):
    """With unreachable = "skip" the optimum is flagged when another design reaches more
    of the grid (coverage by the generated reach kernel, a second route)."""
    space, poses = partial
    out = sweep_designs(space, poses, algorithm="brute_force", unreachable="skip",
                        progress=False)
    cover = [float(np.mean(space.mechanism(d).reachable(poses))) for d in space.designs()]
    assert np.allclose(out["coverage"], cover, rtol=0, atol=1e-12)
    assert cover[out["best"]] < max(cover)
    flag = out["coverage_flag"]
    assert flag["other_coverage"] == pytest.approx(max(cover), abs=1e-12)
    assert flag["optimum_coverage"] == pytest.approx(cover[out["best"]], abs=1e-12)


def test_design_json_has_units_and_resumed_chunks_are_said(tmp_path, capsys):
    """The parameters carry their unit in the key (m, rad: the scene's mm and deg
    converted), the GII is noted dimensionless and σ in 1/(N·m), no σ is the string "inf"; a rerun on
    the same store says its chunks came from it (the 8 designs in chunks of 8 = 1 chunk)."""
    from distkin.app.cli import main
    scene = tmp_path / "ok.toml"
    scene.write_text(SCENE.replace("GRID", "grid = { half = 75, step = 75, rotation = 20, "
                                           "rotation_step = 20 }")
                     .replace("EXTRA", f'unreachable = "skip"\nstore = "{tmp_path / "st"}"'))
    out = tmp_path / "o.json"
    assert main(["run", str(scene), "--no-progress", "--json", str(out)]) == 0
    first = json.loads(out.read_text())["queries"][0]["result"]
    assert first["chunks_resumed"] == 0
    assert {"l2_m", "beta_rad", "gamma_rad", "ld_m"} == set(first["parameters"])
    assert sorted({d["gamma_rad"] for d in first["designs"]}) == pytest.approx([0, D(30)])
    assert sorted({d["ld_m"] for d in first["designs"]}) == pytest.approx([0.02, 0.04])
    assert "dimensionless" in first["units"]["gii"]
    # σ of ST⁻¹Jᵀ are per N·m of actuator torque, not dimensionless (QA 25a F5)
    assert first["units"]["sigma_min"].startswith("1/(N·m)")
    assert "dimensionless" not in first["units"]["sigma_min"]
    assert all(isinstance(first[k], float) for k in ("gii", "sigma_min", "sigma_max"))
    capsys.readouterr()
    assert main(["run", str(scene), "--no-progress", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    again = json.loads(out.read_text())["queries"][0]["result"]
    assert again["chunks_resumed"] == 1
    assert "1 of 1 chunks resumed" in text
    assert "× fewer" not in text and "× shorter" not in text


@pytest.mark.parametrize("mode", ["skip", "zero"])
def test_culling_alone_names_the_unreachable_mode(tmp_path, capsys, mode):
    """QA Q 4: with algorithm = 'culling' the text named no mode (only the JSON did);
    both are the scene's value."""
    from distkin.app.cli import main
    scene = tmp_path / "c.toml"
    scene.write_text(SCENE.replace("GRID", "grid = { half = 40, step = 40, rotation = 20, "
                                           "rotation_step = 20 }")
                     .replace('algorithm = "both"', 'algorithm = "culling"')
                     .replace("EXTRA", f'unreachable = "{mode}"'))
    out = tmp_path / "o.json"
    assert main(["run", str(scene), "--no-progress", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert f"unreachable poses: {mode}" in text
    assert json.loads(out.read_text())["queries"][0]["result"]["unreachable"] == mode


def _design_scene(tmp_path, name, ld, store):
    scene = tmp_path / name
    scene.write_text(SCENE.replace("GRID", "grid = { half = 75, step = 75, rotation = 20, "
                                           "rotation_step = 20 }")
                     .replace("ld = [20, 40, 20]", f"ld = {ld}")
                     .replace("EXTRA", f'unreachable = "skip"\nstore = "{store}"'))
    return scene


def test_a_resumed_brute_force_makes_no_time_comparison(tmp_path, capsys):
    """QA S 5: a rerun timed brute force on chunks loaded from the store (0.0 s) and
    said "culling slower" where the first run said "faster".  Now the comparison is made
    only when every brute-force chunk was computed in this run; text and JSON agree.
    Reference: the chunk files the first run left in the store (1 chunk of 8 designs)."""
    from distkin.app.cli import main
    scene = _design_scene(tmp_path, "t.toml", "[20, 40, 20]", tmp_path / "st")
    out = tmp_path / "o.json"
    runs = []
    for _ in range(2):
        assert main(["run", str(scene), "--no-progress", "--json", str(out)]) == 0
        runs.append((capsys.readouterr().out,
                     json.loads(out.read_text())["queries"][0]["result"]))
    (text1, first), (text2, again) = runs
    stored = len(list((tmp_path / "st").rglob("chunk_*.npz")))
    assert stored == again["chunks_resumed"] == again["chunks"] == 1
    t = first["time_comparison"]
    assert t["comparable"] and t["reason"] is None
    assert t["culling_over_brute_force"] == pytest.approx(
        first["culling"]["seconds"] / first["brute_force"]["seconds"])
    assert ("(culling faster)" in text1) != ("(culling slower)" in text1)
    t = again["time_comparison"]
    assert not t["comparable"] and t["culling_over_brute_force"] is None
    assert "1 of 1 brute force chunks" in t["reason"]
    assert "(culling faster)" not in text2 and "(culling slower)" not in text2
    assert "time not comparable in this run" in text2


def test_a_chunk_of_another_design_sweep_is_refused(tmp_path, capsys):
    """QA S 1 for design sweeps: a chunk of a sweep over another ld range, copied into
    this sweep's folder, was loaded as this sweep's.  Now exit 2 with a hint, and the
    sweep still resumes its own chunk once the foreign one is gone."""
    from distkin.app.cli import main
    store = tmp_path / "st"
    mine = _design_scene(tmp_path, "a.toml", "[20, 40, 20]", store)
    other = _design_scene(tmp_path, "b.toml", "[25, 45, 20]", store)
    out = tmp_path / "o.json"
    folders = []
    for scene in (mine, other):                       # one folder per sweep definition
        assert main(["run", str(scene), "--no-progress", "--json", str(out)]) == 0
        folders += [p.parent for p in store.rglob("chunk_00000.npz")
                    if p.parent not in folders]
    assert len(folders) == 2
    saved = {f: (f / "chunk_00000.npz").read_bytes() for f in folders}
    (folders[0] / "chunk_00000.npz").write_bytes(saved[folders[1]])
    capsys.readouterr()
    code = main(["run", str(mine), "--no-progress", "--json", str(out)])
    err = capsys.readouterr().err
    result = json.loads(out.read_text())["queries"][0]
    assert code == 2, err
    assert result["status"] == "error" and result["error"]["kind"] == "input"
    assert "chunk_00000.npz" in result["error"]["message"] and "hint" in err
    (folders[0] / "chunk_00000.npz").write_bytes(saved[folders[0]])
    for scene in (mine, other):
        assert main(["run", str(scene), "--no-progress", "--json", str(out)]) == 0
        assert json.loads(out.read_text())["queries"][0]["result"]["chunks_resumed"] == 1


def test_a_refused_store_is_refused_before_the_culling(partial, tmp_path, monkeypatch):
    """fix-t's leftover: a design sweep ran its culling (8.5 s in the repro) before the
    brute force opened the store and refused it.  Now the store is checked first: with
    a foreign chunk in the sweep's folder the culling is never called.  Reference: the
    same sweep with that chunk removed runs both algorithms, and they agree."""
    import distkin.indices.design as design
    space, poses = partial
    poses = poses[:40]
    store = tmp_path / "st"
    first = sweep_designs(space, poses, algorithm="brute_force", store=store,
                          unreachable="skip", progress=False)
    chunk = next(store.rglob("chunk_00000.npz"))
    other = sweep_designs(space, poses[:20], algorithm="brute_force", store=tmp_path / "o",
                          unreachable="skip", progress=False)
    assert other["n_poses"] == 20
    good = chunk.read_bytes()
    chunk.write_bytes(next((tmp_path / "o").rglob("chunk_00000.npz")).read_bytes())
    called = []
    real = design.culling_sweep
    monkeypatch.setattr(design, "culling_sweep",
                        lambda *a, **k: called.append(1) or real(*a, **k))
    with pytest.raises(InputError, match="chunk_00000.npz"):
        sweep_designs(space, poses, algorithm="both", store=store, unreachable="skip",
                      progress=False)
    assert called == []
    chunk.write_bytes(good)
    both = sweep_designs(space, poses, algorithm="both", store=store,
                         unreachable="skip", progress=False)
    assert called == [1] and both["agree"] and both["best"] == first["best"]
