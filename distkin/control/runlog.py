"""Run logs a person can plot: per-cycle CSV tables and a JSON-lines event file.

:class:`CsvLog` costs the control loop one row copy per cycle and writes its CSV when
the run ends.  :class:`EventLog` writes each safety event as one
JSON line at once.  :func:`read_csv` loads a table back as a dict of numpy columns;
:func:`plot_run` draws a run (matplotlib, imported lazily).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from ..errors import InputError
from .safety import FAULT, RUN, STOPPED

__all__ = ["CsvLog", "EventLog", "read_csv", "read_events", "plot_run", "run_figure",
           "plot_delay_margin",
           "timing_summary", "run_summary", "EXIT_CODES", "STATE_NAMES",
           "check_log_prefix"]


def check_log_prefix(prefix) -> None:
    """Refuse a ``--log PREFIX`` of ``distkin control`` or ``distkin sim`` that names no
    file (InputError, exit 2): '' (nothing was written while the summary listed
    ``.cycles.csv``, QA) and a prefix ending in a path separator, ``.`` or ``..``
    (``--log dir/`` wrote the hidden files ``dir/.cycles.csv``).  None (no ``--log``)
    passes."""
    if prefix is None:
        return
    p = str(prefix)
    seps = tuple(s for s in (os.sep, os.altsep, "/") if s)
    if not p.strip():
        raise InputError(f"expected a file name prefix (PREFIX.cycles.csv, ...), got "
                         f"{p!r}", field="--log", hint="e.g. --log run or --log out/run")
    if p.endswith(seps) or os.path.basename(p) in ("", ".", ".."):
        raise InputError(f"expected a file name prefix, not a directory, got {p!r} (it "
                         f"would write hidden files such as "
                         f"{p.rstrip(''.join(seps)) or '.'}/.cycles.csv)", field="--log",
                         hint=f"name the files too, e.g. --log "
                              f"{p.rstrip(''.join(seps)) or '.'}/run")


class CsvLog:
    """Rows of floats with a header, written as CSV when the log is closed.

    While the loop runs, rows go into a preallocated block; a full block is appended
    to a binary side file (``PATH.part``, one ``write`` of raw float64, well under a
    millisecond), so that the loop never waits for text formatting and memory stays
    bounded.  :meth:`close` turns the side file into the CSV (called on every way out
    of a run).

    Parameters
    ----------
    path : str or Path or None
        Output file (None: no file).
    columns : sequence of str
    block : int
        Rows per block.
    keep : bool
        Without a file, keep the rows in memory (see :meth:`array`); otherwise only the
        last block is kept.
    """

    def __init__(self, path, columns, block: int = 4096, keep: bool = False):
        self.path = Path(path) if path else None
        self.keep = keep
        self.columns = list(columns)
        self._buf = np.empty((block, len(self.columns)))
        self._n = 0
        self._blocks: list = []
        self._spill = None
        if self.path is not None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._spill_path = self.path.with_name(self.path.name + ".part")
            self._spill = self._spill_path.open("wb")

    def add(self, row) -> None:
        self._buf[self._n] = row
        self._n += 1
        if self._n == self._buf.shape[0]:
            self._push()

    def _push(self) -> None:
        block = self._buf[: self._n]
        if self._spill is not None:
            self._spill.write(block.tobytes())
        elif self.keep:
            self._blocks.append(block.copy())
        self._n = 0

    def array(self) -> np.ndarray:
        """The rows kept in memory (all of them with ``keep=True``), (n, columns)."""
        parts = self._blocks + [self._buf[: self._n]]
        return np.concatenate(parts) if parts else np.zeros((0, len(self.columns)))

    def close(self) -> None:
        """Write the CSV (idempotent)."""
        if self._spill is None:
            return
        if self._n:
            self._push()
        self._spill.close()
        self._spill = None
        data = np.fromfile(self._spill_path, dtype=float).reshape(-1, len(self.columns))
        with self.path.open("w", encoding="utf-8") as fh:
            fh.write(",".join(self.columns) + "\n")
            np.savetxt(fh, data, delimiter=",", fmt="%.9g")
        self._spill_path.unlink()

    flush = close


class EventLog:
    """Safety and link events, one JSON object per line (``{"t", "event", ...}``)."""

    def __init__(self, path=None):
        self.path = Path(path) if path else None
        self.events: list[dict] = []
        if self.path is not None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.path.write_text("", encoding="utf-8")

    def add(self, t: float, event: str, **info) -> None:
        rec = {"t": round(float(t), 6), "event": event, **info}
        self.events.append(rec)
        if self.path is not None:
            with self.path.open("a", encoding="utf-8") as fh:
                fh.write(json.dumps(rec) + "\n")

    def count(self, event: str) -> int:
        return sum(1 for e in self.events if e["event"] == event)


def timing_summary(compute, compute_cpu, periods) -> dict:
    """Percentiles (p50, p99, max; ms, rounded to 0.1 µs) of a run's compute time per
    cycle in wall and CPU time (lists of s) and of its periods (s); None when empty.
    ``loop_rate_hz``: cycles per second from the first frame to the last (the number of
    periods over their sum), beside the summary's ``rate_hz`` (cycles over the run's
    whole wall time, connection and shut-down included)."""
    def pct(x, q):
        x = np.asarray(x) * 1e3
        return round(float(np.percentile(x, q)), 4) if x.size else None

    return {"cycle_p50_ms": pct(compute, 50), "cycle_p99_ms": pct(compute, 99),
            "cycle_max_ms": pct(compute, 100), "cycle_cpu_p50_ms": pct(compute_cpu, 50),
            "cycle_cpu_p99_ms": pct(compute_cpu, 99), "period_p50_ms": pct(periods, 50),
            "period_p99_ms": pct(periods, 99), "period_max_ms": pct(periods, 100),
            "loop_rate_hz": round(len(periods) / sum(periods), 2) if periods else None}


def read_csv(path) -> dict:
    """A CSV written by :class:`CsvLog` as {column: ndarray}."""
    path = Path(path)
    with path.open(encoding="utf-8") as fh:
        cols = fh.readline().strip().split(",")
        empty = not any(line.strip() for line in fh)
    # a run without cycles (no device) wrote the header only: no rows, and no numpy
    # "input contained no data" warning on the user's terminal (QA X1 D8)
    data = (np.zeros((0, len(cols))) if empty else
            np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2))
    return {c: data[:, i] for i, c in enumerate(cols)}


def read_events(path) -> list[dict]:
    """The events of an :class:`EventLog` file."""
    text = Path(path).read_text(encoding="utf-8")
    return [json.loads(line) for line in text.splitlines() if line.strip()]


def plot_run(prefix, out=None, *, effort_unit: str = "N·m", title: str = "",
             effort_limit: float | None = None, walls=()) -> list:
    """Plot a controller run from its log files ``PREFIX.cycles.csv`` and
    ``PREFIX.events.jsonl`` (and ``PREFIX.device.csv`` when the simulator wrote one).

    Panels: end-effector position (estimated, desired, true), hand force, actuator
    commands (torques in N·m, or forces in N for prismatic legs: ``effort_unit``; one
    line per leg, ``effort_limit`` the saturation ±, drawn when given), compute time per
    cycle; safety events are drawn as vertical lines.  ``title`` names the run (scene,
    device, rate); ``walls`` the scene's virtual walls as ``(normal, offset)`` (m):
    those along an axis are drawn in the position panel, at their offset from the
    start position.

    Returns
    -------
    list of Path
        The PNG written (``out`` or ``PREFIX.png``).
    """
    import matplotlib.pyplot as plt
    fig = run_figure(prefix, effort_unit=effort_unit, title=title,
                     effort_limit=effort_limit, walls=walls)
    out = Path(out) if out else Path(str(prefix) + ".png")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return [out]


def run_figure(prefix, *, effort_unit: str = "N·m", title: str = "",
               effort_limit: float | None = None, walls=()):
    """The matplotlib Figure of :func:`plot_run` (same arguments), not saved."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    prefix = str(prefix)
    c = read_csv(prefix + ".cycles.csv")
    ev_path = Path(prefix + ".events.jsonl")
    events = read_events(ev_path) if ev_path.exists() else []
    dev_path = Path(prefix + ".device.csv")
    dev = read_csv(dev_path) if dev_path.exists() else None
    fig, ax = plt.subplots(4, 1, figsize=(9, 10), sharex=True)
    t = c["t_dev"]
    for i, name in enumerate("xyz"):
        x0 = c[f"x_{name}"][0] if t.size else 0.0
        ax[0].plot(t, 1e3 * (c[f"x_{name}"] - x0), label=f"{name} estimated", color=f"C{i}")
        ax[0].plot(t, 1e3 * (c[f"xd_{name}"] - x0), "--", color=f"C{i}", label=f"{name} desired")
        if dev is not None:
            ax[0].plot(dev["t"], 1e3 * (dev[f"x_{name}"] - x0), ":", color=f"C{i}",
                       label=f"{name} true")
    start = [c[f"x_{n}"][0] if t.size else 0.0 for n in "xyz"]
    for normal, offset in walls:
        n = [float(v) for v in normal]
        axis = [i for i, v in enumerate(n) if v != 0.0]
        if len(axis) == 1:          # n = ±e_i: the wall is x_i = ±offset
            i = axis[0]
            ax[0].axhline(1e3 * (offset / n[i] - start[i]), color=f"C{i}", lw=1.2,
                          ls="-.", label=f"{'xyz'[i]} wall")
    ax[0].set_ylabel("displacement from start [mm]")
    ax[0].legend(ncol=3, fontsize=7)
    if title:
        ax[0].set_title(title, fontsize=9)
    for i, name in enumerate("xyz"):
        ax[1].plot(t, c[f"f_{name}"], label=f"F{name}", color=f"C{i}")
    ax[1].set_ylabel("hand force [N]")
    ax[1].legend(fontsize=7)
    k = 0
    while f"tau_{k}" in c:
        ax[2].plot(t, c[f"tau_{k}"], lw=0.8, label=f"leg {k + 1}")
        k += 1
    if effort_limit is not None:
        for sign in (1.0, -1.0):
            ax[2].axhline(sign * effort_limit, color="k", lw=0.8, ls="--",
                          label="limit ±" + f"{effort_limit:g} {effort_unit}"
                          if sign > 0 else None)
    ax[2].set_ylabel(f"{'force' if effort_unit == 'N' else 'torque'} command "
                     f"[{effort_unit}]")
    if k:
        ax[2].legend(ncol=min(k + 1, 5), fontsize=7)
    ax[3].plot(t, 1e3 * c["compute_s"], lw=0.6, label="compute")
    ax[3].plot(t, 1e3 * c["period_s"], lw=0.6, label="period")
    ax[3].set_ylabel("time [ms]")
    ax[3].set_xlabel("device time [s]")
    ax[3].legend(fontsize=7)
    for e in events:
        if "t_dev" in e:
            for a in ax:
                a.axvline(e["t_dev"], color="r", lw=0.5, alpha=0.5)
    fig.tight_layout()
    return fig


#: the summary's ``final_state``: the name of the controller's state after the last
#: cycle (:data:`.safety.RUN`, ``FAULT``, ``STOPPED``)
STATE_NAMES = {RUN: "run", FAULT: "fault", STOPPED: "stopped"}


#: the exit code of each ``exit_reason`` of a run (``distkin control``); any other
#: reason (``internal_error``) is 1, an internal failure, as everywhere in distkin.
#: 2 also when the run did not complete because of the device or the link, not of
#: distkin (DESIGN §4 has three codes: this is no internal failure, and the summary's
#: ``exit_reason`` and the stderr line say which):
#: no state frame (``no_device``), none valid (``no_valid_frames``), the link lost
#: (``disconnect``), the wall-clock limit (``wall_limit``, a device too slow or held up)
EXIT_CODES = {"completed": 0, "device_mismatch": 2, "no_device": 2, "no_valid_frames": 2,
              "disconnect": 2, "wall_limit": 2, "interrupted": 130}


def run_summary(ctl, link, cycles, wall, t_first, t_last, compute, compute_cpu, periods,
                reason, zero_torque_sent=None) -> dict:
    """The summary of :meth:`.controller.Controller.run` (its keys are documented there):
    counts of the link (``link.stats``) and of the controller ``ctl`` (events, refused
    poses, saturated cycles, the largest command), timings (:func:`timing_summary`),
    ``wall`` s, the device clock of the first and last frame ``t_first``/``t_last`` µs.

    The largest command and the limit are named in their unit: ``max_abs_torque_Nm``
    and ``torque_limit_Nm`` for revolute legs, ``max_abs_force_N`` and
    ``force_limit_N`` for prismatic ones (``ctl.scene.effort_unit``); they count the
    efforts sent, which are always finite: ``nonfinite_cycles`` counts the cycles whose
    computed efforts held a NaN or an infinity (sent as zero torque, a fault).

    ``final_state`` ("run", "fault", "stopped"; null without a cycle) is the
    controller's state after the last cycle, and ``fault_seconds`` the device time (s)
    between valid frames spent outside "run" (zero torque or hold): a run can be
    ``completed`` (exit 0) with the device held for most of it.  Every run, however it
    ends, then commands zero torque: ``zero_torque_sent`` says whether one of those
    frames was written whole (None: not known to the caller; QA 2026-11-29: after a
    SIGINT the summary read "state: run at the end" and did not say so)."""
    st = link.stats
    dev_s = 0.0 if t_first is None else (t_last - t_first) * 1e-6
    code = EXIT_CODES.get(reason, 1)
    if ctl.scene.effort_unit == "N":
        effort = {"max_abs_force_N": round(ctl.max_abs_torque, 4),
                  "force_limit_N": ctl.pd.torque_limit}
    else:
        effort = {"max_abs_torque_Nm": round(ctl.max_abs_torque, 4),
                  "torque_limit_Nm": ctl.pd.torque_limit}
    return {
        "cycles": cycles,
        "seconds": round(wall, 4),
        "device_seconds": round(dev_s, 4),
        "rate_hz": round(cycles / wall, 2) if wall > 0 else 0.0,
        **timing_summary(compute, compute_cpu, periods),
        "bad_frames": st.bad_frames,
        "resyncs": st.resyncs,
        "timeouts": st.timeouts,
        "seq_gaps": st.seq_gaps,
        "stale_frames": st.stale_frames,
        "late_frames": st.late_frames,
        "duplicate_frames": st.duplicate_frames,
        "write_timeouts": st.write_timeouts,
        "rejected_frames": ctl.rejected_frames,
        "watchdog_trips": ctl.events.count("watchdog_trip"),
        "estops": ctl.events.count("estop"),
        "saturation_faults": ctl.events.count("saturation_fault"),
        "recoveries_held": ctl.events.count("recovery_held")
        + ctl.events.count("outside_workspace"),
        "device_watchdog_frames": ctl.device_status.frames["device_watchdog"],
        "device_saturated_frames": ctl.device_status.frames["device_saturated"],
        "safety_events": sum(1 for e in ctl.events.events
                             if e["event"] not in ("zero_torque", "realtime_refused",
                                                  "device_saturated")),
        "refused_poses": ctl.refused,
        "saturated_cycles": ctl.saturated_cycles,
        "nonfinite_cycles": ctl.nonfinite_cycles,
        **effort,
        "final_state": STATE_NAMES.get(ctl.state) if cycles else None,
        "zero_torque_sent": zero_torque_sent,
        "fault_seconds": round(ctl.fault_us * 1e-6, 4),
        "gc_collections": ctl.gc_collections,
        "loop_cpu_share": round(ctl.loop_cpu_s / wall, 3) if wall > 0 else None,
        "busy_wait_us": round(getattr(link, "polling_s", 0.0) * 1e6, 3),
        "exit_reason": reason,
        "exit_code": code,
        "error": ctl.error,
        "log": None if ctl.prefix is None else {
            "cycles": f"{ctl.prefix}.cycles.csv", "events": f"{ctl.prefix}.events.jsonl"},
    }


def plot_delay_margin(report: dict, out) -> Path:
    """Plot ``distkin control --delay-margin``'s sweep (the dict of its JSON): the
    spectral radius of the linearised loop against the extra delay (ms), the stable
    side shaded, and the least-damped mode's growth rate (1/s) and frequency (Hz).

    Returns the PNG written (``out``)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    sw = report["sweep"]
    d = [r["delay_ms"] for r in sw]
    fig, ax = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    ax[0].plot(d, [r["spectral_radius"] for r in sw], "o-")
    ax[0].axhline(1.0, color="k", lw=0.8)
    if report["stable_periods"] >= 0:
        ax[0].axvspan(-0.5 * report["period_ms"], report["margin_ms"] + 0.5 *
                      report["period_ms"], color="C2", alpha=0.15, label="stable")
        ax[0].legend()
    ax[0].set_ylabel("spectral radius (1 per period)")
    ax[0].set_title("joint PD loop, linearised at home: extra command delay")
    g = ax[1].plot(d, [r["growth_per_s"] for r in sw], "o-", color="C3",
                   label="growth (1/s, left)")
    ax[1].axhline(0.0, color="k", lw=0.8)
    ax[1].set_ylabel("growth of the least-damped mode (1/s)", color="C3")
    ax[1].tick_params(axis="y", colors="C3")
    tw = ax[1].twinx()
    f = tw.plot(d, [r["frequency_hz"] for r in sw], "s--", color="C0",
                label="frequency (Hz, right)")
    tw.set_ylabel("its frequency (Hz)", color="C0")
    tw.tick_params(axis="y", colors="C0")
    ax[1].legend(g + f, [h.get_label() for h in g + f], fontsize=8, loc="best")
    ax[1].set_xlabel("extra command delay (ms)")
    fig.tight_layout()
    out = Path(out)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out
