"""Helpers of the two-process control tests: scene variants, running the CLI, and the
controller's estimate against the simulator's true pose."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "control_octo.toml"


def scene_text(**replace) -> str:
    """The example scene with some ``key = value`` lines replaced (first occurrence)."""
    lines = EXAMPLE.read_text(encoding="utf-8").splitlines()
    for key, value in replace.items():
        for i, line in enumerate(lines):
            if line.split("=")[0].strip() == key:
                lines[i] = f"{key} = {value}"
                break
        else:
            raise KeyError(key)
    return "\n".join(lines) + "\n"


def run_cli(args, cwd, timeout=120):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", "distkin", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, env=env, timeout=timeout)


def robust_scene_text(**replace) -> str:
    """:func:`scene_text` with the watchdog windows (2 s) and the simulator's wait for
    each answer (1 s) widened: a loaded machine then slows a run down instead of
    changing its physics.  For tests whose subject is not the watchdog."""
    replace.setdefault("watchdog_ms", 2000)
    return scene_text(**replace).replace(
        "[simulator]\n", "[simulator]\nreply_timeout_ms = 1000\ndevice_watchdog_ms = 2000\n")


def estimate_and_truth(prefix):
    """The controller's position estimate and the simulator's true position (n, 3), m,
    of the same device states (a cycle answers the state frame of the same sequence
    number), from the logs ``PREFIX.cycles.csv`` and ``PREFIX.device.csv``."""
    from distkin.control.runlog import read_csv
    cyc, dev = read_csv(f"{prefix}.cycles.csv"), read_csv(f"{prefix}.device.csv")
    at = {int(q): i for i, q in enumerate(dev["seq"])}
    rows = [(i, at[int(q)]) for i, q in enumerate(cyc["seq"]) if int(q) in at]
    ci, di = map(np.array, zip(*rows))
    est = np.stack([cyc[f"x_{k}"][ci] for k in ("x", "y", "z")], axis=-1)
    true = np.stack([dev[f"x_{k}"][di] for k in ("x", "y", "z")], axis=-1)
    return est, true
