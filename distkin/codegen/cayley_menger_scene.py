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
_MODEL_FILES = ("geometry/cayley_menger.py", "codegen/emit.py", "codegen/cayley_menger_scene.py",
                "codegen/checks.py")


def pairs_of(determinants) -> tuple:
    """The pairs ``(i, j)``, ``i < j``, whose squared distance some determinant uses, sorted.

    ``determinants``: sequence of ``(name, rows, cols)`` with 1-based labels."""
    pairs = set()
    for _name, rows, cols in determinants:
        pairs |= {tuple(sorted((i, j))) for i in rows for j in cols if i != j}
    return tuple(sorted(pairs))


def module_text(determinants, flavours, *, generator, title) -> str:
    """Source of the module of ``determinants`` (``(name, rows, cols)``) in ``flavours``
    ("batched" and/or "scalar"): kernel ``determinants`` (suffix ``_scalar``), input the
    squared distances of :func:`pairs_of` in that order (module constant ``PAIRS``)."""
    import sympy
    from ..geometry.cayley_menger import cayley_menger
    from ..mechanisms.kernel_names import _SUFFIX
    from .emit import Kernel, module_source, symbolic_hash
    pairs = pairs_of(determinants)
    sym = {p: sympy.Symbol(f"s{p[0]}_{p[1]}", positive=True) for p in pairs}
    outs = [cayley_menger(sym, rows, cols) for _n, rows, cols in determinants]
    names = tuple(n for n, _r, _c in determinants)
    body = ("Cayley-Menger (bi)determinants {names} (Rojas et al., eq. (1) notation;\n"
            "raw bordered determinants: D(i,j,k) = -16 area^2, D(i,j,k,l) = 288 volume^2).\n\n"
            "sq : {shape} squared distances s(i,j) of the pairs PAIRS, in that order\n"
            "(squared length units).  Returns {out} determinants, in the order above.")
    kernels = [Kernel("determinants" + _SUFFIX[f], (("sq", tuple(sym[p] for p in pairs)),),
                      outs, flavour=f, extra={"cse_optimizations": None, "chunk": CHUNK,
                                             "checked": True, "nonnegative": True},
                      doc=body.format(names=", ".join(names),
                                      shape="(..., P)" if f == "batched" else "(P,)",
                                      out="(..., K)" if f == "batched" else "a list of K"))
               for f in flavours]
    doc = (f"{title}.\n\n"
           "Inputs are squared distances (not the scene's points, which are the whole input\n"
           "of a cayley_menger query: substituting them would leave constants).  Batched\n"
           "kernels take (..., P) arrays; the scalar one (suffix _scalar) a sequence.\n"
           "Inputs are converted to float64 first; a wrong shape or a negative squared\n"
           "distance is a ValueError naming it.\n"
           "Needs only numpy.  Float64 evaluation of the exact expanded polynomials: for\n"
           "exact values use distkin's certified tier.")
    return module_source(kernels, generator=generator, doc=doc,
                         source_hash=symbolic_hash(*outs),
                         constants={"PAIRS": pairs, "DETERMINANTS": names,
                                    "FLAVOURS": tuple(flavours)})


def scene_module(determinants, flavours, *, scene_name):
    """(source, cache_hit) of a points scene's module, through the derivation cache."""
    from ..sourcecache import cached_source, package_text, source_key
    model = package_text(_MODEL_FILES)
    gen = f"distkin codegen {scene_name} (distkin.codegen.cayley_menger_scene)"
    key = source_key(model, repr(tuple(determinants)), tuple(flavours), gen)
    path, hit = cached_source("cayley_menger", key, lambda: module_text(
        determinants, flavours, generator=gen, title=f"Kernels of scene {scene_name}"))
    return path.read_text(encoding="utf-8"), hit
