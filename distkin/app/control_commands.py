"""``distkin sim`` and ``distkin control`` (registered in :data:`distkin.app.cli.SUBCOMMANDS`).

``distkin sim [--scene S] [--port-file F] [--faults SPEC] [--tcp PORT] [--log PREFIX]
[--idle-timeout S]``
    Start the device simulator on a pseudo-terminal (or TCP); print the port.  It stops
    when no client connects, or no command arrives, for S s (default 60).
``distkin control --port URL [--scene S] --seconds T [--json PATH|-] [--log PREFIX]``
    Run the controller against a device (or a simulator) at URL.
``distkin control --sim [--faults SPEC] ...``
    Start a simulator in a second process, wire both over a pty, run for T seconds.

The closing summary is printed (to stderr when the JSON goes to stdout); its JSON has
the fields ``cycles, seconds, rate_hz, cycle_p50_ms, cycle_p99_ms, bad_frames,
watchdog_trips, safety_events, exit_reason`` and more (every field:
docs/protocol.md, "The summary's fields"; the text: :mod:`.control_summary`).  ``cycle_p50_ms`` /
``cycle_p99_ms`` are the controller's compute time per cycle (frame received ->
command written); ``period_p50_ms`` / ``period_p99_ms`` the time between cycles.
Exit codes (:data:`distkin.control.runlog.EXIT_CODES`): 0 the run completed; 2 bad
input (also a device whose first state frame holds another number of joint angles than
the scene has legs: ``device_mismatch``; and on a port, a PD loop that the linearised
analysis shows unstable even lock-stepped, unless ``--allow-unstable``; and the device or
the link ended the run (``no_device``, ``no_valid_frames``, ``disconnect``,
``wall_limit``: the summary's ``exit_reason`` says which)); 130 interrupted; 1 an
internal failure.  Without ``--wall-limit`` a run gives up after ``2 seconds + 10`` s of
wall time.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ..errors import DistkinError, InputError, LinkError
from .control_scene_files import builtin_scene, scene_and_inputs as _scene_and_inputs
from .control_summary import (ENDED_BY, closing_lines, ended_line, format_summary,
                              rate_check as _rate_check, simulator_interrupt)

__all__ = ["add_sim_parser", "add_control_parser", "cmd_sim", "cmd_control", "builtin_scene",
           "format_summary", "check_distinct_outputs", "ended_line", "closing_lines",
           "ENDED_BY", "RUN_SECONDS"]


def _scene(path):
    """The controller scene at ``path`` (the built-in one without)."""
    return _scene_and_inputs(path)[0]


def _seconds(value: str) -> float:
    import argparse
    try:
        v = float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected seconds as a number, got {value!r}") from None
    if not 0 < v < math.inf:
        raise argparse.ArgumentTypeError(f"expected a positive finite number of seconds, "
                                         f"got {value!r}")
    return v


def _periods(value: str) -> int:
    """``--delay-margin N``: a whole number of device periods, 0..MAX_PERIODS."""
    from ..control.delay_margin import MAX_PERIODS
    try:
        n = int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number of periods, got {value!r}")
    if not 0 <= n <= MAX_PERIODS:
        raise argparse.ArgumentTypeError(f"expected 0 <= N <= {MAX_PERIODS} periods (the "
                                         f"sweep's cost grows as N^4), got {n}")
    return n


def _tcp_port(value: str) -> int:
    import argparse
    try:
        v = int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a TCP port number, got {value!r}") from None
    if not 0 <= v <= 65535:
        raise argparse.ArgumentTypeError(f"expected a TCP port in 0..65535, got {value!r}")
    return v


#: ``--faults`` in the help (the kinds of :mod:`distkin.control.faults`, not imported:
#: the parser is built without numpy)
FAULTS_HELP = ("comma-separated KIND@T[:ARG], T in s of device time: corrupt@T:N (flip a "
               "byte in each of N frames, default 1), garbage@T:N (N random bytes, default "
               "64), truncate@T:N (half of each of N frames, default 1), drop@T:N (N "
               "frames unsent, default 1), stall@T:MS (send nothing for MS ms of wall "
               "time, default 50), disconnect@T (close the port); "
               "e.g. 'corrupt@1.0:3,stall@2.0:50'")


def add_sim_parser(sub) -> None:
    p = sub.add_parser("sim", help="start the device simulator on a pty or a TCP port")
    p.add_argument("--scene", help="controller scene TOML ([simulator] table); default: built-in")
    p.add_argument("--port-file", metavar="F", help="also write the port URL to F")
    p.add_argument("--faults", metavar="SPEC", help=FAULTS_HELP)
    p.add_argument("--tcp", metavar="PORT", type=_tcp_port,
                   help="serve on TCP (0 = any free port)")
    p.add_argument("--log", metavar="PREFIX",
                   help="write PREFIX.device.csv and PREFIX.device-events.jsonl (PREFIX "
                        "names files, not a directory: '' and a trailing / are refused)")
    p.add_argument("--seconds", type=_seconds,
                   help="stop after this much device time, s (default: none, serve until "
                        "the host disconnects, --idle-timeout or a signal)")
    p.add_argument("--idle-timeout", type=_seconds, metavar="S", default=None,
                   help="stop when no client connects, or no command arrives, for S s of "
                        "wall time (default 60)")
    p.set_defaults(func=cmd_sim)


def add_control_parser(sub) -> None:
    p = sub.add_parser("control", help="run the admittance controller on a device or simulator")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--port", metavar="URL", help="pyserial URL: /dev/ttyX, pty path, "
                                                 "socket://host:port, loop://")
    g.add_argument("--sim", action="store_true", help="start a simulator and connect over a pty")
    g.add_argument("--delay-margin", nargs="?", const=20, type=_periods, metavar="N",
                   help="no device: how many periods of extra command delay the joint PD "
                        "loop takes (linearised at home), swept to N periods (default 20)")
    p.add_argument("--scene", help="controller scene TOML; default: built-in Octo scene")
    p.add_argument("--seconds", type=_seconds, default=None,
                   help="device time to run, s (default 5)")
    p.add_argument("--faults", metavar="SPEC", help="faults for the simulator (with --sim): "
                   + FAULTS_HELP)
    p.add_argument("--json", metavar="PATH|-", help="write the summary as JSON (- for stdout)")
    p.add_argument("--log", metavar="PREFIX", help="write PREFIX.cycles.csv, PREFIX.events.jsonl "
                                                   "(and PREFIX.device.csv, "
                                                   "PREFIX.device-events.jsonl with --sim; "
                                                   "columns and units: docs/protocol.md); "
                                                   "PREFIX names files (out/run), not a "
                                                   "directory: '' and a trailing / are "
                                                   "refused")
    p.add_argument("--plots", metavar="DIR", help="plot the run into DIR/control.png (with "
                                                  "--log, or from a temporary log); with "
                                                  "--delay-margin, the sweep into "
                                                  "DIR/delay_margin.png")
    p.add_argument("--wall-limit", type=_seconds,
                   help="give up after this much wall time, s (default 2 x --seconds + 10; "
                        "exit 2, exit_reason wall_limit)")
    p.add_argument("--allow-unstable", action="store_true",
                   help="drive a device (--port) even when the PD loop, linearised at home, "
                        "is unstable lock-stepped (refused otherwise, exit 2)")
    p.set_defaults(func=cmd_control)


def cmd_sim(args) -> int:
    from ..control.faults import parse_faults
    from ..control.simulator import IDLE_TIMEOUT_S, INTERRUPTED_EXIT, serve
    from .output_paths import check_output_path
    faults = parse_faults(args.faults)
    scene, inputs = _scene_and_inputs(               # an output never replaces a file read
        args.scene, [("--port-file", args.port_file)]
        + [("--log", p) for p in _log_files(args.log, sim=True).values()])
    check_output_path(args.port_file, "--port-file", inputs=inputs)
    from ..control.runlog import check_log_prefix
    check_log_prefix(args.log)
    for path in _log_files(args.log, sim=True).values():
        check_output_path(path, "--log", inputs=inputs, replace=False)
    check_distinct_outputs([("--port-file", args.port_file)]
                           + [("--log", p) for p in _log_files(args.log, sim=True).values()])
    try:
        code = serve(scene, port_file=args.port_file, tcp_port=args.tcp, faults=faults,
                     log_prefix=args.log, seconds=args.seconds,
                     idle_timeout=IDLE_TIMEOUT_S if args.idle_timeout is None
                     else args.idle_timeout)
    except InputError as exc:
        opt = {"tcp_port": "--tcp", "port_file": "--port-file"}.get(exc.field)
        if opt:                           # the API's argument is the option
            exc.field = None
            exc.with_field(opt)
        raise
    if code == INTERRUPTED_EXIT:     # SIGINT/SIGTERM: the line of every command (README)
        print("distkin: error: interrupted", file=sys.stderr)
    return code


def check_distinct_outputs(outputs) -> None:
    """Refuse two outputs of one command that name the same file (QA X1 D2: ``--json
    run.cycles.csv`` beside ``--log run`` replaced the log the report still listed).

    ``outputs``: ``(option, path)`` pairs in order (None and ``-`` skipped); the error
    names the earlier option of the first colliding pair (list ``--json`` first)."""
    from .output_paths import same_file
    seen = [(f, p) for f, p in outputs if p is not None and str(p) != "-"]
    for i, (fa, pa) in enumerate(seen):
        for fb, pb in seen[i + 1:]:
            if same_file(Path(pa), Path(pb)):
                raise InputError(f"expected an output file of its own, got {str(pa)!r}, "
                                 f"which {fb} writes too ({str(pb)!r})", field=fa,
                                 hint=f"name another file for {fa}")


def _log_files(prefix, *, control: bool = False, sim: bool = False) -> dict:
    """The files ``--log PREFIX`` writes: the controller's (``control``) and the
    simulator's (``sim``), by the keys of the summary's ``log`` object."""
    if not prefix:
        return {}
    files = {}
    if control:
        files.update(cycles=f"{prefix}.cycles.csv", cycles_spill=f"{prefix}.cycles.csv.part",
                     events=f"{prefix}.events.jsonl")
    if sim:
        files.update(device=f"{prefix}.device.csv",
                     device_events=f"{prefix}.device-events.jsonl")
    return files


def _wait_port(proc, port_file: Path, timeout: float) -> str:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if port_file.exists():
            url = port_file.read_text(encoding="utf-8").strip()
            if url:
                return url
        if proc.poll() is not None:
            err = proc.stderr.read().decode(errors="replace").strip().splitlines()
            raise LinkError("expected the simulator to start, got exit code "
                            f"{proc.returncode}: {err[-1] if err else 'no message'}",
                            field="--sim")
        time.sleep(0.02)
    raise LinkError(f"expected the simulator to announce its port within {timeout:.0f} s, "
                    "got nothing", field="--sim")


#: ``--seconds`` when not given, s of device time
RUN_SECONDS = 5.0

def _margin_report(scene, model, periods: int) -> dict:
    """``distkin control --delay-margin``: the sweep of :mod:`distkin.control.delay_margin`
    as a JSON-ready dict (units in the keys)."""
    from ..control.delay_margin import delay_margin
    dm = delay_margin(scene, model, max_periods=periods)
    pd = scene.pd
    head = (f"distkin control --delay-margin: {scene.title or scene.path} ({scene.preset}, "
            f"{scene.rate_hz:g} Hz, KP {pd.kp:g} {scene.effort_unit}/{scene.joint_unit}, "
            f"KD {pd.kd:g} {scene.effort_unit}·s/{scene.joint_unit}, derivative filter "
            f"{pd.derivative_filter_s * 1e3:g} ms), linearised at home")
    return {"text": "\n".join([head] + ["  " + line for line in dm.lines()]),
            "period_ms": dm.period_s * 1e3,
            "stable_periods": dm.stable_periods,
            "lockstep": dm.lockstep,
            "marginal_periods": [int(n) for n in dm.delays[dm.marginal]],
            "margin_ms": dm.margin_s * 1e3 if dm.stable_periods >= 0 else None,
            "sweep": [{"delay_periods": int(n), "delay_ms": float(n * dm.period_s * 1e3),
                       "spectral_radius": float(r), "growth_per_s": float(g),
                       "frequency_hz": float(f)}
                      for n, r, g, f in zip(dm.delays, dm.spectral_radius,
                                            dm.growth_per_s, dm.frequency_hz)]}


def _delay_margin_command(args, scene, inputs, model) -> int:
    from .output_paths import check_output_dir, check_output_path
    for name in ("log", "faults", "wall_limit", "seconds", "allow_unstable"):
        if getattr(args, name):
            raise InputError(f"expected no --{name.replace('_', '-')} with --delay-margin "
                             "(nothing runs), got one", field=f"--{name.replace('_', '-')}")
    check_output_path(args.json, inputs=inputs)
    check_output_dir(args.plots, "--plots", inputs=inputs)     # '' refused, not ignored
    if args.plots:
        check_output_path(Path(args.plots) / "delay_margin.png", "--plots", inputs=inputs)
        check_distinct_outputs([("--json", args.json),
                                ("--plots", Path(args.plots) / "delay_margin.png")])
    rep = _margin_report(scene, model, args.delay_margin)
    text = rep.pop("text")
    if args.plots:
        from ..control.runlog import plot_delay_margin
        Path(args.plots).mkdir(parents=True, exist_ok=True)
        rep["plots"] = [str(plot_delay_margin(rep, Path(args.plots) / "delay_margin.png"))]
        text += "\n  plot: " + rep["plots"][0]
    _emit(text, rep, args.json)
    return 0


def _emit(text: str, data: dict, json_arg) -> None:
    """The text on stdout and the JSON to ``--json PATH``; with ``--json -`` the JSON on
    stdout and the text on stderr."""
    from .output_paths import write_json
    if json_arg == "-":
        print(text, file=sys.stderr)
        print(json.dumps(data, indent=2))
    else:
        print(text)
        if json_arg:
            write_json(json_arg, json.dumps(data, indent=2))


class _slow_start_notice:
    """One stderr line when the set-up (the controller's kernels, the simulator's, the
    link's decoder: numba compiles them once per machine) has not ended after
    ``after`` s, so that a first run is not 20-60 s of silence (QA 24); ``cleanup()``
    cancels it (idempotent)."""

    def __init__(self, after: float = 5.0):
        import threading
        self._timer = threading.Timer(after, self._say)
        self._timer.daemon = True
        self._timer.start()

    @staticmethod
    def _say():
        print("distkin control: still setting up: the controller's and the simulator's "
              "kernels (numba compiles them on a machine's first run, 20-60 s, then loads "
              "them from its cache) ...", file=sys.stderr, flush=True)

    def cleanup(self):
        self._timer.cancel()


def _plot_title(scene, args) -> str:
    """The run plot's title: the scene, the device, the rate and the gains."""
    where = Path(args.scene).name if args.scene else "built-in scene"
    link = "simulated device" if args.sim else f"device on {args.port}"
    unit = scene.effort_unit
    per = "m" if scene.joint == "prismatic" else "rad"
    return (f"distkin control: {where} ({scene.title or scene.preset})\n{link}, "
            f"{scene.rate_hz:g} Hz; PD kp {scene.pd.kp:g} {unit}/{per}, kd {scene.pd.kd:g} "
            f"{unit}·s/{per}")


def _margin_note(scene, model, args) -> dict:
    """The delay margin for the run's summary, and a warning before the run starts when
    the loop is unstable even lock-stepped (with ``--sim``; on a port that is refused,
    exit 2, unless ``--allow-unstable``), or when it takes no extra delay and nothing
    keeps the device in lock step with the host.

    Summary keys: ``delay_margin_periods`` (the largest stable extra delay swept to 3
    periods; -1 when the lock-stepped loop itself is not proved stable, null when home
    admits no linearisation), ``delay_margin_ms``, ``lockstep`` ("stable", "unstable",
    "marginal" or null), ``lockstep_growth_per_s`` and ``lockstep_frequency_hz`` (the
    least-damped mode without extra delay)."""
    from ..control.delay_margin import delay_margin
    try:
        dm = delay_margin(scene, model, max_periods=3)
    except DistkinError:                    # e.g. a singular home: no linearisation
        return {"delay_margin_periods": None, "lockstep": None}
    paced = args.sim and scene.simulator.lockstep
    note = {"delay_margin_periods": dm.stable_periods,
            "delay_margin_ms": (dm.margin_s * 1e3 if dm.stable_periods >= 0 else None),
            "lockstep": dm.lockstep,
            "lockstep_growth_per_s": float(dm.growth_per_s[0]),
            "lockstep_frequency_hz": float(dm.frequency_hz[0])}
    if dm.lockstep == "unstable":
        why = (f"the joint PD loop is unstable even lock-stepped, with no extra command "
               f"delay (linearised at home: spectral radius {dm.spectral_radius[0]:.4g}, "
               f"grows at {dm.growth_per_s[0]:.4g} 1/s at {dm.frequency_hz[0]:.4g} Hz)")
        if not args.sim and not getattr(args, "allow_unstable", False):
            raise InputError(f"expected PD gains whose loop is stable lock-stepped, got "
                             f"kp {scene.pd.kp:g}, kd {scene.pd.kd:g}: {why}", field="[pd]",
                             hint="lower pd.kp or pd.kd, or lengthen pd.derivative_filter_s "
                                  "(distkin control --delay-margin), "
                                  "or pass --allow-unstable to drive the device anyway")
        print(f"distkin: warning: [pd]: {why}: expect it at the torque limit "
              f"(distkin control --delay-margin)", file=sys.stderr)
        return note
    if dm.lockstep == "marginal":
        print("distkin: warning: [pd]: the joint PD loop is marginal even lock-stepped "
              "(linearised at home: an undamped mode, spectral radius within "
              "1e-9 of 1; float64 cannot say whether it grows; distkin control "
              "--delay-margin)", file=sys.stderr)
    elif dm.stable_periods < 1 and not paced:
        grow = (f"; one period of delay makes it grow at {dm.growth_per_s[1]:.1f} 1/s "
                f"({dm.frequency_hz[1]:.1f} Hz)" if dm.stable_periods == 0 else "")
        print(f"distkin: warning: [pd]: the joint PD loop takes no extra command delay "
              f"(linearised at home){grow}: a host that answers a period late drives it "
              f"to the torque limit (distkin control --delay-margin)", file=sys.stderr)
    return note


def _check_run_options(args) -> None:
    """Refuse, before anything is loaded or started, a ``--port ''`` (no device named)
    and a ``--wall-limit`` no longer than the run: device time passes at most as fast as
    wall time (the device keeps its own clock), so T s of it need more than T s of wall
    time (QA 23 D10: ``--seconds 20 --wall-limit 5`` ran 5 s and blamed the device)."""
    if args.port is not None and not args.port.strip():
        raise InputError(f"expected a serial port URL (/dev/ttyUSB0, a pty path, "
                         f"socket://host:port), got {args.port!r}", field="--port")
    if args.port:                  # a file or a folder: said before anything is built
        from ..control.link import not_a_serial_device
        what = not_a_serial_device(args.port)
        if what:
            raise InputError(f"expected a serial device (a tty) or a URL, got "
                             f"{args.port!r}, which is {what}", field="--port")
    seconds = RUN_SECONDS if args.seconds is None else args.seconds
    if args.wall_limit is not None and args.delay_margin is None \
            and args.wall_limit <= seconds:
        raise InputError(f"expected --wall-limit longer than the run's --seconds "
                         f"{seconds:g} s (device time passes at most as fast as wall "
                         f"time), got {args.wall_limit:g} s", field="--wall-limit",
                         hint=f"leave it out (default 2 x --seconds + 10 = "
                              f"{2 * seconds + 10:g} s) or give more than {seconds:g} s")


def cmd_control(args) -> int:
    _check_run_options(args)
    from ..control.controller import Controller
    from ..control.faults import parse_faults
    from ..control.kinematics import model_of
    from ..control.link import Link
    from .output_paths import check_output_dir, check_output_path
    from ..control.runlog import check_log_prefix
    check_log_prefix(args.log)             # '' or a directory refused, not ignored
    scene, inputs = _scene_and_inputs(
        args.scene, [("--json", args.json)]
        + [("--log", p) for p in _log_files(args.log, control=True, sim=args.sim).values()]
        + ([("--plots", args.plots, "a folder")] + [("--plots", Path(args.plots) / n)
                                         for n in ("control.png", "delay_margin.png")]
           if args.plots else []))
    if args.delay_margin is not None:
        return _delay_margin_command(args, scene, inputs, model_of(scene))
    if args.faults and not args.sim:
        raise InputError("expected --faults only with --sim, got it with --port", field="--faults")
    parse_faults(args.faults)              # validate before starting anything
    # every file the run will write, before anything starts (exit 2, one line); none of
    # them may be a file the scene was read from
    check_output_path(args.json, inputs=inputs)
    log_files = _log_files(args.log, control=True, sim=args.sim)
    for path in log_files.values():
        check_output_path(path, "--log", inputs=inputs, replace=False)
    check_output_dir(args.plots, "--plots", inputs=inputs)     # '' refused, not ignored
    if args.plots:
        check_output_path(Path(args.plots) / "control.png", "--plots", inputs=inputs)
    # nor may two of them be one file (the JSON written last replaced the log or plot)
    check_distinct_outputs([("--json", args.json)]
                           + [("--log", p) for p in log_files.values()]
                           + [("--plots", Path(args.plots) / f) for f in
                              (("control.png",) if args.plots else ())])
    tmpdir = None
    prefix = args.log
    if prefix is None and args.plots:
        tmpdir = tempfile.TemporaryDirectory(prefix="distkin-control-")
        prefix = str(Path(tmpdir.name) / "run")
    slow = _slow_start_notice()             # a cold numba cache: 20-60 s of silence
    try:
        model = model_of(scene)
        margin = _margin_note(scene, model, args)
    except BaseException:
        slow.cleanup()
        raise
    proc = None
    cleanup = [slow]
    if tmpdir is not None:
        cleanup.append(tmpdir)
    try:
        if args.sim:
            work = tempfile.TemporaryDirectory(prefix="distkin-sim-")
            cleanup.append(work)
            port_file = Path(work.name) / "port"
            cmd = [sys.executable, "-m", "distkin", "sim", "--port-file", str(port_file)]
            if args.scene:
                cmd += ["--scene", str(args.scene)]
            if args.faults:
                cmd += ["--faults", args.faults]
            if prefix:
                cmd += ["--log", prefix]
            env = dict(os.environ)
            env.setdefault("OPENBLAS_NUM_THREADS", "1")
            proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                    env=env)
            url = _wait_port(proc, port_file, timeout=60.0)
        else:
            url = args.port
        # everything compiled before the port is opened (the controller's kernels and
        # the link's decoder): a cold numba cache costs seconds, never a watchdog
        ctl = Controller(scene, model, log_prefix=prefix)
        slow.cleanup()
        try:
            link = Link(url, busy_wait_s=scene.busy_wait_us * 1e-6)
        except LinkError as exc:
            if args.sim:                # our own simulator's port: an internal failure
                raise
            # the user's --port names no openable device: bad input (exit 2)
            raise InputError(exc.message, field="--port") from None
        if not args.sim:     # a silent port otherwise looks like a hang for 10 s
            wait = ctl.STARTUP_TIMEOUT_S if args.wall_limit is None else \
                min(ctl.STARTUP_TIMEOUT_S, args.wall_limit)     # (checked first)
            print(f"distkin control: waiting for the device's state frames on {url} (up to "
                  f"{wait:g} s)", file=sys.stderr, flush=True)
        try:
            summary = ctl.run(link, RUN_SECONDS if args.seconds is None else args.seconds,
                              wall_limit=args.wall_limit)
        finally:
            link.close()
        summary["port"] = url
        summary.update(margin)
        _rate_check(summary, scene.rate_hz)
        if args.log:                           # all the files --log wrote
            summary["log"] = {k: v for k, v in log_files.items() if k != "cycles_spill"}
        if proc is not None:
            try:
                out, err = proc.communicate(timeout=10)
            except subprocess.TimeoutExpired:
                proc.terminate()
                out, err = proc.communicate(timeout=10)
            summary["simulator_exit_code"] = proc.returncode
            simulator_interrupt(summary, proc.returncode)
            said = out.decode(errors="replace").strip().splitlines()
            if said:
                summary["simulator"] = said[-1]
            lines = err.decode(errors="replace").strip().splitlines()
            if proc.returncode not in (0, 130, -2, -15) and lines:
                summary["simulator_error"] = lines[-1]
        if args.plots and prefix:
            try:
                from ..control.runlog import plot_run
                Path(args.plots).mkdir(parents=True, exist_ok=True)
                summary["plots"] = [str(p) for p in
                                    plot_run(prefix, Path(args.plots) / "control.png",
                                             effort_unit=scene.effort_unit,
                                             title=_plot_title(scene, args),
                                             effort_limit=scene.pd.torque_limit,
                                             walls=[(e.normal, e.offset) for e in
                                                    scene.environment
                                                    if hasattr(e, "normal")])]
            except Exception as exc:   # a plot must never cost the run's summary
                summary["plot_error"] = f"{type(exc).__name__}: {exc}"
                print(f"distkin: warning: --plots: plot failed ({summary['plot_error']}); "
                      "the summary is kept", file=sys.stderr)
        if tmpdir is not None:
            summary["log"] = None             # the temporary log is removed
    finally:
        if proc is not None and proc.poll() is None:
            proc.terminate()
            proc.wait(timeout=10)
        for d in cleanup:
            d.cleanup()
    text = format_summary(summary)
    if summary["exit_reason"] == "device_mismatch":    # bad input: one line naming it
        print(f"distkin: error: {'--scene' if args.scene else 'the built-in scene'}: "
              f"{summary['error']}", file=sys.stderr)
    for line in closing_lines(summary, sim=args.sim):
        print(line, file=sys.stderr)
    _emit(text, summary, args.json)
    return summary["exit_code"]
