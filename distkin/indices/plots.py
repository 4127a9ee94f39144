"""Figures of the study, like Kühne et al. Figs. 5, 6 and 7 (matplotlib, imported lazily).

* :func:`plot_workspace` (Fig. 5): the translational workspace at zero rotation (blue)
  and the desired 150 mm cube (red), with the dexterous positions of the sweep;
* :func:`plot_plane` (Fig. 6): the worst case over all orientations of each output
  capability at every (x, y) of the plane z ≈ 0.30 m;
* :func:`plot_force_polytope` (Fig. 7): the force polytope at zero torque at one pose
  with the sphere of the worst-case force, tangent to its nearest facet;
* :func:`plot_table3_bars`, :func:`plot_table4_bars`: Tables III and IV, ours beside the
  paper's (log scale);
* :func:`plot_design_sweep`: the GII of the Table I sweep over l2 × β, one panel per
  (γ, ld), with the paper's design and our optimum marked.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["plot_workspace", "plot_plane", "plot_force_polytope", "force_slice_polytope",
           "plot_table3_bars", "plot_table4_bars", "plot_design_sweep"]


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_workspace(path, label, reach_pts, cube_half, z0, dexterous_pts=None):
    """Fig. 5.  ``reach_pts`` (n, 3) positions on the boundary of the workspace at zero
    rotation (m); ``dexterous_pts`` the dexterous positions of the sweep grid; the cube
    of half-width ``cube_half`` (m) about ``z0``: a height (centre (0, 0, z0)) or a
    centre (3,) (m)."""
    plt = _plt()
    fig = plt.figure(figsize=(7, 6))
    ax = fig.add_subplot(projection="3d")
    P = np.asarray(reach_pts) * 1e3
    if len(P):
        ax.scatter(P[:, 0], P[:, 1], P[:, 2], s=2, c="tab:blue", alpha=0.25,
                   label="boundary of the workspace at zero rotation")
    if dexterous_pts is not None and len(dexterous_pts):
        D = np.asarray(dexterous_pts) * 1e3
        ax.scatter(D[:, 0], D[:, 1], D[:, 2], s=6, c="tab:green", alpha=0.6,
                   label="dexterous (eq. 17) on the sweep grid")
    h = cube_half * 1e3
    cx, cy, cz = (np.array([0.0, 0.0, z0]) if np.ndim(z0) == 0 else np.asarray(z0)) * 1e3
    c = np.array([[x, y, zz] for x in (cx - h, cx + h) for y in (cy - h, cy + h)
                  for zz in (cz - h, cz + h)])
    for i in range(8):
        for j in range(i + 1, 8):
            if np.sum(c[i] != c[j]) == 1:
                ax.plot(*zip(c[i], c[j]), color="tab:red", lw=1.5)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.set_title(f"{label}: workspace (blue) and desired {2 * h:.4g} mm cube (red)")
    ax.legend(loc="upper left", fontsize=8)
    out = Path(str(path) + "_fig5_workspace.png")
    fig.savefig(out, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return out


def plot_plane(path, label, xs, ys, z, panels, rotation_deg):
    """Fig. 6.  ``panels``: list of (title, unit, array (len(xs), len(ys)))."""
    plt = _plt()
    fig, axes = plt.subplots(2, 3, figsize=(13, 7.5))
    X, Y = np.meshgrid(np.asarray(xs) * 1e3, np.asarray(ys) * 1e3, indexing="ij")
    for ax, (title, unit, V) in zip(axes.ravel(), panels):
        V = np.where(np.isfinite(V), V, np.nan)
        m = ax.pcolormesh(X, Y, V, shading="nearest", cmap="viridis")
        fig.colorbar(m, ax=ax, label=unit)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_aspect("equal")
    fig.suptitle(f"{label}: worst-case output capabilities at z = {z:.3f} m, "
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


def plot_force_polytope(path, label, Gw, limit, pose):
    """Fig. 7: the force polytope (N) at zero torque and the inscribed sphere."""
    plt = _plt()
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection
    V, simp, radius = force_slice_polytope(Gw, limit)
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
    ax.set_title(f"{label}: force polytope at zero torque, worst case {radius:.2f} N\n"
                 f"pose ({p[0]*1e3:.0f}, {p[1]*1e3:.0f}, {p[2]*1e3:.0f}) mm, "
                 f"({np.degrees(p[3]):.0f}, {np.degrees(p[4]):.0f}, "
                 f"{np.degrees(p[5]):.0f})°", fontsize=9)
    out = Path(str(path) + "_fig7_force_polytope.png")
    fig.savefig(out, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return out


def _pos(x):
    return np.nan if x is None or not np.isfinite(x) or x <= 0 else x


def _zero_marks(ax, xs, raw, color):
    """A "0" at the foot of each bar whose value is exactly 0 (a log axis cannot draw it:
    the paper's 0.00 minima of Ergin's device, a singular pose on its grid, QA IX 7)."""
    from matplotlib.transforms import blended_transform_factory
    tr = blended_transform_factory(ax.transData, ax.transAxes)
    for xv, v in zip(xs, raw):
        if v is not None and v == 0:
            ax.text(xv, 0.01, "0", transform=tr, ha="center", va="bottom", fontsize=7,
                    fontweight="bold", color=color)


def plot_table3_bars(path, summaries):
    """Table III as bars: per row, every device's min and max, ours beside the paper's
    (log scale; a value of exactly 0, e.g. the paper's 0.00 minima for Ergin's device, is
    marked "0" at the foot of its bar; a missing bar without it is not available)."""
    from .study import CAPABILITIES, SENSITIVITIES
    plt = _plt()
    rows = [(c[0], c[1], c[2]) for c in CAPABILITIES] + [(s[0], s[1], s[2])
                                                         for s in SENSITIVITIES]
    fig, axes = plt.subplots(2, 5, figsize=(22, 8))
    labels = [s["label"] for s in summaries]
    x = np.arange(len(labels))
    w = 0.2
    for ax, (q, title, unit) in zip(axes.ravel(), rows):
        for k, (key, pkey, hatch, col) in enumerate(
                (("min", "paper_min", "", "tab:blue"), ("min", None, "", "tab:orange"),
                 ("max", "paper_max", "//", "tab:blue"), ("max", None, "//", "tab:orange"))):
            if pkey is None:
                raw = [s["table"][q].get(f"paper_{key}") for s in summaries]
                lab = f"paper {key}"
            else:
                raw = [s["table"][q][key] for s in summaries]
                lab = f"ours {key}"
            ax.bar(x + (k - 1.5) * w, [_pos(v) for v in raw], w, color=col, hatch=hatch,
                   edgecolor="k", linewidth=0.3, label=lab)
            _zero_marks(ax, x + (k - 1.5) * w, raw, col)
        ax.set_yscale("log")
        ax.set_xticks(x)
        ax.set_xticklabels(labels, rotation=30, ha="right", fontsize=8)
        # the devices' own units (a sensitivity's follow the actuators: m/rad or m/m)
        units = sorted({s["table"][q].get("unit", unit) for s in summaries}) or [unit]
        ax.set_title(f"{title} [{' | '.join(units)}]", fontsize=9)
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("Table III: ours (blue) vs Kühne et al. (orange); plain = min, hatched = "
                 "max; \"0\" at a bar's foot: a value of 0 (e.g. the paper's 0.00 for Ergin's "
                 "device, a singular pose on its grid), which the log axis cannot draw")
    fig.tight_layout()
    out = Path(str(path) + "_table3_bars.png")
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out


def plot_table4_bars(path, summaries):
    """Table IV as bars: GII, σmin and σmax of ST⁻¹Jᵀ, ours beside the paper's."""
    plt = _plt()
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    labels = [s["label"] for s in summaries]
    x = np.arange(len(labels))
    for ax, (key, title) in zip(axes, (("gii", "GII"), ("sigma_min", "σmin"),
                                       ("sigma_max", "σmax"))):
        ours = [_pos(s["isotropy"][key]) for s in summaries]
        paper = [_pos(s["isotropy"].get(f"paper_{key}")) for s in summaries]
        ax.bar(x - 0.2, ours, 0.4, color="tab:blue", label="ours")
        ax.bar(x + 0.2, paper, 0.4, color="tab:orange", label="paper")
        _zero_marks(ax, x - 0.2, [s["isotropy"][key] for s in summaries], "tab:blue")
        ax.set_yscale("log")
        ax.set_xticks(x)
        ax.set_xticklabels(labels, rotation=30, ha="right", fontsize=8)
        ax.set_title(title)
    axes[0].legend()
    rots = sorted({f"±{s['isotropy']['rotation_deg']:.0f}°" for s in summaries})
    fig.suptitle(f"Table IV: ours (orientations {' / '.join(rots)}) vs Kühne et al. (±20°)")
    fig.tight_layout()
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
