"""The files of a run store (:mod:`distkin.runstore`): chunk files and their stamps,
``sweep.json``, the temporary files of a save, and what a store that cannot be written
is told as (an :class:`~distkin.errors.InputError` naming the store and the cause: disk
full, not writable; exit 2), with no temporary file left behind.

A chunk file is written to a temporary name of this host and process
(``chunk_NNNNN.npz.HOST@PID.tmp.npz``), then renamed, so a file named like a chunk is
always whole; the temporary files a killed process left are removed when the store is
opened again (:func:`remove_stale_tmp`).  Opening a store (:func:`open_store`) checks
its ``sweep.json`` and the stamps of its chunk files and loads the finished chunks.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import re
import socket
import sys
import time
import zipfile
from pathlib import Path

import numpy as np

from .errors import InputError

__all__ = ["save_chunk", "load_chunk", "chunk_stamp", "stamp_mismatch", "finished_chunks",
           "remove_stale_tmp", "pid_alive", "write_meta", "check_writable",
           "store_write_error", "redo_damaged", "refuse_damaged", "open_store", "META_HINT",
           "HOST", "CHUNK_RE", "TMP_RE", "STALE_TMP_S"]

#: a finished chunk's file name, and a temporary one of :func:`save_chunk`
#: (``.HOST@PID.tmp.npz``; older versions wrote ``.PID.tmp.npz``)
CHUNK_RE = re.compile(r"chunk_\d+\.npz")
TMP_RE = re.compile(r"(?:chunk_\d+\.npz|sweep\.json)\.(?:([A-Za-z0-9_-]+)@)?(\d+)\.tmp(?:\.npz)?")
#: this host in temporary file names (a store shared between hosts: a PID is only
#: judged alive or dead on its own host)
HOST = re.sub(r"[^A-Za-z0-9_-]", "_", socket.gethostname()) or "host"
#: seconds after which a temporary file of a dead process (or of any process: a store
#: shared between hosts) is removed when the store is opened
STALE_TMP_S = (60.0, 86400.0)
#: what an OSError of a write into a store is said as
_CAUSES = {errno.ENOSPC: "disk full", errno.EDQUOT: "disk quota exceeded",
           errno.EROFS: "not writable (a read-only file system)",
           errno.EACCES: "not writable (permission denied)",
           errno.EPERM: "not writable (operation not permitted)"}


def store_write_error(store, exc: OSError, what: str) -> InputError:
    """The error of a write into the chunk store ``store`` that failed with ``exc``
    (``what``: the file being written): the store and the cause, with a hint that the
    chunks saved before are kept."""
    cause = _CAUSES.get(exc.errno) or exc.strerror or type(exc).__name__
    return InputError(f"expected a chunk store that can be written, got {str(store)!r}: "
                      f"{cause} (writing {what})", field="store",
                      hint="free space or use another directory; the chunks saved before "
                           "are kept and a run again resumes from them")


def check_writable(store: Path, left: int, n: int) -> None:
    """Refuse (InputError) a store in which no file can be made, before any work: a
    run with ``left`` of its ``n`` chunks still to compute (a read-only store whose
    chunks are all there is only read).  The probe is a temporary file of this process
    (a name :func:`remove_stale_tmp` knows), removed at once."""
    probe = store / f"sweep.json.{HOST}@{os.getpid()}.tmp"
    try:
        fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    except OSError as exc:
        cause = _CAUSES.get(exc.errno) or exc.strerror or type(exc).__name__
        raise InputError(f"expected a chunk store that can be written, got {str(store)!r}: "
                         f"{cause}, with {left} of {n} chunks still to compute",
                         field="store", hint="make it writable or use another directory; a store that "
                         "holds every chunk is only read") from None
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(probe)


def write_meta(meta: Path, payload: dict, *, needed: bool) -> None:
    """Write ``sweep.json`` whole (a temporary file renamed); a failure removes the
    temporary file and raises :func:`store_write_error` when the store will be written
    (``needed``), else is let be (a read-only store that holds every chunk)."""
    tmp = meta.with_name(f"{meta.name}.{HOST}@{os.getpid()}.tmp")
    try:
        tmp.write_text(json.dumps(payload, default=str, indent=1))
        os.replace(tmp, meta)                            # whole, for a second run too
    except OSError as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        if needed:
            raise store_write_error(meta.parent, exc, meta.name) from None


def _named(damaged: list) -> tuple:
    names = [f"{p.name} ({type(exc).__name__})" for p, exc in damaged]
    return len(names), ", ".join(names[:5]) + (f" and {len(names) - 5} more"
                                               if len(names) > 5 else "")


def refuse_damaged(store: Path, damaged: list) -> None:
    """Refuse (InputError naming them) the chunk files of ``store`` that cannot be read
    (``damaged``: (path, exception) pairs) in a folder that is not a distkin store (no
    ``sweep.json``): a user's file named like a chunk is never deleted (QA)."""
    if damaged:
        count, shown = _named(damaged)
        raise InputError(f"expected the files named like chunks in {str(store)!r} to be "
                         f"chunk files distkin can read, got {count} it cannot: {shown}, "
                         "in a folder that is not a distkin store (no sweep.json)",
                         field="store", hint="use another directory, or move those files "
                         "away; a damaged chunk of this sweep can be deleted, it is "
                         "computed again")


def redo_damaged(store: Path, damaged: list) -> None:
    """Remove the chunk files of the distkin store ``store`` that cannot be read
    (``damaged``: (path, exception) pairs), to be computed again, and say which in one
    line on stderr."""
    if not damaged:
        return
    count, shown = _named(damaged)
    for p, exc in damaged:
        try:
            p.unlink()
        except OSError as err:
            raise InputError(f"expected chunk file {str(p)!r} to be readable or "
                             f"removable, got neither ({type(exc).__name__}; "
                             f"{err.strerror or type(err).__name__})",
                             field="store", hint="remove it by hand or use another "
                             "directory") from None
    print(f"distkin: warning: {count} damaged chunk file(s) in {str(store)!r} "
          f"computed again: {shown}", file=sys.stderr, flush=True)


def save_chunk(path: Path, data: dict, stamp: dict | None = None) -> None:
    """``data`` (name -> array) as one uncompressed ``.npz``, arrays of the same dtype
    and shape stacked into one entry (a study chunk's hundred arrays of per-position
    values become two entries: one zip entry and npy header each instead of a hundred,
    about 0.1 ms instead of 2.5 ms a chunk, which the process collecting the workers'
    chunks spends while they compute); names, groups and places are arrays of str and
    int, so loading needs no pickle.  ``stamp`` (JSON-able: the sweep's key, the code
    version, the chunk's index and the number of chunks, :func:`chunk_stamp`) is kept
    beside them as a JSON string (``stamp__``), which :func:`load_chunk` returns.  An
    OSError of the write (disk full, read-only store) removes the temporary file and is
    raised as :func:`store_write_error`."""
    names = list(data)
    arrays = [np.asarray(data[k]) for k in names]
    keys: dict = {}
    group = np.empty(len(names), np.int64)
    place = np.empty(len(names), np.int64)
    members: list = []
    for i, a in enumerate(arrays):
        g = keys.setdefault((a.dtype.str, a.shape), len(keys))
        if g == len(members):
            members.append([])
        group[i], place[i] = g, len(members[g])
        members[g].append(a)
    entries = {f"group{g}": np.stack(m) for g, m in enumerate(members)}
    # a name of this process's own: two runs into one store must not share it
    tmp = path.with_name(f"{path.name}.{HOST}@{os.getpid()}.tmp.npz")
    extra = {} if stamp is None else {"stamp__": np.array(json.dumps(stamp, sort_keys=True))}
    try:
        np.savez(tmp, names__=np.array(names, dtype=str), group__=group, place__=place,
                 **extra, **entries)
        os.replace(tmp, path)
    except OSError as exc:      # disk full, read-only: no half file left; saved ones kept
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise store_write_error(path.parent, exc, path.name) from None


def load_chunk(path: Path) -> tuple:
    """(the dict :func:`save_chunk` wrote, each array a copy of its row of the stack; the
    chunk's stamp, or None for a file written without one)."""
    with np.load(path) as z:
        if "names__" not in z.files:                     # one entry per array
            return {k: z[k] for k in z.files}, None
        stamp = json.loads(str(z["stamp__"])) if "stamp__" in z.files else None
        stacks = {k: z[k] for k in z.files if k.startswith("group")}
        return ({str(n): stacks[f"group{g}"][p, ...].copy()
                 for n, g, p in zip(z["names__"], z["group__"], z["place__"])}, stamp)


def chunk_stamp(key: str, code: str, index: int, chunks: int) -> dict:
    """What a chunk file says of itself: the key of its sweep's definition, the code
    version that computed it, its index and the number of chunks of its sweep."""
    return {"key": key, "code": code, "chunk": int(index), "chunks": int(chunks)}


def stamp_mismatch(stamp, want: dict) -> str | None:
    """Why a chunk of stamp ``stamp`` is not the chunk ``want`` (:func:`chunk_stamp`)
    of this sweep, or None when it is."""
    if not isinstance(stamp, dict):
        return "no sweep key (written by an older distkin or not by this sweep)"
    if stamp.get("key") != want["key"]:
        return f"made for sweep key {stamp.get('key')}"
    if stamp.get("code") != want["code"]:
        return f"made by distkin {stamp.get('code')}"
    if (stamp.get("chunk"), stamp.get("chunks")) != (want["chunk"], want["chunks"]):
        return f"chunk {stamp.get('chunk')} of {stamp.get('chunks')}"
    return None


def finished_chunks(store) -> list:
    """The finished chunk files of ``store`` (``chunk_NNNNN.npz``; not the temporary
    files of a save in progress or of a killed process)."""
    return sorted(p for p in Path(store).glob("chunk_*.npz")
                  if CHUNK_RE.fullmatch(p.name) and p.is_file())


def pid_alive(pid: int) -> bool:
    """Whether process ``pid`` runs on this host (True when that cannot be told)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (OSError, ValueError, OverflowError):
        return True
    return True


def remove_stale_tmp(store: Path) -> list:
    """Remove the temporary files of :func:`save_chunk` (and of ``sweep.json``) that a killed
    process left: those of a process of this host that no longer runs, older than a
    minute, and any older than a day (another host's: its PID means nothing here; a
    name without a host, of an older version, counts as this host's).  Returns the
    names removed."""
    dead_age, any_age = STALE_TMP_S
    now, removed = time.time(), []
    for p in store.iterdir():
        m = TMP_RE.fullmatch(p.name)
        if m is None or not p.is_file():
            continue
        here, pid = m.group(1) in (None, HOST), int(m.group(2))
        try:
            age = now - p.stat().st_mtime
            if age > any_age or (here and age > dead_age and pid != os.getpid()
                                 and not pid_alive(pid)):
                p.unlink()
                removed.append(p.name)
        except OSError:
            pass                                         # another process's cleanup
    return removed


#: what to do about a sweep.json that is not a store's: every chunk carries its own stamp
META_HINT = ("use another directory, or delete only its sweep.json: every chunk file "
             "carries its own stamp, so the chunks of this sweep are kept and resumed")


def open_store(store: Path, key: str, code: str, definition, n: int) -> tuple:
    """(chunk paths, results with the chunks already there loaded, the indices left to
    do) of a stored run of ``n`` chunks of the sweep of key ``key`` by code version
    ``code`` in the folder ``store`` (:func:`distkin.runstore.run_chunks`).

    A store whose ``sweep.json`` names another sweep or code version is refused; so is a
    chunk file whose stamp (:func:`chunk_stamp`) is not this sweep's chunk of that
    index, or that has none (QA S 1, 2: ``sweep.json`` alone let chunks copied from
    another sweep be loaded, or fail deep in the sweep on their shape).  Refused, not
    recomputed: the folder was filled by hand or by another sweep, and the user decides
    what to keep (docs/design.md, "Run store").  A file that cannot be read is redone,
    with a line on stderr, in a distkin store (its ``sweep.json`` names this sweep), and
    refused in any other folder (a user's file named like a chunk is never deleted).  A
    store in which no file can be made is refused here when chunks are left to compute
    (:func:`check_writable`), before any work."""
    meta = store / "sweep.json"
    if meta.exists():
        try:
            saved = json.loads(meta.read_text())
            if not isinstance(saved, dict):
                raise ValueError("not a JSON object")
        except (OSError, ValueError) as exc:   # JSONDecodeError and UnicodeError too
            raise InputError(f"expected a chunk store whose {meta.name} says which sweep "
                             f"made it, got an unreadable one in {str(store)!r} ({exc})",
                             field="store", hint=META_HINT) from None
        old = saved.get("key")
        if not isinstance(old, str):
            raise InputError(f"expected a chunk store whose {meta.name} says which sweep "
                             f"made it, got a {meta.name} in {str(store)!r} that is not a "
                             "store's metadata (no sweep key"
                             + (": a distkin --json result written there?" if "distkin"
                                in saved else "") + ")", field="store", hint=META_HINT)
        if old != key:
            raise InputError(f"expected a chunk store made for this sweep (key {key}), got "
                             f"one made for key {old} in {str(store)!r}", field="store",
                             hint="use another directory or delete the old chunks")
        if saved.get("code") != code:
            raise InputError(f"expected a chunk store made by this code (distkin {code}), "
                             f"got one made by {saved.get('code') or 'an older version'} in "
                             f"{str(store)!r}", field="store",
                             hint="use another directory or delete the old chunks")
    is_store = meta.exists()                             # and names this sweep (above)
    remove_stale_tmp(store)
    paths = [store / f"chunk_{i:05d}.npz" for i in range(n)]
    results: list = [None] * n
    todo, foreign, damaged = [], [], []
    for i, p in enumerate(paths):
        if p.exists():
            if not p.is_file():                          # QA 7: a folder was IsADirectoryError
                what = "a directory" if p.is_dir() else "no regular file"
                raise InputError(f"expected chunk {i} in {str(store)!r} to be a file "
                                 f"{p.name} (or none), got {what} at {str(p)!r}",
                                 field="store", hint="remove it (the chunk is computed "
                                 "again) or use another directory")
            try:
                results[i], stamp = load_chunk(p)
            except (OSError, ValueError, EOFError, KeyError, IndexError,
                    zipfile.BadZipFile) as exc:
                damaged.append((p, exc))                 # redone in a store, else refused
            else:
                why = stamp_mismatch(stamp, chunk_stamp(key, code, i, n))
                if why is None:
                    continue
                foreign.append(f"{p.name} ({why})")
        todo.append(i)
    if foreign:
        shown = "; ".join(foreign[:3]) + (f"; and {len(foreign) - 3} more"
                                          if len(foreign) > 3 else "")
        raise InputError(f"expected the chunk files in {str(store)!r} to be chunks of this "
                         f"sweep (key {key}, distkin {code}, {n} chunks), got "
                         f"{len(foreign)} that are not: {shown}", field="store",
                         hint="delete those chunk files (they are computed again) or use "
                              "another directory")
    if not is_store:                     # QA: a user's "chunk_00001.npz" was deleted
        refuse_damaged(store, damaged)
    if todo:                             # QA: a read-only store failed after the work
        check_writable(store, len(todo), n)
    redo_damaged(store, damaged)
    if not meta.exists():
        write_meta(meta, {"key": key, "code": code, "chunks": n, "definition": definition},
                   needed=bool(todo))
    return paths, results, todo
