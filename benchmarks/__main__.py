"""``python -m benchmarks [NAME ...]``: run benchmark modules, update BENCHMARKS.md.

Every module ``benchmarks/bench_NAME.py`` defines ``TITLE`` (str), ``DEFAULT`` (bool:
part of the default run?) and ``run() -> (markdown: str, data: dict)``; one that draws
figures also ``plot(data, out=FIGURES) -> {file name: Path written, or why not}``.  Each run
rewrites its own section of ``BENCHMARKS.md`` (between ``<!-- begin NAME -->`` and
``<!-- end NAME -->``) with the machine, the versions and the command, and the raw
numbers go to ``benchmarks/results.json``.  Modules with ``DEFAULT = False`` say so in
the file and run only when named.  A module may name the distributions its comparisons
need in ``REQUIRES`` (e.g. pycapacity, from the extra ``bench``): a run that would
include it refuses to start without them (exit 2), so that no section is ever written
without its comparison.  A block under the title (``<!-- begin run -->``) is the
log of the runs merged into the file: each run adds a numbered entry (command, date,
sections written with their times, machine) after the others, which it keeps, and says
what the default run left out.  ``-h``/``--help`` lists the sections.

``results.json`` and the run's log entry are written after every section, as its
``BENCHMARKS.md`` section is: a run interrupted (Ctrl-C: exit 130) or failed (exit 1,
one line naming the section) keeps the numbers of the sections it wrote, and its log
entry says where it stopped.

``--replot [NAME ...]`` measures nothing: it redraws the figures of the named sections
(default: every section with figures) from the numbers stored in ``results.json``, with
the section's ``plot(data)`` (``benchmarks/plot_NAME.py``), which a run calls too on the
numbers it stores; results.json and BENCHMARKS.md are left as they are.  A figure whose
numbers the file does not hold is left as it is and named on stderr (exit 1); so is a
results.json that is missing, not JSON, or whose section has no ``data`` or lacks a key
its figures need (one line naming the file and what is missing, no traceback).  A name
that is no section, or a section without figures, exits 2 naming the sections.
"""

from __future__ import annotations

import importlib
import json
import os
import pkgutil
import re
import sys
import time
from pathlib import Path

from .harness import machine

ROOT = Path(__file__).resolve().parent.parent
MD = ROOT / "BENCHMARKS.md"
JSON = Path(__file__).resolve().parent / "results.json"

_HEAD = """# distkin benchmarks

Written by `python -m benchmarks [NAME ...]` (each section by its own module,
`benchmarks/bench_NAME.py`). Timings are medians of interleaved rounds in one process,
quoted as ratios against a named baseline; raw numbers are in `benchmarks/results.json`.
Timings never appear in tests. `python -m benchmarks --replot [NAME ...]` redraws the
figures in `benchmarks/figures/` from the numbers in `results.json` without measuring.
"""


def modules() -> list[str]:
    pkg = Path(__file__).resolve().parent
    return sorted(m.name[len("bench_"):] for m in pkgutil.iter_modules([str(pkg)])
                  if m.name.startswith("bench_"))


def section_module(name: str):
    """The module of section ``name`` (``benchmarks.bench_NAME``)."""
    return importlib.import_module(f"benchmarks.bench_{name}")


def _run_block() -> str:
    """The text of the run log (the block under the title) as it is now."""
    md = MD.read_text(encoding="utf-8") if MD.exists() else ""
    found = re.search(r"<!-- begin run -->\n(.*?)\n<!-- end run -->", md, re.S)
    return found.group(1) if found else ""


def _write_json(results: dict) -> None:
    """``results.json``, whole (temporary file + rename: an interrupt leaves the old or
    the new file, never half of one)."""
    tmp = JSON.with_name(f"{JSON.name}.{os.getpid()}.tmp")
    tmp.write_text(json.dumps(results, indent=2, default=str) + "\n", encoding="utf-8")
    os.replace(tmp, JSON)


def _write_section(name: str, text: str, *, first: bool = False) -> None:
    md = MD.read_text(encoding="utf-8") if MD.exists() else _HEAD
    block = f"<!-- begin {name} -->\n{text.rstrip()}\n<!-- end {name} -->"
    pat = re.compile(rf"<!-- begin {re.escape(name)} -->.*?<!-- end {re.escape(name)} -->", re.S)
    if pat.search(md):
        md = pat.sub(lambda _: block, md)
    elif first and _HEAD.strip() in md:
        md = md.replace(_HEAD.strip(), _HEAD.strip() + "\n\n" + block, 1)
    else:
        md = md.rstrip() + "\n\n" + block + "\n"
    MD.write_text(md, encoding="utf-8")


def _write_run(r: dict, old: str | None = None) -> None:
    """The block under the title: the log of the runs merged into the file, one
    numbered entry each (command, date, time, sections written; the first also names
    the machine and the versions).  A run adds its entry after the last one and keeps
    the others (what was written by hand about an entry stays): it rewrote the whole
    block, and the log of the earlier runs was lost.

    ``old``: the block as it was when the run started (:func:`_run_block`; default: as
    it is now), so that a run writing its entry after each section replaces its own
    entry instead of adding one per section."""
    m = r["machine"]
    ran = ", ".join(f"`{n}` {w:.0f} s" for n, w in r["ran"].items())
    out = (", ".join(f"`{n}` (run: `python -m benchmarks {n}`)" for n in r["left_out"])
           or "none")
    if r["command"] != "python -m benchmarks":
        out = "not applicable (only the named sections ran; the others keep their last results)"
    machine_line = (f"Machine: {m['processor']}, {m['cpu_count']} cores, {m['platform']}.  \n"
                    f"Versions: Python {m['python']}, numpy {m['numpy']}, scipy {m['scipy']}, "
                    f"sympy {m['sympy']}, mpmath {m['mpmath']}, python-flint "
                    f"{m['python-flint']}, numba {m.get('numba', '?')}.  \n")
    old = _run_block() if old is None else old
    numbers = [int(n) for n in re.findall(r"^(?:Runs merged here: )?\((\d+)\) ", old, re.M)]
    entry = (f"`{r['command']}` on {r['date']}, {r['seconds']:.0f} s in all; sections "
             f"written: {ran}; machine {m['processor']}, {m['cpu_count']} cores, Python "
             f"{m['python']}, numpy {m['numpy']}, numba {m.get('numba', '?')}"
             + (f"; stopped in `{r['stopped']}` ({r.get('why', '?')})" if r.get("stopped")
                else "") + ".  \n")
    if numbers:
        kept = re.sub(r"^Left out of the default run:.*$", "", old, flags=re.M).rstrip()
        text = (f"{kept}  \n({max(numbers) + 1}) {entry}"
                f"Left out of the default run: {out}.")
    else:
        text = (f"Runs merged here: (1) {entry}{machine_line}"
                f"Left out of the default run: {out}.")
    _write_section("run", text, first=True)


def _missing_requirements(names, available) -> dict:
    """{section: [distributions not installed]} for the sections this run would write."""
    from importlib.metadata import PackageNotFoundError, version
    out = {}
    for name in available:
        if names is not None and name not in names:
            continue
        mod = section_module(name)
        if names is None and not getattr(mod, "DEFAULT", True):
            continue
        miss = []
        for dist in getattr(mod, "REQUIRES", ()):
            try:
                version(dist)
            except PackageNotFoundError:
                miss.append(dist)
        if miss:
            out[name] = miss
    return out


def _json_type(x) -> str:
    """The JSON name of the type of ``x`` (object, array, string, number, ...)."""
    return {dict: "an object", list: "an array", str: "a string", bool: "a boolean",
            int: "a number", float: "a number", type(None): "null"}.get(type(x), "?")


def _load_results():
    """(results, None) from ``results.json``, or (None, one line saying why not): the
    file missing, unreadable, not JSON or not an object of sections (QA 25b F5: a
    traceback, or "no numbers of 'accuracy'" for a file that does not exist)."""
    if not JSON.exists():
        return None, (f"{JSON} does not exist: no stored numbers to draw from (a run "
                      "writes it: python -m benchmarks [NAME ...])")
    try:
        results = json.loads(JSON.read_text(encoding="utf-8"))
    except OSError as exc:
        return None, f"{JSON} cannot be read ({type(exc).__name__}: {exc.strerror or exc})"
    except (ValueError, UnicodeDecodeError) as exc:    # JSONDecodeError is a ValueError
        return None, (f"{JSON} is not valid JSON ({' '.join(str(exc).split())[:160]}); "
                      "expected the object a run writes, {section: {\"data\": {...}}}")
    if not isinstance(results, dict):
        return None, (f"{JSON} holds {_json_type(results)}, expected an object "
                      "{section: {\"data\": {...}}}")
    return results, None


def _redraw(name, results) -> int:
    """Redraw section ``name``'s figures from ``results``; the number of figures not
    redrawn (each named on stderr in one line: no numbers of the section, no ``data``,
    or numbers its ``plot`` cannot draw from, e.g. a key missing)."""
    where = f"[{name}] not redrawn (its figures left as they are)"
    rerun = f"rerun: python -m benchmarks {name}"
    if name not in results:
        print(f"benchmarks: {where}: {JSON} holds no numbers of {name!r} ({rerun})",
              file=sys.stderr)
        return 1
    entry = results[name]
    if not isinstance(entry, dict) or not isinstance(entry.get("data"), dict):
        got = (f"is {_json_type(entry)}, not an object" if not isinstance(entry, dict)
               else "has no \"data\"" if "data" not in entry else
               f"has {_json_type(entry['data'])} as \"data\", not an object")
        print(f"benchmarks: {where}: {JSON}'s {name!r} {got}; expected "
              f"{{\"data\": {{...}}}} as a run writes it ({rerun})", file=sys.stderr)
        return 1
    try:
        drawn = section_module(name).plot(entry["data"])
    except (KeyError, IndexError, TypeError, ValueError, AttributeError) as exc:
        what = (f"has no key {exc.args[0]!r}" if isinstance(exc, KeyError) and exc.args
                else f"is not what its figures are drawn from ({type(exc).__name__}: "
                     f"{' '.join(str(exc).split())[:160]})")
        print(f"benchmarks: {where}: {JSON}'s {name}.data {what} ({rerun})",
              file=sys.stderr)
        return 1
    if not drawn:                       # e.g. certify's data without "fig3": no figure
        print(f"benchmarks: {where}: {JSON}'s {name}.data names no figure to draw "
              f"({rerun})", file=sys.stderr)
        return 1
    missing = 0
    for fig, what in drawn.items():
        if isinstance(what, Path):
            print(f"[{name}] {fig} redrawn from {JSON.name}")
        else:
            print(f"benchmarks: [{name}] {fig} not redrawn (left as it is): {what}",
                  file=sys.stderr)
            missing += 1
    return missing


def replot(names=None) -> int:
    """Redraw the figures of the sections ``names`` (None: every section with a
    ``plot``) from ``results.json`` by each section's ``plot(data)``, measuring nothing
    and writing neither results.json nor BENCHMARKS.md.  Returns 0 when every figure
    was redrawn; 1 when some were not (their numbers are not in the file, or the file
    is missing or not the JSON a run writes; each said in one line on stderr, its PNG
    left as it is); 2 for a name that is no section (naming the sections) or a section
    that draws no figures (naming those that do)."""
    available = modules()
    drawn = [n for n in available if callable(getattr(section_module(n), "plot", None))]
    unknown = [n for n in (names or ()) if n not in available]
    if unknown:
        print(f"benchmarks: --replot: no section named {', '.join(map(repr, unknown))}; "
              f"the sections are {', '.join(available)} (those with figures: "
              f"{', '.join(drawn)})", file=sys.stderr)
        return 2
    bare = [n for n in (names or ()) if n not in drawn]
    if bare:
        print(f"benchmarks: --replot: section {', '.join(map(repr, bare))} draws no "
              f"figures; the sections with figures are {', '.join(drawn)}", file=sys.stderr)
        return 2
    results, why = _load_results()
    if results is None:
        print(f"benchmarks: --replot: nothing redrawn: {why}", file=sys.stderr)
        return 1
    missing = sum(_redraw(name, results) for name in names or drawn)
    return 1 if missing else 0


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if any(a in ("-h", "--help") for a in argv):
        print(f"usage: python -m benchmarks [NAME ...]\n"
              f"       python -m benchmarks --replot [NAME ...]\n\n{__doc__.strip()}\n\n"
              f"sections: {', '.join(modules())}")
        return 0
    if "--replot" in argv:
        return replot([a for a in argv if a != "--replot"] or None)
    names = argv or None
    available = modules()
    if names:
        bad = [n for n in names if n not in available]
        if bad:
            print(f"benchmarks: unknown {bad}; expected some of {available}", file=sys.stderr)
            return 2
    missing = _missing_requirements(names, available)
    if missing:
        for name, dists in missing.items():
            print(f"benchmarks: section {name!r} needs {', '.join(dists)}, not installed; "
                  f"install the extra: pip install -e '.[bench]'", file=sys.stderr)
        return 2
    results = {}
    if JSON.exists():
        # refused before any measurement: a run writes the file whole, so going on
        # would replace every other section's stored numbers by this run's alone
        results, why = _load_results()
        if results is None:
            print(f"benchmarks: nothing measured: {why}; repair or move it (a run keeps "
                  f"the other sections' numbers in it)", file=sys.stderr)
            return 2
    info = machine()
    run = {"command": "python -m benchmarks" + ("" if names is None else " " + " ".join(names)),
           "date": time.strftime("%Y-%m-%d %H:%M"), "machine": info, "ran": {},
           "left_out": [], "seconds": 0.0}
    log = _run_block()
    t_all = time.perf_counter()
    name = None
    try:
        for name in available:
            _run_section(name, names, info, results, run)
            if name in run["ran"]:
                # the numbers and the log entry with the section (QA 8: only at the end)
                _save(run, results, log, t_all)
    except KeyboardInterrupt:
        return _stopped(name, run, results, log, t_all, "interrupted", 130)
    except Exception as exc:                                 # noqa: BLE001 (one line)
        return _stopped(name, run, results, log, t_all,
                        f"failed: {type(exc).__name__}: {' '.join(str(exc).split())[:200]}", 1)
    _save(run, results, log, t_all)
    return 0


def _save(run, results, log, t_all) -> None:
    """The run so far into results.json (``_last_run``) and its entry into the run log
    (replacing the one it wrote after an earlier section: ``log`` is the block as it was
    when the run started)."""
    run["seconds"] = time.perf_counter() - t_all
    results["_last_run"] = run
    _write_run(run, log)
    _write_json(results)


def _run_section(name, names, info, results, run) -> None:
    """Run section ``name`` if this run includes it: its BENCHMARKS.md section written,
    its numbers put in ``results``, its time in ``run["ran"]``."""
    mod = section_module(name)
    if names is None and not getattr(mod, "DEFAULT", True):
        print(f"[{name}] left out of the default run (run: python -m benchmarks {name})")
        run["left_out"].append(name)
        return
    if names is not None and name not in names:
        return
    print(f"[{name}] {mod.TITLE} ...", flush=True)
    t0 = time.perf_counter()
    text, data = mod.run()
    wall = time.perf_counter() - t0
    head = (f"## {mod.TITLE}\n\nCommand: `python -m benchmarks {name}` · "
            f"{info['processor']}, {info['cpu_count']} cores, Python {info['python']}, "
            f"numpy {info['numpy']}, sympy {info['sympy']}, python-flint "
            f"{info['python-flint']}, numba {info.get('numba', '?')} · "
            f"{time.strftime('%Y-%m-%d')} · {wall:.1f} s"
            + ("" if getattr(mod, "DEFAULT", True) else
               " · not in the default run") + "\n\n")
    _write_section(name, head + text)
    results[name] = {"machine": info, "seconds": wall, "data": data}
    run["ran"][name] = wall
    print(text)


def _stopped(name, run, results, log, t_all, why, code) -> int:
    """A run stopped in section ``name``: the log entry and results.json say so (when a
    section was written), one line on stderr; returns the exit code."""
    kept = ", ".join(run["ran"]) or "none"
    try:
        if run["ran"]:
            run["stopped"], run["why"] = name, why
            _save(run, results, log, t_all)
    except (OSError, KeyboardInterrupt) as exc:
        kept += f" (but their log entry could not be written: {type(exc).__name__})"
    print(f"benchmarks: section {name!r} {why}; sections written to BENCHMARKS.md and "
          f"results.json: {kept}", file=sys.stderr)
    return code


if __name__ == "__main__":
    sys.exit(main())
