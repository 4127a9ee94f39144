"""The admittance model (distkin.control.admittance) against analytic references.

Kühne et al., Sec. III-D and Fig. 9: the hand wrench drives a virtual mass-damper
M V̇ = w_h + w_e - D V, stepped by semi-implicit Euler at the loop period.  References:
the closed-form response of a mass-damper to a force step, the exact geometric decay of
the discrete impulse response, the conservation of energy of an undamped spring (and a
wall) to first order in h, and Jury's stability test of the linear step.  Review
findings fixed here: bad parameters gave numpy warnings and tracebacks (a zero mass a
division by zero, a mass of 3 values a broadcasting ValueError, a spring anchor of 3
values an IndexError, a zero wall normal no wall at all); a scene's virtual model could
be unstable at its rate with nothing to say so (check_step)."""

import math

import numpy as np
import pytest

from distkin.control.admittance import (Admittance, Spring, Wall, check_step,
                                        step_spectral_radius)
from distkin.errors import InputError

ROT = [0.005] * 3


def _run(adm, wrench, h, seconds):
    out = []
    for _ in range(int(round(seconds / h))):
        p, v = adm.propose(np.asarray(wrench, dtype=float), h)
        adm.commit(p, v)
        out.append((p.copy(), v.copy()))
    return out


@pytest.mark.parametrize("rate_hz", [1000.0, 4000.0])
def test_force_step_follows_the_mass_damper_solution(rate_hz):
    """F = 2 N on M = 1 kg, D = 15 N·s/m: x(t) = (F/D)(t - τ(1 - e^{-t/τ})), τ = M/D.
    The discrete step is first order: the error at 1 kHz is 4x the error at 4 kHz."""
    M, D, F, h = 1.0, 15.0, 2.0, 1.0 / rate_hz
    adm = Admittance([M] * 3 + ROT, [D] * 3 + [0.1] * 3)
    adm.reset(np.zeros(6))
    xs = np.array([p[0] for p, _ in _run(adm, [F, 0, 0, 0, 0, 0], h, 0.5)])
    t = h * np.arange(1, xs.size + 1)
    tau = M / D
    exact = F / D * (t - tau * (1 - np.exp(-t / tau)))
    err = np.abs(xs - exact).max()
    assert err < 0.15 * h                           # 1.3e-4 m at 1 kHz, 3.3e-5 at 4 kHz
    assert xs[-1] == pytest.approx(exact[-1], rel=5e-3)


def test_impulse_response_is_the_exact_geometric_decay():
    """After an impulse (V = 0.3 m/s, no force) V_k = 0.3 (1 - hD/M)^k exactly."""
    M, D, h = 1.0, 15.0, 1e-3
    adm = Admittance([M] * 3 + ROT, [D] * 3 + [0.1] * 3)
    adm.reset(np.zeros(6))
    adm.twist = np.array([0.3, 0, 0, 0, 0, 0])
    vs = np.array([v[0] for _, v in _run(adm, np.zeros(6), h, 0.2)])
    k = np.arange(1, vs.size + 1)
    np.testing.assert_allclose(vs, 0.3 * (1 - h * D / M) ** k, rtol=1e-12)


@pytest.mark.parametrize("rate_hz", [1000.0, 4000.0])
def test_an_undamped_spring_neither_gains_nor_loses_energy(rate_hz):
    """M = 1 kg on k = 100 N/m for 5 s (8 periods): the energy E = ½MV² + ½kx² stays
    within O(hω) of its start, and the quadratic form that semi-implicit Euler
    conserves exactly, Q = E - ½hkxV (the map V' = V - (hk/M)x, x' = x + hV' has
    determinant 1 and leaves Q invariant), holds to rounding: no drift, so no energy
    gained however long the spring is rendered."""
    M, k, h = 1.0, 100.0, 1.0 / rate_hz
    adm = Admittance([M] * 3 + ROT, [0.0] * 6, [Spring((0,) * 6, (k,) * 3 + (2,) * 3)])
    adm.reset(np.array([0.01, 0, 0, 0, 0, 0]))
    E0 = 0.5 * k * 0.01 ** 2
    xv = np.array([(p[0], v[0]) for p, v in _run(adm, np.zeros(6), h, 5.0)])
    E = 0.5 * M * xv[:, 1] ** 2 + 0.5 * k * xv[:, 0] ** 2
    Q = E - 0.5 * h * k * xv[:, 0] * xv[:, 1]
    assert np.abs(E / E0 - 1).max() < 0.6 * h * math.sqrt(k / M)
    assert np.abs(Q / Q[0] - 1).max() < 1e-11


@pytest.mark.parametrize("rate_hz", [1000.0, 4000.0])
def test_bouncing_off_a_wall_returns_the_speed_to_first_order(rate_hz):
    """A 1 kg handle at 0.1 m/s into a 3000 N/m wall, no damping, from 40 starting
    phases: the outgoing speed equals the incoming one within O(h), with no systematic
    gain (the mean change is below a tenth of the largest)."""
    h, k = 1.0 / rate_hz, 3000.0
    gains = []
    for x0 in np.linspace(0.0195, 0.0200, 40):
        adm = Admittance([1.0] * 3 + ROT, [0.0] * 6, [Wall((1, 0, 0), 0.02, k)])
        adm.reset(np.array([x0, 0, 0, 0, 0, 0]))
        adm.twist = np.array([0.1, 0, 0, 0, 0, 0])
        while not (adm.twist[0] < 0 and adm.pose[0] < 0.02):
            p, v = adm.propose(np.zeros(6), h)
            adm.commit(p, v)
        gains.append(adm.twist[0] ** 2 / 0.01 - 1)
    gains = np.array(gains)
    assert np.abs(gains).max() < 2 * h * math.sqrt(k)
    assert abs(gains.mean()) < 0.1 * np.abs(gains).max()


@pytest.mark.parametrize("args, field", [
    (([0.0] * 6, [1.0] * 6), "admittance.mass"),
    (([1.0] * 3, [1.0] * 6), "admittance.mass"),
    (([1.0] * 6, [-1.0] + [1.0] * 5), "admittance.damping"),
    (([1.0] * 6, [math.nan] * 6), "admittance.damping"),
    (([1.0] * 6, [1.0] * 6, ["wall"]), "environment[0]")])
def test_bad_admittance_parameters_are_named(args, field):
    with pytest.raises(InputError) as exc:
        Admittance(*args)
    assert exc.value.field == field and "expected" in str(exc.value)


@pytest.mark.parametrize("make, field", [
    (lambda: Spring((0, 0, 0), (1,) * 6), "spring.anchor"),
    (lambda: Spring((0,) * 6, (-1,) * 6), "spring.stiffness"),
    (lambda: Wall((0, 0, 0), 0.0, 100.0), "wall.normal"),
    (lambda: Wall((2, 0, 0), 0.0, 100.0), "wall.normal"),
    (lambda: Wall((1, 0, 0), math.inf, 100.0), "wall.offset"),
    (lambda: Wall((1, 0, 0), 0.0, 0.0), "wall.stiffness")])
def test_bad_springs_and_walls_are_named(make, field):
    with pytest.raises(InputError) as exc:
        make()
    assert exc.value.field == field


def test_a_step_of_zero_or_negative_length_is_refused():
    adm = Admittance([1.0] * 6, [1.0] * 6)
    for dt in (0.0, -1e-3, math.nan):
        with pytest.raises(InputError, match="dt"):
            adm.propose(np.zeros(6), dt)


def test_the_stability_bound_is_jurys_and_the_simulation_agrees():
    """One axis, M = 0.01 kg, k = 30 N/m, at 1 kHz: h²k/m + 2hd/m < 4 (Jury) puts the
    boundary at d = (4 - h²k/m) m / (2h) = 19.85 N·s/m.  Below it the free response
    decays, above it it grows (brute force, 2 s); the spectral radius says the same,
    and check_step refuses the unstable one naming the radius."""
    h, m, k = 1e-3, 0.01, 30.0
    d_star = (4 - h * h * k / m) * m / (2 * h)
    for d, stable in ((0.97 * d_star, True), (1.03 * d_star, False)):
        mass, damp = [m] * 3 + ROT, [d] * 3 + [0.0] * 3
        env = [Spring((0,) * 6, (k,) * 3 + (0,) * 3)]
        r = step_spectral_radius(mass, damp, env, h)[0]
        assert (r < 1) == stable
        adm = Admittance(mass, damp, env)
        adm.reset(np.array([1e-3, 0, 0, 0, 0, 0]))
        xs = np.array([abs(p[0]) for p, _ in _run(adm, np.zeros(6), h, 2.0)])
        assert (xs[-50:].max() < 1e-3) == stable
        if stable:
            check_step(mass, damp, env, 1 / h)
        else:
            with pytest.raises(InputError, match="translation spectral radius"):
                check_step(mass, damp, env, 1 / h)


def test_the_builtin_scene_is_stable_at_1_and_4_khz():
    from distkin.control.config import builtin_scene
    sc = builtin_scene()
    for rate in (1000.0, 4000.0):
        t, r = check_step(sc.mass, sc.damping, sc.environment, rate)
        assert t < 1 and r < 1
