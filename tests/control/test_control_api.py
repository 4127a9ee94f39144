"""QA 23 D11: the control package's Python API.  The pieces of a scripted run are
exported from ``distkin.control`` (README's example runs them: tests/test_readme_snippets),
its module table names every module of the folder, ``Controller`` cites the paper, and
the frame encoders refuse what no frame carries with InputError naming the argument."""

import re
from pathlib import Path

import numpy as np
import pytest

import distkin.control as control
from distkin.control.frame_codec import command_encoder, state_encoder
from distkin.control.protocol import encode_command, encode_state
from distkin.errors import InputError


def test_the_pieces_of_a_scripted_run_are_exported():
    for name in ("load_control_scene", "builtin_scene", "model_of", "Controller",
                 "open_link", "run_loopback"):
        assert name in control.__all__ and callable(getattr(control, name))


def test_the_module_table_names_every_module():
    folder = Path(control.__file__).parent
    modules = {p.stem for p in folder.glob("*.py") if p.stem != "__init__"}
    table = set(re.findall(r"^(\w+)\s{2,}\S", control.__doc__, flags=re.M))
    assert modules <= table, sorted(modules - table)


def test_the_controller_cites_the_paper():
    doc = control.Controller.__doc__
    assert "Kühne" in doc and "Octopod Kinematics" in doc and "Sec. III-D" in doc


@pytest.mark.parametrize("encode", [encode_command, command_encoder()],
                         ids=["reference", "compiled"])
def test_a_command_no_frame_carries_is_refused(encode):
    with pytest.raises(InputError) as exc:
        encode(1, 0, 1, np.zeros((2, 4)))          # a block, not 8 torques
    assert exc.value.field == "torques" and "(2, 4)" in exc.value.message
    for seq, ack, field in ((-1, 0, "seq"), (1, -5, "ack"), (2.5, 0, "seq")):
        with pytest.raises(InputError) as exc:
            encode(seq, ack, 1, np.zeros(8))
        assert exc.value.field == field
    # the wire's u32 takes a larger count modulo 2^32 (docs/protocol.md: it wraps)
    assert encode(2**32 + 3, 0, 1, np.zeros(8)) == encode_command(3, 0, 1, np.zeros(8))


def test_a_state_no_frame_carries_is_refused():
    with pytest.raises(InputError) as exc:
        encode_state(1, 0, 0, np.zeros((2, 4)), np.zeros(6))
    assert exc.value.field == "angles"
    with pytest.raises(InputError) as exc:
        encode_state(1, 0, 0, np.zeros(8), np.zeros((2, 3)))
    assert exc.value.field == "wrench"
    with pytest.raises(InputError) as exc:
        state_encoder()(-1, 0, 0, np.zeros(14))
    assert exc.value.field == "seq"
