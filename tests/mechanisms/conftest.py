"""Fixtures of the RSS tests."""

from __future__ import annotations

import pytest

from rss_sampling import PRESET_NAMES


@pytest.fixture(params=PRESET_NAMES)
def any_preset(request):
    from distkin.mechanisms import preset
    return preset(request.param)


@pytest.fixture(autouse=True, scope="session")
def _private_derivation_cache(tmp_path_factory):
    """Derivations of non-preset parameters go to a temporary cache, not the user's."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DISTKIN_CACHE", str(tmp_path_factory.mktemp("distkin_cache")))
        yield
