"""Every column of the ``--log`` CSV files is documented with its unit in
docs/protocol.md (QA: PREFIX.cycles.csv and PREFIX.device.csv had no units and
undocumented columns).  The columns are taken from the objects that write them (the
controller's and the simulator's log), the documentation from the tables of
docs/protocol.md: two sources, held together."""

import re

import pytest

from distkin.app.control_commands import builtin_scene
from distkin.control.controller import Controller
from distkin.control.kinematics import load_model
from distkin.control.simulator import Simulator

from control_helpers import ROOT

DOC = (ROOT / "docs" / "protocol.md").read_text(encoding="utf-8")


def _table(heading):
    """{column name: unit} of the table after the line ``heading``."""
    i = DOC.index(heading)
    rows = {}
    for line in DOC[i:].splitlines()[1:]:
        if rows and not line.startswith("|"):
            break
        m = re.match(r"\|\s*(.+?)\s*\|\s*(.+?)\s*\|\s*(.+?)\s*\|$", line)
        if m and m.group(1) not in ("column", "---"):
            for name in re.findall(r"`([^`]+)`", m.group(1)):
                rows[name] = m.group(2)
    return rows


def _documented(col, table):
    if col in table:
        return table[col]
    stem = re.sub(r"_\d+$", "", col)          # tau_3 -> the tau_0 … row
    return table.get(f"{stem}_0")


@pytest.fixture(scope="module")
def model():
    return load_model("octo", compiled=False)


def test_every_cycles_column_has_a_unit(model):
    cols = Controller(builtin_scene(), model, fused=False).log.columns
    table = _table("`PREFIX.cycles.csv` (host):")
    missing = [c for c in cols if not _documented(c, table)]
    assert not missing
    assert table["tau_0"].startswith("N·m") and "(N)" in table["tau_0"]
    assert table["x_x"] == "m" and table["x_rx"] == "rad" and table["f_x"] == "N"
    assert table["compute_s"] == "s" and table["fk_res"] == "m"


def test_every_device_column_has_a_unit(model):
    cols = Simulator(builtin_scene(), model, transport=None).log.columns
    table = _table("`PREFIX.device.csv` (simulator):")
    missing = [c for c in cols if not _documented(c, table)]
    assert not missing
    assert table["v_x"] == "m/s" and table["v_wx"] == "rad/s" and table["hand_x"] == "N"


def test_the_summary_fields_and_the_nan_rule_are_documented():
    for word in ("final_state", "fault_seconds", "nonfinite_cycles", "nonfinite_torque",
                 "stopped_by_signal"):
        assert f"`{word}`" in DOC, word
