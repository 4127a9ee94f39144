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

from dataclasses import dataclass

from .banana import LEG_PAIRS, SIDE_PAIRS, banana, squared_distance_symbols  # noqa: F401

__all__ = [
    "PART_NAMES",
    "OcticParts",
    "octic_parts",
    "closure_condition",
    "octic_polynomial",
    "naive_double_square",
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
