"""QA 23 D3, D5, D6: unit slips in a controller scene.  A value in the wrong unit that
loads (ms typed as s, mm as m, g as kg, N/mm as N/m) is one ``distkin: warning:`` line,
as ``workspace_m = 75`` already was; the refusals state the received value with its
unit; ``rate_hz = 1`` (1 kHz meant) is blamed on the rate, not on the derivative filter.

References: the paper's values (Kühne et al. Sec. III-D: 1 kHz, a 700 ms filter), the
Octo's geometry (home 0.3 m above the base), the servo stiffness the README and
``PDGains`` state (1.30 N/mm along x at the workspace centre), and the drives' stall
torque 2.63 N·m at the motor through the 1:13 capstan (34.2 N·m)."""

import math
import shutil
from pathlib import Path

import pytest
from control_helpers import run_cli, scene_text

from distkin.app.control_scene_files import scene_and_inputs
from distkin.control.config import loads_control_scene
from distkin.errors import InputError

ROOT = Path(__file__).resolve().parents[2]


def _warned(text):
    return dict(loads_control_scene(text).warnings)


@pytest.mark.parametrize("path", sorted((ROOT / "examples").glob("control_*.toml")))
def test_the_shipped_scenes_load_without_a_warning(path):
    scene, _ = scene_and_inputs(str(path))
    assert scene.warnings == ()


def test_a_filter_in_ms_typed_as_s_is_a_warning():
    w = _warned(scene_text(derivative_filter_s=700))
    msg = w["pd.derivative_filter_s"]
    assert "700 s" in msg and "0.7" in msg
    # the slowest motion it follows: 1/(2π T) Hz
    assert f"{1 / (2 * math.pi * 700):.2g} Hz" in msg
    assert "pd.derivative_filter_s" not in _warned(scene_text(derivative_filter_s=0.7))


def test_a_wall_in_mm_typed_as_m_is_a_warning():
    # the example's wall: normal +x, home at x = 0; the Octo's home is 0.3 m above the
    # base, its size for the rule (10 x: 3 m)
    msg = _warned(scene_text(offset=20))["environment[1].offset"]
    assert "20 m from home" in msg and "0.3 m" in msg and "0.02" in msg
    assert "environment[1].offset" not in _warned(scene_text(offset=2.9))


def test_a_virtual_mass_in_g_typed_as_kg_is_a_warning():
    msg = _warned(scene_text(mass="[1000, 1000, 1000, 0.005, 0.005, 0.005]"))[
        "admittance.mass"]
    assert "x 1000 kg" in msg and "z 1000 kg" in msg and "rx" not in msg
    assert "admittance.mass" not in _warned(scene_text(
        mass="[30, 30, 30, 0.005, 0.005, 0.005]"))


def test_a_spring_in_n_per_mm_typed_as_n_per_m_is_a_warning():
    msg = _warned(scene_text(stiffness="[100000, 100000, 100000, 2, 2, 2]"))[
        "environment[0].stiffness"]
    # the servo's own 1.30 N/mm along x at the workspace centre (README, PDGains)
    servo = float(msg.split("KP JᵀJ: ")[1].split(" N/m")[0])
    assert servo == pytest.approx(1.30e3, rel=5e-3)
    assert "along x" in msg
    # 10 x the servo along x: 12.96 kN/m; below it, nothing said
    assert "environment[0].stiffness" not in _warned(scene_text(
        stiffness="[12000, 12000, 12000, 2, 2, 2]"))


def test_a_rate_in_khz_typed_as_hz_is_blamed_on_the_rate():
    with pytest.raises(InputError) as exc:
        loads_control_scene(scene_text(rate_hz=1, watchdog_ms=5000).replace(
            "[simulator]\n", "[simulator]\ndevice_watchdog_ms = 5000\n"))
    assert exc.value.field == "device.rate_hz"
    assert "1 Hz" in exc.value.message and "700 ms" in exc.value.message
    # without a filter to collide with, a slow rate loads, with a warning naming it
    w = _warned(scene_text(rate_hz=50, watchdog_ms=500, derivative_filter_s=0,
                           mass="[100.0, 100.0, 100.0, 0.5, 0.5, 0.5]").replace(
        "[simulator]\n", "[simulator]\ndevice_watchdog_ms = 500\n"))
    assert "50 Hz" in w["device.rate_hz"] and "1000" in w["device.rate_hz"]


@pytest.mark.parametrize("key, value, field, got", [
    ("kp", -110, "pd.kp", "got -110.0 N·m/rad"),
    ("torque_limit", 2500, "pd.torque_limit", "got 2500 N·m"),
    ("rate_hz", 0.5, "device.rate_hz", "got 0.5 Hz"),
    ("watchdog_ms", -1, "safety.watchdog_ms", "got -1.0 ms"),
])
def test_refusals_state_the_received_value_with_its_unit(key, value, field, got):
    with pytest.raises(InputError) as exc:
        loads_control_scene(scene_text(**{key: value}))
    assert exc.value.field == field and got in exc.value.message, exc.value.message
    if key == "torque_limit":             # 2.63 N·m at the motor x 13 (the capstan)
        assert f"{2.63 * 13:.3g} N·m" in exc.value.message


def test_a_prismatic_devices_gain_is_refused_in_n_per_m(tmp_path):
    for name in ("control_gough6.toml", "gough_stewart_6ups.toml"):
        shutil.copy(ROOT / "examples" / name, tmp_path / name)
    s = tmp_path / "control_gough6.toml"
    s.write_text(s.read_text(encoding="utf-8").replace("kp = 256960", "kp = -5"),
                 encoding="utf-8")
    with pytest.raises(InputError) as exc:
        scene_and_inputs(str(s))
    assert exc.value.field == "pd.kp" and "got -5.0 N/m" in exc.value.message


def test_the_cli_prints_one_warning_line_and_runs(tmp_path):
    (tmp_path / "s.toml").write_text(scene_text(derivative_filter_s=700), encoding="utf-8")
    proc = run_cli(["control", "--delay-margin", "1", "--scene", tmp_path / "s.toml"],
                   tmp_path)
    assert proc.returncode == 0, proc.stderr
    lines = [x for x in proc.stderr.splitlines() if x.startswith("distkin: warning")]
    assert len(lines) == 1 and lines[0].startswith(
        "distkin: warning: pd.derivative_filter_s: 700 s")
