"""Fixtures of the RSS tests."""

from __future__ import annotations

import pytest

from rss_sampling import PRESET_NAMES


@pytest.fixture(params=PRESET_NAMES)
def any_preset(request):
    from distkin.mechanisms import preset
    return preset(request.param)

