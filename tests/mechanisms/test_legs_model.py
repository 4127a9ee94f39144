"""Leg tables (distkin.mechanisms.legs): presets as legs, validation, and the kernels
generated from a leg table against independent routes (finite differences of the IK,
the Plücker Jacobian of Rojas et al. eq. (5), the leg closures)."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
from hypothesis import assume, example, given, settings, strategies as st

from distkin.errors import InputError
from distkin.mechanisms import preset
from distkin.mechanisms.kernels import preset_table_matches
from distkin.mechanisms.kinematics import LegMechanism
from distkin.mechanisms.legs import LegsDescription
from distkin.spatial import rotation_matrix
from legs_sampling import random_legs

PRESETS = ("hunt", "hexa", "ergin", "octopod", "octo")


def _poses(home, n, seed, spread=(0.02, 0.1)):
    rng = np.random.default_rng(seed)
    X = np.tile(home, (n, 1))
    X[:, :3] += rng.uniform(-spread[0], spread[0], (n, 3))
    X[:, 3:] += rng.uniform(-spread[1], spread[1], (n, 3))
    return X


@pytest.mark.parametrize("name", PRESETS)
def test_preset_as_legs_loads_the_committed_module_bit_for_bit(name):
    """A preset's leg table finds the committed module (same LEGS, same source hash) and
    gives bit-identical numbers."""
    m = preset(name)
    lm = LegMechanism.from_description(m)
    mod = importlib.import_module(f"distkin._generated.rss_{name}")
    assert lm.kernels().module is mod and m.kernels().module is mod
    assert preset_table_matches(lm.key(), mod.LEGS)     # equal up to the last bits of trig
    X = _poses(m.home, 50, seed=3)
    for meth in ("inverse_kinematics", "jacobian", "jq_jx", "reach_margin"):
        a, b = getattr(m, meth)(X), getattr(lm, meth)(X)
        for x, y in zip(a if isinstance(a, tuple) else (a,), b if isinstance(b, tuple) else (b,)):
            assert np.array_equal(x, y)
    fa, fb = m.forward_kinematics(m.inverse_kinematics(X[0])[0]), \
        lm.forward_kinematics(lm.inverse_kinematics(X[0])[0])
    assert np.array_equal(fa.pose, fb.pose)


@pytest.mark.parametrize("name", PRESETS)
def test_preset_leg_table_is_the_geometry(name):
    """The leg table is the description's geometry: at the IK angles every distal link
    has length l3 (the closure, recomputed from RSSMechanism.points)."""
    m = preset(name)
    d = m.leg_description()
    X = _poses(m.home, 20, seed=5)
    pts = m.points(X)
    assert np.allclose(np.linalg.norm(pts["P"] - pts["D"], axis=-1), m.l3, atol=1e-12)
    assert [leg.type for leg in d.leg_table] == ["RRRS" if m.l2 else "RSS"] * m.L
    assert all(leg.branch == 1 for leg in d.leg_table)


def _leg(**kw):
    base = dict(type="RSS", base=(0.1, 0, 0), platform=(0.05, 0, 0), axis=(0, 1, 0),
                crank0=(1, 0, 0), crank90=(0, 0, 1), crank=0.05, distal=0.3)
    return {**base, **kw}


@pytest.mark.parametrize("bad, field, words", [
    (dict(axis=(0, 2, 0)), "leg[2].axis", "expected a unit vector"),
    (dict(crank90=(1, 0, 0)), "leg[2].crank90", "orthogonal"),
    (dict(type="RRRS", offset=(0.01, 0, 0)), "leg[2].offset", "along the axis"),
    (dict(offset=(0, 0.01, 0)), "leg[2].offset", "no offset on an RSS"),
    (dict(crank=-1.0), "leg[2].crank", "positive"),
    (dict(type="SPS"), "leg[2].axis", "no axis on a prismatic"),
    (dict(type="RPR"), "leg[2].type", "expected a leg type"),
    (dict(branch=0), "leg[2].branch", "+1 or -1"),
    (dict(range=(1, 0)), "leg[2].range", "min < max"),
    (dict(base=(0, 0)), "leg[2].base", "3 finite numbers"),
])
def test_bad_legs_name_the_leg_and_field(bad, field, words):
    legs = [_leg() for _ in range(6)]
    legs[2] = _leg(**bad)
    with pytest.raises(InputError) as exc:
        LegsDescription("x", legs, (0, 0, 0.3, 0, 0, 0))
    assert exc.value.field == field and words in exc.value.message


def test_fewer_than_six_legs_refused():
    with pytest.raises(InputError, match="at least 6 legs"):
        LegsDescription("x", [_leg()] * 5)


def _check_jacobian(mech, X):
    """J (kernel) against central differences of the IK: dq/d(pose) = J blockdiag(I, E)
    (``pose_jacobian``); prismatic q are lengths, revolute q angles (differences wrapped)."""
    PJ = mech.pose_jacobian(X)
    pris = np.array([leg.prismatic for leg in mech.leg_table])
    fd = np.empty_like(PJ)
    for k, d in enumerate(np.eye(6) * 1e-6):
        dq = mech.inverse_kinematics(X + d)[0] - mech.inverse_kinematics(X - d)[0]
        fd[..., k] = np.where(pris, dq, np.angle(np.exp(1j * dq))) / 2e-6
    scale = np.abs(PJ).max(axis=-1)
    return np.abs(fd - PJ).max(axis=-1) / scale


@settings(max_examples=1, deadline=None)    # each example derives a module (about 6 s)
@given(seed=st.integers(0, 2 ** 31 - 1))
@example(seed=2024)                          # also used by test_legs_numeric (cached)
def test_random_mixed_legs_jacobian_against_finite_differences(seed):
    """Random 7-leg mechanisms with every leg type (RSS, RUS, RRRS, SPS, UPS): the
    generated J against central differences of the generated IK (relative 1e-6), the
    prismatic rows against plucker_jacobian (Rojas et al. eq. (5)), the closure zero at
    the IK angles, and FK back to the pose."""
    from distkin.singularity.conditions import plucker_jacobian
    mech = LegMechanism.from_description(random_legs(seed))
    X = _poses(mech.home, 8, seed + 1, spread=(0.01, 0.05))
    X[0] = mech.home                              # every leg closes there (by construction)
    q, valid = mech.inverse_kinematics(X)
    assert valid[0].all()
    Jq, _ = mech.jq_jx(X, warn=False)          # unreachable poses: kept out below
    keep = valid.all(axis=1) & (np.abs(Jq).min(axis=1) > 1e-2)   # away from leg singularities
    X, q = X[keep], q[keep]
    assume(len(X) >= 1)                           # else every pose is near a leg singularity
    assert _check_jacobian(mech, X).max() < 1e-6
    pris = [i for i, leg in enumerate(mech.leg_table) if leg.prismatic]
    d = mech.arrays()
    P = X[:, None, :3] + np.einsum("nij,lj->nli", rotation_matrix(X[:, 3:]), d["p"])
    for n in range(len(X)):
        u = P[n, pris] - d["B"][pris]
        # plucker_jacobian wants six legs: pad with copies of the prismatic ones
        idx = (pris * 6)[:6]
        ref6 = plucker_jacobian(d["B"][idx], P[n, idx], reference=X[n, :3])
        J = mech.jacobian(X[n])
        assert np.allclose(J[idx], ref6, rtol=0, atol=1e-13 * np.abs(ref6).max())
        assert np.allclose(q[n, pris], np.linalg.norm(u, axis=-1), rtol=1e-14)
    cl = mech.kernels().closure(q, X)
    assert np.abs(cl[..., 0]).max() < 1e-12
    fk = mech.forward_kinematics(q[-1], mech.home)
    assert fk.converged and np.abs(fk.pose - X[-1]).max() < 1e-9


@pytest.mark.parametrize("route", ["generated", "numpy"])
def test_crank_frame_off_orthonormal_within_tolerance_is_one_mechanism(route):
    """A table whose crank0 vectors are off unit by ~4e-10 (accepted: the table checks to
    1e-9, legs._TOL) is one mechanism for the closed-form IK and the closure-based FK:
    the closure vanishes at the IK angles (to 1e-15 m) and FK(IK(X)) gives X back to
    1e-13 (two routes: the IK's closed form, Newton on the closure).  With the literal
    |P - D(q)|^2 closure the two missed each other by 6e-11 m here."""
    import dataclasses
    rng = np.random.default_rng(1)
    legs = []
    for leg in random_legs(4, types=("RSS",) * 6).leg_table:
        kw = dataclasses.asdict(leg)
        kw.pop("limit")
        kw["crank0"] = tuple(np.array(kw["crank0"]) + 4e-10 * rng.standard_normal(3))
        legs.append(kw)
    d = random_legs(4, types=("RSS",) * 6)
    mech = LegMechanism.from_description(LegsDescription("sloppy", legs, d.home_pose),
                                         route=route)
    u = np.array([leg.crank0 for leg in mech.leg_table])
    assert 1e-10 < np.abs(np.linalg.norm(u, axis=1) - 1).max() < 1e-9
    X = np.array(d.home_pose) + 0.3 * np.array([0.001, -0.001, 0.002, 0.01, -0.01, 0.01])
    q, valid = mech.inverse_kinematics(X)
    assert valid.all()
    C = np.asarray(mech.kernels().closure(q[None], X[None]))[0]
    assert np.abs(C[:, 0]).max() < 1e-15
    assert np.abs(mech.forward_kinematics(q, guess=X).pose - X).max() < 1e-13
