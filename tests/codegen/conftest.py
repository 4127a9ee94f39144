"""The fixture ``mods``: the scene modules of :mod:`scene_modules`, written once per
test session (two test files read them)."""

from __future__ import annotations

import pytest

from scene_modules import write_modules


@pytest.fixture(scope="session")
def mods(tmp_path_factory):
    return write_modules(tmp_path_factory.mktemp("scene_modules"))
