"""The scene's ``[device] realtime`` switch and the scheduling requests behind it."""

import os

import pytest

from distkin.control import scheduling
from distkin.control.config import loads_control_scene
from distkin.errors import InputError

from control_helpers import scene_text


def test_realtime_is_off_by_default_and_read_from_the_device_table():
    assert loads_control_scene(scene_text(), "s.toml").realtime is False
    text = scene_text().replace('preset = "octo"', 'preset = "octo"\nrealtime = true', 1)
    assert loads_control_scene(text, "s.toml").realtime is True
    bad = scene_text().replace('preset = "octo"', 'preset = "octo"\nrealtime = 1', 1)
    with pytest.raises(InputError, match="device.realtime"):
        loads_control_scene(bad, "s.toml")


def test_realtime_is_granted_and_undone_or_refused_with_a_reason():
    before = (os.sched_getscheduler(0), os.sched_getparam(0).sched_priority)
    previous, why = scheduling.realtime()
    try:
        if previous is None:
            assert why.startswith("expected SCHED_FIFO")
        else:
            assert why == "" and previous == before
            assert os.sched_getscheduler(0) == os.SCHED_FIFO
            assert os.sched_getparam(0).sched_priority == scheduling.PRIORITY
    finally:
        scheduling.restore(previous)
    assert (os.sched_getscheduler(0), os.sched_getparam(0).sched_priority) == before
