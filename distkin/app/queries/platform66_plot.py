"""The ``--plots`` drawing of the 6-6 forward kinematics (``kind = "platform66"``,
:class:`~.delta.Platform66Forward`): each assembly mode of the Δ 6-6 platform of Rojas,
Borràs and Thomas (Sec. V-VI, Fig. 6) on its own joints, the analogue of the octahedral
query's modes plot (:func:`.octahedral._plotter`, Fig. 8 analogue).

The numbers drawn are the query's result (its ``poses``: ``platform_joints`` in the base
frame, ``s15``, ``det_J66``, ``max_leg_error``; ``base_joints``), in the scene's own
length unit (the 6-6 geometry is used as written, not converted to SI).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["plot_modes66", "modes_drawn"]


def _ring(points) -> np.ndarray:
    """``points`` (6, 3) in the order around their centroid in their own best-fit plane
    (the joints of a 6-6 base or platform, drawn as one polygon)."""
    P = np.asarray(points, dtype=float)
    c = P - P.mean(axis=0)
    _, _, vt = np.linalg.svd(c)
    ang = np.arctan2(c @ vt[1], c @ vt[0])
    return P[np.argsort(ang)]


def modes_drawn(poses) -> list:
    """The indices (0-based) of the result's ``poses`` drawn: per root s15 the pose
    whose platform lies higher (larger mean z), its mirror image in the base plane
    omitted, as the octahedral modes plot does; ordered by s15."""
    best = {}
    for k, pose in enumerate(poses):
        z = float(np.mean(np.asarray(pose["platform_joints"], dtype=float)[:, 2]))
        s = pose["s15"]
        if s not in best or z > best[s][0]:
            best[s] = (z, k)
    return [best[s][1] for s in sorted(best)]


def plot_modes66(result, length: str, stem):
    """Write ``STEM_modes.png``: one 3-D panel per assembly mode of the 6-6 platform
    (:func:`modes_drawn`), the base joints (black), the platform joints (blue) and the
    six m-legs between them (orange), titled with the pose's number as the report
    counts it (1-based), s15, det J66 and the largest m-leg error in the scene's
    ``length`` unit ("none": unitless).  With no pose, the panel says the reason.
    Returns the paths."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import sympy as sp
    u = "" if length == "none" else f" {length}"
    poses = result.get("poses") or []
    shown = modes_drawn(poses)
    n = max(len(shown), 1)
    cols = min(3, n)
    rows = (n + cols - 1) // cols
    fig = plt.figure(figsize=(4.4 * cols, 4.2 * rows))
    if not shown:
        ax = fig.add_subplot(1, 1, 1)
        ax.text(0.5, 0.5, result.get("reason") or "no assembly mode", ha="center",
                va="center", wrap=True)
        ax.axis("off")
    else:
        B = np.array([[float(sp.sympify(v)) for v in row] for row in result["base_joints"]])
    for panel, k in enumerate(shown):
        pose = poses[k]
        P = np.asarray(pose["platform_joints"], dtype=float)
        ax = fig.add_subplot(rows, cols, panel + 1, projection="3d")
        for pts, colour, label in ((B, "k", "base joints"), (P, "tab:blue", "platform joints")):
            ring = _ring(pts)
            ring = np.vstack([ring, ring[:1]])
            ax.plot(ring[:, 0], ring[:, 1], ring[:, 2], "-", color=colour, lw=2,
                    label=label if panel == 0 else None)
        for i in range(6):
            ax.plot(*np.stack([B[i], P[i]]).T, color="tab:orange", lw=1,
                    label="m-legs" if panel == 0 and i == 0 else None)
        ax.set_title(f"pose {k + 1}: s15 = {pose['s15']:.6g}{u}{'^2' if u else ''}\n"
                     f"det J66 = {pose['det_J66']:.3e}{u + '^3' if u else ''}, max |m-leg "
                     f"error| {pose['max_leg_error']:.1e}{u}", fontsize=8)
        allp = np.vstack([B, P])
        ax.set_box_aspect(np.ptp(allp, axis=0) + 1e-9 * np.ptp(allp))
        for set_label, c in ((ax.set_xlabel, "x"), (ax.set_ylabel, "y"), (ax.set_zlabel, "z")):
            set_label(c + (f" [{length}]" if u else " (unitless)"))
        if panel == 0:
            ax.legend(fontsize=6, loc="upper left")
    fig.suptitle(f"6-6 platform: {len(poses)} assembly mode(s) (Rojas et al. Sec. VI; "
                 "Fig. 8 analogue), "
                 + ("mirror images in the base plane omitted" if shown else "none"),
                 fontsize=10)
    fig.tight_layout()
    path = Path(f"{stem}_modes.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [path]
