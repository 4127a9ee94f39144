"""QA X1 D8: inputs that were accepted silently, or answered with a library's warning,
while their neighbours were refused with one line naming the field."""

import warnings

import pytest

from distkin.control.config import loads_control_scene
from distkin.control.runlog import read_csv
from distkin.errors import InputError

from control_helpers import run_cli, scene_text

MINIMAL = """
[device]
preset = "octo"
[admittance]
mass = MASS
damping = [15, 15, 15, 0.1, 0.1, 0.1]
[simulator]
hand = HAND
"""


def _load(mass="[1.0, 1.0, 1.0, 0.005, 0.005, 0.005]", hand="[[0.0, 0, 0, 0]]", title=None):
    text = MINIMAL.replace("MASS", mass).replace("HAND", hand)
    if title is not None:
        text = f"title = {title}\n" + text
    return loads_control_scene(text)


@pytest.mark.parametrize("title", ["5", "{a = 1}", "[1, 2]", "true"])
def test_a_title_that_is_not_a_string_is_refused(title):
    with pytest.raises(InputError) as exc:
        _load(title=title)
    assert exc.value.field == "title" and exc.value.message.startswith("expected a string")
    assert _load(title='"Octo"').title == "Octo"


def test_hand_knots_before_time_zero_are_refused():
    with pytest.raises(InputError) as exc:
        _load(hand="[[-1.0, 0, 0, 0], [1.0, 0, 2, 0]]")
    assert exc.value.field == "simulator.hand" and "got -1 s" in exc.value.message
    assert _load(hand="[[0.0, 0, 0, 0], [1.0, 0, 2, 0]]").simulator.hand.points[1][2] == 2


@pytest.mark.parametrize("mass", ['["1", "1", "1", "0.005", "0.005", "0.005"]',
                                  '[1, 1, 1, 0.005, 0.005, "0.005"]',
                                  '[1, 1, 1, 0.005, 0.005, true]'])
def test_numbers_written_as_strings_are_refused_as_kp_is(mass):
    with pytest.raises(InputError) as kp:
        loads_control_scene(scene_text(kp='"110"'))
    assert kp.value.field == "pd.kp"
    with pytest.raises(InputError) as exc:
        _load(mass=mass)
    assert exc.value.field == "admittance.mass" and "SI, TOML numbers" in exc.value.message


def test_hand_knots_as_strings_are_refused():
    with pytest.raises(InputError) as exc:
        _load(hand='[["0", 0, 0, 0]]')
    assert exc.value.field == "simulator.hand"


@pytest.mark.parametrize("option", [["--seconds", "1"], ["--allow-unstable"]])
def test_delay_margin_refuses_run_options_as_it_refuses_log(tmp_path, option):
    """--log, --faults, --wall-limit were refused with --delay-margin; --seconds and
    --allow-unstable were ignored."""
    proc = run_cli(["control", "--delay-margin", "1", *option], tmp_path)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert lines == [f"distkin: error: {option[0]}: expected no {option[0]} with "
                     f"--delay-margin (nothing runs), got one"]


def test_an_empty_log_reads_and_plots_without_a_numpy_warning(tmp_path):
    """``--port loop:// --plots lp``: no frame, so the cycle log holds its header only;
    numpy's 'loadtxt: input contained no data' reached the terminal."""
    prefix = tmp_path / "run"
    (tmp_path / "run.cycles.csv").write_text("t_wall,t_dev,x_x\n", encoding="utf-8")
    (tmp_path / "run.events.jsonl").write_text("", encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c = read_csv(f"{prefix}.cycles.csv")
        assert list(c) == ["t_wall", "t_dev", "x_x"] and c["t_dev"].shape == (0,)
    (tmp_path / "run.cycles.csv").write_text("t_wall,t_dev,x_x\n1,2,3\n", encoding="utf-8")
    assert read_csv(f"{prefix}.cycles.csv")["x_x"].tolist() == [3.0]
