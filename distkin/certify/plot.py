"""The Fig. 3 analogue (Kühne et al.): the translational workspace at zero rotation with
the certified regular, singular, undecided and unreachable boxes marked.

Only the boxes that contain a pose of zero rotation are drawn (for a 6-D region, their
projection onto x, y, z).  Three panels: a 3-D view of the non-regular boxes inside the
outline of the region, and a section z = const and a section x = const (each at the level
crossed by the most non-regular boxes; the region's centre if all are regular), where
every box crossing the plane is drawn as a rectangle.  matplotlib is imported
lazily, inside :func:`plot_certificate`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .boxes import REGULAR, SINGULAR, UNDECIDED, UNREACHABLE

__all__ = ["plot_certificate", "COLOURS"]

#: status -> (colour, label); the paper's Fig. 3 draws the workspace blue, singularities green
COLOURS = {REGULAR: ("#9ecae1", "certified regular"),
           SINGULAR: ("#2ca02c", "certified singular (det Jx = 0 inside)"),
           UNDECIDED: ("#ff7f0e", "undecided at the resolution"),
           UNREACHABLE: ("#bdbdbd", "certified unreachable")}

_SCALE = {"m": 1.0, "mm": 1e3, "cm": 1e2, "km": 1e-3}


def _section(ax, lo, hi, status, axis, value, dims, f):
    from matplotlib.patches import Rectangle
    cross = (lo[:, axis] <= value) & (hi[:, axis] >= value)
    for code in (REGULAR, UNREACHABLE, UNDECIDED, SINGULAR):
        sel = cross & (status == code)
        colour = COLOURS[code][0]
        for a, b in zip(lo[sel], hi[sel]):
            ax.add_patch(Rectangle((a[dims[0]] * f, a[dims[1]] * f),
                                   (b[dims[0]] - a[dims[0]]) * f, (b[dims[1]] - a[dims[1]]) * f,
                                   facecolor=colour, edgecolor="white", linewidth=0.3))


def _busiest_level(lo, hi, status, axis, default):
    """The section level (box mid-levels along ``axis``) crossed by the most non-regular
    boxes; ``default`` if every box is regular."""
    bad = status != REGULAR
    if not bad.any():
        return default
    levels = np.unique(0.5 * (lo[bad, axis] + hi[bad, axis]))
    counts = [np.sum(bad & (lo[:, axis] <= v) & (hi[:, axis] >= v)) for v in levels]
    return float(levels[int(np.argmax(counts))])


def plot_certificate(cert, stem, *, length_unit: str = "mm") -> Path:
    """Write ``STEM_certified_workspace.png``; returns its path.

    Parameters
    ----------
    cert : WorkspaceCertificate
    stem : path
        Output path without suffix.
    length_unit : str
        Axis unit (m, mm, cm).
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    f = _SCALE.get(length_unit, 1e3)
    lu = length_unit if length_unit in _SCALE else "mm"
    zr = cert.at_zero_rotation()
    lo, hi, st = cert.lo[zr], cert.hi[zr], cert.status[zr]
    L0, U0 = cert.lower, cert.upper
    centre = 0.5 * (L0 + U0)
    fig = plt.figure(figsize=(15, 5))
    ax = fig.add_subplot(1, 3, 1, projection="3d")
    for code in (UNDECIDED, SINGULAR, UNREACHABLE):
        sel = st == code
        if sel.any():
            a, b = lo[sel] * f, hi[sel] * f
            ax.bar3d(a[:, 0], a[:, 1], a[:, 2], b[:, 0] - a[:, 0], b[:, 1] - a[:, 1],
                     b[:, 2] - a[:, 2], color=COLOURS[code][0], alpha=0.5, shade=True)
    # outline of the region
    xs, ys, zs = ([L0[k] * f, U0[k] * f] for k in range(3))
    for y in ys:
        for z in zs:
            ax.plot(xs, [y, y], [z, z], color="tab:blue", lw=0.8)
    for x in xs:
        for z in zs:
            ax.plot([x, x], ys, [z, z], color="tab:blue", lw=0.8)
    for x in xs:
        for y in ys:
            ax.plot([x, x], [y, y], zs, color="tab:blue", lw=0.8)
    ax.set_xlabel(f"x [{lu}]")
    ax.set_ylabel(f"y [{lu}]")
    ax.set_zlabel(f"z [{lu}]")
    ax.set_title("non-regular boxes (blue: region outline)")
    for i, (axis, dims, name) in enumerate(((2, (0, 1), "z"), (0, (1, 2), "x"))):
        a2 = fig.add_subplot(1, 3, 2 + i)
        level = _busiest_level(lo, hi, st, axis, centre[axis])
        _section(a2, lo, hi, st, axis, level, dims, f)
        a2.set_xlim(L0[dims[0]] * f, U0[dims[0]] * f)
        a2.set_ylim(L0[dims[1]] * f, U0[dims[1]] * f)
        a2.set_aspect("equal")
        a2.set_xlabel(f"{'xyz'[dims[0]]} [{lu}]")
        a2.set_ylabel(f"{'xyz'[dims[1]]} [{lu}]")
        a2.set_title(f"section {name} = {level * f:.4g} {lu}")
    s = cert.summary()
    rot = "zero rotation" if np.all(cert.upper[3:] == cert.lower[3:]) else \
        "boxes containing zero rotation, projected"
    fig.suptitle(f"{cert.mechanism.name}: certified workspace ({rot}; Fig. 3 analogue) — "
                 f"regular {100 * s['regular_fraction']:.1f} %, singular "
                 f"{100 * s['singular_fraction']:.1f} %, undecided "
                 f"{100 * s['undecided_fraction']:.1f} % of the region's volume")
    fig.legend(handles=[Patch(color=c, label=t) for c, t in COLOURS.values()],
               loc="lower center", ncol=4)
    fig.tight_layout(rect=(0, 0.07, 1, 0.93))
    out = Path(str(stem) + "_certified_workspace.png")
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out
