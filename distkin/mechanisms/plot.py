"""A drawing of an RSS/RRRS mechanism at a pose (matplotlib, imported lazily).

Shows what the parameters of :mod:`.presets` mean: the base circle (radius l0) with
the crank pivots B (pairs ld apart), the actuator axes a (turned by ±beta), the cranks
B-C (l1), the RRRS offsets C-D (l2), the distal links D-P (l3) and the end-effector
polygon of the spherical joints P (radius lp, pairs turned by ±gamma).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["draw", "plot_poses", "draw_legs", "plot_legs_poses"]


def draw(mech, pose, q=None, ax=None, *, title=None):
    """Draw ``mech`` at ``pose`` (6,) (m, rad) on a 3-D matplotlib axis (lengths in mm).

    Parameters
    ----------
    mech : RSSMechanism
    pose : array (6,)
    q : array (L,), optional
        Crank angles; default the inverse kinematics of ``pose``.
    ax : mpl_toolkits.mplot3d.Axes3D, optional

    Returns
    -------
    ax
    """
    import matplotlib.pyplot as plt
    pose = np.asarray(pose, dtype=float)
    pts = mech.points(pose, q)
    valid = (np.abs(np.linalg.norm(pts["P"] - pts["D"], axis=-1) - mech.l3)
             < 1e-9 * mech.l3)
    if ax is None:
        fig = plt.figure(figsize=(7, 6))
        ax = fig.add_subplot(projection="3d")
    mm = 1e3
    th = np.linspace(0, 2 * np.pi, 200)
    ax.plot(mech.l0 * mm * np.cos(th), mech.l0 * mm * np.sin(th), 0 * th, color="0.7", lw=0.8,
            label=f"base circle l0 = {mech.l0 * mm:.1f} mm")
    g = mech.geometry()
    for i in range(mech.L):
        B, C, D, P = (pts[k][i] * mm for k in ("B", "C", "D", "P"))
        a = g["a"][i]
        ax.plot(*np.stack([B - 25 * a, B + 25 * a]).T, color="0.5", lw=0.8, ls=":")
        ax.plot(*np.stack([B, C]).T, color="tab:blue", lw=2.5,
                label="crank l1" if i == 0 else None)
        if mech.l2 > 0:
            ax.plot(*np.stack([C, D]).T, color="tab:green", lw=2,
                    label=f"offset l2 = {mech.l2 * mm:.1f} mm" if i == 0 else None)
        ax.plot(*np.stack([D, P]).T, color="tab:orange" if valid[i] else "tab:red", lw=1.5,
                label=f"distal l3 = {mech.l3 * mm:.1f} mm" if i == 0 else None)
        ax.scatter(*B, color="k", s=12)
        ax.text(*B, f" {i + 1}", fontsize=7)
    P = pts["P"] * mm
    ax.plot(*np.vstack([P, P[:1]]).T, color="tab:purple", lw=2,
            label=f"end effector lp = {mech.lp * mm:.1f} mm")
    ax.scatter(*(pose[:3] * mm), color="tab:purple", marker="x")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    r = (mech.l0 + mech.l1) * mm
    ax.set_xlim(-r, r)
    ax.set_ylim(-r, r)
    ax.set_zlim(-0.2 * r, 1.8 * r)
    deg = np.degrees
    where = (f"pose ({pose[0] * mm:.0f}, {pose[1] * mm:.0f}, {pose[2] * mm:.0f}) mm, "
             f"({deg(pose[3]):.1f}, {deg(pose[4]):.1f}, {deg(pose[5]):.1f})°")
    ax.set_title(title or (f"{mech.name}: L = {mech.L}, ld = {mech.ld * mm:.1f} mm, "
                           f"beta = {deg(mech.beta):.2f}°, gamma = {deg(mech.gamma):.2f}°\n"
                           + where + ("" if valid.all() else "  (red: legs that do not close)")),
                 fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    return ax


def plot_poses(mech, poses, stem, q=None, *, limit=4, drawer=None):
    """Write one PNG per pose (at most ``limit``) as ``STEM_pose<i>.png``; returns paths.
    ``drawer`` draws one pose (default :func:`draw`)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    poses = np.atleast_2d(np.asarray(poses, dtype=float))
    paths = []
    for i, pose in enumerate(poses[:limit]):
        fig = plt.figure(figsize=(7, 6))
        ax = fig.add_subplot(projection="3d")
        (drawer or draw)(mech, pose, None if q is None else np.asarray(q)[i], ax)
        path = Path(f"{stem}_pose{i}.png")
        fig.savefig(path, dpi=110, bbox_inches="tight")
        plt.close(fig)
        paths.append(path)
    return paths


def draw_legs(mech, pose, q=None, ax=None, *, title=None):
    """Draw a leg-table mechanism (:class:`~.kinematics.LegMechanism`) at ``pose`` (6,)
    (m, rad) on a 3-D axis (mm): cranks B-C, offsets C-D and distal links D-P of
    revolute legs, prismatic legs B-P (red: a leg that does not close)."""
    import matplotlib.pyplot as plt
    pose = np.asarray(pose, dtype=float)
    pts = mech.points(pose, q)
    _, valid = mech.inverse_kinematics(pose)
    if ax is None:
        fig = plt.figure(figsize=(7, 6))
        ax = fig.add_subplot(projection="3d")
    mm = 1e3
    for i, leg in enumerate(mech.leg_table):
        B, C, D, P = (pts[k][i] * mm for k in ("B", "C", "D", "P"))
        bad = not valid[i]
        if leg.prismatic:
            ax.plot(*np.stack([B, P]).T, color="tab:red" if bad else "tab:blue", lw=2.5,
                    label=f"{leg.type} leg" if i == 0 else None)
        else:
            ax.plot(*np.stack([B, C]).T, color="tab:blue", lw=2.5)
            ax.plot(*np.stack([C, D]).T, color="tab:green", lw=2)
            ax.plot(*np.stack([D, P]).T, color="tab:red" if bad else "tab:orange", lw=1.5)
        ax.scatter(*B, color="k", s=12)
        ax.text(*B, f" {i + 1}", fontsize=7)
    P = pts["P"] * mm
    ax.plot(*np.vstack([P, P[:1]]).T, color="tab:purple", lw=2, label="platform joints")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    deg = np.degrees
    ax.set_title(title or (f"{mech.name}: L = {mech.L}; pose ({pose[0] * mm:.0f}, "
                           f"{pose[1] * mm:.0f}, {pose[2] * mm:.0f}) mm, ({deg(pose[3]):.1f}, "
                           f"{deg(pose[4]):.1f}, {deg(pose[5]):.1f})°"), fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    return ax


def plot_legs_poses(mech, poses, stem, q=None, *, limit=4):
    """:func:`plot_poses` for a leg-table mechanism (:func:`draw_legs`)."""
    return plot_poses(mech, poses, stem, q, limit=limit, drawer=draw_legs)
