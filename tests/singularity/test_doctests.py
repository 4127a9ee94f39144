"""The docstring examples of the Δ-transform and singularity modules run as tests."""

import doctest

import pytest

import distkin.delta
import distkin.singularity


@pytest.mark.parametrize("module", [distkin.delta, distkin.singularity])
def test_docstring_examples(module):
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0
