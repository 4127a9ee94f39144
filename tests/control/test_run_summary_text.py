"""QA 23 D4: the run summary's text states the requested rate beside the achieved one,
what the period percentiles are (with their max, and the compute's CPU percentiles), and
``distkin sim``'s closing line says when no host ever connected instead of counting
device time that never started.  The numbers are the summary's own (JSON) fields; the
requested rate is the scene's ``[device] rate_hz``."""

import io
import re

from control_helpers import ScriptedLink, state_frames

from distkin.app.control_summary import format_summary, rate_check
from distkin.control.config import builtin_scene
from distkin.control.controller import Controller
from distkin.control.kinematics import model_of
from distkin.control.simulator import serve


def _summary(monkeypatch):
    scene = builtin_scene()
    model = model_of(scene)
    dev = ScriptedLink(state_frames(model, range(1, 400))).patch(monkeypatch)
    s = Controller(scene, model).run(dev, 5.0)
    rate_check(s, scene.rate_hz)
    return scene, s


def test_the_text_states_the_requested_rate_and_the_periods_max(monkeypatch):
    scene, s = _summary(monkeypatch)
    text = format_summary(s)
    assert f"rate: {s['loop_rate_hz']:.1f} Hz of {scene.rate_hz:g} Hz requested" in text
    assert f"(nominal {1e3 / scene.rate_hz:g} ms)" in text
    assert f"max {s['period_max_ms']} ms" in text
    assert f"CPU time p50 {s['cycle_cpu_p50_ms']} ms" in text
    assert "catching up" not in text             # the scripted device keeps its period


def test_a_p50_below_the_nominal_period_is_explained(monkeypatch):
    scene, s = _summary(monkeypatch)
    s["period_p50_ms"] = 0.3 * 1e3 / scene.rate_hz        # frames back to back
    line = next(x for x in format_summary(s).splitlines() if "period between" in x)
    assert "catching up" in line


def test_an_idle_simulator_says_no_host_connected():
    out = io.StringIO()
    assert serve(builtin_scene(), idle_timeout=0.3, announce=out) == 0
    last = out.getvalue().strip().splitlines()[-1]
    assert "no host sent a command" in last and "ticks late" not in last
    assert not re.search(r"\d s device time", last)
