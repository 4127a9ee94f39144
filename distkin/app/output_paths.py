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
failure and a lost result, with one line naming the option (exit code 2).
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import InputError

__all__ = ["check_output_path", "check_output_dir", "write_text", "write_json", "GENERATED"]

#: the package's generated kernels (``distkin/_generated``): no CLI output goes there
#: (QA U 8: ``distkin codegen -o distkin/_generated/rss_hunt.py`` replaced a kernel)
GENERATED = (Path(__file__).resolve().parents[1] / "_generated").resolve()


def _refuse(path, exc: OSError, field: str) -> InputError:
    blocker = next((a for a in Path(path).parents if a.exists()), None)
    why = (f"{str(blocker)!r} is not a folder" if blocker is not None and not blocker.is_dir()
           else exc.strerror or type(exc).__name__)
    return InputError(f"expected a writable file path, got {str(path)!r} ({why})",
                      field=field)


def _inside(p: Path, folder: Path) -> bool:
    """Whether ``p`` (resolved) lies in ``folder``."""
    try:
        p.resolve().relative_to(folder)
    except (ValueError, OSError):
        return False
    return True


def _same_file(a: Path, b: Path) -> bool:
    """Whether ``a`` and ``b`` name one file: :func:`os.path.samefile` when both exist
    (symbolic and hard links), the resolved paths otherwise."""
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
        return a.resolve() == b.resolve()
    except OSError:
        return False


def check_output_path(path, field: str = "--json", inputs=()) -> None:
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

    Raises
    ------
    InputError
        The path is an input file, a directory, or its folder cannot be made.
    """
    if path is None or path == "-":
        return
    if not str(path).strip():
        raise InputError("expected a file path (or - for stdout), got an empty string",
                         field=field)
    p = Path(path)
    for source in inputs:
        if source is not None and _same_file(p, Path(source)):
            raise InputError(f"expected an output path other than the input file "
                             f"{str(source)!r}, got {str(path)!r} (writing it would "
                             "overwrite the input)", field=field)
    if p.is_dir():
        raise InputError(f"expected a file path, got the directory {str(path)!r}",
                         field=field)
    if _inside(p, GENERATED):
        raise InputError(f"expected a path outside distkin's generated kernels "
                         f"{str(GENERATED)!r} (written only by python -m distkin.codegen, "
                         f"checked against their sources), got {str(path)!r}", field=field,
                         hint="write the file elsewhere; python -m distkin.codegen --check "
                              "names a kernel that was overwritten")
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _refuse(path, exc, field) from None


def check_output_dir(path, field: str) -> None:
    """Refuse an output folder (``--plots``, ``--store``; ``None`` passes) inside the
    package's generated kernels (QA W 5: ``--plots`` and ``--store`` wrote there, which
    ``--json`` and ``--output`` refused)."""
    if path is not None and _inside(Path(path), GENERATED):
        raise InputError(f"expected a folder outside distkin's generated kernels "
                         f"{str(GENERATED)!r} (written only by python -m distkin.codegen), "
                         f"got {str(path)!r}", field=field, hint="write the files elsewhere")


def write_text(path, text: str, field: str) -> None:
    """Write ``text`` to ``path``, making its folders; a failure names ``field``."""
    p = Path(path)
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise _refuse(path, exc, field) from None


def write_json(path, payload: str) -> None:
    """Write ``payload`` (JSON text) and a newline to ``path`` (``--json``)."""
    write_text(path, payload + "\n", "--json")
