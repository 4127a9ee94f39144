"""Leg tables (issue 16): what deriving a new geometry costs (with the elimination shared
between flavours, and without), and the generated kernels against the plain-numpy route."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from .harness import interleaved, ratio_table

__all__ = ["TITLE", "DEFAULT", "run"]

TITLE = "Leg tables: deriving a new geometry, generated kernels vs the numpy route (issue 16)"
DEFAULT = True

ROOT = Path(__file__).resolve().parent.parent
N = 100_000
ROUNDS = 3       # derivations per case and variant (medians)

#: the geometries derived: label -> Python expression of the description (cwd = ROOT)
CASES = {
    "octo, l0 = 165 mm (RSS override)": "preset('octo', l0=0.165)",
    "6-UPS Gough-Stewart (example)": "load_scene('examples/gough_stewart_6ups.toml').mechanism",
    "8-RUS device (example)": "load_scene('examples/rus8_device.toml').mechanism",
}

_PROFILE = r"""
import json, sys
sys.path.insert(0, {root!r})
import sympy  # imported before the clock starts: we time the algebra, not the import
from distkin.mechanisms import preset
from distkin.app.scene import load_scene
from distkin.codegen import emit
if {unshared!r}:
    emit._cse = lambda flat, opt: sympy.cse(flat, symbols=sympy.numbered_symbols("_c"),
                                            optimizations=opt)
from distkin.codegen.rss import derivation_profile
print(json.dumps(derivation_profile({expr})))
"""


def _profile(expr, unshared):
    r = subprocess.run([sys.executable, "-c", _PROFILE.format(root=str(ROOT), expr=expr,
                                                             unshared=unshared)],
                       capture_output=True, text=True, check=True, cwd=ROOT)
    return json.loads(r.stdout)


def run():
    from distkin.app.scene import load_scene
    from distkin.mechanisms.kinematics import LegMechanism

    rows, gen = [], {}
    for label, expr in CASES.items():
        runs = {False: [], True: []}
        for _ in range(ROUNDS):                       # interleaved: load hits both alike
            for unsh in (False, True):
                runs[unsh].append(_profile(expr, unsh))
        med = {u: {k: float(np.median([r[k] for r in rs])) for k in rs[0]}
               for u, rs in runs.items()}
        shared, unshared = med[False], med[True]
        gen[label] = {"shared": shared, "unshared": unshared}
        rows.append(f"| {label} | {shared['total']:.2f} s | {unshared['total']:.2f} s | "
                    f"{shared['cse_and_print']:.2f} s | {unshared['cse_and_print']:.2f} s | "
                    f"{unshared['total'] / shared['total']:.2f}× |")
    # --- generated kernels vs the numpy route (8-RUS example) --------------------------
    m = load_scene(ROOT / "examples" / "rus8_device.toml").mechanism
    num = LegMechanism.from_description(m, route="numpy")
    rng = np.random.default_rng(0)
    P = m.home + np.hstack([rng.uniform(-0.015, 0.015, (N, 3)),
                            rng.uniform(-0.17, 0.17, (N, 3))])
    kg, kn = m.kernels(), num.kernels()
    agree = float(np.abs(kg.jacobian(P) - kn.jacobian(P)).max() / np.abs(kg.jacobian(P)).max())
    med = interleaved({"generated IK + J": lambda: (kg.ik(P), kg.jacobian(P)),
                       "numpy route IK + J": lambda: (kn.ik(P), kn.jacobian(P))}, rounds=5)
    per = {k: v / N for k, v in med.items()}
    table = ratio_table(per, "generated IK + J", per="pose")
    md = f"""Deriving the kernels of a geometry that has no committed module (all five kernels,
batched + scalar flavours; one fresh process per run after `import sympy`; medians of
{ROUNDS} interleaved runs): with the
common-subexpression elimination of a kernel shared by its two flavours
(`distkin.codegen.emit._cse`, this issue) and without it (each flavour eliminating
again, as before).  The printed modules are identical either way.

| geometry | total, shared | total, not shared | CSE + print, shared | CSE + print, not shared | ratio |
|---|---|---|---|---|---|
{chr(10).join(rows)}

**Generated kernels vs the plain-numpy route** (`route = "numpy"`, no derivation), 8-RUS
example, N = {N:,} poses about home (±15 mm, ±10°); the two Jacobians agree to
{agree:.1e} (relative to the largest entry):

{table}

Machine load from other processes inflates absolute times; compare the ratios.
"""
    return md, {"generation": gen, "ik_jacobian_per_pose": per, "agreement": agree}
