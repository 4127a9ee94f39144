"""A run store that cannot be written, and files in it distkin cannot read (QA store24
2, 4, 6).

* A full disk ended a sweep as an internal error (exit 1, ``OSError: [Errno 28]``)
  after the work, leaving ``chunk_NNNNN.npz.HOST@PID.tmp.npz``; a read-only store
  computed its missing chunks, then failed (``[Errno 30]``, exit 1).  Now: an
  InputError (exit 2) naming the store and the cause, no temporary file left, the
  chunks saved before kept for a resume; a store that cannot be written is refused
  before any work when chunks are left to compute.
* A file named like a chunk that distkin cannot read was deleted silently, even in a
  folder that is not a distkin store (a user's ``chunk_00001.npz``): now refused there,
  naming it; in a store it is computed again, with a line on stderr.
* An unreadable ``sweep.json`` said "delete the folder", though only it need go.

References: the file system's state (what is in the folder, a file's bytes), a fresh
run's numbers."""

from __future__ import annotations

import errno
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.runstore import finished_chunks, run_chunks

DEF = {"n": 4}


def _square(spec):
    return {"y": np.arange(spec) ** 2}


def _listing(folder) -> list:
    return sorted(p.name for p in Path(folder).iterdir())


def _same(a, b):
    return [r["y"].tolist() for r in a] == [r["y"].tolist() for r in b]


def test_a_full_disk_while_saving_names_the_store_and_leaves_no_temporary_file(
        tmp_path, monkeypatch):
    store = tmp_path / "s"
    real, calls = np.savez, []

    def savez(file, **arrays):                 # the third save finds the disk full
        calls.append(file)
        if len(calls) == 3:
            Path(file).write_bytes(b"PK half a zip")
            raise OSError(errno.ENOSPC, "No space left on device")
        return real(file, **arrays)
    monkeypatch.setattr(np, "savez", savez)
    with pytest.raises(InputError) as exc:
        run_chunks(_square, [2, 3, 4, 5], store, definition=DEF, progress=False)
    assert exc.value.field == "store"
    assert "disk full" in exc.value.message and str(store) in exc.value.message
    assert _listing(store) == ["chunk_00000.npz", "chunk_00001.npz", "sweep.json"]
    monkeypatch.setattr(np, "savez", real)
    stats: dict = {}
    again = run_chunks(_square, [2, 3, 4, 5], store, definition=DEF, progress=False,
                       stats=stats)
    assert stats["loaded"] == 2                    # the chunks saved before were kept
    assert _same(again, run_chunks(_square, [2, 3, 4, 5], None, progress=False))


def _big(spec):
    return {"y": np.arange(spec * 5000, dtype=float)}


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0
                    or not sys.platform.startswith("linux"),
                    reason="mounts a 200 KiB tmpfs (root on Linux)")
def test_a_real_full_disk(tmp_path):
    """The QA reproduction: a store on a 200 KiB tmpfs (each chunk 40 KB)."""
    store = tmp_path / "tiny"
    store.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=200k", "tmpfs", str(store)],
                      capture_output=True).returncode != 0:
        pytest.skip("cannot mount a tmpfs here")
    try:
        specs = [1] * 8
        with pytest.raises(InputError, match="disk full") as exc:
            run_chunks(_big, specs, store, definition={"big": 8}, progress=False)
        assert str(store) in exc.value.message
        names = _listing(store)
        assert not [n for n in names if ".tmp" in n], names
        saved = len(finished_chunks(store))
        assert 0 < saved < 8
        (store / "chunk_00000.npz").unlink()      # room for one more, not for all
        with pytest.raises(InputError, match="disk full"):
            run_chunks(_big, specs, store, definition={"big": 8}, progress=False)
        assert not [n for n in _listing(store) if ".tmp" in n]
    finally:
        subprocess.run(["umount", str(store)], check=True)


_RO_SCRIPT = textwrap.dedent("""
    import sys
    import numpy as np
    from pathlib import Path
    from distkin.runstore import finished_chunks, run_chunks
    marker = Path(sys.argv[2])

    def task(spec):
        marker.write_text("computed")
        return {"y": np.arange(spec) ** 2}

    try:
        out = run_chunks(task, [2, 3, 4, 5], sys.argv[1], definition={"n": 4},
                         progress=False)
        print("OK", [r["y"].tolist() for r in out])
    except Exception as exc:
        print(type(exc).__name__, exc)
""")


def _unprivileged(cmd):
    """``cmd`` run without the capabilities that let root write anywhere."""
    if os.geteuid() != 0:
        return cmd
    if shutil.which("setpriv") is None:
        pytest.skip("root without setpriv: cannot drop the override capabilities")
    caps = "-dac_override,-dac_read_search,-fowner"
    return ["setpriv", "--bounding-set", caps, "--inh-caps", caps] + cmd


@pytest.mark.skipif(not hasattr(os, "geteuid"), reason="POSIX permissions")
@pytest.mark.parametrize("case", ["partial", "empty", "damaged"])
def test_a_read_only_store_with_work_left_is_refused_before_any_work(tmp_path, case):
    store = tmp_path / "ro"
    full = run_chunks(_square, [2, 3, 4, 5], store, definition=DEF, progress=False)
    if case == "partial":
        (store / "chunk_00002.npz").unlink()
    elif case == "empty":
        shutil.rmtree(store)
        store.mkdir()
    else:
        (store / "chunk_00001.npz").write_bytes(b"damaged")
    before = {p.name: p.read_bytes() for p in store.iterdir()}
    marker = tmp_path / "computed"
    store.chmod(0o555)
    try:
        out = subprocess.run(_unprivileged([sys.executable, "-c", _RO_SCRIPT, str(store),
                                            str(marker)]),
                             capture_output=True, text=True, timeout=300,
                             env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    finally:
        store.chmod(0o755)
    assert out.stdout.startswith("InputError"), out.stdout + out.stderr
    assert "not writable" in out.stdout and str(store) in out.stdout
    assert not marker.exists()                            # refused before any work
    assert {p.name: p.read_bytes() for p in store.iterdir()} == before
    assert full                                           # (the reference run)


def test_a_read_only_store_that_holds_every_chunk_is_read(tmp_path):
    store = tmp_path / "ro"
    full = run_chunks(_square, [2, 3, 4, 5], store, definition=DEF, progress=False)
    (store / "sweep.json").unlink()            # not even sweep.json need be written
    store.chmod(0o555)
    try:
        out = subprocess.run(_unprivileged([sys.executable, "-c", _RO_SCRIPT, str(store),
                                            str(tmp_path / "computed")]),
                             capture_output=True, text=True, timeout=300,
                             env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    finally:
        store.chmod(0o755)
    assert out.stdout.strip() == f"OK {[r['y'].tolist() for r in full]}", out.stderr
    assert not (tmp_path / "computed").exists()


def test_a_file_named_like_a_chunk_in_a_folder_that_is_no_store_is_kept(tmp_path):
    """QA: ``echo notes > userdir/chunk_00001.npz`` was replaced, rc 0, no message."""
    userdir = tmp_path / "userdir"
    userdir.mkdir()
    notes = userdir / "chunk_00001.npz"
    notes.write_text("notes\n")
    with pytest.raises(InputError) as exc:
        run_chunks(_square, [2, 3, 4, 5], userdir, definition=DEF, progress=False)
    assert exc.value.field == "store" and "chunk_00001.npz" in exc.value.message
    assert "not a distkin store" in exc.value.message
    assert notes.read_text() == "notes\n" and _listing(userdir) == ["chunk_00001.npz"]


def test_a_damaged_chunk_in_a_store_is_computed_again_and_said(tmp_path, capsys):
    store = tmp_path / "s"
    ref = run_chunks(_square, [2, 3, 4, 5], store, definition=DEF, progress=False)
    for i in (1, 3):
        (store / f"chunk_{i:05d}.npz").write_bytes(b"garbage")
    capsys.readouterr()
    stats: dict = {}
    again = run_chunks(_square, [2, 3, 4, 5], store, definition=DEF, progress=False,
                       stats=stats)
    err = capsys.readouterr().err.strip().splitlines()
    assert _same(again, ref) and stats["loaded"] == 2
    assert len(err) == 1 and "chunk_00001.npz" in err[0] and "chunk_00003.npz" in err[0]
    assert str(store) in err[0] and "computed again" in err[0]


@pytest.mark.parametrize("text", ["", "{not json", "[1, 2]"])
def test_an_unreadable_sweep_json_hints_to_delete_only_it(tmp_path, text):
    store = tmp_path / "s"
    ref = run_chunks(_square, [2, 3, 4, 5], store, definition=DEF, progress=False)
    (store / "sweep.json").write_text(text)
    with pytest.raises(InputError) as exc:
        run_chunks(_square, [2, 3, 4, 5], store, definition=DEF, progress=False)
    assert "delete only its sweep.json" in (exc.value.hint or "")
    assert "delete the folder" not in str(exc.value)
    (store / "sweep.json").unlink()            # what the hint says: the chunks resume
    stats: dict = {}
    again = run_chunks(_square, [2, 3, 4, 5], store, definition=DEF, progress=False,
                       stats=stats)
    assert stats["loaded"] == 4 and _same(again, ref)
