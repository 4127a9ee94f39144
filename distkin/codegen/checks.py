"""Input checks of the user-facing scene modules (``distkin codegen``): the prologue of a
checked kernel and the helpers it calls, written into the module by :mod:`.emit`.

A kernel with ``extra["checked"]`` (:class:`.emit.Kernel`) first passes every input
through a helper of its module (STYLE.md: bad input fails at the entry point, naming
what was expected and what was received):

``_Inputs.batched(x, name, k, nonnegative, positive)`` (batched flavour)
    ``numpy.asarray(x, dtype=float)`` (an integer array would overflow in the
    kernel's products: int64 wraps silently; a list works; a float64 array is not
    copied; what does not convert is a ``ValueError`` naming its type), then a
    ``ValueError`` unless the last axis has length ``k``.
``_Inputs.batch(names, arrays)`` (batched flavour, a kernel of several inputs)
    the batch shape of the output: the inputs' shapes but the last axis, broadcast
    together (a ``q`` (6,) beside poses (N, 6) gives N rows), or a ``ValueError``
    naming every input's shape (numpy's "operands could not be broadcast together"
    named neither input, QA).  The output and the chunks follow this shape.
the scalar flavour, written out in the kernel (numba compiles it)
    a ``ValueError`` unless ``len(x) == k``, naming the expected shape and the
    received length (or None, a single number, an object without a length: a scalar
    for a pose was a raw ``TypeError`` of ``len``, QA), then ``x`` as a tuple of ``k``
    floats (a NumPy integer would overflow as well), or a ``ValueError`` naming the
    first entry that is not a number, its ``repr`` and the entries' units
    (``extra["units"]``; ``ik_scalar([None] * 6)`` was float()'s raw ``TypeError``, QA).
the loop flavour (``_loop``, for numba), written out in the kernel
    a ``ValueError`` unless every input is an array (N, k) and ``_out`` an array
    (N,) + the output's shape (a single pose was a raw ``IndexError``, QA: the loop
    writes rows, so a single pose is ``pose[None]``; numba types the rows only).

With ``nonnegative`` (inputs that are squared lengths) a negative entry is a
``ValueError`` naming it, in both flavours alike (``math.sqrt`` of it was a bare "math
domain error" in the scalar flavour, a NaN and a RuntimeWarning in the batched one).
With ``positive`` ({input name: column indices}: the prismatic legs' lengths of a
closure) an entry <= 0 of those columns is a ``ValueError`` naming it (the closure
``(|P - B|^2 - q^2) / (2 q)`` divides by q, and a negative length is none: its square
passed it off as the positive one, QA; as :func:`distkin.mechanisms.joint_values.
check_joint_values` refuses it in the package).  NaN passes as NaN in every check.
Numba formats integers into a message but no float, so the scalar and loop flavours
name indices and shapes, the batched one the values too (and the scalar one the entry
that is not a number: a path numba never takes, its input being typed as numbers).

Under numba an input of the wrong kind (a 2-D array for a scalar kernel, a single pose
for a loop kernel) fails to type before any of these lines runs: the dispatcher is
numba's (``numba.njit(m.ik_scalar)``), no wrapper of the module, so its ``TypingError``
stands; the same call uncompiled gets the ``ValueError`` above.

Every check runs once per call on the whole input (vectorised), not per element.

Only the scene modules are checked.  The committed kernels of ``distkin/_generated``
are internal: their callers check and convert their input first, and their scalar
forms are compiled by numba in hot paths (the octahedral fast tier, the control
cycle), where a call costs about a microsecond.
"""

from __future__ import annotations

__all__ = ["prologue", "helpers", "batch_shape_name"]

#: the helpers, as static methods of one class: a module's top-level functions stay its
#: kernels (its ``__all__``; ``distkin codegen`` lists them as the module's kernels)
_CLASS = '''class _Inputs:
    """The input checks of the kernels (distkin.codegen.checks)."""

    @staticmethod
    def batched(x, name, k, nonnegative, positive=()):
        """x as a float64 array (..., k) (integer input would overflow in the kernels'
        products), or a ValueError naming the expected and the received shape; with
        ``nonnegative`` every entry >= 0, with ``positive`` (column indices) those
        columns > 0 (NaN passes)."""
        try:
            a = numpy.asarray(x, dtype=float)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"expected {name} of shape (..., {k}): numbers, got a "
                             f"{type(x).__name__} that is not ({exc})") from None
        if a.shape[-1:] != (k,):
            kind = "" if isinstance(x, numpy.ndarray) else f" (a {type(x).__name__})"
            raise ValueError(f"expected {name} of shape (..., {k}), got shape {a.shape}"
                             f"{kind}")
        if nonnegative and (a < 0).any():
            i = tuple(int(j) for j in numpy.argwhere(a < 0)[0])
            raise ValueError(f"expected {name} >= 0 (squared lengths), got "
                             f"{name}[{', '.join(map(str, i))}] = {float(a[i])!r}")
        if positive:
            v = a if len(positive) == k else a[..., list(positive)]
            if (v <= 0).any():
                i = tuple(int(j) for j in numpy.argwhere(v <= 0)[0])
                i = i[:-1] + (positive[i[-1]],)
                cols = "" if len(positive) == k else f" in the columns {list(positive)}"
                raise ValueError(
                    f"expected {name} > 0{cols} (the prismatic legs' lengths |P - B|, m: "
                    f"the closure divides by them, and a negative length is none), got "
                    f"{name}[{', '.join(map(str, i))}] = {float(a[i])!r} (prismatic leg "
                    f"{i[-1] + 1})")
        return a

    @staticmethod
    def batch(names, arrays):
        """The inputs' batch shapes (all axes but the last) broadcast together: the
        output's, or a ValueError naming every input's shape."""
        shapes = [a.shape[:-1] for a in arrays]
        if all(s == shapes[0] for s in shapes[1:]):      # equal: no broadcast (10x cheaper)
            return shapes[0]
        try:
            return numpy.broadcast_shapes(*shapes)
        except ValueError:
            got = ", ".join(f"{n} {a.shape}" for n, a in zip(names, arrays))
            want = ", ".join(f"{n} (..., {a.shape[-1]})" for n, a in zip(names, arrays))
            raise ValueError(f"expected inputs whose batch shapes (all axes but the "
                             f"last) broadcast together ({want}: the same number of rows, "
                             f"or one), got shapes {got}") from None
'''


def batch_shape_name(kernel):
    """``"_batch"``, the local of the broadcast batch shape that a checked batched kernel
    of several inputs computes (its output's shape and its chunks follow it), or None."""
    if (kernel.extra.get("checked") and kernel.flavour == "batched"
            and len(kernel.inputs) > 1):
        return "_batch"
    return None


def _entry_lines(name, k, units):
    """The scalar flavour's conversion of ``name`` to a tuple of ``k`` floats, or a
    ``ValueError`` naming the first entry that ``float`` refuses and its ``repr`` (a None
    was float()'s raw ``TypeError``, QA).  Written for numba too: the conversion in a
    ``try`` (``except Exception``, the form numba compiles), the search for the entry only
    on the error path; ``units``: the words of the entries' units, or None."""
    conv = ", ".join(f"float({name}[{i}])" for i in range(k)) + ("," if k == 1 else "")
    zeros = ", ".join("0.0" for _ in range(k)) + ("," if k == 1 else "")
    what = f"{k} numbers" + (f" ({units})" if units else "")
    return ["    try:",
            f"        _v = ({conv})",
            "        _j = -1",
            "    except Exception:",
            f"        _v = ({zeros})",
            "        _j = 0",
            f"        for _i in range({k}):",
            "            try:",
            f"                float({name}[_i])",
            "            except Exception:",
            "                _j = _i",
            "                break",
            "    if _j >= 0:",
            f"        raise ValueError(f\"expected {name} of shape ({k},): {what}, got "
            f"{name}[{{_j}}] = \" + repr({name}[_j]))",
            f"    {name} = _v"]


def _scalar_lines(name, k, nonneg, positive, units=None):
    """The scalar flavour's check of the input ``name`` of ``k`` numbers (``units``: the
    words of their units, named when an entry is not a number)."""
    want = f"expected {name} of shape ({k},): {k} numbers"
    lines = ["    try:",
             f"        _n = len({name})",
             "    except Exception:",
             "        _n = -1",
             f"    if _n != {k}:",
             f"        if {name} is None:",
             f"            raise ValueError(\"{want}, got None\")",
             "        if _n < 0:",
             f"            if hasattr({name}, \"__float__\"):",
             f"                raise ValueError(\"{want}, got a single number\")",
             f"            raise ValueError(\"{want}, got an object without a length\")",
             f"        raise ValueError(f\"{want}, got length {{_n}}\")",
             *_entry_lines(name, k, units)]
    if nonneg:
        lines += [f"    for _j in range({k}):",
                  f"        if {name}[_j] < 0.0:",
                  f"            raise ValueError(f\"expected {name} >= 0 (squared lengths), "
                  f"got a negative entry {name}[{{_j}}] < 0\")"]
    if positive:
        cols = ", ".join(str(int(j)) for j in positive) + ("," if len(positive) == 1 else "")
        lines += [f"    for _j in ({cols}):",
                  f"        if {name}[_j] <= 0.0:",
                  f"            raise ValueError(f\"expected {name}[{{_j}}] > 0 (the length "
                  f"|P - B| of prismatic leg {{_j + 1}}, m: the closure divides by it, and "
                  f"a negative length is none), got {name}[{{_j}}] \" + (\"= 0\" if "
                  f"{name}[_j] == 0.0 else \"< 0\"))"]
    return lines


def _loop_lines(kernel, out_shape):
    """The loop flavour's check: every input an array (N, k), ``_out`` (N,) + out_shape."""
    first = kernel.inputs[0][0]
    rows = f"(N, {out_shape[0]}" + "".join(f", {d}" for d in out_shape[1:]) + ")"
    want = (", ".join(f"{n} (N, {len(s)})" for n, s in kernel.inputs) + f", _out {rows}")
    lines = ["    try:",
             *[f"        _s{i} = {n}.shape" for i, (n, _) in enumerate(kernel.inputs)],
             "        _so = _out.shape",
             "    except Exception:",
             f"        raise ValueError(\"expected arrays {want} (loop flavour), got an "
             "input that is not an array\")"]
    for i, (n, syms) in enumerate(kernel.inputs):
        k = len(syms)
        lines += [f"    if len(_s{i}) != 2:",
                  f"        raise ValueError(f\"expected {n} of shape (N, {k}) (loop flavour: "
                  f"rows; a single one is {n}[None]), got a {{len(_s{i})}}-dimensional "
                  "array\")",
                  f"    if _s{i}[1] != {k}" + (f" or _s{i}[0] != _s0[0]:" if i else ":"),
                  f"        raise ValueError(f\"expected {n} of shape (N, {k})"
                  + (f" with N = {{_s0[0]}} (the rows of {first})" if i else "")
                  + f", got shape ({{_s{i}[0]}}, {{_s{i}[1]}})\")"]
    nd = len(out_shape) + 1
    dims = " or ".join(f"_so[{j + 1}] != {d}" for j, d in enumerate(out_shape))
    lines += [f"    if len(_so) != {nd}:",
              f"        raise ValueError(f\"expected _out of shape {rows} with N = "
              f"{{_s0[0]}}, got a {{len(_so)}}-dimensional array\")",
              f"    if _so[0] != _s0[0] or {dims}:",
              f"        raise ValueError(f\"expected _out of shape {rows} with N = "
              f"{{_s0[0]}}, got shape (" + ", ".join(f"{{_so[{j}]}}" for j in range(nd))
              + ("," if nd == 1 else "") + ")\")"]
    return lines


def prologue(kernel, out_shape=None) -> list:
    """The first lines of a checked kernel's body (empty for an unchecked one, or a
    flavour other than batched, scalar and loop).

    The scalar and loop flavours' checks are written out in the kernel, in what numba
    compiles (QA W 1: a call of ``_Inputs`` made ``numba.njit(m.reach_scalar)`` fail to
    type): the length (``try``/``except Exception``, ``is None``, ``hasattr``), then the
    entries as a tuple of floats, then the signs; their messages format integers only
    (numba formats no float).  ``out_shape``: the output's shape (loop flavour)."""
    if not kernel.extra.get("checked") or kernel.flavour not in ("batched", "scalar",
                                                                 "loop"):
        return []
    nonneg = bool(kernel.extra.get("nonnegative"))
    positive = kernel.extra.get("positive") or {}
    if kernel.flavour == "loop":
        return _loop_lines(kernel, out_shape)
    if kernel.flavour == "batched":
        lines = [f"    {name} = _Inputs.batched({name}, {name!r}, {len(syms)}, {nonneg}"
                 + (f", {tuple(positive[name])!r})" if positive.get(name) else ")")
                 for name, syms in kernel.inputs]
        batch = batch_shape_name(kernel)
        if batch:
            names = tuple(name for name, _ in kernel.inputs)
            lines.append(f"    {batch} = _Inputs.batch({names!r}, ({', '.join(names)},))")
        return lines
    lines = []
    units = kernel.extra.get("units") or {}
    for name, syms in kernel.inputs:
        lines += _scalar_lines(name, len(syms), nonneg, positive.get(name), units.get(name))
    return lines


def helpers(kernels) -> list:
    """``(name, source)`` of the helpers the checked ``kernels`` call (none, or the
    class ``_Inputs``)."""
    return [("_Inputs", _CLASS)] if any(k.extra.get("checked") and k.flavour == "batched"
                                        for k in kernels) else []
