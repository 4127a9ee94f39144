"""The Fig. 3 analogue of a region at a non-zero rotation (QA F3): it was titled "zero
rotation" and every panel was empty, since no box contains zero rotation.  The slice is
now the region's rotation nearest to zero; checked against the certificate's own boxes
(the patches drawn in the z section are the boxes crossing it) and the title against the
region's fixed rotation written in degrees."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.certify import certify_workspace
from distkin.mechanisms import preset

RX = np.radians(10.0)


def _capture(monkeypatch):
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure
    drawn = []
    save = Figure.savefig

    def capture(fig, *args, **kwargs):
        drawn.append((fig._suptitle.get_text(), [len(a.patches) for a in fig.axes],
                      [t.get_text() for t in fig.legends[0].get_texts()]))
        return save(fig, *args, **kwargs)
    monkeypatch.setattr(Figure, "savefig", capture)
    return drawn


@pytest.fixture(scope="module")
def cert():
    return certify_workspace(preset("hexa", layout="radial"),
                             [-0.075, -0.075, 0.225, RX, 0, 0], [0.075, 0.075, 0.375, RX, 0, 0],
                             0.15 / 8, tighten=0)


def test_fixed_rotation_slice_is_drawn_and_named(cert, tmp_path, monkeypatch):
    from distkin.certify.plot import plot_certificate
    drawn = _capture(monkeypatch)
    assert not cert.at_zero_rotation().any()              # the old slice: empty
    assert np.allclose(cert.slice_rotation(), [RX, 0, 0])
    assert cert.at_rotation(cert.slice_rotation()).all()  # every box is at rx = 10°
    plot_certificate(cert, tmp_path / "hexa", length_unit="mm", angle_unit="deg")
    title, patches, legend = drawn[0]
    assert "zero rotation" not in title and "(10, 0, 0)°" in title
    # the z section draws one rectangle per box crossing its level: some, not none
    assert patches[1] > 0 and patches[3] > 0
    assert "undecided at the resolution" in legend        # budget not spent here


def test_json_names_the_slice(cert):
    from distkin.app.queries.certify import certificate_json
    js = certificate_json(cert)
    sl = js["rotation_slice"]
    assert sl["rotation"] == pytest.approx([RX, 0, 0]) and sl["units"] == "rad"
    assert sum(sl[k] for k in ("regular", "singular", "undecided", "unreachable")) == len(cert.status)
    assert sum(js["zero_rotation_slice"].values()) == 0


def test_rotation_range_excluding_zero(tmp_path, monkeypatch):
    """A 6-D-style region with rz in [10°, 30°]: the slice is rz = 10° (the nearest to
    zero), named as a projection."""
    from distkin.certify.plot import plot_certificate
    drawn = _capture(monkeypatch)
    lo = [-0.05, -0.05, 0.25, 0, 0, np.radians(10)]
    hi = [0.05, 0.05, 0.35, 0, 0, np.radians(30)]
    c = certify_workspace(preset("hunt"), lo, hi, [0.05] * 3 + [np.radians(10)] * 3, tighten=0)
    assert c.at_rotation(c.slice_rotation()).any()
    plot_certificate(c, tmp_path / "h", angle_unit="deg")
    title, patches, _ = drawn[0]
    assert "(0, 0, 10)°" in title and "projected" in title and patches[1] > 0
