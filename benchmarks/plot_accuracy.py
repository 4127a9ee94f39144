"""The figure of the accuracy section (``accuracy_fk.png``), drawn from the section's
stored numbers (``results.json``: ``accuracy.data``, keys ``rows`` and ``miscount``) by
the run and by ``python -m benchmarks --replot accuracy``."""

from __future__ import annotations

import numpy as np

from .plotting import FIGURES, figure, place_labels, save

__all__ = ["plot", "accuracy_figure", "NAME", "COLOURS"]

NAME = "accuracy_fk.png"
#: tier kind -> colour
COLOURS = {"fast": "tab:blue", "auto": "tab:green", "precise": "tab:orange",
           "certified": "tab:red"}
_MARKER_PT = 9.0
#: tiers drawn as another marker, so that tiers at the same place all show: fast + proof
#: and auto take the same time within a few per cent (a hollow square about a diamond)
_MARKERS = {"fast + proof": dict(fmt="s", markersize=9, markerfacecolor="none",
                                 markeredgewidth=1.5),
            "auto": dict(fmt="D", markersize=4.5)}


def accuracy_figure(data):
    """(fig, annotations): correct digits against CPU time per tier (left; every tier
    named beside its marker, no name over a marker or another name) and the wrong
    real-root counts per tier (right)."""
    rows, miscount = data["rows"], data["miscount"]
    fig, (ax, bx) = figure(1, 2, figsize=(12.5, 5.0))
    points, names, colours, bars = [], [], [], []
    for name, r in rows.items():
        colour = COLOURS[name.split()[0]]
        x, y = r["cpu_per_solve_median"] * 1e3, r["median_digits"]
        style = _MARKERS.get(name, dict(fmt="o", markersize=5))
        ax.errorbar(x, y, yerr=[[y - r["min_digits"]], [0]], color=colour, capsize=3,
                    **style)
        points.append((x, y))
        names.append(name)
        colours.append(colour)
        bars.append((x, r["min_digits"], x, y))
    ax.set_xscale("log")
    ax.set_xlabel("CPU time per solve (ms, median over the digit set)")
    ax.set_ylabel("correct digits of the poses (median; bar down to the minimum)")
    ax.set_title("Octahedral FK: accuracy against cost")
    ax.grid(True, which="both", alpha=0.3)
    ys = [p[1] for p in points] + [b[1] for b in bars]
    xs = [p[0] for p in points]
    ax.set_ylim(min(ys) - 8, max(ys) + 12)               # room for the names
    ax.set_xlim(min(xs) / 8, max(xs) * 6)
    _miscount_panel(bx, miscount)
    fig.tight_layout()
    notes = place_labels(ax, points, names, marker_pt=_MARKER_PT, obstacles=bars,
                         colours=colours)
    return fig, notes


def _miscount_panel(bx, miscount):
    sets = list(miscount)
    names = list(miscount[sets[0]])
    y = np.arange(len(names))
    h = 0.8 / len(sets)
    silent_total = sum(m[n].get("silent", 0) for m in miscount.values() for n in names)
    for k, label in enumerate(sets):
        m = miscount[label]
        rate = [100 * m[n]["wrong"] / m[n]["n"] for n in names]
        silent = [100 * m[n].get("silent", 0) / m[n]["n"] for n in names]
        bx.barh(y + k * h, rate, height=h, label=f"{label}: wrong count",
                color=("tab:gray", "tab:olive")[k % 2])
        bx.barh(y + k * h, silent, height=h, color="tab:red",
                label=(None if k else
                       "... of which not announced" + (" (none in this run)"
                                                       if silent_total == 0 else "")))
        for yy, v in zip(y + k * h, rate):
            bx.text(v, yy, f" {v:.1f} %", va="center", fontsize=7)
    bx.set_yticks(y + 0.4 - h / 2, names, fontsize=8)
    bx.invert_yaxis()
    bx.set_xlim(0, 5 * np.ceil(1.15 * max(100 * m[n]["wrong"] / m[n]["n"]
                                          for m in miscount.values() for n in names) / 5))
    bx.set_xlabel("problems with a wrong count (%)")
    bx.set_title("Real-root count on the hard set and the issue-14 families")
    bx.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3,
              frameon=False)


def plot(data, out=FIGURES) -> dict:
    """Draw ``accuracy_fk.png`` from the section's stored ``data`` into ``out``;
    returns {file name: path written}."""
    fig, _ = accuracy_figure(data)
    return {NAME: save(fig, out, NAME)}
