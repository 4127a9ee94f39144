"""Timing limits of a controller scene (QA S 4, S 6): a watchdog window shorter than two
device periods, and a rate no serial link carries, are refused at load (exit 2, naming
the field), instead of a run that sits at zero torque and reports "completed"."""

import pytest
from control_helpers import run_cli, scene_text

from distkin.control.config import MAX_RATE_HZ, loads_control_scene
from distkin.errors import InputError


def test_a_watchdog_shorter_than_two_periods_is_refused_naming_it_and_the_period():
    # 10 Hz: a period of 100 ms (1000 / rate_hz, computed here by hand), watchdog 20 ms
    with pytest.raises(InputError) as exc:
        loads_control_scene(scene_text(rate_hz=10, watchdog_ms=20))
    assert exc.value.field == "safety.watchdog_ms"
    assert "100 ms" in exc.value.message and ">= 200 ms" in exc.value.message
    assert "got 20 ms" in exc.value.message


def test_two_periods_of_watchdog_are_accepted():
    # a virtual mass 100 times the example's: its admittance is stable at 10 Hz too
    # (h²k/m + 2hd/m = 0.07 and 0.08 < 4; the example's own is not, and is refused)
    s = loads_control_scene(scene_text(
        rate_hz=10, watchdog_ms=200, mass="[100.0, 100.0, 100.0, 0.5, 0.5, 0.5]").replace(
        "[simulator]\n", "[simulator]\ndevice_watchdog_ms = 200\n"))
    assert s.rate_hz == 10 and s.safety.watchdog_ms == 200


def test_a_device_watchdog_shorter_than_two_periods_is_refused():
    # the default device watchdog (100 ms) at 10 Hz: a command comes every 100 ms
    with pytest.raises(InputError) as exc:
        loads_control_scene(scene_text(rate_hz=10, watchdog_ms=500))
    assert exc.value.field == "simulator.device_watchdog_ms"


@pytest.mark.parametrize("rate", ["1e7", "10001"])
def test_a_rate_above_what_a_serial_link_carries_is_refused(rate):
    with pytest.raises(InputError) as exc:
        loads_control_scene(scene_text(rate_hz=rate))
    assert exc.value.field == "device.rate_hz" and "10000 Hz" in exc.value.message
    assert float(rate) > MAX_RATE_HZ


def test_a_rate_below_one_hertz_is_refused():
    with pytest.raises(InputError) as exc:
        loads_control_scene(scene_text(rate_hz="0.5", watchdog_ms=5000).replace(
            "[simulator]\n", "[simulator]\ndevice_watchdog_ms = 5000\n"))
    assert exc.value.field == "device.rate_hz" and "at least 1 Hz" in exc.value.message


def test_the_cli_refuses_a_short_watchdog_with_exit_2_before_starting(tmp_path):
    (tmp_path / "s.toml").write_text(scene_text(rate_hz=10, watchdog_ms=20))
    proc = run_cli(["control", "--sim", "--seconds", 2, "--scene", tmp_path / "s.toml",
                    "--json", tmp_path / "r.json"], tmp_path)
    assert proc.returncode == 2, proc.stderr
    assert "safety.watchdog_ms" in proc.stderr and "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "r.json").exists()
