"""Text and plots of the performance and certify_workspace queries in the scene's
declared length unit (QA: a cm scene printed "40 mm cube", "grid 40 mm", volumes in
"m^3 rad^3", drew Fig. 6 in mm with "z = 0.170 m" and the study's certified cube in mm
beside the certify query's in cm).  The references are the scene's ``[units]`` and the
JSON's SI numbers; the JSON itself stays SI."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

SCENE = """title = "griffis-duffy in cm"
[units]
length = "cm"
angle = "deg"

[mechanism]
kind = "legs"
name = "griffis_duffy"
octahedral = { base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]] }
height = 17
stroke = [14, 22]
force = 50
mass = "0.17"
inertia = "3e-4"

[[query]]
type = "performance"
grid = { half = 1, step = 1, rotation = 10, rotation_step = 10 }
actuators = { stall_force = 100, speed = 1 }
thresholds = { velocity = "0.5", acceleration = "9.81", force = 0 }
workers = 1
certify = true
certify_width = "1"

[[query]]
type = "certify_workspace"
region = { lower = [5, "sqrt(12)-1", 16, -5, -5, -5], upper = [7, "sqrt(12)+1", 18, 5, 5, 5] }
min_width = 1
min_angle = 5
tighten = 64
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    tmp = tmp_path_factory.mktemp("cm")
    figs = {}
    save = Figure.savefig

    def capture(fig, path, *args, **kwargs):
        fig.canvas.draw()
        figs[str(path)] = fig
        return save(fig, path, *args, **kwargs)
    mp = pytest.MonkeyPatch()
    mp.setattr(Figure, "savefig", capture)
    mp.setenv("DISTKIN_CACHE", str(tmp / "cache"))
    try:
        scene = loads_scene(SCENE, str(tmp / "gd.toml"))
        records, texts, worst = run_scene(scene, progress=False, plots_dir=tmp)
    finally:
        mp.undo()
    assert worst == 0, [r.get("error") for r in records]
    return records, texts, figs


def _length_labels(figs):
    out = []
    for path, fig in figs.items():
        for ax in fig.axes:
            for get in ("get_xlabel", "get_ylabel", "get_zlabel"):
                text = getattr(ax, get, lambda: "")()
                if re.match(r"^[xyz] \[", text):
                    out.append((path, text))
    return out


def test_every_plot_of_a_cm_scene_is_in_cm(run):
    _, _, figs = run
    labels = _length_labels(figs)
    names = {p.rsplit("/", 1)[-1] for p, _ in labels}
    assert {"q0_performance_griffis_duffy_fig6_plane.png",
            "q0_performance_griffis_duffy_certified_workspace.png",
            "q1_certify_workspace_certified_workspace.png",
            "q0_performance_griffis_duffy_fig5_workspace.png"} <= names
    assert all(t.endswith("[cm]") for _, t in labels), labels
    fig6 = next(f for p, f in figs.items() if p.endswith("fig6_plane.png"))
    assert "z = 17 cm" in fig6._suptitle.get_text()


def test_the_study_text_speaks_cm(run):
    records, texts, _ = run
    text = texts[0]
    dev = records[0]["result"]["devices"][0]
    half = dev["certificate"]["cube_half_m"]
    assert f"; {2 * half * 100:.4g} cm cube about home" in text
    edge = [c for c in dev["criteria"] if c["number"] == 4][0]["value"]["cube_edge_m"]
    assert f"grid {edge * 100:.4g} cm," in text
    dw = dev["dexterous_workspace"]
    assert f"= {dw['volume_m3'] * 1e6:.0f} cm³ of {dw['grid_volume_m3'] * 1e6:.0f} cm³" in text
    assert " mm" not in text.split("Table III analogue")[0]


def test_the_certify_text_gives_volumes_in_the_scene_units(run):
    records, texts, _ = run
    r, text = records[1]["result"], texts[1]
    assert r["volume_unit"] == "m^3 rad^3"                       # the JSON stays SI
    got = re.search(r"regular\s+(\S+) cm\^3 deg\^3 +\(100\.00 % of (\S+) cm\^3 deg\^3", text)
    assert got, text
    factor = 1e6 * (180 / math.pi) ** 3
    assert float(got.group(1)) == pytest.approx(r["regular_volume"] * factor, rel=1e-3)
    assert float(got.group(2)) == pytest.approx(r["total_volume"] * factor, rel=1e-3)
    assert not re.search(r"(?<![a-z])m\^3", text)          # no volume left in m^3
    # σmin(Jx) stays SI and says so: it is no length and does not convert
    assert "moment columns 4-6 in m, SI in a scene of any length unit" in text


def test_sigma_colour_bar_is_linear_over_a_narrow_range(run):
    from matplotlib import colors
    from distkin.certify.plot import sigma_norm
    _, _, figs = run
    bars = [ax for f in figs.values() for ax in f.axes if "σmin(Jx)" in ax.get_ylabel()]
    assert bars
    for ax in bars:
        lo, hi = ax.get_ylim()
        assert (ax.get_yscale() == "log") == (hi >= 10 * lo), (lo, hi, ax.get_yscale())
        if ax.get_yscale() == "linear":
            assert ax.yaxis.get_offset_text().get_text() == ""
    assert type(sigma_norm(np.array([0.055, 0.0558]))) is colors.Normalize
    assert type(sigma_norm(np.array([1e-3, 0.05]))) is colors.LogNorm


def test_a_mm_scene_gives_its_dexterous_workspace_in_mm3():
    from distkin.app.study_report import _cm3
    assert _cm3(3375e-6, "mm") == "3375000" and _cm3(3375e-6) == "3375"
    assert _cm3(64e-6, "m") == "6.4e-05"


def test_table_prints_min_and_max_of_one_value_alike():
    from distkin.app.study_tables import _f
    below = float(np.nextafter(1.0, 0.0))
    assert _f(below) == _f(1.0) == "1.000"
    assert _f(15168.2) == "15168" and _f(0.0236) == "0.0236"
