"""Input checks, in one place (STYLE.md rule 7).

Every public entry point and every scene handler validates its input through these
helpers, so that messages read the same everywhere: ``FIELD: expected …, got …``.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping

import numpy as np

from .errors import InputError
from .exact import METHODS, Exact, check_method, parse_float, parse_vector

__all__ = [
    "floats_in_range",
    "require",
    "optional",
    "as_table",
    "check_keys",
    "exact_matrix",
    "exact_vector",
    "float_array",
    "as_floats",
    "choice",
    "positive_int",
    "workers_count",
    "MAX_WORKERS",
    "positive_number",
    "pose_list",
    "string_list",
    "method_field",
    "fast_only",
    "executor_fields",
    "scheduler_address",
    "dps_field",
    "relative_tol",
    "tol_field",
    "no_booleans",
    "length_in_range",
    "LENGTH_RANGE",
]

_MISSING = object()


def as_table(value, field: str) -> Mapping:
    if not isinstance(value, Mapping):
        raise InputError(f"expected a table, got {type(value).__name__} {value!r}", field=field)
    return value


def require(table: Mapping, key: str, field: str):
    """``table[key]``, or InputError naming ``field.key`` when missing."""
    if key not in table:
        raise InputError(f"missing required field {key!r}", field=f"{field}.{key}" if field else key)
    return table[key]


def optional(table: Mapping, key: str, default=None):
    return table.get(key, default)


def check_keys(table: Mapping, allowed, field: str):
    """Reject unknown keys (a typo must not be silently ignored)."""
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise InputError(f"unknown field(s) {', '.join(map(repr, unknown))}; expected some of "
                         f"{', '.join(map(repr, sorted(allowed)))}", field=field)


def exact_vector(value, field: str, length: int | None = None, *,
                 allow_symbols: bool = False) -> tuple[Exact, ...]:
    return parse_vector(value, field, length=length, allow_symbols=allow_symbols)


def exact_matrix(value, field: str, rows: int | None = None, cols: int | None = None
                 ) -> tuple[tuple[Exact, ...], ...]:
    """A list of rows of exact numbers, e.g. points ``[[0,0,0], [6,"sqrt(108)",0], ...]``."""
    if not isinstance(value, (list, tuple)):
        raise InputError(f"expected a list of {rows or 'some'} rows, got "
                         f"{type(value).__name__} {value!r}", field=field)
    if rows is not None and len(value) != rows:
        raise InputError(f"expected {rows} rows, got {len(value)}", field=field)
    return tuple(parse_vector(r, f"{field}[{i}]", length=cols) for i, r in enumerate(value))


def as_floats(value, field: str, expected: str = "numbers") -> np.ndarray:
    """``np.asarray(value, dtype=float)`` of any shape; text, ragged lists, booleans
    (:func:`no_booleans`: numpy reads True as 1), complex numbers (numpy drops their
    imaginary part with a warning) and other things that are not real numbers raise
    :class:`InputError` naming ``field``."""
    if isinstance(value, (np.ndarray, np.complexfloating)) and np.iscomplexobj(value):
        raise InputError(f"expected {expected} (real), got complex values", field=field)
    no_booleans(value, field)
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        got = repr(value)
        got = got if len(got) <= 120 else got[:117] + "..."
        raise InputError(f"expected {expected}, got {got}", field=field) from None


def no_booleans(value, field: str) -> None:
    """Refuse a boolean anywhere in numeric input (numpy reads ``True`` as 1 and would
    pass it on as a length): an :class:`InputError` naming its element, e.g.
    ``legs[0]``.  Walks nested lists and tuples and object arrays; a numeric array has
    none."""
    if isinstance(value, (bool, np.bool_)):
        raise InputError(f"expected a number, got the boolean {value!r}", field=field)
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "b" and value.size:
            idx = np.unravel_index(0, value.shape)
            no_booleans(value[idx], field + "".join(f"[{int(i)}]" for i in idx))
        if value.dtype.kind == "O":
            for idx, v in np.ndenumerate(value):
                no_booleans(v, field + "".join(f"[{int(i)}]" for i in idx))
        return
    if isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            no_booleans(v, f"{field}[{i}]")


#: the lengths (m) a mechanism's geometry may have: the generated kernels form powers
#: and products of several lengths, which leave float64's range beyond these (a crank of
#: 1e308 m overflowed, one of 1e-200 m divided by zero: internal failures, not bad input);
#: both are far beyond any device (the observable universe is ~1e27 m)
LENGTH_RANGE = (1e-30, 1e30)


def length_in_range(value: float, field: str, *, zero_ok: bool = False) -> float:
    """``value`` (m, already a finite float) within :data:`LENGTH_RANGE` in magnitude
    (0 too with ``zero_ok``), else an :class:`InputError` naming the field, the bounds
    and the value."""
    lo, hi = LENGTH_RANGE
    if not (lo <= abs(value) <= hi or (zero_ok and value == 0)):
        raise InputError(f"expected a length between {lo:g} and {hi:g} m"
                         f"{' (or 0)' if zero_ok else ''}: the kernels' powers of lengths "
                         f"leave float64's range beyond, got {value!r} m", field=field)
    return value


def floats_in_range(arr, convert, field: str, expected: str, *, show=repr,
                    hint: str | None = None) -> np.ndarray:
    """``convert`` (to float) of every entry of the object array ``arr`` as a float array;
    an entry beyond float64's range (``convert`` raises OverflowError: an exact 1e400)
    is an :class:`InputError` naming the entry (``field[i][j]``), ``expected`` and the
    value as ``show`` gives it."""
    out = np.empty(arr.shape, dtype=float)
    for idx, v in np.ndenumerate(arr):
        try:
            out[idx] = convert(v)
        except OverflowError:
            raise InputError(f"expected {expected}, got {show(v)}",
                             field=field + "".join(f"[{int(i)}]" for i in idx),
                             hint=hint) from None
    return out


def float_array(value, field: str, shape: tuple) -> np.ndarray:
    """A float array of a given shape (``None`` in ``shape`` = any length, shown as N)."""
    shown = "(" + ", ".join("N" if s is None else str(s) for s in shape) + \
        ("," if len(shape) == 1 else "") + ")"
    arr = as_floats(value, field, f"numbers of shape {shown}")
    if arr.ndim != len(shape) or any(s is not None and s != a for s, a in zip(shape, arr.shape)):
        raise InputError(f"expected shape {shown}, got {arr.shape}", field=field)
    if not np.all(np.isfinite(arr)):
        raise InputError("expected finite numbers, got NaN or inf", field=field)
    return arr


def choice(value, field: str, choices) -> str:
    if value not in choices:
        raise InputError(f"expected one of {', '.join(map(repr, choices))}, got {value!r}",
                         field=field)
    return value


def positive_int(value, field: str, *, minimum: int = 1) -> int:
    if not isinstance(value, int) or isinstance(value, bool) or value < minimum:
        raise InputError(f"expected an integer >= {minimum}, got {value!r}", field=field)
    return value


def positive_number(value, field: str) -> float:
    x = parse_float(value, field)
    if not x > 0:
        raise InputError(f"expected a positive number, got {value!r}", field=field)
    return x


def pose_list(value, field: str) -> list:
    """A scene's ``poses``: a non-empty list of rows; a flat list of numbers (one pose
    written without its outer brackets) is refused with a hint."""
    if not isinstance(value, list) or not value:
        raise InputError(f"expected a non-empty list of poses, got {value!r}", field=field)
    if not any(isinstance(r, (list, tuple)) for r in value):
        raise InputError(f"expected a list of poses [[x, y, z, rx, ry, rz], ...], got one "
                         f"flat list of {len(value)} values {value!r}", field=field,
                         hint="write poses = [[...]] or pose = [...]")
    return value


def string_list(value, field: str) -> tuple[str, ...]:
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) for v in value):
        raise InputError(f"expected a list of strings, got {value!r}", field=field)
    return tuple(value)


def method_field(table: Mapping, field: str, default: str = "fast", allowed=METHODS) -> str:
    return check_method(table.get("method", default), allowed=allowed, field=f"{field}.method")


def fast_only(table: Mapping, field: str, what: str, instead: str) -> None:
    """The ``method`` of a query that computes in float64 only (a sampled study): absent
    or ``"fast"``; any other tier is refused, naming ``what`` the query computes and
    ``instead`` where the precise or certified answer is (never a float answer under a
    certified name)."""
    method = check_method(table.get("method", "fast"), field=f"{field}.method")
    if method != "fast":
        raise InputError(f"expected method 'fast' ({what} is computed in float64), got "
                         f"{method!r}; {instead}", field=f"{field}.method")


#: the most local worker processes a sweep starts (each a Python interpreter with numpy
#: and the compiled kernels, about 150-250 MB): far above any machine's useful count, so
#: only an absurd value is refused; above the CPU count a warning says it does not help
MAX_WORKERS = 256


def workers_count(value, field: str) -> int:
    """A number of local worker processes: an integer in 1..:data:`MAX_WORKERS`, else
    :class:`InputError` naming ``field`` (the pool is also capped at the number of
    chunks, and warns above ``os.cpu_count()``: :func:`distkin.runstore.local_executor`)."""
    n = positive_int(value, field)
    if n > MAX_WORKERS:
        raise InputError(f"expected at most {MAX_WORKERS} worker processes (each a Python "
                         f"interpreter of some 200 MB), got {n}", field=field,
                         hint=f"this machine has {os.cpu_count() or 1} CPUs; more workers "
                              "than CPUs add memory, not speed")
    return n


def executor_fields(table: Mapping, field: str):
    """The executor fields of a chunked query (sweeps, certified workspaces):
    ``workers`` (a positive integer), ``scheduler`` (a dask address) and ``store`` (a
    directory), each optional.  Returns ``(workers, scheduler, store)``, None where
    absent."""
    workers = workers_count(table["workers"], f"{field}.workers") if "workers" in table else None
    sched = table.get("scheduler")
    if sched is not None and not isinstance(sched, str):
        raise InputError(f"expected a scheduler address string, got {sched!r}",
                         field=f"{field}.scheduler")
    store = table.get("store")
    if store is not None and not isinstance(store, str):
        raise InputError(f"expected a directory path, got {store!r}", field=f"{field}.store")
    return workers, sched, store


#: dask schemes whose location is ``host:port`` (inproc and the others have their own)
_HOST_PORT_SCHEMES = ("tcp", "tls", "ws", "wss", "ucx")


def scheduler_address(value, field: str = "scheduler") -> str:
    """A dask.distributed scheduler address, ``[SCHEME://]HOST:PORT`` (``tcp://10.0.0.5:8786``,
    ``[::1]:8786``): checked before any connection, so a malformed one is bad input
    naming ``field`` rather than dask's own ``ValueError``."""
    if not isinstance(value, str) or not value.strip():
        raise InputError(f"expected a scheduler address like tcp://HOST:8786, got {value!r}",
                         field=field)
    scheme, sep, loc = value.rpartition("://")
    if sep and not scheme.isalnum():
        raise InputError(f"expected a scheduler address like tcp://HOST:8786, got {value!r} "
                         f"(scheme {scheme!r})", field=field)
    if sep and scheme not in _HOST_PORT_SCHEMES:
        return value                      # inproc://..., another transport's own syntax
    if loc.startswith("["):               # IPv6: [addr]:port
        host, _, tail = loc[1:].partition("]")
        port = tail[1:] if tail.startswith(":") else None
    else:
        host, colon, port = loc.rpartition(":")
        if not colon or ":" in host:
            host, port = loc, None
    why = ("no host" if not host else "no port number" if port is None else
           None if port.isdigit() and 0 < int(port) < 65536 else f"port {port!r}")
    if why:
        raise InputError(f"expected a scheduler address like tcp://HOST:8786, got {value!r} "
                         f"({why})", field=field)
    return value


def relative_tol(value, field: str = "tol", *, digits: int | None = None) -> float:
    """A relative tolerance (a root's residual over its scale, a radius over the size of
    the mechanism): a number with 0 < tol < 1; 1 or more would accept anything.  With
    ``digits`` (the precise tier's dps) also at least :math:`10^{-digits}`: the tier
    works at dps + 20 digits and a smaller tolerance rejected every root, so a smaller
    one asks for a larger dps.  :class:`InputError` naming ``field``."""
    x = parse_float(value, field)
    name = field.rsplit(".", 1)[-1]          # tol, tolerance, ...
    if not 0 < x < 1:
        raise InputError(f"expected {name} as a relative tolerance, a number 0 < {name} < 1, "
                         f"got {value!r}", field=field)
    if digits is not None and x < 10.0 ** -digits:
        raise InputError(f"expected tol >= 1e-{digits} at {digits} digits (the precise "
                         f"tier's dps), got {value!r}", field=field,
                         hint=f"raise dps to at least {math.ceil(-math.log10(x) - 1e-9)} "
                              "for it")
    return x


def tol_field(table: Mapping, method: str, field: str, *, dps: int,
              uses=("precise", "certified", "auto"), precise_dps=None) -> float | None:
    """``tol`` of a query (:func:`relative_tol`; None when not given), given only with a
    method in ``uses`` (the tiers that read it); with another method it would be
    ignored, so it is refused naming ``field.tol``, as :func:`dps_field` refuses dps.
    ``dps``: the precise tier's digits, bounding tol below for ``precise``; for
    ``auto`` ``precise_dps`` (the digits of its precise fallback) does, when given."""
    if "tol" not in table:
        return None
    if method not in uses:
        names = [repr(u) for u in uses]
        which = names[0] if len(names) == 1 else f"{', '.join(names[:-1])} or {names[-1]}"
        raise InputError(f"expected 'tol' only with method {which} (the tiers that refine "
                         f"to it), got method {method!r}", field=f"{field}.tol")
    digits = {"precise": dps, "auto": precise_dps}.get(method)
    return relative_tol(table["tol"], f"{field}.tol", digits=digits)


def dps_field(table: Mapping, method: str, field: str, uses=("precise",)) -> int:
    """``dps`` of a query: the decimal digits of the precise tier (an integer 5..1233,
    default 30), given only with a method in ``uses`` (the ones that compute in mpmath);
    with another method it would be ignored, so it is refused naming ``field.dps``."""
    from .exact import default_dps
    if "dps" not in table:
        return default_dps(None)
    try:
        dps = default_dps(table["dps"])
    except InputError as exc:
        raise InputError(exc.message, field=f"{field}.dps") from None
    if method not in uses:
        raise InputError(f"expected 'dps' only with method "
                         f"{' or '.join(repr(u) for u in uses)} (the mpmath digits), got "
                         f"method {method!r}", field=f"{field}.dps")
    return dps
