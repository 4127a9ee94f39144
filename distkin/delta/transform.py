r"""Δ-transforms: 6-6 platforms kinematically equivalent to the octahedral manipulator.

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited* (ICRA 2012), Sections
IV-VI, and Borràs, Thomas, Torras, "On Δ-transforms", IEEE T-RO 25(6), 2009 (ref. [20]
there).

Every formula here is *derived* with sympy, not typed in from the paper:

1. :func:`derive_eq7` — eq. (7) is the square root of the Cayley-Menger determinant
   :math:`D(1,2,3,4)` of four coplanar points with :math:`P_4` on the line
   :math:`P_1P_2` at distance :math:`\delta` from :math:`P_1`
   (:math:`D(1,2,3,4) = -2\,L^2`, :math:`L` = the left side of eq. (7)).
2. :func:`delta_matrices` — solving eq. (7) for the moved leg gives each row of
   :math:`\mathbf A` and :math:`\mathbf b` of eqs. (8)-(9),
   :math:`m^2 = \mathbf A\, l^2 - \mathbf b` (the *minus* sign of eq. (8) holds with
   :math:`b_i = \delta_i (d_i - \delta_i)`; eq. (4) has :math:`+\mathbf b` with the
   opposite sign convention for :math:`\mathbf b`).
3. :meth:`DeltaTransform.det_factors` — :math:`\det \mathbf A` factorised into
   irreducible factors; its real zero set is the locus of architecturally singular
   platforms.
4. :func:`_generic_inverse` — eq. (8) solved for :math:`l^2` once, for symbolic sides
   and offsets (:math:`\operatorname{adj}(\operatorname{diag}(d)\mathbf A)`); numbers are
   substituted into it, so that float data (sides that are square roots) keep small
   exact forms.  Data are never rounded: a bare float is its exact binary value
   (docs/design.md §3, :mod:`.exact_input`).

Labelling (docs/design.md §3, paper Fig. 4 and eq. (9)): base :math:`P_1P_2P_3`, platform
:math:`P_4P_5P_6`; leg 1 = P1–P4, 2 = P2–P4, 3 = P2–P5, 4 = P3–P5, 5 = P3–P6,
6 = P1–P6.  Row :math:`i` of eq. (9) splits the double-ball joint shared by legs
:math:`i` and :math:`i+1` (cyclically) by moving one end of leg :math:`i` along a
triangle edge by :math:`\delta_i` (:data:`ROWS`).  The resulting 6-6 platform
(Fig. 6) is built by :func:`equivalent_platform`; its forward kinematics
(:func:`forward_kinematics66`) maps the m-legs to l-legs and solves the octahedral
problem.

sympy is imported inside the functions that need it; the numeric 6-6 pose check uses
numpy / mpmath / flint only.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np

from ..errors import DegenerateGeometryError, InfeasibleError, InputError
from .exact_input import (_as_sym, _base_platform, _check_count, _exact_form, _is_zero,
                          _quotient, _readable, _sym_points)

__all__ = [
    "RowSpec",
    "ROWS",
    "SIDE_NAMES",
    "Eq7",
    "derive_eq7",
    "delta_matrices",
    "side_lengths",
    "DeltaTransform",
    "delta_transform",
]


@dataclass(frozen=True)
class RowSpec:
    """One row of eq. (9): which double-ball joint is split and how.

    Attributes
    ----------
    row : int
        1-based row of :math:`\\mathbf A` (= the m-leg it defines).
    edge : (int, int)
        The triangle edge :math:`(P_s, P_e)` along which the joint moves, by
        :math:`\\delta` from :math:`P_s` towards :math:`P_e`.
    side : str
        Name of the edge length (``"d12"``, ...), as in eq. (9).
    legs : (int, int)
        The l-legs ending at :math:`P_s` and at :math:`P_e` (their squares get the
        weights :math:`(d-\\delta)/d` and :math:`\\delta/d`).
    shared : int
        The point both legs share (the end of the m-leg that does not move).
    moved : str
        ``"base"`` or ``"platform"``: which side the new joint lies on.
    """

    row: int
    edge: tuple
    side: str
    legs: tuple
    shared: int
    moved: str


#: the six rows of eq. (9), in order
ROWS = (
    RowSpec(1, (1, 2), "d12", (1, 2), 4, "base"),
    RowSpec(2, (4, 5), "d45", (2, 3), 2, "platform"),
    RowSpec(3, (2, 3), "d23", (3, 4), 5, "base"),
    RowSpec(4, (5, 6), "d56", (4, 5), 3, "platform"),
    RowSpec(5, (3, 1), "d13", (5, 6), 6, "base"),
    RowSpec(6, (6, 4), "d46", (6, 1), 1, "platform"),
)

#: edge-length names in row order of eq. (9)
SIDE_NAMES = tuple(r.side for r in ROWS)


# --------------------------------------------------------------------------- eq. (7)

@dataclass(frozen=True)
class Eq7:
    """Eq. (7) as derived from the Cayley-Menger determinant (sympy objects).

    Attributes
    ----------
    symbols : dict
        ``d`` (edge length :math:`d_{1,2}`), ``delta``, ``s13``, ``s23``, ``s34``.
    cm : sympy.Expr
        :math:`D(1,2,3,4)` with :math:`s_{14}=\\delta^2`, :math:`s_{24}=(d-\\delta)^2`,
        :math:`s_{12}=d^2` (expanded).
    relation : sympy.Expr
        :math:`L` with :math:`D(1,2,3,4) = -2L^2`, normalised so that the coefficient
        of :math:`s_{3,4}` is :math:`-d` (the paper's eq. (7) reads :math:`L = 0`).
    s34 : sympy.Expr
        :math:`s_{3,4}` solved from :math:`L = 0`: affine in :math:`s_{1,3}, s_{2,3}`.
    """

    symbols: dict
    cm: object
    relation: object
    s34: object


@lru_cache(maxsize=1)
def derive_eq7() -> Eq7:
    r"""Derive eq. (7) of Rojas et al. from the vanishing Cayley-Menger determinant.

    Four points with :math:`P_4` on the line :math:`P_1P_2`
    (:math:`|P_1P_4| = \delta`, :math:`|P_4P_2| = d - \delta`) are coplanar whatever
    :math:`P_3`, so :math:`D(1,2,3,4) = 0`.  As a polynomial in the squared distances
    that determinant is :math:`-2L^2` with :math:`L` linear in :math:`s_{1,3}`,
    :math:`s_{2,3}`, :math:`s_{3,4}`:

    .. math:: L = \delta s_{2,3} + (d-\delta) s_{1,3} - d\, s_{3,4} - d\,\delta(d-\delta)

    which is eq. (7).  The factorisation is computed, not assumed: a
    :class:`RuntimeError` is raised if sympy does not find a squared linear factor.

    Returns
    -------
    Eq7
    """
    import sympy as sp

    from ..geometry.cayley_menger import cayley_menger
    d, delta, s13, s23, s34 = sp.symbols("d delta s13 s23 s34", positive=True)
    S = sp.Matrix([[0, d ** 2, s13, delta ** 2],
                   [d ** 2, 0, s23, (d - delta) ** 2],
                   [s13, s23, 0, s34],
                   [delta ** 2, (d - delta) ** 2, s34, 0]])
    cm = sp.expand(cayley_menger(S, (1, 2, 3, 4)))
    const, factors = sp.factor_list(cm)
    squared = [f for f, k in factors if k == 2 and sp.Poly(f, s34).degree() == 1]
    if len(squared) != 1:
        raise RuntimeError(f"D(1,2,3,4) did not factor as c*L^2: {factors}")
    L = squared[0]
    c34 = sp.Poly(L, s34).coeffs()[0]
    L = sp.expand(L * (-d) / c34)            # coefficient of s34 is -d, as printed
    scale = sp.simplify(cm / L ** 2)
    if scale != -2:
        raise RuntimeError(f"D(1,2,3,4) = {scale} * L^2, expected -2 * L^2")
    s34_sol = sp.expand(sp.solve(L, s34)[0])
    return Eq7({"d": d, "delta": delta, "s13": s13, "s23": s23, "s34": s34}, cm, L, s34_sol)


def delta_matrices(sides, offsets):
    r"""The matrix :math:`\mathbf A` and vector :math:`\mathbf b` of eqs. (8)-(9).

    Row :math:`i` is eq. (7) solved for the moved leg (:func:`derive_eq7`) with
    :math:`s_{1,3} \to l_{\text{start}}^2`, :math:`s_{2,3} \to l_{\text{end}}^2`,
    :math:`s_{3,4} \to m_i^2`, :math:`d \to d_i`, :math:`\delta \to \delta_i`
    (:data:`ROWS`), so that

    .. math:: m^2 = \mathbf A\, l^2 - \mathbf b .

    Parameters
    ----------
    sides : sequence of 6 sympy expressions or numbers
        Edge lengths :math:`d_{12}, d_{45}, d_{23}, d_{56}, d_{13}, d_{46}` (row order).
    offsets : sequence of 6 sympy expressions, numbers or symbols
        :math:`\delta_1, \dots, \delta_6` (row order of eq. (9)).

    Returns
    -------
    A : sympy.ImmutableMatrix (6, 6)
    b : sympy.ImmutableMatrix (6, 1)
    """
    import sympy as sp
    eq = derive_eq7()
    sy = eq.symbols
    A = sp.zeros(6, 6)
    b = sp.zeros(6, 1)
    for spec, d, delta in zip(ROWS, sides, offsets):
        expr = eq.s34.subs({sy["d"]: d, sy["delta"]: delta}, simultaneous=True)
        i = spec.row - 1
        start, end = spec.legs
        A[i, start - 1] = sp.factor(sp.diff(expr, sy["s13"]))
        A[i, end - 1] = sp.factor(sp.diff(expr, sy["s23"]))
        b[i] = sp.factor(-expr.subs({sy["s13"]: 0, sy["s23"]: 0}))
    return sp.ImmutableMatrix(A), sp.ImmutableMatrix(b)


def side_lengths(base, platform) -> tuple:
    """Edge lengths :math:`d_{12}, d_{45}, d_{23}, d_{56}, d_{13}, d_{46}` (row order of
    eq. (9)), exact (sympy), from P1..P3 (``base``) and P4..P6 (``platform``, any frame).

    Raises
    ------
    InputError
        Not 3 points of 3 finite numbers each.
    DegenerateGeometryError
        A zero-length edge (coincident points).
    """
    import sympy as sp
    pts = _sym_points(base, platform)
    out = []
    for spec in ROWS:
        i, j = spec.edge
        sq = _exact_form(sum((a - c) ** 2 for a, c in zip(pts[i - 1], pts[j - 1])))
        if sq == 0:
            where = f"base[{j - 1}]" if j <= 3 else f"platform[{j - 4}]"   # QA J 9
            raise DegenerateGeometryError(f"expected distinct points P{i} and P{j}, got "
                                          f"{spec.side} = 0 (length units)", field=where)
        out.append(sp.sqrt(sq))
    return tuple(out)


# ------------------------------------------------------------- eq. (8) solved for l^2

@dataclass(frozen=True)
class _GenericInverse:
    r""":math:`\mathbf A^{-1}` of eq. (9) for symbolic sides and offsets (see
    :func:`_generic_inverse`)."""

    sides: tuple
    offsets: tuple
    N: object
    den: object


@lru_cache(maxsize=1)
def _generic_inverse() -> _GenericInverse:
    r"""Eq. (8) solved for :math:`l^2`, derived once for symbolic :math:`d_i, \delta_i`.

    Row :math:`i` of :math:`\mathbf A` (:func:`delta_matrices`) has the two entries
    :math:`(d_i-\delta_i)/d_i` and :math:`\delta_i/d_i`, so :math:`\mathbf B =
    \operatorname{diag}(d)\,\mathbf A` is polynomial (cyclic bidiagonal) and

    .. math:: \mathbf A^{-1} = \frac{\operatorname{adj}(\mathbf B)\operatorname{diag}(d)}
              {\det \mathbf B}, \qquad
              \det \mathbf B = \prod_i (d_i - \delta_i) - \prod_i \delta_i ,

    whose numerators are products of six factors.  Substituting numbers into this form
    keeps the exact :math:`l^2` small when the sides are square roots (float
    coordinates): inverting the numeric matrix instead grew expressions without bound
    for six different irrational sides.  Rojas, Borràs, Thomas, *The Octahedral
    Manipulator Revisited* (ICRA 2012), Sec. V, eqs. (8)-(9).
    """
    import sympy as sp
    d = sp.symbols("d1:7", positive=True)
    delta = sp.symbols("delta1:7", positive=True)
    A, _ = delta_matrices(d, delta)
    B = (sp.diag(*d) * A).applyfunc(sp.cancel)
    if not all(x.is_polynomial(*d, *delta) for x in B):
        raise RuntimeError(f"diag(d) A is not polynomial: {B}")
    den = sp.expand(B.det(method="berkowitz"))
    N = (B.adjugate(method="berkowitz") * sp.diag(*d)).applyfunc(sp.factor)
    return _GenericInverse(d, delta, sp.ImmutableMatrix(N), den)


# ----------------------------------------------------------------- the transform itself


@dataclass(frozen=True)
class DeltaTransform:
    r"""The affine leg map :math:`m^2 = \mathbf A l^2 - \mathbf b` of eqs. (8)-(9).

    Build it with :func:`delta_transform`.  Everything is exact (sympy); offsets may
    be symbols (``Delta1``), then ``det`` is a polynomial in them.

    Attributes
    ----------
    sides : tuple of 6 sympy expressions (length units)
    offsets : tuple of 6 sympy expressions (length units)
    """

    sides: tuple
    offsets: tuple

    @cached_property
    def _Ab(self):
        return delta_matrices(self.sides, self.offsets)

    @property
    def A(self):
        """:math:`\\mathbf A` (6 x 6, dimensionless), eq. (9)."""
        return self._Ab[0]

    @property
    def b(self):
        """:math:`\\mathbf b` (6, squared length units), eq. (9)."""
        return self._Ab[1]

    @cached_property
    def det(self):
        """:math:`\\det \\mathbf A`, expanded (a polynomial in symbolic offsets)."""
        import sympy as sp
        return sp.expand(self.A.det(method="berkowitz"))

    @cached_property
    def free_symbols(self) -> tuple:
        syms = set()
        for x in self.offsets:
            syms |= getattr(x, "free_symbols", set())
        return tuple(sorted(syms, key=str))

    def det_factors(self):
        """``(constant, [(factor, multiplicity), ...])``: the irreducible factorisation
        of :math:`\\det\\mathbf A` over the rationals (sympy ``factor_list``)."""
        import sympy as sp
        if self.det.free_symbols:
            return sp.factor_list(self.det, *self.free_symbols)
        return sp.factor_list(self.det)

    def vanishing_factors(self) -> list:
        r"""Name the factors of :math:`\det\mathbf A` that vanish at these offsets.

        Rows with the same offset and the same side length are given one symbol (the
        offset ``delta<i>`` of the first such row; for the paper's 3-fold family these
        are ``delta1`` and ``delta2``), :math:`\det\mathbf A` is factorised over that
        family and the factors that vanish are returned.  With six different rows the
        only factor is :math:`\prod(d_i-\delta_i) - \prod\delta_i` (up to a constant).

        Returns
        -------
        list of sympy.Expr
            Empty when :math:`\det\mathbf A \ne 0` or the offsets are symbolic.  A
            factor of more than 12 terms that is the closed form above is returned in
            that form (unevaluated products).
        """
        import sympy as sp
        if self.free_symbols or self.det != 0:
            return []
        groups, fam, subs = [], [], {}
        for i, (o, d) in enumerate(zip(self.offsets, self.sides)):
            for og, dg, sym in groups:
                if sp.simplify(og - o) == 0 and sp.simplify(dg - d) == 0:
                    break
            else:
                sym = sp.Symbol(f"delta{i + 1}", real=True)
                groups.append((o, d, sym))
                subs[sym] = o
            fam.append(sym)
        syms = [g[2] for g in groups]
        det = sp.expand(DeltaTransform(self.sides, tuple(fam)).det)
        _, factors = sp.factor_list(det, *syms)
        out = [f for f, _k in factors if sp.simplify(f.subs(subs)) == 0]
        return [_compact(f, self.sides, fam) for f in (out or [det])]

    def check_regular(self, field: str = "offsets") -> None:
        """Raise :class:`DegenerateGeometryError` when :math:`\\det\\mathbf A = 0`
        (architecturally singular 6-6 platform), naming the vanishing factor."""
        import sympy as sp
        if self.det == 0:
            if self.free_symbols:
                raise DegenerateGeometryError(
                    "expected offsets with det(A) != 0, got det(A) = 0 identically", field=field)
            f = " and ".join(sp.sstr(x) for x in self.vanishing_factors())
            vals = ", ".join(f"delta{i + 1} = {o}" for i, o in enumerate(self.offsets))
            raise DegenerateGeometryError(
                f"expected offsets with det(A) != 0 (else the 6-6 platform is architecturally "
                f"singular), got det(A) = 0: the factor {f} of det(A) vanishes at "
                f"{vals}", field=field,
                hint="move the offsets off the singular locus")

    def inverse(self):
        r"""``(Ainv, c)`` with :math:`l^2 = \mathbf A^{-1}(m^2 + \mathbf b)
        = \mathbf{A}^{-1} m^2 + c` (exact, computed once per transform).  Raises
        :class:`DegenerateGeometryError` when :math:`\det \mathbf A = 0`."""
        self.check_regular()
        return self._inverse

    @cached_property
    def _inverse_parts(self):
        r"""``(N, Nc, den)``: :math:`\mathbf A^{-1} = N/den`, :math:`c = Nc/den`, from the
        derived closed form (:func:`_generic_inverse`) with this transform's sides and
        offsets substituted; numerators and denominator expanded (exact)."""
        import sympy as sp
        g = _generic_inverse()
        sub = dict(zip(g.sides, self.sides)) | dict(zip(g.offsets, self.offsets))
        den = sp.expand(g.den.xreplace(sub))
        N = sp.ImmutableMatrix(g.N.xreplace(sub).applyfunc(sp.expand))
        Nc = sp.ImmutableMatrix((N * self.b).applyfunc(sp.expand))
        return N, Nc, den

    @cached_property
    def _inverse(self):
        import sympy as sp
        N, Nc, den = self._inverse_parts
        return (sp.ImmutableMatrix(N.applyfunc(lambda x: _quotient(x, den))),
                sp.ImmutableMatrix(Nc.applyfunc(lambda x: _quotient(x, den))))

    @cached_property
    def _inverse_float(self):
        Ainv, c = self.inverse()
        return (np.array(Ainv.tolist(), dtype=float), np.array(c.tolist(), dtype=float).ravel())

    def map_legs_float(self, m_legs, field: str = "m_legs"):
        r""":meth:`map_legs` in float64 for the fast tier: :math:`l^2 = \mathbf A^{-1} m^2 + c`
        with the exact inverse rounded once per transform (no algebra per call), except
        where its rounding-error bound cannot prove every :math:`l_k^2 > 0`: the exact
        map then decides (:func:`.leg_map_rounding.map_legs_fast`).

        Returns
        -------
        l_sq, l : arrays (6,) (squared length units, length units)

        Raises
        ------
        InputError
            As :meth:`map_legs`; also m-legs beyond the octahedral solver's range
            (largest below :math:`2^{510}`) or whose mapped squares overflow float64.
        DegenerateGeometryError, InfeasibleError
            As :meth:`map_legs` (infeasible only when the exact :math:`l_k^2 \le 0`).
        """
        from .leg_map_rounding import map_legs_fast
        return map_legs_fast(self, m_legs, field)[:2]

    def map_error_float(self, m_legs, l_sq) -> float:
        r"""A rigorous bound on the relative error of :meth:`map_legs_float`'s ``l_sq``
        against the exact :math:`l^2` of eq. (8) (dimensionless; inf when it cannot be
        bounded): :func:`.leg_map_rounding.leg_map_error` (QA J 1)."""
        from .leg_map_rounding import leg_map_error
        Ainv, c = self._inverse_float
        return leg_map_error(Ainv, c, m_legs, l_sq)

    def forward(self, l_sq):
        r"""m-legs squared from l-legs squared: :math:`\mathbf A l^2 - \mathbf b`, eq. (8)."""
        import sympy as sp
        _check_count(l_sq, "l_sq", "squared leg lengths")
        v = sp.Matrix([_as_sym(x, f"l_sq[{i}]") for i, x in enumerate(l_sq)])
        return tuple(_exact_form(x) for x in (self.A * v - self.b))

    def map_legs(self, m_legs, field: str = "m_legs"):
        r"""The l-legs of the octahedral manipulator equivalent to m-legs ``m_legs``.

        :math:`l^2 = \mathbf A^{-1}(m^2 + \mathbf b)`, exact: eq. (8) of Rojas, Borràs,
        Thomas, *The Octahedral Manipulator Revisited* (ICRA 2012), Sec. V, inverted.
        A bare float is its exact binary value (docs/design.md §3), strings and
        rationals are exact, and the result is only expanded or put over one denominator
        (:func:`~.exact_input._quotient`), never rounded to a "nice" number.

        Parameters
        ----------
        m_legs : sequence of 6 (Exact, str, number or sympy expression)
            Lengths :math:`m_1..m_6` of the 6-6 platform's legs (length units); symbols
            are allowed (then ``l_sq`` is symbolic).

        Returns
        -------
        l_sq : tuple of 6 sympy expressions
            Squared lengths :math:`l_i^2` (squared length units).
        l : tuple of 6 sympy expressions
            :math:`l_i = \sqrt{l_i^2}` (length units; symbolic when offsets are).

        Raises
        ------
        InputError
            Not six values, a non-positive, non-finite or malformed length.
        DegenerateGeometryError
            :math:`\det \mathbf A = 0`.
        InfeasibleError
            A mapped squared length is negative (no real octahedral manipulator has
            these legs); ``margin`` is the most negative :math:`l_i^2`.
        """
        import sympy as sp
        _check_count(m_legs, field)
        ms = []
        for i, m in enumerate(m_legs):
            v = _as_sym(m, f"{field}[{i}]")
            if v.is_number and not v.is_positive:
                raise InputError(f"expected a positive leg length, got {m!r}",
                                 field=f"{field}[{i}]")
            ms.append(v)
        self.check_regular()
        N, Nc, den = self._inverse_parts
        m_sq = sp.Matrix([sp.expand(m ** 2) for m in ms])
        l_sq = tuple(_quotient(x, den) for x in (N * m_sq + Nc))
        bad = [(i, x) for i, x in enumerate(l_sq) if x.is_number and x.is_negative]
        zero = [i for i, x in enumerate(l_sq) if x.is_number and _is_zero(x)]
        if bad:
            # (compared and shown by sympy's evaluation: float() overflows at 1e309)
            i, x = min(bad, key=lambda t: sp.Float(sp.N(t[1], 15)))
            raise InfeasibleError(
                f"expected non-negative squared l-legs, got l{i + 1}^2 = {_readable(x)} "
                f"squared length units after the inverse map of eq. (8)",
                margin=float(x), field=f"{field}",
                hint="no octahedral manipulator, hence no 6-6 pose, has these m-legs")
        if zero:
            raise InfeasibleError(f"expected positive l-legs, got l{zero[0] + 1} = 0",
                                  margin=0.0, field=field)
        return l_sq, tuple(sp.sqrt(x) for x in l_sq)


def delta_transform(octahedral, offsets, field: str = "offsets") -> DeltaTransform:
    """The Δ-transform of an octahedral mechanism with offsets δ1..δ6 (eq. (9) order).

    Parameters
    ----------
    octahedral : distkin.app.scene.Octahedral or (base, platform)
        Base P1..P3 and platform P4..P6 (3 x 3 each; Exact, str or numbers).
    offsets : sequence of 6 values
        Numbers, numeric strings or symbol names such as ``"Delta1"`` (length units).

    Returns
    -------
    DeltaTransform

    Raises
    ------
    InputError
        Not six offsets, or a malformed one; points that are not 3 x 3 finite numbers
        (the field names the coordinate, e.g. ``base[1][1]``).

    Examples
    --------
    The example of Rojas et al., Sec. VI:

    >>> gd = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]],
    ...       [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
    >>> tr = delta_transform(gd, ["12/5", "6/5"] * 3)
    >>> tr.det
    819/3125
    >>> m = ["6/25*sqrt(6170)", "6/5*sqrt(221)", "1/5*sqrt(7349)", "1/50*sqrt(674605)",
    ...      "1/25*sqrt(136210)", "1/5*sqrt(8153)"]
    >>> [str(x) for x in tr.map_legs(m)[1]]
    ['99/5', '18', '18', '17', '149/10', '89/5']
    >>> delta_transform(gd, ["Delta1", "Delta2"] * 3).det_factors()[1][0]
    (Delta1 + 2*Delta2 - 12, 1)
    """
    base, platform = _base_platform(octahedral)
    if not isinstance(offsets, (list, tuple, np.ndarray)) or len(offsets) != 6:
        raise InputError(f"expected 6 offsets delta1..delta6, got {offsets!r}", field=field)
    offs = tuple(_as_sym(o, f"{field}[{i}]") for i, o in enumerate(offsets))
    return _cached_transform(side_lengths(base, platform), offs)


@lru_cache(maxsize=64)
def _cached_transform(sides, offsets) -> DeltaTransform:
    """One :class:`DeltaTransform` per (sides, offsets): its A, b, det and inverse are
    derived once ("derivations are cached", docs/design.md §1)."""
    return DeltaTransform(sides, offsets)


def _compact(f, sides, fam):
    r"""A long factor of :math:`\det\mathbf A` written as :math:`\prod_i(d_i - \delta_i) -
    \prod_i\delta_i` (unevaluated) when it is that product form up to a constant
    (its closed form, :meth:`DeltaTransform.vanishing_factors`; QA J 9: a 60-term
    expansion in the message), else ``f`` as it is."""
    import sympy as sp
    if len(sp.Add.make_args(f)) <= 12:
        return f
    closed = sp.Add(sp.Mul(*[sp.UnevaluatedExpr(d - x) for d, x in zip(sides, fam)],
                           evaluate=False), -sp.Mul(*fam), evaluate=False)
    ratio = sp.cancel(sp.expand(closed.doit()) / f)
    return closed if ratio.is_number and ratio != 0 else f
