r"""The closure condition of an octahedron and its octic in :math:`s_{15}` (symbolic).

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. II
eq. (3) and Sec. III; example eqs. (10)-(11).

Notation (raw Cayley-Menger determinants, see :mod:`.banana`), every one a polynomial
of degree <= 2 in :math:`x = s_{15}`:

* :math:`u = D(5,4,1)`, :math:`v = D(3,5,1)` (shared faces; ``-16`` x squared area);
* :math:`b_1, b_2` the bideterminants of eqs. (1), (2) at :math:`s_{26}=0`;
* :math:`R_1 = D(5,4,1,2)D(5,4,1,6)`, :math:`R_2 = D(3,5,1,2)D(3,5,1,6)`;
* :math:`E_1 = D(5,4,1,2,6)`, :math:`E_2 = D(3,5,1,2,6)` at :math:`s_{26}=0`.

**Closure condition, eq. (3).**  Equating the two banana solutions for :math:`s_{26}`,

.. math::

    \frac{\epsilon_1\sqrt{R_1} - b_1}{u} - \frac{\epsilon_2\sqrt{R_2} - b_2}{v}
    = \frac{P + \epsilon_1 v\sqrt{R_1} - \epsilon_2 u\sqrt{R_2}}{uv} = 0,
    \qquad P = u b_2 - v b_1,

with one sign pair :math:`(\epsilon_1, \epsilon_2)` per branch.  The paper's
denominator :math:`-16A_{351}A_{541}` is :math:`uv` up to a constant.

**Squaring twice.**  Naively, :math:`F = P^2 - v^2R_1 - u^2R_2 = -2\epsilon_1\epsilon_2
uv\sqrt{R_1R_2}` and :math:`F^2 - 4u^2v^2R_1R_2 = 0`, of degree 16.  The Jacobi
identities :math:`b_i^2 - R_i = -D(\text{face}_i)E_i` give :math:`F = -uv\,G` with

.. math:: G = u E_2 + v E_1 + 2 b_1 b_2 \quad(\deg 4),
          \qquad F^2 - 4u^2v^2R_1R_2 = (uv)^2\,\bigl(G^2 - 4R_1R_2\bigr).

So squaring introduces exactly the spurious factor :math:`(uv)^2 = (D(5,4,1)D(3,5,1))^2`
(degree 8, the denominators of eq. (10): roots where a shared face is flat), and the
characteristic polynomial is the **octic**

.. math:: O(x) = G(x)^2 - 4R_1(x)R_2(x), \qquad \deg O = 8,

with :math:`G = 2\epsilon_1\epsilon_2\sqrt{R_1R_2}` on the branch that vanishes.  A real
root of :math:`O` is an assembly mode only if the four tetrahedra are real
(:math:`D \ge 0`) and the faces real (:math:`u, v \le 0`); the others are spurious
(complex assemblies) and are rejected by :mod:`distkin.octahedral.forward`.

Everything here is symbolic (sympy imported inside functions).  The run-time tiers use
the generated kernel :mod:`distkin._generated.octic_general` (written by
:func:`generate_octic_module`), never sympy.
"""

from __future__ import annotations

import os
import pickle
from dataclasses import dataclass

from .banana import LEG_PAIRS, SIDE_PAIRS, banana, squared_distance_symbols

__all__ = [
    "PART_NAMES",
    "OcticParts",
    "octic_parts",
    "closure_condition",
    "octic_polynomial",
    "naive_double_square",
    "octic_in_legs",
    "generate_octic_module",
]

#: the quadratic parts in x = s15, in the order the generated kernel returns them
PART_NAMES = ("u", "v", "b1", "b2", "E1", "E2", "T1a", "T1b", "T2a", "T2b")


@dataclass(frozen=True)
class OcticParts:
    """The parts of eq. (3) as sympy expressions, each of degree <= 2 in ``x``.

    ``T1a, T1b, T2a, T2b`` are :math:`D(5,4,1,2), D(5,4,1,6), D(3,5,1,2), D(3,5,1,6)`;
    the others as in the module docstring.  ``x`` is the symbol :math:`s_{15}`.
    """

    x: object
    u: object
    v: object
    b1: object
    b2: object
    E1: object
    E2: object
    T1a: object
    T1b: object
    T2a: object
    T2b: object

    def as_dict(self):
        return {n: getattr(self, n) for n in PART_NAMES}

    @property
    def G(self):
        r""":math:`G = uE_2 + vE_1 + 2b_1b_2` (unexpanded)."""
        return self.u * self.E2 + self.v * self.E1 + 2 * self.b1 * self.b2

    @property
    def R1(self):
        return self.T1a * self.T1b

    @property
    def R2(self):
        return self.T2a * self.T2b


def octic_parts(values=None) -> OcticParts:
    """The parts of eq. (3) from bananas 1 and 2, with optional substitutions.

    Parameters
    ----------
    values : dict {(i, j): number}, optional
        Squared distances a scene fixes (base and platform sides, or legs too).
    """
    b1, b2 = banana(1, values), banana(2, values)
    x = squared_distance_symbols()[(1, 5)]
    return OcticParts(x, b1.coefficient, b2.coefficient, b1.constant, b2.constant,
                      b1.pentad, b2.pentad, b1.tetra_a, b1.tetra_b, b2.tetra_a, b2.tetra_b)


def closure_condition(signs=(1, 1), values=None, *, cleared=False):
    r"""Eq. (3): :math:`s_{26}` of banana 1 minus :math:`s_{26}` of banana 2.

    Parameters
    ----------
    signs : (int, int)
        The branch :math:`(\epsilon_1, \epsilon_2)` of eqs. (1) and (2).
    values : dict, optional
        Substituted squared distances.
    cleared : bool
        Return the numerator :math:`P + \epsilon_1 v\sqrt{R_1} - \epsilon_2 u\sqrt{R_2}`
        (denominator :math:`uv` cleared) instead of the difference.
    """
    import sympy
    p = octic_parts(values)
    e1, e2 = signs
    num = (p.u * p.b2 - p.v * p.b1 + e1 * p.v * sympy.sqrt(p.R1)
           - e2 * p.u * sympy.sqrt(p.R2))
    return num if cleared else num / (p.u * p.v)


def octic_polynomial(values=None):
    r"""The octic :math:`O = G^2 - 4R_1R_2` as a sympy ``Poly`` in :math:`x = s_{15}`.

    Its coefficients are polynomials in the remaining squared distances (the six legs,
    and the base/platform sides unless ``values`` fixes them).  Fully symbolic, the
    coefficients have up to ~45 000 terms; prefer :func:`octic_in_legs` (cached) or the
    generated kernel.
    """
    import sympy
    p = octic_parts(values)
    G = sympy.Poly(sympy.expand(p.G), p.x)
    R1 = sympy.Poly(p.T1a, p.x) * sympy.Poly(p.T1b, p.x)
    R2 = sympy.Poly(p.T2a, p.x) * sympy.Poly(p.T2b, p.x)
    return G ** 2 - 4 * R1 * R2


def naive_double_square(values):
    r"""Eq. (3) squared twice without cancelling: :math:`F^2 - 4u^2v^2R_1R_2`, degree 16.

    Returns ``(naive, spurious, octic)`` sympy Polys in :math:`s_{15}` with
    ``naive == spurious * octic`` and ``spurious = (uv)^2``.  Intended with all
    sides fixed (``values``), where the expansion is quick.
    """
    import sympy
    p = octic_parts(values)
    X = p.x
    u, v = sympy.Poly(p.u, X), sympy.Poly(p.v, X)
    b1, b2 = sympy.Poly(p.b1, X), sympy.Poly(p.b2, X)
    R1 = sympy.Poly(p.T1a, X) * sympy.Poly(p.T1b, X)
    R2 = sympy.Poly(p.T2a, X) * sympy.Poly(p.T2b, X)
    P = u * b2 - v * b1
    F = P ** 2 - v ** 2 * R1 - u ** 2 * R2
    naive = F ** 2 - 4 * u ** 2 * v ** 2 * R1 * R2
    return naive, (u * v) ** 2, octic_polynomial(values)


def octic_in_legs(values=None, *, use_cache: bool = True):
    r"""The octic's coefficients (highest degree first) as sympy expressions, cached.

    With the base and platform sides fixed by ``values`` (a scene's geometry) the
    coefficients are polynomials in the six squared legs only ("model only what a scene
    requires").  The result is cached on disk under :func:`cache_dir`, keyed by a
    SHA-256 of the symbolic source (the ``srepr`` of the parts and the substitution),
    so a second run does no algebra (the folder of :mod:`distkin.codegen.cache`).

    Returns
    -------
    list of sympy.Expr
        Nine coefficients :math:`o_8, \dots, o_0` of :math:`O(s_{15})`.
    """
    import sympy
    from ..codegen.cache import cache_dir
    from ..codegen.emit import symbolic_hash
    p = octic_parts(values)
    key = symbolic_hash(*[getattr(p, n) for n in PART_NAMES], p.x)[:32]
    path = cache_dir() / f"octic_{key}.pickle"
    if use_cache and path.exists():
        try:
            with open(path, "rb") as fh:
                coeffs = pickle.load(fh)
            if len(coeffs) == 9:
                return coeffs
        except Exception:  # a damaged cache entry is rebuilt, not trusted
            path.unlink(missing_ok=True)
    coeffs = [sympy.expand(c) for c in octic_polynomial(values).all_coeffs()]
    coeffs = [sympy.Integer(0)] * (9 - len(coeffs)) + coeffs
    if use_cache:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp = path.with_suffix(f".{os.getpid()}.tmp")
            with open(tmp, "wb") as fh:
                pickle.dump(coeffs, fh)
            tmp.replace(path)
        except OSError:
            pass
    return coeffs


# ---------------------------------------------------------------- code generation

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


def _kernel_outputs():
    """The 39 outputs of the kernel as sympy expressions of the 12 squared lengths."""
    import sympy
    p = octic_parts()
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


def generate_octic_module() -> str:
    """Source of ``distkin/_generated/octic_general.py`` (registered in
    :data:`distkin.codegen.registry.GENERATED`): a batched numpy kernel
    ``octic_batched``, a scalar one ``octic_scalar`` (and ``parts_scalar``, its quadratic
    parts only), an exact (fmpq/arb) kernel ``octic_exact`` of the same map, and the
    rigorous rounding bounds of the quadratic parts as the two float kernels compute
    them (:mod:`distkin.codegen.rounding`): the magnitude kernel ``parts_magnitude`` and
    the constants ``PARTS_DEPTH``, ``PARTS_DEGREE``, ``PARTS_UNDERFLOW`` (inputs of
    modulus at most 2^24: the squared lengths after :mod:`.scaling`)."""
    from ..codegen.emit import Kernel, kernel_source, module_source, symbolic_hash
    from ..codegen.rounding import analyse, magnitude_source
    outputs = _kernel_outputs()
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
    magnitude = magnitude_source(
        scalar_src, "octic_scalar", "parts_magnitude",
        "Magnitudes of the first 30 outputs of ``octic_scalar`` (the quadratic parts): the "
        "same code with absolute values throughout (distkin.codegen.rounding).  With\n"
        "PARTS_DEPTH, PARTS_DEGREE and PARTS_UNDERFLOW they bound the rounding error of "
        "``octic_scalar`` and ``octic_batched``\n(inputs of modulus <= 2^24).  sides, legs: "
        "(6,); returns a list of 30.", outputs=parts)
    return module_source(
        kernels, generator="distkin.octahedral.octic:generate_octic_module "
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
