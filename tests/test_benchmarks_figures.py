"""The benchmark figures (QA of fig25): drawn from the numbers in results.json by each
section's ``plot(data)``, which ``python -m benchmarks --replot`` calls without measuring;
every series visible (capability grids), every label clear of markers and of the other
labels (accuracy), each line of a twin-axes panel tied to its axis (GII sampling), and
the certify figures' certificates stored exactly enough to draw them again.

The references: the committed ``benchmarks/results.json`` (the numbers drawn must be
those), the figures' rendered pixels and text boxes, and a hand-built certificate."""

from __future__ import annotations

import json
import types
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")

import benchmarks.__main__ as bm                                        # noqa: E402
from benchmarks import plot_accuracy, plot_certify, plot_tradeoffs     # noqa: E402
from benchmarks.plotting import overlaps, text_box                     # noqa: E402

RESULTS = json.loads((Path(bm.__file__).parent / "results.json").read_text("utf-8"))


def _close(fig):
    import matplotlib.pyplot as plt
    plt.close(fig)


# ------------------------------------------------------------------ --replot
def test_replot_draws_the_stored_numbers_and_measures_nothing(tmp_path, monkeypatch,
                                                              capsys):
    stored = {"a": {"data": {"x": [1.5, 2.5]}}, "b": {"data": {"y": 3}}}
    (tmp_path / "results.json").write_text(json.dumps(stored), encoding="utf-8")
    seen = {}

    def run():
        raise AssertionError("--replot measured")

    def plot_a(data):
        seen["a"] = data
        return {"a.png": tmp_path / "a.png"}

    def plot_b(data):
        seen["b"] = data
        return {"b.png": "its boxes are not stored"}
    mods = {"a": types.SimpleNamespace(TITLE="A", run=run, plot=plot_a),
            "b": types.SimpleNamespace(TITLE="B", run=run, plot=plot_b),
            "c": types.SimpleNamespace(TITLE="C", run=run)}
    monkeypatch.setattr(bm, "MD", tmp_path / "BENCHMARKS.md")
    monkeypatch.setattr(bm, "JSON", tmp_path / "results.json")
    monkeypatch.setattr(bm, "modules", lambda: sorted(mods))
    monkeypatch.setattr(bm, "section_module", lambda n: mods[n])
    before = (tmp_path / "results.json").read_bytes()
    assert bm.main(["--replot", "a"]) == 0
    assert seen == {"a": stored["a"]["data"]}
    assert bm.main(["--replot"]) == 1                 # b's figure could not be drawn
    assert seen == {"a": stored["a"]["data"], "b": stored["b"]["data"]}
    err = capsys.readouterr().err
    assert "b.png not redrawn" in err and "its boxes are not stored" in err
    assert bm.main(["--replot", "c"]) == 2            # c draws no figure
    assert (tmp_path / "results.json").read_bytes() == before
    assert not (tmp_path / "BENCHMARKS.md").exists()


#: results.json contents --replot cannot draw from (QA 25b F5: tracebacks of
#: JSONDecodeError, KeyError 'data', KeyError 'rows'), each with the words the one-line
#: error must hold: the keys the plot modules document (plot_accuracy: accuracy.data
#: with ``rows`` and ``miscount``; every section's entry: {"data": ...} as a run writes)
BAD_RESULTS = {
    "truncated": ("{trunc", "accuracy", ["is not valid JSON", "line 1 column 2"]),
    "no data": ('{"accuracy": {"x": 1}}', "accuracy", ["'accuracy' has no \"data\""]),
    "no rows": ('{"accuracy": {"data": {}}}', "accuracy", ["accuracy.data has no key 'rows'"]),
    "no miscount": ('{"accuracy": {"data": {"rows": {}}}}', "accuracy",
                    ["accuracy.data has no key 'miscount'"]),
    "entry not an object": ('{"accuracy": 5}', "accuracy", ["'accuracy' is a number"]),
    "an array": ("[1, 2]", "accuracy", ["holds an array, expected an object"]),
    "section absent": ('{"tradeoffs": {"data": {}}}', "accuracy",
                       ["holds no numbers of 'accuracy'"]),
    "no figure named": ('{"certify": {"data": {}}}', "certify",
                        ["certify.data names no figure"]),
    "tradeoffs device": ('{"tradeoffs": {"data": {}}}', "tradeoffs",
                         ["tradeoffs.data has no key 'octopod'"]),
}


def _replot_isolated(tmp_path, monkeypatch, argv):
    """``main(argv)`` against a results.json in ``tmp_path`` (never the committed one),
    with every section's ``run`` failing the test if called (--replot measures nothing)."""
    def run():
        raise AssertionError("--replot measured")
    for name in bm.modules():
        monkeypatch.setattr(bm.section_module(name), "run", run)
    monkeypatch.setattr(bm, "MD", tmp_path / "BENCHMARKS.md")
    monkeypatch.setattr(bm, "JSON", tmp_path / "results.json")
    return bm.main(argv)


@pytest.mark.parametrize("case", sorted(BAD_RESULTS))
def test_replot_of_unusable_results_says_so_in_one_line(case, tmp_path, monkeypatch, capsys):
    text, section, words = BAD_RESULTS[case]
    path = tmp_path / "results.json"
    path.write_text(text, encoding="utf-8")
    before = sorted(p.name for p in tmp_path.iterdir())
    assert _replot_isolated(tmp_path, monkeypatch, ["--replot", section]) == 1
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert str(path) in lines[0] and all(w in lines[0] for w in words), lines[0]
    assert out == ""                                   # nothing said to be redrawn
    assert path.read_text(encoding="utf-8") == text    # results.json not rewritten
    assert sorted(p.name for p in tmp_path.iterdir()) == before   # no BENCHMARKS.md


def test_replot_without_results_json_says_the_file_is_missing(tmp_path, monkeypatch,
                                                                capsys):
    for argv in (["--replot"], ["--replot", "accuracy"]):
        assert _replot_isolated(tmp_path, monkeypatch, argv) == 1
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "does not exist" in err, err
        assert str(tmp_path / "results.json") in err and "no numbers of" not in err
    assert list(tmp_path.iterdir()) == []              # nothing written


def test_replot_of_an_unknown_name_is_not_a_section_without_figures(tmp_path, monkeypatch,
                                                                    capsys):
    """--replot foo said "['foo'] draw no figures", the words for a real section
    without figures; now an unknown name lists the sections, and a section without
    figures (tiers: no ``plot``) lists those with figures (exit 2 both)."""
    sections = bm.modules()
    with_figures = [n for n in sections if callable(getattr(bm.section_module(n), "plot",
                                                            None))]
    assert "tiers" in sections and "tiers" not in with_figures
    assert _replot_isolated(tmp_path, monkeypatch, ["--replot", "foo"]) == 2
    unknown = capsys.readouterr().err
    assert "no section named 'foo'" in unknown and "draws no figures" not in unknown
    assert all(n in unknown for n in sections), unknown
    assert _replot_isolated(tmp_path, monkeypatch, ["--replot", "tiers"]) == 2
    bare = capsys.readouterr().err
    assert "section 'tiers' draws no figures" in bare and "no section named" not in bare
    assert bare.strip().endswith(", ".join(with_figures))
    assert unknown.count("\n") == bare.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ accuracy
def test_accuracy_labels_cover_no_marker_and_no_other_label():
    data = RESULTS["accuracy"]["data"]
    fig, notes = plot_accuracy.accuracy_figure(data)
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    r = 0.5 * 9 * fig.dpi / 72                      # the largest marker: 9 pt
    from matplotlib.transforms import Bbox
    marks = []
    for row in data["rows"].values():
        px, py = ax.transData.transform((row["cpu_per_solve_median"] * 1e3,
                                         row["median_digits"]))
        marks.append(Bbox.from_extents(px - r, py - r, px + r, py + r))
    boxes = [text_box(n, renderer) for n in notes]
    assert [n.get_text() for n in notes] == list(data["rows"])
    for i, b in enumerate(boxes):
        assert frame.x0 <= b.x0 and b.x1 <= frame.x1 and frame.y0 <= b.y0 and b.y1 <= frame.y1
        assert not any(overlaps(b, m) for m in marks), notes[i].get_text()
        assert not any(overlaps(b, o) for j, o in enumerate(boxes) if j != i)
    _close(fig)


# ------------------------------------------------------------------ tradeoffs
def _pixels(fig, ax):
    """The RGB pixels (n, 3) inside ``ax`` of the rendered figure."""
    fig.canvas.draw()
    img = np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(int)
    b = ax.get_window_extent()
    h = img.shape[0]
    return img[int(h - b.y1) + 1:int(h - b.y0) - 1, int(b.x0) + 1:int(b.x1) - 1].reshape(-1, 3)


@pytest.mark.parametrize("device", ["octopod", "hexa"])
def test_every_capability_series_shows_with_the_stored_numbers(device):
    from matplotlib.colors import to_rgb
    d = RESULTS["tradeoffs"]["data"][device]
    fig = plot_tradeoffs.capability_figure(device, d)
    caps = list(d["table"])
    keys = [str(float(s)) for s in d["rot_steps_deg"]]
    for k, ax in enumerate(fig.axes[:2]):
        lines = [ln for ln in ax.get_lines() if not ln.get_label().startswith(("_", "0."))]
        assert len(lines) == len(caps) == 6
        px = _pixels(fig, ax)
        for n, ln in zip(caps, lines):
            want = ([100 * d["misses"][n][s]["worst_rel"] for s in keys] if k == 0 else
                    [100 * (d["table"][n]["grid_min"][s] / d["table"][n]["refined_min"] - 1)
                     for s in keys])
            assert list(ln.get_ydata()) == list(np.maximum(want, plot_tradeoffs.FLOOR))
            assert list(ln.get_xdata()) == [d["seconds"][s] for s in keys]
            rgb = np.round(255 * np.array(to_rgb(ln.get_color()))).astype(int)
            shown = np.sum(np.all(np.abs(px - rgb) <= 2, axis=1))
            assert shown > 10, f"{ln.get_label()} hidden in panel {k}"
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert len(labels) == 7 and "Continuous force (N)" in labels
    _close(fig)


def test_gii_panel_ties_each_line_to_its_axis():
    from matplotlib.colors import same_color
    d = RESULTS["tradeoffs"]["data"]
    fig = plot_tradeoffs.gii_figure(d["gii_octopod"]["runs"],
                                    d["gii_octopod"]["refined"]["gii"], d["gii_culling"])
    left, right = fig.axes[1], fig.axes[2]
    (t_line,), (g_line,) = left.get_lines(), right.get_lines()
    assert list(t_line.get_ydata()) == [s["seconds"] for s in d["gii_culling"]]
    assert list(g_line.get_ydata()) == [s["gii"] for s in d["gii_culling"]]
    assert same_color(left.yaxis.label.get_color(), t_line.get_color())
    assert same_color(right.yaxis.label.get_color(), g_line.get_color())
    assert not same_color(t_line.get_color(), g_line.get_color())
    fig.canvas.draw()
    for ax, ln in ((left, t_line), (right, g_line)):
        ticks = [t for t in ax.get_yticklabels() if t.get_text()]
        assert ticks and all(same_color(t.get_color(), ln.get_color()) for t in ticks)
    legend = left.get_legend()
    texts = [t.get_text() for t in legend.get_texts()]
    assert "left axis" in texts[0] and "right axis" in texts[1]
    _close(fig)


# ------------------------------------------------------------------ certify
def _certificate():
    """A hand-built certificate of a 3-D region (rotation fixed at 0): four boxes per
    axis along x, z split once, statuses of every kind, σ bounds not dyadic."""
    from distkin.certify.tighten import SigmaBound
    from distkin.certify.workspace import WorkspaceCertificate
    lower = np.array([-0.075, -0.075, 0.225, 0, 0, 0])
    upper = np.array([0.075, 0.075, 0.375, 0, 0, 0])
    xs, zs = np.linspace(-0.075, 0.075, 5), np.linspace(0.225, 0.375, 3)
    lo, hi = [], []
    for i in range(4):
        for k in range(2):
            lo.append([xs[i], -0.075, zs[k], 0, 0, 0])
            hi.append([xs[i + 1], 0.075, zs[k + 1], 0, 0, 0])
    lo, hi = np.array(lo), np.array(hi)
    status = np.array([1, 1, 2, 0, 1, 3, 1, 0], np.int8)
    sigma = np.where(status == 1, (np.arange(8) + 1) / 3e3, 0.0)
    tb = SigmaBound(value=1 / 7e3, initial=1 / 3e3, evaluated=6, seconds=0.25,
                    lo=lo[status == 1], hi=hi[status == 1], sigma=sigma[status == 1] * 1.1)
    return WorkspaceCertificate(
        mechanism=types.SimpleNamespace(name="hexa*", L=6), lower=lower, upper=upper,
        min_width=np.array([0.01] * 3 + [1] * 3), form="quadratic64", lo=lo, hi=hi,
        status=status, sigma_lower=sigma, det_sign=np.where(status == 1, -1, 0).astype(np.int8),
        evaluated=15, seconds=1.5, wall_seconds=0.9, chunks=8, sigma_bound=tb, resumed=0,
        budget=np.arange(8) == 3, max_boxes=100, reason=np.array([0, 0, 0, 0, 0, 0, 0, 3],
                                                                 np.int8))


def test_a_stored_certificate_is_the_certificate(tmp_path):
    cert = _certificate()
    rec = json.loads(json.dumps(plot_certify.certificate_record(cert)))
    assert rec["columns"] == [0, 1, 2]                # the fixed rotations not stored
    back = plot_certify.certificate_from_record(rec)
    for key in ("lower", "upper", "min_width", "lo", "hi", "status", "sigma_lower",
                "det_sign", "budget", "reason"):
        assert np.array_equal(getattr(back, key), getattr(cert, key)), key
        assert getattr(back, key).dtype == getattr(cert, key).dtype, key
    for key in ("lo", "hi", "sigma"):
        assert np.array_equal(getattr(back.sigma_bound, key), getattr(cert.sigma_bound, key))
    assert back.summary() == cert.summary()
    data = {"fig3": {"hexa, radial reading": {}, "hunt": {}},
            plot_certify.RECORDS: {"hexa, radial reading": rec}}
    out = plot_certify.plot(data, out=tmp_path)
    png = out["certify_hexa_radial_reading_certified_workspace.png"]
    assert png == tmp_path / "certify_hexa_radial_reading_certified_workspace.png"
    assert png.stat().st_size > 0
    assert "not in results.json" in out["certify_hunt_certified_workspace.png"]


@pytest.mark.parametrize("text", ["{trunc", "[1, 2]"])
def test_a_measuring_run_refuses_a_corrupt_results_json_before_measuring(
        text, tmp_path, monkeypatch, capsys):
    """``python -m benchmarks NAME`` read results.json with a bare json.loads: a
    corrupt file was a traceback (QA 25b), and a run writes the file whole, so going on
    would have dropped every other section's numbers.  Now one line, exit 2, nothing
    measured (every section's ``run`` fails the test if called), the file unchanged."""
    path = tmp_path / "results.json"
    path.write_text(text, encoding="utf-8")
    assert _replot_isolated(tmp_path, monkeypatch, ["tiers"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert "nothing measured" in err and str(path) in err
    assert path.read_text(encoding="utf-8") == text
    assert sorted(p.name for p in tmp_path.iterdir()) == ["results.json"]
