"""Every event name the controller and the simulator write to their ``--log`` events
files is in docs/protocol.md (QA: ``watchdog_trip``, ``recovered``, ``zero_torque``,
``armed``, ``host_disconnected``, the events of a plain ``distkin control --sim`` run,
were named nowhere in the docs).  The names are read from the sources, not listed
here."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SOURCES = ["distkin/control/loop.py", "distkin/control/simulator.py",
           "distkin/control/safety.py"]
PATTERNS = [r'_event\("([a-z_]+)"', r'events\.add\([^,]+, "([a-z_]+)"',
            r'_enter_fault\(ctl, last, "([a-z_]+)"', r'\(STATUS_[A-Z_]+, "([a-z_]+)"\)']


def test_every_event_name_is_documented():
    names = set()
    for src in SOURCES:
        text = (ROOT / src).read_text(encoding="utf-8")
        for pat in PATTERNS:
            names |= set(re.findall(pat, text))
    assert {"watchdog_trip", "recovered", "zero_torque", "armed", "estop"} <= names
    doc = (ROOT / "docs" / "protocol.md").read_text(encoding="utf-8")
    missing = sorted(n for n in names if f"`{n}`" not in doc)
    assert not missing, missing
