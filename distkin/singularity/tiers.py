"""Number types of the singularity tests (:mod:`.conditions`), and their input checks.

The tiers of docs/design.md §3: ``fast`` (float64, batched over leading axes),
``precise`` (mpmath object arrays), ``certified`` (flint ``fmpq`` exact or ``arb``
balls), plus sympy numbers for exact symbolic checks.  Every public entry point of
:mod:`.conditions` and :mod:`.paths` passes its arrays through :func:`_prepare`, which
refuses booleans, non-finite and complex entries (:class:`~distkin.errors.InputError`
naming the field and the entry) with the shared checks of :mod:`distkin.argcheck`.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from ..argcheck import no_booleans
from ..errors import DegenerateGeometryError, InputError, UncertifiedError
from ..exact import check_method

__all__: list[str] = []     # helpers of distkin.singularity; the public API is in .conditions


def _kind(x) -> str:
    arr = np.asarray(x)
    if arr.dtype != object:
        return "fast"
    first = arr.ravel()[0]
    name = type(first).__name__
    if (type(first).__module__ or "").startswith("sympy"):
        return "sympy"
    if name in ("arb", "fmpq", "fmpz"):
        return "certified"
    if name == "mpf":
        return "precise"
    if isinstance(first, (int, Fraction)):
        return "exact"
    return "fast"


def _cross(a, b):
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def _sqrt(x, kind):
    if kind == "fast":
        return np.sqrt(x)
    if kind == "precise":
        import mpmath
        return np.vectorize(mpmath.sqrt, otypes=[object])(x)
    if kind == "sympy":
        import sympy
        return np.vectorize(sympy.sqrt, otypes=[object])(x)
    import flint
    return np.vectorize(lambda v: flint.arb(v).sqrt(), otypes=[object])(x)


def _det(M, kind):
    """Determinant of (..., n, n): batched float, or one object matrix."""
    if kind == "fast":
        return np.linalg.det(np.asarray(M, dtype=float))
    M = np.asarray(M, dtype=object)
    if M.ndim != 2:
        raise InputError(f"expected one matrix in the {kind} tier, got shape {M.shape}")
    n = M.shape[0]
    if kind == "precise":
        from ..exact import mp_det
        return mp_det(M.tolist())            # not mpmath.det: see mp_det
    if kind == "sympy":
        import sympy
        return sympy.expand(sympy.Matrix(M.tolist()).det(method="berkowitz"))
    import flint
    flat = [_to_flint(x) for x in M.ravel()]
    if all(type(v).__name__ == "fmpq" for v in flat):
        return flint.fmpq_mat(n, n, flat).det()
    zero = np.array([v == 0 for v in flat]).reshape(n, n)   # arb: exact zero only
    if zero.all(axis=0).any() or zero.all(axis=1).any():
        return flint.arb(0)                  # a zero row or column: det exactly 0
    return flint.arb_mat(n, n, [flint.arb(v) if type(v).__name__ != "arb" else v
                                for v in flat]).det()


def _to_flint(x):
    import flint
    if isinstance(x, Fraction):
        return flint.fmpq(x.numerator, x.denominator)
    if isinstance(x, (int, np.integer)):
        return flint.fmpq(int(x))
    if isinstance(x, (float, np.floating)):
        f = Fraction(float(x))
        return flint.fmpq(f.numerator, f.denominator)
    return x


def _finite(v) -> bool:
    """False for a NaN or infinite float, mpf, arb or sympy value (exact ones are finite)."""
    if isinstance(v, (float, np.floating)):
        return math.isfinite(v)
    name = type(v).__name__
    if name == "arb":
        return v.is_finite()
    if name == "mpf":
        import mpmath
        return mpmath.isfinite(v)
    if (type(v).__module__ or "").startswith("sympy"):
        return v.is_finite is not False and not v.has(__import__("sympy").nan)
    return True


def _checked(points, field: str) -> np.ndarray:
    """``points`` as an array; a boolean, a complex or a NaN/inf entry is an
    :class:`InputError` naming ``field`` and the entry.  Float arrays cost one
    ``isfinite`` pass; object arrays (exact tiers) one pass over the entries."""
    if isinstance(points, np.ndarray):
        arr = points
    else:
        no_booleans(points, field)            # in a list numpy would read True as 1
        try:
            arr = np.asarray(points)
        except (TypeError, ValueError):
            got = repr(points)
            raise InputError(f"expected an array of numbers, got "
                             f"{got if len(got) <= 80 else got[:77] + '...'}",
                             field=field) from None
    kind = arr.dtype.kind
    if kind in "iuU":
        return arr
    if kind == "f":
        if not np.isfinite(arr).all():
            idx = tuple(np.argwhere(~np.isfinite(arr))[0])
            raise InputError(f"expected finite coordinates, got {arr[idx]}",
                             field=field + "".join(f"[{int(i)}]" for i in idx))
        return arr
    if kind == "O":
        no_booleans(arr, field)
        for idx, v in np.ndenumerate(arr):
            if not _finite(v):
                raise InputError(f"expected finite coordinates, got {v}",
                                 field=field + "".join(f"[{int(i)}]" for i in idx))
        return arr
    if kind == "b":
        no_booleans(arr, field)
    raise InputError(f"expected real coordinates, got an array of dtype {arr.dtype}", field=field)


def _prepare(points, method, field: str = "points"):
    """points -> array in the tier's type; method None keeps the input's type.  Input
    checks (:func:`_checked`) name ``field``."""
    arr = _checked(points, field)
    if method is None:
        kind = _kind(arr)
        if kind == "exact":
            arr = np.vectorize(_to_flint, otypes=[object])(arr)
            kind = "certified"
        return arr, kind
    check_method(method)
    if method == "fast":
        if arr.dtype == object:
            arr = np.vectorize(_float, otypes=[float])(arr)
        return np.asarray(arr, dtype=float), "fast"
    if method == "precise":
        import mpmath
        return np.vectorize(lambda v: v if type(v).__name__ == "mpf" else mpmath.mpf(_float_or_str(v)),
                            otypes=[object])(arr), "precise"
    return np.vectorize(_to_flint, otypes=[object])(np.asarray(arr, dtype=object)), "certified"


def _sympify(v):
    import sympy
    return sympy.sympify(v)


def _float(v):
    if type(v).__name__ == "arb":
        return float(v.mid())
    if type(v).__name__ == "fmpq":
        return int(v.p) / int(v.q)
    return float(v)


def _float_or_str(v):
    import mpmath
    if isinstance(v, Fraction):
        return mpmath.mpf(v.numerator) / v.denominator
    if type(v).__name__ == "fmpq":
        return mpmath.mpf(int(v.p)) / int(v.q)
    if type(v).__name__ == "arb":
        return mpmath.mpf(v.mid().str(mpmath.mp.dps + 5, radius=False))
    return mpmath.mpf(v)


def _check_legs(sq, kind):
    """Refuse a leg of zero length (its line, a row of eq. (5), is undefined):
    :class:`DegenerateGeometryError` naming the leg (and the batch index), in every tier;
    an arb ball of the squared length that contains 0 is :class:`UncertifiedError`."""
    if kind == "fast":
        if (sq > 0).all():
            return
        idx = tuple(int(i) for i in np.argwhere(~(sq > 0))[0])
    else:
        for idx, v in np.ndenumerate(np.asarray(sq, dtype=object)):
            if type(v).__name__ == "arb" and not v > 0 and not v.is_zero():
                raise UncertifiedError(f"expected a leg length ball excluding 0, got squared "
                                       f"length {v.str(5, radius=True)} for leg {idx[-1] + 1}"
                                       f"{_at(idx[:-1])}", field="platform_joints",
                                       hint="raise the precision")
            if v == 0 or getattr(v, "is_zero", None) is True:
                break
        else:
            return
    k = idx[-1]
    raise DegenerateGeometryError(
        f"expected legs of non-zero length, got leg {k + 1} of length 0 (base_joints[{k}] = "
        f"platform_joints[{k}]{_at(idx[:-1])}): its line is undefined", field="platform_joints",
        hint="normalised=False gives det Jhat = l1...l6 det J, defined (0) there")


def _at(batch) -> str:
    return f" at batch index {tuple(batch)}" if len(batch) else ""
