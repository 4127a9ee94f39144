"""The first fast octahedral solve on a machine: numba's compile in one process against
two (:mod:`distkin.octahedral.warmup`), and the first ``distkin demo`` both ways.

Every sample is a fresh interpreter with an empty numba cache (``NUMBA_CACHE_DIR`` in a
temporary folder), so that each compiles everything; the two ways alternate round by
round.  Wall time is what the user waits; CPU time is of the process and its children
(the warm-up's child included), from ``getrusage(RUSAGE_CHILDREN)``.
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

__all__ = ["TITLE", "DEFAULT", "run"]

TITLE = "First fast octahedral solve on a machine: the compile in one or two processes"
DEFAULT = False

ROOT = Path(__file__).resolve().parent.parent

_SOLVE = r"""
import sys, numpy as np
from distkin.octahedral import forward_kinematics, warmup
if sys.argv[1] == "two":
    warmup.compile_fast_tier()
B = np.array([[0.0, 0.0, 0.0], [12.0, 0.0, 0.0], [6.0, 6.0 * 3 ** 0.5, 0.0]])
forward_kinematics(B, 0.5 * B, [20.0, 18.0, 18.0, 17.0, 15.0, 18.0])
"""

#: ``distkin demo`` with the warm-up (as shipped) or without it (``one``)
_DEMO = r"""
import sys
import distkin.octahedral.warmup as w
if sys.argv[1] == "one":
    w.compile_fast_tier = lambda **kw: ()
from distkin.app.cli import main
sys.exit(main(["demo", "--no-progress"]))
"""


def _sample(program: str, way: str) -> tuple:
    """(wall s, CPU s of the process and its children) of one fresh-cache run."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache,
                   PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        w0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", program, way], check=True, env=env,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        wall = time.perf_counter() - w0
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def run(rounds: int = 3, demo_rounds: int = 1):
    rows, data = [], {}
    for label, program, n in (("first fast solve (Griffis-Duffy)", _SOLVE, rounds),
                              ("`distkin demo`", _DEMO, demo_rounds)):
        got = {"one": [], "two": []}
        for _ in range(n):
            for way in got:
                got[way].append(_sample(program, way))
        med = {w: (statistics.median(s[0] for s in v), statistics.median(s[1] for s in v))
               for w, v in got.items()}
        data[label] = {w: {"wall_s": m[0], "cpu_s": m[1], "samples": got[w]}
                       for w, m in med.items()}
        rows.append(f"| {label} | {med['one'][0]:.1f} s | {med['two'][0]:.1f} s | "
                    f"{med['one'][0] / med['two'][0]:.2f}× | {med['one'][1]:.1f} s | "
                    f"{med['two'][1]:.1f} s |")
    load = os.getloadavg()
    text = (f"Fresh interpreter and empty numba cache per sample, the two ways alternated; "
            f"median of {rounds} rounds for the solve, {demo_rounds} for the demo (load "
            f"{load[0]:.1f} at the end).  *one process*: numba compiles the scan, then "
            "the proof, on the first call; *two processes*: "
            "`distkin.octahedral.warmup.compile_fast_tier` (what the CLI's octahedral and "
            "Δ queries call before their first fast solve) compiles the proof in a child "
            "beside the scan.\n\n| run | wall, one process | wall, two processes | "
            "speed-up | CPU, one | CPU, two (with the child) |\n|---|---|---|---|---|---|\n"
            + "\n".join(rows) + "\n")
    return text, data
