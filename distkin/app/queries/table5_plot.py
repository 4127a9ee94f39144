"""The ``--plots`` drawing of the ``table5`` query (:class:`.control.Table5Query`): Table
V of Kühne et al. emulated on the simulated device (:mod:`distkin.control.table5`).

Top panel: per Table V row (force, torque, velocity, angular velocity, acceleration,
angular acceleration), the emulated measurement (the mean of the trials, each trial a
black dot, their min..max an error bar), our analysis (the Table III minimum over the
query's grid) and the paper's experiment and simulation columns (Kühne et al. Table V,
where printed), each divided by our analysis, so that rows of different units share
one axis (1 = the analysis); every bar carries its value in the row's own unit.

Bottom panels: the first trial of each row against time from the start of the smoothed
step, in the row's unit: for a blocked row (force, torque) the wrench ``Jᵀτ`` on the
block along the worst direction and the F/T readings the row averages (shaded: the
averaging window); for a free row the speed or acceleration along the worst direction,
its peak (the row's value) marked.  The worst poses are in the scene's units.

The numbers drawn are the query's result (its ``rows``, as in the JSON) and the traces
:func:`distkin.control.table5.run_table5` returns with ``traces = True``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...numfmt import fixed
from ..units import display_length

__all__ = ["plot_table5", "table5_figure", "SERIES"]

#: the bars of the top panel: (key of a row, legend label, colour)
SERIES = (("emulated", "emulated experiment (mean of the trials)", "tab:blue"),
          ("analysis", "our analysis (Table III minimum, 25 mm / 10° grid, ±30°)",
           "0.55"),
          ("paper_experiment", "paper's experiment (Table V)", "tab:orange"),
          ("paper_simulation", "paper's simulation (Table V)", "tab:green"))

_WIDTH = 0.2


def _number(v) -> float | None:
    """A finite float, or None (a column the paper does not print, a NaN)."""
    if v is None or isinstance(v, bool):
        return None
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def _shown(key, v) -> str:
    """A value as the report prints it: ours in 4 significant digits, fixed notation;
    the paper's as printed there."""
    return str(v) if key.startswith("paper_") else fixed(v)


def _ratio(v, analysis) -> float:
    v = _number(v)
    return v / analysis if v is not None and analysis else math.nan


def _label(row: str) -> str:
    return row.replace("_", " ")


def _comparison(ax, rows):
    """The top panel; returns whether it used a log axis."""
    names = list(rows)
    x = np.arange(len(names), dtype=float)
    ana = {n: (_number(rows[n].get("analysis")) or 0.0) for n in names}
    ana = {n: (a if a > 0 else None) for n, a in ana.items()}
    trials = {n: [_number(v) for v in rows[n].get("trial_values",
                                                   [rows[n].get("emulated")])]
              for n in names}
    drawn = [_ratio(rows[n].get(k), ana[n]) for n in names for k, _, _ in SERIES]
    drawn += [_ratio(v, ana[n]) for n in names for v in trials[n]]
    pos = [v for v in drawn if np.isfinite(v) and v > 0]
    log = bool(pos) and max(pos) >= 100 * min(pos)
    if log:
        ax.set_yscale("log")
    top = max(pos) if pos else 1.0
    for j, (key, label, colour) in enumerate(SERIES):
        off = (j - 1.5) * _WIDTH
        h = np.array([_ratio(rows[n].get(key), ana[n]) for n in names])
        ax.bar(x + off, np.where(np.isfinite(h), h, 0.0), _WIDTH, color=colour,
               label=label, edgecolor="k", linewidth=0.4)
        for i, n in enumerate(names):
            v = _number(rows[n].get(key))
            if v is None or not np.isfinite(h[i]):
                continue
            tip = h[i]
            if key == "emulated":
                r = [_ratio(t, ana[n]) for t in trials[n] if t is not None]
                if r:
                    tip = max(tip, max(r))
            ax.annotate(f"{_shown(key, rows[n][key])} {rows[n].get('unit', '')}",
                        (x[i] + off, tip), xytext=(0, 6), textcoords="offset points",
                        rotation=90, ha="center", va="bottom", fontsize=7,
                        gid=f"value:{n}:{key}")
    # the trials: dots, and their min..max as an error bar on the mean
    off = -1.5 * _WIDTH
    tx, ty = [], []
    for i, n in enumerate(names):
        r = [_ratio(t, ana[n]) for t in trials[n] if t is not None]
        r = [v for v in r if np.isfinite(v)]
        if not r:
            continue
        tx += [x[i] + off] * len(r)
        ty += r
        m = _ratio(rows[n].get("emulated"), ana[n])
        if np.isfinite(m) and len(r) > 1:
            ax.errorbar([x[i] + off], [m], yerr=[[m - min(r)], [max(r) - m]], fmt="none",
                        ecolor="k", capsize=3, lw=1)
    ax.plot(tx, ty, "o", color="k", ms=3, ls="none", label="each trial", gid="trials")
    ax.axhline(1.0, color="0.3", ls="--", lw=0.8)
    for i, n in enumerate(names):
        if ana[n] is None:
            ax.text(x[i], 0.5, "analysis 0 or missing:\nnot normalised", ha="center",
                    fontsize=7, transform=ax.get_xaxis_transform())
    ax.set_xticks(x)
    ax.set_xticklabels([f"{_label(n)}\n[{rows[n].get('unit', '')}]" for n in names],
                       fontsize=9)
    ax.set_xlim(-0.6, len(names) - 0.4)
    if log:
        ax.set_ylim(min(pos) / 2, top * 30)
    else:
        ax.set_ylim(0, top * 1.45)
    ax.set_xlabel("Table V row [the unit of its values, written on its bars]")
    ax.set_ylabel("value / our analysis [1]  (1 = the analysis)")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", ncol=5)
    return log


def _where(r, lu, au) -> str:
    p = r.get("pose")
    if p is None or len(p) != 6:
        return ""
    return (f"at ({', '.join(f'{v:.4g}' for v in p[:3])}) {lu}, "
            f"({', '.join(f'{v:.4g}' for v in p[3:])}) {au}")


def _trace_panel(ax, n, r, tr, how, lu, au):
    unit = r.get("unit", "")
    t = 1e3 * np.asarray(tr["t"], dtype=float)
    v = np.asarray(tr["value"], dtype=float)
    ana = _number(r.get("analysis"))
    if "reading" in tr:
        rd = np.asarray(tr["reading"], dtype=float)
        held = np.isfinite(rd)
        ax.plot(t, v, color="tab:blue", lw=1.2, gid="wrench",
                label="Jᵀτ on the block along the worst direction (no sensor noise)")
        ax.plot(t[held], rd[held], ".", color="tab:purple", ms=2, gid="reading",
                label="F/T readings the row averages (shaded)")
        if held.any():
            ax.axvspan(t[held][0], t[held][-1], color="tab:purple", alpha=0.08)
        first = (r.get("trial_values") or [r.get("emulated")])[0]
        if _number(first) is not None:
            ax.axhline(first, color="tab:purple", lw=0.8, gid="trial_mean",
                       label=f"this trial: {fixed(first)} {unit}")
        what = f"{_label(n)}, blocked, trial 1"
        ylab = f"{_label(n)} on the block [{unit}]"
    else:
        ax.plot(t, v, color="tab:blue", lw=1.2, gid="along",
                label=f"along the worst direction ({how})")
        if v.size:
            k = int(np.nanargmax(v))
            ax.plot([t[k]], [v[k]], "v", color="tab:red", ms=7, gid="peak",
                    label=f"peak: {fixed(v[k])} {unit}")
        what = f"{_label(n)}, free, {how}"
        ylab = f"{_label(n)} along the worst direction [{unit}]"
    if ana is not None:
        ax.axhline(ana, color="0.45", ls="--", lw=0.8,
                   label=f"our analysis: {fixed(ana)} {unit}")
    ax.set_title(f"{what}\n{_where(r, lu, au)}", fontsize=8)
    ax.set_xlabel("time from the start of the step [ms]", fontsize=8)
    ax.set_ylabel(ylab, fontsize=8)
    ax.tick_params(labelsize=7)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6.5, loc="best")


def table5_figure(result, traces=None, *, name="octo", length_unit="m", angle_unit="rad"):
    """The matplotlib Figure of :func:`plot_table5` (same arguments), not saved."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = result["rows"]
    traces = {n: t for n, t in (traces or {}).items() if n in rows and t is not None}
    lu = display_length(length_unit)[1]
    au = angle_unit if angle_unit in ("rad", "deg") else "rad"
    n_tr = len(traces)
    cols = 3
    lines = (n_tr + cols - 1) // cols
    height = 5.2 + 3.6 * lines
    fig = plt.figure(figsize=(15, height))
    # a fixed layout in inches (tight_layout took as long as the drawing)
    gs = fig.add_gridspec(1 + lines, cols, height_ratios=[1.6] + [1.0] * lines,
                          left=0.055, right=0.985, bottom=0.6 / height,
                          top=1 - 0.95 / height, hspace=0.62, wspace=0.24)
    ax = fig.add_subplot(gs[0, :])
    ax.set_gid("comparison")
    _comparison(ax, rows)
    trials = max((len(r.get("trial_values") or [0]) for r in rows.values()), default=1)
    step, ang = result.get("step"), result.get("step_angle")
    for k, (n, tr) in enumerate((n, traces[n]) for n in rows if n in traces):
        a = fig.add_subplot(gs[1 + k // cols, k % cols])
        a.set_gid(f"trace:{n}")
        angular = n.startswith("angular")
        move = (f"{step:g} {lu} step" if not angular and step is not None else
                f"{ang:g} {au} rotation" if angular and ang is not None else "step")
        _trace_panel(a, n, rows[n], tr, move, lu, au)
    head = (f"Table V emulated on the simulated '{name}' (distkin.control.table5): each "
            "worst-case output capability divided by our analysis (1 = analysis),\n"
            f"{trials} trial(s) per blocked row, 1 per free row (deterministic); every "
            "bar labelled with its value in its row's unit")
    if n_tr:
        head += ("\nbelow: the first trial of each row at its worst pose (lengths in "
                 f"{lu}, angles in {au}), time from the start of the smoothed step")
    fig.suptitle(head, fontsize=10, y=1 - 0.1 / height, va="top")
    return fig


def plot_table5(stem, result, traces=None, *, name="octo", length_unit="m",
                angle_unit="rad"):
    """Write ``STEM_comparison.png`` (module docstring) from the query's ``result``
    (its ``rows``: "unit", "emulated", "trial_values", "analysis", "paper_experiment",
    "paper_simulation", "pose" in the scene's ``length_unit`` and ``angle_unit``;
    ``step``, ``step_angle``) and the ``traces`` of :func:`run_table5` (row -> {"t",
    "value", "reading"?}; None: the top panel only).  Returns the paths."""
    import matplotlib.pyplot as plt
    fig = table5_figure(result, traces, name=name, length_unit=length_unit,
                        angle_unit=angle_unit)
    out = Path(f"{stem}_comparison.png")
    try:
        fig.savefig(out, dpi=100)
    finally:
        plt.close(fig)
    return [out]
