"""The mechanism and singularity plots say what their query says (QA plot audit): the
forward kinematics drawing's red legs against the query's own verdict, the jacobian
plot's heat map and singular values against the JSON's J, the drawings' lengths in the
scene's declared unit, the legs out of stroke named as the inverse_kinematics query
names them, a note for a query without a plot, the 6-6 modes drawn from the JSON's
poses, and the singularity path's scaling and undefined samples as the text states
them.  The figures are inspected (artists, labels, data), not pixels."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from distkin.app.cli import run_scene
from distkin.app.scene import loads_scene

RED = (0.8392156862745098, 0.15294117647058825, 0.1568627450980392, 1.0)   # tab:red


def _capture(monkeypatch):
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure
    figs = []
    save = Figure.savefig

    def capture(fig, *args, **kwargs):
        figs.append(fig)
        return save(fig, *args, **kwargs)
    monkeypatch.setattr(Figure, "savefig", capture)
    return figs


def _run(text, tmp_path):
    scene = loads_scene(text, str(tmp_path / "s.toml"))
    records, texts, worst = run_scene(scene, progress=False, plots_dir=tmp_path / "plots")
    assert worst == 0, [r.get("error") for r in records]
    return records, texts


def _drawn_red(ax):
    """Drawn (non-empty) lines of ``ax`` in tab:red."""
    from matplotlib.colors import to_rgba
    return [ln for ln in ax.get_lines()
            if len(ln.get_xdata()) and np.allclose(to_rgba(ln.get_color()), RED)]


def _legend_texts(ax):
    leg = ax.get_legend()
    return [t.get_text() for t in leg.get_texts()] if leg else []


OCTOPOD = """title = "octopod"
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "octopod"
"""

FK = OCTOPOD + """[[query]]
type = "forward_kinematics"
angles = [18.99, 21.35, 31.55, 32.47, 30.91, 31.52, 18.66, 20.50]
guess = [0, 0, 300, 0, 0, 0]
residual_tol = 0.01
"""


def test_fk_drawing_agrees_with_the_querys_verdict(tmp_path, monkeypatch):
    """Rounded (measured) angles of the Octopod verify within residual_tol: the drawing
    has no red leg, and its title states the query's residual and tolerance in mm (it
    drew every distal link red, "legs that do not close", beside "verified: yes")."""
    figs = _capture(monkeypatch)
    records, texts = _run(FK, tmp_path)
    res = records[0]["result"]
    assert res["verified"] is True
    ax = figs[0].axes[0]
    assert _drawn_red(ax) == []
    title = ax.get_title()
    assert f"residual_tol {res['residual_tol'] * 1e3:.3g} mm" in title
    assert f"rms closure residual {res['residual'] * 1e3:.3g} mm" in title
    assert "verified: yes" in title
    # the same numbers as the text report's verdict line
    assert re.search(rf"rms closure residual {res['residual'] * 1e3:.3g} mm <= residual_tol",
                     texts[0])


JAC = OCTOPOD + """[[query]]
type = "jacobian"
pose = [40, -30, 330, 15, -10, 20]
"""


def test_jacobian_plot_shows_j_its_units_and_singular_values(tmp_path, monkeypatch):
    """The jacobian plot draws J itself (the JSON's numbers), its columns labelled with
    the units the JSON's unit block gives, the singular values of the JSON and κ in a
    title (it was the inverse kinematics' pose drawing, byte for byte)."""
    figs = _capture(monkeypatch)
    records, _ = _run(JAC, tmp_path)
    res = records[0]["result"]
    row = res["poses"][0]
    fig, = figs
    images = [im for ax in fig.axes for im in ax.get_images()]
    assert len(images) == 1
    np.testing.assert_array_equal(np.asarray(images[0].get_array()), np.asarray(row["J"]))
    heat = images[0].axes
    lin = re.search(r"(\S+) \(columns 1-3\)", res["unit"]["J"]).group(1)
    ang = re.search(r"(\S+) \(columns 4-6\)", res["unit"]["J"]).group(1)
    labels = [t.get_text() for t in heat.get_xticklabels()]
    assert all(f"[{lin}]" in t for t in labels[:3]) and all(f"[{ang}]" in t for t in labels[3:])
    assert [t.get_text() for t in heat.get_yticklabels()] == [f"leg {i} (RSS)"
                                                             for i in range(1, 9)]
    stems = [c for ax in fig.axes for c in ax.containers if hasattr(c, "markerline")]
    assert len(stems) == 1
    np.testing.assert_allclose(stems[0].markerline.get_ydata(), row["singular_values"],
                               rtol=0, atol=0)
    assert any(f"κ = {row['kappa']:.6g}" in ax.get_title() for ax in fig.axes)


#: the example's Griffis-Duffy leg table (a cm scene), its queries replaced
GDI_MECHANISM = (Path(__file__).parents[2] / "examples" / "griffis_duffy_indices.toml"
                 ).read_text().split("[[query]]")[0]
GDI = GDI_MECHANISM + """[[query]]
type = "inverse_kinematics"
pose = [7, 4, 18, 10, -5, 15]
"""


def test_drawing_is_in_the_scenes_length_unit(tmp_path, monkeypatch):
    """A cm scene is drawn in cm: the axes say cm, the title gives the pose as the text
    report does, and the platform joints drawn are the mechanism's (m) times 100 (the
    drawing said "pose (70, 40, 180) mm" beside the text's "(7, 4, 18) cm")."""
    figs = _capture(monkeypatch)
    records, texts = _run(GDI, tmp_path)
    ax = figs[0].axes[0]
    assert [ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()] == ["x [cm]", "y [cm]",
                                                                  "z [cm]"]
    assert "pose (7, 4, 18) cm" in ax.get_title() and "(7, 4, 18) cm" in texts[0]
    scene = loads_scene(GDI, str(tmp_path / "s.toml"))
    pose = np.array(records[0]["result"]["poses"][0]["pose"], dtype=float)
    P = scene.mechanism.points(pose)["P"] / float(scene.units.length_factor)
    poly, = [ln for ln in ax.get_lines() if ln.get_label() == "platform joints"]
    drawn = np.array(poly.get_data_3d()).T[:-1]
    np.testing.assert_allclose(drawn, P, rtol=1e-12)


#: the example's 6-UPS Gough-Stewart platform (stroke 350 ... 550 mm), its queries replaced
GOUGH = (Path(__file__).parents[2] / "examples" / "gough_stewart_6ups.toml"
         ).read_text().split("[[query]]")[0] + """[[query]]
type = "inverse_kinematics"
poses = [[0, 0, 400, 0, 0, 0], [0, 0, 600, 0, 0, 0]]
"""


def test_unreachable_legs_are_named_with_the_reason(tmp_path, monkeypatch):
    """At a pose beyond the stroke the legend and title name the legs the query calls
    NOT reachable, as out of stroke with the stroke in mm (every leg was red under the
    swatch "UPS leg", no word of why); at the reachable pose no leg is red."""
    figs = _capture(monkeypatch)
    records, texts = _run(GOUGH, tmp_path)
    bad = re.search(r"pose 1: .*NOT reachable \(legs (\[[\d, ]+\])\)", texts[0]).group(1)
    ok_ax, bad_ax = (f.axes[0] for f in figs)
    assert _drawn_red(ok_ax) == [] and "every leg reaches" in ok_ax.get_title()
    assert len(_drawn_red(bad_ax)) == len(eval(bad)) == 6
    legend = _legend_texts(bad_ax)
    assert f"red: NOT reachable: out of stroke: legs {bad}" in legend
    assert all(any(t.strip().startswith(f"leg {i}:") and "outside its stroke [350, 550] mm"
                   in t for t in legend) for i in eval(bad))
    assert f"red: legs {bad} out of stroke" in bad_ax.get_title()
    assert "UPS leg" not in legend          # no blue swatch: no leg is within its stroke


def test_a_query_without_plot_says_so(tmp_path, capsys):
    """--plots and a query that has no plot: one note on stderr naming it (it produced
    nothing, silently)."""
    text = GOUGH.replace('type = "inverse_kinematics"', 'type = "singularity"').replace(
        "poses = [[0, 0, 400, 0, 0, 0], [0, 0, 600, 0, 0, 0]]", "pose = [0, 0, 400, 0, 0, 0]")
    records, _ = _run(text, tmp_path)
    assert "plots" not in records[0]
    assert "distkin: note: no plot for query 0 (singularity)" in capsys.readouterr().err


P66 = """title = "6-6"
[units]
length = "none"
[mechanism]
kind = "platform66"
base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]
[[query]]
type = "forward_kinematics"
legs = ["6/25*sqrt(6170)", "6/5*sqrt(221)", "1/5*sqrt(7349)",
        "1/50*sqrt(674605)", "1/25*sqrt(136210)", "1/5*sqrt(8153)"]
method = "fast"
"""


def test_platform66_modes_are_drawn_from_the_result(tmp_path, monkeypatch):
    """The 6-6 forward kinematics has a plot (it had none): one panel per s15 root, each
    drawing the platform joints of a pose of the JSON (the mirror above the base) and
    titled with its number as the report counts it."""
    figs = _capture(monkeypatch)
    records, texts = _run(P66, tmp_path)
    res = records[0]["result"]
    fig, = figs
    assert len(fig.axes) == len({p["s15"] for p in res["poses"]}) == res["count"] // 2
    for ax in fig.axes:
        k = int(re.match(r"pose (\d+):", ax.get_title()).group(1))
        pose = res["poses"][k - 1]
        assert f"pose {k:2d}: s15 = {pose['s15']:.8g}" in texts[0]
        assert pose["translation"][2] > 0
        plat, = [ln for ln in ax.get_lines() if ln.get_color() == "tab:blue"]
        drawn = np.array(plat.get_data_3d()).T[:-1]
        pj = np.asarray(pose["platform_joints"], dtype=float)
        assert all(np.min(np.linalg.norm(pj - x, axis=1)) < 1e-12 for x in drawn)


def test_singularity_path_plot_states_its_scaling_and_undefined_samples(tmp_path,
                                                                        monkeypatch):
    """The built-in Δ scene's path: the y label and legend say what det J and the four
    planes are divided by, and the sample the text calls undefined (the signed CM form
    at s = 0) is marked at the s the report names."""
    from importlib import resources
    figs = _capture(monkeypatch)
    scene_text = (resources.files("distkin") / "scenes" / "delta_griffis_duffy.toml"
                  ).read_text()
    records, texts = _run(scene_text, tmp_path)
    k = next(i for i, r in enumerate(records) if r["type"] == "singularity"
             and "crossings" in r["result"] and "samples" in r["result"])
    said = re.search(r"the signed CM form undefined at 1 of the \d+ samples \(s = ([\d.]+)\)",
                     texts[k])
    assert said, texts[k]
    ax = next(f.axes[0] for f in figs if f.axes[0].get_title() ==
              "Singularity tests along the path")
    assert "max |value|" in ax.get_ylabel()
    legend = _legend_texts(ax)
    assert any(t.startswith("det J (eq. 5) / its max |value| on the path") for t in legend)
    mark, = [ln for ln in ax.get_lines() if "undefined" in ln.get_label()]
    assert f"s = {said.group(1)}" in mark.get_label()
    assert list(mark.get_xdata()) == [pytest.approx(float(said.group(1)), abs=1e-9)]


GDI_PATH = GDI.replace("""[[query]]
type = "inverse_kinematics"
pose = [7, 4, 18, 10, -5, 15]
""", """[[query]]
type = "singularity"
path = { from = [6, "sqrt(12)", 17, 0, 0, 0], to = [6, "sqrt(12)", 17, 0, 0, 180], samples = 30 }
""")


def test_leg_singularity_path_has_a_plot(tmp_path, monkeypatch):
    """The leg-table singularity query along a path draws det J with the crossing the
    JSON gives (it had no plot): the twist's crossing at 90° of 180° is at s = 1/2."""
    figs = _capture(monkeypatch)
    records, _ = _run(GDI_PATH, tmp_path)
    res = records[0]["result"]
    assert len(res["crossings"]) == 1 and "plots" in records[0]
    ax = figs[0].axes[0]
    det = [ln for ln in ax.get_lines() if ln.get_label().startswith("det J (eq. 5)")]
    dets = np.array([r["det_J"] for r in res["poses"]], dtype=float)
    np.testing.assert_allclose(det[0].get_ydata() * np.max(np.abs(dets)), dets, rtol=1e-12)
    cross = [ln for ln in ax.get_lines() if ln.get_label() == "det J = 0 (crossing)"]
    s = res["crossings"][0]["pose"][5] / np.pi
    assert cross[0].get_xdata()[0] == pytest.approx(s, abs=1e-9) == pytest.approx(0.5)
