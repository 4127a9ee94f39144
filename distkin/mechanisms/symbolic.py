"""The sympy model of a mechanism's legs: closure, closed-form IK, Jq, Jx, J = Jq^-1 Jx.

:class:`ModelExprs` builds it from a leg table (:mod:`.legs`: revolute RSS/RUS/RRRS legs
as below with the leg's own vectors, crank direction v at q = 90 deg in place of z and
its own branch; prismatic SPS/UPS legs with q = |P - B| and the normalised Plücker line,
Rojas et al. eq. (5)); an RSS description (kind "rss") is built from the parametric leg
of Fig. 2 below, the same algebra, which keeps the committed preset kernels as they were.

Kühne et al., Sec. II-C, eqs. (1)-(2), Fig. 2; parametrisation in :mod:`.presets`,
pose in :mod:`distkin.spatial`.  This module imports sympy; numeric code uses the kernels
generated from it (:mod:`.kernels`), never this module.

Leg i (side s = ±1), with constant vectors B (crank pivot), a (actuator axis), u
(horizontal crank direction at q = 0), o (crank tip -> universal joint, length l2 along
the axis) and p (spherical joint in the end-effector frame); the reading of Fig. 2
(:mod:`.presets`) fixes a, u and o: "tangential" a = Rz(s beta) t, u = a x z (radially
outwards at beta = 0), o = s l2 a; "radial" a = Rz(s beta) e, u = s z x a, o = l2 a::

    D(q) = B + o + l1 (cos q u + sin q z)          universal-joint centre
    P    = x + R(r) p                               spherical joint
    Phi(q, x) = (|P - D(q)|^2 - l3^2) / (2 l3)      closure, metres (≈ length error)

With w = P - B - o the closure is ``A cos q + Bz sin q = C`` where A = w.u,
Bz = w.z, C = (w.w + l1^2 - l3^2) / (2 l1).  With rho^2 = A^2 + Bz^2 and
h = sqrt(rho^2 - C^2) the two solutions are
``cos q = (A C + sigma Bz h) / rho^2``, ``sin q = (Bz C - sigma A h) / rho^2``;
sigma = :data:`BRANCH` is the branch nearer to q = 0 at the workspace centre
(``q = phi - sigma delta`` with phi the direction of (A, Bz) and cos delta = C/rho).  A leg closes
iff the *reach margin* rho^2 - C^2 >= 0; otherwise h = sqrt(|rho^2 - C^2|) keeps q
finite (flagged invalid, never NaN).

Differentiating Phi: Jq_ii = dPhi_i/dq_i and, with g = dPhi/dP and r = R p,
dPhi = g.(v + omega x r) + Jq_ii dq, so Jx_i = -(g, r x g) and J_i = Jx_i / Jq_ii
(eqs. (1)-(2)).  Fixed parameters are substituted *before* the differentiation and
before common-subexpression elimination (docs/design.md §1).
"""

from __future__ import annotations

import math

import sympy as sp

__all__ = ["POSE", "BRANCH", "pose_symbols", "q_symbols", "rotation_matrix", "generic_leg",
           "leg_values", "exact_number", "ModelExprs", "model_expressions"]

#: IK branch sign sigma (see the module docstring); checked by derivations/rss_model.py
BRANCH = 1

POSE = sp.symbols("x y z rx ry rz", real=True)

_PAR = sp.symbols("l0 l1 l2 l3 lp ld", positive=True)
_TRIG = sp.symbols("ce se cb sb cg sg s", real=True)


def pose_symbols():
    """(x, y, z, rx, ry, rz)."""
    return POSE


def q_symbols(L: int):
    """(q1, ..., qL), the crank angles."""
    return sp.symbols(f"q1:{L + 1}", real=True)


def rotation_matrix(rx, ry, rz):
    """R = Rz(rz) Ry(ry) Rx(rx) (:mod:`distkin.spatial`)."""
    cx, sx, cy, sy, cz, sz = sp.cos(rx), sp.sin(rx), sp.cos(ry), sp.sin(ry), sp.cos(rz), sp.sin(rz)
    Rx = sp.Matrix([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    Ry = sp.Matrix([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rz = sp.Matrix([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return Rz * Ry * Rx


def generic_leg(layout: str = "tangential"):
    """The leg model in terms of parameter symbols, for a reading of Fig. 2.

    Parameters
    ----------
    layout : {"tangential", "radial", "tangential_in"}
        :data:`distkin.mechanisms.rss.LAYOUTS`.

    Returns
    -------
    dict
        ``B, a, u, o, p`` (3-vectors), ``P`` (symbols Px, Py, Pz), ``q``, ``Phi(q, P)``,
        and the symbols used (``params``: l0 l1 l2 l3 lp ld; ``trig``: cos/sin of the
        pair azimuth, of beta, of gamma, and the side s).
    """
    l0, l1, l2, l3, lp, ld = _PAR
    ce, se, cb, sb, cg, sg, s = _TRIG
    e = sp.Matrix([ce, se, 0])
    t = sp.Matrix([-se, ce, 0])
    zh = sp.Matrix([0, 0, 1])
    B = l0 * e + s * ld / 2 * t
    if layout in ("tangential", "tangential_in"):
        a = sp.Matrix([cb * t[0] - s * sb * t[1], s * sb * t[0] + cb * t[1], 0])  # Rz(s beta) t
        u = a.cross(zh)                   # horizontal crank, radially outwards ...
        if layout == "tangential_in":
            u = -u                        # ... or inwards
        o = s * l2 * a                    # RRRS offset along the axis, away from the pair
    elif layout == "radial":
        a = sp.Matrix([cb * e[0] - s * sb * e[1], s * sb * e[0] + cb * e[1], 0])  # Rz(s beta) e
        u = s * zh.cross(a)               # horizontal crank, away from the pair's centre
        o = l2 * a                        # RRRS offset, outwards along the axis
    else:
        raise ValueError(f"expected layout 'tangential', 'radial' or 'tangential_in', got "
                         f"{layout!r}")
    p0 = lp * e + s * ld / 2 * t
    p = sp.Matrix([cg * p0[0] - s * sg * p0[1], s * sg * p0[0] + cg * p0[1], 0])  # Rz(s gamma)
    q = sp.Symbol("q", real=True)
    P = sp.Matrix(sp.symbols("Px Py Pz", real=True))
    D = B + o + l1 * (sp.cos(q) * u + sp.sin(q) * zh)
    Phi = ((P - D).dot(P - D) - l3 ** 2) / (2 * l3)
    return {"B": B, "a": a, "u": u, "o": o, "p": p, "P": P, "q": q, "Phi": Phi, "D": D,
            "params": _PAR, "trig": _TRIG}


def _num(v: float):
    """A parameter value as a sympy number: exact 0, ±1, ±1/2 where the float is, else Float."""
    for r in (0, 1, -1, sp.Rational(1, 2), sp.Rational(-1, 2)):
        if v == float(r):
            return sp.sympify(r)
    return sp.Float(v)


def exact_number(v: float):
    """A float as its exact binary value, a sympy ``Rational`` (0.1 is
    3602879701896397/2^55): the numbers of the exact model (:class:`ModelExprs` with
    ``exact=True``), whose products and quotients sympy keeps exact."""
    return sp.Rational(float(v))


def leg_values(mech, i: int, exact: bool = False) -> dict:
    """Substitution of leg i's parameters: {symbol: number} (floats as sympy Floats).

    With ``exact=True`` the exact model's (:class:`ModelExprs`): every parameter its
    float's exact binary value (:func:`exact_number`), the cosine and sine of the pair
    azimuth 2 pi k / (L/2) exact (0, ±1/2, ±1, ±sqrt(3)/2, ...), and those of beta and
    gamma the exact cosine and sine of their floats' exact values (sympy ``cos`` of a
    rational, evaluated by the kernels)."""
    L = mech.legs
    k, s = i // 2, (-1 if i % 2 == 0 else 1)
    th = 2 * sp.pi * k / (L // 2)
    ce, se = sp.cos(th), sp.sin(th)
    vals = dict(zip(_PAR, [mech.l0, mech.l1, mech.l2, mech.l3, mech.lp, mech.ld]))
    tc, ts = _TRIG[:2]
    if exact:
        out = {sym: exact_number(v) for sym, v in vals.items()}
        out[tc], out[ts] = ce, se
        b, g = exact_number(mech.beta), exact_number(mech.gamma)
        out.update(zip(_TRIG[2:6], (sp.cos(b), sp.sin(b), sp.cos(g), sp.sin(g))))
        out[_TRIG[6]] = sp.Integer(s)
        return out
    out = {sym: _num(float(v)) for sym, v in vals.items()}
    out[tc] = ce if ce.is_Rational else _num(float(ce))
    out[ts] = se if se.is_Rational else _num(float(se))
    out[_TRIG[2]] = _num(math.cos(mech.beta))
    out[_TRIG[3]] = _num(math.sin(mech.beta))
    out[_TRIG[4]] = _num(math.cos(mech.gamma))
    out[_TRIG[5]] = _num(math.sin(mech.gamma))
    out[_TRIG[6]] = sp.Integer(s)
    return out


def _root_abs(e):
    """sqrt(|e|), built without sympy's (slow, here pointless) sign queries on ``e``."""
    return sp.Pow(sp.Abs(e, evaluate=False), sp.Rational(1, 2), evaluate=False)


class ModelExprs:
    r"""The symbolic kernels of one mechanism, built from its leg table
    (:class:`~.legs.LegsDescription`) and derived lazily (each only when asked).

    Revolute legs (RSS, RUS, RRRS) follow the module docstring with the leg's own
    vectors (crank direction v at q = 90 deg in place of z, its own branch sigma); a
    prismatic leg (SPS, UPS) has ``Phi = (|P - B|^2 - q^2) / (2 q)``, IK ``q = |P - B|``,
    ``Jq_ii = -1`` and ``Jx_i = -(n, r x n)`` with ``n = (P - B) / q``, so its row of J is
    the normalised Plücker line of the leg (Rojas et al., eq. (5)); its reach margin is
    ``(q - qmin)(qmax - q)`` (m^2) within a stroke ``range``, else ``q^2``.

    With ``exact=True`` (the arb flavour, :mod:`distkin.codegen.rss`) it is the *exact
    model*, the mechanism the certified tier certifies; sympy keeps every product and
    quotient of its numbers exact (rationals, sqrt(3), cos of a rational):

    - an RSS description: the parametric leg of Fig. 2 with its parameters exactly
      (:func:`leg_values` with ``exact=True``: each float's exact binary value, the pair
      azimuths' trigonometry exact, beta and gamma the floats' exact values).  Its crank
      frame is exactly orthonormal, so the closure and the closed-form IK describe the
      same mechanism.  (Its leg table, ``LEGS``, is that mechanism rounded to float64:
      cos 90° as 6.1e-17.)
    - a leg table: every number of the table its exact binary value
      (:func:`exact_number`).

    A revolute leg of a leg table has its closure written in the closed form the IK
    solves, in both models (the float one too),

    .. math:: \Phi = \bigl(w\cdot w - 2 l_1 (w\cdot u \cos q + w\cdot v \sin q)
              + l_1^2 - l_3^2\bigr) / (2 l_3)
              = (C - A\cos q - B_z \sin q)\, l_1 / l_3,

    with w = P - B - o.  That is :math:`(|P - D(q)|^2 - l_3^2) / (2 l_3)` when u and v
    are exactly orthonormal (directions of 0 and ±1); otherwise it *defines* the
    mechanism: the crank circle of radius l1 in the frame (u, v) taken as orthonormal,
    one mechanism for the IK, the Jacobian, the closure and so the forward kinematics.
    A float direction such as (cos 10°, sin 10°, 0) is unit only to ~1e-16, and the leg
    table accepts directions unit and orthogonal to 1e-9 (:mod:`.legs`): with the
    literal :math:`|P - D(q)|^2` the forward kinematics of such a table missed the
    closed-form IK's pose by up to ~l1 x 1e-9 (6e-11 m on a table whose crank0 is off
    by 4e-10, tests/mechanisms/test_legs_model.py).

    Attributes (sympy Matrices, functions of :data:`POSE` and, for ``closure``, of
    ``q_symbols(L)``)
    ----------
    ik : (L, 1) joint coordinates (rad; m for prismatic legs)
    reach : (L, 1) reach margins (m^2)
    jacobian : (L, 6) J
    jq_jx : (L, 7) [Jq_ii, Jx_i]
    closure : (L, 7) [Phi_i, dPhi_i/d(v, omega)]
    ranges : (R, 1) range margins (m^2) of the R revolute legs whose ``range`` is not the
        full turn, in leg order (:meth:`range_legs`; (0, 1) when there is none): with the
        range's middle m = (qmin + qmax)/2 and half-width w = (qmax - qmin)/2 (exactly,
        in the exact model), ``rho^2 (cos(q - m) - cos w)``, where ``rho^2 cos q`` and
        ``rho^2 sin q`` are ``A C + sigma B h`` and ``B C - sigma A h`` (h = sqrt(rho^2 -
        C^2), the IK's branch): > 0 iff q lies strictly inside [qmin, qmax] modulo 2π
        (w < π; :func:`~.legs.in_revolute_range`), a polynomial in A, B, C and h with no
        arctangent, so the certified workspace can enclose it over a box
        (:mod:`distkin.certify`).
    """

    NAMES = ("ik", "reach", "jacobian", "jq_jx", "closure", "ranges")

    def __init__(self, mech, exact: bool = False):
        self.desc = mech.leg_description()
        self.exact = bool(exact)
        #: the numbers: exact rationals, or Floats (exact 0, ±1, ±1/2)
        self.num = exact_number if self.exact else _num
        #: an RSS description (kind "rss") is derived from the parametric leg of Fig. 2
        #: (:func:`generic_leg`), the same algebra as its leg table; the two routes give
        #: the same kernels up to the rounding of the leg vectors (<= 1.4e-15 rad of IK,
        #: 8e-14 of J on the study grids), and the committed presets keep theirs
        self.rss = mech if getattr(mech, "kind", None) == "rss" else None
        self.L = self.desc.L
        self._legs = None
        self._cache = {}
        self.timings = {}

    def _leg_parts(self):
        """Per leg: Phi(q, P) with the leg's numbers, its derivatives, the IK pieces."""
        import time
        if self._legs is not None:
            return self._legs
        if self.rss is not None:
            self._legs = self._rss_parts()
            return self._legs
        t0 = time.perf_counter()
        x, y, zz, rx, ry, rz = POSE
        R = rotation_matrix(rx, ry, rz)
        X = sp.Matrix([x, y, zz])
        q = sp.Symbol("q", real=True)
        Psym = sp.Matrix(sp.symbols("Px Py Pz", real=True))
        legs = []
        t_diff = 0.0
        num = self.num
        for leg in self.desc.leg_table:
            vec = lambda v: sp.Matrix([num(c) for c in v])  # noqa: E731
            B, p = vec(leg.base), vec(leg.platform)
            r = R * p
            Pexpr = X + r
            part = dict(r=r, P=Pexpr, prismatic=leg.prismatic, branch=leg.branch,
                        range=leg.range)
            if leg.prismatic:
                d = Psym - B
                Phi = (d.dot(d) - q ** 2) / (2 * q)
                w = Pexpr - B
                part.update(Phi=Phi, w=w, n2=w.dot(w))
            else:
                o, u, v = vec(leg.offset), vec(leg.crank0), vec(leg.crank90)
                l1, l3 = num(leg.crank), num(leg.distal)
                # the closed form the IK solves (class docstring), in both models
                d = Psym - B - o
                Phi = (d.dot(d) - 2 * l1 * (sp.cos(q) * d.dot(u) + sp.sin(q) * d.dot(v))
                       + l1 ** 2 - l3 ** 2) / (2 * l3)
                w = Pexpr - B - o
                part.update(Phi=Phi, A=w.dot(u), Bz=w.dot(v),
                            C=(w.dot(w) + l1 ** 2 - l3 ** 2) / (2 * l1))
            tb = time.perf_counter()
            part["dPhi_dq"] = sp.diff(Phi, q)
            part["gP"] = sp.Matrix([sp.diff(Phi, c) for c in Psym])
            t_diff += time.perf_counter() - tb
            legs.append(part)
        self.timings["substitute"] = time.perf_counter() - t0 - t_diff
        self.timings["differentiate"] = t_diff
        self._legs = legs
        return legs

    @staticmethod
    def _cos_sin(leg):
        A, Bz, C, sigma = leg["A"], leg["Bz"], leg["C"], leg["branch"]
        rho2 = A ** 2 + Bz ** 2
        h = _root_abs(rho2 - C ** 2)
        cq = (A * C + sigma * Bz * h) / rho2
        sq = (Bz * C - sigma * A * h) / rho2
        return cq, sq, rho2

    def _rss_parts(self):
        """Per leg of an RSS description: the parametric leg of Fig. 2 (:func:`generic_leg`)
        with the parameters substituted, its derivatives and the IK pieces."""
        import time
        t0 = time.perf_counter()
        g = generic_leg(self.rss.layout)
        x, y, zz, rx, ry, rz = POSE
        R = rotation_matrix(rx, ry, rz)
        X = sp.Matrix([x, y, zz])
        q, Psym = g["q"], g["P"]
        legs = []
        t_subs = t_diff = 0.0
        for i in range(self.L):
            ta = time.perf_counter()
            vals = leg_values(self.rss, i, self.exact)
            # parameters first (docs/design.md §1): everything below sees numbers
            Phi = g["Phi"].xreplace(vals)
            p = g["p"].xreplace(vals)
            B, o, u = (g[n].xreplace(vals) for n in ("B", "o", "u"))
            l1, l3 = vals[_PAR[1]], vals[_PAR[3]]
            r = R * p
            Pexpr = X + r
            tb = time.perf_counter()
            dPhi_dq = sp.diff(Phi, q)
            gP = sp.Matrix([sp.diff(Phi, c) for c in Psym])
            tc = time.perf_counter()
            w = Pexpr - B - o
            A = w.dot(u)
            Bz = w[2]
            C = (w.dot(w) + l1 ** 2 - l3 ** 2) / (2 * l1)
            legs.append(dict(Phi=Phi, dPhi_dq=dPhi_dq, gP=gP, r=r, P=Pexpr, A=A, Bz=Bz, C=C,
                             prismatic=False, branch=BRANCH, range=None))
            t_subs += tb - ta
            t_diff += tc - tb
        self.timings["substitute"] = time.perf_counter() - t0 - t_diff
        self.timings["differentiate"] = t_diff
        self._legs = legs
        return legs

    def _subsP(self, expr, leg):
        Psym = sp.symbols("Px Py Pz", real=True)
        return expr.xreplace(dict(zip(Psym, leg["P"])))

    def legs(self):
        """Per leg: ``Phi`` (closure in q, Px, Py, Pz with the leg's numbers) and ``P``
        (the platform joint as a function of the pose)."""
        return self._leg_parts()

    def signature(self) -> str:
        """What the kernels depend on besides the closures: branches and ranges ("" for
        an RSS description, whose branch is :data:`BRANCH` of this model)."""
        if self.rss is not None:
            return ""
        return repr([(leg["prismatic"], leg["branch"], leg["range"]) for leg in self.legs()])

    def _row(self, name, leg, i):
        q = sp.Symbol("q", real=True)
        if leg["prismatic"]:
            qv = _root_abs(leg["n2"])
            if name == "ik":
                return [qv]
            if name == "reach":
                lo, hi = leg["range"] or (None, None)
                return [leg["n2"] if lo is None else (qv - self.num(lo)) * (self.num(hi) - qv)]
            if name == "closure":
                qs = q_symbols(self.L)
                phi = self._subsP(leg["Phi"], leg).xreplace({q: qs[i]})
                gP = self._subsP(leg["gP"], leg).xreplace({q: qs[i]})
                return [phi] + list(gP.col_join(leg["r"].cross(gP)))
            n = leg["w"] / qv
            line = list(n.col_join(leg["r"].cross(n)))       # Plücker, Rojas et al. eq. (5)
            return [sp.Integer(-1)] + [-c for c in line] if name == "jq_jx" else line
        if name == "ik":
            A, Bz, C, sigma = leg["A"], leg["Bz"], leg["C"], leg["branch"]
            h = _root_abs(A ** 2 + Bz ** 2 - C ** 2)
            # evaluate=False: sympy would otherwise query signs of large expressions
            return [sp.atan2(Bz * C - sigma * A * h, A * C + sigma * Bz * h, evaluate=False)]
        if name == "reach":
            return [leg["A"] ** 2 + leg["Bz"] ** 2 - leg["C"] ** 2]
        if name in ("jacobian", "jq_jx"):
            cq, sq, _ = self._cos_sin(leg)
            rep = {sp.cos(q): cq, sp.sin(q): sq}
            jq = self._subsP(leg["dPhi_dq"], leg).xreplace(rep)
            gP = self._subsP(leg["gP"], leg).xreplace(rep)
            jx = -gP.col_join(leg["r"].cross(gP))
            return [jq] + list(jx) if name == "jq_jx" else [c / jq for c in jx]
        rep = {q: q_symbols(self.L)[i]}
        phi = self._subsP(leg["Phi"], leg).xreplace(rep)
        gP = self._subsP(leg["gP"], leg).xreplace(rep)
        return [phi] + list(gP.col_join(leg["r"].cross(gP)))

    def range_legs(self) -> list[int]:
        """The revolute legs (0-based) whose ``range`` is not the full turn: the rows of
        the ``ranges`` kernel (:func:`.legs.ranged_legs`; an RSS description has none)."""
        from .legs import ranged_legs
        return [] if self.rss is not None else ranged_legs(self.desc.leg_table)

    def _range_row(self, leg):
        """``rho^2 (cos(q - m) - cos w)`` of a revolute leg (class docstring, ``ranges``)."""
        A, Bz, C, sigma = leg["A"], leg["Bz"], leg["C"], leg["branch"]
        h = _root_abs(A ** 2 + Bz ** 2 - C ** 2)
        lo, hi = (self.num(v) for v in leg["range"])
        m, w = (lo + hi) / 2, (hi - lo) / 2       # exact rationals in the exact model
        cm, sm, cw = sp.cos(m), sp.sin(m), sp.cos(w)
        return [(A * C + sigma * Bz * h) * cm + (Bz * C - sigma * A * h) * sm
                - (A ** 2 + Bz ** 2) * cw]

    def get(self, name: str) -> sp.Matrix:
        if name in self._cache:
            return self._cache[name]
        if name not in self.NAMES:
            raise ValueError(f"expected a kernel in {self.NAMES}, got {name!r}")
        if name == "ranges":
            legs = self._leg_parts()
            rows = [self._range_row(legs[i]) for i in self.range_legs()]
            M = sp.Matrix(rows) if rows else sp.zeros(0, 1)
            self._cache[name] = M
            return M
        M = sp.Matrix([self._row(name, leg, i) for i, leg in enumerate(self._leg_parts())])
        self._cache[name] = M
        return M


def model_expressions(mech, exact: bool = False) -> ModelExprs:
    """The lazily derived symbolic kernels of ``mech`` (anything with a
    ``leg_description()``: :class:`~.legs.LegsDescription`, an RSS description); with
    ``exact=True`` its exact model (:class:`ModelExprs`)."""
    return ModelExprs(mech, exact)
