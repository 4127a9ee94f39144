"""The Fig. 3 analogue (Kühne et al.): the translational workspace at zero rotation with
the certified regular, singular, undecided and unreachable boxes marked.

The coordinates drawn are the ones the region varies (:func:`plot_axes`): its varying
positions, then its varying rotations, three at most (QA: a region varying rx alone, or
x alone, was drawn as four empty or zero-height panels).  Three of them give the layout
below; two give their plane and its σmin-margin map; one a strip chart along its axis
with the σmin bound per box; a single pose one panel with its verdict.

Only the boxes that contain a pose of the slice's rotation are drawn (for a 6-D region,
their projection onto x, y, z): zero rotation when the region contains it, else the
region's rotation nearest to zero (its fixed rotation when fixed), named in the title.  Four panels: a 3-D view of the non-regular boxes inside the
outline of the region; a section z = const and a section x = const (each at the level
crossed by the most non-regular boxes; the region's centre if all are regular), where
every box crossing the plane is drawn as a rectangle; and the σmin-margin map, the same
z section with every regular box coloured by its certified lower bound of σmin(Jx) (how
far the box is from a singularity; a log scale when the bounds span a decade or more,
else linear: :func:`sigma_norm`).  The paper's Fig. 3 draws the workspace
blue and the singularities green; here singular boxes are red so they cannot be
mistaken for either.  matplotlib is imported lazily, inside :func:`plot_certificate`.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np

from .boxes import REGULAR, SINGULAR, STATUS_NAMES, UNDECIDED, UNREACHABLE

__all__ = ["plot_certificate", "plot_axes", "COLOURS", "SIGMA_UNITS", "sigma_norm"]

#: status -> (colour, label); the paper's Fig. 3 draws the workspace blue and singularities
#: green: singular boxes are red here, so neither colour can be misread
COLOURS = {REGULAR: ("#9ecae1", "certified regular"),
           SINGULAR: ("#d62728", "certified singular (det Jx = 0 inside)"),
           UNDECIDED: ("#ff7f0e", "undecided at the resolution"),
           UNREACHABLE: ("#bdbdbd", "certified unreachable")}

_NAMES = ("x", "y", "z", "rx", "ry", "rz")
#: σmin(Jx)'s units as the certify_workspace report states them (QA IX 7): SI in every
#: scene, since σmin of columns of mixed units has no conversion to another length unit
SIGMA_UNITS = ("force columns 1-3 dimensionless, moment columns 4-6 in m, SI in a "
               "scene of any length unit")
_SIGMA_LABEL = "\n".join(textwrap.wrap(f"certified lower bound of σmin(Jx) [Jx L × 6: "
                                       f"{SIGMA_UNITS}]", 44))


def plot_axes(cert) -> tuple:
    """The coordinates (indices 0..5) the plot draws: the region's varying positions, then
    its varying rotations, three at most; () for a single pose."""
    vary = cert.vary
    return tuple(([k for k in vary if k < 3] + [k for k in vary if k >= 3])[:3])


class _Axes:
    """Scale factors and labels of the six coordinates in the scene's units."""

    def __init__(self, length_unit, angle_unit):
        from ..app.units import display_length
        lf, lu = display_length(length_unit, "mm")
        af, au = (180 / np.pi, "deg") if angle_unit == "deg" else (1.0, "rad")
        self.f = np.array([lf] * 3 + [af] * 3)
        self.unit = [lu] * 3 + [au] * 3
        self.lu = lu

    def label(self, k):
        return f"{_NAMES[k]} [{self.unit[k]}]"

    def value(self, k, v):
        return f"{_NAMES[k]} = {v * self.f[k]:.4g} {self.unit[k]}"


def _slice_point(cert) -> np.ndarray:
    """(6,): the slice through the coordinates not drawn: the region's centre in
    position, its rotation nearest to zero (:meth:`slice_rotation`)."""
    return np.concatenate([0.5 * (cert.lower[:3] + cert.upper[:3]), cert.slice_rotation()])


def _in_slice(lo, hi, plotted, point) -> np.ndarray:
    """(n,) bool: boxes containing ``point`` in every coordinate not drawn."""
    rest = [k for k in range(6) if k not in plotted]
    return np.all((lo[:, rest] <= point[rest]) & (hi[:, rest] >= point[rest]), axis=1)


def _section(ax, lo, hi, status, axis, value, dims, f):
    """Boxes crossing ``axis = value`` (every box when ``axis`` is None) drawn as
    rectangles over ``dims``, coloured by status; ``f`` (6,) the unit factors."""
    from matplotlib.patches import Rectangle
    cross = (np.ones(len(lo), bool) if axis is None else
             (lo[:, axis] <= value) & (hi[:, axis] >= value))
    i, j = dims
    for code in (REGULAR, UNREACHABLE, UNDECIDED, SINGULAR):
        sel = cross & (status == code)
        colour = COLOURS[code][0]
        for a, b in zip(lo[sel], hi[sel]):
            ax.add_patch(Rectangle((a[i] * f[i], a[j] * f[j]), (b[i] - a[i]) * f[i],
                                   (b[j] - a[j]) * f[j], facecolor=colour,
                                   edgecolor="white", linewidth=0.3))


def _busiest_level(lo, hi, status, axis, default):
    """The section level (box mid-levels along ``axis``) crossed by the most non-regular
    boxes; ``default`` if every box is regular."""
    bad = status != REGULAR
    if not bad.any():
        return default
    levels = np.unique(0.5 * (lo[bad, axis] + hi[bad, axis]))
    counts = [np.sum(bad & (lo[:, axis] <= v) & (hi[:, axis] >= v)) for v in levels]
    return float(levels[int(np.argmax(counts))])


def _frame(ax, cert, dims, ax_u):
    """Limits and labels of a panel over the coordinates ``dims`` (both varying); equal
    aspect for two positions of comparable extent."""
    i, j = dims
    f = ax_u.f
    ax.set_xlim(cert.lower[i] * f[i], cert.upper[i] * f[i])
    ax.set_ylim(cert.lower[j] * f[j], cert.upper[j] * f[j])
    wi, wj = cert.upper[i] - cert.lower[i], cert.upper[j] - cert.lower[j]
    if i < 3 and j < 3 and max(wi, wj) <= 10 * min(wi, wj):
        ax.set_aspect("equal")
    ax.set_xlabel(ax_u.label(i))
    ax.set_ylabel(ax_u.label(j))


def _sigma_boxes(cert, keep):
    """The regular boxes with their certified σmin bounds, after the tightening of
    :mod:`.tighten` when it ran (its final boxes: the classification's regular boxes,
    the weakest bisected); ``keep(lo, hi)`` selects the boxes drawn."""
    tb = cert.sigma_bound
    if tb is not None and len(tb.sigma):
        rc = keep(tb.lo, tb.hi) & (tb.sigma > 0)
        return tb.lo[rc], tb.hi[rc], tb.sigma[rc], "after bisecting the weakest boxes"
    rc = keep(cert.lo, cert.hi) & (cert.status == REGULAR) & (cert.sigma_lower > 0)
    return cert.lo[rc], cert.hi[rc], cert.sigma_lower[rc], "the classification's boxes"


def _log_scale(vmin: float, vmax: float) -> bool:
    """A log scale for σmin bounds spanning a decade or more (max/min >= 10), linear
    below: a log scale over 5.5e-2..5.58e-2 had one or two tick labels (QA)."""
    return vmin > 0 and vmax >= 10 * vmin


def sigma_norm(sig):
    """The colour norm of the σmin-margin map for the bounds ``sig`` (n,): log when they
    span a decade (:func:`_log_scale`), else linear."""
    from matplotlib import colors
    vmin = float(sig.min()) if sig.size else 1e-3
    vmax = float(sig.max()) if sig.size else 1.0
    vmax = max(vmax, vmin * 1.0001)
    return (colors.LogNorm(vmin=vmin, vmax=vmax) if _log_scale(vmin, vmax)
            else colors.Normalize(vmin=vmin, vmax=vmax))


def _margin_panel(ax, cert, lo, hi, st, dims, axis, level, ax_u):
    """σmin-margin map over ``dims``: the regular boxes crossing ``axis = level`` (every
    box of the slice when ``axis`` is None), coloured by the certified lower bound of
    σmin(Jx) (:func:`sigma_norm`: log over a decade or more, else linear); other boxes in
    their status colour."""
    from matplotlib import cm, colors
    from matplotlib.patches import Rectangle
    from matplotlib.ticker import ScalarFormatter
    import matplotlib
    plotted, point = plot_axes(cert), _slice_point(cert)

    def keep(a, b):
        m = _in_slice(a, b, plotted, point)
        return m if axis is None else m & (a[:, axis] <= level) & (b[:, axis] >= level)
    rlo, rhi, rsig, what = _sigma_boxes(cert, keep)
    norm, cmap, f = sigma_norm(rsig), matplotlib.colormaps["viridis"], ax_u.f
    i, j = dims
    for a, b, v in zip(rlo, rhi, rsig):
        ax.add_patch(Rectangle((a[i] * f[i], a[j] * f[j]), (b[i] - a[i]) * f[i],
                               (b[j] - a[j]) * f[j], facecolor=cmap(norm(v)),
                               edgecolor="white", linewidth=0.3))
    other = st != REGULAR
    _section(ax, lo[other], hi[other], st[other], axis, level, dims, f)
    _frame(ax, cert, dims, ax_u)
    where = "" if axis is None else f", section {ax_u.value(axis, level)}"
    ax.set_title(f"σmin margin{where}\n({what})", fontsize=9)
    cb = ax.figure.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax,
                            label=_SIGMA_LABEL)
    if not isinstance(norm, colors.LogNorm):      # no "+5.5e-2" offset above the ticks
        cb.ax.yaxis.set_major_formatter(ScalarFormatter(useOffset=False))


def _rotation_label(cert, angle_unit, plotted=(0, 1, 2)):
    """The title's words for the slice through the rotations not drawn (the region's
    rotation nearest to zero, :meth:`slice_rotation`); "" when every rotation is drawn."""
    ks = [k for k in range(3, 6) if k not in plotted]
    if not ks:
        return ""
    r0 = cert.slice_rotation()[[k - 3 for k in ks]]
    fixed = all(cert.upper[k] == cert.lower[k] for k in ks)
    names = ", ".join(_NAMES[k] for k in ks)
    zero = "zero rotation" if len(ks) == 3 else f"{names} = 0"
    if not r0.any():
        return zero if fixed else f"boxes containing {zero}, projected"
    f, u = (180 / np.pi, "°") if angle_unit == "deg" else (1.0, " rad")
    r = "(" + ", ".join(f"{x * f:.4g}" for x in r0) + f"){u}"
    what = f"rotation ({names})" if len(ks) == 3 else f"({names})"
    return (f"fixed {what} = {r}" if fixed else
            f"boxes containing the {what} = {r}, the region's nearest to zero, projected")


def _three(fig, cert, lo, hi, st, plotted, ax_u):
    """The Fig. 3 layout over three coordinates: a 3-D view of the non-regular boxes in
    the region's outline, two sections, the σmin-margin map."""
    f, (p, q, r) = ax_u.f, plotted
    L0, U0 = cert.lower, cert.upper
    centre = 0.5 * (L0 + U0)
    ax = fig.add_subplot(1, 4, 1, projection="3d")
    for code in (UNDECIDED, SINGULAR, UNREACHABLE):
        sel = st == code
        if sel.any():
            a, b = lo[sel] * f, hi[sel] * f
            ax.bar3d(a[:, p], a[:, q], a[:, r], b[:, p] - a[:, p], b[:, q] - a[:, q],
                     b[:, r] - a[:, r], color=COLOURS[code][0], alpha=0.5, shade=True)
    xs, ys, zs = ([L0[k] * f[k], U0[k] * f[k]] for k in plotted)    # the region's outline
    for y in ys:
        for z in zs:
            ax.plot(xs, [y, y], [z, z], color="tab:blue", lw=0.8)
    for x in xs:
        for z in zs:
            ax.plot([x, x], ys, [z, z], color="tab:blue", lw=0.8)
        for y in ys:
            ax.plot([x, x], [y, y], zs, color="tab:blue", lw=0.8)
    ax.set_xlabel(ax_u.label(p))
    ax.set_ylabel(ax_u.label(q))
    ax.set_zlabel(ax_u.label(r))
    ax.set_title("non-regular boxes (blue: region outline)")
    for i, (axis, dims) in enumerate(((r, (p, q)), (p, (q, r)))):
        a2 = fig.add_subplot(1, 4, 2 + i)
        level = _busiest_level(lo, hi, st, axis, centre[axis])
        _section(a2, lo, hi, st, axis, level, dims, f)
        _frame(a2, cert, dims, ax_u)
        a2.set_title(f"section {ax_u.value(axis, level)}")
    level = _busiest_level(lo, hi, st, r, centre[r])
    _margin_panel(fig.add_subplot(1, 4, 4), cert, lo, hi, st, (p, q), r, level, ax_u)


def _two(fig, cert, lo, hi, st, plotted, ax_u):
    """A plane: every box of the slice over the two coordinates, and the σmin map."""
    a1 = fig.add_subplot(1, 2, 1)
    _section(a1, lo, hi, st, None, None, plotted, ax_u.f)
    _frame(a1, cert, plotted, ax_u)
    a1.set_title("boxes by status")
    _margin_panel(fig.add_subplot(1, 2, 2), cert, lo, hi, st, plotted, None, None, ax_u)


def _one(fig, cert, lo, hi, st, plotted, ax_u):
    """A strip chart along the one varying coordinate: the boxes by status (one row per
    status) and the certified σmin bound of each regular box."""
    from matplotlib.patches import Rectangle
    k, f = plotted[0], ax_u.f[plotted[0]]
    codes = (REGULAR, SINGULAR, UNDECIDED, UNREACHABLE)
    a1 = fig.add_subplot(1, 2, 1)
    for row, code in enumerate(codes):
        for a, b in zip(lo[st == code, k], hi[st == code, k]):
            a1.add_patch(Rectangle((a * f, row - 0.4), (b - a) * f, 0.8,
                                   facecolor=COLOURS[code][0], edgecolor="white", lw=0.3))
    a1.set_xlim(cert.lower[k] * f, cert.upper[k] * f)
    a1.set_ylim(-0.6, len(codes) - 0.4)
    a1.set_yticks(range(len(codes)), [STATUS_NAMES[c] for c in codes])
    a1.set_xlabel(ax_u.label(k))
    a1.set_title(f"boxes along {_NAMES[k]} by status (status: no unit)")
    a2 = fig.add_subplot(1, 2, 2)
    point = _slice_point(cert)
    rlo, rhi, rsig, what = _sigma_boxes(cert, lambda a, b: _in_slice(a, b, plotted, point))
    a2.set_xlim(cert.lower[k] * f, cert.upper[k] * f)
    a2.set_xlabel(ax_u.label(k))
    a2.set_ylabel(_SIGMA_LABEL, fontsize=8)
    if rsig.size:
        a2.hlines(rsig, rlo[:, k] * f, rhi[:, k] * f, colors="tab:green", lw=2)
        lo_s, hi_s = float(rsig.min()), float(rsig.max())
        if _log_scale(lo_s, hi_s):
            a2.set_yscale("log")
            a2.set_ylim(lo_s / 2, hi_s * 2)
        else:
            pad = 0.1 * max(hi_s - lo_s, 1e-3 * hi_s)
            a2.set_ylim(lo_s - pad, hi_s + pad)
        a2.set_title(f"σmin margin per box ({what})", fontsize=9)
    else:
        a2.set_yticks([])
        a2.text(0.5, 0.5, "no regular box: no σmin bound", ha="center", va="center",
                transform=a2.transAxes)
        a2.set_title("σmin margin", fontsize=9)


def _point(fig, cert, st, ax_u):
    """A single pose: its coordinates and its verdict, in its status's colour."""
    ax = fig.add_subplot(1, 1, 1)
    ax.set_axis_off()
    code = int(st[0]) if len(st) else UNDECIDED
    pose = ", ".join(ax_u.value(k, cert.lower[k]) for k in range(6))
    sig = cert.summary()["sigma_lower_min"]
    said = (f"\nσmin(Jx) >= {sig:.3g} (certified; Jx L × 6:\n{SIGMA_UNITS})"
            if sig is not None else "")
    ax.text(0.5, 0.5, f"single pose: {pose}\n{STATUS_NAMES[code]}: "
            f"{COLOURS[code][1]}{said}", ha="center", va="center", fontsize=11,
            transform=ax.transAxes, bbox={"facecolor": COLOURS[code][0], "pad": 12})


def plot_certificate(cert, stem, *, length_unit: str = "mm", angle_unit: str = "deg") -> Path:
    """Write ``STEM_certified_workspace.png``; returns its path.

    Parameters
    ----------
    cert : WorkspaceCertificate
    stem : path
        Output path without suffix.
    length_unit : str
        Position axes' unit (m, mm, cm, km).
    angle_unit : str
        Rotation axes' unit (deg, rad).
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    ax_u = _Axes(length_unit, angle_unit)
    plotted = plot_axes(cert)
    zr = _in_slice(cert.lo, cert.hi, plotted, _slice_point(cert))
    lo, hi, st = cert.lo[zr], cert.hi[zr], cert.status[zr]
    s = cert.summary()
    rot = _rotation_label(cert, angle_unit, plotted)
    drawn = ", ".join(_NAMES[k] for k in plotted)
    if len(plotted) == 3:
        fig = plt.figure(figsize=(20, 5))
        _three(fig, cert, lo, hi, st, plotted, ax_u)
        what = ("Fig. 3 analogue" if plotted == (0, 1, 2) else f"over {drawn}")
    elif plotted:
        fig = plt.figure(figsize=(13, 5))
        (_two if len(plotted) == 2 else _one)(fig, cert, lo, hi, st, plotted, ax_u)
        what = f"over {drawn}, the coordinate{'s' if len(plotted) > 1 else ''} it varies"
    else:
        fig = plt.figure(figsize=(13, 4))
        _point(fig, cert, st, ax_u)
        what = "a single pose"
    head = f"{cert.mechanism.name}: certified workspace ({(rot + '; ') if rot else ''}{what})"
    if plotted:
        head += (f" — regular {100 * s['regular_fraction']:.1f} %, singular "
                 f"{100 * s['singular_fraction']:.1f} %, undecided "
                 f"{100 * s['undecided_fraction']:.1f} % of the region's volume")
    fig.suptitle(head)
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
