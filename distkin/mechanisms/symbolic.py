"""The sympy model of an RRRS leg: closure, closed-form IK, Jq, Jx, J = Jq^-1 Jx.

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
           "leg_values", "ModelExprs", "model_expressions"]

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


def leg_values(mech, i: int) -> dict:
    """Substitution of leg i's parameters: {symbol: number} (floats as sympy Floats)."""
    L = mech.legs
    k, s = i // 2, (-1 if i % 2 == 0 else 1)
    th = 2 * sp.pi * k / (L // 2)
    ce, se = sp.cos(th), sp.sin(th)
    vals = dict(zip(_PAR, [mech.l0, mech.l1, mech.l2, mech.l3, mech.lp, mech.ld]))
    out = {sym: _num(float(v)) for sym, v in vals.items()}
    tc, ts = _TRIG[:2]
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
    """The symbolic kernels of one mechanism, derived lazily (each only when asked).

    Attributes (sympy Matrices, functions of :data:`POSE` and, for ``closure``, of
    ``q_symbols(L)``)
    ----------
    ik : (L, 1) crank angles
    reach : (L, 1) reach margins rho^2 - C^2 (m^2)
    jacobian : (L, 6) J
    jq_jx : (L, 7) [Jq_ii, Jx_i]
    closure : (L, 7) [Phi_i, dPhi_i/d(v, omega)]
    """

    NAMES = ("ik", "reach", "jacobian", "jq_jx", "closure")

    def __init__(self, mech):
        self.mech = mech
        self.L = mech.legs
        self._legs = None
        self._cache = {}
        self.timings = {}

    def _leg_parts(self):
        """Per leg: substituted Phi(q, P), its derivatives, and the IK pieces."""
        import time
        if self._legs is not None:
            return self._legs
        t0 = time.perf_counter()
        g = generic_leg(self.mech.layout)
        x, y, zz, rx, ry, rz = POSE
        R = rotation_matrix(rx, ry, rz)
        X = sp.Matrix([x, y, zz])
        q, Psym = g["q"], g["P"]
        legs = []
        t_subs = t_diff = 0.0
        for i in range(self.L):
            ta = time.perf_counter()
            vals = leg_values(self.mech, i)
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
            legs.append(dict(Phi=Phi, dPhi_dq=dPhi_dq, gP=gP, r=r, P=Pexpr, A=A, Bz=Bz, C=C))
            t_subs += tb - ta
            t_diff += tc - tb
        self.timings["substitute"] = time.perf_counter() - t0 - t_diff
        self.timings["differentiate"] = t_diff
        self._legs = legs
        return legs

    @staticmethod
    def _cos_sin(leg):
        A, Bz, C = leg["A"], leg["Bz"], leg["C"]
        rho2 = A ** 2 + Bz ** 2
        h = _root_abs(rho2 - C ** 2)
        cq = (A * C + BRANCH * Bz * h) / rho2
        sq = (Bz * C - BRANCH * A * h) / rho2
        return cq, sq, rho2

    def _subsP(self, expr, leg):
        Psym = sp.symbols("Px Py Pz", real=True)
        return expr.xreplace(dict(zip(Psym, leg["P"])))

    def legs(self):
        """Per leg: ``Phi`` (substituted closure in q, Px, Py, Pz) and ``P`` (pose)."""
        return self._leg_parts()

    def get(self, name: str) -> sp.Matrix:
        if name in self._cache:
            return self._cache[name]
        legs = self._leg_parts()
        q = sp.Symbol("q", real=True)
        rows = []
        if name == "ik":
            for leg in legs:
                A, Bz, C = leg["A"], leg["Bz"], leg["C"]
                h = _root_abs(A ** 2 + Bz ** 2 - C ** 2)
                # evaluate=False: sympy would otherwise query signs of large expressions
                rows.append([sp.atan2(Bz * C - BRANCH * A * h, A * C + BRANCH * Bz * h,
                                      evaluate=False)])
        elif name == "reach":
            for leg in legs:
                rows.append([leg["A"] ** 2 + leg["Bz"] ** 2 - leg["C"] ** 2])
        elif name in ("jacobian", "jq_jx"):
            for leg in legs:
                cq, sq, _ = self._cos_sin(leg)
                rep = {sp.cos(q): cq, sp.sin(q): sq}
                jq = self._subsP(leg["dPhi_dq"], leg).xreplace(rep)
                gP = self._subsP(leg["gP"], leg).xreplace(rep)
                jx = -gP.col_join(leg["r"].cross(gP))
                if name == "jq_jx":
                    rows.append([jq] + list(jx))
                else:
                    rows.append([c / jq for c in jx])
        elif name == "closure":
            qs = q_symbols(self.L)
            for i, leg in enumerate(legs):
                rep = {q: qs[i]}
                phi = self._subsP(leg["Phi"], leg).xreplace(rep)
                gP = self._subsP(leg["gP"], leg).xreplace(rep)
                rows.append([phi] + list(gP.col_join(leg["r"].cross(gP))))
        else:
            raise ValueError(f"expected a kernel in {self.NAMES}, got {name!r}")
        M = sp.Matrix(rows)
        self._cache[name] = M
        return M


def model_expressions(mech) -> ModelExprs:
    """The lazily derived symbolic kernels of ``mech`` (an :class:`RSSMechanism`)."""
    return ModelExprs(mech)
