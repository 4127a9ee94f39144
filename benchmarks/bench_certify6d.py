"""The 6-D rows of the certified workspace (issue 17): the Octopod's and the Octo's
150 mm cube × ±20° / ±30° with the batched binary64 route, and that route against the
arb route on the same chunks.  The full section is ``python -m benchmarks certify``."""

from __future__ import annotations

import time

from .bench_certify import _routes_section, _six_d_section
from .harness import fmt_time

__all__ = ["TITLE", "DEFAULT", "run"]

TITLE = "Certified workspace, 6-D rows: binary64 Taylor models, boxes per wall second"
DEFAULT = False          # about 2-3 min on 2 cores: `python -m benchmarks certify6d`


def run():
    data = {}
    t0 = time.perf_counter()
    parts = [_six_d_section(data), _routes_section(data)]
    data["total_seconds"] = time.perf_counter() - t0
    parts.append(f"Total benchmark time {fmt_time(data['total_seconds'])}.")
    return "\n\n".join(parts) + "\n", data
