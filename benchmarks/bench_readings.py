"""Readings of Kühne et al.'s Fig. 2 and of Stocco's scaling (issue 15, findings 1 and 4):
for every reading tried, per preset, the reach over the study box, the link interference
(:mod:`distkin.mechanisms.interference`) and the Table IV figures; an explicit
identification of the leg length on Table IV with Table III held out.  Also writes
``docs/fig2_readings.md``."""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

__all__ = ["TITLE", "DEFAULT", "run", "READINGS"]

TITLE = "Readings of Fig. 2 and of the scaling: reach, interference, Table IV"
DEFAULT = False          # 1198 s on 2 cores in BENCHMARKS.md's run (1): run by name

PRESETS = ("hunt", "hexa", "ergin", "octopod", "octo")
#: name -> (description, function preset name -> mechanism)
READINGS = {
    "radial": ("radial axes, tangential cranks away from the pair, cranks horizontal at "
               "the centre (before issue 15)", lambda n: _p(n, layout="radial")),
    "tangential, horizontal": ("tangential axes, cranks radially outwards, horizontal at "
                               "the centre", lambda n: _p(n, l3=_p(n).horizontal_crank_l3())),
    "tangential_in": ("tangential axes, cranks radially inwards, horizontal at the centre",
                      lambda n: _p(n, layout="tangential_in")),
    "tangential, K (chosen)": ("tangential axes, cranks outwards, l2 + l3 = K = 349.7 mm "
                               "(centre of the closing interval)", lambda n: _p(n)),
}


def _p(name, **kw):
    from distkin.mechanisms import preset
    return preset(name, **kw)


def _box(mech, step, rot_step):
    from distkin.mechanisms.presets import study_box
    return study_box(mech, step=step, rot_step_deg=rot_step)


def _table4(mech, step=0.010, rot_step=5.0, batch=200_000):
    """GII, σmin, σmax of every scaling reading over the Table II grid (±20°) and the
    reachable share; numpy route (no kernel derivation per reading)."""
    from distkin.indices.isotropy import reading_singular_values
    from distkin.mechanisms.reference import ik_jacobian
    from distkin.indices.workspace import table2_grid
    g = table2_grid(mech.z0, step=step, rot_deg=20.0, rot_step_deg=rot_step)
    X = g.poses(np.arange(g.n_positions))
    lo, hi, ok_n = {}, {}, 0
    for a in range(0, len(X), batch):
        _, valid, J, Jq = ik_jacobian(mech, X[a:a + batch], return_jq=True)
        ok = valid.all(axis=1) & np.all(np.isfinite(J), axis=(1, 2))
        ok_n += int(ok.sum())
        for r, (s1, s2) in reading_singular_values(J[ok], Jq=Jq[ok]).items():
            lo[r] = min(lo.get(r, np.inf), float(s1.min()))
            hi[r] = max(hi.get(r, 0.0), float(s2.max()))
    return {r: (lo[r] / hi[r], lo[r], hi[r]) for r in lo}, ok_n / len(X)


def _reach_and_interference(mech):
    from distkin.mechanisms.reference import ik_jacobian
    from distkin.mechanisms.interference import interference
    X = _box(mech, 0.010, 10.0)
    q, valid, _ = ik_jacobian(mech, X)
    reach = float(valid.all(axis=1).mean())
    home = interference(mech, mech.home, q=ik_jacobian(mech, mech.home[None])[0])
    Xc = _box(mech, 0.025, 10.0)
    qc, vc, _ = ik_jacobian(mech, Xc)
    okc = vc.all(axis=1)
    box = interference(mech, Xc[okc], q=qc[okc])
    k = int(np.argmin(box.distance)) if len(box.distance) else 0
    return {"reach": reach, "home_mm": float(home.distance[0] * 1e3),
            "home_pair": home.pair[0], "box_min_mm": float(box.distance.min() * 1e3),
            "box_pair": box.pair[k], "box_below": float(np.mean(~box.ok))}


def _identify(data):
    """Explicit identification: K (= l2 + l3, tangential reading) fitted to the three
    GIIs of Table IV (least squares in log), Table III held out."""
    from distkin.indices.study import PAPER_TABLE3, PAPER_TABLE4, evaluate_poses
    Ks = np.arange(0.330, 0.3801, 0.002)
    errs = []
    for K in Ks:
        e = 0.0
        for n in ("hunt", "octopod", "octo"):
            m0 = _p(n)
            m = _p(n, l3=K - m0.l2)
            t4, frac = _table4(m, step=0.025, rot_step=10.0)
            g = t4["wrench"][0]
            e += math.log10(max(g, 1e-12) / PAPER_TABLE4[n][0]) ** 2 if frac == 1.0 else 1e3
        errs.append(e)
    kf = float(Ks[int(np.argmin(errs))])
    out = {"K_grid_m": Ks.tolist(), "fit_error": errs, "K_fit_m": kf}
    held = {}
    for label, K in (("rule", 0.3497), ("identified", kf)):
        logs = []
        for n in ("hunt", "octopod", "octo"):
            m0 = _p(n)
            m = _p(n, l3=K - m0.l2)
            X = _box(m, 0.025, 10.0)
            ok, v = evaluate_poses(m, X, route="numpy")
            for row, (pmin, pmax) in PAPER_TABLE3[n].items():
                for ours, paper in ((v[row].min(), pmin), (v[row].max(), pmax)):
                    if paper > 0 and ours > 0:
                        logs.append(abs(math.log10(ours / paper)))
            if not ok.all():
                logs.append(np.inf)              # an unreachable pose: no comparison
        held[label] = {"K_m": K, "median_abs_log10": float(np.median(logs)),
                       "within_2x": float(np.mean(np.asarray(logs) <= math.log10(2)))}
    out["table3_held_out"] = held
    data["identification"] = out
    return out


def run():
    t0 = time.perf_counter()
    data = {"readings": {}}
    from distkin.indices.isotropy import SCALING_READINGS
    from distkin.indices.study import PAPER_TABLE4
    rows, t4rows = [], []
    for key, (desc, make) in READINGS.items():
        rd = data["readings"].setdefault(key, {"description": desc})
        for n in PRESETS:
            m = make(n)
            ri = _reach_and_interference(m)
            t4, frac = _table4(m)
            rd[n] = {"l3_mm": m.l3 * 1e3, **ri, "table4": t4, "table4_reach": frac}
            rows.append(f"| {key} | {n} | {m.l3 * 1e3:.1f} | {100 * ri['reach']:.1f} % | "
                        f"{ri['home_mm']:.1f} ({ri['home_pair']}) | {ri['box_min_mm']:.1f} "
                        f"({ri['box_pair']}) | {100 * ri['box_below']:.2f} % |")
            if n in PAPER_TABLE4:
                g, s1, s2 = t4["wrench"]
                p = PAPER_TABLE4[n]
                t4rows.append(f"| {key} | {n} | {g:.3g} ({g / p[0]:.3g}×) | {s1:.3g} "
                              f"({s1 / p[1]:.3g}×) | {s2:.3g} ({s2 / p[2]:.3g}×) | "
                              f"{100 * frac:.1f} % |")
    ident = _identify(data)
    scal = []
    for n in ("hunt", "octopod", "octo"):
        t4 = data["readings"]["tangential, K (chosen)"][n]["table4"]
        p = PAPER_TABLE4[n]
        scal.append(f"| {n} | " + " | ".join(
            f"{t4[r][1]:.3g} / {t4[r][2]:.3g}" for r in SCALING_READINGS)
            + f" | {p[1]} / {p[2]} |")
    secs = time.perf_counter() - t0
    md = [f"Command: `python -m benchmarks readings` ({secs:.0f} s).  Every reading of "
          "Fig. 2 tried (`distkin.mechanisms.presets`), per preset: l3, the share of its "
          "study box (Table II positions at 10 mm, ±20° for L = 6 and ±30° for L = 8, "
          "10° steps) where every leg closes, the smallest link-to-link distance "
          "(`distkin.mechanisms.interference`: segments of cranks, offsets, distal links, "
          "end-effector and base spokes) at the centre pose and over the box (25 mm / 10° "
          "grid) with the share of box poses below the 5 mm clearance.", "",
          "| reading | preset | l3 [mm] | reach | min distance at the centre [mm] | "
          "min distance over the box [mm] | box poses < 5 mm |", "|---|---|---|---|---|---|---|",
          *rows, "",
          "Table IV figures of each reading (ST⁻¹Jᵀ, the Table II grid: 10 mm, 5°, ±20°), "
          "ours (ratio to the paper's):", "",
          "| reading | kinematics | GII | σmin | σmax | grid reached |", "|---|---|---|---|---|---|",
          *t4rows, "",
          "Readings of Stocco's scaling on the chosen geometry (σmin / σmax over the same "
          "grid; `distkin.indices.isotropy.SCALING_READINGS`); the paper's Table IV last:",
          "", "| kinematics | " + " | ".join(SCALING_READINGS.values()) + " | paper |",
          "|---|" + "---|" * (len(SCALING_READINGS) + 1), *scal, "",
          "Explicit identification (not used by the presets): K = l2 + l3 of the "
          "tangential reading fitted to Table IV's three GIIs (least squares of log10 "
          "ratios, K from 330 to 380 mm in 2 mm steps, 25 mm / 10° grid, a K that leaves "
          f"a pose unreachable excluded): K = {ident['K_fit_m'] * 1e3:.0f} mm.  Table III "
          "held out (Hunt-type, Octopod, Octo, every min and max the paper prints > 0, "
          "25 mm / 10° grid):", "",
          "| K | median abs log10(ours / paper) | rows within 2× |", "|---|---|---|"]
    for label, h in ident["table3_held_out"].items():
        md.append(f"| {label}: {h['K_m'] * 1e3:.1f} mm | {h['median_abs_log10']:.3f} | "
                  f"{100 * h['within_2x']:.0f} % |")
    text = "\n".join(md)
    doc = Path(__file__).resolve().parent.parent / "docs" / "fig2_readings.md"
    doc.write_text("# Readings of Fig. 2 and of the scaling (Kühne et al.)\n\n"
                   "Written by `python -m benchmarks readings`; the reading the presets use "
                   "and why: `distkin/mechanisms/presets.py`; the scaling: "
                   "`distkin/indices/isotropy.py`.\n\n" + text + "\n", encoding="utf-8")
    return text + "\n", data
