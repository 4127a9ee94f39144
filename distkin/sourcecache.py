"""The derivation cache: generated module sources keyed by a hash of their symbolic source.

"Model only what a scene requires" (docs/design.md §1): a generated kernel module is derived
once per distinct symbolic source and stored as a ``.py`` file; the second run of a scene
reads it back and does no algebra (it does not even import sympy).

The cache folder is ``$DISTKIN_CACHE`` if set, else ``$XDG_CACHE_HOME/distkin``, else
``~/.cache/distkin``.  Files are written atomically (temporary file + rename), and on
POSIX a lock file beside each entry (``fcntl.flock``, released by the system when its
holder dies) lets one process derive a module while the others wait for it and load it
(parallel workers used to derive it once each); without ``fcntl`` they may at worst derive
it twice.  Deleting the folder is always safe.

A generator's key holds :func:`closure_text` of its modules: the text of every distkin
file they import, transitively (:func:`import_closure`), and the versions of sympy,
numpy, mpmath and python, so no edited dependency or upgrade is served a stale module.
"""

from __future__ import annotations

import ast
import contextlib
import hashlib
import importlib.util
import os
import platform
import sys
import tempfile
from functools import lru_cache
from pathlib import Path

from .runstore import user_cache_dir

try:
    import fcntl
except ImportError:           # not POSIX: no lock; concurrent processes may derive twice
    fcntl = None

__all__ = ["cache_dir", "source_key", "import_closure", "closure_text",
           "toolchain_versions", "cached_source", "entry_lock", "load_module_file", "load_source"]

#: the distkin package folder (the root of :func:`import_closure`)
PACKAGE_ROOT = Path(__file__).resolve().parent


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


def _module_file(root: Path, module: str):
    """The file of ``distkin.a.b`` under ``root`` (``a/b.py`` or ``a/b/__init__.py``),
    or None for a name that is no module of the package (an attribute, say)."""
    parts = module.split(".")[1:]
    base = root.joinpath(*parts) if parts else root
    for f in (base.with_suffix(".py") if parts else None, base / "__init__.py"):
        if f is not None and f.is_file():
            return f
    return None


@lru_cache(maxsize=512)
def _imports_of(path: str, mtime_ns: int, size: int, module: str, is_pkg: bool) -> tuple:
    """The imports of one file that name distkin (at module level or inside functions: a
    deferred import is still a dependency), as ``(package, names)``: ``import a.b`` is
    ``("a.b", ())``, ``from a import b, c`` is ``("a", ("b", "c"))`` with relative
    names resolved; memoised by the file's stat, so a changed file is parsed again."""
    tree = ast.parse(Path(path).read_text(encoding="utf-8"), filename=path)
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(a.name, ()) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = module.split(".") if is_pkg else module.split(".")[:-1]
                base = base[:len(base) - (node.level - 1)]
                pkg = ".".join(base + ([node.module] if node.module else []))
            else:
                pkg = node.module or ""
            out.append((pkg, tuple(a.name for a in node.names)))
    return tuple((p, n) for p, n in out if p.split(".")[0] == "distkin")


def import_closure(modules, root=None) -> tuple:
    """The files of the ``distkin`` modules that ``modules`` import, transitively
    (``import`` and ``from ... import``, relative or absolute, at module level or inside
    functions), with their own files: every source a generator's output can depend on.

    ``from pkg import name`` depends on the module ``pkg.name`` if there is one, else
    on ``pkg`` (its ``__init__``); the ``__init__`` of a package a module merely sits in
    is not a dependency (the arrows of the package's import graph, docs/design.md).

    Parameters
    ----------
    modules : iterable of str
        Dotted names (``"distkin.codegen.rss"``).
    root : Path, optional
        The package folder (default: the installed ``distkin``; a copy, for tests).

    Returns
    -------
    tuple of str
        Paths relative to ``root`` (``"mechanisms/kernel_names.py"``), sorted.
    """
    root = Path(root) if root is not None else PACKAGE_ROOT
    seen, files, todo = set(), set(), list(modules)
    while todo:
        mod = todo.pop()
        if mod in seen:
            continue
        seen.add(mod)
        f = _module_file(root, mod)
        while f is None and "." in mod:          # an attribute: its module
            mod = mod.rsplit(".", 1)[0]
            f = _module_file(root, mod)
        if f is None or f in files:
            continue
        files.add(f)
        st = f.stat()
        for pkg, names in _imports_of(str(f), st.st_mtime_ns, st.st_size, mod,
                                      f.name == "__init__.py"):
            subs = [f"{pkg}.{n}" for n in names if _module_file(root, f"{pkg}.{n}")]
            todo += subs if len(subs) == len(names) and names else [pkg, *subs]
    return tuple(sorted(f.relative_to(root).as_posix() for f in files))


def toolchain_versions() -> str:
    """``"sympy 1.14.0, numpy ..., mpmath ..., python 3.11"``: the versions a generated
    module's header names (:func:`distkin.codegen.emit.module_source`), read from the
    installed distributions (no import of sympy)."""
    from importlib import metadata
    out = []
    for dist in ("sympy", "numpy", "mpmath"):
        try:
            out.append(f"{dist} {metadata.version(dist)}")
        except metadata.PackageNotFoundError:
            out.append(f"{dist} missing")
    return ", ".join(out) + f", python {platform.python_version().rsplit('.', 1)[0]}"


def closure_text(modules, root=None) -> str:
    """The cache-key text of a generator: the toolchain's versions
    (:func:`toolchain_versions`) and the path and text of every file of
    :func:`import_closure` ``(modules)``, so that a change in any module the generator
    imports, or a sympy upgrade, derives its modules again."""
    root = Path(root) if root is not None else PACKAGE_ROOT
    parts = [toolchain_versions()]
    for rel in import_closure(modules, root):
        parts += [f"\x00{rel}\x00", (root / rel).read_text(encoding="utf-8")]
    return "".join(parts)


def cached_source(prefix: str, key: str, build, on_wait=None):
    """The module source stored under ``key``, or ``build()`` it and store it.

    Parameters
    ----------
    prefix : str
        File-name prefix (a readable hint: ``rss``).
    key : str
        :func:`source_key` of everything the source depends on.
    build : callable () -> str
        Derives the source (the expensive, sympy part).  Between the check of the cache
        and the write, the entry's lock file (``.lock``) is held, so of processes asking
        for the same missing entry at once one builds and the others wait and load it.
    on_wait : callable () -> None, optional
        Called once before waiting for another process that holds the entry's lock (to
        say so); the wait can be interrupted (Ctrl-C).

    Returns
    -------
    path : Path
        The cached file.  Its SHA-256 is kept beside it (``.sha256``, written after it);
        a file that does not match it (truncated, emptied, edited) is derived again.
    hit : bool
        True if no derivation was needed (in this process).
    """
    d = cache_dir()
    path = d / f"{prefix}_{key[:24]}.py"
    digest = path.with_suffix(".sha256")
    if _intact(path, digest):
        return path, True
    try:
        d.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _unwritable(d, exc) from None
    with entry_lock(path.with_suffix(".lock"), on_wait):
        if _intact(path, digest):          # derived by the process we waited for
            return path, True
        src = build()
        try:
            _write_atomic(d, path, src)
            _write_atomic(d, digest, hashlib.sha256(src.encode("utf-8")).hexdigest() + "\n")
        except OSError as exc:               # QA U 9: was an internal failure (exit 1)
            raise _unwritable(d, exc) from None
    return path, False


def _intact(path, digest) -> bool:
    """Whether ``path`` exists and matches its ``.sha256`` (a damaged file is not)."""
    try:
        return path.is_file() and digest.read_text(encoding="ascii").strip() == \
            hashlib.sha256(path.read_bytes()).hexdigest()
    except (OSError, UnicodeError):
        return False


def _unwritable(d, exc):
    """The InputError of a cache folder that cannot be written: field ``DISTKIN_CACHE``
    (the setting that names the folder; QA pkg 7: the field was ``HOME`` when the default
    folder was used, shown as ``query[0].HOME``), the message saying where an unset
    variable's default came from."""
    from .errors import InputError
    why = exc.strerror or type(exc).__name__
    if not os.environ.get("DISTKIN_CACHE"):
        source = ("$XDG_CACHE_HOME/distkin" if os.environ.get("XDG_CACHE_HOME") else
                  f"~/.cache/distkin, HOME={os.environ.get('HOME', '')!r}")
        why += f"; DISTKIN_CACHE is not set, so the cache folder is {source}"
    return InputError(f"expected a writable cache folder for the derived kernels, got "
                      f"{str(d)!r} ({why})", field="DISTKIN_CACHE",
                      hint="set DISTKIN_CACHE to a folder that can be written")


@contextlib.contextmanager
def entry_lock(lock, on_wait=None):
    """Hold an exclusive ``fcntl.flock`` on the file ``lock`` (created if missing, never
    removed: removing it would let two processes lock two files).  The system releases
    it when the holder exits or dies, so a crashed deriver blocks nobody; a blocking wait
    is interrupted by a signal whose handler raises (Ctrl-C, PEP 475).  Without
    ``fcntl``, or where the file cannot be opened or locked (a read-only folder, a file
    system without locks), nothing is held."""
    fd = None
    if fcntl is not None:
        try:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                if on_wait is not None:
                    on_wait()
                fcntl.flock(fd, fcntl.LOCK_EX)
        except OSError:
            if fd is not None:
                os.close(fd)
            fd = None
        except BaseException:              # Ctrl-C while waiting: let go of the file
            if fd is not None:
                os.close(fd)
            raise
    try:
        yield
    finally:
        if fd is not None:
            os.close(fd)                    # releases the lock


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
