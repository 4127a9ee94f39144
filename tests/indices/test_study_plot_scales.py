"""The study's figures in the scene's units and on honest scales (QA audit of the plots):
Fig. 6 in mm and "z = 0.170 m" in a cm scene, a colour-bar offset "+2.8867e1" over ticks
of 0.0005, one near-singular cell taking a whole linear scale, a 40 mm cube drawn as a
tall box, Table III bars on a log axis whose floor sat under the smallest value (a
min = max = 1.0 m/s bar invisible), "paper min/max" in the legend of a device the paper
does not have, and a worst case "0.00 N" beside a table's 6.182e-05 N.  Each test reads
the matplotlib Figure (labels, scales, data) and compares it with the data passed in."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.fixture
def figs(monkeypatch):
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure
    out = []
    save = Figure.savefig

    def capture(fig, *args, **kwargs):
        fig.canvas.draw()
        out.append(fig)
        return save(fig, *args, **kwargs)
    monkeypatch.setattr(Figure, "savefig", capture)
    return out


XS = np.array([0.04, 0.05, 0.06, 0.07, 0.08])           # m: a cm scene's 4 .. 8 cm


def _panels():
    X, Y = np.meshgrid(XS, XS - 0.03, indexing="ij")
    smooth = 44 + 100 * (X - 0.06) ** 2 + 50 * Y
    outlier = 7.0 + 0.3 * np.sin(40 * X) * np.cos(30 * Y)
    outlier[0, 0] = 1e-4                                 # one near-singular cell
    decades = 10.0 ** (1 + 60 * (X - 0.04))             # 10 .. 1e3.4: spans decades
    return [("Continuous force", "N", smooth),
            ("Velocity", "m/s", np.ones_like(X) + 1e-13 * X),          # constant
            ("Angular velocity", "rad/s", 28.8675 + 1e-5 * 28.8675 * X / 0.08),
            ("Acceleration", "m/s²", outlier),
            ("Angular acceleration", "rad/s²", decades),
            ("Continuous torque", "N·m", smooth / 20)]


def test_fig6_follows_the_scene_unit_and_its_scales_say_what_they_are(tmp_path, figs):
    from matplotlib import colors
    from distkin.indices.plots import plot_plane
    plot_plane(tmp_path / "p", "gd", XS, XS - 0.03, 0.17, _panels(), 10.0, length_unit="cm")
    fig = figs[0]
    assert "z = 17 cm" in fig._suptitle.get_text()
    data = {ax.get_title().split("\n")[0]: ax for ax in fig.axes if ax.get_xlabel()}
    for ax in data.values():
        assert (ax.get_xlabel(), ax.get_ylabel()) == ("x [cm]", "y [cm]")
        mesh = ax.collections[0]
        cx = mesh.get_coordinates()[:, :, 0] if hasattr(mesh, "get_coordinates") else None
        if cx is not None:        # cell edges around the centres 4 .. 8 cm
            assert cx.min() == pytest.approx(3.5) and cx.max() == pytest.approx(8.5)
    # constant: no colour map, the value in words
    assert "constant = 1 m/s" in data["Velocity"].get_title()
    bars = {ax.get_ylabel().split(" (")[0]: ax for ax in fig.axes if not ax.get_xlabel()}
    assert "m/s" not in bars
    # a real variation of 1e-5 relative: no offset above the ticks, every tick in full
    av = bars["rad/s"]
    assert av.yaxis.get_offset_text().get_text() == ""
    ticks = [float(t.get_text().replace("−", "-")) for t in av.get_yticklabels() if t.get_text()]
    assert ticks and all(28.8 < t < 28.9 for t in ticks)
    # one near-singular cell: clipped to the percentiles, said in the colour-bar label
    norm = data["Acceleration"].collections[0].norm
    v = _panels()[3][2]
    assert norm.vmin > 1.0 and norm.vmin >= np.sort(v.ravel())[1] - 1e-12
    assert "clipped" in bars["m/s²"].get_ylabel()
    # values spanning decades: a log scale, said in the label
    assert isinstance(data["Angular acceleration"].collections[0].norm, colors.LogNorm)
    assert "log scale" in bars["rad/s²"].get_ylabel()
    # an ordinary panel: linear over its data
    n = data["Continuous force"].collections[0].norm
    assert (n.vmin, n.vmax) == (_panels()[0][2].min(), _panels()[0][2].max())


def test_fig5_draws_a_cube_as_a_cube_in_the_scene_unit(tmp_path, figs):
    from distkin.indices.plots import plot_workspace
    rng = np.random.default_rng(1)
    reach = rng.uniform([-0.05, -0.04, 0.10], [0.17, 0.10, 0.21], (400, 3))
    plot_workspace(tmp_path / "w", "gd", reach, 0.02, (0.06, 0.035, 0.17), length_unit="cm")
    ax = figs[0].axes[0]
    assert [ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()] == ["x [cm]", "y [cm]",
                                                                  "z [cm]"]
    assert "4 cm cube" in ax.get_title()
    spans = np.array([np.diff(ax.get_xlim3d())[0], np.diff(ax.get_ylim3d())[0],
                      np.diff(ax.get_zlim3d())[0]])
    box = np.array(ax.get_box_aspect())
    assert np.allclose(box / box[0], spans / spans[0])      # equal scales on x, y, z
    want = np.ptp(np.r_[reach[:, 0], 0.04, 0.08]) * 100     # the data's x range, in cm
    assert spans[0] == pytest.approx(want)


def _summary(label, table, iso, paper=False):
    from distkin.indices.study import CAPABILITIES, SENSITIVITIES
    rows = [c[:3] for c in CAPABILITIES] + [s[:3] for s in SENSITIVITIES]
    out = {"label": label, "table": {}, "isotropy": {"rotation_deg": 20.0, **iso}}
    for q, _, unit in rows:
        lo, hi = table.get(q, (1.0, 2.0))
        out["table"][q] = {"min": lo, "max": hi, "unit": unit}
        if paper:
            out["table"][q].update(paper_min=lo / 2, paper_max=hi * 2)
    return out


def test_table3_of_one_device_draws_its_range_without_paper_entries(tmp_path, figs):
    from distkin.indices.plots import plot_table3_bars
    s = _summary("griffis_duffy", {"force": (40.34, 54.63), "velocity": (1.0, 1.0)},
                 {"gii": 0.15, "sigma_min": 0.02, "sigma_max": 0.16})
    plot_table3_bars(tmp_path / "t", [s])
    fig = figs[0]
    head = fig._suptitle.get_text()
    assert "griffis_duffy" in head and "Ergin" not in head and "Kühne" not in head
    labels = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert labels and not any("paper" in t for t in labels)
    assert all(ax.get_legend() is None for ax in fig.axes)   # the legend is off the data
    ax = {a.get_title().split(" [")[0]: a for a in fig.axes}
    force, vel = ax["Continuous force"], ax["Velocity"]
    assert force.get_yscale() == "linear"
    ys = sorted(float(y) for line in force.lines for y in line.get_ydata())
    assert ys == [40.34, 54.63]
    lo, hi = force.get_ylim()
    assert lo < 40.34 and hi > 54.63
    # min = max = 1.0: both dots drawn at 1.0, inside the axis
    vy = [float(y) for line in vel.lines for y in line.get_ydata()]
    assert vy == [1.0, 1.0] and vel.get_ylim()[0] < 1.0 < vel.get_ylim()[1]


def test_table4_puts_the_paper_beside_ours_only_where_it_has_a_value(tmp_path, figs):
    from distkin.indices.plots import plot_table4_bars
    a = _summary("HEXA", {}, {"gii": 0.0237, "sigma_min": 0.052, "sigma_max": 2.2})
    b = _summary("Octo", {}, {"gii": 0.0818, "sigma_min": 0.12, "sigma_max": 1.49,
                              "paper_gii": 0.0072, "paper_sigma_min": 0.191,
                              "paper_sigma_max": 26.64})
    plot_table4_bars(tmp_path / "t", [a, b])
    fig = figs[0]
    assert all(ax.get_legend() is None for ax in fig.axes)
    assert fig.legends and "HEXA, Octo" in fig._suptitle.get_text()
    gii = fig.axes[0]
    paper = [line for line in gii.lines if line.get_color() == "tab:orange"]
    assert len(paper) == 1
    py = np.asarray(paper[0].get_ydata(), dtype=float)
    assert np.isnan(py[0]) and py[1] == 0.0072             # HEXA: no paper dot
    texts = {t.get_text() for t in gii.texts}
    assert {"0.0237", "0.0818", "0.0072"} <= texts


def test_force_polytope_title_has_the_worst_case_in_significant_digits(tmp_path, figs):
    from distkin.indices.plots import force_slice_polytope, plot_force_polytope
    rng = np.random.default_rng(3)
    Gw = rng.normal(size=(6, 6))
    limit = 1e-4
    radius = force_slice_polytope(Gw, limit)[2]
    plot_force_polytope(tmp_path / "f", "ergin", Gw, limit, [0.01, 0.0, 0.3, 0.1, 0, 0],
                        length_unit="mm")
    title = figs[0].axes[0].get_title()
    assert radius < 1e-3
    assert f"worst case {radius:.4g} N" in title and "0.00 N" not in title
    assert "(10, 0, 300) mm" in title
