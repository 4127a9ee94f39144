"""Exact power-of-two rescaling of the index kernels' inputs (QA Z2 4).

The capability and sensitivity kernels are homogeneous of degree one in the generator
matrix and in the actuator limits (Kühne et al., eqs. (8)-(16): the set ``G·box``
scales with both), but their intermediates (facet normals ~ ``1/||G||``, their squared
norms, ``pinv(J)``) leave the float64 range long before the result does: ``G·1e-155``
gave inf.  A pose whose largest entry lies outside ``[2^-SAFE, 2^SAFE]`` is therefore
scaled by ``2^-e`` (:func:`numpy.ldexp`, exact: no digit changes) before the kernel and
its result by ``2^e`` after, with :mod:`distkin.geometry.pow2_scale`, as Cayley-Menger
determinants are.  Poses inside the range are not touched (bit-identical
results).  A result that itself does not fit float64 is returned as inf or 0 with a
:class:`~distkin.errors.FloatRangeWarning`.
"""

from __future__ import annotations

import numpy as np

from ..geometry import pow2_scale
from ..geometry.pow2_scale import exponent

__all__ = ["pow2_exponent", "scale_back", "SAFE"]

#: |binary exponent| of the largest entry up to which a pose is left unscaled
SAFE = 128


def pow2_exponent(a, axes):
    """Per-pose binary exponent ``e`` (int array) of the largest ``|a|`` over ``axes``,
    0 where it is within ``2^±SAFE`` or zero: ``ldexp(a, -e)`` has entries <= 1 there."""
    e = exponent(np.max(np.abs(a), axis=axes))
    return np.where(np.abs(e) > SAFE, e, 0)


def scale_back(out, e, what: str):
    """``out·2^e`` elementwise (broadcast), with one FloatRangeWarning naming ``what``
    where a finite non-zero value becomes inf or leaves the normal range
    (:func:`distkin.geometry.pow2_scale.scale_back`)."""
    return pow2_scale.scale_back(out, e, what, "other units")[0]
