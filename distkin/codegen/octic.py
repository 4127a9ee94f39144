"""Deriving the octic kernel of the octahedral manipulator (sympy, :mod:`.emit`).

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited* (ICRA 2012), eqs. (1)-(3):
the parts of eq. (3) (:func:`distkin.octahedral.octic.octic_parts`) become the committed
kernel ``distkin/_generated/octic_general.py`` (:func:`generate_octic_module`); a scene's
octic in its legs is derived and cached by :func:`octic_in_legs`.
"""

from __future__ import annotations

import os
import pickle

from ..octahedral.octic import (LEG_PAIRS, PART_NAMES, SIDE_PAIRS, octic_parts,
                                octic_polynomial, squared_distance_symbols)

__all__ = ["octic_in_legs", "kernel_outputs", "generate_octic_module"]


#: the sources the cached octic depends on beyond its inputs (the cache key): every
#: distkin file these modules import, with the toolchain's versions (a pickle of sympy
#: expressions is another sympy's only by chance; QA 6: hand-kept file lists missed
#: files), :func:`~distkin.sourcecache.closure_text`
_OCTIC_MODULES = ("distkin.codegen.octic",)


def octic_in_legs(values=None, *, use_cache: bool = True):
    r"""The octic's coefficients (highest degree first) as sympy expressions, cached.

    With the base and platform sides fixed by ``values`` (a scene's geometry) the
    coefficients are polynomials in the six squared legs only ("model only what a scene
    requires").  The result is cached on disk under :func:`cache_dir`, keyed by a
    SHA-256 of the symbolic source (the ``srepr`` of the parts and the substitution)
    and of the sources that derive the octic (:data:`_OCTIC_MODULES`), so a second run
    does no algebra (the folder of :mod:`.cache`).

    Returns
    -------
    list of sympy.Expr
        Nine coefficients :math:`o_8, \dots, o_0` of :math:`O(s_{15})`.
    """
    from ..sourcecache import cache_dir, closure_text, entry_lock, source_key
    from .emit import symbolic_hash
    p = octic_parts(values)
    # the inputs and the algorithm: the parts' srepr, and the source of the code that
    # squares eq. (3) into the octic (a cache keyed by the inputs alone served the old
    # octic after a change of octic_polynomial)
    key = source_key(symbolic_hash(*[getattr(p, n) for n in PART_NAMES], p.x),
                     closure_text(_OCTIC_MODULES))[:32]
    path = cache_dir() / f"octic_{key}.pickle"
    if not use_cache:
        return _octic_coeffs(values)
    coeffs = _load(path)
    if coeffs is not None:
        return coeffs
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError:
        return _octic_coeffs(values)
    # parallel workers asking at once: one derives, the others wait and load it
    with entry_lock(path.with_suffix(".lock")):
        coeffs = _load(path)
        if coeffs is not None:
            return coeffs
        coeffs = _octic_coeffs(values)
        try:
            tmp = path.with_suffix(f".{os.getpid()}.tmp")
            with open(tmp, "wb") as fh:
                pickle.dump(coeffs, fh)
            tmp.replace(path)
        except OSError:
            pass
    return coeffs


def _octic_coeffs(values) -> list:
    """The nine coefficients of the octic, derived (sympy; :func:`octic_in_legs`)."""
    import sympy
    coeffs = [sympy.expand(c) for c in octic_polynomial(values).all_coeffs()]
    return [sympy.Integer(0)] * (9 - len(coeffs)) + coeffs


def _load(path):
    """The cached coefficients at ``path``, or None (missing; a damaged entry is
    removed, to be derived again, not trusted)."""
    if not path.exists():
        return None
    try:
        with open(path, "rb") as fh:
            coeffs = pickle.load(fh)
        if len(coeffs) == 9:
            return coeffs
    except Exception:
        pass
    path.unlink(missing_ok=True)
    return None


_KERNEL_DOC = """Octic of the octahedral manipulator and the parts of eq. (3).

Rojas, Borràs, Thomas, The Octahedral Manipulator Revisited (ICRA 2012), eqs. (1)-(3),
Sec. III: O(x) = G^2 - 4 R1 R2 with G = u E2 + v E1 + 2 b1 b2, x = s15 (see
distkin.octahedral.octic).

Parameters
----------
sides : (..., 6)  squared base and platform sides s12 s13 s23 s45 s46 s56
legs : (..., 6)   squared legs s14 s24 s25 s35 s36 s16 (legs 1..6)

Returns
-------
(..., 39): entries 0..29 are the quadratics {names} in x, three coefficients each
(constant, x, x^2); entries 30..38 are the octic's coefficients o8 .. o0 (highest
degree first).  Units: squared length to the power of each coefficient's degree."""


def kernel_outputs(values=None):
    """The 39 outputs of the kernel as sympy expressions of the 12 squared lengths (or of
    those that ``values`` leaves free: a scene's sides substituted before CSE, see
    :mod:`.octahedral_scene`)."""
    import sympy
    p = octic_parts(values)
    X = p.x
    quad = {}
    out = []
    for name in PART_NAMES:
        poly = sympy.Poly(getattr(p, name), X)
        c = [poly.coeff_monomial(X ** k) for k in range(3)]
        if poly.degree() > 2:
            raise AssertionError(f"part {name} has degree {poly.degree()} in s15")
        quad[name] = c
        out.extend(c)

    def mul(a, b):
        r = [sympy.Integer(0)] * (len(a) + len(b) - 1)
        for i, ai in enumerate(a):
            for j, bj in enumerate(b):
                r[i + j] += ai * bj
        return r

    def add(*polys):
        n = max(len(q) for q in polys)
        return [sum((q[k] for q in polys if k < len(q)), sympy.Integer(0)) for k in range(n)]

    # intermediate coefficient symbols keep the expression tree small for CSE
    sym = {name: [sympy.Symbol(f"_{name}{k}") for k in range(3)] for name in PART_NAMES}
    G = add(mul(sym["u"], sym["E2"]), mul(sym["v"], sym["E1"]),
            [2 * t for t in mul(sym["b1"], sym["b2"])])
    R = mul(mul(sym["T1a"], sym["T1b"]), mul(sym["T2a"], sym["T2b"]))
    O = add(mul(G, G), [-4 * t for t in R])
    back = {sym[n][k]: quad[n][k] for n in PART_NAMES for k in range(3)}
    octic = [o.xreplace(back) for o in reversed(O)]
    return out + octic


def _inputs():
    s = squared_distance_symbols()
    return (("sides", tuple(s[k] for k in SIDE_PAIRS)), ("legs", tuple(s[k] for k in LEG_PAIRS)))


def _statements(src: str) -> tuple:
    """The arithmetic of a scalar or loop kernel's source: its common subexpressions
    (``_cN = ...``) and its outputs in order, as text (the input unpacking and the
    indentation aside)."""
    lines = [ln.strip() for ln in src.splitlines()]
    cse = tuple(ln for ln in lines if ln.startswith("_c") and " = " in ln)
    out = [ln.split(" = ", 1)[1] for ln in lines if ln.startswith("_out[_n, ")]
    if not out:
        ret = src[src.index("    return [") + len("    return ["):].rstrip()
        out = [e.strip() for e in _top_level(ret[:ret.rindex("]")])]
    return cse, tuple(out)


def _top_level(text: str) -> list:
    """``text`` split at its commas outside parentheses and brackets."""
    parts, depth, cur = [], 0, []
    for ch in text:
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append("".join(cur))
            cur = []
        else:
            cur.append(ch)
    return parts + ["".join(cur)]


def generate_octic_module() -> str:
    """Source of ``distkin/_generated/octic_general.py`` (registered in
    :data:`distkin.codegen.registry.GENERATED`): a batched numpy kernel
    ``octic_batched``, a scalar one ``octic_scalar`` (and ``parts_scalar``, its quadratic
    parts only, and ``octic_rows``, its loop over rows for numba), an exact (fmpq/arb) kernel ``octic_exact`` of the same map, and the
    rigorous rounding bounds of the quadratic parts as the two float kernels compute
    them (:mod:`.rounding`): the magnitude kernel ``parts_magnitude`` (writing into an
    array) and
    the constants ``PARTS_DEPTH``, ``PARTS_DEGREE``, ``PARTS_UNDERFLOW`` (inputs of
    modulus at most 2^24: the squared lengths after :mod:`.scaling`)."""
    from .emit import Kernel, kernel_source, module_source, symbolic_hash
    from .rounding import analyse, magnitude_source
    outputs = kernel_outputs()
    inputs = _inputs()
    doc = _KERNEL_DOC.format(names=", ".join(PART_NAMES))
    fast = {"cse_optimizations": None}  # sympy's "basic" pre-pass costs ~4 s, gains nothing
    kernels = [Kernel("octic_batched", inputs, outputs, flavour="batched", doc=doc, extra=fast),
               Kernel("octic_scalar", inputs, outputs, flavour="scalar", extra=fast,
                      doc=doc.replace("(..., 6)", "(6,)").replace("(..., 39)", "list of 39")),
               Kernel("parts_scalar", inputs, outputs[:30], flavour="scalar", extra=fast,
                      doc="The first 30 outputs of ``octic_scalar`` only (the quadratic "
                          "parts, without the octic), for evaluations at other inputs "
                          "than the fast tier's own.  sides, legs: (6,); returns a list "
                          "of 30."),
               Kernel("octic_rows", inputs, outputs, flavour="loop", extra=fast,
                      doc="``octic_scalar`` row by row into ``_out`` (N, 39): sides, legs "
                          "(N, 6).  The same expressions (the same CSE, checked), written "
                          "to an array instead of a list (compiled by numba, the fast "
                          "batched tier's kernel: issue 17)."),
               Kernel("octic_exact", inputs, outputs, flavour="exact", extra=fast,
                      doc=doc.replace("(..., 6)", "(6,) fmpq or arb")
                      .replace("(..., 39)", "list of 39 (exact on fmpq, balls on arb)"))]
    # the rounding bounds of the parts as octic_scalar and octic_batched compute them
    # (the same CSE, so the same evaluation order: checked)
    parts = range(30)
    scalar_src, batched_src = kernel_source(kernels[1]), kernel_source(kernels[0])
    bounds = analyse(scalar_src, "octic_scalar", outputs=parts, leaf_bound=2 ** 24)
    if analyse(batched_src, "octic_batched", outputs=parts, leaf_bound=2 ** 24) != bounds:
        raise AssertionError("octic_scalar and octic_batched evaluate the parts differently")
    if _statements(kernel_source(kernels[3])) != _statements(scalar_src):
        raise AssertionError("octic_scalar and octic_rows evaluate differently")
    magnitude = magnitude_source(
        scalar_src, "octic_scalar", "parts_magnitude",
        "Magnitudes of the first 30 outputs of ``octic_scalar`` (the quadratic parts): the "
        "same code with absolute values throughout (distkin.codegen.rounding).  With\n"
        "PARTS_DEPTH, PARTS_DEGREE and PARTS_UNDERFLOW they bound the rounding error of "
        "``octic_scalar`` and ``octic_batched``\n(inputs of modulus <= 2^24).  sides, legs: "
        "(6,); written into ``_out`` (30,) (numba builds a returned list element by "
        "element: ~0.04 µs more per call,\nissue 17).", outputs=parts, into=True)
    return module_source(
        kernels, generator="distkin.codegen.octic:generate_octic_module "
        "(derivation: derivations/octahedral_octic.py)",
        doc="Octic coefficient map of the octahedral manipulator (Rojas et al. 2012, eq. (3)).",
        source_hash=symbolic_hash(*outputs),
        constants={"PART_NAMES": PART_NAMES, "N_PARTS": len(PART_NAMES),
                   # where the parts and the octic sit in the 39 outputs
                   "PARTS": slice(0, 3 * len(PART_NAMES)),
                   "OCTIC": slice(3 * len(PART_NAMES), 3 * len(PART_NAMES) + 9),
                   "PARTS_DEPTH": bounds.depth, "PARTS_DEGREE": bounds.degree,
                   "PARTS_UNDERFLOW": bounds.underflow},
        functions=[("parts_magnitude", magnitude)])
