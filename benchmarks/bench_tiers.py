"""The three tiers of the RSS inverse kinematics and Jacobian
(distkin.mechanisms.kinematics_tiers): cost per pose against the fast kernels, and the
precise tier against the alternative route of lambdifying the sympy IK for mpmath; and
the three tiers of the forward kinematics (distkin.mechanisms.forward_tiers: Gauss-Newton,
Newton in mpmath, Krawczyk's test on arb balls) against the fast Gauss-Newton; and the
time of deriving the arb-flavour module (from the exact model) in a fresh process."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from .harness import interleaved, ratio_table

__all__ = ["TITLE", "DEFAULT", "run"]

TITLE = "IK, Jacobian and forward kinematics in three tiers (fast, precise, certified)"
DEFAULT = True

N = 20
ROOT = Path(__file__).resolve().parent.parent

_DERIVE = r"""
import json, sys
sys.path.insert(0, {root!r})
import sympy  # imported before the clock starts: we time the algebra, not the import
from distkin.mechanisms import preset
from distkin.mechanisms.kernel_names import ARB_KERNELS
from distkin.codegen.rss import derivation_profile
print(json.dumps(derivation_profile(preset({name!r}), ARB_KERNELS, ("arb",))))
"""


def _derive_arb(name):
    """Seconds per step of deriving preset ``name``'s arb module, in a fresh process."""
    r = subprocess.run([sys.executable, "-c", _DERIVE.format(root=str(ROOT), name=name)],
                       capture_output=True, text=True, check=True)
    return json.loads(r.stdout)


def run():
    import mpmath
    import sympy as sp
    from distkin.mechanisms import preset
    from distkin.mechanisms.kinematics_tiers import ik_tier, jacobian_tier
    from distkin.mechanisms.symbolic import POSE, model_expressions

    m = preset("octo")
    rng = np.random.default_rng(0)
    X = m.home + rng.normal(size=(N, 6)) * [0.01, 0.01, 0.01, 0.1, 0.1, 0.1]
    t0 = time.perf_counter()
    # the precise tier's own source: the exact model (constants exact rationals)
    ik_expr = list(model_expressions(m, exact=True).get("ik"))
    lam = sp.lambdify([POSE], ik_expr, modules="mpmath")
    t_build = time.perf_counter() - t0

    def lambdified():
        with mpmath.workdps(30):
            return [lam([mpmath.mpf(float(c)) for c in x]) for x in X]

    comp = {
        "IK kernel alone (mech.inverse_kinematics)": lambda: m.inverse_kinematics(X),
        "fast IK with its error estimate": lambda: ik_tier(m, X, "fast"),
        "precise IK (30 digits, two runs)": lambda: ik_tier(m, X, "precise"),
        "certified IK (arb, 128 bits)": lambda: ik_tier(m, X, "certified"),
        "sympy IK lambdified for mpmath (30 digits, one run)": lambdified,
        "Jacobian (mech.jacobian: kernel, resolution and reach checks)":
            lambda: m.jacobian(X),
        "fast Jacobian with its error estimate": lambda: jacobian_tier(m, X, "fast"),
        "precise Jacobian": lambda: jacobian_tier(m, X, "precise"),
        "certified Jacobian (with its IK)": lambda: jacobian_tier(m, X, "certified"),
    }
    med = interleaved(comp, rounds=15)
    per = {n: t / N for n, t in med.items()}
    prec = ik_tier(m, X, "precise")
    with mpmath.workdps(30):
        ref = np.array([[float(v) for v in row] for row in lambdified()])
    agree = float(np.abs(prec.q - ref).max())
    cert = ik_tier(m, X, "certified")
    md = (f"Octo preset, {N} poses about the workspace centre (±10 mm, ±0.1 rad, normal), "
          "one batched call; per pose.  The fast tier's error estimate evaluates the closure "
          "and Jq kernels and the joint points besides the IK.\n\n"
          + ratio_table(per, "IK kernel alone (mech.inverse_kinematics)", per="pose")
          + f"\n\nThe lambdified sympy IK (the exact model's, the precise tier's source) "
          f"took {t_build:.1f} s to derive and build; its "
          f"values agree with the precise tier to {agree:.1e} rad (float64 of both). "
          f"Largest certified radius of the float q: {cert.q_error.max():.1e} rad (its "
          f"rounding to float64: the balls themselves are at most "
          f"{max(float(b.rad()) for b in cert.values.ravel()):.1e} rad wide, "
          f"`TieredIK.values`); all {cert.certified.sum()} legs certified.")
    fk_md, fk = _forward(m, X)
    prof = _derive_arb("octo")
    md += ("\n\n" + fk_md + "\n\nDeriving the Octo's arb module (ik, reach, jq_jx, closure "
           "from the exact model; `derivation_profile(preset('octo'), ARB_KERNELS, "
           f"('arb',))` in a fresh process): {prof['total']:.2f} s, of which "
           f"{prof['cse_and_print']:.2f} s CSE and printing; {prof['source_chars']:,} "
           "characters of source.")
    return md, {"per_pose_seconds": per, "lambdify_build_seconds": t_build,
                "precise_vs_lambdify_rad": agree,
                "certified_max_radius_rad": float(cert.q_error.max()), "forward": fk,
                "arb_derivation": prof}


def _forward(m, X):
    """The forward kinematics of the Octo in three tiers, one pose per call (from the
    joint values of the first poses of ``X``, warm started at the pose itself)."""
    from distkin.mechanisms.forward_tiers import forward_tier
    n = 5
    Q = m.inverse_kinematics(X[:n])[0]
    comp = {
        "fast FK (Gauss-Newton, float64)": lambda: [m.forward_kinematics(Q[i], X[i])
                                                    for i in range(n)],
        "fast FK with its error estimate": lambda: [forward_tier(m, Q[i], X[i])
                                                    for i in range(n)],
        "precise FK (Newton, mpmath, 30 digits)": lambda: [
            forward_tier(m, Q[i], X[i], method="precise") for i in range(n)],
        "certified FK (Krawczyk, arb, 128 bits)": lambda: [
            forward_tier(m, Q[i], X[i], method="certified") for i in range(n)],
    }
    med = interleaved(comp, rounds=15)
    per = {k: t / n for k, t in med.items()}
    cert = [forward_tier(m, Q[i], X[i], method="certified") for i in range(n)]
    rad = max(float(c.error.max()) for c in cert)
    md = (f"Forward kinematics of the Octo (L = 8), {n} of these poses, one call each "
          "(the precise and certified tiers include the fast Gauss-Newton they start from; "
          "certified: the box of six legs, the other two bounded):\n\n"
          + ratio_table(per, "fast FK (Gauss-Newton, float64)", per="pose")
          + f"\n\nLargest certified radius: {rad:.1e} (m or rad); every pose certified.")
    return md, {"per_pose_seconds": per, "certified_max_radius": rad}
