"""Fixtures of the stability tests (issue 8: numerical stability at the extremes)."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True, scope="session")
def _private_derivation_cache(tmp_path_factory):
    """Kernels of the scaled (non-preset) mechanisms go to a temporary cache, not the
    user's."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DISTKIN_CACHE", str(tmp_path_factory.mktemp("distkin_cache_stability")))
        yield
