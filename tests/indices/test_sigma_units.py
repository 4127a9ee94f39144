"""σmin and σmax of W = ST⁻¹Jᵀ carry a unit (QA 25a F5): the reciprocal of the actuator
effort, 1/(N·m) for revolute actuators and 1/N for prismatic ones; only κ and the GII
are dimensionless.  They were labelled "dimensionless" (design_sweep text and JSON,
docstrings) and Table IV printed them without a unit.

Reference: dimensional analysis done numerically, independent of the labels: the same
mechanism written with another length unit (mm) or force unit (kN) must scale σ by the
unit's factor to the power the label says (a dimensionless σ would not change); Kühne
et al. Sec. III-B-2: ST = diag(15 N, 15 N, 15 N, 1 N·m, 1 N·m, 1 N·m), f = Jᵀτ (eq. (3))."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from distkin.indices.actuators import leg_limits, limit_text
from distkin.indices.isotropy import ST_DEFAULT, SIGMA_UNITS, scaled_singular_values, sigma_unit
from distkin.indices.study import ACTUATORS, Device, study_chunk, summarise
from distkin.indices.workspace import PoseGrid
from distkin.mechanisms.platforms import platform_mechanism

BASE = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
PLAT = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
PRISMATIC_ACT = {"nominal_force": 50.0, "stall_force": 100.0, "speed": 1.0}


def _gd():
    """Griffis-Duffy with prismatic legs (rows of J: m/m, m/rad), force limits 50 N."""
    m = platform_mechanism((BASE, PLAT), unit=0.01, height=17, name="gd_units",
                           mass=0.17, inertia=3e-4, route="numpy")
    return dataclasses.replace(m, leg_table=tuple(dataclasses.replace(leg, limit=(-50, 50))
                                                  for leg in m.leg_table))


def _sigma_in_units(J, length, force):
    """σ of ST⁻¹Jᵀ with lengths in units of ``length`` m and forces in ``force`` N, for
    J's rows: the translational columns of a revolute row are rad per length (÷ length
    factor), its angular columns rad/rad; a prismatic row is length/length and
    length/rad (× 1/length).  Returns the revolute and prismatic variants' inputs."""
    st = np.asarray(ST_DEFAULT) / force
    st[3:] /= length                                    # N·m -> force·length units
    return st


def test_sigma_scales_as_its_unit_says(presets):
    hunt, gd = presets["hunt"], _gd()
    for mech, pris, a in ((hunt, False, 1), (gd, True, 0)):
        J = mech.jacobian(mech.home)[None]
        smin, smax = scaled_singular_values(J)
        for length, force in ((1e-3, 1.0), (1.0, 1e3), (1e-3, 1e3)):
            Jn = J.copy()
            if pris:
                Jn[..., 3:] /= length                  # m/rad -> mm/rad
            else:
                Jn[..., :3] *= length                  # rad/m -> rad/mm
            s2 = scaled_singular_values(Jn, _sigma_in_units(J, length, force))
            # 1/(N·m): σ per mm·... is σ × length^a × force; 1/N: σ × force
            factor = length ** a * force
            assert s2[1] == pytest.approx(smax * factor, rel=1e-12)
            assert s2[0] == pytest.approx(smin * factor, rel=1e-12)
        assert sigma_unit([pris] * mech.L) == ("1/N" if pris else "1/(N·m)")
    assert sigma_unit([True, False]) == "mixed (1/(N·m) revolute, 1/N prismatic columns)"
    assert sigma_unit([True], "wrench_nominal") == "1" and sigma_unit(False, "jx") == "1/N"
    assert "dimensionless" not in " ".join(str(v) for v in SIGMA_UNITS.values())


def _summary(label, mech, paper, act):
    grid = PoseGrid((0.0,), (0.0,), (float(mech.home[2]),), (0.0,), (0.0,), (0.0,))
    per = study_chunk({"mech": mech, "grid": grid, "lo": 0, "hi": 1, "actuators": act,
                       "ST": ST_DEFAULT, "inner": None, "route": "numpy",
                       "compiled": False})        # no compiled kernels to load
    s = summarise(Device(label, mech, grid, paper), per)
    lim = leg_limits(mech, act)
    s["actuator_limits"] = {"prismatic": lim["prismatic"].tolist(),
                            "text": {w: limit_text(lim, w) for w in ("nominal", "stall",
                                                                      "rate")}}
    return s


def test_table4_prints_the_sigma_unit(presets):
    from distkin.app.study_tables import markdown_tables
    hunt = _summary("Hunt-type", presets["hunt"], "hunt", ACTUATORS)
    md = markdown_tables([hunt])
    t4 = md[md.index("Table IV analogue"):]
    assert "| σmin ours [1/(N·m)] |" in t4 and "| σmax ours [1/(N·m)] |" in t4
    assert "The GII is dimensionless" in t4
    assert "ST⁻¹Jᵀ (chosen): 1/(N·m)" in t4 and "J#ᵀ·ST = pinv(ST⁻¹Jᵀ): N·m" in t4
    # a prismatic device beside it: the unit by device, in the first column
    gd = _summary("GD", _gd(), None, PRISMATIC_ACT)
    t4 = markdown_tables([hunt, gd])
    t4 = t4[t4.index("Table IV analogue"):]
    assert "| σmin ours [unit] |" in t4
    assert "| Hunt-type (σ in 1/(N·m)) |" in t4 and "| GD (σ in 1/N) |" in t4


def test_json_units_of_the_study_name_the_sigma_unit():
    from distkin.app.study_report import _units_block
    iso = _units_block(ACTUATORS)["devices[].isotropy"]
    assert "1/(N·m) for revolute actuators, 1/N for prismatic" in iso
    assert "gii, gii_full_range, readings[].gii: 1 (dimensionless)" in iso
