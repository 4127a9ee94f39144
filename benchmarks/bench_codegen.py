"""Scene kernel modules of ``distkin codegen`` (octahedral, platform66, points scenes).

Two tables:

1. Deriving each example scene's module from a fresh cache (sympy: substitution, CSE,
   printing) and reading it back from the cache (the second run: no algebra); among
   them a 6-6 platform with float coordinates (``platform66_measured.toml``: the exact
   map of eq. (8) has long coefficients, so its kernels compute l^2 first).
2. The octic coefficients of N = 100 000 leg sets about the Griffis-Duffy example: the
   scene module's ``octic`` (the scene's sides substituted before CSE) against the
   committed general kernel ``octic_general.octic_batched`` (sides as inputs; it also
   returns the 30 quadratic parts, which the scene module's ``parts`` kernel gives
   separately), batched and scalar; and the 6-6 platform's octic in the m-legs against
   the float map l^2 = A^-1 m^2 + c followed by the general kernel.
"""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

import numpy as np

__all__ = ["TITLE", "DEFAULT", "run"]

TITLE = "distkin codegen: scene modules of octahedral, 6-6 and points scenes"
DEFAULT = True

_EX = Path(__file__).resolve().parent.parent / "examples"
_SCENES = ("octahedral_griffis_duffy.toml", "platform66_griffis_duffy.toml",
           "points_banana.toml", "platform66_measured.toml")


def _modules(cache):
    """Derive (timed) and re-read (timed) each scene's module; load them."""
    from distkin.app.codegen_command import scene_module_source
    from distkin.app.scene import load_scene
    from distkin.sourcecache import load_module_file
    old = os.environ.get("DISTKIN_CACHE")
    os.environ["DISTKIN_CACHE"] = str(cache)
    times, mods = {}, {}
    try:
        for name in _SCENES:
            scene = load_scene(_EX / name)
            t0 = time.perf_counter()
            src, hit, _ = scene_module_source(scene)
            t1 = time.perf_counter()
            src2, hit2, _ = scene_module_source(scene)
            t2 = time.perf_counter()
            assert not hit and hit2 and src == src2
            path = Path(cache) / f"bench_{name.split('.')[0]}.py"
            path.write_text(src, encoding="utf-8")
            mods[name] = load_module_file(path)
            times[name] = {"derive_s": t1 - t0, "cached_s": t2 - t1, "lines": len(src.splitlines())}
    finally:
        if old is None:
            del os.environ["DISTKIN_CACHE"]
        else:
            os.environ["DISTKIN_CACHE"] = old
    return times, mods


def run():
    from benchmarks.harness import fmt_time, interleaved, ratio_table
    from distkin._generated import octic_general as og
    from distkin.delta import delta_transform
    with tempfile.TemporaryDirectory() as tmp:
        times, mods = _modules(tmp)
    gd, p66 = mods[_SCENES[0]], mods[_SCENES[1]]
    n = 100_000
    rng = np.random.default_rng(0)
    legs = np.array([19.8, 18, 18, 17, 14.9, 17.8]) + rng.uniform(-1, 1, (n, 6))
    L2 = legs * legs
    S = np.tile([144.0, 144.0, 144.0, 36.0, 36.0, 36.0], (n, 1))
    tr = delta_transform(([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]],
                          [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]), ["12/5", "6/5"] * 3)
    A = np.array(tr.A.tolist(), dtype=float)
    b = np.array(tr.b.tolist(), dtype=float).ravel()
    M2 = L2 @ A.T - b                         # eq. (8): m^2 = A l^2 - b
    Ainv, c = (np.array(x.tolist(), dtype=float) for x in tr.inverse())
    c = c.ravel()
    ref = og.octic_batched(S, L2)[:, 30:]
    err = float(np.max(np.abs(gd.octic(L2) - ref) / np.abs(ref)))
    err66 = float(np.max(np.abs(p66.octic(M2) - ref) / np.abs(ref)))
    batched = interleaved({
        "octic_general.octic_batched (sides as inputs, 39 outputs)":
            lambda: og.octic_batched(S, L2),
        "scene module octic (sides substituted, 9 outputs)": lambda: gd.octic(L2),
        "map A^-1 m^2 + c, then octic_general": lambda: og.octic_batched(S, M2 @ Ainv.T + c),
        "6-6 scene module octic (m-legs, map composed)": lambda: p66.octic(M2),
    }, rounds=7)
    per = {k: v / n for k, v in batched.items()}
    l0, s0 = list(L2[0]), list(S[0])
    scalar = interleaved({"octic_general.octic_scalar": lambda: og.octic_scalar(s0, l0),
                          "scene module octic_scalar": lambda: gd.octic_scalar(l0)},
                         rounds=7, number=2000)
    rows = "\n".join(f"| `{name}` | {t['lines']} | {fmt_time(t['derive_s'])} | "
                     f"{fmt_time(t['cached_s'])} |" for name, t in times.items())
    text = ("Each example scene's module (both flavours) derived from a fresh cache in "
            "one process, then read back from the cache.\n\n"
            "| scene | lines | derive | from the cache |\n|---|---|---|---|\n" + rows +
            f"\n\n{n} random leg sets (Griffis-Duffy legs ± 1), per leg set:\n\n"
            + ratio_table(per, "octic_general.octic_batched (sides as inputs, 39 outputs)",
                          per="leg set")
            + "\n\nOne leg set, scalar flavour:\n\n"
            + ratio_table(scalar, "octic_general.octic_scalar")
            + f"\n\nLargest relative difference of a coefficient from `octic_general`: "
              f"{err:.1e} (octahedral module), {err66:.1e} (6-6 module, m-legs from eq. (8) "
              "in float64).")
    return text, {"derive": times, "batched_per_set_s": per, "scalar_s": scalar,
                  "max_rel_diff": err, "max_rel_diff_66": err66, "n": n}
