"""Figures of the study, like Kühne et al. Figs. 5, 6 and 7 (matplotlib, imported lazily).

Lengths are drawn in the scene's declared unit (``length_unit``: m, mm, cm, km; the
arrays passed in are SI, docs/design.md "Conventions").

* :func:`plot_workspace` (Fig. 5): the translational workspace at zero rotation (blue)
  and the desired cube (red, the paper's 150 mm for its devices), with the dexterous
  positions of the sweep, on equal axis scales;
* :func:`plot_plane` (Fig. 6): the worst case over all orientations of each output
  capability at every (x, y) of the plane z ≈ home (the paper: 0.30 m), each panel on
  the colour scale :func:`colour_scale` chooses (constant, log, clipped or linear);
* :func:`plot_force_polytope` (Fig. 7): the force polytope at zero torque at one pose
  with the sphere of the worst-case force, tangent to its nearest facet;
* :func:`plot_table3_bars`, :func:`plot_table4_bars`: Tables III and IV as dots and
  min..max ranges, ours beside the paper's where the paper has the device;
* :func:`plot_design_sweep`: the GII of the Table I sweep over l2 × β, one panel per
  (γ, ld), with the paper's design and our optimum marked.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..app.units import display_length as length_unit_of
from ..numfmt import sig

__all__ = ["plot_workspace", "plot_plane", "plot_force_polytope", "force_slice_polytope",
           "plot_table3_bars", "plot_table4_bars", "plot_design_sweep", "colour_scale",
           "CONSTANT_RTOL", "CLIP_PERCENTILES"]


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _points_3d(ax, P, **kw):
    if len(P):
        ax.scatter(P[:, 0], P[:, 1], P[:, 2], **kw)


def plot_workspace(path, label, reach_pts, cube_half, z0, dexterous_pts=None, *,
                   length_unit="mm"):
    """Fig. 5.  ``reach_pts`` (n, 3) positions on the boundary of the workspace at zero
    rotation (m); ``dexterous_pts`` the dexterous positions of the sweep grid; the cube
    of half-width ``cube_half`` (m) about ``z0``: a height (centre (0, 0, z0)) or a
    centre (3,) (m).  Drawn in the scene's ``length_unit`` (m, mm, cm, km) with equal
    scales on the three axes (``set_box_aspect`` from the data's ranges: a cube looks
    like a cube)."""
    plt = _plt()
    f, lu = length_unit_of(length_unit)
    fig = plt.figure(figsize=(7.5, 6.5))
    ax = fig.add_subplot(projection="3d")
    P = np.asarray(reach_pts, dtype=float).reshape(-1, 3) * f
    _points_3d(ax, P, s=7, c="tab:blue", alpha=0.55, depthshade=False, edgecolors="none",
               label="boundary of the workspace at zero rotation")
    D = (np.zeros((0, 3)) if dexterous_pts is None
         else np.asarray(dexterous_pts, dtype=float).reshape(-1, 3) * f)
    _points_3d(ax, D, s=10, c="tab:green", alpha=0.8, depthshade=False,
               label="dexterous (eq. 17) on the sweep grid")
    h = cube_half * f
    cx, cy, cz = (np.array([0.0, 0.0, z0]) if np.ndim(z0) == 0 else np.asarray(z0)) * f
    c = np.array([[x, y, zz] for x in (cx - h, cx + h) for y in (cy - h, cy + h)
                  for zz in (cz - h, cz + h)])
    for i in range(8):
        for j in range(i + 1, 8):
            if np.sum(c[i] != c[j]) == 1:
                ax.plot(*zip(c[i], c[j]), color="tab:red", lw=1.5)
    every = np.vstack([P, D, c])
    lo, hi = every.min(axis=0), every.max(axis=0)
    span = np.maximum(hi - lo, 1e-12 * max(1.0, float(np.abs(every).max())))
    mid = 0.5 * (lo + hi)
    for setter, m, w in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid, span):
        setter(m - 0.5 * w, m + 0.5 * w)
    ax.set_box_aspect(tuple(span))            # equal scales: one unit is one unit long
    ax.set_xlabel(f"x [{lu}]")
    ax.set_ylabel(f"y [{lu}]")
    ax.set_zlabel(f"z [{lu}]")
    ax.set_title(f"{label}: workspace (blue) and desired {sig(2 * h)} {lu} cube (red)")
    ax.legend(loc="upper left", fontsize=8)
    out = Path(str(path) + "_fig5_workspace.png")
    fig.savefig(out, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return out


#: a panel whose values spread by at most this, relative to their magnitude, is drawn
#: as one colour and labelled "constant = ..." (its differences are rounding, not a map)
CONSTANT_RTOL = 1e-6
#: the percentiles of a clipped colour scale (when the extremes take over the scale)
CLIP_PERCENTILES = (2.0, 98.0)


def colour_scale(V, accuracy=0.0):
    """How :func:`plot_plane` colours the finite values ``V`` of one panel.

    Returns ``(kind, norm_args, words)``: ``kind`` "constant" (every value within
    :data:`CONSTANT_RTOL` relative, or within ``accuracy`` (the quantity's unit), of each
    other: no map, the value in words), "log" (positive values whose 2nd..98th
    percentiles span two decades or more), "clipped" (the extremes take more than 4 × the
    2nd..98th percentile range: a near-singular cell would flatten every other cell; the
    scale is clipped to that range and the colour bar extended) or "linear";
    ``norm_args`` (vmin, vmax) and ``words`` the colour bar's note."""
    v = np.asarray(V, dtype=float)
    v = v[np.isfinite(v)]
    if not v.size:
        return "empty", (0.0, 1.0), "no reachable position"
    lo, hi = float(v.min()), float(v.max())
    if hi - lo <= max(CONSTANT_RTOL * max(abs(lo), abs(hi)), float(accuracy)):
        return "constant", (lo, hi), f"constant = {sig(0.5 * (lo + hi), 7)}"
    # "higher"/"lower": on a small plane (25 cells) the percentiles leave out at least
    # the one extreme cell at either end, rather than interpolate towards it
    p_lo = float(np.percentile(v, CLIP_PERCENTILES[0], method="higher"))
    p_hi = float(np.percentile(v, CLIP_PERCENTILES[1], method="lower"))
    if lo > 0 and p_hi >= 100 * p_lo:
        return "log", (lo, hi), "log scale"
    if hi - lo > 4 * (p_hi - p_lo) and p_hi > p_lo:
        a, b = CLIP_PERCENTILES
        return "clipped", (p_lo, p_hi), (f"linear, clipped to the {a:g}..{b:g}th percentile; "
                                         f"all {sig(lo)}..{sig(hi)}")
    return "linear", (lo, hi), ""


def plot_plane(path, label, xs, ys, z, panels, rotation_deg, *, length_unit="mm"):
    """Fig. 6.  ``panels``: list of (title, unit, array (len(xs), len(ys))[, accuracy])
    (``xs``, ``ys``, ``z`` in m, drawn in the scene's ``length_unit``).  Each panel's
    colour scale is chosen by :func:`colour_scale` (constant, log, clipped or linear; the
    colour bar says which) and its ticks carry no offset (a "+2.8867e1" above ticks of
    0.0005 read as structure)."""
    plt = _plt()
    from matplotlib import colors
    from matplotlib.ticker import ScalarFormatter
    f, lu = length_unit_of(length_unit)
    fig, axes = plt.subplots(2, 3, figsize=(13, 7.5))
    X, Y = np.meshgrid(np.asarray(xs) * f, np.asarray(ys) * f, indexing="ij")
    for ax, (title, unit, V, *acc) in zip(axes.ravel(), panels):
        V = np.where(np.isfinite(V), V, np.nan)
        kind, (vmin, vmax), words = colour_scale(V, acc[0] if acc else 0.0)
        if kind == "constant":
            ax.pcolormesh(X, Y, np.where(np.isfinite(V), 0.5, np.nan), shading="nearest",
                          cmap="viridis", vmin=0.0, vmax=1.0)
            ax.set_title(f"{title}\n{words} {unit}", fontsize=10)
        else:
            norm = (colors.LogNorm(vmin, vmax) if kind == "log"
                    else colors.Normalize(vmin, vmax))
            m = ax.pcolormesh(X, Y, V, shading="nearest", cmap="viridis", norm=norm)
            cb = fig.colorbar(m, ax=ax, label=f"{unit}" + (f" ({words})" if words else ""),
                              extend="both" if kind == "clipped" else "neither")
            if kind != "log":
                fmt = ScalarFormatter(useOffset=False)
                cb.ax.yaxis.set_major_formatter(fmt)
            ax.set_title(title, fontsize=10)
        ax.set_xlabel(f"x [{lu}]")
        ax.set_ylabel(f"y [{lu}]")
        ax.set_aspect("equal")
    fig.suptitle(f"{label}: worst-case output capabilities at z = {sig(z * f)} {lu}, "
                 f"rotations ±{rotation_deg:.0f}° about all axes")
    fig.tight_layout()
    out = Path(str(path) + "_fig6_plane.png")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def force_slice_polytope(Gw, limit):
    """Vertices and hull of the force polytope at zero torque of one pose.

    ``Gw`` (6, L) = Jᵀ, limits ±``limit`` (a number or (L,): per leg, N·m or N).  Returns (vertices (n, 3), hull simplices,
    worst-case radius) from the zonotope's half-spaces (:mod:`.zonotope`).
    """
    from scipy.spatial import ConvexHull, HalfspaceIntersection
    from .zonotope import _facets
    L = Gw.shape[1]
    n, h, _ = _facets(Gw[None], np.zeros((1, L)),
                      np.broadcast_to(np.asarray(limit, dtype=float), (1, L)).copy())
    nS = n[0][:, :3]
    keep = np.linalg.norm(nS, axis=1) > 1e-12 * np.linalg.norm(n[0], axis=1)
    A = np.vstack([nS[keep], -nS[keep]])
    b = np.concatenate([h[0][keep], h[0][keep]])
    radius = float(np.min(b / np.linalg.norm(A, axis=1)))
    hs = HalfspaceIntersection(np.hstack([A, -b[:, None]]), np.zeros(3))
    V = hs.intersections
    hull = ConvexHull(V)
    return V, hull.simplices, radius


def plot_force_polytope(path, label, Gw, limit, pose, *, length_unit="mm"):
    """Fig. 7: the force polytope (N) at zero torque and the inscribed sphere; the pose
    (m, rad) named in the scene's ``length_unit`` and degrees, the worst case with
    significant digits (not "0.00 N" for 6.2e-05 N)."""
    plt = _plt()
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection
    V, simp, radius = force_slice_polytope(Gw, limit)
    f, lu = length_unit_of(length_unit)
    fig = plt.figure(figsize=(7, 6))
    ax = fig.add_subplot(projection="3d")
    ax.add_collection3d(Poly3DCollection(V[simp], alpha=0.25, facecolor="tab:blue",
                                         edgecolor="k", linewidths=0.3))
    u, v = np.mgrid[0:2 * np.pi:30j, 0:np.pi:15j]
    ax.plot_surface(radius * np.cos(u) * np.sin(v), radius * np.sin(u) * np.sin(v),
                    radius * np.cos(v), color="grey", alpha=0.6)
    lim = np.abs(V).max()
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_zlim(-lim, lim)
    ax.set_xlabel("fx [N]")
    ax.set_ylabel("fy [N]")
    ax.set_zlabel("fz [N]")
    p = np.asarray(pose)
    ax.set_title(f"{label}: force polytope at zero torque, worst case {sig(radius)} N\n"
                 f"pose ({', '.join(sig(x * f) for x in p[:3])}) {lu}, "
                 f"({', '.join(sig(np.degrees(x)) for x in p[3:])})°", fontsize=9)
    out = Path(str(path) + "_fig7_force_polytope.png")
    fig.savefig(out, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return out


def _log_axis(values) -> bool:
    """A log axis for a panel whose positive values span two decades or more; else a
    linear one (the values are dots, not bars: no baseline to choose)."""
    v = np.asarray([x for x in values if x is not None and np.isfinite(x) and x > 0])
    return v.size > 0 and float(v.max()) >= 100 * float(v.min())


def _zero_marks(ax, xs, raw, color):
    """A "0" at the foot of a log axis (or beside the dot on a linear one) for each value
    of exactly 0 (the paper's 0.00 minima of Ergin's device, a singular pose on its grid,
    QA IX 7)."""
    from matplotlib.transforms import blended_transform_factory
    log = ax.get_yscale() == "log"
    tr = blended_transform_factory(ax.transData, ax.transAxes) if log else ax.transData
    for xv, v in zip(xs, raw):
        if v is not None and v == 0:
            ax.text(xv, 0.01 if log else 0.0, "0", transform=tr, ha="center",
                    va="bottom", fontsize=7, fontweight="bold", color=color)


def _drawn(v):
    """A value as the panel draws it: NaN for None/non-finite (nothing), else itself."""
    return np.nan if v is None or not np.isfinite(v) else float(v)


def _range_panel(ax, x, series, log):
    """Dots for each (offset, lows, highs, colour, name) of ``series`` at ``x``: a
    vertical line from min to max with a circle at the min and a triangle at the max
    (one dot when there is no max); a device without a value gets nothing."""
    handles = {}
    for off, lows, highs, colour, name in series:
        xs = x + off
        lo = np.array([_drawn(v) for v in lows])
        if log:
            lo = np.where(lo > 0, lo, np.nan)
        if not np.isfinite(lo).any() and all(v != 0 for v in lows if v is not None):
            continue                          # no value of this series in this panel
        h = ax.plot(xs, lo, "o", color=colour, ms=6, ls="none")[0]
        handles[f"{name} min" if highs is not None else name] = h
        if highs is not None:
            hi = np.array([_drawn(v) for v in highs])
            if log:
                hi = np.where(hi > 0, hi, np.nan)
            ax.vlines(xs, lo, hi, color=colour, lw=2, alpha=0.6)
            handles[f"{name} max"] = ax.plot(xs, hi, "^", color=colour, ms=7, ls="none",
                                             mfc="white")[0]
        _zero_marks(ax, xs, lows, colour)
    return handles


def _has_paper(summaries, get) -> bool:
    return any(get(s) is not None for s in summaries)


def plot_table3_bars(path, summaries):
    """Table III as a range plot: per row and device, our min..max (blue: circle = min,
    triangle = max) beside the paper's (orange) where the paper has the device (Kühne et
    al. Table III); a log axis only when a row spans two decades (a value of exactly 0,
    e.g. the paper's 0.00 minima for Ergin's device, is marked "0" at its foot)."""
    from .study import CAPABILITIES, SENSITIVITIES
    plt = _plt()
    rows = [(c[0], c[1], c[2]) for c in CAPABILITIES] + [(s[0], s[1], s[2])
                                                         for s in SENSITIVITIES]
    fig, axes = plt.subplots(2, 5, figsize=(22, 8.5))
    labels = [s["label"] for s in summaries]
    x = np.arange(len(labels), dtype=float)
    handles, zeros = {}, False
    for ax, (q, title, unit) in zip(axes.ravel(), rows):
        get = [lambda s, k=k: s["table"][q].get(k)
               for k in ("min", "max", "paper_min", "paper_max")]
        vals = [g(s) for g in get for s in summaries]
        if _log_axis(vals):
            ax.set_yscale("log")
        zeros |= any(v == 0 for v in vals if v is not None)
        paper = _has_paper(summaries, get[2])
        series = [(-0.12 if paper else 0.0, [get[0](s) for s in summaries],
                   [get[1](s) for s in summaries], "tab:blue", "ours")]
        if paper:
            series.append((0.12, [get[2](s) for s in summaries],
                           [get[3](s) for s in summaries], "tab:orange", "paper"))
        handles.update(_range_panel(ax, x, series, ax.get_yscale() == "log"))
        ax.set_xticks(x)
        ax.set_xticklabels(labels, rotation=30, ha="right", fontsize=8)
        ax.set_xlim(-0.5, len(labels) - 0.5)
        ax.grid(axis="y", alpha=0.3)
        # the devices' own units (a sensitivity's follow the actuators: m/rad or m/m)
        units = sorted({s["table"][q].get("unit", unit) for s in summaries}) or [unit]
        ax.set_title(f"{title} [{' | '.join(units)}]", fontsize=9)
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=len(handles),
               fontsize=9)
    papers = any(_has_paper(summaries, lambda s, q=q: s["table"][q].get("paper_min"))
                 for q, _, _ in rows)
    head = (f"Table III analogue of {', '.join(labels)}: min .. max of ours"
            + (" (blue) beside Kühne et al. Table III (orange, in the paper's units)"
               if papers else "") + "; circle = min, triangle = max")
    if zeros:
        head += ("\n\"0\": a value of exactly 0 (e.g. the paper's 0.00 minima, a singular "
                 "pose on the grid), at the foot of a log axis, which cannot draw it")
    fig.suptitle(head)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    out = Path(str(path) + "_table3_bars.png")
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out


def plot_table4_bars(path, summaries):
    """Table IV as dots: GII, σmin and σmax of ST⁻¹Jᵀ per device, ours (blue) beside
    the paper's (orange, Kühne et al. Table IV) where the paper has the device, each
    value printed beside its dot; the legend below the panels."""
    plt = _plt()
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.6))
    labels = [s["label"] for s in summaries]
    x = np.arange(len(labels), dtype=float)
    handles = {}
    for ax, (key, title) in zip(axes, (("gii", "GII"), ("sigma_min", "σmin"),
                                       ("sigma_max", "σmax"))):
        ours = [s["isotropy"][key] for s in summaries]
        paper = [s["isotropy"].get(f"paper_{key}") for s in summaries]
        if _log_axis(ours + paper):
            ax.set_yscale("log")
        has = any(v is not None for v in paper)
        series = [(-0.12 if has else 0.0, ours, None, "tab:blue", "ours")]
        if has:
            series.append((0.12, paper, None, "tab:orange", "Kühne et al. Table IV"))
        handles.update(_range_panel(ax, x, series, ax.get_yscale() == "log"))
        for off, vs, _, colour, _ in series:
            for xv, v in zip(x + off, vs):
                if v is not None and np.isfinite(v) and (v > 0 or ax.get_yscale() != "log"):
                    ax.annotate(sig(v, 3), (xv, v), textcoords="offset points",
                                xytext=(4, 3), fontsize=7, color=colour)
        ax.set_xticks(x)
        ax.set_xticklabels(labels, rotation=30, ha="right", fontsize=8)
        ax.set_xlim(-0.5, len(labels) - 0.5)
        ax.grid(axis="y", alpha=0.3)
        ax.set_title(title)
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=len(handles))
    rots = sorted({f"±{s['isotropy']['rotation_deg']:.0f}°" for s in summaries})
    papers = any(s["isotropy"].get("paper_gii") is not None for s in summaries)
    fig.suptitle(f"Table IV analogue of {', '.join(labels)} (orientations "
                 f"{' / '.join(rots)})" + (" vs Kühne et al. (±20°)" if papers else ""))
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    out = Path(str(path) + "_table4_bars.png")
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out


def plot_design_sweep(path, space, designs, gii_all, best, paper):
    """GII over l2 × β, one panel per (γ, ld); the paper's design (Table I) and our
    optimum marked."""
    plt = _plt()
    vals = dict(space.values)
    l2s, betas = vals.get("l2", (0.0,)), vals.get("beta", (0.0,))
    gammas, lds = vals.get("gamma", (0.0,)), vals.get("ld", (0.02,))
    idx = {tuple(round(d.get(k, 0.0), 12) for k in ("l2", "beta", "gamma", "ld")): i
           for i, d in enumerate(designs)}
    g = np.asarray(gii_all, dtype=float)
    vmax = float(np.nanmax(g)) if len(g) else 1.0
    fig, axes = plt.subplots(len(gammas), len(lds), figsize=(3.4 * len(lds), 3.0 * len(gammas)),
                             squeeze=False, constrained_layout=True)
    from matplotlib import colors
    norm = colors.LogNorm(vmin=max(vmax * 1e-3, float(np.nanmin(g[g > 0])) if np.any(g > 0)
                                   else 1e-6), vmax=vmax)
    bd = designs[best]
    for a, gm in enumerate(gammas):
        for b, ld in enumerate(lds):
            ax = axes[a, b]
            M = np.full((len(betas), len(l2s)), np.nan)
            for i, l2 in enumerate(l2s):
                for j, be in enumerate(betas):
                    k = idx.get(tuple(round(v, 12) for v in (l2, be, gm, ld)))
                    if k is not None and g[k] > 0:
                        M[j, i] = g[k]
            m = ax.pcolormesh(np.asarray(l2s) * 1e3, np.degrees(betas), M, shading="nearest",
                              norm=norm, cmap="viridis")
            if abs(gm - paper["gamma"]) < 1e-12 and abs(ld - paper["ld"]) < 1e-12:
                ax.plot(paper["l2"] * 1e3, np.degrees(paper["beta"]), "r*", ms=14,
                        label="paper (Table I)")
            if abs(gm - bd.get("gamma", 0)) < 1e-12 and abs(ld - bd.get("ld", 0.02)) < 1e-12:
                ax.plot(bd.get("l2", 0) * 1e3, np.degrees(bd.get("beta", 0)), "wo", ms=9,
                        mfc="none", mew=2, label="our optimum")
            ax.set_title(f"γ = {np.degrees(gm):.0f}°, ld = {ld * 1e3:.0f} mm", fontsize=8)
            ax.set_xlabel("l2 [mm]", fontsize=8)
            ax.set_ylabel("β [°]", fontsize=8)
            if ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize=6, loc="upper right")
    fig.colorbar(m, ax=axes.ravel().tolist(), label="GII")
    fig.suptitle("Table I design sweep: GII over l2 × β per (γ, ld)")
    out = Path(str(path) + "_design_gii.png")
    fig.savefig(out, dpi=90, bbox_inches="tight")
    plt.close(fig)
    return out
