"""The ``distkin`` command line (docs/design.md §4).

``distkin run SCENE.toml [--json PATH|-] [--plots DIR]``
    Run every query of a scene; print the readable report (to stderr when the JSON
    goes to stdout) and write the JSON contract.
``distkin demo [--json PATH|-] [--plots DIR]``
    Run the built-in scenes (``distkin/scenes/``).  Its JSON is the same contract as
    ``run``'s: ``scene`` is :data:`DEMO_SCENE`, a text naming the built-in scenes (no
    file has that path), and ``queries`` holds every scene's records in order, each with
    a ``scene`` key naming its file (``"distkin/scenes/rss_octopod.toml"``).

Exit codes: 0 ok; 2 bad input or a query whose data admit no answer (one line on
stderr naming the field); 1 an internal failure (one line; ``--debug`` shows the
traceback); 130 interrupted (Ctrl-C or SIGTERM: ``distkin: error: interrupted``; ``run``
and ``demo`` still write the report and the JSON of the queries so far, marked
``"interrupted": true``, :class:`RunInterrupted`); 141 when the
reader of stdout left (``distkin demo | head``: nothing on stderr).  A usage error
(an unknown option, no command) is one line too, exit 2.  A plot that fails (``--plots``) is a warning on stderr and a
``plot_error`` in the query's JSON record; its results are kept and the exit code does
not change.  A query that has no plot says so on stderr with ``--plots`` (``distkin:
note: no plot for query N (type)``).  Further subcommands (``codegen``, ``sim``, ``control``) are registered in
:data:`SUBCOMMANDS` (functions importing the modules that implement them).
"""

from __future__ import annotations

import argparse
import signal
import sys
import time
import traceback
import warnings
from importlib import resources
from pathlib import Path

from .._version import __version__
from ..errors import DistkinError, InputError, is_input_error
from .stdout_guard import STDOUT_COMMANDS, GuardedStdout, closed_stdout, stdout_to_devnull

__all__ = ["main", "run_scene", "RunInterrupted", "interrupted_document", "DEMO_SCENES",
           "DEMO_SCENE", "SUBCOMMANDS", "CHUNKED", "format_warning"]

#: built-in scenes run by ``distkin demo``, in order (files in distkin/scenes/)
DEMO_SCENES = [
    "cayley_menger_tetrahedron.toml",
    "delta_griffis_duffy.toml",
    "octahedral_griffis_duffy.toml",
    "rss_octopod.toml",
    "certify_hunt.toml",
]

#: the ``scene`` of ``distkin demo``'s JSON (docs/design.md §4): the built-in scenes
DEMO_SCENE = f"distkin/scenes (built-in: {', '.join(DEMO_SCENES)})"

def _add_sim(sub):
    from .control_commands import add_sim_parser
    add_sim_parser(sub)


def _add_control(sub):
    from .control_commands import add_control_parser
    add_control_parser(sub)


def _add_codegen(sub):
    from .codegen_command import add_parser
    add_parser(sub)


def _add_sweep(sub):
    """``distkin sweep SCENE [--scheduler ADDRESS] [--workers N] [--store DIR]``."""
    s = sub.add_parser("sweep", help="run a scene's chunked queries (performance, "
                                     "design_sweep, certify_workspace) on a local pool or a "
                                     "dask cluster")
    s.add_argument("scene", help="scene TOML file")
    s.add_argument("--scheduler", metavar="ADDRESS",
                   help="dask.distributed scheduler, e.g. tcp://10.0.0.5:8786 "
                        "(extra 'distributed')")
    s.add_argument("--workers", type=int, metavar="N", help="local worker processes")
    s.add_argument("--store", metavar="DIR", help="directory of the resumable chunks")
    _add_output_options(s)
    s.set_defaults(func=_cmd_sweep)


def _add_output_options(p) -> None:
    """``--json``, ``--plots`` and ``--no-progress`` of run, demo and sweep."""
    p.add_argument("--json", metavar="PATH|-", help="write the JSON result (- for stdout)")
    p.add_argument("--plots", metavar="DIR", help="write plots into DIR (matplotlib); a plot "
                                                  "that fails is a warning, never a lost result")
    p.add_argument("--no-progress", action="store_true", help="no progress bars")


def _cmd_sweep(args):
    if args.workers is not None:
        from ..argcheck import workers_count
        workers_count(args.workers, "--workers")
    if args.scheduler is not None:
        from ..argcheck import scheduler_address
        scheduler_address(args.scheduler, "--scheduler")   # before the run, naming the option
    return _cmd_run(args)          # --store/--workers/--scheduler reach the RunContext


#: the query types that run in chunks (the run store; ``distkin sweep`` overrides them)
CHUNKED = ("performance", "design_sweep", "certify_workspace")


def _scene_stores(scene, store) -> list:
    """(option, folder) of the chunk stores a run writes: ``--store``, else each chunked
    query's own ``store`` (relative to the scene file, as :meth:`RunContext.store_dir`)."""
    if store is not None:
        return [("--store", store)]
    out = []
    for q in scene.queries:
        named = getattr(q.params, "store", None) if q.type in CHUNKED else None
        if named:
            p = Path(named)
            out.append((f"{q.field}.store",
                        p if p.is_absolute() else Path(scene.path).resolve().parent / p))
    return out


#: subcommand -> the function that adds its parser (called with the subparsers)
SUBCOMMANDS: dict = {
    "sim": _add_sim,
    "control": _add_control,
    "codegen": _add_codegen,
    "sweep": _add_sweep,
}


def format_warning(message, category, filename, lineno, line=None) -> str:
    """:func:`warnings.formatwarning` while a command runs: a warning of distkin's own
    (its class defined in the package: ``GeometryWarning``, ``ConditioningWarning``...)
    is one line, ``distkin: warning: ...``, as the CLI's other warnings, never Python's
    ``/path/file.py:123: GeometryWarning: ...`` and the source line below it (QA: a legs
    scene's home outside a stroke); any other warning keeps Python's format."""
    if getattr(category, "__module__", "").split(".")[0] != "distkin":
        return _python_formatwarning(message, category, filename, lineno, line)
    return f"distkin: warning: {' '.join(str(message).split())}\n"


#: Python's own :func:`warnings.formatwarning` (for the warnings of other packages)
_python_formatwarning = warnings.formatwarning


def _err(msg: str) -> None:
    print(f"distkin: error: {msg}", file=sys.stderr)


class RunInterrupted(KeyboardInterrupt):
    """Ctrl-C or SIGTERM while :func:`run_scene` ran a query: the run stops, and the JSON
    records so far go with it (QA 23 D1: an interrupt wrote no JSON at all).

    Attributes
    ----------
    records, texts : list
        As :func:`run_scene` returns them: the finished queries, then the interrupted
        one (status ``"error"``, ``error.kind`` ``"interrupted"``).
    not_run : list of dict
        ``{"field", "type"}`` of each query after it, which never started.
    """

    def __init__(self, records, texts, not_run):
        super().__init__("interrupted")
        self.records, self.texts, self.not_run = records, texts, not_run


def interrupted_document(doc: dict, not_run: list) -> dict:
    """Mark a JSON document (:func:`.report.document`) as that of an interrupted run
    (README "Using it"): ``"interrupted": true`` and ``not_run``, the queries that never
    started (``{"field", "type"}``, with ``scene`` in ``distkin demo``'s)."""
    doc["interrupted"] = True
    doc["not_run"] = not_run
    return doc


def run_scene(scene, *, plots_dir=None, progress=True, store=None, workers=None,
              scheduler=None):
    """Run every query of a loaded scene.

    ``store``, ``workers`` and ``scheduler`` (``distkin sweep``) override the scene's
    fields of the same names for every chunked query (:class:`.registry.RunContext`).

    Returns
    -------
    records : list of dict
        The JSON records (one per query), errors included.
    texts : list of str
        The readable text of each query.
    worst : int
        0 if every query succeeded, 2 if one failed on its data, 1 on internal failure.

    Raises
    ------
    RunInterrupted
        Ctrl-C or SIGTERM (a ``KeyboardInterrupt``) during a query: it carries the
        records of the finished queries and of the interrupted one.
    """
    from . import registry as queries
    from .registry import RunContext
    from .report import jsonable
    from .scene import ANCHORS
    from .units import SCENE_UNIT_KINDS, name_scene_units
    ctx = RunContext(plots_dir=Path(plots_dir) if plots_dir else None, progress=progress,
                     store=Path(store) if store else None, workers=workers,
                     scheduler=scheduler)
    records, texts, worst = [], [], 0
    for q in scene.queries:
        spec = queries.get(q.type, scene.mechanism.kind)
        t0 = time.perf_counter()
        rec = {"type": q.type, "status": "ok"}
        text = ""
        try:
            out = spec.run(q.params, scene, ctx)
            rec["result"] = jsonable(out.result)
            text = out.text
            if ctx.plots_dir is not None and out.plot is not None:
                text += _plot(out, ctx.plots_dir, q, rec)
            elif ctx.plots_dir is not None:         # --plots asked, this query has none
                print(f"distkin: note: no plot for query {q.index} ({q.type})",
                      file=sys.stderr)
        except DistkinError as exc:
            # "legs[0]" -> "query[2].legs[0]"; a command-line option ("--scheduler",
            # "--store") is no field of the query
            ctx.option_field(exc)
            if exc.field is None or not exc.field.startswith((*ANCHORS, "--")):
                exc.with_field(q.field)
            if scene.mechanism.kind in SCENE_UNIT_KINDS:   # "length units" -> "mm"
                name_scene_units(exc, scene.units)
            rec.update(status="error", result={},
                       error={"kind": exc.kind, "message": exc.one_line()})
            worst = max(worst, 2 if is_input_error(exc) else 1)
        except Exception as exc:  # an internal failure must not hide the other queries
            rec.update(status="error", result={},
                       error={"kind": "internal", "message": f"{type(exc).__name__}: {exc}"})
            if "--debug" in sys.argv:
                traceback.print_exc()
            worst = 1
        except KeyboardInterrupt:
            seconds = time.perf_counter() - t0
            later = scene.queries[len(records) + 1:]
            rec.update(status="error", result={}, seconds=seconds, error={
                "kind": "interrupted",
                "message": f"{q.field} ({q.type}): interrupted (Ctrl-C or SIGTERM) after "
                           f"{seconds:.1f} s, before its result (a chunked query keeps "
                           "the chunks it finished in its store)"
                           + (f"; not run: {', '.join(r.field for r in later)}"
                              if later else "")})
            raise RunInterrupted(records + [rec], texts + [""],
                                 [{"field": r.field, "type": r.type} for r in later]
                                 ) from None
        rec["seconds"] = time.perf_counter() - t0
        records.append(rec)
        texts.append(text)
    return records, texts, worst


def _plot(out, plots_dir, q, rec) -> str:
    """Draw one query's plots; a failure (no matplotlib, a full disk, a bug in the plot)
    keeps the query's result: it is recorded as ``rec["plot_error"]`` and said on
    stderr, and the exit code does not change.  Returns the text to add."""
    try:
        plots_dir.mkdir(parents=True, exist_ok=True)
        paths = out.plot(plots_dir / f"q{q.index}_{q.type}")
    except Exception as exc:  # a plot must never cost the computed results
        msg = f"{type(exc).__name__}: {exc}"
        rec["plot_error"] = msg
        print(f"distkin: warning: {q.field} ({q.type}): plot failed ({msg}); the results "
              "are kept", file=sys.stderr)
        if "--debug" in sys.argv:
            traceback.print_exc()
        return f"\nplot failed: {msg}"
    rec["plots"] = [str(p) for p in paths]
    return "\nplots: " + ", ".join(str(p) for p in paths)


def _emit(scene_path, records, texts, args, not_run=None) -> None:
    """Print the readable report and write the JSON; ``not_run`` (a list) marks the
    document as that of an interrupted run (:func:`interrupted_document`)."""
    from .output_paths import write_json
    from .report import document, dumps, render_text
    text = render_text(scene_path, records, texts)
    doc = document(scene_path, records, __version__)
    if not_run is not None:
        interrupted_document(doc, not_run)
    if args.json == "-":
        print(text, file=sys.stderr)
        print(dumps(doc))
    else:
        print(text)
        if args.json:
            write_json(args.json, dumps(doc))
            print(f"JSON written to {args.json}")


def _refused_scene(args, exc) -> None:
    """A scene refused at load (every query is validated before any work starts): with
    ``--json`` the JSON contract still comes out, no query run and the reason in
    ``error`` (``{kind, message}``, as a query's), so that a pipeline reading ``--json -``
    always gets a document (QA R 9).  The one-line reason goes to stderr as always."""
    from .output_paths import check_output_path, write_json
    from .report import document, dumps
    doc = document(args.scene, [], __version__)
    doc["error"] = {"kind": exc.kind, "message": exc.one_line()}
    if args.json == "-":
        print(dumps(doc))
    elif args.json:
        # (the files the scene reads are unknown: write only a new file or a .json one)
        if Path(args.json).exists() and Path(args.json).suffix.lower() != ".json":
            return
        try:
            check_output_path(args.json, inputs=(args.scene,))
        except DistkinError:
            return                   # the scene's own error is the one to report
        write_json(args.json, dumps(doc))


def _cmd_run(args) -> int:
    from .output_paths import check_apart, check_output_dir, check_output_path
    from .scene import input_files, load_scene
    try:
        scene = load_scene(args.scene)
    except DistkinError as exc:
        _refused_scene(args, exc)
        raise
    # before the run (a long sweep loses nothing), never over the scene or its CSV, the
    # package, each other or the chunk store (read back on resume)
    inputs = input_files(scene)
    store = getattr(args, "store", None)
    check_apart(files=[("--json", args.json)], folders=[("--plots", args.plots)],
                stores=_scene_stores(scene, store))
    check_output_path(args.json, inputs=inputs)
    check_output_dir(args.plots, "--plots", inputs=inputs)
    if store is not None:
        from ..runstore import make_store
        check_output_dir(store, "--store", inputs=inputs, make=False)
        make_store(store, "--store")
    if getattr(args, "command", None) == "sweep" and not any(q.type in CHUNKED
                                                             for q in scene.queries):
        print(f"distkin: warning: {args.scene}: the scene has no chunked query "
              f"({', '.join(CHUNKED)}), so --workers, --scheduler and --store change "
              "nothing; its queries run as with distkin run", file=sys.stderr)
    try:
        records, texts, worst = run_scene(scene, plots_dir=args.plots,
                                          progress=not args.no_progress,
                                          store=store,
                                          workers=getattr(args, "workers", None),
                                          scheduler=getattr(args, "scheduler", None))
    except RunInterrupted as stop:
        # what finished is kept: the report and the JSON (written atomically) with the
        # interrupted query and those not run; then exit 130 as any interrupt
        with _signals_held():
            _emit(args.scene, stop.records, stop.texts, args, not_run=stop.not_run)
        raise
    _emit(args.scene, records, texts, args)
    for rec in records:
        if rec["status"] == "error":
            _err(rec["error"]["message"])
    return worst


def _cmd_demo(args) -> int:
    from .output_paths import check_apart, check_output_dir, check_output_path
    from .scene import loads_scene
    # never over a built-in scene it reads (QA: --json <package>/scenes/certify_hunt.toml)
    builtin = [Path(str(resources.files("distkin.scenes").joinpath(n))) for n in DEMO_SCENES]
    check_apart(files=[("--json", args.json)], folders=[("--plots", args.plots)])
    check_output_path(args.json, inputs=builtin)
    check_output_dir(args.plots, "--plots", inputs=builtin)
    worst = 0
    records_all = []
    scenes = [loads_scene(resources.files("distkin.scenes").joinpath(name)
                          .read_text(encoding="utf-8"), f"distkin/scenes/{name}")
              for name in DEMO_SCENES]
    for k, (name, scene) in enumerate(zip(DEMO_SCENES, scenes)):
        plots = Path(args.plots) / Path(name).stem if args.plots else None
        try:
            records, texts, w = run_scene(scene, plots_dir=plots,
                                          progress=not args.no_progress)
        except RunInterrupted as stop:      # as run's: what finished, then exit 130
            records_all += [{"scene": scene.path, **rec} for rec in stop.records]
            not_run = [{"scene": scene.path, **r} for r in stop.not_run]
            not_run += [{"scene": later.path, "field": q.field, "type": q.type}
                        for later in scenes[k + 1:] for q in later.queries]
            with _signals_held():
                _demo_output(args, scene.path, stop.records, stop.texts, records_all,
                             not_run=not_run)
            raise
        worst = max(worst, w)
        records_all += [{"scene": scene.path, **rec} for rec in records]
        _demo_output(args, scene.path, records, texts,
                     records_all if k + 1 == len(scenes) else None)
    for rec in records_all:          # as run's: one line per failed query (QA pkg 3)
        if rec["status"] == "error":
            _err(f"{rec['scene']}: {rec['error']['message']}")
    return worst


def _demo_output(args, scene_path, records, texts, records_all, not_run=None) -> None:
    """One built-in scene's readable report; then, at the demo's end (``records_all``,
    every scene's records, given) the JSON, marked interrupted when ``not_run`` is a
    list (:func:`interrupted_document`)."""
    from .output_paths import write_json
    from .report import document, dumps, render_text
    out = sys.stderr if args.json == "-" else sys.stdout
    print(render_text(scene_path, records, texts), file=out)
    if records_all is None or not args.json:
        return
    doc = document(DEMO_SCENE, records_all, __version__)
    if not_run is not None:
        interrupted_document(doc, not_run)
    payload = dumps(doc)        # the contract of 'run', over the queries of every scene
    if args.json == "-":
        print(payload)
    else:
        write_json(args.json, payload)
        print(f"JSON written to {args.json}")


class _signals_held:
    """Hold SIGINT and SIGTERM while an interrupted run writes what it finished (a second
    Ctrl-C would leave no document); they are delivered when the block ends."""

    def __enter__(self):
        try:
            self._old = signal.pthread_sigmask(signal.SIG_BLOCK,
                                               {signal.SIGINT, signal.SIGTERM})
        except (AttributeError, ValueError, OSError):
            self._old = None
        return self

    def __exit__(self, *exc):
        if self._old is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, self._old)
        return False


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        """A usage error (an unknown option, a missing argument): exit 2 with one line on
        stderr, as every bad input, naming where the usage is (``--help`` is unchanged);
        argparse printed the usage first, two to four lines."""
        _err(f"{' '.join(message.split())} (see {self.prog} --help)")
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="distkin", description="Distance-based kinematics of parallel robots.")
    p.add_argument("--version", action="version", version=f"distkin {__version__}")
    p.add_argument("--debug", action="store_true", help="show tracebacks of internal failures")
    sub = p.add_subparsers(dest="command", parser_class=_Parser)
    r = sub.add_parser("run", help="run every query of a scene file")
    r.add_argument("scene", help="scene TOML file")
    _add_output_options(r)
    r.set_defaults(func=_cmd_run)
    d = sub.add_parser("demo", help="run the built-in demonstration scenes")
    _add_output_options(d)
    d.set_defaults(func=_cmd_demo)
    for add in SUBCOMMANDS.values():
        add(sub)
    for sp in sub.choices.values():        # 'distkin run S.toml --debug' works too
        sp.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                        help="show tracebacks of internal failures")
    return p


def _check_cache_env() -> None:
    """A ``DISTKIN_CACHE`` that cannot be a folder is refused before any work, once
    (QA W 6: each query derived its kernels, said "cached", then failed on its own)."""
    import os
    value = os.environ.get("DISTKIN_CACHE")
    if not value:
        return
    path = Path(value)
    try:
        if path.exists() and not path.is_dir():
            raise FileExistsError
        path.mkdir(parents=True, exist_ok=True)
        why = None
    except FileExistsError:
        why = "it is a file"
    except OSError as exc:
        blocker = next((a for a in path.parents if a.exists() and not a.is_dir()), None)
        why = (f"{str(blocker)!r} is a file" if blocker is not None
               else exc.strerror or type(exc).__name__)
    if why is not None:
        raise InputError(f"expected a folder for distkin's cache, got {value!r} ({why})",
                         field="DISTKIN_CACHE", hint="set DISTKIN_CACHE to a folder that "
                                                     "can be written, or unset it")


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):     # one line, as every usage error (not the help)
        commands = ", ".join(["run", "demo", *SUBCOMMANDS])
        _err(f"expected a command ({commands}), got none (see distkin --help)")
        return 2
    if sys.stdout is None and args.command in STDOUT_COMMANDS:
        _err(closed_stdout(args.command).one_line())
        return 2
    old_term = _term_as_interrupt()
    old_format, warnings.formatwarning = warnings.formatwarning, format_warning
    old_stdout = sys.stdout
    if sys.stdout is not None:
        sys.stdout = GuardedStdout(sys.stdout)
    try:
        _check_cache_env()
        code = int(args.func(args) or 0)
        if sys.stdout is not None:
            sys.stdout.flush()       # a full disk said here, not at the exit (exit 120)
        return code
    except DistkinError as exc:
        if getattr(sys.stdout, "failed", False):
            stdout_to_devnull()      # the exit's flush of what is left must not fail again
        _err(exc.one_line())
        return 2 if is_input_error(exc) else 1
    except KeyboardInterrupt:
        _err("interrupted")
        return 130
    except BrokenPipeError as exc:
        # the reader of stdout left (``distkin demo | head``): stop quietly, as a
        # program killed by SIGPIPE would (exit 128 + 13), instead of an "internal
        # failure"; stdout goes to devnull so that the exit's flush does not fail again.
        # Another pipe (a socket, a worker's) is an internal failure as before (review)
        if not _stdout_broken():
            if args.debug:
                traceback.print_exc()
            _err(f"internal failure: {type(exc).__name__}: {exc} (run with --debug for the "
                 "traceback)")
            return 1
        stdout_to_devnull()
        return 141
    except Exception as exc:
        if args.debug:
            traceback.print_exc()
        _err(f"internal failure: {type(exc).__name__}: {exc} (run with --debug for the traceback)")
        return 1
    finally:
        sys.stdout = old_stdout
        warnings.formatwarning = old_format
        if old_term is not None:
            signal.signal(signal.SIGTERM, old_term)


def _stdout_broken() -> bool:
    """Whether stdout is a pipe whose reader left (poll reports an error on its write
    end; a file or a terminal never does)."""
    try:
        import select
        poller = select.poll()
        poller.register(sys.stdout.fileno(), select.POLLOUT)
        return any(ev & select.POLLERR for _, ev in poller.poll(0))
    except (OSError, ValueError, AttributeError):
        return False


def _term_as_interrupt():
    """SIGTERM (``kill``, ``timeout``, a CI cancel) stops a command as Ctrl-C does: the
    chunks a run finished are kept, its pool workers are shut down, ``distkin: error:
    interrupted``, exit 130 (QA: the default handler killed the process alone, and its
    pool workers ran on as orphans holding the output pipes, so ``timeout 60 distkin run
    S.toml | ...`` never returned; its workers get SIGINT, as from a terminal's Ctrl-C, so a
running chunk does not delay the exit).  ``distkin control`` installs its own handlers for
    the run (zero torque first).  Returns the handler it replaced (None off the main
    thread, where none can be installed)."""
    def _raise(signum, frame):
        import multiprocessing
        import os
        for child in multiprocessing.active_children():   # as Ctrl-C: the pool's too
            try:
                os.kill(child.pid, signal.SIGINT)
            except (ProcessLookupError, TypeError):
                pass
        raise KeyboardInterrupt
    try:
        return signal.signal(signal.SIGTERM, _raise)
    except ValueError:                      # not the main thread
        return None
