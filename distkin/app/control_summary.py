"""The closing summary of ``distkin control`` (:mod:`.control_commands`): its text, the
stderr line of a run the device, the link or a signal ended, and the achieved rate
against the requested one.  The JSON fields are documented in docs/protocol.md
("The run summary")."""

from __future__ import annotations

import signal
import sys

__all__ = ["format_summary", "ended_line", "closing_lines", "ENDED_BY", "RATE_SHORTFALL",
           "rate_check", "simulator_interrupt", "SIGNAL_EXIT_CODES"]


def format_summary(s: dict) -> str:
    """The closing summary, one line per topic, units on every number."""
    from ..control.delay_margin import format_ms
    cpu = (f"; its CPU time p50 {s['cycle_cpu_p50_ms']} ms, p99 {s['cycle_cpu_p99_ms']} ms"
           if s.get("cycle_cpu_p50_ms") is not None else "")
    compute = ("compute per cycle: no frames" if s["cycle_p50_ms"] is None else
               f"compute per cycle (state frame in -> command out, wall): p50 "
               f"{s['cycle_p50_ms']} ms, p99 {s['cycle_p99_ms']} ms"
               + (f", max {s['cycle_max_ms']} ms" if s.get("cycle_max_ms") is not None
                  else "") + cpu)
    want = s.get("requested_rate_hz")
    nominal = f" (nominal {1e3 / want:.4g} ms)" if want else ""
    period = ("period between cycles: fewer than two cycles" if s["period_p50_ms"] is None
              else f"period between cycles{nominal}: p50 {s['period_p50_ms']} ms, p99 "
                   f"{s['period_p99_ms']} ms"
                   + (f", max {s['period_max_ms']} ms" if s.get("period_max_ms") is not None
                      else "")
                   + ("; a p50 below the nominal period: frames that waited in the port "
                      "after a hold-up came back to back (the device catching up)"
                      if want and s["period_p50_ms"] < 0.95e3 / want else ""))
    rate = (f"rate: {s['loop_rate_hz']:.1f} Hz" + (f" of {want:g} Hz requested" if want
                                                    else "")
            + " from the first frame to the last" if s.get("loop_rate_hz") else "")
    lines = [
        f"distkin control: {s['exit_reason']} -- {s['cycles']} cycles in {s['seconds']:.3f} s "
        f"wall ({s['rate_hz']:.1f} Hz, start-up and shut-down included), "
        f"{s['device_seconds']:.3f} s device time",
        f"  {compute}",
        f"  {period}",
        "  " + "; ".join(x for x in (rate, (
            f"loop CPU {100 * s['loop_cpu_share']:.0f}% of a core"
            + (f" (polling the port up to {s['busy_wait_us']:g} µs)" if s["busy_wait_us"]
               else "") if s.get("loop_cpu_share") is not None else "")) if x),
        f"  link: {s['bad_frames']} bad frames, {s['resyncs']} resyncs, {s['timeouts']} read "
        f"timeouts, {s['seq_gaps']} frames missing, {s['stale_frames']} stale frames skipped, "
        f"{s['late_frames']} late and {s['duplicate_frames']} duplicate frames dropped, "
        f"{s['write_timeouts']} write timeouts",
        f"  safety: {s['watchdog_trips']} watchdog trips, {s['estops']} e-stops, "
        f"{s['recoveries_held']} held outside the safe workspace or moving, "
        f"{s['rejected_frames']} rejected readings, {s['safety_events']} safety events, "
        f"{s['refused_poses']} refused set points, {s['saturated_cycles']} saturated cycles"
        + (f", {s['saturation_faults']} faults oscillating at the torque limit"
           if s.get("saturation_faults") else ""),
        f"  device: {s['device_watchdog_frames']} frames with its watchdog tripped, "
        f"{s['device_saturated_frames']} with a drive saturated",
        (f"  force: max |f| {s['max_abs_force_N']} N (limit {s['force_limit_N']} N)"
         if "max_abs_force_N" in s else
         f"  torque: max |tau| {s['max_abs_torque_Nm']} N·m (limit {s['torque_limit_Nm']} N·m)")
        + (f"; {s['nonfinite_cycles']} cycles computed a NaN or infinite command, sent as "
           f"zero torque (a fault)" if s.get("nonfinite_cycles") else ""),
    ]
    lines = [x for x in lines if x.strip()]          # (no rate, no CPU share: no line)
    if s.get("final_state") is not None:
        share = (f" ({100 * s['fault_seconds'] / s['device_seconds']:.0f}% of the device "
                 f"time)" if s.get("device_seconds") else "")
        sent = {True: ", then zero torque commanded on exit",
                False: ", then zero torque on exit NOT sent (the link refused it)"}.get(
                    s.get("zero_torque_sent"), "")
        lines.append(f"  state: {s['final_state']} after the last cycle{sent}; "
                     f"{s['fault_seconds']:.3f} s of device time in fault or hold{share}")
    if s.get("delay_margin_periods") is not None:
        n = s["delay_margin_periods"]
        lines.append("  PD loop (linearised at home): " + (
            f"UNSTABLE even lock-stepped, without extra delay (grows at "
            f"{s['lockstep_growth_per_s']:.4g} 1/s, {s['lockstep_frequency_hz']:.4g} Hz)"
            if s.get("lockstep") == "unstable" else
            "marginal without extra delay (an undamped mode: not decided)" if n < 0 else
            "stable only without extra command delay (one period makes it unstable; "
            "distkin control --delay-margin)" if n == 0 else
            f"stable with up to {n} period{'s' if n != 1 else ''} "
            f"({format_ms(s['delay_margin_ms'])} ms) of extra command delay"
            + (" or more" if n >= 3 else "")))
    if s.get("rate_shortfall"):
        lines.append(f"  rate: {s['rate_shortfall']}")
    if s.get("log"):
        lines.append("  log: " + ", ".join(str(v) for v in s["log"].values() if v))
    if s.get("error"):
        lines.append(f"  error: {s['error']}")
    if s.get("simulator_stopped"):
        lines.append(f"  {s['simulator_stopped']}")
    if s.get("simulator"):
        lines.append(f"  {s['simulator']}")
    if s.get("simulator_error"):
        lines.append(f"  simulator failed (exit code {s['simulator_exit_code']}): "
                     f"{s['simulator_error']}")
    if s.get("plots"):
        lines.append("  plots: " + ", ".join(s["plots"]))
    if s.get("plot_error"):
        lines.append(f"  plot failed: {s['plot_error']}")
    return "\n".join(lines)


#: the runs the device or the link ended (exit 2): the option the stderr line names
ENDED_BY = {"no_device": None, "no_valid_frames": None, "disconnect": None,
            "wall_limit": "--wall-limit"}


def ended_line(summary: dict, *, sim: bool) -> str:
    """The one stderr line of a run the device or the link ended (README, docs/design.md
    §4: ``no_device``, ``no_valid_frames``, ``disconnect``, ``wall_limit``, exit 2;
    QA X1 D3: they printed nothing): ``distkin: error: FIELD: expected ..., got ...
    (exit_reason R)``, FIELD ``--port`` (``--sim``: the simulator's port) or
    ``--wall-limit``; "" for the other reasons."""
    reason = summary.get("exit_reason")
    if reason not in ENDED_BY:
        return ""
    field = ENDED_BY[reason] or ("--sim" if sim else "--port")
    why = summary.get("error") or f"expected a completed run, got {reason}"
    return f"distkin: error: {field}: {why} (exit_reason {reason})"


def closing_lines(summary: dict, *, sim: bool) -> list:
    """The stderr lines after a run's summary: :func:`ended_line` for a run the device
    or the link ended, and ``distkin: error: interrupted`` for one that SIGINT or
    SIGTERM stopped (exit 130; README: Ctrl-C stops any command with that line, which
    :func:`distkin.app.cli.main` prints for the other commands)."""
    if summary.get("exit_reason") == "interrupted":
        return ["distkin: error: interrupted"]
    line = ended_line(summary, sim=sim)
    return [line] if line else []


#: the achieved rate (first frame to last) below this share of ``[device] rate_hz`` is a
#: warning: the delay margin and the watchdog were stated in periods that did not happen
RATE_SHORTFALL = 0.5


def rate_check(summary: dict, rate_hz: float) -> None:
    """Warn (stderr, and the summary's ``rate_shortfall``) when the loop ran at less
    than :data:`RATE_SHORTFALL` of the requested rate."""
    got = summary.get("loop_rate_hz")
    summary["requested_rate_hz"] = rate_hz
    if got and summary.get("cycles", 0) >= 2 and got < RATE_SHORTFALL * rate_hz:
        summary["rate_shortfall"] = (
            f"the loop ran at {got:.4g} Hz, {100 * got / rate_hz:.2g}% of the requested "
            f"[device] rate_hz = {rate_hz:g}: the machine or the link cannot keep it")
        print(f"distkin: warning: [device] rate_hz: {summary['rate_shortfall']}",
              file=sys.stderr)


#: the exit codes of a ``distkin sim`` that a signal stopped: 130 (its SIGINT/SIGTERM
#: handling, README) or killed by SIGINT/SIGTERM before it handles them (-2, -15)
#: (this module is imported to build the parser: no distkin.control, no numpy here)
SIGNAL_EXIT_CODES = (130, -signal.SIGINT, -signal.SIGTERM)


def simulator_interrupt(summary: dict, sim_exit_code) -> None:
    """``distkin control --sim``: a run that ended ``disconnect`` because its own
    simulator was stopped by a signal was interrupted, not ended by the device (QA: Ctrl-C
    reaches the simulator in the same process group; when it closed the port before the
    controller saw its own SIGINT, the run reported a disconnect, exit 2, 1 run in 5).
    Rewrites ``summary`` in place: ``exit_reason`` "interrupted", exit 130, the
    disconnect's message kept as ``simulator_stopped``."""
    from ..control.runlog import EXIT_CODES
    if summary.get("exit_reason") != "disconnect" or sim_exit_code not in SIGNAL_EXIT_CODES:
        return
    summary["simulator_stopped"] = (f"the simulator was stopped by a signal (exit code "
                                    f"{sim_exit_code}), which closed the port: "
                                    f"{summary.get('error')}")
    summary.update(exit_reason="interrupted", exit_code=EXIT_CODES["interrupted"],
                   error=None)
