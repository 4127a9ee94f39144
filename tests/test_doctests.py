"""Every module's docstring examples run as tests (one test per module that has any).

Modules are found on disk (``distkin/**/*.py``, the generated kernels included) and
imported; a module with examples must run them all without a failure.  The examples
compare against the numbers they show, so they are checked like any other value.
"""

import doctest
import importlib
from pathlib import Path

import pytest

import distkin

ROOT = Path(distkin.__file__).parent
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def _module_names():
    for path in sorted(ROOT.rglob("*.py")):
        parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
        if parts[-1] == "__main__":
            continue
        if parts[-1] == "__init__":
            parts = parts[:-1]
        yield ".".join(parts)


def _with_examples():
    finder = doctest.DocTestFinder(exclude_empty=True)
    out = []
    for name in _module_names():
        module = importlib.import_module(name)
        if any(t.examples for t in finder.find(module)):
            out.append(name)
    return out


MODULES = _with_examples()


def test_modules_with_examples_are_found():
    # the Δ-transform and the singularity conditions carry worked examples
    assert "distkin.delta.transform" in MODULES
    assert "distkin.singularity.conditions" in MODULES


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=FLAGS, report=False)
    assert result.attempted > 0
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {name} fail"
