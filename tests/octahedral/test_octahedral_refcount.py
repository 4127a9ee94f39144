"""The compiled stages without numba's reference counting (perf-oct-4) free what they
allocate.

The allocation-free stages of the fast tier (the scan, the polish, the placement, the
proof and their helpers) are compiled with ``_nrt=False``: no reference counting of
their array arguments and views.  Such a function must neither allocate nor keep an
array that an allocating callee returns (nothing would free it: the first version of
``descartes.recover`` leaked the 14 work arrays of ``descartes._workspace`` on every
call).  Independent check: numba's own allocation statistics (live allocations before
and after repeated calls) on every route of the fast tier, the recovery included.
"""

from __future__ import annotations

import gc
import warnings

import numpy as np
from numba.core.runtime import _nrt_python, rtsys

from distkin.octahedral import forward_kinematics, forward_kinematics_batched
from distkin.octahedral.reference import GD_BASE, GD_LEGS, GD_PLATFORM, random_octahedron


def _live():
    s = rtsys.get_allocation_stats()
    return s.alloc - s.free, s.mi_alloc - s.mi_free


def test_fast_tier_routes_free_what_they_allocate():
    rng = np.random.default_rng(17)
    probs = [random_octahedron(rng) for _ in range(2000)]
    B, Q, L = (np.array([p[k] for p in probs]) for k in range(3))
    # problem 1678: refused by the proof and recovered (batched.recover_flagged), so the
    # recovery route runs too; 12 random ones: the careful (eigenvalue) route of the
    # doubted problems among them or not, the bare tier
    calls = [lambda: forward_kinematics_batched(B, Q, L),
             lambda: forward_kinematics_batched(B[:300], Q[:300], L[:300], prove=False),
             lambda: forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS),
             lambda: forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, warn=False).poses]
    was = _nrt_python.memsys_stats_enabled()
    _nrt_python.memsys_enable_stats()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = forward_kinematics_batched(B, Q, L)
            assert 1678 in res.raw["recovered"]
            for f in calls:
                f()
            gc.collect()
            before = _live()
            for _ in range(5):
                for f in calls:
                    f()
            del res
            gc.collect()
            after = _live()
    finally:
        if not was:
            _nrt_python.memsys_disable_stats()
    assert after[0] - before[0] <= 0 and after[1] - before[1] <= 0, (before, after)
