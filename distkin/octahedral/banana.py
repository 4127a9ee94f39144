r"""Bananas: two tetrahedra sharing a face, and their linear equation in :math:`s_{26}`.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. II,
eqs. (1)-(2).  An octahedron P1..P6 (base P1 P2 P3, platform P4 P5 P6, docs/design.md §3)
splits into two *bananas*, each a pair of tetrahedra on a common face:

* banana 1: tetrahedra :math:`P_5P_4P_1P_2` and :math:`P_5P_4P_1P_6` on face
  :math:`P_5P_4P_1`, eq. (1)

  .. math:: D(5,4,1,2;5,4,1,6) = \pm\sqrt{D(5,4,1,2)\,D(5,4,1,6)}

* banana 2: tetrahedra :math:`P_3P_5P_1P_2` and :math:`P_3P_5P_1P_6` on face
  :math:`P_3P_5P_1`, eq. (2)

  .. math:: D(3,5,1,2;3,5,1,6) = \pm\sqrt{D(3,5,1,2)\,D(3,5,1,6)}

Both relations hold because the five points of a banana lie in 3-space: the
Desnanot-Jacobi identity on the bordered 6x6 Cayley-Menger matrix gives

.. math:: D(i,j,k,l;i,j,k,m)^2 - D(i,j,k,l)\,D(i,j,k,m) = -D(i,j,k)\,D(i,j,k,l,m)

and :math:`D(i,j,k,l,m) = 0` for five points in 3-space.  (Fig. 3's caption of the
paper names :math:`s_{16}` and :math:`s_{34}`; eqs. (1)-(3) use :math:`s_{26}` and
:math:`s_{15}`, and so do we.)

The bideterminant contains :math:`s_{26}` linearly, with coefficient the cofactor
:math:`D(i,j,k)` (``-16`` times the squared area of the shared face), so each banana
gives :math:`s_{26}` as an explicit branch pair

.. math:: s_{26} = \frac{\pm\sqrt{D(i,j,k,2)\,D(i,j,k,6)} - b}{D(i,j,k)},
          \qquad b = D(i,j,k,2;i,j,k,6)\big|_{s_{26}=0}.

Determinants are the raw bordered ones of :mod:`distkin.geometry.cayley_menger`
(:math:`D(i,j,k) = -16A^2`, :math:`D(i,j,k,l) = 288V^2`).  Everything here is
symbolic (sympy, imported inside the functions), for derivations and codegen only.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

__all__ = [
    "BANANAS",
    "LEG_PAIRS",
    "SIDE_PAIRS",
    "Banana",
    "squared_distance_symbols",
    "distance_matrix",
    "banana",
]

#: the two bananas of Rojas et al. Fig. 3 / eqs. (1)-(2): (shared face, apex a, apex b)
BANANAS = {1: ((5, 4, 1), 2, 6), 2: ((3, 5, 1), 2, 6)}

#: leg k (1-based) joins these points (docs/design.md §3): 1=P1P4 2=P2P4 3=P2P5 4=P3P5 5=P3P6 6=P1P6
LEG_PAIRS = ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))

#: base sides s12 s13 s23, then platform sides s45 s46 s56
SIDE_PAIRS = ((1, 2), (1, 3), (2, 3), (4, 5), (4, 6), (5, 6))


@lru_cache(maxsize=None)
def squared_distance_symbols():
    """sympy symbols ``s_ij`` (i < j, labels 1..6) as a dict ``{(i, j): Symbol}``."""
    import sympy
    return {(i, j): sympy.Symbol(f"s{i}{j}", positive=True)
            for i in range(1, 7) for j in range(i + 1, 7)}


def distance_matrix(values=None):
    """The symmetric 6x6 sympy matrix of squared distances.

    Parameters
    ----------
    values : dict {(i, j): expr}, optional
        Substitutions for some ``s_ij`` (i < j); the rest stay symbols.
    """
    import sympy
    s = dict(squared_distance_symbols())
    if values:
        for (i, j), v in values.items():
            s[(min(i, j), max(i, j))] = sympy.sympify(v)
    S = sympy.zeros(6, 6)
    for (i, j), v in s.items():
        S[i - 1, j - 1] = S[j - 1, i - 1] = v
    return S


@dataclass(frozen=True)
class Banana:
    r"""One banana of Rojas et al. Sec. II, as sympy polynomials.

    Attributes
    ----------
    index : int
        1 (eq. (1)) or 2 (eq. (2)).
    face : tuple of int
        The shared face (i, j, k).
    bideterminant : sympy.Expr
        :math:`D(i,j,k,2;i,j,k,6)`, linear in :math:`s_{26}`.
    coefficient : sympy.Expr
        Its coefficient of :math:`s_{26}`, equal to :math:`D(i,j,k)`.
    constant : sympy.Expr
        Its value at :math:`s_{26}=0` (``b`` in the module docstring).
    tetra_a, tetra_b : sympy.Expr
        :math:`D(i,j,k,2)` and :math:`D(i,j,k,6)` (``288 V^2`` each).
    pentad : sympy.Expr
        :math:`D(i,j,k,2,6)` at :math:`s_{26}=0` (``E`` in the Jacobi identity
        :math:`b^2 - D(i,j,k,2)D(i,j,k,6) = -D(i,j,k)\,E`).
    """

    index: int
    face: tuple
    bideterminant: object
    coefficient: object
    constant: object
    tetra_a: object
    tetra_b: object
    pentad: object

    def s26_branches(self):
        r"""The explicit pair :math:`s_{26} = (\pm\sqrt{D_a D_b} - b)/D(i,j,k)` (eq. (1) or (2)
        solved for :math:`s_{26}`), as ``(plus, minus)`` sympy expressions."""
        import sympy
        root = sympy.sqrt(self.tetra_a * self.tetra_b)
        return ((root - self.constant) / self.coefficient,
                (-root - self.constant) / self.coefficient)

    def equation(self, sign=1):
        """eq. (1) or (2) as ``lhs - rhs`` (zero on the chosen branch)."""
        import sympy
        return self.bideterminant - sign * sympy.sqrt(self.tetra_a * self.tetra_b)


@lru_cache(maxsize=None)
def _banana(index: int, subs_key) -> Banana:
    import sympy
    from ..geometry.cayley_menger import cayley_menger
    face, a, b = BANANAS[index]
    S = distance_matrix(dict(subs_key))
    s26 = squared_distance_symbols()[(2, 6)]
    bi = sympy.expand(cayley_menger(S, face + (a,), face + (b,)))
    coeff = sympy.expand(bi.coeff(s26, 1))
    const = sympy.expand(bi.subs(s26, 0))
    ta = sympy.expand(cayley_menger(S, face + (a,)))
    tb = sympy.expand(cayley_menger(S, face + (b,)))
    pent = sympy.expand(cayley_menger(S, face + (a, b)).subs(s26, 0))
    return Banana(index, face, bi, coeff, const, ta, tb, pent)


def banana(index: int, values=None) -> Banana:
    """Banana 1 (eq. (1)) or 2 (eq. (2)), optionally with some ``s_ij`` substituted.

    Parameters
    ----------
    index : {1, 2}
    values : dict {(i, j): number}, optional
        Squared distances fixed by a scene (e.g. the base and platform sides).

    Examples
    --------
    >>> from distkin.octahedral.banana import banana, squared_distance_symbols
    >>> b = banana(1)
    >>> s = squared_distance_symbols()
    >>> import sympy
    >>> sympy.expand(b.bideterminant - b.coefficient * s[(2, 6)] - b.constant)
    0
    """
    if index not in BANANAS:
        from ..errors import InputError
        raise InputError(f"expected banana 1 or 2, got {index!r}", field="index")
    key = tuple(sorted(((min(i, j), max(i, j)), v) for (i, j), v in (values or {}).items()))
    return _banana(index, key)
