"""A controller scene whose virtual model the rate's step makes unstable is refused at
load (QA: mass 1 g, damping 15 N s/m loaded silently; the admittance then gains
energy every period).  The boundary comes from the per-axis Jury condition
h²k/m + 2hd/m < 4 (admittance.step_spectral_radius), checked here against a
brute-force run of the semi-implicit Euler recurrence."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.control.config import BUILTIN_SCENE, loads_control_scene
from distkin.errors import InputError


def _scene(mass, damping, rate=1000):
    m = ", ".join(str(x) for x in [mass] * 3 + [0.001] * 3)
    d = ", ".join(str(x) for x in [damping] * 3 + [0.01] * 3)
    return f"""
[device]
preset = "octo"
rate_hz = {rate}
[admittance]
mass = [{m}]
damping = [{d}]
"""


def _grows(mass, damping, h, steps=2000):
    """The free mass-damper stepped like Admittance.propose (semi-implicit Euler)."""
    x, v = 0.0, 1.0
    for _ in range(steps):
        v = v + h * (-damping * v) / mass
        x = x + h * v
        if abs(v) > 1e6:                     # before it overflows (inf - inf is NaN)
            return True
    return False


@pytest.mark.parametrize("mass, damping", [(0.001, 15.0), (0.01, 25.0)])
def test_an_unstable_virtual_model_is_refused_naming_admittance(mass, damping):
    assert _grows(mass, damping, 1e-3)                 # brute force: it blows up
    with pytest.raises(InputError, match="spectral radius") as e:
        loads_control_scene(_scene(mass, damping))
    assert e.value.field == "admittance"


def test_a_stable_one_loads_and_the_rate_decides():
    mass, damping = 0.01, 15.0                          # 2hd/m = 3 at 1 kHz: stable
    assert not _grows(mass, damping, 1e-3) and _grows(mass, damping, 1e-3 * 4 / 3 * 1.01)
    loads_control_scene(_scene(mass, damping))
    with pytest.raises(InputError, match="spectral radius"):
        loads_control_scene(_scene(mass, damping, rate=740))   # h = 1.35 ms: 2hd/m > 4


def test_the_builtin_and_example_scenes_stay_loadable():
    from importlib import resources
    text = resources.files("distkin.control").joinpath(BUILTIN_SCENE).read_text()
    assert loads_control_scene(text).rate_hz > 0
