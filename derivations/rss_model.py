"""Derivation of the RSS/RRRS leg model used by distkin.mechanisms (Kühne et al., Sec. II-C).

Run ``python derivations/rss_model.py`` (``--help`` describes it; any other argument is
refused with exit status 2).  It prints the generic leg closure and checks,
symbolically where the algebra is generic and numerically per preset:

1. the closure Phi = (|P - D(q)|^2 - l3^2)/(2 l3) equals (C - A cos q - B sin q) l1/l3
   with A = w.u, B = w.z, C = (w.w + l1^2 - l3^2)/(2 l1), w = P - B0 - o;
2. the closed form cos q = (A C + s B h)/rho^2, sin q = (B C - s A h)/rho^2
   (h^2 = rho^2 - C^2) satisfies A cos q + B sin q = C and cos^2 + sin^2 = 1;
3. the branch sign distkin.mechanisms.symbolic.BRANCH gives, at the workspace centre,
   the crank angle nearer 0 of the two that close each leg (presets.py), every leg at
   the same angle, and q = 0 exactly under the radial reading's horizontal-crank rule;
4. the generated kernels ``distkin/_generated/rss_<preset>.py`` are this model's: the
   generic leg's dPhi/dP is (P - D)/l3; per preset, the committed kernel's Jq, Jx and J
   at a pose against sympy's derivatives of the model's closure; their headers name
   this script; ``python -m distkin.codegen --check`` regenerates them unchanged;
5. the exact model (``model_expressions(mech, exact=True)``: every number exact, the
   source of the arb kernels ``rss_<preset>_arb.py`` and so what the certified tier
   certifies) holds no float, and per preset, at a pose off the centre, its closure
   vanishes at its own IK angles to 60 digits (the float model's to float64 only): the
   IK and the closure describe one mechanism, exactly;
6. the range margin of a revolute leg with a joint range [qmin, qmax] (the arb kernel
   ``ranges``, which the certified workspace encloses): with m, w the range's middle and
   half-width, rho^2 (cos(q - m) - cos w) = (A C + s B h) cos m + (B C - s A h) sin m -
   rho^2 cos w by item 2; its sign is that of "q in [qmin, qmax] modulo 2 pi"
   (distkin.mechanisms.legs.in_revolute_range) for 0 < w < pi, on a grid of angles and
   ranges written past ±pi; and a leg table's exact ``ranges`` kernel equals
   rho^2 (cos(q - m) - cos w) with q its own IK (atan2) angle, to 1e-40 (60 digits),
   both branches.

Every claim is checked with :func:`check` (``SystemExit`` naming the claim when it
fails, as the other derivation scripts do), never with ``assert``, which ``python -O``
skips; the script ends with "all checks passed".
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from distkin.mechanisms import PRESETS, preset  # noqa: E402
from distkin.mechanisms.symbolic import (BRANCH, POSE, generic_leg,  # noqa: E402
                                         model_expressions, q_symbols)


def check(cond, what):
    if not cond:
        raise SystemExit(f"CHECK FAILED: {what}")
    print(f"   ok: {what}")


def parse_args(argv=None):
    ap = argparse.ArgumentParser(
        prog="rss_model.py",
        description="Derive and check the RSS/RRRS leg model of distkin.mechanisms "
                    "(Kühne et al., Design and Evaluation of a Haptic Interface With Octopod "
                    "Kinematics, Sec. II-C, eqs. (1)-(2)): the closure, its "
                    "closed-form IK, the branch, the generated kernels and the exact "
                    "model.  Exit status 0 means every check passed.")
    return ap.parse_args(argv)


def main(argv=None):
    parse_args(argv)
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
    check(lhs == 0, "1. Phi = (C - A cos q - B sin q) l1/l3")
    check(e1 == 0, "2. the closed form satisfies A cos q + B sin q = C")
    check(e2 == 0, "2. the closed form satisfies cos^2 q + sin^2 q = 1")
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
            check(spread < 1e-12, f"{name} {layout}: every leg at the same angle "
                                  f"(spread {spread:.1e} < 1e-12 rad)")
            check(all(abs(a) < abs(b) for a, b in zip(q, other)),
                  f"{name} {layout}: BRANCH gives the angle nearer 0 of the two on every leg")
            if layout == "radial":
                check(max(abs(v) for v in q) < 1e-12,
                      f"{name} radial: q = 0 at the centre (horizontal crank)")
    print("4. Jq_ii = dPhi_i/dq_i, Jx_i = -(g, r x g) with g = dPhi/dP = (P - D)/l3;"
          " J = Jq^-1 Jx (eqs. (1)-(2))")
    check_generated_kernels()
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
                check(not any(e.atoms(sp.Float) for leg in me.legs()
                              for e in (leg["Phi"], leg["P"])),
                      f"{name}: the exact model holds no float")
            qv = [e.xreplace(x).evalf(60) for e in me.get("ik")]
            sub = {**x, **dict(zip(q_symbols(m.L), qv))}
            worst.append(max(abs(row[0].xreplace(sub).evalf(60))
                             for row in me.get("closure").tolist()))
        print(f"   {name:8s} exact {float(worst[0]):.1e} m, float {float(worst[1]):.1e} m")
        check(worst[0] < sp.Float("1e-50"), f"{name}: the exact closure vanishes at its "
                                            "own IK to 1e-50 m (60 digits)")
        check(worst[1] < 1e-14, f"{name}: the float model's closure to 1e-14 m")
    print("6. the range margin rho^2 (cos(q - m) - cos w) of a revolute joint range:")
    check_range_margin()
    print("\nall checks passed")


def check_range_margin(row=None):
    """Item 6.  ``row(leg)``: the margin of one leg part of the exact model; None, the
    model's own ``ranges`` kernel (tests/test_derivation_scripts.py feeds a wrong one)."""
    import numpy as np

    from distkin.mechanisms.legs import LegsDescription, in_revolute_range
    a, b, c, h, m, w = sp.symbols("A B C h m w", real=True)
    rho2 = a ** 2 + b ** 2
    for sgn in (1, -1):
        cq, sq = (a * c + sgn * b * h) / rho2, (b * c - sgn * a * h) / rho2
        e = sp.simplify(rho2 * (cq * sp.cos(m) + sq * sp.sin(m) - sp.cos(w))
                        - ((a * c + sgn * b * h) * sp.cos(m) + (b * c - sgn * a * h) * sp.sin(m)
                           - rho2 * sp.cos(w)))
        check(e == 0, f"(a) branch {sgn:+d}: rho^2 (cos(q - m) - cos w) in A, B, C, h")
    qs = np.linspace(-np.pi, np.pi, 721)[:-1] + 1e-3
    bad = 0
    for lo, hi in ((-0.3, 0.5), (2.0, 7.0), (-7.0, -5.5), (-2.0, 1.5), (3.0, 3.3)):
        mm, ww = (lo + hi) / 2, (hi - lo) / 2
        inside = in_revolute_range(qs, lo, hi)
        bad += int(np.sum((np.cos(qs - mm) - np.cos(ww) > 0) != inside))
    check(bad == 0, "(b) cos(q - m) > cos w iff q is in the range modulo 2 pi (720 angles, "
                    "5 ranges, two written past ±pi)")
    # the rus8 example's legs (examples/rus8_device.toml), the first two of branch +1 and
    # -1, with a range within a half turn and one of 5 rad written past +pi
    from distkin.app.scene import load_scene
    root = Path(__file__).resolve().parents[1]
    rus8 = load_scene(root / "examples" / "rus8_device.toml").mechanism.leg_description()
    ranges = ((-0.3, 0.5), (2.0, 7.0))
    legs = [{**leg.as_dict(), "range": ranges[i % 2], "branch": (1, -1)[i % 2]}
            for i, leg in enumerate(rus8.leg_table)]
    desc = LegsDescription("rus8 ranged", legs, rus8.home_pose, rus8.mass, rus8.inertia)
    me = model_expressions(desc, exact=True)
    x = dict(zip(POSE, [sp.Rational(3, 1000), sp.Rational(-2, 1000), sp.Rational(21, 100),
                        sp.Rational(1, 50), sp.Rational(-1, 40), sp.Rational(1, 30)]))
    worst = 0
    rows = me.get("ranges")
    for i, (leg, qe, (lo, hi)) in enumerate(zip(me.legs()[:2], me.get("ik")[:2], ranges)):
        qv = qe.xreplace(x).evalf(60)
        lo_, hi_ = sp.Rational(lo), sp.Rational(hi)
        ref = ((leg["A"] ** 2 + leg["Bz"] ** 2) * (sp.cos(qv - (lo_ + hi_) / 2)
                                                   - sp.cos((hi_ - lo_) / 2))).xreplace(x)
        got = (rows[i] if row is None else row(leg)).xreplace(x)
        worst = max(worst, abs((got - ref).evalf(60)) / abs(ref.evalf(60)))
    print(f"   (c) exact kernel against rho^2 (cos(q_IK - m) - cos w): {float(worst):.1e} "
          "relative")
    check(worst < sp.Float("1e-40"), "(c) the exact ranges kernel is rho^2 (cos(q - m) - "
                                     "cos w) at its own IK angle, both branches, to 1e-40")


def check_generated_kernels():
    """Item 4: the committed kernels are this model's.  (a) g = dPhi/dP is (P - D)/l3
    for the generic leg; (b) per preset, at a pose off the centre, the committed
    kernel's [Jq_ii, Jx_i] against sympy's derivatives of the model's closure Phi_i(q_i,
    pose) (Jq_ii = dPhi_i/dq_i; Jx_i = -(dPhi_i/dt, dPhi_i/dr E(r)^-1), omega = E(r) rdot,
    distkin.spatial.omega_map), and its J against Jx / Jq; (c) each module's header
    names this script, and ``python -m distkin.codegen --check`` regenerates the
    preset modules from the model and finds them unchanged."""
    import subprocess

    import numpy as np

    from distkin.spatial import omega_map
    g = generic_leg()
    gP = [sp.diff(g["Phi"], c) for c in g["P"]]
    l3 = g["params"][3]
    diff = [sp.simplify(a - (p - d) / l3) for a, p, d in zip(gP, g["P"], g["D"])]
    print("   (a) dPhi/dP - (P - D)/l3 =", diff)
    check(all(d == 0 for d in diff), "(a) dPhi/dP = (P - D)/l3 for the generic leg")
    root = Path(__file__).resolve().parents[1]
    for name in PRESETS:
        m = preset(name)
        x = np.array([0.004, -0.003, m.z0 + 0.006, 0.03, -0.02, 0.025])
        me = model_expressions(m)
        sub = dict(zip(POSE, (sp.Float(v, 30) for v in x)))
        qv = [e.xreplace(sub).evalf(30) for e in me.get("ik")]
        qs = q_symbols(m.L)
        phi = me.get("closure")[:, 0]
        qsub = {**sub, **dict(zip(qs, qv))}
        jq = np.array([float(sp.diff(phi[i], qs[i]).xreplace(qsub).evalf(30))
                       for i in range(m.L)])
        dx = np.array([[float(sp.diff(phi[i], v).xreplace(qsub).evalf(30)) for v in POSE]
                       for i in range(m.L)])
        jx = -np.hstack([dx[:, :3], dx[:, 3:] @ np.linalg.inv(omega_map(x[3:]))])
        k = m.kernels("batched")
        got = k.jq_jx(x[None])[0]
        J = k.jacobian(x[None])[0]
        e1 = np.abs(got[:, 0] - jq).max() / np.abs(jq).max()
        e2 = np.abs(got[:, 1:] - jx).max() / np.abs(jx).max()
        e3 = np.abs(J - jx / jq[:, None]).max() / np.abs(J).max()
        print(f"   (b) {name:8s} kernel vs d(closure): Jq {e1:.1e}, Jx {e2:.1e}, "
              f"J {e3:.1e} (relative)")
        check(max(e1, e2, e3) < 1e-12, f"(b) {name}: the kernel's Jq, Jx and J against "
                                       "sympy's derivatives, to 1e-12 relative")
        header = (root / "distkin" / "_generated" / f"rss_{name}.py").read_text().splitlines()[0]
        check("derivations/rss_model.py" in header,
              f"(b) {name}: the module's header names this script ({header!r})")
    names = [f"rss_{n}" for n in PRESETS]
    run = subprocess.run([sys.executable, "-m", "distkin.codegen", "--check", *names],
                         cwd=root, capture_output=True, text=True)
    print("   (c) python -m distkin.codegen --check " + " ".join(names) + ":\n      "
          + run.stdout.strip().replace("\n", "\n      "))
    check(run.returncode == 0, "(c) the committed modules regenerate unchanged"
                               + (f" ({run.stderr.strip()})" if run.returncode else ""))


if __name__ == "__main__":
    main()
