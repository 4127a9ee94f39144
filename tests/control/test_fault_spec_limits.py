"""Fault specs (distkin sim --faults) that are no test but a hazard are refused.

Review findings: ``garbage@1:100000000000`` was accepted and would draw 100 GB of random
bytes in memory at once; ``stall@1:99999999999999`` held the simulator for three thousand
years; ``drop@inf`` (and ``drop@1e400``) scheduled a fault that never fires, silently."""

import pytest

from distkin.control.faults import FAULT_MAX, FaultInjector, parse_faults
from distkin.errors import InputError


@pytest.mark.parametrize("spec, says", [
    ("garbage@1:100000000000", "at most 10000000 bytes"),
    ("stall@1:99999999999999", "at most 600000 ms"),
    ("drop@inf", "finite time"), ("drop@1e400", "finite time"), ("drop@nan", "finite")])
def test_hazards_are_refused_naming_the_item(spec, says):
    with pytest.raises(InputError) as exc:
        parse_faults(f"corrupt@0.5,{spec}")
    assert exc.value.field == "--faults[1]" and says in str(exc.value)


def test_the_largest_allowed_burst_is_sent_whole():
    f = parse_faults(f"garbage@0:{FAULT_MAX['garbage']},stall@0:{FAULT_MAX['stall']}")
    inj = FaultInjector(f)
    out = inj.outgoing(0.0, b"\x01\x02\x00")
    assert len(out) == FAULT_MAX["garbage"] + 3 and out.endswith(b"\x01\x02\x00")
    assert inj.take_stall_ms() == 600_000
