"""Drawings of an RSS/RRRS or leg-table mechanism at a pose, and of its Jacobian
(matplotlib, imported lazily).

:func:`draw` shows what the parameters of :mod:`.presets` mean: the base circle (radius
l0) with the crank pivots B (pairs ld apart), the actuator axes a (turned by ±beta), the
cranks B-C (l1), the RRRS offsets C-D (l2), the distal links D-P (l3) and the
end-effector polygon of the spherical joints P (radius lp, pairs turned by ±gamma).
:func:`draw_legs` draws any leg table (:class:`~.kinematics.LegMechanism`).

Every drawing is in the scene's units (``units``: a :class:`distkin.app.units.Units`,
default mm and deg), as the text report of the same query prints them.  A leg drawn red
is one that the inverse kinematics at the pose marks invalid (``valid`` of
:meth:`~.kinematics.KernelMethods.inverse_kinematics`, the inverse_kinematics query's
"NOT reachable"), and the legend and title say why (:func:`leg_faults`): a revolute leg
whose distal link cannot close (reach margin < 0), a crank angle outside its declared
range, a prismatic leg out of its stroke; with given joint values ``q``, also a leg that
they leave open by more than ``closure_tol``.

:func:`jacobian_figure` draws J = Jq⁻¹ Jx (Kühne et al. eqs. (1)-(2)) as a heat map
(rows: legs, columns: the pose coordinates, each with its unit), its singular values and
κ of eq. (4), beside the pose.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["draw", "plot_poses", "draw_legs", "plot_legs_poses", "leg_faults",
           "jacobian_column_units", "jacobian_figure", "plot_jacobians", "scene_units"]

#: the drawn actuator axis: this length (m) either side of the crank pivot
_AXIS_HALF = 0.025


def scene_units(units=None):
    """``(length name, scene lengths per metre, angle name, scene angles per rad)`` of a
    :class:`distkin.app.units.Units` (default: mm and deg, the presets' own)."""
    from ..app.units import Units, angle_factor, length_factor
    u = units if units is not None else Units("mm", "deg")
    return u.length, 1.0 / length_factor(u, "units"), u.angle, 1.0 / angle_factor(u)


def _pose_text(pose, units) -> str:
    lu, lf, au, af = scene_units(units)
    return (f"pose ({', '.join(f'{v * lf:.4g}' for v in pose[:3])}) {lu}, "
            f"({', '.join(f'{v * af:.4g}' for v in pose[3:])}) {au}")


def leg_faults(mech, pose, q=None, *, closure_tol=None, units=None):
    """Why each leg of ``mech`` is drawn red at ``pose`` (6,) (m, rad): a list (L,) of
    ``None`` (the leg is valid: it closes, within its declared range) or ``(kind,
    words)``, the words in the scene's ``units``.  ``kind`` is ``"no reach"`` (a revolute
    leg whose distal link cannot close: reach margin < 0), ``"out of range"`` (a crank
    that closes at an angle outside its declared range), ``"out of stroke"`` (a
    prismatic leg whose length |P - B| lies outside its stroke), ``"zero length"``, or,
    with joint values ``q`` (L,) given, ``"open"``: the distal link's closure error
    | |P - D| - l3 | of the drawn joints above ``closure_tol`` (m; default 1e-9 l3)."""
    lu, lf, au, af = scene_units(units)
    pose = np.asarray(pose, dtype=float)
    _, valid = mech.inverse_kinematics(pose)
    margin = np.asarray(mech.reach_margin(pose), dtype=float)
    table = mech.leg_description().leg_table
    pts = mech.points(pose, None if q is None else np.asarray(q, dtype=float))
    l3 = np.asarray(mech.leg_arrays()["l3"], dtype=float)
    out = []
    for i, leg in enumerate(table):
        fault = None
        if not valid[i]:
            if leg.prismatic:
                length = float(np.linalg.norm(pts["P"][i] - pts["B"][i]))
                if leg.range is not None and margin[i] < 0:
                    lo, hi = (float(v) * lf for v in leg.range)
                    fault = ("out of stroke", f"leg {i + 1}: length {length * lf:.4g} {lu} "
                                              f"outside its stroke [{lo:.4g}, {hi:.4g}] {lu}")
                else:
                    fault = ("zero length", f"leg {i + 1}: zero length")
            elif margin[i] < 0:
                fault = ("no reach", f"leg {i + 1}: the distal link "
                                     f"({l3[i] * lf:.4g} {lu}) cannot close")
            else:
                lo, hi = (float(v) * af for v in leg.range)
                fault = ("out of range", f"leg {i + 1}: crank angle outside its range "
                                         f"[{lo:.4g}, {hi:.4g}] {au}")
        elif q is not None and not leg.prismatic:
            tol = 1e-9 * l3[i] if closure_tol is None else closure_tol
            err = abs(float(np.linalg.norm(pts["P"][i] - pts["D"][i])) - l3[i])
            if not err <= tol:
                fault = ("open", f"leg {i + 1}: closure error {err * lf:.3g} {lu} > "
                                 f"{tol * lf:.3g} {lu}")
        out.append(fault)
    return out


#: the legend's words for each kind of :func:`leg_faults`
_KIND_WORDS = {"no reach": "NOT reachable: distal link cannot close",
               "out of range": "NOT reachable: crank outside its declared range",
               "out of stroke": "NOT reachable: out of stroke",
               "zero length": "NOT reachable: zero length",
               "open": "does not close at the drawn joint values"}


def _fault_legend(ax, faults, lw):
    """One red legend entry per kind of fault, naming the legs (1-based); returns the
    title's line (empty when every leg is valid)."""
    kinds = {}
    for i, f in enumerate(faults):
        if f is not None:
            kinds.setdefault(f[0], []).append((i + 1, f[1]))
    parts = []
    for kind, legs in kinds.items():
        nums = [n for n, _ in legs]
        ax.plot([], [], color="tab:red", lw=lw, label=f"red: {_KIND_WORDS[kind]}: legs {nums}")
        for _, words in legs:
            ax.plot([], [], " ", label="  " + words)
        parts.append(f"legs {nums} {_KIND_WORDS[kind].split(': ', 1)[-1]}")
    if not kinds:
        return "every leg reaches this pose (a red leg would not)"
    return "red: " + "; ".join(parts)


def _new_axis(ax):
    if ax is None:
        import matplotlib.pyplot as plt
        fig = plt.figure(figsize=(7, 6))
        ax = fig.add_subplot(projection="3d")
    return ax


def draw(mech, pose, q=None, ax=None, *, title=None, units=None, closure_tol=None,
         note=None):
    """Draw ``mech`` at ``pose`` (6,) (m, rad) on a 3-D matplotlib axis, in the scene's
    ``units`` (default mm, deg).

    Parameters
    ----------
    mech : RSSMechanism
    pose : array (6,)
    q : array (L,), optional
        Crank angles (rad); default the inverse kinematics of ``pose``.
    ax : mpl_toolkits.mplot3d.Axes3D, optional
    units : distkin.app.units.Units, optional
    closure_tol : float, optional
        m: with ``q`` given, a leg whose distal link the angles leave open by more is
        red (default 1e-9 l3; :func:`leg_faults`).
    note : str, optional
        A last title line (what was drawn, the query's verdict).

    Returns
    -------
    ax
    """
    lu, lf, au, af = scene_units(units)
    pose = np.asarray(pose, dtype=float)
    pts = mech.points(pose, q)
    faults = leg_faults(mech, pose, q, closure_tol=closure_tol, units=units)
    ax = _new_axis(ax)
    th = np.linspace(0, 2 * np.pi, 200)
    ax.plot(mech.l0 * lf * np.cos(th), mech.l0 * lf * np.sin(th), 0 * th, color="0.7",
            lw=0.8, label=f"base circle l0 = {mech.l0 * lf:.4g} {lu}")
    g = mech.geometry()
    ok = [i for i in range(mech.L) if faults[i] is None]
    for i in range(mech.L):
        B, C, D, P = (pts[k][i] * lf for k in ("B", "C", "D", "P"))
        a = g["a"][i] * _AXIS_HALF * lf
        ax.plot(*np.stack([B - a, B + a]).T, color="0.5", lw=0.8, ls=":")
        ax.plot(*np.stack([B, C]).T, color="tab:blue", lw=2.5,
                label=f"crank l1 = {mech.l1 * lf:.4g} {lu}" if i == 0 else None)
        if mech.l2 > 0:
            ax.plot(*np.stack([C, D]).T, color="tab:green", lw=2,
                    label=f"offset l2 = {mech.l2 * lf:.4g} {lu}" if i == 0 else None)
        ax.plot(*np.stack([D, P]).T, color="tab:red" if faults[i] else "tab:orange", lw=1.5,
                label=(f"distal l3 = {mech.l3 * lf:.4g} {lu}" if ok and i == ok[0]
                       else None))
        ax.scatter(*B, color="k", s=12)
        ax.text(*B, f" {i + 1}", fontsize=7)
    P = pts["P"] * lf
    ax.plot(*np.vstack([P, P[:1]]).T, color="tab:purple", lw=2,
            label=f"end effector lp = {mech.lp * lf:.4g} {lu}")
    ax.scatter(*(pose[:3] * lf), color="tab:purple", marker="x")
    red = _fault_legend(ax, faults, 1.5)
    for set_label, k in ((ax.set_xlabel, "x"), (ax.set_ylabel, "y"), (ax.set_zlabel, "z")):
        set_label(f"{k} [{lu}]")
    r = (mech.l0 + mech.l1) * lf
    ax.set_xlim(-r, r)
    ax.set_ylim(-r, r)
    ax.set_zlim(-0.2 * r, 1.8 * r)
    ax.set_title(title or (f"{mech.name}: L = {mech.L}, ld = {mech.ld * lf:.4g} {lu}, "
                           f"beta = {mech.beta * af:.4g} {au}, gamma = {mech.gamma * af:.4g} "
                           f"{au}\n{_pose_text(pose, units)}\n{red}"
                           + (f"\n{note}" if note else "")), fontsize=8)
    ax.legend(fontsize=6, loc="upper left")
    return ax


def plot_poses(mech, poses, stem, q=None, *, limit=4, drawer=None, units=None, note=None):
    """Write one PNG per pose (at most ``limit``) as ``STEM_pose<i>.png``; returns paths.
    ``drawer`` draws one pose (default :func:`draw`) in the scene's ``units``; ``note``:
    a last title line."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    poses = np.atleast_2d(np.asarray(poses, dtype=float))
    paths = []
    for i, pose in enumerate(poses[:limit]):
        fig = plt.figure(figsize=(7, 6.4))
        ax = fig.add_subplot(projection="3d")
        (drawer or draw)(mech, pose, None if q is None else np.asarray(q)[i], ax,
                         units=units, note=note)
        path = Path(f"{stem}_pose{i}.png")
        fig.savefig(path, dpi=110, bbox_inches="tight")
        plt.close(fig)
        paths.append(path)
    return paths


def draw_legs(mech, pose, q=None, ax=None, *, title=None, units=None, closure_tol=None,
              note=None):
    """Draw a leg-table mechanism (:class:`~.kinematics.LegMechanism`) at ``pose`` (6,)
    (m, rad) on a 3-D axis in the scene's ``units`` (default mm, deg): cranks B-C, offsets
    C-D and distal links D-P of revolute legs, prismatic legs B-P; red legs as
    :func:`leg_faults` says, named in the legend and title with the reason."""
    lu, lf, au, af = scene_units(units)
    pose = np.asarray(pose, dtype=float)
    pts = mech.points(pose, q)
    faults = leg_faults(mech, pose, q, closure_tol=closure_tol, units=units)
    ax = _new_axis(ax)
    labelled = set()
    for i, leg in enumerate(mech.leg_table):
        B, C, D, P = (pts[k][i] * lf for k in ("B", "C", "D", "P"))
        bad = faults[i] is not None
        label = None
        if not bad and leg.type not in labelled:
            labelled.add(leg.type)
            label = f"{leg.type} leg" + (" (within its stroke)" if leg.prismatic
                                         and leg.range is not None else "")
        if leg.prismatic:
            ax.plot(*np.stack([B, P]).T, color="tab:red" if bad else "tab:blue", lw=2.5,
                    label=label)
        else:
            ax.plot(*np.stack([B, C]).T, color="tab:blue", lw=2.5, label=label)
            ax.plot(*np.stack([C, D]).T, color="tab:green", lw=2)
            ax.plot(*np.stack([D, P]).T, color="tab:red" if bad else "tab:orange", lw=1.5)
        ax.scatter(*B, color="k", s=12)
        ax.text(*B, f" {i + 1}", fontsize=7)
    P = pts["P"] * lf
    ax.plot(*np.vstack([P, P[:1]]).T, color="tab:purple", lw=2, label="platform joints")
    red = _fault_legend(ax, faults, 2.5)
    for set_label, k in ((ax.set_xlabel, "x"), (ax.set_ylabel, "y"), (ax.set_zlabel, "z")):
        set_label(f"{k} [{lu}]")
    ax.set_title(title or (f"{mech.name}: L = {mech.L}; {_pose_text(pose, units)}\n{red}"
                           + (f"\n{note}" if note else "")), fontsize=8)
    ax.legend(fontsize=6, loc="upper left")
    return ax


def plot_legs_poses(mech, poses, stem, q=None, *, limit=4, units=None, note=None):
    """:func:`plot_poses` for a leg-table mechanism (:func:`draw_legs`)."""
    return plot_poses(mech, poses, stem, q, limit=limit, drawer=draw_legs, units=units,
                      note=note)


def jacobian_column_units(mech) -> list:
    """The unit of each column (6,) of J = Jq⁻¹ Jx (SI, qdot = J (v, omega)): per leg
    kind, rad/m and rad/rad for a revolute leg's row, m/m and m/rad for a prismatic
    one's; "rad/m | m/m" where the table mixes them."""
    pris = {bool(leg.prismatic) for leg in mech.leg_description().leg_table}
    lin = " | ".join(u for p, u in ((False, "rad/m"), (True, "m/m")) if p in pris)
    ang = " | ".join(u for p, u in ((False, "rad/rad"), (True, "m/rad")) if p in pris)
    return [lin] * 3 + [ang] * 3


def jacobian_figure(mech, row, *, units=None):
    """A figure of the jacobian query's result ``row`` at one pose (its ``pose``, ``J``
    (L, 6), ``singular_values``, ``kappa``, ``kappa_unscaled``, ``reachable``,
    ``singular``; SI, as in the JSON): J as a heat map (rows: legs, columns: vx, vy, vz,
    ωx, ωy, ωz with their units, :func:`jacobian_column_units`), the singular values of
    the unscaled J as stems, κ (Kühne et al. eq. (4), of ST⁻¹Jᵀ) in the title, and the
    pose drawn (:func:`draw` or :func:`draw_legs`, scene ``units``)."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import TwoSlopeNorm
    J = np.asarray(row["J"], dtype=float)
    fig = plt.figure(figsize=(17, 5.6))
    grid = fig.add_gridspec(1, 3, width_ratios=[1.25, 0.8, 1.15], wspace=0.4)
    ax = fig.add_subplot(grid[0])
    shown = np.where(np.isfinite(J), J, 0.0)
    m = max(float(np.max(np.abs(shown))), 1e-300)
    im = ax.imshow(shown, cmap="RdBu_r", norm=TwoSlopeNorm(0.0, -m, m), aspect="auto")
    cols = jacobian_column_units(mech)
    ax.set_xticks(range(6), [f"{c}\n[{u}]" for c, u in
                             zip(("vx", "vy", "vz", "ωx", "ωy", "ωz"), cols)], fontsize=7)
    table = mech.leg_description().leg_table
    ax.set_yticks(range(len(J)), [f"leg {i + 1} ({leg.type})" for i, leg in enumerate(table)],
                  fontsize=7)
    for (i, k), v in np.ndenumerate(J):
        ax.text(k, i, f"{v:.3g}", ha="center", va="center", fontsize=6,
                color="w" if abs(v) > 0.6 * m else "k")
    fig.colorbar(im, ax=ax, label="entry of J (the unit of its column)")
    ax.set_xlabel("pose velocity coordinate (qdot = J (v, ω))")
    ax.set_title("J = Jq⁻¹ Jx (Kühne et al. eqs. (1)-(2))"
                 + ("" if row["reachable"] else "\nNOT reachable: J is meaningless"),
                 fontsize=9)
    ax2 = fig.add_subplot(grid[1])
    sv = row.get("singular_values")
    if sv is None:
        ax2.text(0.5, 0.5, "singular values: undefined\n(pose not reachable)",
                 ha="center", va="center", transform=ax2.transAxes)
        ax2.set_title("κ (eq. (4)): undefined (pose not reachable)", fontsize=9)
    else:
        sv = np.asarray(sv, dtype=float)
        ax2.stem(np.arange(1, len(sv) + 1), sv, basefmt="0.6")
        ax2.set_xticks(np.arange(1, len(sv) + 1))
        ax2.set_xlabel("i")
        ax2.set_ylabel("σ_i of the unscaled J (mixed units: " + ", ".join(
            dict.fromkeys(u for c in cols for u in c.split(" | "))) + ")")
        ax2.set_title(f"κ = {row['kappa']:.6g} (eq. (4): σmin/σmax of ST⁻¹Jᵀ)"
                      + (" SINGULAR" if row.get("singular") else "")
                      + f"\nunscaled σmin/σmax = {row['kappa_unscaled']:.6g}", fontsize=9)
        ax2.set_ylim(0, 1.1 * float(sv.max()) if sv.max() > 0 else 1.0)
    ax3 = fig.add_subplot(grid[2], projection="3d")
    (draw if mech.kind == "rss" else draw_legs)(mech, row["pose"], None, ax3, units=units)
    fig.suptitle(f"{mech.name}: Jacobian at {_pose_text(np.asarray(row['pose']), units)}",
                 fontsize=10)
    return fig


def plot_jacobians(mech, rows, stem, *, units=None, limit=4):
    """Write :func:`jacobian_figure` of each of the jacobian query's pose ``rows`` (at
    most ``limit``) as ``STEM_pose<i>.png``; returns the paths."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    paths = []
    for i, row in enumerate(rows[:limit]):
        fig = jacobian_figure(mech, row, units=units)
        path = Path(f"{stem}_pose{i}.png")
        fig.savefig(path, dpi=100, bbox_inches="tight")
        plt.close(fig)
        paths.append(path)
    return paths
