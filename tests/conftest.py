"""Fixtures of the whole suite."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory):
    """Every test (and every CLI subprocess it starts, which inherits the environment)
    writes sweep stores, derived kernels and compiled cycle wrappers to one temporary
    cache, never to the user's; set once for the session, so it cannot leak from one
    test folder into the next."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DISTKIN_CACHE", str(tmp_path_factory.mktemp("distkin_cache")))
        yield
