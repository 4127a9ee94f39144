"""The run store: chunked, resumable sweeps on any ``concurrent.futures``-style executor.

Used by the performance-index studies and design sweeps (:mod:`distkin.indices`) and by
the certified workspace (:mod:`distkin.certify.workspace`).

A sweep is a list of independent chunks (picklable specs) and a module-level task
function ``task(spec) -> dict of numpy arrays``.  :func:`run_chunks`

* stores every finished chunk at once as ``DIR/chunk_NNNNN.npz`` (written to a
  temporary name, then renamed, so a file on disk is always complete; the temporary
  files a killed process left are removed when the store is opened again);
* skips the chunks already on disk, so a sweep interrupted by Ctrl-C (or a crash)
  continues from where it stopped; ``DIR/sweep.json`` holds a key of the sweep's
  definition and refuses to mix chunks of a different sweep, and every chunk file carries
  that key, the code version, its index and the number of chunks, checked when it is
  loaded (a chunk copied in from another sweep is refused with a hint);
* runs on the executor given (anything with ``submit`` returning futures), by default a
  local process pool with ``OPENBLAS_NUM_THREADS=1`` (and the OMP/MKL equivalents) in
  its workers (docs/design.md §6: two processes each running a threaded BLAS on two cores
  were slower than one);
* with a ``dask.distributed`` scheduler address (``scheduler="tcp://host:8786"``,
  optional extra ``distributed``) runs the same chunks on that cluster, through
  ``Client.get_executor()``; a cluster left without workers for
  :data:`NO_WORKER_TIMEOUT_S` ends the sweep with a clear error instead of a wait that
  never ends (the finished chunks stay on disk);
* shows a progress bar with the ETA (rich) on the terminal (stderr, so that
  ``--json -`` keeps stdout clean).

Chunks are keyed by the **code version** as well as by the sweep's definition
(:func:`code_version`: the package version and a hash of the package's source), so
chunks computed by other code are never mixed in: the default store of a query
(:func:`default_store`, under the user cache) is a folder per code version, with a
sub-folder per sweep definition (:func:`keyed_store`: an edited scene, or another scene
of the same file name, starts its own store), and a store given by the user that holds
another version's or another sweep's chunks is refused with a hint.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import multiprocessing
import multiprocessing.context
import multiprocessing.queues
import os
import signal
import sys
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from multiprocessing.reduction import ForkingPickler
from pathlib import Path

from ._version import __version__
from .chunkfiles import HOST as _HOST, TMP_RE as _TMP_RE  # noqa: F401 (tests read them)
from .chunkfiles import (chunk_stamp as _chunk_stamp, finished_chunks, open_store,
                         save_chunk as _save)
from .errors import DistkinError, InputError
from .progress import ChunkProgress

__all__ = ["run_chunks", "check_store", "make_store", "local_executor", "dask_executor",
           "executor_for", "sweep_key", "code_version", "user_cache_dir", "default_store",
           "keyed_store", "ChunkProgress", "WORKER_ENV", "NO_WORKER_TIMEOUT_S",
           "finished_chunks"]

#: worker counts already warned about (above the CPU count), once per process
_WARNED: set = set()
#: environment of the local pool's workers (single-threaded BLAS)
WORKER_ENV = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
#: a dask cluster without a single worker for this long (s) ends the sweep
NO_WORKER_TIMEOUT_S = 60.0
#: how often (s) a sweep waiting on a cluster checks that it still has workers
_HEALTH_POLL_S = 2.0
#: how often (s) a worker without prctl (not Linux) checks that its parent still runs
_PARENT_POLL_S = 1.0
#: what a local pool's worker does, for its SIGINT handler (:func:`_worker_sigint`):
#: "task" (runs one), "idle" (waits for one, or unpickles it) or "busy" (starts, reads
#: a message off the call queue, sends a result back)
_STATE = "busy"
#: a SIGINT came: the worker ends before its next task
_EXIT = False
#: held while a worker process starts with :data:`WORKER_ENV` set in this process
_START_LOCK = threading.Lock()


def user_cache_dir() -> Path:
    """The distkin cache folder: ``$DISTKIN_CACHE`` if set, else
    ``$XDG_CACHE_HOME/distkin``, else ``~/.cache/distkin`` (not created here)."""
    if os.environ.get("DISTKIN_CACHE"):
        return Path(os.environ["DISTKIN_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "distkin"


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """``VERSION-HASH``: the package version and the first 12 hex digits of a SHA-256 of
    every ``.py`` file of the installed package (paths and contents, sorted), so any
    change of the code (an edit between releases too) gives another version."""
    root = Path(__file__).resolve().parent
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        if "__pycache__" in path.parts:
            continue
        h.update(path.relative_to(root).as_posix().encode())
        h.update(b"\x00")
        h.update(path.read_bytes())
        h.update(b"\x00")
    return f"{__version__}-{h.hexdigest()[:12]}"


def _default_root() -> Path:
    return user_cache_dir() / "sweeps" / code_version()


def default_store(name: str) -> Path:
    """Where a query keeps its chunks when the scene names no ``store``:
    ``user_cache_dir()/sweeps/<code_version()>/<name>`` (one folder per code version, so
    chunks left by another version are neither reused nor in the way).  :func:`run_chunks`
    keeps a sweep's chunks in a sub-folder named by the key of the sweep's definition
    (:func:`keyed_store`), so a changed sweep under the same name starts a new store and
    an unchanged one resumes."""
    return _default_root() / name


def keyed_store(store, key: str) -> Path:
    """The folder :func:`run_chunks` uses for a sweep of key ``key`` in ``store``: below
    the default stores (:func:`default_store`), ``store/key`` (unless ``store`` already
    ends in it: the studies key their stores themselves); a store the user named, as it
    is (a different sweep there is refused with a hint)."""
    store = Path(store)
    if store.name == key:
        return store
    try:
        store.resolve().relative_to(_default_root().resolve())
    except ValueError:
        return store
    return store / key


def sweep_key(definition) -> str:
    """A short stable hash of a sweep's definition (JSON-able)."""
    text = json.dumps(definition, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


@contextlib.contextmanager
def local_executor(workers: int | None = None):
    """A process pool whose workers start with :data:`WORKER_ENV` (spawned, so the
    setting reaches BLAS before numpy loads; set as each one starts,
    :class:`_WorkerProcess`).  ``workers`` defaults to the CPU count; more than
    :data:`~distkin.argcheck.MAX_WORKERS` is refused, more than the CPU count warned
    about (one line on stderr).  Processes start as chunks are submitted, and
    :func:`run_chunks` submits at most as many as it has chunks, so the pool never runs
    more processes than chunks.

    The workers end with this process, even when it is killed (SIGKILL, the OOM
    killer; QA: idle workers of 225 MB each were left to PID 1): Linux's
    ``PR_SET_PDEATHSIG``, elsewhere a thread that watches the parent
    (:func:`_worker_start`).  A Ctrl-C stops the chunks they run (and their workers: no
    chunk already queued starts) and ends the idle workers and those still starting,
    without a traceback (:func:`_worker_sigint`, :class:`_WorkerProcess`,
    :class:`_CallQueue`)."""
    from .argcheck import workers_count
    cpus = os.cpu_count() or 1
    if workers is not None:
        workers_count(workers, "workers")
        if workers > cpus and workers not in _WARNED:
            _WARNED.add(workers)
            print(f"distkin: warning: {workers} worker processes on {cpus} CPUs: the extra "
                  "processes share them (more memory, no speed-up)", file=sys.stderr,
                  flush=True)
    ex = _LocalPool(max_workers=workers or cpus, mp_context=_WorkerContext(),
                    initializer=_worker_start, initargs=(os.getpid(),))
    try:
        yield ex
    except BaseException:
        # the workers end now, quietly: one still unpickling its start-up data when the
        # queues' semaphores go printed "FileNotFoundError ... SemLock._rebuild" after
        # a Ctrl-C at the pool's start (QA 25b: 6 runs in 56); the chunks that ran are
        # stopped already (their SIGINT) and the finished ones saved by this process
        for proc in list((getattr(ex, "_processes", None) or {}).values()):
            try:
                proc.kill()
            except (OSError, ValueError, AttributeError):
                pass
        try:
            ex.shutdown(wait=True, cancel_futures=True)
        except RuntimeError:
            # a Ctrl-C inside the pool's own Thread.start (its manager thread made, not
            # started): shutdown's join raised "cannot join thread before it is
            # started" in place of the KeyboardInterrupt, exit 1 with a traceback (QA
            # 25b, 1 run in ~70); the workers end with this process (PR_SET_PDEATHSIG)
            ex.shutdown(wait=False, cancel_futures=True)
        raise
    ex.shutdown(wait=True, cancel_futures=True)


class _LocalPool(ProcessPoolExecutor):
    """The local pool: every task runs inside :class:`_Task`, which tells the worker's
    SIGINT handler whether a task runs (:func:`_worker_sigint`)."""

    def submit(self, fn, /, *args, **kwargs):
        return super().submit(_Task(fn), *args, **kwargs)


class _WorkerProcess(multiprocessing.context.SpawnProcess):
    """A local pool's worker process.

    Spawned with :data:`WORKER_ENV` in its environment, set in this process while it
    starts (set around the pool's creation, it reached no worker: a pool starts them at
    a submit), and with SIGINT blocked (the mask of the thread that starts it), which
    :meth:`run` unblocks once :func:`_worker_sigint` handles it.  A Ctrl-C while the
    worker started (Python's start-up, the imports of unpickling) printed ``Fatal Python
    error: init_import_site ... KeyboardInterrupt`` (2 runs in 30 of a Ctrl-C at the
    pool's start); now it is held until then, and the worker ends before its first task.
    CPython starts its resource tracker so too; the threads started meanwhile keep
    SIGINT blocked, so it reaches the main thread.  Its ``_process_worker`` reads the
    call queue through :class:`_CallQueue` (a queue of another kind, from another
    Python's internals, is read as it is)."""

    def start(self):
        sigmask = getattr(signal, "pthread_sigmask", None)      # None on Windows
        with _START_LOCK:
            saved = {k: os.environ.get(k) for k in WORKER_ENV}
            os.environ.update(WORKER_ENV)
            mask = sigmask and sigmask(signal.SIG_BLOCK, {signal.SIGINT})
            try:
                super().start()
            finally:
                if sigmask:
                    sigmask(signal.SIG_SETMASK, mask)
                for k, v in saved.items():
                    if v is None:
                        os.environ.pop(k, None)
                    else:
                        os.environ[k] = v

    def run(self):
        signal.signal(signal.SIGINT, _worker_sigint)
        if hasattr(signal, "pthread_sigmask"):      # a Ctrl-C while starting: _EXIT
            signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
        if self._args and _CallQueue.can_read(self._args[0]):
            self._args = (_CallQueue(self._args[0]), *self._args[1:])  # _process_worker's
        super().run()


class _WorkerContext(multiprocessing.context.SpawnContext):
    """The spawn context of the local pool, whose processes are :class:`_WorkerProcess`."""
    Process = _WorkerProcess


class _CallQueue:
    """The pool's call queue as a worker reads it: ``multiprocessing.Queue.get`` (the same
    lock, pipe and semaphore), except that a SIGINT never ends the worker halfway through
    a message.  The SIGINT of a Ctrl-C can be handled after the read it should have
    interrupted has returned data: the kernel woke the idle worker for it, but the worker
    ran only after the parent's shutdown had written its sentinels (7 ms later in a
    logged run), or another thread took the signal.  The worker then exited with the
    4-byte header of a sentinel read and its body left in the pipe; the next worker read
    that body as a header (a negative length) and printed ``EOFError: Ran out of input``
    (6 runs in 60 of tests/test_runstore_workers.py's Ctrl-C script, 13 in 60 with a busy
    core).  Here the worker waits until a message is there ("idle": a SIGINT, however
    late, ends it before a byte is read), reads the message whole ("busy": a SIGINT then
    ends it after the read) and unpickles it "idle"."""

    #: the internals of ``multiprocessing.Queue.get`` it reads (CPython 3.11-3.13)
    INTERNALS = ("_rlock", "_reader", "_sem")

    def __init__(self, queue):
        self._queue = queue

    @classmethod
    def can_read(cls, queue) -> bool:
        """``queue`` is a ``multiprocessing.Queue`` with the internals this reader uses;
        a Python whose queue lacks them keeps its own ``get`` (the pool works, with the
        rare torn message at a Ctrl-C this class prevents)."""
        return isinstance(queue, multiprocessing.queues.Queue) and all(
            hasattr(queue, name) for name in cls.INTERNALS) and hasattr(
            getattr(queue, "_reader", None), "poll")

    def get(self, block=True):                      # as _process_worker calls it
        global _STATE
        q = self._queue
        if _EXIT:
            raise SystemExit(0)
        _STATE = "idle"
        with q._rlock:                              # one reader at a time
            q._reader.poll(None)                    # a late SIGINT runs on its return
            _STATE = "busy"
            res = q._reader.recv_bytes()
        q._sem.release()
        if _EXIT:
            raise SystemExit(0)
        _STATE = "idle"
        try:
            return ForkingPickler.loads(res)
        finally:
            _STATE = "busy"


class _Task:
    """A task of a local pool's worker (picklable when ``fn`` is): marks the worker
    running a task while ``fn`` runs."""

    def __init__(self, fn):
        self.fn = fn

    def __call__(self, *args, **kwargs):
        global _STATE
        _STATE = "task"
        try:
            if _EXIT:                   # a Ctrl-C since the call was read: not started
                raise KeyboardInterrupt
            return self.fn(*args, **kwargs)
        finally:
            _STATE = "busy"


def _worker_sigint(signum, frame):
    """SIGINT in a local pool's worker (a Ctrl-C reaches the whole process group).

    * In a running task ("task"): a KeyboardInterrupt (its chunk stops; the parent,
      interrupted too, keeps the chunks saved before), and the worker ends at its next
      wait for work: it took the chunks already in the call queue, which the parent
      cannot cancel, and ran them to their end (3 s to 6 s more for a pool of 2 running
      3 s chunks).
    * Waiting for work ("idle"): a quiet exit (SystemExit, no traceback), which printed
      ``Process SpawnProcess-N: ... KeyboardInterrupt`` (QA).  It exits rather than
      waits for the pool's shutdown: an idle worker left alive hung the exit when a
      second SIGINT (``timeout -s INT`` signals the process and its group) cut the
      parent's shutdown short; its exit ends the pool at once.
    * Otherwise ("busy": starting, reading a message off the call queue, sending a
      result back): the worker ends at its next wait for work (:class:`_CallQueue`), a
      task it took meanwhile stops before it starts (:class:`_Task`); an exit halfway
      through a message of the call queue left it torn for the other workers."""
    global _EXIT
    if _STATE == "task":
        _EXIT = True                            # and no other task after this one
        raise KeyboardInterrupt
    if _STATE == "idle":
        raise SystemExit(0)
    _EXIT = True


def _worker_start(parent: int) -> None:
    """Initializer of a local pool's worker (process ``parent``'s child, a
    :class:`_WorkerProcess`): an end with the parent: SIGTERM when it dies (Linux
    ``prctl(PR_SET_PDEATHSIG)``), elsewhere a daemon thread that exits when
    ``os.getppid()`` is no longer ``parent`` (:func:`_watch_parent`)."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes
            libc = ctypes.CDLL(None, use_errno=True)
            if libc.prctl(1, int(signal.SIGTERM), 0, 0, 0) == 0:      # PR_SET_PDEATHSIG
                if os.getppid() != parent:           # died before the prctl took effect
                    os._exit(1)
                return
        except (OSError, AttributeError):
            pass
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True,
                     name="distkin-parent-watch").start()


def _watch_parent(parent: int, poll: float | None = None) -> None:
    """Exit this process (status 1) once its parent is no longer ``parent`` (re-parented:
    the parent died), checking every ``poll`` s (default :data:`_PARENT_POLL_S`)."""
    while os.getppid() == parent:
        time.sleep(_PARENT_POLL_S if poll is None else poll)
    os._exit(1)


@contextlib.contextmanager
def dask_executor(address: str, timeout: str = "10s"):
    """A ``concurrent.futures`` executor on the ``dask.distributed`` cluster at
    ``address`` (needs the ``distributed`` extra); ``timeout`` for the connection."""
    try:
        from distributed import Client
    except ImportError:
        raise InputError("expected the optional dependency 'distributed' for --scheduler, "
                         "got an environment without it", field="scheduler",
                         hint="pip install 'distkin[distributed]'") from None
    from .argcheck import scheduler_address
    scheduler_address(address, "scheduler")
    try:
        client = Client(address, timeout=timeout)
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"expected a reachable dask scheduler, got {address!r}: {exc}",
                         field="scheduler") from None
    try:
        yield _DaskExecutor(client, address)
    finally:
        client.close()


class _DaskExecutor:
    """``Client.get_executor()`` plus :meth:`workers`, the number of live workers (for
    :func:`run_chunks` to notice a cluster that lost them all)."""

    def __init__(self, client, address):
        self._ex = client.get_executor()
        self._client = client
        self.address = address

    def submit(self, fn, *args, **kw):
        return self._ex.submit(fn, *args, **kw)

    def workers(self) -> int:
        try:
            return len(self._client.scheduler_info().get("workers", {}))
        except Exception:       # the scheduler itself is gone: no workers either
            return 0


@contextlib.contextmanager
def executor_for(executor=None, scheduler: str | None = None, workers: int | None = None):
    """The executor to use: one given, a dask cluster (``scheduler``), a local pool
    (``workers`` > 1, default the CPU count) or in-process execution (``workers=1``)."""
    if executor is not None:
        yield executor
    elif scheduler:
        with dask_executor(scheduler) as ex:
            yield ex
    elif workers == 1:
        yield None
    else:
        with local_executor(workers) as ex:
            yield ex


def make_store(store, field: str = "store") -> Path:
    """The chunk directory ``store``, made with its parents; a path that cannot be a
    directory (below a file, no permission) is an :class:`InputError` naming ``field``."""
    store = Path(store)
    try:
        store.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        try:                        # a default store: the cache folder is the culprit
            store.resolve().relative_to(user_cache_dir().resolve())
            hint = ("the scene names no store, so the chunks go to the cache folder "
                    f"{str(user_cache_dir())!r}: set DISTKIN_CACHE to a folder that can be "
                    "written, or give the query a store")
        except (ValueError, OSError):
            hint = None
        raise InputError(f"expected a directory for the chunks, got {str(store)!r} "
                         f"({exc.strerror or type(exc).__name__})", field=field,
                         hint=hint) from None
    return store


def run_chunks(task, specs, store, *, definition=None, executor=None, progress=True,
               desc="sweep", max_pending: int | None = None,
               no_worker_timeout: float | None = None, stats: dict | None = None,
               warmup=None):
    """Run ``task(spec)`` for every spec, keeping finished chunks on disk.

    Parameters
    ----------
    task : callable
        Module-level (picklable) function ``spec -> dict of ndarray``.
    specs : sequence
        Picklable chunk descriptions, in order.
    store : path or None
        Directory of the chunk files (created).  Chunks already there are reused.  A
        default store (:func:`default_store`) gets a sub-folder per sweep definition
        (:func:`keyed_store`).  None keeps the chunks in memory only (nothing resumes).
    definition : JSON-able, optional
        What defines the sweep; its key is kept in ``store/sweep.json`` and a store
        made for another definition is refused (InputError).
    executor : concurrent.futures.Executor or None
        None runs the chunks in this process.
    progress : bool
        Show a rich progress bar with the ETA.
    no_worker_timeout : float, optional
        An executor that reports its live workers (the dask one) and has none for this
        long (s; default :data:`NO_WORKER_TIMEOUT_S`) ends the sweep with a
        :class:`~distkin.errors.DistkinError`; the finished chunks are on disk.
    stats : dict, optional
        Filled with ``loaded``: how many chunks came from the store (computed by an
        earlier run) rather than by this call; ``store``: the folder the chunks are in
        (the keyed sub-folder under a default store, :func:`keyed_store`).
    warmup : callable, optional
        Run here before the first chunk of an in-process sweep (``executor`` None) while
        the bar says "loading kernels" (compiled, cached): the one-off cost of the task's
        first call (QA: a bar at "0/4 chunks" for 18 s, then 4/4 at once).

    Returns
    -------
    list of dict
        The chunk results, in the order of ``specs``.

    A ``KeyboardInterrupt`` cancels the pending chunks and propagates; every chunk
    finished before it is on disk.
    """
    key = sweep_key(definition if definition is not None else [repr(s) for s in specs])
    if store is None:
        paths, results, todo = None, [None] * len(specs), list(range(len(specs)))
    else:
        store, paths, results, todo = _open_store(store, key, definition, len(specs))

    def stamp(i):
        return _chunk_stamp(key, code_version(), i, len(specs))
    if stats is not None:
        stats["loaded"] = len(specs) - len(todo)
        stats["store"] = None if store is None else str(store)
    bar = ChunkProgress(len(specs), len(specs) - len(todo), desc, progress)
    pending: dict = {}
    try:
        if executor is None:
            if warmup is not None and todo:
                bar.note(" · loading kernels")
                warmup()
                bar.note("")
            for i in todo:
                results[i] = task(specs[i])
                if paths is not None:
                    _save(paths[i], results[i], stamp(i))
                bar.advance()
        else:
            # never more pending than chunks: a process pool starts its processes as
            # chunks are submitted, so it is capped at the number of chunks too
            limit = min(max_pending or 4 * (getattr(executor, "_max_workers", None) or 4),
                        max(1, len(todo)))
            queue = list(todo)
            while queue or pending:
                while queue and len(pending) < limit:
                    i = queue.pop(0)
                    pending[executor.submit(task, specs[i])] = i
                done = _wait_alive(executor, pending, store, no_worker_timeout)
                for f in done:
                    i = pending.pop(f)
                    results[i] = f.result()
                    if paths is not None:
                        _save(paths[i], results[i], stamp(i))
                    bar.advance()
    except BaseException as exc:         # Ctrl-C, a store that cannot be written, ...
        for f in pending:                                 # the running ones finish
            f.cancel()
        running = [f for f in pending if f.running()]
        if running and isinstance(exc, KeyboardInterrupt):   # the pool's shutdown waits
            print(f"distkin: interrupted: waiting for {len(running)} running chunk(s) to "
                  "stop (the chunks saved before are kept)", file=sys.stderr, flush=True)
        raise
    finally:
        bar.close()
    return results


def check_store(store, definition, n: int) -> Path:
    """The folder :func:`run_chunks` would use for a sweep of ``n`` chunks defined by
    ``definition`` in ``store``, checked now: a store it would refuse (another sweep's or
    another code version's, chunk files that are not this sweep's) raises the same
    InputError before any work is done (a caller with work to do first, such as the
    design sweep's culling ahead of its brute force, calls it then)."""
    return _open_store(store, sweep_key(definition), definition, n)[0]


def _open_store(store, key, definition, n):
    """(store folder, chunk paths, results with the chunks already there loaded, the
    indices left to do) of a stored run of ``n`` chunks (:func:`run_chunks`): the folder
    :func:`keyed_store` names, made, opened by :func:`~distkin.chunkfiles.open_store`."""
    store = make_store(keyed_store(store, key))
    return (store, *open_store(store, key, code_version(), definition, n))


def _wait_alive(executor, pending, store, timeout):
    """The futures of ``pending`` that finish first; with an executor that counts its
    workers, raise when it has had none for ``timeout`` s (a dask cluster whose workers
    all died never finishes a future)."""
    if not hasattr(executor, "workers"):
        return wait(list(pending), return_when=FIRST_COMPLETED)[0]
    limit = NO_WORKER_TIMEOUT_S if timeout is None else timeout
    since = None
    while True:
        done, _ = wait(list(pending), timeout=min(_HEALTH_POLL_S, limit),
                       return_when=FIRST_COMPLETED)
        if done:
            return done
        if executor.workers() > 0:
            since = None
            continue
        now = time.monotonic()
        since = now if since is None else since
        if now - since >= limit:
            for f in pending:
                f.cancel()
            kept = ("no store: the finished chunks are lost" if store is None else
                    f"the {len(finished_chunks(store))} finished chunks are "
                    f"kept in {str(store)!r} (run again to continue)")
            raise DistkinError(
                f"expected live workers on the dask cluster at "
                f"{getattr(executor, 'address', '?')}, got none for {limit:g} s; {kept}",
                field="scheduler")
