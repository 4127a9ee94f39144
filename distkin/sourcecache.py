"""The derivation cache: generated module sources keyed by a hash of their symbolic source.

"Model only what a scene requires" (docs/design.md §1): a generated kernel module is derived
once per distinct symbolic source and stored as a ``.py`` file; the second run of a scene
reads it back and does no algebra (it does not even import sympy).

The cache folder is ``$DISTKIN_CACHE`` if set, else ``$XDG_CACHE_HOME/distkin``, else
``~/.cache/distkin``.  Files are written atomically (temporary file + rename), so
concurrent processes at worst derive the same module twice.  Deleting the folder is
always safe.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import sys
import tempfile
from pathlib import Path

from .runstore import user_cache_dir

__all__ = ["cache_dir", "source_key", "package_text", "cached_source", "load_module_file",
           "load_source"]


def cache_dir() -> Path:
    """The cache folder (created on demand; :func:`distkin.runstore.user_cache_dir`)."""
    return user_cache_dir()


def source_key(*parts) -> str:
    """SHA-256 of the parts' text (source files of the model, parameter values, ...)."""
    h = hashlib.sha256()
    for p in parts:
        h.update(p if isinstance(p, bytes) else str(p).encode())
        h.update(b"\x00")
    return h.hexdigest()


def package_text(files) -> str:
    """The text of ``files`` (paths relative to the ``distkin`` package), concatenated:
    the model source a generated module depends on, for :func:`source_key`."""
    root = Path(__file__).resolve().parent
    return "".join((root / f).read_text(encoding="utf-8") for f in files)


def cached_source(prefix: str, key: str, build):
    """The module source stored under ``key``, or ``build()`` it and store it.

    Parameters
    ----------
    prefix : str
        File-name prefix (a readable hint: ``rss``).
    key : str
        :func:`source_key` of everything the source depends on.
    build : callable () -> str
        Derives the source (the expensive, sympy part).

    Returns
    -------
    path : Path
        The cached file.  Its SHA-256 is kept beside it (``.sha256``, written after it);
        a file that does not match it (truncated, emptied, edited) is derived again.
    hit : bool
        True if no derivation was needed.
    """
    d = cache_dir()
    path = d / f"{prefix}_{key[:24]}.py"
    digest = path.with_suffix(".sha256")
    if path.is_file():
        try:                     # a damaged file (truncated, emptied) is derived again
            if digest.read_text(encoding="ascii").strip() == \
                    hashlib.sha256(path.read_bytes()).hexdigest():
                return path, True
        except (OSError, UnicodeError):
            pass
    src = build()
    try:
        d.mkdir(parents=True, exist_ok=True)
        _write_atomic(d, path, src)
        _write_atomic(d, digest, hashlib.sha256(src.encode("utf-8")).hexdigest() + "\n")
    except OSError as exc:               # QA U 9: was an internal failure (exit 1)
        from .errors import InputError
        var = ("DISTKIN_CACHE" if os.environ.get("DISTKIN_CACHE") else
               "XDG_CACHE_HOME" if os.environ.get("XDG_CACHE_HOME") else "HOME")
        raise InputError(f"expected a writable cache folder for the derived kernels, got "
                         f"{str(d)!r} ({exc.strerror or type(exc).__name__})", field=var,
                         hint="set DISTKIN_CACHE to a folder that can be written") from None
    return path, False


def _write_atomic(d, path, text):
    fd, tmp = tempfile.mkstemp(dir=d, suffix=".tmp")
    with os.fdopen(fd, "w", encoding="utf-8", newline="") as fh:
        fh.write(text)
    os.replace(tmp, path)


def load_module_file(path, name: str | None = None):
    """Import a generated module from a file path (not added to ``sys.modules``)."""
    path = Path(path)
    name = name or f"distkin_generated_{path.stem}"
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def load_source(source: str, name: str = "distkin_generated"):
    """Execute module source text into a fresh module object."""
    import types
    mod = types.ModuleType(name)
    mod.__file__ = f"<{name}>"
    exec(compile(source, mod.__file__, "exec"), mod.__dict__)
    sys.modules.pop(name, None)
    return mod
