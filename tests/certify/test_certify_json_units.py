"""The certify_workspace JSON states its units and gives each box's det Jx sign (QA F9),
and the σ wording names Jx's columns, not rows (QA F10: Jx is L x 6, its rows are legs).
The per-box signs are checked against det Jx of the fast tier at each regular box's
centre (an independent float evaluation, not the certifier's)."""

from __future__ import annotations

import numpy as np

from distkin.app.queries.certify import certificate_json, certificate_text
from distkin.certify import certify_workspace
from distkin.certify.boxes import REGULAR
from distkin.mechanisms import preset


def test_json_units_and_per_box_det_sign():
    mech = preset("hexa", layout="radial")
    cert = certify_workspace(mech, [-0.075, -0.075, 0.225, 0, 0, 0],
                             [0.075, 0.075, 0.375, 0, 0, 0], 0.15 / 8, tighten=0)
    js = certificate_json(cert)
    unit = js["unit"]
    for key in ("region", "min_width", "sigma_lower", "boxes"):
        assert key in unit
    assert js["boxes"]["units"] == "m, m, m, rad, rad, rad"
    reg = js["boxes"]["status"] == REGULAR
    centres = 0.5 * (cert.lo[reg] + cert.hi[reg])
    _, jx = mech.jq_jx(centres)
    assert jx.shape == (reg.sum(), 6, 6)
    assert np.array_equal(np.sign(np.linalg.det(jx)).astype(int), js["boxes"]["det_sign"][reg])
    # the two sides of the singular surface are both present in this region
    assert set(js["boxes"]["det_sign"][reg].tolist()) == set(js["det_signs"])
    text = certificate_text(cert, "mm", "deg")
    assert "moment columns 4-6 in m" in text and "rows" not in text
