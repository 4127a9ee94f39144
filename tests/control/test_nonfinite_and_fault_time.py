"""A NaN or infinite effort never reaches the wire, and the summary says how the run
ended (QA: NaN torques were sent while the run reported clean; a run held for most of
its time reported only ``completed``).

The device is :class:`control_helpers.PlantLink` (the simulated plant, lock-stepped on
a simulated clock).  The scenes bypass the loader's refusal of an unstable derivative
filter (``dataclasses.replace``): kd = 0 and T = 0.1 ms at 1 kHz make the filter's
forward-Euler eigenvalue 1 - h/T = -9, so its state overflows within a few hundred
cycles and ``kp e + 0 · inf`` is NaN.  The expectations come from the protocol's
promise (every command finite, at most the float32 limit) and, for the fault time,
from a second route: the per-cycle ``state`` column of the cycles log.
"""

import dataclasses
import types

import numpy as np
import pytest

import distkin.control.link as link_mod
import distkin.control.loop as loop_mod
from distkin.app.control_commands import builtin_scene, format_summary
from distkin.control.controller import Controller
from distkin.control.kinematics import load_model
from distkin.control.protocol import MODE_RUN, float32_floor
from distkin.control.runlog import read_csv

from control_helpers import PlantLink


@pytest.fixture(scope="module")
def model():
    return load_model("octo")


def _unstable_filter_scene():
    s = builtin_scene()
    return dataclasses.replace(s, pd=dataclasses.replace(s.pd, kd=0.0,
                                                         derivative_filter_s=1e-4))


def _run(monkeypatch, scene, model, seconds, *, fused=True, log_prefix=None):
    dev = PlantLink(scene, model, int(seconds * scene.rate_hz) + 2000)
    clock = types.SimpleNamespace(perf_counter=dev.perf_counter,
                                  thread_time=dev.thread_time)
    monkeypatch.setattr(loop_mod, "time", clock)
    monkeypatch.setattr(link_mod, "time", clock)
    ctl = Controller(scene, model, fused=fused, log_prefix=log_prefix)
    with np.errstate(all="ignore"):        # the reference route overflows on purpose
        summary = ctl.run(dev, seconds)
    return ctl, dev, summary


@pytest.mark.parametrize("fused", [True, False])
def test_a_nan_torque_is_a_fault_with_zero_torque_on_the_wire(monkeypatch, model, fused):
    scene = _unstable_filter_scene()
    ctl, dev, s = _run(monkeypatch, scene, model, 1.0, fused=fused)
    limit = float32_floor(scene.pd.torque_limit)
    sent = np.array([c.torques for _, c in dev.commands])
    # the protocol's promise (docs/protocol.md): finite, never beyond the limit
    assert np.all(np.isfinite(sent))
    assert np.all(np.abs(sent.astype(np.float32)) <= limit)
    ev = [e for e in ctl.events.events if e["event"] == "nonfinite_torque"]
    assert len(ev) == s["nonfinite_cycles"] >= 1
    assert s["final_state"] == "fault"
    # after the event no run command with a torque goes out until a recovery
    i = next(k for k, (_, c) in enumerate(dev.commands)
             if c.mode != MODE_RUN and k > 0 and dev.commands[k - 1][1].mode == MODE_RUN)
    assert not np.any(sent[i:]) or any(e["event"] == "recovered" for e in ctl.events.events)
    assert np.isfinite(s["max_abs_torque_Nm"]) and s["max_abs_torque_Nm"] <= limit
    text = format_summary(s)
    assert "NaN or infinite" in text
    assert "state: fault after the last cycle, then zero torque" in text


def test_fault_seconds_agrees_with_the_state_column_of_the_log(monkeypatch, model, tmp_path):
    ctl, dev, s = _run(monkeypatch, _unstable_filter_scene(), model, 0.8,
                       log_prefix=str(tmp_path / "r"))
    c = read_csv(tmp_path / "r.cycles.csv")
    t, state = c["t_dev"], c["state"]
    # intervals between consecutive cycles with either end outside RUN (state 0)
    held = (state[:-1] != 0) | (state[1:] != 0)
    want = float(np.sum(np.diff(t)[held]))
    assert s["fault_seconds"] == pytest.approx(want, abs=2e-3)
    assert 0.1 < s["fault_seconds"] < s["device_seconds"]
    assert s["exit_reason"] == "completed" and s["final_state"] == "fault"


def test_a_clean_run_reports_run_and_no_fault_time(monkeypatch, model):
    ctl, dev, s = _run(monkeypatch, builtin_scene(), model, 0.3)
    assert s["final_state"] == "run" and s["fault_seconds"] == 0.0
    assert s["nonfinite_cycles"] == 0
    assert "0.000 s of device time in fault or hold" in format_summary(s)
