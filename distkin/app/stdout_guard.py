"""Standard output of the commands whose report goes there (``run``, ``demo``,
``sweep``): closed, or failing to take the text (QA pkg 6).

``distkin run S.toml --json - >&-`` exited 0 and lost the JSON (Python sets
``sys.stdout`` to None for a closed descriptor 1, and ``print`` then writes nothing);
:func:`distkin.app.cli.main` refuses it before any work with :func:`closed_stdout`
(exit 2).  ``distkin demo >/dev/full`` said "internal failure: OSError: [Errno 28] No
space left on device" (exit 1): while a command runs, ``sys.stdout`` is a
:class:`GuardedStdout`, whose failed write or flush is an :class:`InputError` naming
standard output, exit 2 as any output that cannot be written (a ``--json`` file on a
full disk is too).  A reader that left (BrokenPipeError) is not such an error: the CLI
stops quietly with exit 141.
"""

from __future__ import annotations

import os
import sys

from ..errors import InputError

__all__ = ["STDOUT_COMMANDS", "GuardedStdout", "closed_stdout", "stdout_to_devnull"]

#: the commands whose output goes to stdout (a closed one is refused before any work)
STDOUT_COMMANDS = ("run", "demo", "sweep")


def closed_stdout(command: str) -> InputError:
    """The error of a closed stdout for ``command`` (one of :data:`STDOUT_COMMANDS`)."""
    return InputError(f"expected an open standard output (the report of {command} goes "
                      "there, and --json -), got it closed (>&-)", field="stdout",
                      hint="redirect it to /dev/null to discard the report")


class GuardedStdout:
    """``sys.stdout`` while a command runs: a write or a flush that fails with an
    :class:`OSError` other than :class:`BrokenPipeError` raises an :class:`InputError`
    (field ``stdout``, the errno and its text) and sets ``failed``; every other
    attribute is the wrapped stream's."""

    def __init__(self, stream):
        self._stream = stream
        self.failed = False

    def __getattr__(self, name):
        return getattr(self._stream, name)

    def _fail(self, exc: OSError) -> InputError:
        self.failed = True
        return InputError(f"expected a standard output that can be written, got "
                          f"{exc.strerror or type(exc).__name__} (errno {exc.errno}) "
                          "writing it", field="stdout",
                          hint="redirect the output to a file system with room")

    def write(self, text):
        try:
            return self._stream.write(text)
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise self._fail(exc) from None

    def flush(self):
        try:
            return self._stream.flush()
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise self._fail(exc) from None


def stdout_to_devnull() -> None:
    """Point file descriptor 1 at /dev/null once stdout failed, so that the
    interpreter's flush of what is left at exit does not fail again ("Exception
    ignored", exit 120)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):
        pass
