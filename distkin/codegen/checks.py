"""Input checks of the user-facing scene modules (``distkin codegen``): the prologue of a
checked kernel and the helpers it calls, written into the module by :mod:`.emit`.

A kernel with ``extra["checked"]`` (:class:`.emit.Kernel`) first passes every input
through a helper of its module (STYLE.md: bad input fails at the entry point, naming
what was expected and what was received):

``_Inputs.batched(x, name, k, nonnegative)`` (batched flavour)
    ``numpy.asarray(x, dtype=float)`` (an integer array would overflow in the
    kernel's products: int64 wraps silently; a list works; a float64 array is not
    copied), then a ``ValueError`` unless the last axis has length ``k``.
``_Inputs.scalar(x, name, k, nonnegative)`` (scalar flavour)
    a list of ``k`` floats (a NumPy integer would overflow as well), else a
    ``ValueError`` naming the shape received.

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

    @staticmethod
    def scalar(x, name, k, nonnegative):
        """x as a list of k floats, or a ValueError naming the expected and the
        received shape."""
        try:
            n = len(x)
        except TypeError:
            raise TypeError(f"expected {name}: a sequence of {k} numbers, got "
                            f"{type(x).__name__}") from None
        got = tuple(x.shape) if hasattr(x, "shape") else (n,)
        if got != (k,):
            raise ValueError(f"expected {name} of shape ({k},), got shape {got}")
        v = [float(e) for e in x]
        if nonnegative:
            for i, e in enumerate(v):
                if e < 0:
                    raise ValueError(f"expected {name} >= 0 (squared lengths), got "
                                     f"{name}[{i}] = {e!r}")
        return v
'''


def prologue(kernel) -> list:
    """The first lines of a checked kernel's body (empty for an unchecked one, or a
    flavour other than batched and scalar)."""
    if not kernel.extra.get("checked") or kernel.flavour not in ("batched", "scalar"):
        return []
    nonneg = bool(kernel.extra.get("nonnegative"))
    return [f"    {name} = _Inputs.{kernel.flavour}({name}, {name!r}, {len(syms)}, {nonneg})"
            for name, syms in kernel.inputs]


def helpers(kernels) -> list:
    """``(name, source)`` of the helpers the checked ``kernels`` call (none, or the
    class ``_Inputs``)."""
    return [("_Inputs", _CLASS)] if any(k.extra.get("checked") for k in kernels) else []
