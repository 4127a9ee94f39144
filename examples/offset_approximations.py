"""Measure what the joint offsets of Rojas, Borràs, Thomas (ICRA 2012) Fig. 2 (b)-(d) cost.

Run from the repository root::

    python examples/offset_approximations.py            # writes docs/offset_approximations.md
                                                        # and docs/figures/offset_approximations.png
    python examples/offset_approximations.py --out /tmp/oa  # the same files elsewhere
    python examples/offset_approximations.py --quick    # fewer poses and offsets, prints only

The octahedral manipulator is the Griffis-Duffy example of Sec. VI (base side 12, platform
side 6, unitless lengths; docs/design.md §5).  Poses: its six assembly modes above the
base (legs 19.8, 18, 18, 17, 14.9, 17.8) and random poses around them.  For each
approximation (:mod:`distkin.delta.approximations`) and offset delta from 0.1 % to 10 % of
the base side: the pose error of neglecting the offsets, the exact Δ-transform route for
Fig. 2(d), and how far the zeros of det J (eq. (5)) move along lines through the singular
poses nearest to the six modes and along the pure 90-degree twist of the Griffis-Duffy
platform (flipped, turned about the vertical through both centroids; the path of
examples/delta_griffis_duffy.toml is tilted and is not this line)
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from distkin.delta import (KINDS, PoseLine, approximation, compare_approximations,  # noqa: E402
                           normal_line)
from distkin.delta.offset_study import det_along, neglected_offset_error, platform_frame  # noqa: E402
from distkin.octahedral import forward_kinematics  # noqa: E402
from distkin.singularity import rotation_from_vector  # noqa: E402

GD = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
LEGS = ["19.8", "18", "18", "17", "14.9", "17.8"]
BASE = 12.0
RELATIVE = (0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1)
LABEL = {"standard": "(b) standard", "stoughton_arai": "(c) Stoughton-Arai",
         "griffis_duffy": "(d) Griffis-Duffy"}


def example_poses(n_random: int, seed: int = 0):
    """The six assembly modes above the base and ``n_random`` poses around them
    (translation N(0, 0.5^2) per axis, rotation vector N(0, 0.05^2) rad per axis)."""
    res = forward_kinematics(*GD, LEGS, method="certified")
    modes = [p for p in res.poses if p.translation[2] > 0]
    Rs = [np.asarray(p.rotation, float) for p in modes]
    ts = [np.asarray(p.translation, float) for p in modes]
    rng = np.random.default_rng(seed)
    for i in range(n_random):
        j = i % len(modes)
        Rs.append(rotation_from_vector(rng.normal(scale=0.05, size=3)) @ Rs[j])
        ts.append(ts[j] + rng.normal(scale=0.5, size=3))
    return np.array(Rs), np.array(ts), len(modes)


def twist_line():
    """The pure 90-degree twist of the Griffis-Duffy platform as a pose line: the
    platform flipped (Rx(180 deg)), its centroid 10 above the base centroid, twisted about
    the vertical through the centroids from 60 to 120 degrees (s = 0.5 is 90 degrees).
    (The path of examples/delta_griffis_duffy.toml is not this line: it tilts the
    platform by ~6 degrees midway and crosses at s = 0.50167.)"""
    from distkin.spatial import axis_angle
    R0 = axis_angle([0, 0, 1], np.pi / 2) @ axis_angle([1, 0, 0], np.pi)
    centre = np.array([6.0, 2 * np.sqrt(3), 10.0])
    local = np.array([3.0, np.sqrt(3), 0.0])            # platform centroid, own frame
    return PoseLine(R0, centre - R0 @ local, np.zeros(3), np.array([0, 0, np.pi / 6]),
                    tuple(centre))


#: shifts below this (length units, the base side is 12) are float64 rounding: printed
#: as such, so that the table does not change with the BLAS or the machine
NOISE = 1e-12


def shift_text(v) -> str:
    return f"< {NOISE:.0e}" if np.isfinite(v) and v < NOISE else f"{v:.3e}"


def stats(a):
    a = np.asarray(a, float).ravel()
    a = a[np.isfinite(a)]
    return (np.median(a), np.max(a)) if a.size else (np.nan, np.nan)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="3 offsets, 4 random poses, no files")
    ap.add_argument("--random", type=int, default=14, help="random poses (default 14)")
    ap.add_argument("--out", type=Path, default=ROOT / "docs", metavar="DIR",
                    help="folder for offset_approximations.md and figures/ (default: the "
                         "checkout's docs/, whose copies are tracked)")
    args = ap.parse_args(argv)
    rel = (0.001, 0.01, 0.1) if args.quick else RELATIVE
    deltas = [f"{r * BASE:.6g}" for r in rel]
    Rs, ts, nmodes = example_poses(4 if args.quick else args.random)
    lines = [twist_line()] + [normal_line(GD, Rs[j], ts[j], 1.0) for j in range(nmodes)]
    t0 = time.perf_counter()
    cmp = compare_approximations(GD, Rs, ts, deltas, lines=lines,
                                 progress=lambda s: print("  " + s, file=sys.stderr))
    seconds = time.perf_counter() - t0
    # the precise tier on the six modes at one offset: how far fast is from it
    dps_check = []
    for k in KINDS:
        plat = approximation(GD, k, deltas[len(deltas) // 2])
        for j in range(nmodes):
            f = neglected_offset_error(GD, plat, Rs[j], ts[j], method="fast")
            p = neglected_offset_error(GD, plat, Rs[j], ts[j], method="precise", dps=30)
            dps_check.append((abs(f.position - p.position), abs(f.orientation - p.orientation),
                              p.exact_position))
    # how far each assembly mode is from the octahedral singular locus
    from distkin.delta import octahedral_as_66
    from distkin.singularity.paths import nearest_singularity
    _, L = platform_frame(GD)
    oct66 = octahedral_as_66(GD)
    near = [nearest_singularity(lambda R, t: det_along(oct66, R, t, L), Rs[j], ts[j], L).distance
            for j in range(nmodes)]
    grid = sign_grid(Rs[:nmodes], ts[:nmodes], deltas, L)
    text = report(cmp, nmodes, len(lines), seconds, dps_check, deltas[len(deltas) // 2], near,
                  grid)
    print(text)
    if not args.quick:
        (args.out / "figures").mkdir(parents=True, exist_ok=True)
        (args.out / "offset_approximations.md").write_text(text)
        plot(cmp, args.out / "figures" / "offset_approximations.png")
    return 0


def sign_grid(Rs, ts, deltas, L, n=4000, seed=1):
    """Poses scattered around the modes (translation N(0, 2^2), rotation N(0, 0.4^2) rad
    per axis): the fraction where sign(det J) of an approximation differs from
    sign(det A) sign(det J) of the octahedral manipulator, per offset and kind."""
    from distkin.delta import octahedral_as_66
    rng = np.random.default_rng(seed)
    j = rng.integers(len(Rs), size=n)
    R = rotation_from_vector(rng.normal(scale=0.4, size=(n, 3))) @ Rs[j]
    t = ts[j] + rng.normal(scale=2.0, size=(n, 3))
    ref = np.sign(det_along(octahedral_as_66(GD), R, t, L))
    out = {}
    for d in deltas:
        for k in KINDS:
            plat = approximation(GD, k, d)
            sgn = np.sign(float(plat.transform.det)) if plat.transform is not None else 1.0
            out[d, k] = int(np.sum(np.sign(det_along(plat, R, t, L)) != sgn * ref))
    return n, out


def report(cmp, nmodes, nlines, seconds, dps_check, mid, near, grid) -> str:
    npose = cmp.position[cmp.kinds[0]].shape[1]
    out = ["# Offset approximations of the octahedral manipulator: measured", "",
           "Generated by `python examples/offset_approximations.py` (do not edit by hand). "
           "Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, "
           "Fig. 2 (b)-(d), eqs. (5), (8); constructions in `distkin/delta/approximations.py` "
           "(which leg goes where), measurements in `distkin/delta/offset_study.py`.", "",
           f"Octahedral manipulator: the Griffis-Duffy example of Sec. VI (base side "
           f"{cmp.base_size:g}, platform side 6, lengths unitless). {npose} poses: its "
           f"{nmodes} assembly modes above the base and {npose - nmodes} random poses around "
           "them. δ is the centre distance of the two single joints replacing a double-ball "
           f"joint. Tier `{cmp.method}`; {cmp.untrusted} octahedral solves left unproved "
           "(`auto`: the fast tier's proof, else the certified tier). Run time "
           f"{seconds:.1f} s.", "",
           "![errors and singularities](figures/offset_approximations.png)", "",
           "## Pose error of neglecting the offsets", "",
           "The 6-6 legs at the true pose are given to the octahedral forward kinematics; the "
           "assembly mode nearest the true pose is compared with it. Position: displacement "
           "of the platform centroid (length units); orientation: rotation angle (rad). "
           "Median and maximum over the poses. For (d), *exact* is the Δ-transform route "
           "(eq. (8): l² = A⁻¹(m² + b), then the octahedral forward kinematics).", "",
           "*Off linear*: poses where the measured position error and the first-order "
           "prediction J⁻¹(m − l) of eq. (5) differ by more than 50 % (the nearest octahedral "
           "assembly mode is then on another branch, or the mode has merged with another).",
           "",
           "| δ (length) | δ / base | kind | position median | position max | "
           "orientation median (rad) | orientation max (rad) | max error / δ | off linear |",
           "|---|---|---|---|---|---|---|---|---|"]
    for i, d in enumerate(cmp.deltas):
        for k in cmp.kinds:
            pm, px = stats(cmp.position[k][i])
            om, ox = stats(cmp.orientation[k][i])
            off = np.abs(cmp.first_order_position[k][i] / cmp.position[k][i] - 1) > 0.5
            out.append(f"| {d:.4g} | {d / cmp.base_size:.1%} | {LABEL[k]} | {pm:.3e} | "
                       f"{px:.3e} | {om:.3e} | {ox:.3e} | {px / d:.3g} | "
                       f"{int(off.sum())}/{off.size} |")
        pm, px = stats(cmp.exact_position[i])
        om, ox = stats(cmp.exact_orientation[i])
        out.append(f"| {d:.4g} | {d / cmp.base_size:.1%} | (d) exact route | {pm:.1e} | "
                   f"{px:.1e} | {om:.1e} | {ox:.1e} | | |")
    out += ["", "Per assembly mode (smallest δ): the error grows as the mode nears the "
            "singular locus. Distance to the nearest octahedral singular pose (pose space, "
            "rotations scaled by the platform circumradius; local search) and position "
            "error / δ:", "",
            "| mode (s15 order: 269.2 … 513.0) | distance to singularity | " +
            " | ".join(LABEL[k] for k in cmp.kinds) + " |", "|---|---|" +
            "---|" * len(cmp.kinds)]
    for j in range(nmodes):
        out.append(f"| {j + 1} | {near[j]:.3g} | " + " | ".join(
            f"{cmp.position[k][0, j] / cmp.deltas[0]:.3g}" for k in cmp.kinds) + " |")
    out += ["", "First-order check: the twist J⁻¹(m − l) of eq. (5) against the measured error "
            "(relative difference of the position error, median over the poses):", "",
            "| δ / base | " + " | ".join(LABEL[k] for k in cmp.kinds) + " |",
            "|---|" + "---|" * len(cmp.kinds)]
    for i, d in enumerate(cmp.deltas):
        cells = []
        for k in cmp.kinds:
            r = np.abs(cmp.first_order_position[k][i] / cmp.position[k][i] - 1)
            cells.append(f"{np.nanmedian(r):.2e}")
        out.append(f"| {d / cmp.base_size:.1%} | " + " | ".join(cells) + " |")
    fp = max(x[0] for x in dps_check)
    fo = max(x[1] for x in dps_check)
    ex = np.nanmax([x[2] for x in dps_check])
    out += ["", f"Tiers: at δ = {mid} the precise tier (mpmath, 30 digits) agrees with the "
            f"fast one to {fp:.1e} (position) and {fo:.1e} rad (orientation) on the "
            f"{nmodes} assembly modes; its exact-route error for (d) is {ex:.1e}.", "",
            "## Do the singularities move?", "",
            f"det J of eq. (5) (normalised Plücker coordinates, moments divided by the "
            f"platform circumradius) along {nlines} lines in pose space: the pure 90° twist "
            "of the Griffis-Duffy platform (flipped, centroid 10 above the base centroid, "
            "turned about the vertical through both centroids from 60° to 120°; the path "
            "of `examples/delta_griffis_duffy.toml` tilts the platform and is not this "
            "line) and, for each assembly mode, the line "
            "through the nearest octahedral singular pose along the locus normal (±1 "
            "length unit, rotations scaled by the circumradius). Each octahedral zero is "
            "matched with the nearest zero of the approximation; the shift is the "
            f"pose-space distance (length units); shifts below {NOISE:.0e} are float64 "
            "rounding and printed as such.", "",
            "| δ (length) | δ / base | kind | twist: shift | normal lines: median | "
            "normal lines: max | max shift / δ | zeros lost |",
            "|---|---|---|---|---|---|---|---|"]
    for i, d in enumerate(cmp.deltas):
        for k in cmp.kinds:
            s = cmp.shift[k][i]
            m, x = stats(s[1:])
            ratio = (f"< {NOISE / d:.0e}" if np.nanmax(s) < NOISE
                     else f"{np.nanmax(s) / d:.3g}")
            out.append(f"| {d:.4g} | {d / cmp.base_size:.1%} | {LABEL[k]} | "
                       f"{shift_text(s[0])} | {shift_text(m)} | {shift_text(x)} | {ratio} | "
                       f"{int(np.sum(~np.isfinite(s)))} |")
    out += ["", "For (d), eq. (6) holds as a matrix identity, Ĵ₆₆ = A Ĵ (unnormalised "
            "Plücker matrices): worst relative residual over the poses "
            f"{np.nanmax(cmp.identity_residual):.1e}, so det J₆₆ = det A · det Ĵ / Π m and "
            "the singular sets coincide.", "",
            f"On a scatter of {grid[0]} poses around the six modes (translation σ = 2, "
            "rotation σ = 0.4 rad per axis), the poses where sign(det J) of the approximation "
            "differs from sign(det A)·sign(det J) of the octahedral manipulator (poses "
            "between the two singular loci):", "",
            "| δ / base | " + " | ".join(LABEL[k] for k in cmp.kinds) + " |",
            "|---|" + "---|" * len(cmp.kinds)]
    for d in cmp.deltas:
        key = f"{d:.6g}"
        out.append(f"| {d / cmp.base_size:.1%} | " + " | ".join(
            str(grid[1][key, k]) for k in cmp.kinds) + " |")
    out += ["",
            "On the twist line the standard split (b) keeps the octahedral zero at 90° "
            f"(measured shift below {NOISE:.0e}, rounding; certified bracket [0, 7.3e-12] at δ = 1 %, "
            "`tests/delta/test_approximations.py`): its six base joints lie on one circle "
            "and its six platform joints on another (radius √(r² + δ²/4)), which is the "
            "setting of Fichter's 90° twist singularity. The radial split (c) puts the "
            "joints of each triangle on two radii and moves it.",
            ""]
    return "\n".join(out)


def plot(cmp, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 2, figsize=(11, 8.5))
    rel = cmp.deltas / cmp.base_size
    colors = {"standard": "C0", "stoughton_arai": "C1", "griffis_duffy": "C2"}
    for k in cmp.kinds:
        for a, data in ((ax[0, 0], cmp.position[k]), (ax[0, 1], cmp.orientation[k])):
            med = np.nanmedian(data, axis=1)
            mx = np.nanmax(data, axis=1)
            a.loglog(rel, med, "o-", color=colors[k], label=f"{LABEL[k]}, median")
            a.loglog(rel, mx, "--", color=colors[k], alpha=0.6, label=f"{LABEL[k]}, max")
        sh = cmp.shift[k]
        if np.isfinite(sh).any():
            ax[1, 0].loglog(rel, np.maximum(np.nanmax(sh, axis=1), 1e-17), "o-",
                            color=colors[k], label=f"{LABEL[k]}, max")
    for a, data in ((ax[0, 0], cmp.exact_position), (ax[0, 1], cmp.exact_orientation)):
        a.loglog(rel, np.maximum(np.nanmax(data, axis=1), 1e-17), "s:", color="k",
                 label="(d) exact route (eq. (8)), max")
    ax[0, 0].set(xlabel="δ / base side", ylabel="position error (length units)",
                 title="Neglecting the offsets: position")
    ax[0, 1].set(xlabel="δ / base side", ylabel="orientation error (rad)",
                 title="Neglecting the offsets: orientation")
    ax[1, 0].set(xlabel="δ / base side", ylabel="zero shift of det J (length units)",
                 title="Movement of the singular locus")
    for a in (ax[0, 0], ax[0, 1], ax[1, 0]):
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=7)
    line = twist_line()
    _, L = platform_frame(GD)
    s = np.linspace(0, 1, 401)
    deg = 90 + 30 * (2 * s - 1)
    from distkin.delta import octahedral_as_66
    d5 = f"{0.05 * cmp.base_size:.6g}"
    ax[1, 1].plot(deg, det_along(octahedral_as_66(GD), *line.at(s), L), "k-", lw=2,
                  label="octahedral (a)")
    for k in cmp.kinds:
        ax[1, 1].plot(deg, det_along(approximation(GD, k, d5), *line.at(s), L),
                      color=colors[k], label=f"{LABEL[k]}, δ = 5 % of base")
    ax[1, 1].axhline(0, color="gray", lw=0.5)
    ins = ax[1, 1].inset_axes([0.58, 0.08, 0.38, 0.38])
    for ln in ax[1, 1].get_lines():
        ins.plot(*ln.get_data(), color=ln.get_color(), lw=ln.get_linewidth())
    ins.axhline(0, color="gray", lw=0.5)
    ins.set(xlim=(87, 92), ylim=(-0.12, 0.12))
    ins.tick_params(labelsize=6)
    ax[1, 1].set(xlabel="twist about the vertical (deg)", ylabel="det J (dimensionless)",
                 title="det J of eq. (5) along the 90° twist (inset: zoom)")
    ax[1, 1].legend(fontsize=7)
    fig.suptitle("Rojas et al. Fig. 2 (b)-(d) approximations of the Griffis-Duffy octahedral "
                 "manipulator")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    raise SystemExit(main())
