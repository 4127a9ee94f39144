"""What a run store holds besides chunk files (QA 7): a directory where a chunk file
should be ended in "distkin: error: IsADirectoryError" (exit 1, from the cleanup's
``unlink``); the temporary files of a killed process's saves were never removed and
were counted as finished chunks.  Reference: the chunks a run actually wrote."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from concurrent.futures import Future
from pathlib import Path

import numpy as np
import pytest

from distkin import runstore
from distkin.errors import DistkinError, InputError
from distkin.runstore import run_chunks


def _square(spec):
    return {"y": np.arange(spec) ** 2}


def _dead_pid() -> int:
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def test_a_directory_for_a_chunk_file_is_an_input_error_naming_it(tmp_path):
    store = tmp_path / "s"
    run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    chunk = store / "chunk_00001.npz"
    chunk.unlink()
    chunk.mkdir()
    with pytest.raises(InputError) as exc:
        run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    assert exc.value.field == "store"
    assert str(chunk) in exc.value.message and "directory" in exc.value.message
    assert chunk.is_dir()                                # refused, not removed


def test_the_cli_exits_2_on_it(tmp_path, capsys):
    """The QA reproduction through ``distkin sweep`` (exit 2, one line, no traceback)."""
    from distkin.app.cli import main
    from test_runstore import _CERT
    scene = tmp_path / "c.toml"
    scene.write_text(_CERT.format(x=10), encoding="utf-8")
    store = tmp_path / "st"
    assert main(["sweep", str(scene), "--no-progress", "--store", str(store)]) == 0
    chunk = sorted(store.rglob("chunk_*.npz"))[0]
    chunk.unlink()
    chunk.mkdir()
    capsys.readouterr()
    assert main(["sweep", str(scene), "--no-progress", "--store", str(store)]) == 2
    err = capsys.readouterr().err
    assert "IsADirectoryError" not in err and chunk.name in err and "Traceback" not in err


def test_a_damaged_chunk_that_cannot_be_removed_is_an_input_error(tmp_path, monkeypatch):
    store = tmp_path / "s"
    run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    chunk = store / "chunk_00000.npz"
    chunk.write_bytes(b"not a zip file")
    real = Path.unlink

    def unlink(self, *a, **k):
        if self == chunk:
            raise PermissionError(13, "Permission denied")
        return real(self, *a, **k)
    monkeypatch.setattr(Path, "unlink", unlink)
    with pytest.raises(InputError, match="chunk_00000") as exc:
        run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    assert exc.value.field == "store"


def test_stale_temporary_files_are_removed_and_never_counted(tmp_path):
    store = tmp_path / "s"
    run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    kept = sorted(p.name for p in store.glob("chunk_*.npz"))
    old = time.time() - 3600
    dead = store / f"chunk_00001.npz.{_dead_pid()}.tmp.npz"
    live = store / f"chunk_00001.npz.{os.getppid()}.tmp.npz"      # a running process
    fresh = store / f"chunk_00000.npz.{_dead_pid()}.tmp.npz"     # too recent to judge
    for p in (dead, live, fresh):
        p.write_bytes(b"partial")
    for p in (dead, live):
        os.utime(p, (old, old))
    assert [p.name for p in runstore.finished_chunks(store)] == kept
    run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    assert not dead.exists() and live.exists() and fresh.exists()


def test_the_dead_cluster_message_counts_finished_chunks_only(tmp_path, monkeypatch):
    """_wait_alive's "N finished chunks are kept": the chunks written, not temp files."""
    store = tmp_path / "s"
    run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    written = len(list(store.glob("chunk_?????.npz")))
    (store / f"chunk_00002.npz.{os.getpid()}.tmp.npz").write_bytes(b"partial")
    monkeypatch.setattr(runstore, "_HEALTH_POLL_S", 0.01)

    class NoWorkers:
        address = "tcp://nowhere:8786"

        def workers(self):
            return 0
    with pytest.raises(DistkinError) as exc:
        runstore._wait_alive(NoWorkers(), {Future()}, store, 0.05)
    assert f"the {written} finished chunks are kept" in exc.value.message


def test_another_hosts_temporary_file_is_judged_by_age_only(tmp_path):
    """Review: on a store shared between hosts a PID means nothing on another host, so
    a temporary file of another host's writer (a dead PID here, an hour old) is kept;
    the same name of this host is removed; any older than a day goes."""
    store = tmp_path / "s"
    run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    pid = _dead_pid()
    other = store / f"chunk_00001.npz.otherhost@{pid}.tmp.npz"
    mine = store / f"chunk_00001.npz.{runstore._HOST}@{pid}.tmp.npz"
    ancient = store / f"chunk_00000.npz.otherhost@{pid}.tmp.npz"
    for p, age in ((other, 3600), (mine, 3600), (ancient, 2 * 86400)):
        p.write_bytes(b"partial")
        os.utime(p, (time.time() - age, time.time() - age))
    run_chunks(_square, [2, 3], store, definition={"n": 2}, progress=False)
    assert other.exists() and not mine.exists() and not ancient.exists()


def test_a_save_names_its_host_and_process(tmp_path, monkeypatch):
    """The temporary name a save writes carries this host and PID (what the cleanup
    reads back)."""
    seen = []
    real = os.replace

    def spy(src, dst):
        seen.append(Path(src).name)
        return real(src, dst)

    monkeypatch.setattr(os, "replace", spy)
    run_chunks(_square, [2], tmp_path / "s", definition={"n": 1}, progress=False)
    tag = f"{runstore._HOST}@{os.getpid()}"
    assert seen and all(tag in n and runstore._TMP_RE.fullmatch(n) for n in seen), seen
