"""Fixtures of the whole suite."""

from __future__ import annotations

import os

import pytest


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory):
    """Every test (and every CLI subprocess it starts, which inherits the environment)
    writes sweep stores, derived kernels and compiled cycle wrappers to one temporary
    cache, never to the user's; set once for the session, so it cannot leak from one
    test folder into the next."""
    if os.environ.get("PYTEST_XDIST_WORKER"):
        # the workers of one ``-n`` run share it (pytest-N/, the parent of each worker's
        # popen-gwK/): a scene's cycle or leg module is compiled once per run, not once
        # per worker (~10 s of numba each; the cache's own locks order the writers)
        cache = tmp_path_factory.getbasetemp().parent / "distkin_cache"
        cache.mkdir(exist_ok=True)
    else:
        cache = tmp_path_factory.mktemp("distkin_cache")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DISTKIN_CACHE", str(cache))
        yield
