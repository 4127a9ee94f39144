"""Input checks of the user-facing scene modules (``distkin codegen``): the prologue of a
checked kernel and the helpers it calls, written into the module by :mod:`.emit`.

A kernel with ``extra["checked"]`` (:class:`.emit.Kernel`) first passes every input
through a helper of its module (STYLE.md: bad input fails at the entry point, naming
what was expected and what was received):

``_Inputs.batched(x, name, k, nonnegative)`` (batched flavour)
    ``numpy.asarray(x, dtype=float)`` (an integer array would overflow in the
    kernel's products: int64 wraps silently; a list works; a float64 array is not
    copied), then a ``ValueError`` unless the last axis has length ``k``.
the scalar flavour, written out in the kernel (numba compiles it)
    a ``ValueError`` unless ``len(x) == k`` (naming the expected shape; numba formats
    no message), then ``x`` as a tuple of ``k`` floats (a NumPy integer would overflow
    as well).

With ``nonnegative`` (inputs that are squared lengths) a negative entry is a
``ValueError`` naming it, in both flavours alike (``math.sqrt`` of it was a bare "math
domain error" in the scalar flavour, a NaN and a RuntimeWarning in the batched one).

Only the scene modules are checked.  The committed kernels of ``distkin/_generated``
are internal: their callers check and convert their input first, and their scalar
forms are compiled by numba in hot paths (the octahedral fast tier, the control
cycle), where a call costs about a microsecond.
"""

from __future__ import annotations

__all__ = ["prologue", "helpers"]

#: the helpers, as static methods of one class: a module's top-level functions stay its
#: kernels (its ``__all__``; ``distkin codegen`` lists them as the module's kernels)
_CLASS = '''class _Inputs:
    """The input checks of the kernels (distkin.codegen.checks)."""

    @staticmethod
    def batched(x, name, k, nonnegative):
        """x as a float64 array (..., k) (integer input would overflow in the kernels'
        products), or a ValueError naming the expected and the received shape."""
        x = numpy.asarray(x, dtype=float)
        if x.shape[-1:] != (k,):
            raise ValueError(f"expected {name} of shape (..., {k}), got shape {x.shape}")
        if nonnegative and (x < 0).any():
            i = tuple(int(j) for j in numpy.argwhere(x < 0)[0])
            raise ValueError(f"expected {name} >= 0 (squared lengths), got "
                             f"{name}[{', '.join(map(str, i))}] = {float(x[i])!r}")
        return x
'''


def prologue(kernel) -> list:
    """The first lines of a checked kernel's body (empty for an unchecked one, or a
    flavour other than batched and scalar).

    The scalar flavour's check is written out in the kernel, in what numba compiles
    (QA W 1: a call of ``_Inputs`` made ``numba.njit(m.reach_scalar)`` fail to type):
    the length, then the entries as a tuple of floats, then the signs; its messages
    are constants (numba formats none), naming the expected shape only."""
    if not kernel.extra.get("checked") or kernel.flavour not in ("batched", "scalar"):
        return []
    nonneg = bool(kernel.extra.get("nonnegative"))
    if kernel.flavour == "batched":
        return [f"    {name} = _Inputs.batched({name}, {name!r}, {len(syms)}, {nonneg})"
                for name, syms in kernel.inputs]
    lines = []
    for name, syms in kernel.inputs:
        k = len(syms)
        lines += [f"    if len({name}) != {k}:",
                  f"        raise ValueError(\"expected {name} of shape ({k},): {k} numbers\")",
                  f"    {name} = (" + ", ".join(f"float({name}[{i}])" for i in range(k))
                  + ("," if k == 1 else "") + ")"]
        if nonneg:
            lines += [f"    for _v in {name}:",
                      "        if _v < 0.0:",
                      f"            raise ValueError(\"expected {name} >= 0 (squared "
                      f"lengths), got a negative entry\")"]
    return lines


def helpers(kernels) -> list:
    """``(name, source)`` of the helpers the checked ``kernels`` call (none, or the
    class ``_Inputs``)."""
    return [("_Inputs", _CLASS)] if any(k.extra.get("checked") and k.flavour == "batched"
                                        for k in kernels) else []
