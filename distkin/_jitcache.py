"""Numba's on-disk caches of the package, dropped when any of its sources changed.

Numba (``njit(cache=True)``) checks a cached function against the timestamp of the
file that defines it only, not against the files of the functions it calls: after an
edit (or an upgrade that leaves ``__pycache__`` behind) of ``admittance.py`` alone, the
cached control cycle kept calling the old ``rotation_log`` (QA round E).  The first
import of a package that compiles (``distkin.octahedral``, ``distkin.control``,
``distkin.indices``) compares :func:`distkin.runstore.code_version` (a hash of every
source of the package) with the one written beside the caches, and on a difference
deletes every numba cache file of the package (``__pycache__/*.nbi``, ``*.nbc``): the
next calls compile again.  Nothing happens when the folders are not writable (numba
then keeps its caches elsewhere, for an installation nobody edits).
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["ensure_fresh", "STAMP"]

_ROOT = Path(__file__).resolve().parent
#: the code version the numba caches of the package were written by
STAMP = _ROOT / "__pycache__" / "numba-code-version"


def ensure_fresh() -> bool:
    """Drop the package's numba caches if its sources changed since they were written
    (module docstring); True when they were dropped."""
    from .runstore import code_version
    try:
        version = code_version()
        if STAMP.is_file() and STAMP.read_text(encoding="ascii").strip() == version:
            return False
        for pattern in ("__pycache__/*.nbi", "__pycache__/*.nbc"):
            for path in _ROOT.rglob(pattern):
                try:
                    path.unlink()
                except OSError:
                    pass
        STAMP.parent.mkdir(exist_ok=True)
        tmp = STAMP.with_name(f"{STAMP.name}.{os.getpid()}.tmp")
        tmp.write_text(version + "\n", encoding="ascii")
        os.replace(tmp, STAMP)
        return True
    except (OSError, UnicodeError):
        return False


ensure_fresh()
