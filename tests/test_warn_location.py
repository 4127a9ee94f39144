"""distkin.errors.warn: every warning names the user's line (the first frame outside
the distkin package), whatever the depth of the kernel that raises it below the public
function.  Before, each site counted its own depth (``stacklevel=N``), and a count
that was one short pointed into distkin (the fast singularity conditions' range
warning pointed at distkin/singularity/conditions.py)."""

from __future__ import annotations

import warnings

import numpy as np

from distkin.errors import CancellationWarning, ConditioningWarning, GeometryWarning, warn


def _record(call):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        call()
    return rec


def test_warn_called_from_outside_distkin_names_its_caller():
    def user_function():
        warn("from a user function", UserWarning)
    [w] = _record(user_function)
    assert w.filename == __file__ and w.category is UserWarning
    assert w.lineno == user_function.__code__.co_firstlineno + 1


def test_a_cancellation_warning_three_levels_down_names_this_file():
    from distkin.geometry import cayley_menger, squared_distances
    Q = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.3, 0.3, 1e-7]])     # nearly flat
    rec = _record(lambda: cayley_menger(squared_distances(Q), (1, 2, 3, 4)))
    assert [w.category for w in rec] == [CancellationWarning]
    assert rec[0].filename == __file__


def test_a_conditioning_warning_of_the_indices_names_this_file():
    from distkin.indices import max_sensitivities
    J = np.random.default_rng(5).normal(size=(8, 6))
    U, s, Vt = np.linalg.svd(J, full_matrices=False)
    s[-1] = 0.0
    rec = _record(lambda: max_sensitivities((U * s) @ Vt))
    assert [w.category for w in rec] == [ConditioningWarning]
    assert rec[0].filename == __file__


def test_a_geometry_warning_of_a_mechanism_names_this_file():
    """A leg out of reach at home (tests/mechanisms/test_degenerate_legs.py's stretched
    RUS leg): the warning comes from the mechanism's constructor, several calls down."""
    from distkin.mechanisms import LegMechanism
    legs = [dict(type="RUS", base=(0, 0, 0), platform=(0.375, 0, 0), axis=(0, 0, 1),
                 crank0=(1, 0, 0), crank90=(0, 1, 0), crank=0.125, distal=0.25, branch=1)]
    for i in range(1, 6):
        th = 2 * np.pi * i / 6
        e, t = np.array([np.cos(th), np.sin(th), 0]), np.array([-np.sin(th), np.cos(th), 0])
        p = 0.1 * np.array([np.cos(th + 0.3 * (-1) ** i), np.sin(th + 0.3 * (-1) ** i), 0])
        legs.append(dict(type="RUS", base=tuple(0.2 * e), platform=tuple(p), axis=tuple(t),
                         crank0=tuple(e), crank90=tuple(np.cross(t, e)), crank=0.08,
                         distal=0.25))
    rec = _record(lambda: LegMechanism("stretched", tuple(legs), (0, 0, 0.22, 0, 0, 0)))
    ours = [w for w in rec if w.category is GeometryWarning]
    assert len(ours) == 1 and ours[0].filename == __file__


def test_a_warning_raised_while_distkin_imports_a_module_names_the_importer(tmp_path):
    """The import machinery's frames are not counted (warnings.warn skips them): a
    distkin module that warns at import, imported by another distkin module, names the
    user's import line, not the distkin importer (review)."""
    import sys

    import distkin
    (tmp_path / "_warntop.py").write_text("import distkin._warnleaf\n")
    (tmp_path / "_warnleaf.py").write_text(
        "from distkin.errors import warn\nwarn('at import', UserWarning)\n")
    distkin.__path__.append(str(tmp_path))
    try:
        def user_import():
            import distkin._warntop  # noqa: F401
        [w] = _record(user_import)
        assert w.filename == __file__, w.filename
    finally:
        distkin.__path__.remove(str(tmp_path))
        for name in ("distkin._warntop", "distkin._warnleaf"):
            sys.modules.pop(name, None)
