"""The docstring examples of the Δ-transform and singularity modules run as tests."""

import doctest

import pytest

import distkin.delta.transform
import distkin.singularity.conditions


@pytest.mark.parametrize("module", [distkin.delta.transform, distkin.singularity.conditions])
def test_docstring_examples(module):
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0
