"""The ``certify_workspace`` scene query: validation, JSON contract, resume, executors,
plot, CLI exit codes."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from distkin.certify.workspace import certify_workspace, initial_boxes
from distkin.app.cli import run_scene
from distkin.errors import InputError
from distkin.mechanisms import preset
from distkin.app.scene import loads_scene

ROOT = Path(__file__).resolve().parents[2]

SCENE = """
[units]
length = "mm"
angle = "deg"

[mechanism]
kind = "rss"
preset = "{preset}"

[[query]]
type = "certify_workspace"
{fields}
"""


def _scene(preset_name="hunt", **fields):
    body = "\n".join(f"{k} = {v}" for k, v in fields.items())
    return loads_scene(SCENE.format(preset=preset_name, fields=body), "test.toml")


@pytest.mark.parametrize("fields, match", [
    ({"method": '"fast"'}, "certified"),
    ({"min_widht": "5"}, "unknown field"),
    ({"region": "{ lower = [0, 0, 300, 0, 0, 0], upper = [-1, 0, 300, 0, 0, 0] }"},
     "lower <= upper"),
    ({"region": "{ lower = [0, 0, 300, 0, 0], upper = [1, 0, 300, 0, 0, 0] }"}, "6 numbers"),
    ({"min_width": "-2"}, "positive"),
    ({"form": '"taylor"'}, "affine"),
    ({"split": "0"}, "integer >= 1"),
    ({"tighten": "-1"}, "integer >= 0"),
    ({"tighten": "2.5"}, "integer >= 0"),
    # fix-v's leftover: a corner float64 cannot mean (1e300 mm) was certified
    # "unreachable 100 %"; refused as a pose query's (QA R 8), naming the corner
    ({"region": "{ lower = [0, 0, 1e300, 0, 0, 0], upper = [1, 0, 1e300, 0, 0, 0] }"},
     r"lower\[2\].*at most 5\.5e\+10 mm.*got 1e\+300 mm"),
    ({"region": "{ lower = [0, 0, 300, 0, 0, 0], upper = [1, 0, 300, 0, 0, 1e17] }"},
     r"upper\[5\].*rotation component"),
])
def test_bad_fields_are_rejected_at_load(fields, match):
    with pytest.raises(InputError, match=match):
        _scene(**fields)


def test_default_region_is_the_paper_cube():
    q = _scene().queries[0]
    p = q.params
    assert np.allclose(p.lower, [-0.075, -0.075, 0.225, 0, 0, 0])
    assert np.allclose(p.upper, [0.075, 0.075, 0.375, 0, 0, 0])
    assert p.min_width[0] == pytest.approx(0.15 / 16)


def test_query_json_volumes_resume_and_plot(tmp_path):
    """Hunt-type at zero rotation (Fig. 3): certified free; volumes add up to the
    region's; the second run loads every chunk from the store; the plot is written."""
    store = tmp_path / "store"
    fields = {"region": "{ lower = [-75, -75, 225, 0, 0, 0], upper = [75, 75, 375, 0, 0, 0] }",
              "min_width": "37.5", "workers": "1", "store": f'"{store.as_posix()}"'}
    scene = _scene(**fields)
    rec, texts, worst = run_scene(scene, plots_dir=tmp_path / "plots", progress=False)
    assert worst == 0, rec
    r = rec[0]["result"]
    assert r["total_volume"] == pytest.approx(0.15 ** 3, rel=1e-12)
    assert r["volume_unit"] == "m^3"
    assert r["regular_volume"] == pytest.approx(r["total_volume"], rel=1e-12)
    assert r["singular_volume"] == 0.0 and r["undecided_volume"] == 0.0
    total = sum(r[f"{n}_volume"] for n in ("regular", "singular", "undecided", "unreachable"))
    assert total == pytest.approx(r["total_volume"], rel=1e-12)
    assert r["regular_fraction"] == pytest.approx(1.0)
    boxes = r["boxes"]
    assert len(boxes["lower"]) == len(boxes["upper"]) == len(boxes["status"])
    assert set(boxes["legend"].values()) == {"regular", "singular", "undecided", "unreachable"}
    assert "mm" in texts[0] and "m^3" in texts[0]
    # the σmin bound: tightened (the default), never below the boxes' own minimum
    assert r["sigma_tightening"]["boxes"] > 0
    assert r["sigma_lower_min"] >= r["sigma_lower_min_boxes"] == min(
        s for s, st in zip(boxes["sigma_lower"], boxes["status"]) if st == 1)
    assert "the weakest bisected" in texts[0]
    assert any(Path(p).suffix == ".png" for p in rec[0].get("plots", [])) or \
        list((tmp_path / "plots").glob("*.png"))
    chunks = sorted(store.glob("chunk_*.npz"))
    assert len(chunks) == 8
    stamps = [c.stat().st_mtime_ns for c in chunks]
    assert r["chunks_resumed"] == 0 and "boxes per wall second" in texts[0]
    rec2, texts2, _ = run_scene(_scene(**fields), progress=False)
    assert [c.stat().st_mtime_ns for c in sorted(store.glob("chunk_*.npz"))] == stamps
    assert rec2[0]["result"]["boxes"]["status"] == boxes["status"]
    # nothing was computed: the report says so instead of a wall rate of loaded boxes
    assert rec2[0]["result"]["chunks_resumed"] == 8
    assert "all 8 chunks loaded from the store" in texts2[0]
    assert "per wall second" not in texts2[0]
    for c in chunks[:3]:                       # three chunks lost: computed again
        c.unlink()
    rec4, texts4, _ = run_scene(_scene(**fields), progress=False)
    assert rec4[0]["result"]["chunks_resumed"] == 5
    assert rec4[0]["result"]["boxes"]["status"] == boxes["status"]
    assert "(5 of the 8 chunks loaded from the store" in texts4[0]
    # a store made for another resolution is refused
    fields["min_width"] = "18.75"
    rec3, _, worst3 = run_scene(_scene(**fields), progress=False)
    assert worst3 == 2 and "chunk store" in rec3[0]["error"]["message"]


def test_process_pool_gives_the_in_process_result(tmp_path):
    """The same chunks on a local process pool (spawned workers) and in process."""
    from distkin.runstore import local_executor
    mech = preset("hexa")
    lo = np.array([-0.075, -0.075, 0.225, 0, 0, 0])
    hi = np.array([0.075, -0.025, 0.275, 0, 0, 0])
    minw = [0.025] * 3 + [1] * 3
    a = certify_workspace(mech, lo, hi, minw, split=2)
    with local_executor(2) as ex:
        b = certify_workspace(mech, lo, hi, minw, split=2, executor=ex,
                              store=tmp_path / "s")
    assert np.array_equal(a.status, b.status)
    assert np.array_equal(a.lo, b.lo) and np.array_equal(a.hi, b.hi)
    # the two rates: per wall second of the call, and per process (chunks' own seconds)
    s = b.summary()
    assert s["boxes_per_second"] == pytest.approx(b.evaluated / b.wall_seconds)
    assert s["boxes_per_process_second"] == pytest.approx(b.evaluated / b.seconds)


def test_initial_boxes_tile_the_region():
    lo = np.array([0, 0, 0.3, -0.1, 0, 0])
    hi = np.array([0.1, 0.2, 0.3, 0.1, 0, 0])
    boxes = initial_boxes(lo, hi, 3)
    assert len(boxes) == 27
    vol = sum(np.prod((b - a)[[0, 1, 3]]) for a, b in boxes)
    assert vol == pytest.approx(0.1 * 0.2 * 0.2, rel=1e-12)
    assert min(a[0] for a, _ in boxes) == 0 and max(b[1] for _, b in boxes) == 0.2


def test_cli_exit_code_2_for_a_non_certified_method(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text(SCENE.format(preset="hunt", fields='method = "fast"'), encoding="utf-8")
    r = subprocess.run([sys.executable, "-m", "distkin", "run", str(p)], capture_output=True,
                       text=True, cwd=ROOT, timeout=600)
    assert r.returncode == 2
    assert "certified" in r.stderr and "Traceback" not in r.stderr


def test_examples_load():
    from distkin.app.scene import load_scene
    for path in sorted((ROOT / "examples").glob("certify_*.toml")):
        scene = load_scene(path)
        assert scene.queries[0].type == "certify_workspace"


def test_json_document_is_valid(tmp_path):
    from distkin.app.report import document, dumps
    scene = _scene(region="{ lower = [0, 0, 290, 0, 0, 0], upper = [10, 10, 300, 0, 0, 0] }",
                   min_width="10", workers="1", store=f'"{(tmp_path / "s").as_posix()}"')
    rec, _, worst = run_scene(scene, progress=False)
    assert worst == 0
    doc = json.loads(dumps(document("test.toml", rec, "0")))
    assert doc["queries"][0]["result"]["regular_fraction"] == 1.0


def test_plot_legend_clears_the_axis_labels(tmp_path, monkeypatch):
    """The legend row of the Fig. 3 analogue sat on the x labels of the section panels
    (tight_layout kept 7 % of the height for it): every axis label's box must be clear
    of the legend's, measured in the drawn figure."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from distkin.certify.plot import plot_certificate
    drawn = []
    save = Figure.savefig

    def capture(fig, *args, **kwargs):
        fig.canvas.draw()
        r = fig.canvas.get_renderer()
        legend = fig.legends[0].get_window_extent(r)
        labels = [a.xaxis.label.get_window_extent(r) for a in fig.axes
                  if a.xaxis.label.get_text()]
        drawn.append((legend, labels))
        return save(fig, *args, **kwargs)
    monkeypatch.setattr(Figure, "savefig", capture)
    m = preset("hunt")
    cert = certify_workspace(m, [-0.075, -0.075, 0.225, 0, 0, 0],
                             [0.075, 0.075, 0.375, 0, 0, 0], [0.0375] * 3 + [1.0] * 3)
    plot_certificate(cert, tmp_path / "hunt")
    legend, labels = drawn[0]
    assert len(labels) >= 3
    assert not any(legend.overlaps(b) for b in labels)


LO, HI = [-0.075, -0.075, 0.225, 0, 0, 0], [0.075, 0.075, 0.375, 0, 0, 0]   # m, rad


@pytest.mark.parametrize("args, kwargs, field, words", [
    ((LO, HI, -0.01), {}, "min_width", "positive finite resolution"),
    ((LO, HI, 0.0), {}, "min_width", "got 0.0"),
    ((HI, LO, 0.04), {}, "upper", "lower[0] = 0.075 > upper[0] = -0.075"),
    ((LO[:3], HI[:3], 0.04), {}, "lower", "shape (6,)"),
    ((["abc"] * 6, HI, 0.04), {}, "lower", "numbers of shape"),
    ((LO, HI, 0.04), {"form": "quad"}, "form", "'quadratic64'"),
    ((LO, HI, 0.04), {"split": 0}, "split", ">= 1"),
])
def test_python_entry_point_checks_its_input(args, kwargs, field, words):
    """certify_workspace(...) from Python: a resolution <= 0 used to bisect until the box
    budget ran out (minutes, looking hung), lower > upper returned a certificate of an
    empty region, and the rest raised IndexError or numpy's ValueError (its form list
    left out the default, quadratic64)."""
    with pytest.raises(InputError) as exc:
        certify_workspace(preset("hunt"), *args, **kwargs)
    assert exc.value.field == field and words in exc.value.message
