"""The generated arb-flavour kernels on mpmath numbers: the precise tier's arithmetic.

:class:`MPNumber` gives an mpmath number the methods the arb-flavour kernels call, and
:func:`on_mpmath` rebinds a kernel to it; :func:`precise_runs` evaluates kernels at
``dps`` and ``dps + GUARD`` digits and :func:`estimate` turns the two into the error
estimate of :mod:`.kinematics_tiers` (module docstring, ``precise``).  A division by
zero inside a kernel is a :class:`~distkin.errors.SingularConfigurationError` naming the
pose, never mpmath's bare ``ZeroDivisionError``.
"""

from __future__ import annotations

import types

import numpy as np

from ..errors import SingularConfigurationError
from ..exact import float_mpf

__all__ = ["MPNumber", "on_mpmath", "precise_runs", "estimate", "GUARD"]

#: extra digits of the precise tier's second evaluation (its error estimate)
GUARD = 15

_to_float = np.vectorize(float, otypes=[float])


class MPNumber:
    """An mpmath number with the methods the arb-flavour kernels call (``x.sqrt()``,
    ``x.sin()``, ``x.cos()``, ``abs(x)``, ``MPNumber.atan2(y, x)``, arithmetic with
    ints and floats, ``MPNumber(p)`` for the kernels' ``_A(p)``), at the current
    ``mpmath.mp.dps``.  ``.v`` is the :class:`mpmath.mpf`; an integer is held exactly,
    whatever its size (the kernels' ``_integers``), and rounded only by the arithmetic."""

    __slots__ = ("v",)

    def __init__(self, v):
        import mpmath
        if isinstance(v, MPNumber):
            self.v = v.v
        elif isinstance(v, int) and abs(v).bit_length() > 53:
            with mpmath.workprec(abs(v).bit_length()):
                self.v = mpmath.mpf(v)
        else:
            self.v = mpmath.mpf(v)

    @staticmethod
    def _of(x):
        return x.v if isinstance(x, MPNumber) else x

    def __add__(self, o):
        return MPNumber(self.v + self._of(o))

    __radd__ = __add__

    def __sub__(self, o):
        return MPNumber(self.v - self._of(o))

    def __rsub__(self, o):
        return MPNumber(self._of(o) - self.v)

    def __mul__(self, o):
        return MPNumber(self.v * self._of(o))

    __rmul__ = __mul__

    def __truediv__(self, o):
        return MPNumber(self.v / self._of(o))

    def __rtruediv__(self, o):
        return MPNumber(self._of(o) / self.v)

    def __neg__(self):
        return MPNumber(-self.v)

    def __pos__(self):
        return self

    def __abs__(self):
        return MPNumber(abs(self.v))

    def __pow__(self, n):
        return MPNumber(self.v ** n)

    def sqrt(self):
        import mpmath
        return MPNumber(mpmath.sqrt(self.v))

    def sin(self):
        import mpmath
        return MPNumber(mpmath.sin(self.v))

    def cos(self):
        import mpmath
        return MPNumber(mpmath.cos(self.v))

    @staticmethod
    def atan2(y, x):
        import mpmath
        return MPNumber(mpmath.atan2(MPNumber._of(y), MPNumber._of(x)))

    def __repr__(self):
        return f"MPNumber({self.v!r})"


_MP_KERNELS: dict = {}


def on_mpmath(fn):
    """The generated arb kernel ``fn`` with its ball type ``_A`` bound to
    :class:`MPNumber` (the same code object, other globals; the integers ``_Z`` of its
    rational constants, :func:`distkin.codegen.emit.kernel_source`, rebuilt as exact
    :class:`MPNumber`): called on a pose of six :class:`MPNumber`, it evaluates the
    kernel in mpmath at the current ``mp.dps``, the constants ``_Z[i] / _Z[j]`` too."""
    key = (fn.__module__, fn.__qualname__, id(fn.__code__))
    if key not in _MP_KERNELS:
        g = {**fn.__globals__, "_A": MPNumber}
        if "_integers" in g:
            g["_Z"] = g["_integers"](MPNumber)
        _MP_KERNELS[key] = types.FunctionType(fn.__code__, g, fn.__name__)
    return _MP_KERNELS[key]


def precise_runs(ks, names, X, dps):
    """Two evaluations of the kernels ``names`` at the poses X (N, 6) on mpmath numbers:
    ({name: object array of mpf} at ``dps`` digits, the same at ``dps + GUARD``)."""
    import mpmath
    runs = []
    for digits in (dps, dps + GUARD):
        with mpmath.workdps(digits):
            res = {}
            for n in names:
                fn = on_mpmath(getattr(ks, n))
                res[n] = np.array([_mp_call(fn, x, i, n, digits) for i, x in enumerate(X)],
                                  dtype=object)
            runs.append(res)
    return runs


def _mp_call(fn, x, i, name, digits):
    """The kernel ``fn`` at pose ``x`` (pose i) on mpmath numbers; a division by zero in
    it (a degenerate leg the caller did not name first) is a
    :class:`SingularConfigurationError` naming the pose, not mpmath's bare error."""
    try:
        return _unwrap(fn([MPNumber(float(c)) for c in x]))
    except ZeroDivisionError:
        raise SingularConfigurationError(
            f"expected the {name} kernel to be defined at pose {i}, got a division by zero "
            f"at {digits} digits: a leg there is degenerate (a serial singularity or a "
            f"prismatic leg of zero length)", field="poses") from None


def estimate(val, ref, dps):
    """Error estimate (float array) of the floats of the mpf array ``val`` (at ``dps``
    digits) against ``ref`` (more digits): |val - ref|, at least 10^(1 - dps)
    max(|val|, 1), plus |float(val) - val| (the floats are what the caller reads next to
    the estimate; ``values`` keeps the digits)."""
    import mpmath
    with mpmath.workdps(dps + GUARD):
        diff = np.vectorize(lambda a, b: float(abs(a - b)), otypes=[float])(val, ref)
        rounding = np.vectorize(lambda a: float_mpf(a)[1], otypes=[float])(val)
    mag = np.maximum(np.abs(_to_float(val)), 1.0)
    return np.maximum(diff, mag * 10.0 ** (1 - dps)) + rounding


def _unwrap(v):
    if isinstance(v, list):
        return [_unwrap(x) for x in v]
    return v.v if isinstance(v, MPNumber) else v
