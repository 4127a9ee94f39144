"""Fixtures of the certified-workspace tests."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory):
    """Sweep stores and derivations go to a temporary cache, not the user's."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DISTKIN_CACHE", str(tmp_path_factory.mktemp("distkin_cache")))
        yield
