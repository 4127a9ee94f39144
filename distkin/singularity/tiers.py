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
from ..exact import check_method, default_dps, dps_without_precise

__all__: list[str] = []     # helpers of distkin.singularity; the public API is in .conditions


def _kind(x) -> str:
    """The tier of ``x``'s numbers: "fast" (a numeric dtype, or input that is not an
    array of numbers: :func:`_checked` refuses it), "precise" (mpf), "certified" (arb,
    fmpq), "exact" (int, Fraction) or "sympy"; an object array by its first entry."""
    if isinstance(x, np.ndarray):
        arr = x
    else:
        try:
            arr = np.asarray(x)
        except (TypeError, ValueError):       # ragged: refused by _checked
            return "fast"
    if arr.dtype != object or not arr.size:
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


def _digits(dps, method, *inputs):
    """The decimal digits of the precise tier, or None where the computation is not in
    it: ``dps`` (5..1233) only with method "precise"; else 30 (:func:`distkin.exact.default_dps`)
    with method "precise", or with method None and mpf ``inputs``."""
    if dps is not None:
        digits = default_dps(dps)
        if method != "precise":
            raise dps_without_precise(dps, method)
        return digits
    if method == "precise" or (method is None and any(_kind(x) == "precise" for x in inputs)):
        return default_dps(None)
    return None


#: the least working precision (bits) of the certified tier's arb balls: python-flint's
#: global default is 53, at which the certified det J of near-singular leg sets was an
#: undecided ball 40,203 times in 189,889 (QA 23d 5); a caller's higher ``flint.ctx.prec``
#: is kept
CERTIFIED_BITS = 128


def _precision(dps, method, *inputs):
    """A context: ``mpmath.workdps`` at :func:`_digits` where the tier is precise (its
    own default, never mpmath's global ``mp.dps``: QA 23 found 15 digits used); where it
    is certified, arb balls at no fewer than :data:`CERTIFIED_BITS` bits; a null
    context otherwise."""
    import contextlib
    digits = _digits(dps, method, *inputs)
    if digits is None:
        if method == "certified" or (method is None and any(_kind(x) == "certified"
                                                            for x in inputs)):
            import flint
            from ..exact_roots import working_precision
            return working_precision(max(flint.ctx.prec, CERTIFIED_BITS))
        return contextlib.nullcontext()
    import mpmath
    return mpmath.workdps(digits)


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
    if (type(x).__module__ or "").startswith("sympy"):    # a numeric string's exact value
        from ..exact import to_tier
        return to_tier(x, "certified")
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
    """``points`` as an array; a boolean, a complex or a NaN/inf entry, or one that is not
    a number, is an :class:`InputError` naming ``field`` and the entry (its type).  Float
    arrays cost one ``isfinite`` pass; object arrays (exact tiers) one pass over the
    entries.  Numeric strings are exact (:func:`distkin.exact.parse_exact`: ``"1/3"``,
    ``"sqrt(2)"``), as in a scene: an object array of Fraction or sympy values (QA 23:
    ``"abc"`` and ``None`` were raw ValueError / TypeError)."""
    if isinstance(points, np.ndarray):
        arr = points
    else:
        no_booleans(points, field)            # in a list numpy would read True as 1
        try:
            arr = np.asarray(points)
        except (TypeError, ValueError):
            raise InputError(f"expected an array of numbers (a regular shape such as "
                             f"(..., 6, 3)), got {_shown(points)}", field=field) from None
        if arr.dtype.kind in "US":            # a mixed list: keep each entry's own type
            arr = np.array(points, dtype=object)
    kind = arr.dtype.kind
    if kind in "iu":
        return arr
    if kind == "f":
        if not np.isfinite(arr).all():
            idx = tuple(np.argwhere(~np.isfinite(arr))[0])
            raise InputError(f"expected finite coordinates, got {arr[idx]}",
                             field=field + "".join(f"[{int(i)}]" for i in idx))
        return arr
    if kind in "US":
        arr = arr.astype(object)
        kind = "O"
    if kind == "O":
        no_booleans(arr, field)
        if not arr.ndim:
            raise InputError(f"expected an array of numbers, got {_shown(arr.item())}",
                             field=field)
        out = np.empty(arr.shape, dtype=object)
        for idx, v in np.ndenumerate(arr):
            name = field + "".join(f"[{int(i)}]" for i in idx)
            v = _number(v, name)
            if not _finite(v):
                raise InputError(f"expected finite coordinates, got {v}", field=name)
            out[idx] = v
        return out
    if kind == "b":
        no_booleans(arr, field)
    raise InputError(f"expected real coordinates, got an array of dtype {arr.dtype}", field=field)


def _shown(v) -> str:
    got = f"{type(v).__name__} {v!r}"
    return got if len(got) <= 80 else got[:77] + "..."


def _number(v, field: str):
    """One entry of an object array: a real number of a tier as it is (numpy scalars as
    Python numbers), a numeric string parsed exactly (a Fraction, or a sympy number),
    anything else an :class:`InputError` naming ``field`` and the type."""
    if isinstance(v, str):
        from ..exact import parse_exact
        return parse_exact(str(v), field).value
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, (int, float, Fraction, np.floating)):
        return v
    name, module = type(v).__name__, type(v).__module__ or ""
    if name in ("mpf", "arb", "fmpq", "fmpz"):
        return v
    if module.startswith("sympy") and getattr(v, "is_number", False) and v.is_real is not False:
        return v
    raise InputError(f"expected real numbers (float, int, Fraction, numeric string, mpf, fmpq, "
                     f"arb or a sympy number), got {_shown(v)}", field=field)


def _prepare(points, method, field: str = "points"):
    """points -> array in the tier's type; method None keeps the input's type (an integer
    array is float64, the fast tier's; exact Python ints and Fractions, and numeric
    strings, certified).  Input checks (:func:`_checked`) name ``field``."""
    if method is not None:
        check_method(method)
    had_strings = _has_strings(points)
    arr = _checked(points, field)
    if method is None:
        kind = "exact" if had_strings else _kind(arr)
        if kind == "exact":
            arr = np.vectorize(_to_flint, otypes=[object])(arr)
            kind = "certified"
        elif kind == "fast":
            arr = np.asarray(arr, dtype=float)   # (integers: QA 23, AttributeError)
        return arr, kind
    if method == "fast":
        if arr.dtype == object:
            arr = _converted(arr, _float, field)
        return np.asarray(arr, dtype=float), "fast"
    if method == "precise":
        import mpmath
        return np.vectorize(lambda v: v if type(v).__name__ == "mpf" else mpmath.mpf(_float_or_str(v)),
                            otypes=[object])(arr), "precise"
    return np.vectorize(_to_flint, otypes=[object])(np.asarray(arr, dtype=object)), "certified"


def _has_strings(points) -> bool:
    """True for a string array, or a list / tuple whose first leaf entry is a string (a
    numeric string is exact input)."""
    if isinstance(points, np.ndarray):
        return points.dtype.kind in "US" or (points.dtype == object and points.size > 0
                                             and isinstance(points.flat[0], str))
    while isinstance(points, (list, tuple)) and points:
        points = points[0]
    return isinstance(points, str)


def _converted(arr, to, field: str):
    """``to`` (:func:`_float`) of every entry as a float array; a value beyond float64
    (an exact 1e400) is an :class:`InputError` naming its entry."""
    from ..argcheck import floats_in_range
    return floats_in_range(arr, to, field, "coordinates within float64's range "
                           "(|x| < 1.8e308) for method 'fast'", show=_shown,
                           hint="method='precise' or 'certified'")


def _sympify(v):
    import sympy
    return sympy.sympify(v)


def _float(v):
    if type(v).__name__ == "arb":
        return float(v.mid())
    if type(v).__name__ == "fmpq":
        return float(Fraction(int(v.p), int(v.q)))
    if type(v).__name__ == "fmpz":
        return float(int(v))
    out = float(v)
    if not math.isfinite(out):                # a sympy or mpf value beyond float64
        raise OverflowError(f"{v} is beyond float64")
    return out


def _float_or_str(v):
    import mpmath
    if isinstance(v, Fraction):
        return mpmath.mpf(v.numerator) / v.denominator
    if type(v).__name__ == "fmpq":
        return mpmath.mpf(int(v.p)) / int(v.q)
    if type(v).__name__ == "arb":
        return mpmath.mpf(v.mid().str(mpmath.mp.dps + 5, radius=False))
    if (type(v).__module__ or "").startswith("sympy"):
        from ..exact import to_tier
        return to_tier(v, "precise")
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
