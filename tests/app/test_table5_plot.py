"""The ``table5`` query draws a plot with ``--plots`` (it said ``distkin: note: no plot
for query 0 (table5)``): ``q0_table5_comparison.png``, each Table V row relative to our
analysis beside the paper's columns, and one trial's time trace per row.

Reference: the query's own JSON.  The plot is read back from the matplotlib figure the
drawer builds (bar heights, the value written on each bar, the trial dots, the traces'
peak and mean lines), not from the drawer's inputs.  The run is the real one, on the
Octo's four worst poses (as tests/control/test_table5_traces.py) instead of the full
grid, which gives the same rows at a fraction of the cost."""

import json
import math

import numpy as np
import pytest

import distkin.app.queries.control as q5
import distkin.app.queries.table5_plot as t5plot
from distkin.app.cli import main
from distkin.control import table5
from distkin.numfmt import fixed

D30, D10 = math.pi / 6, math.pi / 18
#: the Octo's worst poses of the six rows over the default grid (m, rad)
WORST_POSES = np.array([[0.075, -0.075, 0.375, -D30, D10, D30],
                        [-0.075, -0.075, 0.300, D30, 0.0, D30],
                        [-0.075, 0.075, 0.375, -D30, -D30, -D30],
                        [0.075, 0.075, 0.300, -D30, 0.0, D30]])

SCENE = """
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "octo"
[[query]]
type = "table5"
trials = 2
step = 40
step_angle = 23
"""


#: what the fixture's run printed on stdout (the text report)
_RUN = {}


@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    """One ``distkin run --plots --json`` of the scene: (JSON record, stderr, the figure
    drawn, the plots folder)."""
    tmp = tmp_path_factory.mktemp("t5plot")
    scene = tmp / "t5.toml"
    scene.write_text(SCENE, encoding="utf-8")
    figs = []
    real_run, real_figure = table5.run_table5, t5plot.table5_figure

    def small(name, **kw):
        return real_run(name, poses=WORST_POSES, **kw)

    def spy(*a, **kw):
        figs.append(real_figure(*a, **kw))
        return figs[-1]

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(q5, "run_table5", small)
        mp.setattr(t5plot, "table5_figure", spy)
        import contextlib
        import io
        err, out = io.StringIO(), io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
            code = main(["run", str(scene), "--plots", str(tmp / "plots"), "--json",
                         str(tmp / "out.json"), "--no-progress"])
    assert code == 0, err.getvalue()
    rec = json.loads((tmp / "out.json").read_text(encoding="utf-8"))["queries"][0]
    assert len(figs) == 1
    _RUN["report"] = out.getvalue()
    return rec, err.getvalue(), figs[0], tmp / "plots"


def test_the_plot_is_written_and_listed(drawn):
    rec, err, _, plots = drawn
    assert "no plot for query" not in err and "plot failed" not in err, err
    assert "plot_error" not in rec
    png = plots / "q0_table5_comparison.png"
    assert rec["plots"] == [str(png)]
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # the traces are the plot's: the JSON rows are as without --plots
    for r in rec["result"]["rows"].values():
        assert "trace" not in r and r["emulated"] == float(np.mean(r["trial_values"]))


def _axes(fig):
    return {ax.get_gid(): ax for ax in fig.axes}


def test_the_bars_are_the_json_values_over_the_analysis(drawn):
    rec, _, fig, _ = drawn
    rows = rec["result"]["rows"]
    ax = _axes(fig)["comparison"]
    bars = {c.get_label(): [p.get_height() for p in c.patches] for c in ax.containers
            if hasattr(c, "patches")}
    assert set(bars) == {label for _, label, _ in t5plot.SERIES}
    texts = {t.get_gid(): t.get_text() for t in ax.texts if t.get_gid()}
    for key, label, _ in t5plot.SERIES:
        for h, (row, r) in zip(bars[label], rows.items()):
            assert h == r[key] / r["analysis"], (row, key)
            shown = str(r[key]) if key.startswith("paper_") else fixed(r[key])
            assert texts[f"value:{row}:{key}"] == f"{shown} {r['unit']}"
    assert bars[t5plot.SERIES[1][1]] == [1.0] * 6            # the analysis is the unit
    dots = next(line for line in ax.lines if line.get_gid() == "trials")
    want = [v / r["analysis"] for r in rows.values() for v in r["trial_values"]]
    assert list(dots.get_ydata()) == want and len(want) == 2 * 2 + 4
    assert [t.get_text().split("\n")[0] for t in ax.get_xticklabels()] == [
        row.replace("_", " ") for row in rows]
    assert "[1]" in ax.get_ylabel()


def test_the_traces_end_in_the_json_values(drawn):
    rec, _, fig, _ = drawn
    rows = rec["result"]["rows"]
    axes = _axes(fig)
    for row, r in rows.items():
        ax = axes[f"trace:{row}"]
        lines = {line.get_gid(): line for line in ax.lines}
        assert "[ms]" in ax.get_xlabel() and f"[{r['unit']}]" in ax.get_ylabel()
        assert "mm" in ax.get_title() and "deg" in ax.get_title()        # the pose's
        if r["kind"] == "free":
            assert lines["peak"].get_ydata()[0] == r["emulated"]
            assert max(lines["along"].get_ydata()) == r["emulated"]
        else:
            assert lines["trial_mean"].get_ydata()[0] == r["trial_values"][0]
            assert np.mean(lines["reading"].get_ydata()) == pytest.approx(
                r["trial_values"][0], rel=1e-12)
    assert "40 mm step" in axes["trace:velocity"].get_title()
    assert "23 deg rotation" in axes["trace:angular_velocity"].get_title()


def test_a_result_without_traces_or_a_paper_column_draws_the_comparison_alone(tmp_path):
    """The drawer on a result of two rows (hand-written: 10 N against an analysis of
    8 N; a paper column not printed, None) and no traces: one panel, the missing
    column drawn as nothing and written nowhere."""
    rows = {"force": {"unit": "N", "emulated": 10.0, "analysis": 8.0,
                      "paper_experiment": None, "paper_simulation": 16.02,
                      "pose": [0.0] * 6, "kind": "blocked"},
            "velocity": {"unit": "m/s", "emulated": 1.0, "analysis": 2.0,
                         "paper_experiment": 1.12, "paper_simulation": 2.93,
                         "pose": [0.0] * 6, "kind": "free"}}
    res = {"rows": rows, "step": 40.0, "step_angle": 23.0}
    fig = t5plot.table5_figure(res, None, length_unit="mm", angle_unit="deg")
    assert [ax.get_gid() for ax in fig.axes] == ["comparison"]
    ax = fig.axes[0]
    bars = {c.get_label(): [p.get_height() for p in c.patches] for c in ax.containers
            if hasattr(c, "patches")}
    assert bars[t5plot.SERIES[0][1]] == [1.25, 0.5]
    assert bars[t5plot.SERIES[2][1]] == [0.0, 0.56]          # not printed: no bar
    texts = {t.get_gid(): t.get_text() for t in ax.texts if t.get_gid()}
    assert "value:force:paper_experiment" not in texts
    assert texts["value:force:emulated"] == "10.00 N"
    assert texts["value:velocity:paper_experiment"] == "1.12 m/s"
    assert t5plot.plot_table5(tmp_path / "q3_table5", res) == [
        tmp_path / "q3_table5_comparison.png"]
    assert (tmp_path / "q3_table5_comparison.png").stat().st_size > 0


def _report():
    """The text report the fixture's run printed on stdout."""
    return _RUN["report"]


def test_the_header_counts_the_trials_each_row_ran(drawn):
    """The report's header said "(2 trials each)" while the free rows run once (their
    response is deterministic): it now says both counts, which the JSON's
    ``trial_values`` of each row confirm."""
    text = _report()
    assert "(2 trials of each blocked row, the mean; one of each free row" in text, text
    rows = drawn[0]["result"]["rows"]
    counts = {name: len(r["trial_values"]) for name, r in rows.items()}
    blocked = {"force", "torque"}
    assert blocked < set(counts) and len(counts) > 2, counts
    assert all(n == (2 if name in blocked else 1) for name, n in counts.items()), counts
