"""Fixtures of the performance-index tests."""

import pytest


@pytest.fixture(scope="session")
def presets():
    from distkin.mechanisms import preset
    return {name: preset(name) for name in ("ergin", "hexa", "hunt", "octopod", "octo")}
