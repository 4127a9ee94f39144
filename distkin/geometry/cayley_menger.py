r"""Cayley-Menger determinants with 1-based point labels.

Notation of Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*
(ICRA 2012), eq. (1):

.. math::

    D(i_1,\dots,i_n; j_1,\dots,j_n) =
    \begin{vmatrix} 0 & 1 & \cdots & 1 \\
                    1 & s_{i_1 j_1} & \cdots & s_{i_1 j_n} \\
                    \vdots & & \ddots & \vdots \\
                    1 & s_{i_n j_1} & \cdots & s_{i_n j_n} \end{vmatrix},
    \qquad D(i_1,\dots,i_n) = D(i_1,\dots,i_n; i_1,\dots,i_n)

where :math:`s_{ij}` is the squared distance between :math:`P_i` and :math:`P_j`.

Sign conventions (the raw bordered determinant, exactly as displayed above):

* two points: :math:`D(i,j) = 2 s_{ij}` (never negative);
* three points: :math:`D(i,j,k) = -16 A_{ijk}^2` (never positive for a real triangle);
* four points: :math:`D(i,j,k,l) = 288 V_{ijkl}^2` (never negative for a real tetrahedron);
* five points in 3-D: :math:`D = 0`.

The paper's eq. (3) writes :math:`A_{ijk} = \tfrac14 D(i,j,k)` and
:math:`V_{ijkl} = \tfrac16\sqrt{D(i,j,k,l)}`; those use the normalised determinant of
Porta, Ros and Thomas (ref. [1] there), which is :math:`(-1)^n D / 2^{n-1}` of the raw one
for three and four points.  In general the raw determinant of n points is
:math:`(-1)^n\, 2^{n-1} ((n-1)!)^2` times the squared (n-1)-volume of their simplex.
:func:`triangle_area_squared` and :func:`tetrahedron_volume_squared` return the true
squared area and volume whatever the convention.

The result has the number type of the input: a sympy expression, ``float`` (numpy,
batched over leading axes), ``mpmath.mpf``, ``flint.fmpq``, ``flint.arb``, or
``fractions.Fraction`` for plain ints and Fractions.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from fractions import Fraction

import numpy as np

from ..errors import InputError
from ..exact import check_method, default_dps, dps_without_precise, parse_exact
from .cm_float import (CancellationWarning, FloatRangeWarning, _bordered, _bordered_array,
                       _float_mismatch, _refuse, _refuse_range, _symmetric_array,
                       float_determinant)

__all__ = [
    "FloatRangeWarning",
    "CancellationWarning",
    "cayley_menger",
    "squared_distances",
    "triangle_area_squared",
    "tetrahedron_volume_squared",
    "parse_label",
]


def _exact_strings(arr, field):
    """A copy of the object array ``arr`` with numeric strings parsed exactly
    (:func:`distkin.exact.parse_exact`: ``"19.8"`` -> 99/5, ``"sqrt(2)"`` -> a sympy
    number), as everywhere in distkin; other entries unchanged."""
    out = np.array(arr, dtype=object, copy=True)
    for idx, v in np.ndenumerate(out):
        if isinstance(v, str):
            out[idx] = parse_exact(v, field + "".join(f"[{i}]" for i in idx)).value
    return out


def _float_entry(v, i, j):
    """s(i, j) = ``v`` (a float, int, Fraction or fmpq) as a float64: a value beyond the
    float64 range (``10**400``) is an :class:`InputError` naming the entry (as
    :func:`distkin.exact.parse_float` words it), not Python's OverflowError."""
    try:
        x = float(v)
    except OverflowError:
        x = math.inf
    if math.isinf(x) and not isinstance(v, (float, np.floating)):
        _refuse_range(i, j, v)
    return x


def _float_matrix(arr):
    """The object array ``arr`` (n, n) of floats and exact numbers as float64 (entries
    beyond the float64 range refused by :func:`_float_entry`)."""
    out = np.empty(arr.shape)
    for (a, b), v in np.ndenumerate(arr):
        out[a, b] = _float_entry(v, a + 1, b + 1)
    return out


def _kind_of(values, what: str = "squared distances", field: str = "sq") -> str:
    kinds = set()
    for v in values:
        t = type(v)
        name = t.__name__
        mod = t.__module__ or ""
        if mod.startswith("sympy"):
            kinds.add("sympy")
        elif name == "arb":
            kinds.add("arb")
        elif name in ("fmpq", "fmpz"):
            kinds.add("fmpq")
        elif name == "mpf" or mod.startswith("mpmath"):
            kinds.add("mpf")
        elif isinstance(v, (bool, np.bool_)):
            raise InputError(f"expected {what} as numbers, got the boolean {v!r}", field=field)
        elif isinstance(v, (int, Fraction, np.integer)):
            kinds.add("exact")
        elif isinstance(v, (float, np.floating)):
            kinds.add("float")
        else:
            raise InputError(f"expected {what} as numbers, got {name} {v!r}", field=field)
    for k in ("sympy", "arb", "mpf", "fmpq", "float", "exact"):
        if k in kinds:
            if k == "fmpq" and "float" in kinds:
                return "float"
            return k
    return "exact"


def _accessor(sq):
    """Return (s(i, j) with 1-based labels, number of points or None, kind)."""
    if isinstance(sq, Mapping):
        table = {}
        for key, val in sq.items():
            if (not isinstance(key, tuple) or len(key) != 2
                    or not all(isinstance(k, int) and not isinstance(k, bool) and k >= 1
                               for k in key)):
                raise InputError(f"expected keys (i, j) with 1-based integer labels, got {key!r}",
                                 field="sq")
            if isinstance(val, str):
                val = parse_exact(val, f"sq[{key!r}]").value
            if key[0] == key[1]:
                if val != 0:
                    raise InputError(f"expected s({key[0]},{key[0]}) = 0 (a point's squared "
                                     f"distance to itself), got {val!r}", field="sq")
                continue
            if key[::-1] in table and table[key[::-1]] != val:
                raise InputError(f"expected one squared distance per pair, got s{key} = {val!r} "
                                 f"and s{key[::-1]} = {table[key[::-1]]!r}", field="sq")
            table[key] = val
            table[key[::-1]] = val

        def s(i, j):
            if i == j:
                return 0
            try:
                return table[(i, j)]
            except KeyError:
                raise InputError(f"squared distance s({i},{j}) is missing from the mapping",
                                 field="sq") from None

        kind = _kind_of(table.values())
        if kind == "float":                # floats mixed with exact values: all floats
            table = {k: _float_entry(v, *k) for k, v in table.items()}
        return s, None, kind
    mod = type(sq).__module__ or ""
    if mod.startswith("sympy"):
        if sq.rows != sq.cols:
            raise InputError(f"expected a square matrix, got shape {sq.shape}", field="sq")
        return (lambda i, j: sq[i - 1, j - 1]), sq.rows, "sympy"
    if mod.startswith("mpmath") and hasattr(sq, "rows") and hasattr(sq, "cols"):
        # an mpmath.matrix iterates as one flat sequence (numpy read it as shape (n², ),
        # QA 2026-11-29): its rows, as the nested lists of mpf it equals
        sq = [[sq[i, j] for j in range(sq.cols)] for i in range(sq.rows)]
    arr = np.asarray(sq, dtype=object) if not isinstance(sq, np.ndarray) else sq
    if arr.ndim < 2 or arr.shape[-1] != arr.shape[-2]:
        raise InputError(f"expected a square array of squared distances, got shape {arr.shape}",
                         field="sq")
    if arr.dtype.kind in "OU":
        arr = _exact_strings(arr, "sq")
    if arr.dtype != object:
        if not np.issubdtype(arr.dtype, np.number):
            raise InputError(f"expected numeric squared distances, got dtype {arr.dtype}",
                             field="sq")
        kind = "float" if np.issubdtype(arr.dtype, np.floating) else "exact"
        if kind == "float":
            return (lambda i, j: arr[..., i - 1, j - 1]), arr.shape[-1], "float"
        arr = arr.astype(object)
    if arr.ndim != 2:
        raise InputError(f"expected one square array (n, n) of exact values, got shape {arr.shape}",
                         field="sq")
    kind = _kind_of(arr.ravel().tolist())
    if kind == "float":
        arr = _float_matrix(arr)
        return (lambda i, j: arr[i - 1, j - 1]), arr.shape[-1], "float"
    return (lambda i, j: arr[i - 1, j - 1]), arr.shape[0], kind


_LABEL_FORM = ("a determinant label like 'D(1,2,3,4)' or 'D(5,4,1,2;5,4,1,6)' (one list "
               "of 1-based point labels, or two lists of the same length)")


def parse_label(text: str):
    """Parse ``"D(5,4,1,2;5,4,1,6)"`` or ``"5,4,1,2"`` into (rows, cols).

    ``cols`` is None for a single list.  Raises :class:`InputError` quoting the text
    on any fault: not of that form, an empty list, a label below 1, or two lists of
    different lengths (``"D(5,4;1)"``).
    """
    import re
    t = str(text).strip()
    m = re.fullmatch(r"D\((.*)\)", t, flags=re.S)
    body = m.group(1) if m else t
    parts = body.split(";")
    lists = r"\s*\d+\s*(,\s*\d+\s*)*"
    if len(parts) > 2 or not all(re.fullmatch(lists, p, flags=re.A) for p in parts):
        raise InputError(f"expected {_LABEL_FORM}, got {text!r}")
    groups = [tuple(int(x) for x in p.split(",")) for p in parts]
    if any(x < 1 for g in groups for x in g):
        raise InputError(f"expected {_LABEL_FORM}, got {text!r} (labels start at 1)")
    if len(groups) == 2 and len(groups[0]) != len(groups[1]):
        raise InputError(f"expected {_LABEL_FORM}, got {text!r} ({len(groups[0])} row "
                         f"labels and {len(groups[1])} column labels)")
    rows = groups[0]
    cols = groups[1] if len(groups) == 2 else None
    return rows, cols


def _label_tuple(labels, name: str) -> tuple:
    """``rows`` or ``cols`` as a tuple; a single label or None is an InputError naming
    the argument (a bare ``5`` is not ``(5,)``: D(5) is not what was meant)."""
    if isinstance(labels, (str, bytes)) or not hasattr(labels, "__iter__"):
        raise InputError(f"expected a sequence of 1-based point labels for {name}, such as "
                         f"(1, 2, 3, 4), got {labels!r}")
    return tuple(labels)


def _check_labels(rows, cols, n):
    for name, labels in (("rows", rows), ("cols", cols)):
        for lab in labels:
            if not isinstance(lab, (int, np.integer)) or isinstance(lab, bool) or lab < 1:
                raise InputError(f"expected 1-based integer point labels, got {lab!r} in {name}")
            if n is not None and lab > n:
                raise InputError(f"label {lab} is out of range: the source has {n} points "
                                 f"(labels 1..{n})")
    if len(rows) != len(cols):
        raise InputError(f"expected as many row labels as column labels, got {len(rows)} "
                         f"and {len(cols)}")
    if len(rows) < 1:
        raise InputError("expected at least one label")


def cayley_menger(sq, rows, cols=None, *, method: str | None = None, dps: int | None = None):
    r"""The Cayley-Menger (bi)determinant :math:`D(\text{rows}; \text{cols})`.

    Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*, eq. (1) notation.

    Parameters
    ----------
    sq : array_like (..., n, n), sympy.Matrix, or mapping {(i, j): s_ij}
        Squared distances, indexed by 1-based labels (label ``i`` is row ``i - 1``):
        finite and >= 0 (those the determinant uses; symbols pass), numbers of any tier
        or numeric strings (parsed exactly, as everywhere in distkin).
        A float array may carry leading batch axes; the determinant is batched.
    rows : sequence of int
        1-based labels :math:`i_1, \dots, i_k`.
    cols : sequence of int, optional
        1-based labels :math:`j_1, \dots, j_k`; defaults to ``rows``.
    method : {None, "fast", "precise", "certified"}
        ``None``: the input's own number type (below).  ``"fast"``: float64 (numpy LU,
        batched), with a relative error estimate from Hadamard's inequality
        (:mod:`.cm_float`): above 1e-6 a :class:`~.cm_float.CancellationWarning` says
        the value lost most of its digits (a nearly flat simplex, or a determinant that
        is 0 exactly, like five points in 3-D); an exact entry beyond the float64 range
        is an InputError.  ``"precise"``: ``mpmath.mpf`` at ``dps`` digits (default 30):
        when every entry is rational (ints, Fractions, fmpq, numeric strings, floats and
        mpf at their binary values) the exact determinant correctly rounded, so 0 only
        when it is 0; otherwise (irrational sympy numbers, arb midpoints) LU at ``dps``
        + 20 digits, with a CancellationWarning where the error estimate exceeds
        :math:`10^{-dps}` (the value may have fewer than ``dps`` right digits, or be 0).
        ``"certified"``: exact ``flint.fmpq`` when every
        entry is rational (ints, Fractions, numeric strings, and floats taken at their
        exact binary value: the determinant of exactly those numbers), else an
        ``flint.arb`` ball (irrational sympy numbers, arb input) with a certified
        radius.  Precise and certified evaluate a batch one matrix at a time (an
        object array of the batch shape).
    dps : int, optional
        Decimal digits of the precise tier (5..1233); only with ``method="precise"``
        (another tier would ignore it: InputError).

    Returns
    -------
    number
        Of the input's type (see the module docstring) when ``method`` is None, else of
        the tier's; a float array of the batch shape for batched float input (fast).

    Raises
    ------
    InputError
        Bad labels, a non-square array, entries that are not numbers, a squared
        distance that is NaN, infinite or negative (in every tier), one beyond the
        float64 range where float64 is asked for, or ``dps`` without ``"precise"``.

    Examples
    --------
    >>> import numpy as np
    >>> P = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> round(float(cayley_menger(squared_distances(P), (1, 2, 3, 4))) / 288, 12)  # V^2 = 1/36
    0.027777777778
    """
    if method is not None:
        check_method(method)
    if dps is not None:
        _check_dps(dps, method)
    if isinstance(sq, np.ndarray) and sq.ndim > 2 and sq.dtype.kind in "iuOU":
        out = np.empty(sq.shape[:-2], dtype=object)  # batched exact: each matrix exactly
        for idx in np.ndindex(*sq.shape[:-2]):
            out[idx] = cayley_menger(sq[idx], rows, cols, method=method, dps=dps)
        return out
    s, n, kind = _accessor(sq)
    rows = _label_tuple(rows, "rows")
    cols = rows if cols is None else _label_tuple(cols, "cols")
    _check_labels(rows, cols, n)
    if n is not None:
        labels = sorted(set(rows) | set(cols))
        if not (kind == "float" and _symmetric_array(sq, labels)):
            _check_symmetric(s, labels, kind)
    k = len(rows)
    label = "D(" + ",".join(map(str, rows)) + ("" if cols == rows else
                                               ";" + ",".join(map(str, cols))) + ")"
    if kind == "float" and method in (None, "fast"):
        M = (_bordered_array(sq, rows, cols)
             if isinstance(sq, np.ndarray) and np.issubdtype(sq.dtype, np.floating)
             else _bordered(s, rows, cols))
        return float_determinant(M, k, label)
    if kind == "float" and isinstance(sq, np.ndarray) and sq.ndim > 2:   # batched: each
        out = np.empty(sq.shape[:-2], dtype=object)
        for idx in np.ndindex(*sq.shape[:-2]):
            out[idx] = cayley_menger(sq[idx], rows, cols, method=method, dps=dps)
        return out
    entries = [[0] + [1] * k]
    for i in rows:
        entries.append([1] + [0 if i == j else _checked(s(i, j), i, j, kind) for j in cols])
    if method is not None:
        from .cm_tiers import tier_determinant
        return tier_determinant(entries, k, method, dps, label, rows, cols)
    if kind == "sympy":
        import sympy
        return sympy.expand(sympy.Matrix(entries).det(method="berkowitz"))
    if kind == "mpf":
        from ..exact import mp_det
        return mp_det(entries)               # not mpmath.det: see mp_det
    import flint
    flat = [x for row in entries for x in row]
    if kind == "arb":
        return flint.arb_mat(k + 1, k + 1, [flint.arb(x) if type(x).__name__ != "arb" else x
                                            for x in _to_flint_list(flat)]).det()
    det = flint.fmpq_mat(k + 1, k + 1, _to_flint_list(flat)).det()
    if kind == "exact":
        return Fraction(int(det.p), int(det.q))
    return det


def _check_dps(dps, method):
    """``dps`` only with method "precise" (the tier that reads it; ignored otherwise, so
    refused as by the other entry points), an integer 5..1233."""
    try:
        default_dps(dps)
    except InputError as exc:
        raise InputError(exc.message, field="dps") from None
    if method != "precise":
        raise dps_without_precise(dps, method)


def _check_ragged(points):
    """Rows of different lengths (a ragged list, which numpy refuses with a ValueError):
    an InputError naming the first row whose length differs from the first's (QA J 8)."""
    if isinstance(points, (str, bytes)) or not isinstance(points, Sequence):
        return
    lens = [len(r) if isinstance(r, (Sequence, np.ndarray)) and not isinstance(r, str)
            else None for r in points]
    if not lens or lens[0] is None:
        return
    for i, n in enumerate(lens):
        if n != lens[0]:
            got = "a scalar" if n is None else f"{n} coordinates"
            raise InputError(f"expected every point with {lens[0]} coordinates (points of "
                             f"shape (n, {lens[0]})), got {got}", field=f"points[{i}]")


def _check_symmetric(s, labels, kind):
    """Refuse a matrix that is not one of squared distances on ``labels``: s(i, j) must
    equal s(j, i) and s(i, i) must be 0 (floats within 8 ulps of the larger entry, arb
    balls when they cannot overlap, sympy when the difference is not provably 0, other
    numbers exactly).  The determinant reads only one triangle of the matrix, so an
    asymmetric one would otherwise give the determinant of another configuration."""
    where = ""

    def differ(a, b):
        nonlocal where
        if kind == "float":
            a, b = np.asarray(a, float), np.asarray(b, float)
            bad = _float_mismatch(a, b)
            if bad.ndim and bad.any():
                first = tuple(int(x) for x in np.argwhere(bad)[0])
                where = f" (batch index {first}: {float(a[first])!r} and {float(b[first])!r})"
            return bool(np.any(bad))
        if kind == "sympy":
            import sympy
            d = sympy.expand(sympy.sympify(a) - sympy.sympify(b))
            return d != 0 and d.is_zero is not True
        if kind == "arb":
            import flint
            return not flint.arb(a).overlaps(flint.arb(b))
        if kind == "mpf":
            import mpmath
            return abs(a - b) > 8 * mpmath.mp.eps * max(abs(a), abs(b))
        return a != b
    for a, i in enumerate(labels):
        if differ(s(i, i), 0):
            raise InputError(f"expected s({i},{i}) = 0 (a point's squared distance to "
                             f"itself), got {_show(s(i, i))}", field="sq")
        for j in labels[a + 1:]:
            if differ(s(i, j), s(j, i)):
                raise InputError(f"expected a symmetric matrix of squared distances, got "
                                 f"s({i},{j}) = {_show(s(i, j))} and s({j},{i}) = "
                                 f"{_show(s(j, i))}{where}", field="sq")


def _show_big(v):
    """A number beyond float64 for a message (8 significant digits)."""
    import mpmath
    from ..exact import to_tier
    with mpmath.workdps(15):
        return mpmath.nstr(to_tier(v, "precise"), 8)


def _show(v):
    if isinstance(v, np.ndarray) and v.ndim:
        return "an array"
    if isinstance(v, (np.floating, np.ndarray)):
        return repr(float(v))
    if isinstance(v, np.integer):
        return repr(int(v))
    return repr(v)


def _checked(v, i, j, kind):
    """``v`` = s(i, j) if it is a squared distance: finite and not negative (an arb ball
    or a sympy expression only when certainly negative; symbols pass)."""
    if isinstance(v, np.ndarray) and v.ndim == 0:
        v = v[()]                          # a float array's entry: a numpy scalar
    tname = type(v).__name__
    if (type(v).__module__ or "").startswith("sympy"):
        import sympy
        if v.is_negative or (v.is_number and (v.is_finite is False or v.has(sympy.nan))):
            _refuse(i, j, v)
    elif tname == "arb":
        if not v.is_finite() or v < 0:
            _refuse(i, j, v)
    elif tname == "mpf":
        import mpmath
        if not mpmath.isfinite(v) or v < 0:
            _refuse(i, j, v)
    elif isinstance(v, (float, np.floating)) and not (math.isfinite(v) and v >= 0):
        _refuse(i, j, float(v))            # NaN and inf too: mpmath would carry them on
    elif v < 0:
        _refuse(i, j, v)
    return v


def _to_flint_list(flat):
    import flint
    out = []
    for x in flat:
        if isinstance(x, Fraction):
            out.append(flint.fmpq(x.numerator, x.denominator))
        elif isinstance(x, (int, np.integer)):
            out.append(flint.fmpq(int(x)))
        else:
            out.append(x)
    return out


def squared_distances(points):
    """The (n, n) matrix of squared distances of n points.

    Parameters
    ----------
    points : array_like (..., n, dim), or a sequence of n points of exact or symbolic
        coordinates (ints, Fractions, fmpq, arb, mpf or sympy expressions, or numeric
        strings, parsed exactly: ``"19.8"`` is 99/5, ``"sqrt(108)"`` a sympy number).

    Returns
    -------
    numpy.ndarray (..., n, n) for float input (a squared distance beyond the float64
    range is an InputError, never inf); a sympy Matrix for sympy input;
    an (..., n, n) object array otherwise (entries of the coordinates' type, Fractions
    for integers; batched exactly, one point set at a time).
    """
    if not isinstance(points, np.ndarray):
        _check_ragged(points)
    arr = np.asarray(points, dtype=object) if not isinstance(points, np.ndarray) else points
    if arr.ndim < 2:
        raise InputError(f"expected points of shape (n, dim), got shape {np.shape(points)}",
                         field="points")
    if arr.dtype != object and np.issubdtype(arr.dtype, np.floating):
        if not np.all(np.isfinite(arr)):
            raise InputError("expected finite coordinates, got NaN or inf", field="points")
        with np.errstate(over="ignore", invalid="ignore"):
            diff = arr[..., :, None, :] - arr[..., None, :, :]
            out = np.einsum("...k,...k->...", diff, diff)
        if not np.all(np.isfinite(out)):
            bad = tuple(int(x) for x in np.argwhere(~np.isfinite(out))[0])
            pair = f"s({bad[-2] + 1},{bad[-1] + 1})"
            raise InputError(f"expected points whose squared distances are within the "
                             f"float64 range (|x| < 1.8e308), got {pair} beyond it"
                             + (f" (batch index {bad[:-2]})" if bad[:-2] else ""),
                             field="points", hint="exact coordinates (ints, Fractions, "
                             "numeric strings) give exact squared distances")
        return out
    if arr.dtype.kind in "OU":
        arr = _exact_strings(arr, "points")
    flat = arr.ravel().tolist()
    kind = _kind_of(flat, "coordinates", "points")
    if kind == "float":
        from ..argcheck import floats_in_range
        out = floats_in_range(arr, float, "points", "coordinates within the float64 range "
                              "(|x| < 1.8e308) among float ones", show=_show_big)
        return squared_distances(out)
    if kind in ("mpf", "arb"):             # exact entries (ints, fmpq) are finite
        import mpmath
        for v in flat:
            name = type(v).__name__
            if (name == "arb" and not v.is_finite()) or (name == "mpf" and
                                                          not mpmath.isfinite(v)):
                raise InputError(f"expected finite coordinates, got {v}", field="points")
    n = arr.shape[0]
    if arr.ndim > 2 and kind != "sympy":         # batched exact: each point set exactly
        out = np.empty(arr.shape[:-1] + arr.shape[-2:-1], dtype=object)
        for idx in np.ndindex(*arr.shape[:-2]):
            out[idx] = squared_distances(arr[idx])
        return out
    if arr.ndim != 2:
        raise InputError(f"expected one point set (n, dim) of exact values, got shape {arr.shape}",
                         field="points")
    if kind == "exact":
        arr = np.vectorize(Fraction, otypes=[object])(arr)
    out = np.empty((n, n), dtype=object)
    for i in range(n):
        out[i, i] = 0 if kind != "sympy" else __import__("sympy").Integer(0)
        for j in range(i + 1, n):
            d = [arr[i, c] - arr[j, c] for c in range(arr.shape[1])]
            v = d[0] * d[0]
            for x in d[1:]:
                v = v + x * x
            out[i, j] = out[j, i] = v
    if kind == "sympy":
        import sympy
        return sympy.Matrix(out.tolist())
    return out


def triangle_area_squared(sq, i: int, j: int, k: int):
    r"""Squared area of the triangle :math:`P_iP_jP_k`: :math:`A^2 = -D(i,j,k)/16`."""
    return -cayley_menger(sq, (i, j, k)) / 16


def tetrahedron_volume_squared(sq, i: int, j: int, k: int, l: int):
    r"""Squared volume of the tetrahedron :math:`P_iP_jP_kP_l`: :math:`V^2 = D(i,j,k,l)/288`."""
    return cayley_menger(sq, (i, j, k, l)) / 288
