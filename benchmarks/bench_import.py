"""Import cost of ``import distkin`` and what it pulls in (foundation issue)."""

from __future__ import annotations

import json
import statistics
import subprocess
import sys

__all__ = ["TITLE", "DEFAULT", "run"]

TITLE = "Import time of distkin"
DEFAULT = True

_PROBE = r"""
import sys, time, json
t0 = time.perf_counter()
import {mod}
dt = time.perf_counter() - t0
print(json.dumps({{"t": dt, "sympy": "sympy" in sys.modules, "numpy": "numpy" in sys.modules,
                  "flint": "flint" in sys.modules}}))
"""


def _measure(mod: str, n: int = 7):
    out = []
    for _ in range(n):
        r = subprocess.run([sys.executable, "-c", _PROBE.format(mod=mod)], capture_output=True,
                           text=True, check=True)
        out.append(json.loads(r.stdout))
    return statistics.median(o["t"] for o in out), out[-1]


def run():
    rows, data = [], {}
    for mod in ("numpy", "sympy", "distkin", "distkin.geometry", "distkin.app.scene"):
        t, flags = _measure(mod)
        data[mod] = {"median_s": t, **flags}
        rows.append(f"| `import {mod}` | {t * 1e3:.0f} ms | {'yes' if flags['sympy'] else 'no'} |")
    base = data["distkin"]["median_s"]
    text = ("Fresh interpreter per sample, 7 samples, median. Target: `import distkin` under "
            "0.5 s without sympy.\n\n| statement | median | sympy imported? |\n|---|---|---|\n"
            + "\n".join(rows)
            + f"\n\n`import distkin` costs {base / data['sympy']['median_s']:.2f}× an "
              "`import sympy` alone.\n")
    return text, data
