"""The study: per-position reductions, grids, dexterous workspace, criteria, and the
``performance`` / ``design_sweep`` scene queries end to end (tiny grids)."""

import json
import math

import numpy as np
import pytest
from indices_helpers import random_reachable_poses

from distkin.errors import InputError
from distkin.indices.study import QUANTITIES, evaluate_poses, study_chunk
from distkin.indices.workspace import (PoseGrid, axis_values, design_criteria,
                                       dexterous_workspace, table2_grid)


def test_table2_grid_has_the_papers_size():
    """Table II: 16³ positions × 9³ orientations = 2,985,984 poses."""
    g = table2_grid()
    assert (g.n_positions, g.n_orientations, g.size) == (4096, 729, 2_985_984)
    assert min(g.z) == pytest.approx(0.225) and max(g.z) == pytest.approx(0.375)
    assert max(g.rx) == pytest.approx(math.radians(20))
    P = g.poses([0, 4095])
    assert P.shape == (2 * 729, 6)
    assert np.allclose(P[0], [-0.075, -0.075, 0.225, *np.radians([-20, -20, -20])])


def test_axis_values_rejects_a_step_that_does_not_divide():
    with pytest.raises(InputError, match="multiple of step"):
        axis_values(-0.075, 0.075, 0.02)
    with pytest.raises(InputError, match="positive step"):
        axis_values(0, 1, 0)


def test_chunk_reductions_equal_direct_evaluation(presets):
    mech = presets["octopod"]
    grid = table2_grid(step=0.075, rot_deg=30, rot_step_deg=15)
    spec = {"mech": mech, "grid": grid, "lo": 3, "hi": 11, "ST": (15, 15, 15, 1, 1, 1),
            "actuators": {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51.0},
            "inner": math.radians(15), "batch": 200}
    res = study_chunk(spec)
    no = grid.n_orientations
    O = grid.orientations()
    inner = np.all(np.abs(O) <= math.radians(15) + 1e-9, axis=1)
    for k, pos in enumerate(range(3, 11)):
        P = grid.poses([pos])
        ok, vals = evaluate_poses(mech, P)
        assert res["n_ok"][k] == ok.sum()
        for q in QUANTITIES:
            full = np.full(no, np.nan)
            full[ok] = vals[q]
            assert res[f"{q}_min"][k] == np.nanmin(full)
            assert res[f"{q}_max"][k] == np.nanmax(full)
            assert res[f"{q}_min_in"][k] == np.nanmin(np.where(inner, full, np.nan))


def test_numpy_route_gives_the_same_indices(presets):
    mech = presets["ergin"]
    P = random_reachable_poses(mech, 100, 20, seed=9)
    ok1, v1 = evaluate_poses(mech, P)
    ok2, v2 = evaluate_poses(mech, P, route="numpy")
    assert np.array_equal(ok1, ok2)
    for q in QUANTITIES:
        assert np.allclose(v1[q], v2[q], rtol=1e-8), q


def test_dexterous_workspace_and_criteria_on_a_synthetic_sweep():
    t = tuple(np.linspace(-0.075, 0.075, 4))
    r = tuple(np.radians([-30, 0, 30]))
    g = PoseGrid(t, t, tuple(0.3 + np.array(t)), r, r, r)
    n = g.n_positions
    reach = np.ones(n, bool)
    reach[0] = False
    minima = {"velocity": np.full(n, 2.0), "acceleration": np.full(n, 50.0),
              "force": np.full(n, 5.0)}
    minima["velocity"][1] = 0.5
    dex = dexterous_workspace(g, reach, minima, {"velocity": 1.0, "acceleration": 9.81})
    assert dex["count"] == n - 2
    # positions 0 and 1 are the corner (x0, y0, z0) and (x0, y0, z1): they touch the
    # cells (0, 0, 0) and (0, 0, 1) of the 27
    assert dex["cells"] == 25 and dex["volume_m3"] == pytest.approx(25 * 0.05 ** 3)
    kw = dict(sigma_min=0.1, transmission_min=0.3, sensitivities_max=[0.3, 5.0, 40.0, 2.0],
              gii_others={"Hunt-type": 0.001})
    crit = design_criteria(8, g, reach, minima, 0.01, **kw)
    by = {c["number"]: c for c in crit}
    assert [c["number"] for c in crit] == [1, 2, 3, 4, 5, 6]
    assert by[2]["held"] is True and by[5]["held"] is True and by[6]["held"] is True
    assert by[1]["held"] is False                 # one position is unreachable
    assert by[3]["held"] is False and by[4]["held"] is False
    reach[:] = True
    minima["velocity"][:] = 2.0
    crit = design_criteria(8, g, reach, minima, 0.01, **kw)
    assert all(c["held"] for c in crit)
    # each criterion fails on its own evidence
    bad = {2: dict(kw, transmission_min=0.0), 5: dict(kw, gii_others={"x": 0.02}),
           6: dict(kw, sensitivities_max=[0.3, None, 40.0, 2.0]),
           1: dict(kw, sigma_min=0.0)}
    for k, args in bad.items():
        c = {c["number"]: c for c in design_criteria(8, g, reach, minima, 0.01, **args)}
        assert c[k]["held"] is False, k
    c = {c["number"]: c for c in design_criteria(6, g, reach, minima, 0.01, **kw,
                                                 det_sign_changes=True)}
    assert c[1]["held"] is False and c[4]["held"] is False and c[6]["held"] is False
    assert design_criteria(8, g, reach, minima)[4]["held"] is None     # nothing to compare


def test_criterion_3_needs_the_cube_and_the_range_to_pass():
    """A 1 cm grid at zero rotation passed criterion 3 while criterion 4 said None for
    lack of coverage (QA round H 8): a pass on a grid smaller than the 150 mm cube or
    ±30° now decides nothing (None), a failure on it is still a failure."""
    t = tuple(axis_values(-0.005, 0.005, 0.005))
    r = (0.0,)
    g = PoseGrid(t, t, tuple(0.3 + np.array(t)), r, r, r)
    n = g.n_positions
    minima = {"velocity": np.full(n, 2.0), "acceleration": np.full(n, 20.0),
              "force": np.full(n, 5.0)}
    kw = dict(sigma_min=0.1, transmission_min=0.5, sensitivities_max=[1, 1, 1, 1])
    c = {c["number"]: c for c in design_criteria(8, g, np.ones(n, bool), minima, **kw)}
    assert c[3]["held"] is None and c[4]["held"] is None
    minima["acceleration"][3] = 5.0                            # below 9.81 m/s²
    c = {c["number"]: c for c in design_criteria(8, g, np.ones(n, bool), minima, **kw)}
    assert c[3]["held"] is False


SCENE = """
[units]
length = "mm"
angle = "deg"

[mechanism]
kind = "rss"
preset = "octopod"

[[query]]
type = "performance"
devices = [
  { label = "Ergin's device", preset = "ergin", rotation = 20 },
  { label = "HEXA", preset = "hexa", rotation = 20 },
  { label = "Hunt-type", preset = "hunt", rotation = 20 },
  { label = "Octopod", preset = "octopod", rotation = 30, inner_rotation = 20 },
]
grid = { half = 75, step = 75, rotation_step = 10 }
workers = 1
store = "STORE"
certify = true
certify_width = 37.5
"""


@pytest.mark.slow   # 19 s; the study CLI is also run by test_sweep_subcommand_runs_a_scene and README's snippets
def test_performance_scene_end_to_end(tmp_path):
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    path = tmp_path / "study.toml"
    path.write_text(SCENE.replace("STORE", str(tmp_path / "chunks")))
    scene = loads_scene(path.read_text(), str(path))
    records, texts, worst = run_scene(scene, plots_dir=tmp_path / "plots", progress=False)
    assert worst == 0, records[0].get("error")
    res = records[0]["result"]
    assert [d["label"] for d in res["devices"]] == ["Ergin's device", "HEXA", "Hunt-type",
                                                    "Octopod"]
    octo = res["devices"][3]
    assert octo["poses"] == 27 * 7 ** 3 and octo["rotation_deg"] == pytest.approx(30)
    assert octo["isotropy"]["rotation_deg"] == pytest.approx(20)
    assert octo["table"]["force"]["paper_min"] == 21.68          # Table III
    assert octo["isotropy"]["paper_gii"] == 0.0080               # Table IV
    # issue 15: Fig. 3 certificates (3), Sec. III-B-3 (3), Sec. III-C (9 with an Octopod
    # and the Hunt-type, no Octo; QA 23: Table IV's factors as direction and magnitude)
    assert len(res["findings"]) == 15
    st = {f["finding"]: f["status"] for f in res["findings"]}
    assert set(st.values()) <= {"HELD", "NOT HELD", "NOT COMPARABLE"}
    for f in res["findings"]:
        assert (f["held"] is None) == (f["status"] == "NOT COMPARABLE")
    # our hexa and ergin presets are certified free at zero rotation, unlike Fig. 3: no
    # comparison against them is marked held
    assert res["devices"][1]["certificate"]["zero_rotation_cube"] == "regular"
    assert st["the Hunt-type beats HEXA and Ergin's device in minimum force"] == \
        "NOT COMPARABLE"
    assert st["HEXA: singularities in the 150 mm cube at zero rotation"] == "NOT HELD"
    assert [c["number"] for c in octo["criteria"]] == [1, 2, 3, 4, 5, 6]
    assert "Table III analogue" in texts[0] and "[HELD]" in texts[0]
    assert "| same def. |" in texts[0]
    # the grid's own resolution is stated (QA 25a F6), and Table IV's "same def." of the
    # devices without a paper value follows the grid as the others' does
    assert ("positions x, y, z: ±75 mm in steps of 75 mm (3 values each) about z = 300 mm; "
            "orientations rx, ry, rz: ±20° in steps of 10° (5 values each)") in texts[0]
    t4 = texts[0][texts[0].index("Table IV analogue"):]
    for dev in ("Ergin's device", "HEXA"):
        row = next(r for r in t4.splitlines() if r.strip().startswith(f"| {dev} |"))
        assert row.split("|")[2].strip().startswith("no: 27 positions, not Table II's")
        assert "the paper prints no Table IV value for it" in row
    names = {p.split("/")[-1] for p in records[0]["plots"]}
    assert {"q0_performance_tables.md", "q0_performance_tables.json",
            "q0_performance_table3_bars.png", "q0_performance_table4_bars.png",
            "q0_performance_octopod_fig5_workspace.png"} <= names
    for dev in ("ergin_s_device", "hexa", "hunt_type", "octopod"):
        for fig in ("fig6_plane", "fig7_force_polytope", "certified_workspace"):
            assert f"q0_performance_{dev}_{fig}.png" in names
    tables = json.loads((tmp_path / "plots" / "q0_performance_tables.json").read_text())
    assert tables["devices"][3]["table"]["force"]["min"] == octo["table"]["force"]["min"]
    # a second run reads every chunk back from the store
    records2, _, _ = run_scene(scene, progress=False)

    def strip(devs):
        return [{k: ({c: w for c, w in v.items() if c != "seconds"} if k == "certificate"
                     else v) for k, v in d.items() if k not in ("seconds", "chunks_resumed")}
                for d in devs]
    assert strip(records2[0]["result"]["devices"]) == strip(res["devices"])
    # every chunk of the second run came from the store, and it says so (QA L 11)
    assert [d["chunks_resumed"] for d in records2[0]["result"]["devices"]] == \
        [d["chunks"] for d in records2[0]["result"]["devices"]]
    assert all(d["chunks_resumed"] == 0 for d in res["devices"])


@pytest.mark.parametrize("bad, match", [
    ('grid = { half = 75, step = 20 }', "multiple of step"),
    ('devices = [{ label = "x", preset = "tripod" }]', "expected one of"),
    ('devices = [{ label = "x", preset = "hunt", rotation = 10, inner_rotation = 20 }]',
     "inner_rotation <= rotation"),
    ('devices = [{ label = "x", preset = "hunt", colour = 1 }]', "unknown field"),
    ('scaling = [1, 2, 3]', "6 scaling factors"),
    ('plot_device = "Nope"', "device labels"),
    ('actuators = { torque = 1 }', "unknown field"),
    ('workers = 0', "integer >= 1"),
])
def test_performance_query_rejects_bad_fields(bad, match):
    from distkin.app.scene import loads_scene
    text = ('[units]\nlength = "mm"\nangle = "deg"\n[mechanism]\nkind = "rss"\n'
            'preset = "hunt"\n[[query]]\ntype = "performance"\n' + bad + "\n")
    with pytest.raises(InputError, match=match) as err:
        loads_scene(text)
    assert err.value.field.startswith("query[0]")


def test_design_sweep_query_reports_the_optimum(tmp_path):
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    text = """
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "hunt"
[[query]]
type = "design_sweep"
l2 = [0, 10, 10]
beta = [0, 0, 10]
gamma = [0, 10, 10]
ld = [20, 20, 5]
grid = { half = 75, step = 75, rotation = 20, rotation_step = 20 }
workers = 1
store = "STORE"
""".replace("STORE", str(tmp_path / "s"))
    scene = loads_scene(text, str(tmp_path / "x.toml"))
    records, texts, worst = run_scene(scene, progress=False)
    assert worst == 0, records[0].get("error")
    r = records[0]["result"]
    assert r["n_designs"] == 4 and r["agree"] is True
    assert r["gii"] == max(r["brute_force"]["gii_all"])
    assert "optimum:" in texts[0] and "bit for bit: yes" in texts[0]


def test_sweep_subcommand_runs_a_scene(tmp_path, capsys):
    from distkin.app.cli import main
    path = tmp_path / "s.toml"
    path.write_text(SCENE.replace("STORE", "chunks").replace(
        'grid = { half = 75, step = 75, rotation_step = 10 }',
        'grid = { half = 75, step = 75, rotation_step = 20 }'))
    code = main(["sweep", str(path), "--workers", "1", "--store", str(tmp_path / "c"),
                 "--no-progress", "--json", str(tmp_path / "out.json")])
    assert code == 0
    doc = json.loads((tmp_path / "out.json").read_text())
    assert doc["queries"][0]["type"] == "performance"
    assert (tmp_path / "c").is_dir()


def test_shared_facets_equal_separate_kernels(presets):
    """evaluate_poses derives the twist and acceleration facets from those of Jᵀ; the
    public kernel on each generator matrix separately gives the same values."""
    from distkin.indices import output_generators, worst_case_output
    from distkin.indices.study import ACTUATORS, CAPABILITIES
    for name in ("hunt", "octo"):
        mech = presets[name]
        P = random_reachable_poses(mech, 200, 30, seed=10)
        ok, vals = evaluate_poses(mech, P)
        gens = output_generators(mech.jacobian(P[ok]),
                                 mass=np.diag(mech.cartesian_mass_matrix()))
        for q, _, _, gen, lim, keep in CAPABILITIES:
            ref = worst_case_output(gens[gen], -ACTUATORS[lim], ACTUATORS[lim], list(keep))
            assert np.max(np.abs(vals[q] - ref) / ref) < 1e-10, (name, q)


@pytest.mark.parametrize("name", ["octopod_study.toml", "octopod_study_coarse.toml",
                                  "octopod_design_sweep.toml"])
def test_example_scenes_load(name):
    """The example scenes validate at load time (running them takes minutes)."""
    from pathlib import Path

    from distkin.app.scene import load_scene
    path = Path(__file__).resolve().parents[2] / "examples" / name
    scene = load_scene(path)
    q = scene.queries[0]
    if q.type == "performance":
        assert [d.label for d in q.params.devices] == ["Ergin's device", "HEXA", "Hunt-type",
                                                       "Octopod", "Octo"]
        assert q.params.devices[3].rotation == pytest.approx(math.radians(30))
    else:
        assert len(q.params.space.designs()) == 560          # Table I: 7·4·4·5


def test_dexterous_volume_counts_cells_of_a_known_cube():
    """Finding 6 of issue 15: the Table II grid (16³ positions, ±75 mm) is a 150 mm
    cube, 3375 cm³, when every position is dexterous (15³ cells), not 16³ cells'
    worth; half of it (x <= 0: 8 of 16 position planes, 7 cells) is 70 × 150 × 150 mm³
    by cells and exactly half the cube by the dual-cell (trapezoidal) weights."""
    from distkin.indices.workspace import dexterous_workspace, table2_grid
    g = table2_grid()
    n = g.n_positions
    ones = np.ones(n)
    r = dexterous_workspace(g, np.ones(n, bool), {"velocity": ones}, {"velocity": 0.5})
    assert r["cells"] == 15 ** 3 == r["cells_total"] and r["count"] == 16 ** 3
    assert r["volume_m3"] == pytest.approx(0.150 ** 3, rel=1e-12)
    assert r["volume_nodes_m3"] == pytest.approx(0.150 ** 3, rel=1e-12)
    x = g.positions()[:, 0]
    r = dexterous_workspace(g, x <= 0, {"velocity": ones}, {"velocity": 0.5})
    assert r["volume_m3"] == pytest.approx(0.070 * 0.150 ** 2, rel=1e-12)
    assert r["volume_nodes_m3"] == pytest.approx(0.150 ** 3 / 2, rel=1e-12)
    # a single dexterous position spans no cell
    one = np.zeros(n, bool)
    one[n // 2] = True
    assert dexterous_workspace(g, one, {"velocity": ones}, {"velocity": 0.5})["cells"] == 0
