"""The paper's tables as stored in distkin, digit by digit against the seed text itself.

Reference: Kühne et al., *Design and Evaluation of a Haptic Interface With Octopod
Kinematics*, the text of the seed paper (``../shared/seeds/000_81531e2621793aa6.txt``
beside the clone): Table III (five columns, ten rows, min and max), Table IV (GII, σmin,
σmax), Table V (experiment, simulation) and the GII optimum of Sec. III-B-2 ("the GII
is 0.0006 with σmin = 0.0127 and σmax = 20.0052").  Every number the study and the
findings compare with is one of these (``PAPER_TABLE3``, ``PAPER_TABLE4``,
``PAPER_TABLE5``, ``PAPER_TABLE1``); the numbers are parsed from the text here, not
retyped, so a transcription slip fails."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

SEED = (Path(__file__).resolve().parents[2].parent / "shared" / "seeds"
        / "000_81531e2621793aa6.txt")

#: the paper's row labels (Table III), in the order of distkin.indices.study._ROWS
T3_LABELS = ("Continuous force [N]", "Continuous torque [N · m]", "Velocity [m/s]",
             "Angular velocity [rad/s]", "Acceleration [m/s2]",
             "Angular Acceleration [rad/s2]", "Max. translational sensitivity [m/rad]",
             "Max. rotational sensitivity [rad/rad]", "Max. force sensitivity [N/N·m]",
             "Max. torque sensitivity [N·m/N·m]")
#: Table III's columns as the paper orders them
T3_COLUMNS = ("ergin", "hexa", "hunt", "octopod", "octo")
#: a printed number; Table V groups thousands with a space ("34 341.13")
NUM = r"\d{1,3}(?: \d{3})*\.\d+|\d+\.\d+"


@pytest.fixture(scope="module")
def text():
    if not SEED.is_file():
        pytest.skip(f"the seed paper's text is not at {SEED} (../shared/seeds beside the "
                    "clone): nothing to check the transcription against")
    return SEED.read_text(encoding="utf-8")


def _block(text, start, end):
    i = text.index(start)
    return text[i:text.index(end, i)]


def _num(s):
    return float(s.replace(" ", ""))


def _row(block, label):
    line = next(ln for ln in block.splitlines() if ln.startswith(label + " "))
    return line[len(label):]


def test_table3_digit_by_digit(text):
    from distkin.indices.study import _ROWS, PAPER_TABLE3
    block = _block(text, "TABLE III", "The Octopod kinematics and the realized Octo")
    assert "Ergin’s device HEXA Hunt-type Octopod (Rot. ±30◦) Octo (Rot. ±30◦)" in block
    assert len(_ROWS) == len(T3_LABELS)
    for row, label in zip(_ROWS, T3_LABELS):
        pairs = re.findall(rf"({NUM}) \(({NUM})\)", _row(block, label))
        assert len(pairs) == len(T3_COLUMNS), (label, pairs)
        for col, (lo, hi) in zip(T3_COLUMNS, pairs):
            assert PAPER_TABLE3[col][row] == (_num(lo), _num(hi)), (col, row)
    assert set(PAPER_TABLE3) == set(T3_COLUMNS)


def test_table4_digit_by_digit(text):
    from distkin.indices.study import PAPER_TABLE4
    block = _block(text, "TABLE IV", "be employed to improve")
    for col, label in (("hunt", "Hunt-type kinematics"), ("octopod", "Octopod kinematics"),
                       ("octo", "Octo kinematics")):
        got = tuple(_num(v) for v in re.findall(NUM, _row(block, label)))
        assert PAPER_TABLE4[col] == got, col
    assert set(PAPER_TABLE4) == {"hunt", "octopod", "octo"}


def test_table5_digit_by_digit(text):
    from distkin.control.table5 import PAPER_TABLE5
    block = _block(text, "TABLE V", "Angular Acceleration [rad/s2]")
    block += "\n" + next(ln for ln in text[text.index("TABLE V"):].splitlines()
                         if ln.startswith("Angular Acceleration [rad/s2]"))
    for row, label in zip(("force", "torque", "velocity", "angular_velocity",
                           "acceleration", "angular_acceleration"), T3_LABELS):
        got = tuple(_num(v) for v in re.findall(NUM, _row(block, label)))
        assert PAPER_TABLE5[row] == got, row
    assert PAPER_TABLE5["angular_acceleration"][1] == 34341.13      # "34 341.13"


def test_gii_optimum_of_sec_3b2(text):
    from distkin.app.design_report import PAPER_TABLE1
    m = re.search(r"The optimum for the GII was found for l2 = (\d+) mm,\s*β = (\d+)◦, "
                  r"γ = (\d+)◦, and d = (\d+) mm\. Here, the GII is ([\d.]+) with\s*"
                  r"σmin = ([\d.]+) and σmax = ([\d.]+)\.", text)
    assert m, "the sentence of Sec. III-B-2 was not found"
    l2, beta, gamma, ld, gii, smin, smax = (float(g) for g in m.groups())
    assert (PAPER_TABLE1["l2"], PAPER_TABLE1["beta"], PAPER_TABLE1["gamma"]) == \
        (l2 / 1000, beta, gamma)
    assert PAPER_TABLE1["ld"] == pytest.approx(ld / 1000, abs=1e-15)
    assert (PAPER_TABLE1["gii"], PAPER_TABLE1["sigma_min"], PAPER_TABLE1["sigma_max"]) == \
        (gii, smin, smax)
    from distkin.indices.study import PAPER_TABLE4     # Table IV's Hunt-type row agrees
    assert PAPER_TABLE4["hunt"] == (gii, smin, smax)
