"""Presets built through the Python API check what the scene path checks (QA): a length
override 100x off the preset's value warns as the scene does (a unit slip), a home pose
some leg does not reach warns, and ``ld = 0`` (the two legs of a pair at one pivot) is
refused when built, naming ``ld`` with units."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from distkin.app.mechanism_scene import unit_slips
from distkin.app.scene import loads_scene
from distkin.app.units import parse_units
from distkin.errors import InputError
from distkin.mechanisms import GeometryWarning, LegMechanism, preset
from distkin.mechanisms.presets import PRESETS


def test_presets_and_layouts_build_without_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error", GeometryWarning)
        for name in PRESETS:
            for layout in ("tangential", "radial", "tangential_in"):
                preset(name, layout=layout)
        preset("octo", l0=0.165, z0=0.31)


@pytest.mark.parametrize("k, v", [("l0", 160.0), ("z0", 300.0), ("ld", 2e-5),
                                  ("mass", 170.0)])
def test_unit_slip_warns_as_the_scene_path(k, v):
    """The Python API's warning carries the scene path's own words (unit_slips of
    distkin.app.mechanism_scene, a scene in m given the same value)."""
    scene = unit_slips("octo", {k: v}, {k: f"{v:g}"}, parse_units({"length": "m"}), "mechanism")
    assert len(scene) == 1
    shown = scene[0].split(": ", 1)[1].split(" (")[0]   # "160 m is 1e+03 x the preset's 0.16 m"
    with pytest.warns(GeometryWarning) as rec:
        preset("octo", **{k: v})
    assert any(str(w.message).startswith(f"{k}: {shown} (") for w in rec), \
        [str(w.message) for w in rec]


@pytest.mark.parametrize("over", [dict(l0=160.0), dict(z0=300.0), dict(l3=0.05)])
def test_unreachable_home_warns(over):
    """The margins the warning reports are the leg table's own (the plain-numpy route's
    reach margin at home, an independent implementation), and they are negative."""
    with pytest.warns(GeometryWarning) as rec:                 # and l0, z0: a unit slip
        m = preset("octo", **over)
    assert any(str(w.message).startswith("home: expected a home pose (0, 0, z0) that every "
                                         "leg reaches") for w in rec)
    with warnings.catch_warnings():            # the leg table of it warns again
        warnings.simplefilter("ignore", GeometryWarning)
        legs = LegMechanism.from_description(m.leg_description(), route="numpy")
    ref = legs.reach_margin(m.home)
    assert np.all(ref < 0)
    assert np.allclose(m.home_margins(), ref, rtol=1e-9, atol=0)
    text = [str(w.message) for w in rec if "home:" in str(w.message)][0]
    assert f"leg 1 margin {ref[0]:.3g} m^2" in text and "8 of 8 legs" in text


def test_ld_zero_refused_when_built():
    """The pivot the message prints is the preset's own pair centre (its geometry at a
    vanishing ld); refused only where the two legs of a pair are one leg (hunt: beta =
    gamma = l2 = 0); the octo (l2 = 25.6 mm, gamma = 13.18 deg) builds at ld = 0: its
    pairs are distinct legs (review)."""
    with pytest.raises(InputError) as exc:
        preset("hunt", ld=0.0)
    assert exc.value.field == "ld" and "got ld = 0 m" in exc.value.message
    with warnings.catch_warnings():            # ld 1e-15 m: a unit slip, says preset()
        warnings.simplefilter("ignore", GeometryWarning)
        B = preset("hunt", ld=1e-15).geometry()["B"][0]
    assert f"({B[0]:.6g}, 0, 0) m" in exc.value.message and abs(B[1]) < 1e-15
    assert "the same leg twice" in exc.value.message
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GeometryWarning)
        g = preset("octo", ld=0.0).geometry()
    assert not np.allclose(g["p"][0], g["p"][1])       # the pair's end joints differ


def test_ld_zero_scene_names_the_field_and_units():
    text = ('[units]\nlength = "mm"\nangle = "deg"\n[mechanism]\nkind = "rss"\n'
            'preset = "hunt"\nld = 0\n[[query]]\ntype = "inverse_kinematics"\n'
            'pose = [0, 0, 300, 0, 0, 0]\n')
    with pytest.raises(InputError) as exc:
        loads_scene(text)
    assert exc.value.field == "mechanism.ld"
    assert "got ld = 0 m" in exc.value.message and "(the scene's ld = 0 mm)" in exc.value.message


def test_ld_zero_is_refused_only_where_the_legs_of_a_pair_coincide():
    """Review: ld = 0 was refused whatever beta, gamma and l2; with beta or gamma != 0
    the two legs of a pair have different axes (distinct legs).  Reference: the numpy
    route's J at home (distkin.mechanisms.reference), regular (its smallest singular value
    far from 0) there, and with equal rows for each pair when l2 = beta = gamma = ld = 0
    (built past the check through the description's dataclass replace)."""
    import numpy as np

    from distkin.errors import InputError
    from distkin.mechanisms import preset
    from distkin.mechanisms.reference import ik_jacobian
    m = preset("hunt", ld=0.0, beta=0.3, gamma=0.2)
    _, valid, J = ik_jacobian(m, m.home[None, :])
    assert valid.all()
    sv = np.linalg.svd(J[0], compute_uv=False)
    assert sv[-1] / sv[0] > 1e-4
    with pytest.raises(InputError, match="legs of each pair coincide") as e:
        preset("hunt", ld=0.0, beta=0.0, gamma=0.0, l2=0.0)
    assert e.value.field == "ld"


def test_a_design_space_gives_no_geometry_warnings():
    """Review: every design of a sweep warned (a deliberate ld = 0.1 mm twice as a 'unit
    slip'); the sweep scores what each design reaches instead.  The preset itself still
    warns (reference: preset() with the same override)."""
    import warnings

    from distkin.indices.design import DesignSpace
    from distkin.mechanisms import GeometryWarning, preset
    with pytest.warns(GeometryWarning, match="ld"):
        preset("hunt", ld=1e-4)
    with warnings.catch_warnings():
        warnings.simplefilter("error", GeometryWarning)
        DesignSpace("hunt", (("ld", (1e-4,)),)).mechanism({"ld": 1e-4})
