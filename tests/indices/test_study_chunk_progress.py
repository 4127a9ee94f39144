"""The study's progress bar moves within the work (QA: "0/4 chunks · ETA -:--:--" for
18 s, then 4/4 at once): a small grid is cut into at least ``MIN_CHUNKS`` chunks, and
the one-off loading of the compiled kernels happens before the first chunk under a
word on the bar.  The chunking changes no number: the per-position arrays are compared
bit for bit with those of one chunk per sweep (the planning before this change)."""

from __future__ import annotations

import math

import numpy as np


class _Recorder:
    """Stands in for :class:`distkin.progress.ChunkProgress`, recording its calls."""
    made: list = []

    def __init__(self, total, done, desc, enabled):
        self.total, self.events = total, []
        _Recorder.made.append(self)

    def advance(self):
        self.events.append("advance")

    def note(self, text):
        self.events.append(("note", text))

    def close(self):
        self.events.append("close")


def test_small_grid_gets_many_chunks_and_the_same_numbers(presets, tmp_path, monkeypatch):
    from distkin import runstore
    from distkin.indices import study
    from distkin.indices.study import Device, planned_chunk, run_device
    from distkin.indices.workspace import table2_grid
    grid = table2_grid(step=0.075, rot_deg=20, rot_step_deg=20)        # 27 positions
    dev = Device("hunt", presets["hunt"], grid, None, math.radians(20))
    assert grid.n_positions == 27
    assert planned_chunk(27, 32) == 1 and planned_chunk(125, 32) == 7 and planned_chunk(4096, 32) == 32
    monkeypatch.setattr(runstore, "ChunkProgress", _Recorder)
    _Recorder.made.clear()
    new, _ = run_device(dev, store=tmp_path / "a", chunk_positions=32)
    bar = _Recorder.made[-1]
    assert bar.total >= study.MIN_CHUNKS and bar.total == 27
    assert bar.events[0] == ("note", " · loading kernels")           # before any chunk
    assert bar.events.count("advance") == bar.total
    monkeypatch.setattr(study, "MIN_CHUNKS", 1)                       # the old planning
    old, _ = run_device(dev, store=tmp_path / "b", chunk_positions=32)
    assert _Recorder.made[-1].total == 1
    assert new.keys() == old.keys()
    for k in old:
        assert new[k].dtype == old[k].dtype and np.array_equal(new[k], old[k],
                                                                equal_nan=True), k
