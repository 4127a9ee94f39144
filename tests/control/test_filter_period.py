"""The derivative filter's time constant is refused below one period (QA: T = 0.4 ms at
1 kHz, h/T = 2.5, was accepted; the forward-Euler low-pass then diverged and NaN
torques went out).  The bound is checked against the recurrence itself, iterated here
(an impulse response), not against the loader's own arithmetic."""

import numpy as np
import pytest

from distkin.control.config import loads_control_scene
from distkin.errors import InputError

from control_helpers import scene_text


def _impulse_response(T, h, n=200):
    """|d_f| of ``d_f += (h/T)(d - d_f)`` after a unit impulse in d, n steps."""
    d_f, out = 0.0, []
    for k in range(n):
        d = 1.0 if k == 0 else 0.0
        d_f = d_f + (h / T) * (d - d_f)
        out.append(d_f)
    return np.array(out)


def _load(T, rate=1000):
    text = scene_text(derivative_filter_s=T, rate_hz=rate)
    return loads_control_scene(text, "s.toml")


@pytest.mark.parametrize("T_ms, rate", [(0.4, 1000), (0.9, 1000), (0.1, 4000),
                                        (1.999, 500)])
def test_a_filter_shorter_than_a_period_is_refused(T_ms, rate):
    h = 1.0 / rate
    r = _impulse_response(T_ms * 1e-3, h)
    assert np.any(np.diff(np.sign(r[1:6])) != 0)       # it rings (or diverges)
    with pytest.raises(InputError) as ei:
        _load(T_ms * 1e-3, rate)
    e = ei.value
    assert e.field == "pd.derivative_filter_s"
    msg = str(e)
    assert f"{T_ms:g} ms" in msg and f"{h * 1e3:g} ms" in msg
    assert "lower pd.kp" not in msg


def test_the_qa_value_diverges_and_names_the_bound():
    r = _impulse_response(0.4e-3, 1e-3)
    assert abs(r[-1]) > 1e20                            # |1 - 2.5| = 1.5 per step
    with pytest.raises(InputError, match=r"0\.5 ms it diverges"):
        _load(0.0004)


@pytest.mark.parametrize("T, rate", [(0.0, 1000), (1e-3, 1000), (0.7, 1000),
                                     (0.25e-3, 4000)])
def test_zero_and_one_period_or_more_are_accepted(T, rate):
    r = _impulse_response(T, 1.0 / rate) if T else np.zeros(3)
    assert np.all(r >= 0) and abs(r[-1]) <= 1.0          # no ringing, no growth
    assert _load(T, rate).pd.derivative_filter_s == T
