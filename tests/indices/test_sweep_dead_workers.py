"""A dask sweep whose cluster loses every worker ends with a clear error (issue 14).

A future never finishes on a cluster without workers; :func:`run_chunks` used to wait
for it forever.  Here an in-process LocalCluster loses its only worker after the first
chunk is on disk: the sweep must raise a DistkinError naming the scheduler and keep the
finished chunks.  No timing is asserted: the whole sweep runs in a thread joined with a
generous timeout, so that a hang fails the test.
"""

import threading
import time

import numpy as np
import pytest

from distkin.errors import DistkinError
from distkin.runstore import run_chunks

_HANG = 120


def slow_chunk(i):
    """Module-level task: a chunk that takes a moment."""
    time.sleep(0.2)
    return {"x": np.array([i], dtype=float)}


def test_sweep_without_workers_ends_and_keeps_finished_chunks(tmp_path):
    distributed = pytest.importorskip(
        "distributed", reason="dask.distributed is not installed (extra 'distributed')")
    from distkin.runstore import dask_executor
    store = tmp_path / "store"
    out = {}
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:

        def kill_after_first_chunk():
            while not list(store.glob("chunk_*.npz")):
                time.sleep(0.02)
            cluster.scale(0)

        def sweep():
            try:
                with dask_executor(cluster.scheduler_address) as ex:
                    run_chunks(slow_chunk, list(range(40)), store, executor=ex,
                               progress=False, no_worker_timeout=1.0)
                out["result"] = "finished"
            except DistkinError as exc:
                out["error"] = exc

        killer = threading.Thread(target=kill_after_first_chunk, daemon=True)
        runner = threading.Thread(target=sweep, daemon=True)
        killer.start()
        runner.start()
        runner.join(timeout=_HANG)
        assert not runner.is_alive(), "the sweep kept waiting for workers that are gone"
    exc = out.get("error")
    assert exc is not None, out
    assert exc.field == "scheduler" and "no" in exc.message and "workers" in exc.message
    kept = sorted(store.glob("chunk_*.npz"))
    assert kept and f"{len(kept)} finished chunks are kept" in exc.message
    assert len(kept) < 40
