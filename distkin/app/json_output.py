"""Where ``--json PATH`` goes: checked before any work, written without a traceback.

``distkin run``, ``demo``, ``sweep`` and ``control`` take ``--json PATH|-``.  A path
that cannot be written (a directory, a file where a folder is needed, no permission)
is bad input: it is refused before the scene runs, so that a long sweep never ends in
an internal failure and a lost result, with one line naming ``--json`` (exit code 2).
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError

__all__ = ["check_json_path", "write_json"]


def _refuse(path, exc: OSError) -> InputError:
    blocker = next((a for a in Path(path).parents if a.exists()), None)
    why = (f"{str(blocker)!r} is not a folder" if blocker is not None and not blocker.is_dir()
           else exc.strerror or type(exc).__name__)
    return InputError(f"expected a writable file path, got {str(path)!r} ({why})",
                      field="--json")


def check_json_path(path) -> None:
    """Refuse a ``--json`` target that cannot be written (``None`` and ``-`` pass).

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
                         field="--json")
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _refuse(path, exc) from None


def write_json(path, payload: str) -> None:
    """Write ``payload`` (JSON text) and a newline to ``path``, making its folders."""
    p = Path(path)
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(payload + "\n", encoding="utf-8")
    except OSError as exc:
        raise _refuse(path, exc) from None
