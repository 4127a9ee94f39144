"""The Fig. 3 analogue (Kühne et al.): the translational workspace at zero rotation with
the certified regular, singular, undecided and unreachable boxes marked.

Only the boxes that contain a pose of the slice's rotation are drawn (for a 6-D region,
their projection onto x, y, z): zero rotation when the region contains it, else the
region's rotation nearest to zero (its fixed rotation when fixed), named in the title.  Four panels: a 3-D view of the non-regular boxes inside the
outline of the region; a section z = const and a section x = const (each at the level
crossed by the most non-regular boxes; the region's centre if all are regular), where
every box crossing the plane is drawn as a rectangle; and the σmin-margin map, the same
z section with every regular box coloured by its certified lower bound of σmin(Jx) (how
far the box is from a singularity, log scale).  The paper's Fig. 3 draws the workspace
blue and the singularities green; here singular boxes are red so they cannot be
mistaken for either.  matplotlib is imported lazily, inside :func:`plot_certificate`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .boxes import REGULAR, SINGULAR, UNDECIDED, UNREACHABLE

__all__ = ["plot_certificate", "COLOURS"]

#: status -> (colour, label); the paper's Fig. 3 draws the workspace blue and singularities
#: green: singular boxes are red here, so neither colour can be misread
COLOURS = {REGULAR: ("#9ecae1", "certified regular"),
           SINGULAR: ("#d62728", "certified singular (det Jx = 0 inside)"),
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


def _margin_panel(ax, cert, lo, hi, st, centre, f, lu):
    """σmin-margin map: the regular boxes crossing the busiest z section, coloured by the
    certified lower bound of σmin(Jx) (log scale); other boxes in their status colour.
    After the tightening of :mod:`.tighten` its final boxes (the classification's regular
    boxes, the weakest of them bisected) are drawn with their raised bounds."""
    from matplotlib import cm, colors
    from matplotlib.patches import Rectangle
    level = _busiest_level(lo, hi, st, 2, centre[2])
    cross = (lo[:, 2] <= level) & (hi[:, 2] >= level)
    tb = cert.sigma_bound
    if tb is not None and len(tb.sigma):
        r0 = cert.slice_rotation()
        zr = np.all((tb.lo[:, 3:] <= r0) & (tb.hi[:, 3:] >= r0), axis=1)
        rc = zr & (tb.lo[:, 2] <= level) & (tb.hi[:, 2] >= level) & (tb.sigma > 0)
        rlo, rhi, rsig = tb.lo[rc], tb.hi[rc], tb.sigma[rc]
        what = "after bisecting the weakest boxes"
    else:
        sig = cert.sigma_lower[cert.at_rotation(cert.slice_rotation())]
        rc = cross & (st == REGULAR) & (sig > 0)
        rlo, rhi, rsig = lo[rc], hi[rc], sig[rc]
        what = "the classification's boxes"
    vmin = float(rsig.min()) if rsig.size else 1e-3
    vmax = float(rsig.max()) if rsig.size else 1.0
    norm = colors.LogNorm(vmin=vmin, vmax=max(vmax, vmin * 1.0001))
    import matplotlib
    cmap = matplotlib.colormaps["viridis"]
    for a, b, v in zip(rlo, rhi, rsig):
        ax.add_patch(Rectangle((a[0] * f, a[1] * f), (b[0] - a[0]) * f, (b[1] - a[1]) * f,
                               facecolor=cmap(norm(v)), edgecolor="white", linewidth=0.3))
    other = st != REGULAR
    _section(ax, lo[other], hi[other], st[other], 2, level, (0, 1), f)
    ax.set_xlim(cert.lower[0] * f, cert.upper[0] * f)
    ax.set_ylim(cert.lower[1] * f, cert.upper[1] * f)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x [{lu}]")
    ax.set_ylabel(f"y [{lu}]")
    ax.set_title(f"σmin margin, section z = {level * f:.4g} {lu}\n({what})", fontsize=9)
    sm = cm.ScalarMappable(norm=norm, cmap=cmap)
    # σmin of Jx has mixed units, as the certify_workspace report states them (QA IX 7)
    ax.figure.colorbar(sm, ax=ax, label="certified lower bound of σmin(Jx)\n[Jx L × 6: "
                       "force columns 1-3 dimensionless, moment columns 4-6 in m]")


def _rotation_label(cert, angle_unit):
    """The title's words for the slice's rotation (:meth:`slice_rotation`)."""
    r0 = cert.slice_rotation()
    fixed = np.all(cert.upper[3:] == cert.lower[3:])
    if not r0.any():
        return "zero rotation" if fixed else "boxes containing zero rotation, projected"
    f, u = (180 / np.pi, "°") if angle_unit == "deg" else (1.0, " rad")
    r = "(" + ", ".join(f"{x * f:.4g}" for x in r0) + f"){u}"
    return (f"fixed rotation (rx, ry, rz) = {r}" if fixed else
            f"boxes containing the rotation (rx, ry, rz) = {r}, the region's nearest to zero, "
            "projected")


def plot_certificate(cert, stem, *, length_unit: str = "mm", angle_unit: str = "deg") -> Path:
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
    zr = cert.at_rotation(cert.slice_rotation())
    lo, hi, st = cert.lo[zr], cert.hi[zr], cert.status[zr]
    L0, U0 = cert.lower, cert.upper
    centre = 0.5 * (L0 + U0)
    fig = plt.figure(figsize=(20, 5))
    ax = fig.add_subplot(1, 4, 1, projection="3d")
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
        a2 = fig.add_subplot(1, 4, 2 + i)
        level = _busiest_level(lo, hi, st, axis, centre[axis])
        _section(a2, lo, hi, st, axis, level, dims, f)
        a2.set_xlim(L0[dims[0]] * f, U0[dims[0]] * f)
        a2.set_ylim(L0[dims[1]] * f, U0[dims[1]] * f)
        a2.set_aspect("equal")
        a2.set_xlabel(f"{'xyz'[dims[0]]} [{lu}]")
        a2.set_ylabel(f"{'xyz'[dims[1]]} [{lu}]")
        a2.set_title(f"section {name} = {level * f:.4g} {lu}")
    _margin_panel(fig.add_subplot(1, 4, 4), cert, lo, hi, st, centre, f, lu)
    s = cert.summary()
    rot = _rotation_label(cert, angle_unit)
    fig.suptitle(f"{cert.mechanism.name}: certified workspace ({rot}; Fig. 3 analogue) — "
                 f"regular {100 * s['regular_fraction']:.1f} %, singular "
                 f"{100 * s['singular_fraction']:.1f} %, undecided "
                 f"{100 * s['undecided_fraction']:.1f} % of the region's volume")
    labels = dict(COLOURS)
    if s["budget_exhausted"]:           # QA F4: not all of them at the resolution
        labels[UNDECIDED] = (COLOURS[UNDECIDED][0],
                             "undecided (at the resolution, or the box budget spent)")
    fig.legend(handles=[Patch(color=c, label=t) for c, t in labels.values()],
               loc="lower center", ncol=4)
    fig.tight_layout(rect=(0, 0.1, 1, 0.93))      # the legend's row below the x labels
    out = Path(str(stem) + "_certified_workspace.png")
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out
