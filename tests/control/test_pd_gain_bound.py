"""QA X1 D4: ``pd.kp = 1.7e308`` reached the linearisation of ``--delay-margin`` and
the run's summary: ``internal failure: LinAlgError: Array must not contain infs or
NaNs``, exit 1 (1e307 passed).  Gains beyond ``MAX_GAIN_PER_LIMIT x torque_limit``
(the whole torque limit for an error of 1e-12 rad, or rad/s, or rad·s) are refused at
load, exit 2, naming the gain."""

import dataclasses

import numpy as np
import pytest

from distkin.control.config import MAX_GAIN_PER_LIMIT, loads_control_scene
from distkin.control.delay_margin import closed_loop_matrix
from distkin.control.kinematics import load_model
from distkin.control.plant import Motors
from distkin.errors import InputError

from control_helpers import run_cli, scene_text


def test_the_bound_is_far_below_an_encoder_count():
    """At the bound the whole limit comes from an error of 1e-12 rad: under a millionth
    of the Octo's encoder count at the crank (2 pi / (2000 x 13) rad)."""
    count = 2 * np.pi / (2000 * 13)
    assert Motors().resolution == pytest.approx(count)
    assert 1.0 / MAX_GAIN_PER_LIMIT < 1e-6 * count


@pytest.mark.parametrize("key", ["kp", "kd", "ki"])
@pytest.mark.parametrize("value", ["1.7e308", "1e307", "2.6e12"])
def test_gains_beyond_the_bound_are_refused_at_load(key, value):
    with pytest.raises(InputError) as exc:
        loads_control_scene(scene_text(**{key: value}))
    assert exc.value.field == f"pd.{key}"
    assert "2.5e+12" in exc.value.message and repr(float(value)) in exc.value.message


def test_a_gain_at_the_bound_linearises_to_finite_numbers():
    scene = loads_control_scene(scene_text(kp="2.5e12"))
    A = closed_loop_matrix(scene, load_model("octo"))
    assert np.all(np.isfinite(A))


@pytest.mark.parametrize("mode", [["--delay-margin", "1"], ["--sim", "--seconds", "0.2"]])
def test_the_cli_refuses_it_with_one_line(tmp_path, mode):
    scene = tmp_path / "kp.toml"
    scene.write_text(scene_text(kp="1.7e308"), encoding="utf-8")
    proc = run_cli(["control", *mode, "--scene", scene], tmp_path)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("distkin: error: pd.kp: expected at most")
