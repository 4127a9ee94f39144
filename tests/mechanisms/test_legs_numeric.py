"""The plain-numpy route of a leg table (distkin.mechanisms.reference.NumericKernels)
against the generated kernels and against finite differences of its own IK."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from distkin.errors import InputError
from distkin.mechanisms import preset
from distkin.mechanisms.kinematics import LegMechanism
from distkin.mechanisms.reference import NumericKernels
from legs_sampling import random_legs
from test_legs_model import _check_jacobian, _poses

PRESETS = ("hunt", "hexa", "ergin", "octopod", "octo")


def _compare(mech, X):
    """Largest differences numpy route - generated kernels, relative to each output's
    magnitude, for every kernel (batched and scalar)."""
    gen = mech.kernels("batched")
    num = NumericKernels(mech.leg_description())
    # where a leg does not close the generated J uses the unnormalised (cos q, sin q) of
    # the closed form, the numpy route cos and sin of q: compare where every leg closes
    X = X[(gen.reach(X) >= 0).all(axis=1)]
    assert len(X) > 10
    out = {}
    for name in ("ik", "reach", "jacobian", "jq_jx"):
        a, b = getattr(gen, name)(X), getattr(num, name)(X)
        if name == "ik":
            a, b = np.angle(np.exp(1j * a)), np.angle(np.exp(1j * b))
        out[name] = np.abs(a - b).max() / max(1.0, np.abs(a).max())
    q = gen.ik(X)
    a, b = gen.closure(q, X), num.closure(q, X)
    out["closure"] = np.abs(a - b).max()
    sc = NumericKernels(mech.leg_description(), "scalar")
    assert np.allclose(sc.jacobian(X[0].tolist()), num.jacobian(X[0]), rtol=0, atol=0)
    assert np.array_equal(sc.closure(q[0].tolist(), X[0].tolist()), num.closure(q[0], X[0]))
    return out


@pytest.mark.parametrize("name", PRESETS)
def test_numpy_route_matches_committed_kernels(name):
    m = preset(name)
    lm = LegMechanism.from_description(m)
    X = _poses(m.home, 200, seed=9, spread=(0.07, 0.35))
    worst = _compare(lm, X)
    assert max(worst.values()) < 1e-12, worst


def test_numpy_route_matches_derived_kernels_of_every_leg_type():
    """seed 2024: derived (and cached) by test_legs_model's explicit example."""
    mech = LegMechanism.from_description(random_legs(2024))
    X = _poses(mech.home, 100, seed=1, spread=(0.01, 0.05))
    worst = _compare(mech, X)
    assert max(worst.values()) < 1e-12, worst


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2 ** 31 - 1))
def test_numpy_route_jacobian_against_finite_differences(seed):
    """Random mechanisms with every leg type: J of the numpy route against central
    differences of its IK (relative 1e-6), away from each leg's own singularity."""
    mech = LegMechanism.from_description(random_legs(seed), route="numpy")
    assert isinstance(mech.kernels(), NumericKernels)
    X = _poses(mech.home, 8, seed + 1, spread=(0.01, 0.05))
    X[0] = mech.home
    q, valid = mech.inverse_kinematics(X)
    assert valid[0].all()
    Jq, _ = mech.jq_jx(X, warn=False)          # unreachable poses: kept out below
    keep = valid.all(axis=1) & (np.abs(Jq).min(axis=1) > 1e-2)
    assume(keep.any())                            # else every pose is near a leg singularity
    assert _check_jacobian(mech, X[keep]).max() < 1e-6
    fk = mech.forward_kinematics(q[-1] if keep[-1] else q[0], mech.home)
    assert fk.converged and fk.residual < 1e-12


def test_numpy_route_has_no_arb_flavour():
    mech = LegMechanism.from_description(preset("hunt"), route="numpy")
    with pytest.raises(InputError, match="arb"):
        mech.kernels("arb")
    with pytest.raises(InputError, match="route"):
        LegMechanism.from_description(preset("hunt"), route="sympy")


def test_reference_ik_jacobian_takes_leg_mechanisms():
    """indices.study's numpy route (reference.ik_jacobian) on a leg mechanism gives the
    kernels' IK, J and Jq (the preset's committed module)."""
    from distkin.mechanisms.reference import ik_jacobian
    m = preset("ergin")
    lm = LegMechanism.from_description(m)
    X = _poses(m.home, 50, seed=4, spread=(0.03, 0.2))
    q, valid, J, jq = ik_jacobian(lm, X, return_jq=True)
    qk, vk = lm.inverse_kinematics(X)
    Jq, _ = lm.jq_jx(X)
    ok = vk.all(axis=1)
    assert np.array_equal(valid, vk) and ok.sum() > 40
    assert np.allclose(q[ok], qk[ok], atol=1e-13)
    assert np.allclose(J[ok], lm.jacobian(X)[ok], rtol=1e-11, atol=1e-11)
    assert np.allclose(jq[ok], Jq[ok], atol=1e-13)


def test_geometry_caches_are_bounded(monkeypatch):
    """A sweep over geometries keeps only the most recent leg arrays and kernel sets
    (they grew without bound); an evicted geometry is made again with the same IK."""
    from distkin.mechanisms import kernels as kernels_mod
    from distkin.mechanisms import kinematics as kin_mod
    monkeypatch.setattr(kin_mod, "_ARRAYS_KEPT", 3)
    monkeypatch.setattr(kernels_mod, "_LOADED_KEPT", 3)
    # empty caches: a geometry an earlier test of this process loaded is a hit, which
    # evicts nothing (seen once under xdist: 165 kernel sets kept at the first check)
    monkeypatch.setattr(kin_mod, "_ARRAYS", {})
    monkeypatch.setattr(kernels_mod, "_LOADED", {})
    mechs = [LegMechanism.from_description(random_legs(100 + s), route="numpy")
             for s in range(5)]
    first = mechs[0].inverse_kinematics(mechs[0].home[None])[0]
    for m in mechs:
        m.leg_arrays()
        m.kernels()
        assert len(kin_mod._ARRAYS) <= 3 and len(kernels_mod._LOADED) <= 3
    again = mechs[0].inverse_kinematics(mechs[0].home[None])[0]   # evicted, made again
    assert np.array_equal(first, again)
