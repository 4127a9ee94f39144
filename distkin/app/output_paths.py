"""Files the CLI writes (``--json``, ``--port-file``, ``--log``, ``--output``): checked
before any work, written without a traceback.

``distkin run``, ``demo``, ``sweep`` and ``control`` take ``--json PATH|-``; ``sim``
takes ``--port-file`` and ``--log``; ``codegen`` takes ``--output``.  A path that cannot be written (a directory, a
file where a folder is needed, no permission) is bad input: it is refused before the
scene runs or the simulator starts, so that a long sweep never ends in an internal
failure and a lost result, with one line naming the option (exit code 2).
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError

__all__ = ["check_output_path", "write_text", "write_json"]


def _refuse(path, exc: OSError, field: str) -> InputError:
    blocker = next((a for a in Path(path).parents if a.exists()), None)
    why = (f"{str(blocker)!r} is not a folder" if blocker is not None and not blocker.is_dir()
           else exc.strerror or type(exc).__name__)
    return InputError(f"expected a writable file path, got {str(path)!r} ({why})",
                      field=field)


def check_output_path(path, field: str = "--json") -> None:
    """Refuse an output file that cannot be written (``None`` and ``-`` pass); ``field``
    names the option.

    Creates the missing parent folders, as :func:`write_json` would.

    Raises
    ------
    InputError
        The path is a directory, or its folder cannot be made.
    """
    if path is None or path == "-":
        return
    p = Path(path)
    if p.is_dir():
        raise InputError(f"expected a file path, got the directory {str(path)!r}",
                         field=field)
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _refuse(path, exc, field) from None


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
