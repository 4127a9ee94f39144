"""The study's plots say what they cannot draw and carry units (QA IX 7): the paper's
0.00 minima for Ergin's device vanished on the Table III chart's log axis without a
note; the σmin-margin colorbar of the certified-workspace plot had no unit.  References:
the paper's Table III as printed (the seed text: Ergin's force, torque, acceleration and
angular acceleration minima are 0.00) and the units the certify_workspace report states
for σmin(Jx)."""

from __future__ import annotations

import pytest

#: Kühne et al. Table III, Ergin's device, min column as printed (0.00 four times)
ERGIN_ZERO_MINIMA = {"Continuous force", "Continuous torque", "Acceleration",
                     "Angular acceleration"}


def _capture(monkeypatch):
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure
    figs = []
    save = Figure.savefig

    def capture(fig, *args, **kwargs):
        fig.canvas.draw()
        figs.append(fig)
        return save(fig, *args, **kwargs)
    monkeypatch.setattr(Figure, "savefig", capture)
    return figs


def test_table3_marks_the_papers_zero_minima(tmp_path, monkeypatch):
    from distkin.indices.plots import plot_table3_bars
    from distkin.indices.study import CAPABILITIES, PAPER_TABLE3, SENSITIVITIES
    figs = _capture(monkeypatch)
    rows = [c[:3] for c in CAPABILITIES] + [s[:3] for s in SENSITIVITIES]
    summary = {"label": "Ergin's device",
               "table": {q: {"min": 1.0, "max": 2.0, "unit": unit,
                             "paper_min": PAPER_TABLE3["ergin"][q][0],
                             "paper_max": PAPER_TABLE3["ergin"][q][1]}
                         for q, _, unit in rows}}
    plot_table3_bars(tmp_path / "t", [summary])
    fig = figs[0]
    marked = {ax.get_title().split(" [")[0] for ax in fig.axes
              if any(t.get_text() == "0" for t in ax.texts)}
    assert marked == ERGIN_ZERO_MINIMA
    assert "0" in fig._suptitle.get_text() and "log axis" in fig._suptitle.get_text()


CERTIFY = """title = "hunt cube"
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "hunt"
[[query]]
type = "certify_workspace"
method = "certified"
region = { lower = [-75, -75, 225, 0, 0, 0], upper = [75, 75, 375, 0, 0, 0] }
min_width = 37.5
workers = 1
"""


def test_certificate_colorbar_has_the_reports_units(tmp_path, monkeypatch):
    """The colorbar of the σmin-margin map states the units the text report gives for
    σmin(Jx), taken from the report of the same region."""
    import re

    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    figs = _capture(monkeypatch)
    scene = loads_scene(CERTIFY, str(tmp_path / "c.toml"))
    records, texts, worst = run_scene(scene, progress=False, plots_dir=tmp_path)
    assert worst == 0, records[0].get("error")
    units = re.search(r"σmin\(Jx\) >= \S+ \(certified[^;]*; Jx is L x 6: ([^)]*)\)",
                      texts[0])
    assert units, texts[0]
    bars = [ax.get_ylabel() for f in figs for ax in f.axes if "σmin(Jx)" in ax.get_ylabel()]
    assert len(bars) == 1, [ax.get_ylabel() for f in figs for ax in f.axes]
    assert units.group(1) in bars[0].replace("\n", " ")
