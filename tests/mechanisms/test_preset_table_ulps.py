"""A preset's leg table loads its committed module up to the last bits of numpy's trig
(QA pkg 2): numpy 1.24, or another CPU's SIMD cos/sin, builds a table that differs from
the committed ``LEGS`` in the last bit (-0.06733974596215557 vs ...58 on Hunt), and an
exact match re-derived the kernels with sympy at run time.  A table within
``PRESET_ULPS`` ulps per number loads the committed module; one 1e-9 off does not."""

from __future__ import annotations

import dataclasses
import importlib

import numpy as np
import pytest

from distkin.mechanisms import kernels as kernels_mod
from distkin.mechanisms.description import RSSDescription
from distkin.mechanisms.kinematics import LegMechanism
from distkin.mechanisms.legs import LegsDescription
from distkin.mechanisms.presets import preset_description

PRESETS = ("hunt", "hexa", "ergin", "octopod", "octo")


def _nudge(x, ulps, rng):
    """``x`` moved by ``ulps`` units in the last place, in a random direction (zeros
    stay zero: trig's exact zeros are exact on every platform)."""
    if x == 0.0:
        return x
    toward = np.inf if rng.random() < 0.5 else -np.inf
    for _ in range(ulps):
        x = float(np.nextafter(x, toward))
    return x


def _perturbed_geometry(ulps, seed):
    original = RSSDescription.geometry
    rng = np.random.default_rng(seed)

    def geometry(self):
        g = original(self)
        for k in ("B", "a", "u", "p"):
            g[k] = np.vectorize(lambda x: _nudge(float(x), ulps, rng))(g[k])
        return g
    return geometry


def _no_derivation(*args, **kwargs):
    raise AssertionError("derived the kernels of a preset's table")


@pytest.fixture
def fresh_cache(monkeypatch):
    monkeypatch.setattr(kernels_mod, "_LOADED", {})
    import distkin.codegen.rss as rss
    monkeypatch.setattr(rss, "derived_module", _no_derivation)


@pytest.mark.parametrize("ulps", [1, 2])
@pytest.mark.parametrize("name", PRESETS)
def test_a_preset_built_with_other_trig_loads_the_committed_module(name, ulps, monkeypatch,
                                                                   fresh_cache):
    """The preset's constructor on a numpy whose cos/sin round differently (every nonzero
    vector entry 1 or 2 ulps off): the committed module, no sympy."""
    monkeypatch.setattr(RSSDescription, "geometry", _perturbed_geometry(ulps, seed=ulps))
    desc = preset_description(name)
    committed = importlib.import_module(f"distkin._generated.rss_{name}")
    assert desc.leg_description().key() != committed.LEGS        # the numbers do differ
    from distkin.mechanisms.kernels import load_kernels
    assert load_kernels(desc).module is committed
    lm = LegMechanism.from_description(desc.leg_description())
    assert lm.kernels().module is committed


def _legs_off_by(name, delta):
    desc = preset_description(name).leg_description()
    legs = list(desc.leg_table)
    b = legs[2].base
    legs[2] = dataclasses.replace(legs[2], base=(b[0] + delta, b[1], b[2]))
    return LegsDescription(desc.name, tuple(legs), desc.home_pose, desc.mass,
                           desc.inertia, desc.scale)


@pytest.mark.parametrize("name", PRESETS)
def test_a_table_1e9_off_is_not_the_preset(name):
    """A base coordinate 1e-9 m off (~1e8 ulps) is another mechanism: no preset
    module (the kernels would be derived)."""
    assert kernels_mod._preset_for(_legs_off_by(name, 1e-9)) is None
    assert kernels_mod._preset_for(preset_description(name)) == name


def test_the_match_is_by_number_not_by_type_or_sign():
    m = kernels_mod.preset_table_matches
    assert m((("x", 0.1),), (("x", float(np.nextafter(0.1, 1.0))),))
    assert not m((("x", 0.1),), (("x", 0.1 * (1 + 1e-12)),))
    assert not m((("x", 0.0),), (("x", 1e-300),))              # a zero is only a zero
    assert not m((("branch", 1),), (("branch", -1),))
    assert not m((("range", None),), (("range", (0.0, 1.0)),))
    assert not m((("x", 1.0), ("y", 2.0)), (("x", 1.0),))
