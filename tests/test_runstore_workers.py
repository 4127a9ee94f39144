"""The local pool's workers (QA store24 3, 5).

* When the main process was SIGKILLed (the OOM killer) its two idle ``spawn_main``
  workers (~225 MB each) and the resource tracker were re-parented to PID 1 and idled
  forever.  Now they end with it.  Reference: the process table (``/proc``).
* A Ctrl-C (SIGINT to the whole process group) printed ``Process SpawnProcess-N:
  Traceback ... KeyboardInterrupt`` from idle workers.  Now idle workers end quietly, and
  a running chunk still stops.
* A SIGINT handled late by an idle worker (after its read of the call queue returned the
  header of the parent's shutdown sentinel) left the queue torn, and the next worker's
  read printed ``EOFError: Ran out of input`` (6 runs in 60, 13 with a busy core); a
  Ctrl-C while a worker started printed ``Fatal Python error: init_import_site ...
  KeyboardInterrupt`` (2 runs in 30).  Reference: no traceback on stderr."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="reads /proc, signals a process group")

_ENV = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}


def _alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie left to a PID 1 that does not reap is dead)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def _children(pid: int) -> list:
    out = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                stat = (d / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                out.append(int(d.name))
    return out


_KILLED = textwrap.dedent("""
    import os, sys, time
    from distkin.runstore import local_executor
    with local_executor(2) as ex:
        pids = {ex.submit(os.getpid).result() for _ in range(4)}
        a, b = ex.submit(time.sleep, 0.5), ex.submit(time.sleep, 0.5)
        a.result(); b.result()
        print("ready", flush=True)
        time.sleep(600)
""")


def _wait_gone(pids, limit=60.0):
    end = time.monotonic() + limit            # a deadline for a hang, not a timing assert
    while time.monotonic() < end and any(_alive(p) for p in pids):
        time.sleep(0.2)
    return [p for p in pids if _alive(p)]


def test_workers_and_the_resource_tracker_end_when_the_main_process_is_killed():
    main = subprocess.Popen([sys.executable, "-c", _KILLED], stdout=subprocess.PIPE,
                            text=True, env=_ENV)
    try:
        assert main.stdout.readline().strip() == "ready"
        children = _children(main.pid)
        assert len(children) >= 2                 # two workers (and the resource tracker)
        os.kill(main.pid, signal.SIGKILL)
        main.wait()
        left = _wait_gone(children)
        assert left == [], f"orphaned: {left}"
    finally:
        if main.poll() is None:
            main.kill()


def test_the_fallback_watcher_ends_a_process_whose_parent_died():
    """Without prctl (not Linux) a thread watches ``os.getppid()``: a grandchild running
    only the watcher ends when its parent is killed.  The parent's pid is read before the
    grandchild says it is ready (as ``local_executor`` passes it from the parent): read
    after, a parent killed in between was never seen (a loaded machine, full suite)."""
    parent = textwrap.dedent("""
        import subprocess, sys, time
        child = subprocess.Popen([sys.executable, "-c",
            "import os, sys, time; from distkin.runstore import _watch_parent; "
            "ppid = os.getppid(); print(os.getpid(), flush=True); _watch_parent(ppid, 0.05)"],
            stdout=sys.stdout)
        child.wait()                                  # ends at once if the child fails
    """)
    p = subprocess.Popen([sys.executable, "-c", parent], stdout=subprocess.PIPE, text=True,
                         env=_ENV)
    try:
        grandchild = int(p.stdout.readline())
        assert _alive(grandchild)
        p.kill()
        p.wait()
        assert _wait_gone([grandchild]) == []
    finally:
        if p.poll() is None:
            p.kill()


_INTERRUPTED = textwrap.dedent("""
    import os, sys, time
    from distkin.runstore import local_executor
    with local_executor(2) as ex:
        two = [ex.submit(time.sleep, 0.5) for _ in range(2)]      # two workers start
        for f in two:
            f.result()
        busy = ex.submit(time.sleep, 600)   # one runs a chunk, the other one is idle
        while not busy.running():
            time.sleep(0.05)
        time.sleep(1.0)                               # started in the worker, not queued
        try:
            print("ready", flush=True)
            time.sleep(600)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
        # the running chunk stopped (else a TimeoutError after 100 s): its own
        # KeyboardInterrupt, or the pool ended by the idle worker's exit
        stop = type(busy.exception(timeout=100)).__name__
        print("stopped" if stop in ("KeyboardInterrupt", "BrokenProcessPool") else stop,
              flush=True)
""")


def test_ctrl_c_prints_no_traceback_from_idle_workers_and_stops_running_chunks():
    p = subprocess.Popen([sys.executable, "-c", _INTERRUPTED], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=_ENV,
                         start_new_session=True)
    try:
        assert p.stdout.readline().strip() == "ready"
        os.killpg(p.pid, signal.SIGINT)               # what a terminal's Ctrl-C does
        out, err = p.communicate(timeout=120)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
    assert out.split() == ["interrupted", "stopped"], out + err
    assert "KeyboardInterrupt" not in err, err
    assert "Traceback" not in err, err           # EOFError: Ran out of input (1 run in ~8)


def _late_sigint(meet: str) -> int:
    """A task that makes this pool worker handle its SIGINTs late, as a loaded machine
    can: a thread takes them (it waits forever) while the main thread blocks them, so
    the handler runs when the main thread next runs Python (after a blocking read
    returned).  Returns this worker's pid once two workers ran it (files in ``meet``)."""
    threading.Thread(target=threading.Event().wait, daemon=True).start()
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    Path(meet, str(os.getpid())).touch()
    end = time.monotonic() + 60                  # a deadline for a hang, not a timing
    while len(os.listdir(meet)) < 2 and time.monotonic() < end:
        time.sleep(0.01)
    return os.getpid()


def _until_interrupted() -> None:
    print("started", flush=True)
    while True:
        time.sleep(0.01)


_LATE = textwrap.dedent("""
    import sys
    from distkin.runstore import local_executor
    from test_runstore_workers import _late_sigint, _until_interrupted
    with local_executor(2) as ex:
        print(*{f.result() for f in [ex.submit(_late_sigint, sys.argv[1]) for _ in "ab"]},
              flush=True)
        busy = ex.submit(_until_interrupted)   # one worker runs it, the other one waits
        print(type(busy.exception(timeout=100)).__name__, flush=True)
""")


@pytest.mark.skipif(not hasattr(signal, "pthread_sigmask"), reason="no signal masks")
def test_an_idle_worker_s_late_sigint_leaves_the_call_queue_whole(tmp_path):
    """Both workers handle their SIGINT late (:func:`_late_sigint`); the idle one waits
    for work.  The running chunk stops, and the pool's shutdown ends both workers
    without a traceback: the idle one used to exit with the header of the shutdown's
    sentinel read, and the other one read its body as a header (``EOFError``, every
    run)."""
    p = subprocess.Popen([sys.executable, "-c", _LATE, str(tmp_path)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=_ENV)
    try:
        pids = [int(w) for w in p.stdout.readline().split()]
        assert len(pids) == 2 and p.stdout.readline().strip() == "started"
        time.sleep(0.3)     # the idle worker back in its read (not a timing assertion: a
        for pid in pids:    # SIGINT before that comes while it is busy, and is deferred)
            os.kill(pid, signal.SIGINT)
        out, err = p.communicate(timeout=120)
    finally:
        if p.poll() is None:
            p.kill()
    assert out.split() == ["KeyboardInterrupt"], out + err
    assert "Traceback" not in err, err


_STARTING = textwrap.dedent("""
    import time
    from distkin.runstore import local_executor
    with local_executor(1) as ex:
        try:                      # the Ctrl-C can come before submit returns
            ex.submit(time.sleep, 0)                      # the worker starts
            while True:
                time.sleep(0.01)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
""")

#: a ``sitecustomize`` that holds a pool worker in Python's start-up until a file exists
_SITE = textwrap.dedent("""
    import os, sys, time
    if "--multiprocessing-fork" in sys.argv:
        print("starting", flush=True)
        end = time.monotonic() + 60
        while not os.path.exists(os.environ["DISTKIN_TEST_GO"]) and time.monotonic() < end:
            time.sleep(0.01)
""")


def test_ctrl_c_while_a_worker_starts_prints_no_traceback(tmp_path):
    """A Ctrl-C while a worker is still in Python's start-up (its ``site`` import, held
    there by a ``sitecustomize``): the worker ends quietly once started; it printed
    ``Fatal Python error: init_import_site ... KeyboardInterrupt``."""
    (tmp_path / "sitecustomize.py").write_text(_SITE)
    go = tmp_path / "go"
    env = {**_ENV, "PYTHONPATH": os.pathsep.join([str(tmp_path), _ENV["PYTHONPATH"]]),
           "DISTKIN_TEST_GO": str(go)}
    p = subprocess.Popen([sys.executable, "-c", _STARTING], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=env, start_new_session=True)
    try:
        assert p.stdout.readline().strip() == "starting"
        os.killpg(p.pid, signal.SIGINT)               # what a terminal's Ctrl-C does
        go.touch()
        out, err = p.communicate(timeout=120)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
    assert out.split() == ["interrupted"], out + err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err


def _marked_sleep(folder: str, i: int, seconds: float) -> None:
    """Chunk ``i``: a file ``i-PID`` in ``folder`` when it starts, then a sleep."""
    Path(folder, f"{i}-{os.getpid()}").touch()
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        time.sleep(0.01)


def test_a_worker_whose_chunk_was_interrupted_starts_no_other(tmp_path):
    """Both workers of a pool of 2 get a SIGINT in their chunks (as from a Ctrl-C, or
    the CLI's SIGTERM handler): the chunks already in the call queue (which the parent
    cannot cancel) start on no worker and fail with the broken pool.  Each worker took
    one and ran it to its end (reference: the chunks' start files)."""
    from concurrent.futures.process import BrokenProcessPool

    from distkin.runstore import local_executor
    with local_executor(2) as ex:
        fs = [ex.submit(_marked_sleep, str(tmp_path), i, 60 if i < 2 else 0.2)
              for i in range(5)]
        end = time.monotonic() + 60           # a deadline for a hang, not a timing
        while len(list(tmp_path.iterdir())) < 2 and time.monotonic() < end:
            time.sleep(0.01)
        for mark in tmp_path.iterdir():
            os.kill(int(mark.name.split("-")[1]), signal.SIGINT)
        got = [type(f.exception(timeout=100)) for f in fs]
    assert got == [KeyboardInterrupt] * 2 + [BrokenProcessPool] * 3
    assert sorted(m.name.split("-")[0] for m in tmp_path.iterdir()) == ["0", "1"]


def test_the_call_queue_reader_reads_only_the_queues_it_knows():
    """:class:`distkin.runstore._CallQueue` reads CPython's private Queue internals
    (3.11-3.13); on a queue without them the worker keeps the queue's own ``get``
    instead of failing at its first read."""
    import multiprocessing
    from distkin.runstore import _CallQueue
    q = multiprocessing.get_context("spawn").Queue()
    try:
        assert _CallQueue.can_read(q)
        assert all(hasattr(q, name) for name in _CallQueue.INTERNALS)
        del q._sem                               # as a Python that renamed it
        assert not _CallQueue.can_read(q)
    finally:
        q._reader.close()
        q._writer.close()
    assert not _CallQueue.can_read(object())


_START_INTERRUPTED = textwrap.dedent("""
    import concurrent.futures.process as cfp
    import time
    from distkin.runstore import local_executor

    def interrupted_start(self):       # the signal, inside the pool's own Thread.start
        time.sleep(0.3)                # the worker spawned meanwhile is starting up
        raise KeyboardInterrupt
    cfp._ExecutorManagerThread.start = interrupted_start
    try:
        with local_executor(1) as ex:
            ex.submit(int, 1)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
    time.sleep(3)                      # a worker left starting would print by now
""")


def test_a_ctrl_c_inside_the_pools_thread_start_stays_a_keyboard_interrupt():
    """A Ctrl-C that lands in the pool's own ``Thread.start`` (its manager thread made,
    not started) made ``shutdown``'s join raise "cannot join thread before it is
    started" in place of the KeyboardInterrupt: exit 1 and a traceback instead of exit
    130 (QA 25b); and a worker still unpickling its start-up data when the pool went
    printed ``FileNotFoundError`` from ``SemLock._rebuild``.  Reproduced by a start that
    raises KeyboardInterrupt, as the signal did: the interrupt comes out, no process
    prints a traceback."""
    p = subprocess.run([sys.executable, "-c", _START_INTERRUPTED], capture_output=True,
                       text=True, env=_ENV, timeout=120)
    assert p.stdout.split() == ["interrupted"], p.stdout + p.stderr
    assert "Traceback" not in p.stderr and "Error" not in p.stderr, p.stderr
