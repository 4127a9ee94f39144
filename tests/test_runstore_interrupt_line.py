"""An interrupted chunked run says that it waits for its running chunks (the pool's
shutdown waits for them: ~18 s for certify_hexa's, silently, QA) -- and only then."""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor

import pytest

from distkin import runstore


def _interrupt_first_wait(monkeypatch, started):
    def wait(executor, pending, store, timeout):
        started.wait(5)                 # a chunk is running when the interrupt comes
        raise KeyboardInterrupt
    monkeypatch.setattr(runstore, "_wait_alive", wait)


def test_the_running_chunks_are_said(monkeypatch, capsys):
    started, release = threading.Event(), threading.Event()

    def task(spec):
        started.set()
        release.wait(5)
        return spec

    _interrupt_first_wait(monkeypatch, started)
    with ThreadPoolExecutor(max_workers=1) as ex:
        with pytest.raises(KeyboardInterrupt):
            runstore.run_chunks(task, [1, 2, 3], None, executor=ex, progress=False)
        release.set()
    err = capsys.readouterr().err
    assert "interrupted: waiting for 1 running chunk(s) to stop" in err


def test_no_line_when_nothing_runs(monkeypatch, capsys):
    started = threading.Event()
    started.set()

    class Idle:                         # an executor whose futures never start
        _max_workers = 1

        def submit(self, fn, *a):
            from concurrent.futures import Future
            return Future()

    _interrupt_first_wait(monkeypatch, started)
    with pytest.raises(KeyboardInterrupt):
        runstore.run_chunks(lambda s: s, [1, 2], None, executor=Idle(), progress=False)
    assert "waiting for" not in capsys.readouterr().err


def test_finished_chunks_are_not_counted_as_running(monkeypatch, capsys):
    """Futures already done are not running (review: cancel() is False for them too, so
    two finished chunks were said to be running)."""
    import time

    def wait(executor, pending, store, timeout):
        time.sleep(0.3)                 # both chunks finish meanwhile
        raise KeyboardInterrupt
    monkeypatch.setattr(runstore, "_wait_alive", wait)
    with ThreadPoolExecutor(max_workers=2) as ex:
        with pytest.raises(KeyboardInterrupt):
            runstore.run_chunks(lambda s: s, [1, 2], None, executor=ex, progress=False)
    assert "waiting for" not in capsys.readouterr().err
