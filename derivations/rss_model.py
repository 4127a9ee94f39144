"""Derivation of the RSS/RRRS leg model used by distkin.mechanisms (Kühne et al., Sec. II-C).

Run ``python derivations/rss_model.py``.  It prints the generic leg closure and checks,
symbolically where the algebra is generic and numerically per preset:

1. the closure Phi = (|P - D(q)|^2 - l3^2)/(2 l3) equals (C - A cos q - B sin q) l1/l3
   with A = w.u, B = w.z, C = (w.w + l1^2 - l3^2)/(2 l1), w = P - B0 - o;
2. the closed form cos q = (A C + s B h)/rho^2, sin q = (B C - s A h)/rho^2
   (h^2 = rho^2 - C^2) satisfies A cos q + B sin q = C and cos^2 + sin^2 = 1;
3. the branch sign distkin.mechanisms.symbolic.BRANCH gives, at the workspace centre,
   the crank angle nearer 0 of the two that close each leg (presets.py), every leg at
   the same angle, and q = 0 exactly under the radial reading's horizontal-crank rule;
4. the generated kernels ``distkin/_generated/rss_<preset>.py`` were written from this
   model (their headers name this script; ``python -m distkin.codegen --check``);
5. the exact model (``model_expressions(mech, exact=True)``: every number exact, the
   source of the arb kernels ``rss_<preset>_arb.py`` and so what the certified tier
   certifies) holds no float, and per preset, at a pose off the centre, its closure
   vanishes at its own IK angles to 60 digits (the float model's to float64 only): the
   IK and the closure describe one mechanism, exactly.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from distkin.mechanisms import PRESETS, preset  # noqa: E402
from distkin.mechanisms.symbolic import (BRANCH, POSE, generic_leg,  # noqa: E402
                                         model_expressions, q_symbols)


def main():
    g = generic_leg()
    l0, l1, l2, l3, lp, ld = g["params"]
    q, P = g["q"], g["P"]
    w = P - g["B"] - g["o"]
    A, Bz = w.dot(g["u"]), w[2]
    C = (w.dot(w) + l1 ** 2 - l3 ** 2) / (2 * l1)
    ce, se, cb, sb, cg, sg, s = g["trig"]
    unit = {ce ** 2: 1 - se ** 2, cb ** 2: 1 - sb ** 2, s ** 2: 1}
    lhs = sp.expand(g["Phi"] - (C - A * sp.cos(q) - Bz * sp.sin(q)) * l1 / l3)
    lhs = sp.expand(lhs.subs(sp.cos(q) ** 2, 1 - sp.sin(q) ** 2).subs(unit).subs(unit))
    print("1. Phi - (C - A cos q - B sin q) l1/l3 =", sp.simplify(lhs))
    a, b, c, h = sp.symbols("A B C h", real=True)
    rho2 = a ** 2 + b ** 2
    cq = (a * c + BRANCH * b * h) / rho2
    sq = (b * c - BRANCH * a * h) / rho2
    hs = {h ** 2: rho2 - c ** 2}
    e1 = sp.simplify(sp.expand(a * cq + b * sq - c).subs(hs))
    e2 = sp.simplify(sp.expand((cq ** 2 + sq ** 2 - 1) * rho2 ** 2).subs(hs))
    print("2. A cos q + B sin q - C =", e1, "; (cos^2 + sin^2 - 1) rho^4 =", e2)
    assert lhs == 0 and e1 == 0 and e2 == 0
    print(f"3. BRANCH = {BRANCH}; q at the workspace centre:")
    for name in PRESETS:
        for layout in ("tangential", "radial"):
            m = preset(name, layout=layout)
            me = model_expressions(m)
            home = dict(zip(POSE, [0, 0, m.z0, 0, 0, 0]))
            q = [float(e.xreplace(home).evalf(30)) for e in me.get("ik")]
            # the other solution of A cos q + Bz sin q = C: q = phi + BRANCH delta
            other = []
            for leg in me.legs():
                A, Bz, C = (float(leg[k].xreplace(home).evalf(30)) for k in ("A", "Bz", "C"))
                phi, delta = math.atan2(Bz, A), math.acos(C / math.hypot(A, Bz))
                other.append(math.remainder(phi + BRANCH * delta, 2 * math.pi))
            spread = max(q) - min(q)
            print(f"   {name:8s} {layout:10s} L = {m.L}, l3 = {m.l3 * 1e3:.4f} mm, "
                  f"q = {math.degrees(q[0]):.4f} deg (spread {spread:.1e} rad)")
            assert spread < 1e-12
            assert all(abs(a) < abs(b) for a, b in zip(q, other))          # nearer 0
            if layout == "radial":
                assert max(abs(v) for v in q) < 1e-12
    print("4. Jq_ii = dPhi_i/dq_i, Jx_i = -(g, r x g) with g = dPhi/dP = (P - D)/l3;"
          " J = Jq^-1 Jx (eqs. (1)-(2))")
    print("5. the exact model (arb kernels, certified tier): max |Phi_i(IK(x), x)| at 60 "
          "digits, exact model against the float one:")
    for name in PRESETS:
        m = preset(name)
        x = dict(zip(POSE, [sp.Rational(3, 1000), sp.Rational(-2, 1000),
                            sp.Rational(m.z0) + sp.Rational(5, 1000), sp.Rational(1, 50),
                            sp.Rational(-1, 40), sp.Rational(1, 30)]))
        worst = []
        for exact in (True, False):
            me = model_expressions(m, exact)
            if exact:
                assert not any(e.atoms(sp.Float) for leg in me.legs()
                               for e in (leg["Phi"], leg["P"]))
            qv = [e.xreplace(x).evalf(60) for e in me.get("ik")]
            sub = {**x, **dict(zip(q_symbols(m.L), qv))}
            worst.append(max(abs(row[0].xreplace(sub).evalf(60))
                             for row in me.get("closure").tolist()))
        print(f"   {name:8s} exact {float(worst[0]):.1e} m, float {float(worst[1]):.1e} m")
        assert worst[0] < sp.Float("1e-50") and worst[1] < 1e-14


if __name__ == "__main__":
    main()
