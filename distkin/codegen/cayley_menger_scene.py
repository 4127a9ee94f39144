r"""Scene kernel modules of Cayley-Menger (bi)determinants (``kind = "points"`` scenes).

``distkin codegen`` on a scene with ``cayley_menger`` queries: each requested
determinant :math:`D(i_1..i_k; j_1..j_k)` (Rojas, Borràs, Thomas, *The Octahedral
Manipulator Revisited*, ICRA 2012, eq. (1) notation; :mod:`distkin.geometry.cayley_menger`)
is expanded by sympy as a polynomial in the squared distances :math:`s_{ij}` among its
labels, and emitted through CSE as a kernel of those squared distances.

The scene's points are **not** substituted: they are the whole input of the query, so
substituting them would leave constants.  The module evaluates the same determinants
for any point set (of any dimension), batched over many.
"""

from __future__ import annotations

__all__ = ["module_text", "scene_module", "pairs_of"]

CHUNK = 4096
#: the modules whose import closure keys the derivation cache
#: (:func:`~distkin.sourcecache.closure_text`)
_MODEL_MODULES = ("distkin.codegen.cayley_menger_scene",)


def pairs_of(determinants) -> tuple:
    """The pairs ``(i, j)``, ``i < j``, whose squared distance some determinant uses, sorted.

    ``determinants``: sequence of ``(name, rows, cols)`` with 1-based labels."""
    pairs = set()
    for _name, rows, cols in determinants:
        pairs |= {tuple(sorted((i, j))) for i in rows for j in cols if i != j}
    return tuple(sorted(pairs))


def module_text(determinants, flavours, *, generator, title, length_unit=None) -> str:
    """Source of the module of ``determinants`` (``(name, rows, cols)``) in ``flavours``
    ("batched" and/or "scalar"): kernel ``determinants`` (suffix ``_scalar``), input the
    squared distances of :func:`pairs_of` in that order (module constant ``PAIRS``).
    ``length_unit``, the scene's ("mm", ...), is named in the docstrings and as
    ``LENGTH_UNIT``; None or "none": unitless, the generic words."""
    import sympy
    from ..geometry.cayley_menger import cayley_menger
    from ..mechanisms.kernel_names import _SUFFIX
    from .emit import Kernel, module_source, symbolic_hash
    pairs = pairs_of(determinants)
    sym = {p: sympy.Symbol(f"s{p[0]}_{p[1]}", positive=True) for p in pairs}
    outs = [cayley_menger(sym, rows, cols) for _n, rows, cols in determinants]
    names = tuple(n for n, _r, _c in determinants)
    unitless = length_unit in (None, "none")
    # a k x k bordered determinant of squared distances: (k - 1) factors of them
    det_unit = ("" if unitless else
                " (each in " + ", ".join(f"{n}: {length_unit}^{2 * (len(r) - 1)}"
                                         for n, r, _c in determinants) + ")")
    sq = "squared length units" if unitless else f"in {length_unit}^2, the scene's unit"
    body = ("Cayley-Menger (bi)determinants {names} (Rojas et al., eq. (1) notation;\n"
            "raw bordered determinants: D(i,j,k) = -16 area^2, D(i,j,k,l) = 288 volume^2).\n\n"
            "sq : {shape} squared distances s(i,j) of the pairs PAIRS, in that order\n"
            "({sq}).  Returns {out} determinants, in the order above{det_unit}.")
    kernels = [Kernel("determinants" + _SUFFIX[f], (("sq", tuple(sym[p] for p in pairs)),),
                      outs, flavour=f, extra={"cse_optimizations": None, "chunk": CHUNK,
                                             "checked": True, "nonnegative": True,
                                             "units": {"sq": sq}},
                      doc=body.format(names=", ".join(names), sq=sq, det_unit=det_unit,
                                      shape="(..., P)" if f == "batched" else "(P,)",
                                      out="(..., K)" if f == "batched" else "a list of K"))
               for f in flavours]
    doc = (f"{title}.\n\n"
           "Inputs are squared distances (not the scene's points, which are the whole input\n"
           "of a cayley_menger query: substituting them would leave constants).  Batched\n"
           "kernels take (..., P) arrays; the scalar one (suffix _scalar) a sequence.\n"
           "Inputs are converted to float64 first; a wrong shape or a negative squared\n"
           "distance is a ValueError naming it.\n"
           + ("Units: the scene's lengths are unitless; the inputs are in the squares of "
              "its\nlength unit.\n" if unitless else
              f"Units: lengths in {length_unit} (the scene's [units] length); the inputs "
              f"are in {length_unit}^2.\n") +
           "Needs only numpy.  Float64 evaluation of the exact expanded polynomials: for\n"
           "exact values use distkin's certified tier.")
    return module_source(kernels, generator=generator, doc=doc,
                         source_hash=symbolic_hash(*outs),
                         constants={"PAIRS": pairs, "DETERMINANTS": names,
                                    "LENGTH_UNIT": None if unitless else length_unit,
                                    "FLAVOURS": tuple(flavours)})


def scene_module(determinants, flavours, *, scene_name, length_unit=None):
    """(source, cache_hit) of a points scene's module, through the derivation cache
    (``length_unit``, the scene's, named in the module: :func:`module_text`)."""
    from ..sourcecache import cached_source, closure_text, source_key
    model = closure_text(_MODEL_MODULES)
    gen = f"distkin codegen {scene_name} (distkin.codegen.cayley_menger_scene)"
    key = source_key(model, repr(tuple(determinants)), tuple(flavours), gen,
                     repr(length_unit))
    path, hit = cached_source("cayley_menger", key, lambda: module_text(
        determinants, flavours, generator=gen, title=f"Kernels of scene {scene_name}",
        length_unit=length_unit))
    return path.read_text(encoding="utf-8"), hit
