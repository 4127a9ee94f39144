"""Lengths beyond float64's reach are bad input, not internal failures
(distkin.argcheck.length_in_range).  QA: ``preset("octo", l0=1e200)`` and a leg-table
crank of 1e308 m overflowed, a crank of 1e-200 m divided by zero (exit 1, "internal
failure").  Reference for the bounds not being too tight: the kinematics are
homogeneous in length, so a mechanism scaled by 1e-25 or 1e25 with its pose's position
has the same crank angles as the unscaled one."""

import warnings

import numpy as np
import pytest

from distkin.argcheck import LENGTH_RANGE
from distkin.errors import InputError
from distkin.mechanisms import preset
from distkin.mechanisms.legs import Leg
from distkin.mechanisms.presets import preset_parameters

LENGTHS = ("l0", "l1", "l2", "l3", "lp", "ld", "z0")


@pytest.mark.parametrize("field,value", [("l0", 1e200), ("l1", 1e-200), ("z0", 2e30),
                                         ("lp", 1e-31), ("l2", 1e-300), ("l3", 1e40)])
def test_rss_lengths_out_of_range_are_refused(field, value):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(InputError) as ei:
            preset("octo", **{field: value})
    assert ei.value.field == field
    assert f"{value!r} m" in str(ei.value) and f"{LENGTH_RANGE[1]:g}" in str(ei.value)


def test_zero_offsets_stay_allowed():
    assert preset("octo", l2=0.0).l2 == 0.0


_LEG = dict(type="RUS", base=(0.1, 0.0, 0.0), platform=(0.05, 0.0, 0.0), axis=(1, 0, 0),
            crank0=(0, 1, 0), crank90=(0, 0, 1), crank=0.06, distal=0.22)


@pytest.mark.parametrize("field,value", [("crank", 1e308), ("crank", 1e-200),
                                         ("distal", 5e30), ("base", (1e31, 0.0, 0.0)),
                                         ("platform", (0.0, -2e30, 0.0))])
def test_leg_lengths_out_of_range_are_refused(field, value):
    with pytest.raises(InputError) as ei:
        Leg(**{**_LEG, field: value})
    assert ei.value.field == field and f"{LENGTH_RANGE[1]:g}" in str(ei.value)


@pytest.mark.parametrize("scale", [1e-25, 1e25])
def test_scaled_mechanisms_within_the_range_keep_their_angles(scale):
    _, p = preset_parameters("hunt")
    base = preset("hunt")
    pose = np.array([0.01, -0.02, p["z0"] + 0.005, 0.05, -0.04, 0.1])
    q0, ok0 = base.inverse_kinematics(pose)
    assert np.all(ok0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                    # "1e25 x the preset's l0"
        big = preset("hunt", **{k: base.parameters()[k] * scale for k in LENGTHS})
    ps = pose.copy()
    ps[:3] *= scale
    q, ok = big.inverse_kinematics(ps)
    assert np.all(ok)
    np.testing.assert_allclose(q, q0, rtol=0, atol=1e-12)
