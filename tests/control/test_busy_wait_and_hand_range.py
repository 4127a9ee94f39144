"""``[device] busy_wait_us`` beyond one period is refused, and a scripted hand beyond
the sensor range is warned about (QA optional items: both loaded silently; the hand's
readings were then rejected by the controller, the run sat at zero torque).  The period
is 1e6/rate_hz µs by definition; the sensor range is checked against the controller's
own reading check (:func:`distkin.control.safety.check_reading`), a second route."""

import types

import numpy as np
import pytest

from distkin.control.config import loads_control_scene
from distkin.control.safety import check_reading
from distkin.errors import InputError

from control_helpers import scene_text


def _with_busy(us, rate=1000):
    text = scene_text(rate_hz=rate).replace("[device]\n", f"[device]\nbusy_wait_us = {us}\n")
    return loads_control_scene(text, "s.toml")


@pytest.mark.parametrize("rate", [1000, 4000])
def test_busy_wait_up_to_one_period_loads_and_beyond_is_refused(rate):
    period_us = 1e6 / rate
    assert _with_busy(period_us, rate).busy_wait_us == period_us
    with pytest.raises(InputError) as ei:
        _with_busy(period_us + 1, rate)
    assert ei.value.field == "device.busy_wait_us"
    assert f"{period_us:g} µs" in str(ei.value) and f"{period_us + 1:g} µs" in str(ei.value)


def _with_hand(fx):
    tail = "[4.4, 7, 0, 0], [5.0, 7, 0, 0]]"
    text = scene_text()
    assert tail in text
    text = text.replace(tail, f"[4.4, {fx}, 0, 0], [5.0, {fx}, 0, 0]]")
    return loads_control_scene(text, "s.toml")


def _rejected(scene, fx):
    frame = types.SimpleNamespace(angles=np.zeros(8), wrench=np.array([fx, 0, 0, 0, 0, 0.]),
                                  status=0)
    return bool(check_reading(frame, 8, scene.safety))


def test_a_hand_beyond_the_sensor_range_warns():
    ok = _with_hand(7)
    assert ok.warnings == () and not _rejected(ok, 7)
    far = _with_hand(500)
    assert _rejected(far, 500)                          # the controller would reject it
    assert [f for f, _ in far.warnings] == ["simulator.hand"]
    assert "500 N" in far.warnings[0][1] and "100 N" in far.warnings[0][1]
