"""The delay margin of the joint PD loop (distkin/control/delay_margin.py) against two
independent references: the analytic spectrum of semi-implicit Euler on an undamped
spring-mass, and the nonlinear in-process loop (encoders, sensor noise, drives, frames)
run with the delay: the growth rate and frequency of the oscillation it shows."""

import dataclasses

import numpy as np
import pytest

from distkin.control.config import default_scene
from distkin.control.delay_margin import closed_loop_matrix, delay_margin
from distkin.control.kinematics import load_model
from distkin.control.loopback import run_loopback
from distkin.errors import InputError


@pytest.fixture(scope="module")
def octo():
    """The Octo with the paper's PD (KP 110, KD 0.4, filter 700 ms), no hand."""
    return dataclasses.replace(default_scene(), preset="octo"), load_model("octo")


def _with_pd(scene, **kw):
    return dataclasses.replace(scene, pd=dataclasses.replace(scene.pd, **kw))


def test_undamped_servo_has_the_spectrum_of_semi_implicit_euler(octo):
    """KD = 0, no friction: x'' = -M^-1 KP J^T J x stepped by semi-implicit Euler has
    |lambda| = 1 and lambda + 1/lambda = 2 - h^2 w^2 for every mode w^2 of the pencil."""
    scene, model = octo
    motors = dataclasses.replace(scene.simulator.motors, friction=0.0)
    scene = dataclasses.replace(_with_pd(scene, kd=0.0, derivative_filter_s=0.0),
                                simulator=dataclasses.replace(scene.simulator, motors=motors))
    h = 1.0 / scene.rate_hz
    J = model.jacobian(model.home)
    Meff = model.mass + motors.joint_inertia * J.T @ J
    w2 = np.sort(np.linalg.eigvals(np.linalg.solve(Meff, scene.pd.kp * J.T @ J)).real)
    lam = np.linalg.eigvals(closed_loop_matrix(scene, model))
    osc = lam[np.abs(lam) > 1e-6]                  # the rest: the PD's filter states (0)
    assert np.allclose(np.abs(osc), 1.0, atol=1e-9)
    got = np.sort(np.unique(np.round(np.arccos((osc + 1 / osc).real / 2), 9)))
    want = np.sort(np.arccos(1 - h * h * w2 / 2))
    np.testing.assert_allclose(got, np.unique(np.round(want, 9)), atol=1e-8)


def _ideal(scene):
    """Ideal sensors: no noise, encoders of 2^40 counts.  Only gravity, in the periods
    before the first command arrives, starts the motion: a vertical (z) mode."""
    mo = dataclasses.replace(scene.simulator.motors, counts_per_rev=2 ** 40,
                             force_noise=0.0, torque_noise=0.0)
    return dataclasses.replace(scene, simulator=dataclasses.replace(scene.simulator,
                                                                    motors=mo))


def _z_mode(scene, model, delay):
    """Growth (1/s) and frequency (Hz) of the least-damped oscillatory mode of the
    linearised loop whose pose part is mostly z."""
    lam, vec = np.linalg.eig(closed_loop_matrix(scene, model, delay))
    z = (np.argmax(np.abs(vec[:6]), axis=0) == 2) & (np.abs(lam.imag) > 0)
    i = np.flatnonzero(z)[np.argmax(np.abs(lam[z]))]
    h = 1.0 / scene.rate_hz
    return np.log(abs(lam[i])) / h, abs(np.angle(lam[i])) / (2 * np.pi * h)


def _saturates(scene, model, delay, seconds):
    """Whether the nonlinear loop reaches the torque limit, and the z deviation from the
    set point up to then."""
    r = run_loopback(scene, model, seconds, delay_periods=delay)
    sat = np.flatnonzero(np.abs(r["tau_cmd"]).max(axis=1) >= 0.99 * scene.pd.torque_limit)
    end = sat[0] if sat.size else len(r["pose"])
    return bool(sat.size), (r["pose"] - r["desired"])[:end, 2]


def _growth_and_frequency(z, rate_hz, skip=100):
    """Exponential rate (1/s) of the oscillation's peaks and its frequency (Hz, from the
    zero crossings), after ``skip`` samples, the slow drift removed by a 29-sample
    moving average."""
    c = z[skip:] - np.convolve(z[skip:], np.ones(29) / 29, mode="same")
    c = c[14:-14]
    a = np.abs(c)
    pk = np.flatnonzero((a[1:-1] >= a[:-2]) & (a[1:-1] > a[2:])) + 1
    growth = np.polyfit(pk / rate_hz, np.log(a[pk]), 1)[0]
    cross = np.flatnonzero(np.signbit(c[1:]) != np.signbit(c[:-1]))
    return growth, (cross.size - 1) / 2 / ((cross[-1] - cross[0]) / rate_hz)


@pytest.mark.parametrize("filter_s, delay", [(0.7, 1), (0.7, 2), (0.0007, 3)])
def test_growing_oscillation_has_the_predicted_rate_and_frequency(octo, filter_s, delay):
    """Where the linearised loop is unstable, the nonlinear loop (ideal sensors) shows
    the z mode's growth within 10 % and its frequency within 5 %, until the torque
    limit; the paper's gains (filter 700 ms) already at one period of extra delay."""
    scene, model = octo
    scene = _ideal(_with_pd(scene, derivative_filter_s=filter_s))
    g, f = _z_mode(scene, model, delay)
    assert g > 0
    saturated, z = _saturates(scene, model, delay, 0.8)
    assert saturated
    growth, freq = _growth_and_frequency(z, scene.rate_hz)
    assert growth == pytest.approx(g, rel=0.1)
    assert freq == pytest.approx(f, rel=0.05)


def test_paper_gains_have_no_margin(octo):
    """The paper's gains as we read Sec. III-D (KP 110, KD 0.4, derivative filter
    700 ms): stable lock-stepped, unstable from one period of extra delay on; the
    realistic loop (encoder steps, sensor noise) stays below the torque limit for 2 s
    without delay and reaches it within 0.6 s with one period."""
    scene, model = octo
    dm = delay_margin(scene, model, max_periods=3)
    assert dm.stable_periods == 0 and np.all(dm.spectral_radius[1:] > 1)
    assert not _saturates(scene, model, 0, 2.0)[0]
    assert _saturates(scene, model, 1, 0.6)[0]


def test_both_sides_of_a_margin(octo):
    """A derivative filter of 0.7 ms instead of 700 ms gives a margin of a few periods:
    the realistic loop stays below the torque limit at the margin and reaches it one
    period beyond."""
    scene, model = octo
    scene = _with_pd(scene, derivative_filter_s=0.0007)
    dm = delay_margin(scene, model, max_periods=6)
    n = dm.stable_periods
    assert 1 <= n < 6 and dm.spectral_radius[n + 1] > 1 > dm.spectral_radius[n]
    assert not _saturates(scene, model, n, 1.5)[0]
    assert _saturates(scene, model, n + 1, 1.5)[0]


def test_bad_arguments_are_named(octo):
    scene, model = octo
    for kw, field in (({"delay_periods": -1}, "delay_periods"),
                      ({"delay_periods": 1.5}, "delay_periods"),
                      ({"pose": [0, 0, 0]}, "pose")):
        with pytest.raises(InputError) as exc:
            closed_loop_matrix(scene, model, **kw)
        assert exc.value.field == field
    with pytest.raises(InputError) as exc:
        delay_margin(scene, model, max_periods=10 ** 6)
    assert exc.value.field == "max_periods" and "1000000" in str(exc.value)
    with pytest.raises(InputError):
        run_loopback(scene, model, 0.01, delay_periods=-2)


def test_cli_sweep_is_the_library_sweep(tmp_path, capsys):
    """``distkin control --delay-margin N --json`` gives the library's numbers (the
    example scene), the text names the margin, a plot is written; options that only a
    run uses are refused (exit 2, one line)."""
    import json
    from distkin.app.cli import main
    from distkin.control.config import load_control_scene
    from distkin.control.kinematics import model_of
    scene_path = "examples/control_octo.toml"
    out = tmp_path / "dm.json"
    code = main(["control", "--delay-margin", "3", "--scene", scene_path, "--json", str(out),
                 "--plots", str(tmp_path)])
    text = capsys.readouterr().out
    assert code == 0
    scene = load_control_scene(scene_path)
    dm = delay_margin(scene, model_of(scene), max_periods=3)
    rep = json.loads(out.read_text())
    assert rep["stable_periods"] == dm.stable_periods == 0
    np.testing.assert_array_equal([r["spectral_radius"] for r in rep["sweep"]],
                                  dm.spectral_radius)
    assert "unstable with 1 (1.00 ms)" in text and (tmp_path / "delay_margin.png").is_file()
    code = main(["control", "--delay-margin", "--log", str(tmp_path / "x")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and err[0].startswith("distkin: error: --log:")


def test_a_run_on_a_port_warns_and_states_the_margin(capsys):
    """On a device's port nothing keeps the host in lock step: a loop without margin is
    warned about before the run, and the summary states the margin (here loop://, which
    sends no frames: the run ends at its wall limit)."""
    import json
    from distkin.app.cli import main
    main(["control", "--port", "loop://", "--seconds", "0.05", "--wall-limit", "0.3",
          "--json", "-"])
    out, err = capsys.readouterr()
    assert "warning: [pd]: the joint PD loop takes no extra command delay" in err
    summary = json.loads(out)
    assert summary["delay_margin_periods"] == 0 and summary["delay_margin_ms"] == 0.0


def test_an_undamped_loop_is_marginal_not_decided(octo):
    """KD = 0, no filter, no friction: the spectral radius is 1 (semi-implicit Euler
    conserves the undamped spring-mass), so float64 cannot decide stability: marginal,
    never 'stable' or 'unstable' by rounding (QA O 2)."""
    scene, model = octo
    motors = dataclasses.replace(scene.simulator.motors, friction=0.0)
    scene = dataclasses.replace(_with_pd(scene, kd=0.0, derivative_filter_s=0.0),
                                simulator=dataclasses.replace(scene.simulator, motors=motors))
    dm = delay_margin(scene, model, max_periods=1)
    assert dm.marginal[0] and dm.stable_periods == -1
    assert "marginal without extra delay" in dm.lines()[-1]
    assert "marginal (spectral radius within" in dm.lines()[0]


@pytest.mark.parametrize("rate_hz", [1000.0, 4000.0])
def test_the_sweep_lines_are_one_column(octo, rate_hz):
    # QA 24: "(  0.00 ms)" beside "(  10.0 ms)" and "1 periods".  Reference: the delay
    # n / rate_hz of each line, read back from the printed text
    import re
    scene, model = octo
    dm = delay_margin(dataclasses.replace(scene, rate_hz=rate_hz), model, max_periods=12)
    rows = [re.match(r"extra delay +(\d+) (period |periods) \(( *[\d.]+) ms\)", line)
            for line in dm.lines()[:-1]]
    assert all(rows)
    cells = [r.group(3) for r in rows]
    assert len({len(c) for c in cells}) == 1                 # one width
    assert len({len(c.partition(".")[2]) for c in cells}) == 1  # one number of decimals
    for r in rows:
        n = int(r.group(1))
        assert r.group(2) == ("period " if n == 1 else "periods")
        assert float(r.group(3)) == pytest.approx(n * 1e3 / rate_hz, abs=1e-9)
