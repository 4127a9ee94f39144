"""The figures of the tradeoffs section, drawn from the section's stored numbers
(``results.json``: ``tradeoffs.data``) by the run and by ``python -m benchmarks
--replot tradeoffs``:

* ``tradeoffs_capability_grid_{octopod,hexa}.png`` from ``data[device]``
  (``rot_steps_deg``, ``seconds``, ``misses[cap][step]["worst_rel"]``,
  ``table[cap]["grid_min"][step]`` and ``["refined_min"]``);
* ``tradeoffs_kernel_digits.png`` from ``data["kernels"]["records"]``;
* ``tradeoffs_gii_sampling.png`` from ``data["gii_octopod"]`` and ``data["gii_culling"]``.
"""

from __future__ import annotations

import math

import numpy as np

from .plotting import FIGURES, figure, save

__all__ = ["plot", "capability_figure", "kernel_figure", "gii_figure", "DEVICES",
           "FLOOR"]

#: device key of the stored data -> the name the figure gives it (the HEXA of this
#: section is the preset under the radial reading of Fig. 2, bench_tradeoffs)
DEVICES = {"octopod": "Octopod", "hexa": "hexa* (HEXA, radial reading of Fig. 2)"}
#: a miss below this (%) is drawn at it: the grid found the refined minimum
FLOOR = 1e-4
#: one style per capability, drawn in this order: the markers shrink and the lines thin
#: from the first to the last, so that series lying on one another all show (rings
#: about the later ones), each with its own marker shape and dash
_STYLES = ({"marker": "o", "markersize": 12, "lw": 4.0, "ls": "-"},
           {"marker": "s", "markersize": 10, "lw": 3.2, "ls": "-"},
           {"marker": "D", "markersize": 8, "lw": 2.5, "ls": "--"},
           {"marker": "^", "markersize": 6.5, "lw": 2.0, "ls": "-."},
           {"marker": "v", "markersize": 5, "lw": 1.5, "ls": ":"},
           {"marker": "o", "markersize": 3.2, "lw": 1.0, "ls": "-"})


def _capabilities():
    """(name, label, unit) of the six capabilities (Kühne et al., Table III)."""
    from distkin.indices.study import CAPABILITIES
    return [(c[0], c[1], c[2]) for c in CAPABILITIES]


def capability_figure(device, d):
    """The capability-grid figure of ``device`` from its stored ``d``: the worst miss
    over the positions (left) and the miss of the global minimum (right), in % above
    the refined minimum, against the grid's evaluation time."""
    steps = d["rot_steps_deg"]
    keys = [str(float(s)) for s in steps]
    t = [d["seconds"][k] for k in keys]
    fig, axes = figure(1, 2, figsize=(11, 5.6))
    for (n, label, unit), style in zip(_capabilities(), _STYLES):
        worst = [100 * d["misses"][n][k]["worst_rel"] for k in keys]
        glob = [100 * (d["table"][n]["grid_min"][k] / d["table"][n]["refined_min"] - 1)
                for k in keys]
        for ax, v in zip(axes, (worst, glob)):
            ax.plot(t, np.maximum(v, FLOOR), label=f"{label} ({unit})", **style)
    for ax, title in zip(axes, (f"worst miss over the {d['positions']} positions",
                                "miss of the global minimum")):
        found = ax.axhline(FLOOR, color="k", lw=0.8, ls=(0, (1, 3)),
                           label=f"{FLOOR:g} %: the grid found the refined minimum "
                                 f"(smaller misses drawn here)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("grid evaluation time (s); points: "
                      + ", ".join(f"{s:g}°" for s in steps) + " grids")
        ax.set_ylabel("grid minimum above refined minimum (%)")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.set_ylim(FLOOR / 3, ax.get_ylim()[1])
    handles, labels = axes[0].get_legend_handles_labels()     # the floor's line last
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=8,
               title="capability (its unit; the misses are relative, in %)",
               title_fontsize=8)
    fig.suptitle(f"{DEVICES.get(device, device)}: worst-case capabilities, orientation "
                 f"grid (±20°) against accuracy")
    fig.tight_layout(rect=(0, 0.19, 1, 1))
    return fig


def kernel_figure(recs):
    """Digits lost by the float64 Jacobian kernel and what is computed from it,
    against log10 σmin, from the stored records."""
    x = [math.log10(r["sigma_min"]) for r in recs]
    fig, ax = figure(figsize=(7.5, 4.8))
    for key, lab, mk in (("rel_err_entries", "J entries (normwise)", "o"),
                         ("rel_err_det", "det J (numpy)", "s"),
                         ("rel_err_sigma_min_lapack", "σmin (LAPACK SVD)", "^"),
                         ("rel_err_sigma_min_kernel_only", "σmin of float64 J, exact SVD",
                          "v")):
        ax.plot(x, [r["digits_lost"][key] for r in recs], mk + "-", label=lab, alpha=0.8)
    ax.plot(x, [math.log10(r["kappa"]) for r in recs], "k--",
            label="prediction log10 κ (κ·eps)")
    ax.set_xlabel("log10 σmin(J)   (σmin in SI; J's columns rad/m and rad/rad)")
    ax.set_ylabel("digits lost (log10 rel. error / eps; no unit)")
    ax.invert_xaxis()
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("HEXA Jacobian kernel (float64) vs mpmath (50 digits), approaching "
                 "det J = 0", fontsize=10)
    fig.tight_layout()
    return fig


def gii_figure(runs, gii_ref, sweeps):
    """The GII against its sampling time (left) and the Table I culling sweep's time
    and optimum against the poses sampled (right; two y axes, each coloured like its
    line, and a legend naming the axis of each line)."""
    from matplotlib.ticker import FormatStrFormatter
    fig, axes = figure(1, 2, figsize=(11.5, 4.4))
    pos = [r for r in runs if r["rot_step_deg"] == 10.0]
    rot = sorted([r for r in runs if r["positions_per_axis"] == 5],
                 key=lambda r: -r["rot_step_deg"])
    for series, lab in ((pos, "position step (10° orientations)"),
                        (rot, "orientation step (5³ positions)")):
        axes[0].plot([r["seconds"] for r in series], [r["gii"] for r in series], "o-",
                     label=lab)
    axes[0].axhline(gii_ref, color="k", ls="--", label="refined (continuous box)")
    axes[0].set_xscale("log")
    axes[0].set_xlabel("time of the sampled GII (s)")
    axes[0].set_ylabel("GII of the Octopod (no unit)")
    axes[0].legend(fontsize=8, loc="best")
    axes[0].grid(True, which="both", alpha=0.3)
    axes[0].set_title("GII against sampling time")
    left, c_left, c_right = axes[1], "C0", "C1"
    poses = [s["poses"] for s in sweeps]
    h1, = left.plot(poses, [s["seconds"] for s in sweeps], "o-", color=c_left,
                    label="culling sweep time (s; left axis)")
    right = left.twinx()
    h2, = right.plot(poses, [s["gii"] for s in sweeps], "s--", color=c_right,
                     label="GII of the optimal design (right axis)")
    left.set_xscale("log")
    left.set_yscale("log")
    left.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    left.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
    left.set_xlabel("poses sampled")
    left.set_ylabel("culling sweep time (s)", color=c_left)
    right.set_ylabel("GII of the optimum (no unit)", color=c_right)
    left.tick_params(axis="y", which="both", colors=c_left, labelsize=8)
    right.tick_params(axis="y", which="both", colors=c_right, labelsize=8)
    right.spines["left"].set_color(c_left)
    right.spines["right"].set_color(c_right)
    left.set_title("Table I design sweep (560 designs)")
    left.grid(True, which="both", alpha=0.3)
    left.legend([h1, h2], [h1.get_label(), h2.get_label()], fontsize=8, ncol=2,
                loc="upper center", bbox_to_anchor=(0.5, -0.14), frameon=False)
    fig.tight_layout()
    return fig


def plot(data, out=FIGURES) -> dict:
    """Draw the section's four figures from its stored ``data`` into ``out``; returns
    {file name: path written}."""
    written = {}
    for device in ("octopod", "hexa"):
        name = f"tradeoffs_capability_grid_{device}.png"
        written[name] = save(capability_figure(device, data[device]), out, name)
    name = "tradeoffs_kernel_digits.png"
    written[name] = save(kernel_figure(data["kernels"]["records"]), out, name)
    name = "tradeoffs_gii_sampling.png"
    g = data["gii_octopod"]
    written[name] = save(gii_figure(g["runs"], g["refined"]["gii"], data["gii_culling"]),
                         out, name)
    return written
