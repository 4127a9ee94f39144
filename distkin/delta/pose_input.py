"""Checks of the true poses given to the offset study (:mod:`.offset_study`): a rotation
is a finite 3x3 matrix, orthonormal within :data:`ROTATION_TOL` and of determinant +1;
a translation is a finite 3-vector.  Built on :mod:`distkin.argcheck` (shapes, finite
numbers, booleans), so that messages read ``FIELD: expected …, got …`` as everywhere.

A scaled rotation or a reflection is not a pose of a rigid platform: its "legs" belong
to no assembly mode, and the error of neglecting the offsets measured there means
nothing (a reflection made the linearised error 1e11 while the solver called its
answer trusted).
"""

from __future__ import annotations

import numpy as np

from ..argcheck import float_array
from ..errors import InputError
from ..spatial import rotation_defect
from .platform66 import Platform66

__all__ = [
    "ROTATION_TOL",
    "check_rotation",
    "check_translation",
    "check_poses",
    "check_platform66",
]

#: largest accepted max|R^T R - I| (and |det R - 1|) of a rotation, dimensionless: far
#: above float64 round-off of a computed rotation, far below any real deformation
ROTATION_TOL = 1e-9


def _rotation_defect(R: np.ndarray, field: str) -> np.ndarray:
    dev, det = rotation_defect(R)
    det = float(det)
    if not (dev <= ROTATION_TOL and abs(det - 1.0) <= ROTATION_TOL):
        raise InputError(f"expected a rotation matrix (orthonormal within {ROTATION_TOL:g}, "
                         f"determinant +1), got max|R^T R - I| = {dev:.3g} and det R = "
                         f"{det:.6g}", field=field,
                         hint="a reflection has det -1; a scaled rotation is not one")
    return R


def check_rotation(value, field: str = "rotation") -> np.ndarray:
    """A rotation matrix (3, 3) as float64, or :class:`~distkin.errors.InputError`
    naming ``field`` (wrong shape, booleans, NaN/inf, not orthonormal, det -1)."""
    return _rotation_defect(float_array(value, field, (3, 3)), field)


def check_translation(value, field: str = "translation") -> np.ndarray:
    """A translation (3,) as float64 (length units), or InputError naming ``field``."""
    return float_array(value, field, (3,))


def check_poses(rotations, translations, fields=("rotations", "translations")):
    """``n`` poses: rotations (n, 3, 3) and translations (n, 3) as float64, each rotation
    checked as :func:`check_rotation` (the field names the pose, ``rotations[j]``) and
    both of the same length ``n``."""
    fr, ft = fields
    Rs = float_array(rotations, fr, (None, 3, 3))
    ts = float_array(translations, ft, (None, 3))
    if len(Rs) != len(ts):
        raise InputError(f"expected as many translations as rotations ({len(Rs)}), got "
                         f"{len(ts)}", field=ft)
    for j, R in enumerate(Rs):
        _rotation_defect(R, f"{fr}[{j}]")
    return Rs, ts


def check_platform66(platform, field: str = "platform") -> Platform66:
    """``platform`` itself when it is a :class:`~.platform66.Platform66`, else
    InputError naming ``field``."""
    if not isinstance(platform, Platform66):
        raise InputError(f"expected a Platform66 (distkin.delta.approximation), got "
                         f"{type(platform).__name__}", field=field)
    return platform
