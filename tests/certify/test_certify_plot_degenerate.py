"""The certify plot of regions that do not vary x, y and z together (QA: a region varying
rx alone gave four empty panels and matplotlib's "identical low and high xlims" warning;
a line region along x was drawn as zero-height strips).  The plot now draws the
coordinates the region varies.  Checked against the certificate itself: every box is
drawn once, the drawn extents add up to the region's span in the scene's unit (the
region's bounds converted by hand, not by the plot's factors), and no warning is
raised."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from distkin.certify import certify_workspace
from distkin.mechanisms import preset

HUNT = preset("hunt")
D = np.radians


def _draw(cert, tmp_path, monkeypatch):
    """Plot with every warning an error; the figure's axes as drawn."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from distkin.certify.plot import plot_certificate
    figs = []
    save = Figure.savefig

    def capture(fig, *args, **kwargs):
        fig.canvas.draw()
        figs.append(fig)
        return save(fig, *args, **kwargs)
    monkeypatch.setattr(Figure, "savefig", capture)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = plot_certificate(cert, tmp_path / "c", length_unit="mm", angle_unit="deg")
    assert out.exists()
    return figs[0]


def _strip_widths(ax):
    return sorted(p.get_width() for p in ax.patches)


def test_rotation_only_region_is_a_strip_chart_along_rx(tmp_path, monkeypatch):
    cert = certify_workspace(HUNT, [0, 0, 0.3, -D(40), 0, 0], [0, 0, 0.3, D(40), 0, 0],
                             [0.01] * 3 + [D(10)] * 3, tighten=0)
    fig = _draw(cert, tmp_path, monkeypatch)
    strips = [a for a in fig.axes if a.get_xlabel() == "rx [deg]"]
    assert len(strips) == 2                              # status strip and σmin bounds
    status = strips[0]
    assert status.get_xlim() == pytest.approx((-40.0, 40.0))
    assert len(status.patches) == len(cert.status) > 1   # every box, none empty
    assert sum(_strip_widths(status)) == pytest.approx(80.0)
    assert all(p.get_height() > 0 for p in status.patches)
    assert "σmin(Jx)" in strips[1].get_ylabel() and "moment columns 4-6 in m" in \
        strips[1].get_ylabel().replace("\n", " ")
    assert "ry, rz = 0" in fig._suptitle.get_text()


def test_line_region_has_nonzero_strips(tmp_path, monkeypatch):
    cert = certify_workspace(HUNT, [-0.05, 0, 0.3, 0, 0, 0], [0.05, 0, 0.3, 0, 0, 0],
                             0.02, tighten=0)
    fig = _draw(cert, tmp_path, monkeypatch)
    status = next(a for a in fig.axes if a.get_xlabel() == "x [mm]" and a.patches)
    assert status.get_xlim() == pytest.approx((-50.0, 50.0))
    assert len(status.patches) == len(cert.status)
    assert sum(_strip_widths(status)) == pytest.approx(100.0)
    assert min(p.get_height() for p in status.patches) > 0
    assert "zero rotation" in fig._suptitle.get_text()


def test_plane_region_draws_its_plane(tmp_path, monkeypatch):
    """x and y vary, z fixed: no section of zero height, every box drawn in the plane."""
    cert = certify_workspace(HUNT, [-0.05, -0.05, 0.3, 0, 0, 0], [0.05, 0.05, 0.3, 0, 0, 0],
                             0.05, tighten=0)
    fig = _draw(cert, tmp_path, monkeypatch)
    planes = [a for a in fig.axes if a.get_xlabel() == "x [mm]"]
    assert len(planes) == 2
    for a in planes:
        assert a.get_ylabel() == "y [mm]"
        assert a.get_ylim() == pytest.approx((-50.0, 50.0))
        assert len(a.patches) == len(cert.status)
        area = sum(p.get_width() * p.get_height() for p in a.patches)
        assert area == pytest.approx(100.0 * 100.0)


def test_position_and_rotation_region(tmp_path, monkeypatch):
    """x and rx vary: the plane x, rx in mm and degrees."""
    cert = certify_workspace(HUNT, [-0.05, 0, 0.3, -D(20), 0, 0], [0.05, 0, 0.3, D(20), 0, 0],
                             [0.05] * 3 + [D(20)] * 3, tighten=0)
    fig = _draw(cert, tmp_path, monkeypatch)
    plane = next(a for a in fig.axes if a.get_xlabel() == "x [mm]")
    assert plane.get_ylabel() == "rx [deg]"
    assert plane.get_ylim() == pytest.approx((-20.0, 20.0))
    assert sum(p.get_width() * p.get_height() for p in plane.patches) == pytest.approx(4000.0)


def test_single_pose_is_one_panel_with_its_verdict(tmp_path, monkeypatch):
    pose = [0, 0, 0.3, 0, 0, 0]
    cert = certify_workspace(HUNT, pose, pose, 0.01, tighten=0)
    fig = _draw(cert, tmp_path, monkeypatch)
    assert len(fig.axes) == 1
    text = " ".join(t.get_text() for t in fig.axes[0].texts)
    # the fast tier at the pose: reachable and det Jx away from zero, so regular
    _, jx = HUNT.jq_jx(np.array([pose]))
    assert abs(np.linalg.det(jx[0])) > 1e-6
    assert "regular" in text and "z = 300 mm" in text and "rx = 0 deg" in text
