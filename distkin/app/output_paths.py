"""Files the CLI writes (``--json``, ``--port-file``, ``--log``, ``--output``): checked
before any work, written without a traceback.

An output that is the same file as one of the command's inputs (the scene, a
``legs_csv`` it names, a controller scene) is refused too: ``distkin run S.toml --json
S.toml`` used to replace the scene by its result; so is one inside the package's
generated kernels (:data:`GENERATED`), which only ``python -m distkin.codegen`` writes.

``distkin run``, ``demo``, ``sweep`` and ``control`` take ``--json PATH|-``; ``sim``
takes ``--port-file`` and ``--log``; ``codegen`` takes ``--output``.  A path that cannot be written (a directory, a
file where a folder is needed, no permission) is bad input: it is refused before the
scene runs or the simulator starts, so that a long sweep never ends in an internal
failure and a lost result, with one line naming the option (exit code 2).  So is an
output inside the installed package (:data:`PACKAGE`, resolved through symbolic links
and ``..``: ``distkin codegen S.toml -o <package>/errors.py`` replaced a source file),
and outputs of one command that would land on each other (:func:`check_apart`: ``--json``
the ``--plots`` folder or a file a query writes there, or a file inside the ``--store`` of
the chunks).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from ..errors import InputError

__all__ = ["check_output_path", "check_not_input", "check_output_dir", "check_apart", "same_file",
           "write_text", "write_json", "GENERATED", "PACKAGE"]

#: the installed package (``distkin/``, resolved): no CLI output goes there (QA: ``distkin
#: codegen S.toml -o <package>/errors.py`` replaced a source file, exit 0)
PACKAGE = Path(__file__).resolve().parents[1]

#: the package's generated kernels (``distkin/_generated``): no CLI output goes there
#: (QA U 8: ``distkin codegen -o distkin/_generated/rss_hunt.py`` replaced a kernel)
GENERATED = (PACKAGE / "_generated").resolve()


def _refuse(path, exc: OSError, field: str) -> InputError:
    blocker = next((a for a in Path(path).parents if a.exists()), None)
    why = (f"{str(blocker)!r} is not a folder" if blocker is not None and not blocker.is_dir()
           else exc.strerror or type(exc).__name__)
    return InputError(f"expected a writable file path, got {str(path)!r} ({why})",
                      field=field)


def _inside(p: Path, folder: Path) -> bool:
    """Whether ``p`` (resolved) is ``folder`` or lies in it (``folder`` resolved too)."""
    try:
        p.resolve().relative_to(Path(folder).resolve())
    except (ValueError, OSError):
        return False
    return True


def _check_not_package(p: Path, field: str, what: str) -> None:
    """Refuse an output ``p`` (a ``what``: "path" or "folder") in the generated kernels
    (their own message: ``python -m distkin.codegen --check``) or anywhere else in the
    installed package (a source file or a built-in scene replaced breaks the install)."""
    if _inside(p, GENERATED):
        raise InputError(f"expected a {what} outside distkin's generated kernels "
                         f"{str(GENERATED)!r} (written only by python -m distkin.codegen, "
                         f"checked against their sources), got {str(p)!r}", field=field,
                         hint="write the file elsewhere; python -m distkin.codegen --check "
                              "names a kernel that was overwritten")
    if _inside(p, PACKAGE):
        raise InputError(f"expected a {what} outside the installed distkin package "
                         f"{str(PACKAGE)!r}, got {str(p)!r} (writing there would replace "
                         "or add to the package's files)", field=field,
                         hint="write the files elsewhere")


def same_file(a: Path, b: Path) -> bool:
    """Whether ``a`` and ``b`` name one file: :func:`os.path.samefile` when both exist
    (symbolic and hard links), the resolved paths otherwise."""
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
        return a.resolve() == b.resolve()
    except OSError:
        return False


def check_output_path(path, field: str = "--json", inputs=(), replace: bool = True) -> None:
    """Refuse an output file that cannot be written (``None`` and ``-`` pass); ``field``
    names the option.

    Creates the missing parent folders, as :func:`write_json` would.

    Parameters
    ----------
    path : str or Path or None
        The output file (``-`` is stdout).
    field : str
        The option that names it (``--json``, ``--output``, ``--log``, ...).
    inputs : iterable of str or Path
        The files the command reads (the scene, ...); ``None`` entries are skipped.  The
        output must not be one of them (compared with :func:`os.path.samefile`, or the
        resolved paths when a file does not exist yet).
    replace : bool
        The writer replaces the file by a temporary one renamed over it
        (:func:`write_text`; its folder must be writable); False for one that opens an
        existing file in place (the run logs).

    Raises
    ------
    InputError
        The path is an input file, a directory, an existing read-only file, or its
        folder cannot be made or written.
    """
    if path is None or path == "-":
        return
    if not str(path).strip():
        raise InputError("expected a file path (or - for stdout), got an empty string",
                         field=field)
    p = Path(path)
    check_not_input(path, field, inputs)
    if p.is_dir():
        raise InputError(f"expected a file path, got the directory {str(path)!r}",
                         field=field)
    _check_not_package(p, field, "path")
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _refuse(path, exc, field) from None
    _check_writable(path, field, replace)


def _check_writable(path, field: str, replace: bool) -> None:
    """Refuse, before any work, what :func:`write_text` would fail on at the end (QA pkg
    4-5): a read-only existing file (the rename would replace it, mode and all, where
    the shell's ``>`` refuses), a device or pipe that cannot be opened for writing, and
    a folder where no file can be made (the temporary file beside the target; with
    ``replace`` False, a writer that opens an existing file in place, only for a new
    file).  :func:`os.access` with the real ids: root passes, as its writes would."""
    real = Path(os.path.realpath(path))
    if real.exists():
        if not os.access(real, os.W_OK):
            kind = "file" if real.is_file() else "non-regular file"
            raise InputError(f"expected a writable file path, got {str(path)!r} (an existing "
                             f"read-only {kind})", field=field,
                             hint="name another file, or make it writable (chmod u+w) or "
                                  "remove it first")
        if not real.is_file() or not replace:
            return                      # a device, a pipe: written in place
    folder = real.parent
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(f"expected a writable file path, got {str(path)!r} (its folder "
                         f"{str(folder)!r} is not writable)", field=field,
                         hint="write the file in another folder")


def check_not_input(path, field: str = "--json", inputs=(), what: str = "an output path"
                    ) -> None:
    """Refuse an output ``path`` that is one of the files ``inputs`` (None and ``-``
    pass; :func:`same_file`): the part of :func:`check_output_path` without its side
    effect (the parent folders), for a check as soon as an input is known; ``what`` the
    output's kind in the message ("a folder" for ``--plots``)."""
    if path is None or path == "-" or not str(path).strip():
        return
    for source in inputs:
        if source is not None and same_file(Path(path), Path(source)):
            raise InputError(f"expected {what} other than the input file "
                             f"{str(source)!r}, got {str(path)!r} (writing it would "
                             "overwrite the input)", field=field)


def check_output_dir(path, field: str, inputs=(), make: bool = True) -> None:
    """Refuse an output folder (``--plots``, ``--store``; ``None`` passes) that cannot be
    written, before any work: an empty string, an existing file (one of ``inputs`` said
    as such), a folder that cannot be made, or one inside the installed package or its
    generated kernels (QA W 5: ``--plots`` and ``--store`` wrote there, which ``--json``
    and ``--output`` refused).  Makes the folder, as the plots or the chunks would.

    ``--plots hunt.txt`` (a file) and ``--plots /proc/pl`` used to run every query, then
    warn that the plots failed.  ``make=False`` (``--store``, which
    :func:`distkin.runstore.make_store` makes with its own message) skips the existing
    file and the making."""
    if path is None:
        return
    if not str(path).strip():
        raise InputError("expected a folder path, got an empty string", field=field)
    p = Path(path)
    for source in inputs:
        if source is not None and same_file(p, Path(source)):
            raise InputError(f"expected a folder other than the input file "
                             f"{str(source)!r}, got {str(path)!r}", field=field)
    _check_not_package(p, field, "folder")
    if not make:
        return
    if p.exists() and not p.is_dir():
        raise InputError(f"expected a folder, got {str(path)!r} (a file of that name "
                         "exists)", field=field)
    try:
        p.mkdir(parents=True, exist_ok=True)
        if not os.access(p, os.W_OK | os.X_OK):
            raise PermissionError(13, "Permission denied")
    except OSError as exc:
        blocker = next((a for a in p.parents if a.exists()), None)
        why = (f"{str(blocker)!r} is not a folder" if blocker is not None
               and not blocker.is_dir() else exc.strerror or type(exc).__name__)
        raise InputError(f"expected a folder that can be written, got {str(path)!r} "
                         f"({why})", field=field) from None


def check_apart(files=(), folders=(), stores=()) -> None:
    """Refuse outputs of one command that would land on each other, before any work.

    Parameters
    ----------
    files : iterable of (field, path)
        Output files (``--json``, ``--log``, ...); ``None`` and ``-`` are skipped.
    folders : iterable of (field, path)
        Folders files are written into (``--plots``).
    stores : iterable of (field, path)
        Chunk stores (``--store``, a query's ``store``): folders read back on resume, so
        no other output goes inside them (``--json S/sweep.json`` replaced the store's
        metadata, ``--json S/chunk_00000.npz`` a chunk).

    Raises
    ------
    InputError
        Two files are one; a file is a folder, or is inside a store (or inside a
        plots folder under a name a query's files may have: ``q{i}_*`` or ``*.png``);
        a folder is inside a file; a folder is, or is inside, a store.  Names the later
        option.
    """
    def keep(pairs):
        return [(f, Path(p)) for f, p in pairs if p is not None and str(p) not in ("", "-")]

    files, folders, stores = keep(files), keep(folders), keep(stores)
    for i, (fa, a) in enumerate(files):
        for fb, b in files[:i]:
            if same_file(a, b):
                raise InputError(f"expected a file other than the {fb} file {str(b)!r}, "
                                 f"got {str(a)!r} (one would overwrite the other)",
                                 field=fa)
    for fd, d in folders + stores:
        kind = "chunk store" if (fd, d) in stores else "folder"
        for ff, f in files:
            # a plots folder holds the files the queries write, each named after its
            # query, q{i}_{type}* (PNGs, and performance's q{i}_performance_tables.json
            # and .md; demo's in a sub-folder per scene): a JSON of another name
            # (--plots out --json out/r.json) overwrites nothing; the folder itself, a
            # q{i}_* name or a .png does (QA 23 D2: --json P/q3_performance_tables.json)
            beside = (kind == "folder" and not _plot_name(f) and not same_file(f, d))
            if _inside(f, d) and not beside:
                why = (f" (the files a query writes in the {fd} folder are named "
                       "q{i}_{type}*, as q3_performance_tables.json; one would overwrite "
                       "the other)" if kind == "folder" and not same_file(f, d) else "")
                raise InputError(f"expected a path outside the {fd} {kind} {str(d)!r}, "
                                 f"got {str(f)!r}{why}", field=ff,
                                 hint=f"write {ff} beside the {kind}, not in it")
            if _inside(d, f):
                raise InputError(f"expected a folder apart from the {ff} file {str(f)!r}, "
                                 f"got {str(d)!r}", field=fd)
    for fd, d in folders:
        for fs, s in stores:
            if _inside(d, s):
                raise InputError(f"expected a folder outside the {fs} chunk store "
                                 f"{str(s)!r}, got {str(d)!r}", field=fd,
                                 hint="write the plots beside the store, not in it")


def _plot_name(f: Path) -> bool:
    """Whether a file may be one a query writes into a plots folder: a ``.png``, or a
    name of the queries' pattern ``q{i}_{type}*`` (``cli._plot``'s stem)."""
    return f.suffix.lower() == ".png" or re.match(r"q\d+_", f.name) is not None


def write_text(path, text: str, field: str) -> None:
    """Write ``text`` to ``path``, making its folders; a failure names ``field``.

    Atomic for a regular file (or a new one): the text goes to a temporary file beside
    it (``.NAME.PID.tmp``, made with the usual permissions), which then replaces it
    (:func:`os.replace`), so an interrupt or a full disk never leaves half a file, nor an
    earlier run's file looking as if it were this run's.  A symbolic link is followed
    (its target is replaced); a device or a pipe (``/dev/stdout``) is written in place."""
    p = Path(os.path.realpath(path))
    tmp = None
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        if p.exists() and not p.is_file():
            with open(p, "w", encoding="utf-8") as fh:
                fh.write(text)
            return
        tmp = p.parent / f".{p.name}.{os.getpid()}.tmp"
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, p)
    except OSError as exc:
        raise _refuse(path, exc, field) from None
    finally:
        if tmp is not None and tmp.exists():
            try:
                tmp.unlink()
            except OSError:
                pass


def write_json(path, payload: str) -> None:
    """Write ``payload`` (JSON text) and a newline to ``path`` (``--json``)."""
    write_text(path, payload + "\n", "--json")
