"""The exception and warning family lives in :mod:`distkin.errors` (the engineering
rules: one hierarchy); the modules that raise a warning re-export the same class, so
``from distkin.mechanisms import GeometryWarning`` and ``from distkin.errors import
GeometryWarning`` filter the same warnings."""

from __future__ import annotations

import inspect
import warnings

import pytest

import distkin.errors as errors


def test_every_warning_class_of_the_package_is_defined_in_errors():
    import importlib
    import pkgutil

    import distkin
    found = {}
    for info in pkgutil.walk_packages(distkin.__path__, "distkin."):
        if info.name.startswith("distkin._generated") or info.name.endswith("__main__"):
            continue
        mod = importlib.import_module(info.name)
        for name, obj in vars(mod).items():
            if inspect.isclass(obj) and issubclass(obj, Warning) and \
                    obj.__module__.startswith("distkin"):
                found.setdefault(obj, set()).add(info.name)
    assert found, "no distkin warning class found"
    stray = {cls.__qualname__: cls.__module__ for cls in found if cls.__module__ != "distkin.errors"}
    assert stray == {}, stray
    assert {c.__name__ for c in found} <= set(errors.__all__)


def test_re_exported_warnings_are_the_same_classes():
    from distkin.geometry.cm_float import CancellationWarning, FloatRangeWarning
    from distkin.mechanisms import GeometryWarning
    assert CancellationWarning is errors.CancellationWarning
    assert FloatRangeWarning is errors.FloatRangeWarning
    assert GeometryWarning is errors.GeometryWarning
    assert issubclass(errors.CancellationWarning, errors.ConditioningWarning)


def test_filtering_by_the_errors_class_catches_a_mechanism_warning():
    """A 100x override of a preset's length (a unit slip) warns; filtered as an error
    through distkin.errors it is refused."""
    from distkin.mechanisms import preset
    ref = preset("octo")
    with warnings.catch_warnings():
        warnings.simplefilter("error", errors.GeometryWarning)
        with pytest.raises(errors.GeometryWarning):
            preset("octo", l1=ref.l1 * 1000)
