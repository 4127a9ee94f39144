"""Chunked resumable sweeps: resume after an interrupt, executors (in process, local
process pool, dask LocalCluster) give identical results."""

import json

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.indices.study import Device, study_chunk
from distkin.runstore import local_executor, run_chunks
from distkin.indices.workspace import table2_grid


def square_chunk(spec):
    """Module-level task (picklable)."""
    if spec.get("interrupt"):
        raise KeyboardInterrupt
    x = np.arange(spec["lo"], spec["hi"], dtype=float)
    return {"x": x, "y": x ** 2}


def _specs(n, interrupt_at=None):
    return [{"lo": 10 * i, "hi": 10 * i + 10, "interrupt": i == interrupt_at}
            for i in range(n)]


def test_interrupted_sweep_keeps_finished_chunks_and_resumes(tmp_path):
    store = tmp_path / "s"
    definition = {"task": "square", "n": 6}
    with pytest.raises(KeyboardInterrupt):
        run_chunks(square_chunk, _specs(6, interrupt_at=3), store, definition=definition,
                   progress=False)
    done = sorted(p.name for p in store.glob("chunk_*.npz"))
    assert done == [f"chunk_{i:05d}.npz" for i in range(3)]
    before = {p.name: p.stat().st_mtime_ns for p in store.glob("chunk_*.npz")}
    res = run_chunks(square_chunk, _specs(6), store, definition=definition, progress=False)
    for p in store.glob("chunk_*.npz"):            # finished chunks were not recomputed
        if p.name in before:
            assert p.stat().st_mtime_ns == before[p.name]
    y = np.concatenate([r["y"] for r in res])
    assert np.array_equal(y, np.arange(60.0) ** 2)
    assert json.loads((store / "sweep.json").read_text())["chunks"] == 6


def test_store_of_another_sweep_is_refused(tmp_path):
    run_chunks(square_chunk, _specs(2), tmp_path, definition={"a": 1}, progress=False)
    with pytest.raises(InputError, match="chunk store made for this sweep"):
        run_chunks(square_chunk, _specs(2), tmp_path, definition={"a": 2}, progress=False)


def test_damaged_chunk_file_is_recomputed(tmp_path):
    run_chunks(square_chunk, _specs(2), tmp_path, definition={"a": 1}, progress=False)
    (tmp_path / "chunk_00001.npz").write_bytes(b"not an npz")
    res = run_chunks(square_chunk, _specs(2), tmp_path, definition={"a": 1}, progress=False)
    assert np.array_equal(res[1]["y"], np.arange(10.0, 20.0) ** 2)


def _study_specs(mech):
    grid = table2_grid(step=0.075, rot_step_deg=20)
    dev = Device("Octopod", mech, grid)
    return [{"mech": dev.mech, "grid": grid, "lo": a, "hi": min(27, a + 9),
             "actuators": {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51.0},
             "ST": (15, 15, 15, 1, 1, 1), "inner": None, "route": "kernels", "batch": 500}
            for a in range(0, 27, 9)]


def test_local_process_pool_equals_in_process(tmp_path, presets):
    specs = _study_specs(presets["octopod"])
    ref = run_chunks(study_chunk, specs, tmp_path / "a", definition={"x": 1}, progress=False)
    with local_executor(2) as ex:
        par = run_chunks(study_chunk, specs, tmp_path / "b", definition={"x": 1},
                         executor=ex, progress=False)
    for r, p in zip(ref, par):
        assert r.keys() == p.keys()
        for k in r:
            assert np.array_equal(r[k], p[k]), k


def test_dask_local_cluster_equals_local_pool(tmp_path, presets):
    """A small sweep on a dask.distributed LocalCluster (the --scheduler route) gives the
    same chunks as the local process pool."""
    distributed = pytest.importorskip(
        "distributed", reason="dask.distributed is not installed (extra 'distributed')")
    from distkin.runstore import dask_executor
    specs = _study_specs(presets["octopod"])
    with local_executor(2) as ex:
        ref = run_chunks(study_chunk, specs, tmp_path / "a", definition={"x": 1},
                         executor=ex, progress=False)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with dask_executor(cluster.scheduler_address) as ex:
            got = run_chunks(study_chunk, specs, tmp_path / "b", definition={"x": 1},
                             executor=ex, progress=False)
    for r, p in zip(ref, got):
        for k in r:
            assert np.array_equal(r[k], p[k]), k


def test_unreachable_scheduler_is_an_input_error():
    pytest.importorskip("distributed", reason="dask.distributed is not installed")
    from distkin.runstore import dask_executor
    with pytest.raises(InputError, match="reachable dask scheduler"):
        with dask_executor("tcp://127.0.0.1:1", timeout="1s"):
            pass


def test_table1_sweep_and_presets_are_one_model():
    """Issue 15, finding 3: under the paper's rule (l2 + l3 constant, baseline Ergin's
    device, Sec. III-B-2) the sweep's Hunt-type design (l2 = β = γ = 0, ld = 20 mm) is
    the hunt preset, and every design keeps the leg length of the presets."""
    import math

    from distkin.indices.design import DesignSpace
    from distkin.mechanisms import preset
    from distkin.mechanisms.rss import LEG_LENGTH
    deg = math.pi / 180
    space = DesignSpace("hunt", (("l2", (0.0, 0.015, 0.030)), ("beta", (0.0, 10 * deg)),
                                 ("gamma", (0.0, 30 * deg)), ("ld", (0.020, 0.040))))
    for d in space.designs():
        m = space.mechanism(d)
        assert m.l2 + m.l3 == pytest.approx(LEG_LENGTH, abs=1e-15)
    m = space.mechanism({"l2": 0.0, "beta": 0.0, "gamma": 0.0, "ld": 0.020})
    assert m.geometry_key() == preset("hunt").geometry_key() and m.name == "hunt"
    e = preset("ergin")
    assert space.mechanism({"l2": e.l2, "beta": e.beta, "gamma": e.gamma,
                            "ld": e.ld}).geometry_key() == e.geometry_key()
