"""Workspace grids, the dexterous workspace (eq. (17)) and the design criteria of
Sec. II-A (Kühne et al.).

A :class:`PoseGrid` is the product of a translational grid (x, y, z in m, the z values
absolute, i.e. offset by z0) and an orientational grid (rx, ry, rz in rad, the
mechanism's R = Rz Ry Rx).  Table II: 16³ positions (±75 mm, step 10 mm) × 9³
orientations (±20°, step 5°) = 2,985,984 poses, centred at z0 = 0.30 m.

The dexterous workspace (eq. (17)) is the set of grid positions at which every
orientation of the grid is reachable and the minimum velocity, acceleration and force
hold.  Its volume counts the grid *cells* (step_x · step_y · step_z) whose eight corner
positions are all dexterous: a grid of n³ positions spans (n − 1)³ cells, so the
Table II cube (16³ positions, ±75 mm) is 150³ mm³ = 3375 cm³ when every position is
dexterous.  The dual-cell count (each position weighted by its cell clipped to the grid
box, the trapezoidal rule) is reported beside it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["PoseGrid", "inner_covered", "axis_values", "MAX_AXIS", "table2_grid",
           "dexterous_workspace", "design_criteria", "CRITERIA", "RTOL", "at_least"]

#: relative tolerance of a sampled float64 value against a threshold: a value within
#: RTOL·max(|value|, |threshold|) of it is "at the threshold (within float64 rounding)",
#: not decided (the worst cases come from a few dozen float64 operations on J: their
#: rounding, a few ulps times the conditioning, stays far below 1e-12 relative on any
#: pose whose σmin/σmax is above RANK_TOL)
RTOL = 1e-12


def at_least(value, threshold, rtol: float = RTOL):
    """``value >= threshold`` decided outside float64 rounding: True, False, or None
    (within ``rtol`` relative of the threshold: undecided).  Arrays elementwise (None
    there is NaN in a float array: use :func:`numpy.isnan`)."""
    v = np.asarray(value, dtype=float)
    t = float(threshold)
    tol = rtol * np.maximum(np.abs(v), abs(t))
    near = np.abs(v - t) <= tol
    if v.ndim == 0:
        return None if bool(near) else bool(v >= t)
    return np.where(near, np.nan, (v >= t).astype(float))


#: the most values one grid axis may have: 10^5 per axis is already 10^15 positions of a
#: 3-D grid; a smaller step is a slip (a grid of 1.5e8 values per axis took minutes to
#: build before anything was evaluated)
MAX_AXIS = 100_000


def axis_values(lo: float, hi: float, step: float, field: str = "grid") -> np.ndarray:
    """``lo, lo+step, ..., hi`` (inclusive; hi must be reached to 1e-9 of a step)."""
    for name, v in (("min", lo), ("max", hi), ("step", step)):
        if not (isinstance(v, (int, float, np.integer, np.floating))
                and not isinstance(v, (bool, np.bool_)) and math.isfinite(v)):
            raise InputError(f"expected a finite number for the axis' {name}, got {v!r}",
                             field=field)
    if not step > 0:
        raise InputError(f"expected a positive step, got {step!r}", field=field)
    if hi < lo:
        raise InputError(f"expected min <= max, got {lo!r} > {hi!r}", field=field)
    n = (hi - lo) / step
    if n >= MAX_AXIS:
        raise InputError(f"expected at most {MAX_AXIS} values on a grid axis, got "
                         f"({hi!r} - {lo!r}) / {step!r} + 1 = {n + 1:.6g}: a step too "
                         f"small for the range (a unit slip?)", field=field)
    k = round(n)
    if abs(n - k) > 1e-9 * max(1.0, abs(n)):
        raise InputError(f"expected (max - min) to be a multiple of step, got "
                         f"({hi!r} - {lo!r}) / {step!r} = {n:.6g}", field=field)
    return lo + step * np.arange(k + 1)


@dataclass(frozen=True)
class PoseGrid:
    """Positions × orientations; all arrays in SI (m, rad).

    Attributes
    ----------
    x, y, z : tuple of float
        Position axes (z absolute).
    rx, ry, rz : tuple of float
        Orientation axes.

    Raises
    ------
    InputError
        An axis empty or not finite; a position axis not increasing in equal steps (the
        cell volume and the dual weights assume one step per axis; :func:`axis_values`).
    """

    def __post_init__(self):
        for name in ("x", "y", "z", "rx", "ry", "rz"):
            a = np.asarray(getattr(self, name), dtype=float)
            if a.ndim != 1 or not a.size or not np.all(np.isfinite(a)):
                raise InputError(f"expected a non-empty axis of finite numbers, got "
                                 f"{getattr(self, name)!r}", field=f"grid.{name}")
            if name in ("x", "y", "z") and a.size > 1:
                d = np.diff(a)
                if not (np.all(d > 0) and np.ptp(d) <= 1e-9 * d[0]):
                    raise InputError(f"expected an increasing axis of equal steps, got "
                                     f"{getattr(self, name)!r}", field=f"grid.{name}",
                                     hint="axis_values(min, max, step)")

    x: tuple
    y: tuple
    z: tuple
    rx: tuple
    ry: tuple
    rz: tuple

    @property
    def n_positions(self) -> int:
        return len(self.x) * len(self.y) * len(self.z)

    @property
    def n_orientations(self) -> int:
        return len(self.rx) * len(self.ry) * len(self.rz)

    @property
    def size(self) -> int:
        return self.n_positions * self.n_orientations

    @property
    def cell_volume(self) -> float:
        def step(a):
            return (a[1] - a[0]) if len(a) > 1 else 0.0
        return step(self.x) * step(self.y) * step(self.z)

    def positions(self, idx=None) -> np.ndarray:
        """(n, 3) positions, x fastest... in C order of (x, y, z) index."""
        X, Y, Z = np.meshgrid(self.x, self.y, self.z, indexing="ij")
        P = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)
        return P if idx is None else P[idx]

    def orientations(self) -> np.ndarray:
        A, B, C = np.meshgrid(self.rx, self.ry, self.rz, indexing="ij")
        return np.stack([A.ravel(), B.ravel(), C.ravel()], axis=1)

    def poses(self, pos_idx) -> np.ndarray:
        """(len(pos_idx) · n_orientations, 6): every orientation at each position
        (orientation index fastest)."""
        P = self.positions(np.asarray(pos_idx))
        O = self.orientations()
        n, m = len(P), len(O)
        return np.hstack([np.repeat(P, m, axis=0), np.tile(O, (n, 1))])

    def as_dict(self) -> dict:
        return {"x_m": list(self.x), "y_m": list(self.y), "z_m": list(self.z),
                "rx_rad": list(self.rx), "ry_rad": list(self.ry), "rz_rad": list(self.rz),
                "positions": self.n_positions, "orientations": self.n_orientations,
                "poses": self.size}


def table2_grid(z0: float = 0.30, half: float = 0.075, step: float = 0.010,
                rot_deg: float = 20.0, rot_step_deg: float = 5.0) -> PoseGrid:
    """The Table II grid (defaults): ±75 mm step 10 mm about (0, 0, z0), ±20° step 5°.

    ``z0``, ``half``, ``step`` in m; ``rot_deg``, ``rot_step_deg`` in degrees.  Refused
    with an :class:`InputError` naming the argument and its unit: not a finite number, a
    negative half-width, an axis of more than :data:`MAX_AXIS` values."""
    for name, v, unit in (("z0", z0, "m"), ("half", half, "m"), ("step", step, "m"),
                          ("rot_deg", rot_deg, "deg"), ("rot_step_deg", rot_step_deg, "deg")):
        if not (isinstance(v, (int, float, np.integer, np.floating))
                and not isinstance(v, (bool, np.bool_)) and math.isfinite(v)):
            raise InputError(f"expected a finite number ({unit}), got {v!r}", field=name)
    for name, v, unit in (("half", half, "m"), ("rot_deg", rot_deg, "deg")):
        if v < 0:
            raise InputError(f"expected a half-width >= 0 {unit} (the grid spans -{name} "
                             f"to +{name}), got {v!r} {unit}", field=name)
    t = axis_values(-half, half, step, "half/step (m)")
    r = np.deg2rad(axis_values(-rot_deg, rot_deg, rot_step_deg, "rot_deg/rot_step_deg (deg)"))
    return PoseGrid(tuple(t), tuple(t), tuple(z0 + t), tuple(r), tuple(r), tuple(r))


def _dual_weights(axis):
    a = np.asarray(axis, dtype=float)
    if len(a) < 2:
        return np.zeros(len(a))
    w = np.zeros(len(a))
    d = np.diff(a)
    w[:-1] += d / 2
    w[1:] += d / 2
    return w


def dexterous_workspace(grid: PoseGrid, reachable_all, minima: dict, thresholds: dict):
    """Dexterous workspace of eq. (17) on a grid.

    Parameters
    ----------
    grid : PoseGrid
    reachable_all : ndarray (n_positions,) bool
        Every orientation of the grid reachable at that position.
    minima : dict name -> ndarray (n_positions,)
        The worst case over the orientations at each position (e.g. ``"velocity"``);
        +inf where no orientation is reachable; NaN is refused (InputError naming
        ``minima.<name>`` and the position).
    thresholds : dict name -> float
        Required minimum of each (same unit).

    Returns
    -------
    dict
        ``mask`` (n_positions,) bool, ``count`` (positions), ``cells`` (grid cells with
        all eight corners dexterous) and ``cells_total``, ``volume_m3`` (cells · cell
        volume, m³), ``volume_nodes_m3`` (dual-cell weights, m³), ``grid_volume_m3``
        and ``fraction`` of the grid's positions; ``at_threshold_positions``: positions
        kept whose minimum equals a threshold within float64 rounding (:data:`RTOL`; an
        exact 1 m/s computed as 0.9999999999999998 is not a shortfall).
    """
    mask = _position_mask(grid, reachable_all)
    near = np.zeros_like(mask)
    for name, lim in thresholds.items():
        if name not in minima:
            raise InputError(f"expected a minimum for {name!r}, got only "
                             f"{sorted(minima)}", field="thresholds")
        if isinstance(lim, (bool, np.bool_)) or not isinstance(
                lim, (int, float, np.integer, np.floating)) or math.isnan(lim):
            raise InputError(f"expected a number (not NaN), got {lim!r}",
                             field=f"thresholds.{name}")
        v = _per_position(grid, minima[name], f"minima.{name}")
        ok = at_least(v, lim)
        near |= mask & np.isnan(ok)
        mask &= np.isnan(ok) | (ok == 1)        # at the threshold within rounding: kept
    near &= mask
    count = int(mask.sum())
    nx, ny, nz = len(grid.x), len(grid.y), len(grid.z)
    m3 = mask.reshape(nx, ny, nz)                  # positions are in C order of (x, y, z)
    if min(nx, ny, nz) >= 2:
        cell = np.ones((nx - 1, ny - 1, nz - 1), bool)
        for dx in (0, 1):
            for dy in (0, 1):
                for dz in (0, 1):
                    cell &= m3[dx:nx - 1 + dx, dy:ny - 1 + dy, dz:nz - 1 + dz]
        cells, total = int(cell.sum()), int(cell.size)
    else:
        cells, total = 0, 0
    wx, wy, wz = _dual_weights(grid.x), _dual_weights(grid.y), _dual_weights(grid.z)
    w = (wx[:, None, None] * wy[None, :, None] * wz[None, None, :]).ravel()
    return {"mask": mask, "count": count, "cells": cells, "cells_total": total,
            "volume_m3": cells * grid.cell_volume,
            "volume_nodes_m3": float(np.sum(w[mask])),
            "grid_volume_m3": total * grid.cell_volume,
            "fraction": count / max(1, grid.n_positions),
            "at_threshold_positions": int(near.sum())}


def _position_mask(grid, reachable_all):
    """``reachable_all`` as a bool array (n_positions,), or InputError naming it."""
    r = np.asarray(reachable_all)
    if r.shape != (grid.n_positions,) or r.dtype.kind not in "bi":
        raise InputError(f"expected {grid.n_positions} booleans (one per grid position), got "
                         f"shape {r.shape} of {r.dtype}", field="reachable_all")
    return r.astype(bool)


def _per_position(grid, values, field):
    """Per-position values as floats (n_positions,) (±inf allowed: no reachable
    orientation), or InputError naming ``field``; NaN is refused, naming its first
    position (QA IX 4: a NaN minimum compared below every threshold and silently
    emptied the dexterous workspace)."""
    from ..argcheck import as_floats
    v = as_floats(values, field, f"{grid.n_positions} numbers (one per grid position)")
    if v.shape != (grid.n_positions,):
        raise InputError(f"expected {grid.n_positions} values (one per grid position), got "
                         f"shape {v.shape}", field=field)
    nan = np.flatnonzero(np.isnan(v))
    if nan.size:
        raise InputError(f"expected a number (or ±inf: no reachable orientation) at every "
                         f"grid position, got NaN at position {int(nan[0])}"
                         + (f" (and {nan.size - 1} more)" if nan.size > 1 else ""),
                         field=field)
    return v


#: Sec. II-A design criteria (values in SI)
CRITERIA = {"cube_m": 0.150, "rotation_rad": math.radians(30.0), "velocity": 1.0,
            "acceleration": 9.81}


def design_criteria(L: int, grid: PoseGrid, reachable_all, minima: dict,
                    gii_value: float | None = None, criteria=CRITERIA, *,
                    sigma_min: float | None = None, transmission_min: float | None = None,
                    det_sign_changes: bool = False, sensitivities_max=None,
                    gii_others: dict | None = None, certified: str | None = None,
                    any_reachable: bool | None = None, gii_more_legs: dict | None = None):
    """Check the six design criteria of Sec. II-A on the result of a sweep over ``grid``.

    Parameters
    ----------
    L : int
        Number of actuated legs.
    grid : PoseGrid
        The grid the sweep covered.
    reachable_all : ndarray (n_positions,) bool
    minima : dict
        Worst cases over orientations per position: ``velocity`` [m/s] (the true set
        for L = 8 if given as ``velocity_true``), ``acceleration`` [m/s²], ``force`` [N].
    gii_value : float, optional
        The device's GII.
    sigma_min : float, optional
        Smallest σmin(ST⁻¹Jᵀ) over the sampled poses.
    transmission_min : float, optional
        Smallest |Jq_ii|/l1 over the sampled poses (0 at an inverse singularity).
    det_sign_changes : bool
        det J takes both signs over the grid (L = 6): a singularity lies in between.
    sensitivities_max : sequence of float, optional
        The largest of each maximum sensitivity over the grid (None: not finite).
    gii_others : dict label -> GII, optional
        The GII of the other compared kinematics with at most L legs (criterion 5).
    certified : {"regular", "singular", None}
        A certificate of the cube at zero rotation (:mod:`distkin.certify`), if run.
    any_reachable : bool, optional
        Some pose of the grid is reachable (default: some position reaches every
        orientation).  Without one, every criterion that rests on sampled values is
        undecided ("no reachable pose"), never NOT held on placeholder zeros.
    gii_more_legs : dict label -> GII, optional
        The devices of the study left out of criterion 5 (more legs than L), named in
        its value.

    Values are compared with thresholds outside float64 rounding (:func:`at_least`,
    :data:`RTOL`): a value equal to its threshold within rounding is "at the
    threshold", undecided, not a verdict.

    Returns
    -------
    list of dict
        One entry per criterion, numbered as the paper: ``{"number", "criterion",
        "held", "value", "required", "test"}``; ``held`` is None where the data cannot
        decide (e.g. the grid is smaller than the 150 mm cube or the ±30° range).
    """
    out = []
    reach = _position_mask(grid, reachable_all)
    missing = [k for k in ("acceleration", "force") if k not in minima] + \
        ([] if "velocity" in minima or "velocity_true" in minima else ["velocity"])
    if missing:
        raise InputError(f"expected the minima velocity (or velocity_true), acceleration "
                         f"and force, got {sorted(minima)} (missing {', '.join(missing)})",
                         field="minima")
    full = bool(reach.all())
    regular = sigma_min is not None and sigma_min > 0 and not det_sign_changes
    some = bool(reach.any()) if any_reachable is None else bool(any_reachable)
    none_note = None if some else "undecided: no reachable pose"
    out.append({"number": 1, "criterion": "six actuated DOF (d = 6)",
                "held": None if sigma_min is None else bool(regular and full),
                "value": {"sigma_min": sigma_min, "all_reachable": full,
                          "det_sign_changes": bool(det_sign_changes), "note": none_note},
                "required": "rank J = 6 at every pose of the grid",
                "test": "every grid pose reachable, the smallest σmin(ST⁻¹Jᵀ) > 0 and (L = 6) "
                        "det J of one sign (a sign change encloses a rank loss)"})
    out.append({"number": 2, "criterion": "rotary non-floating actuators at the first joint, "
                                          "L >= d",
                "held": None if transmission_min is None else bool(L >= 6
                                                                  and transmission_min > 0),
                "value": {"L": L, "transmission_min": transmission_min, "note": none_note},
                "required": {"L": ">= 6", "transmission_min": "> 0"},
                "test": "L >= 6 and every crank keeps authority over its leg: "
                        "min |Jq_ii|/l1 > 0 (no inverse singularity) at every grid pose"})
    # the cube and the ±30° of the dexterous workspace (criteria 3 and 4)
    ext = [max(a_) - min(a_) for a_ in (grid.x, grid.y, grid.z)]
    rot = min(min(abs(min(r)), abs(max(r))) for r in (grid.rx, grid.ry, grid.rz))
    covers = bool(min(ext) >= criteria["cube_m"] - 1e-12
                  and rot >= criteria["rotation_rad"] - 1e-12)
    vkey = "velocity_true" if "velocity_true" in minima else "velocity"
    v = _per_position(grid, minima[vkey], f"minima.{vkey}")[reach]
    a = _per_position(grid, minima["acceleration"], "minima.acceleration")[reach]
    f = _per_position(grid, minima["force"], "minima.force")
    vmin = float(v.min()) if v.size else None
    amin = float(a.min()) if a.size else None
    notes3 = []
    if not some:
        held3 = None
        notes3.append("undecided: no reachable pose")
    elif vmin is None:
        held3 = False                        # reachable poses, but no complete position
    else:
        dv = at_least(vmin, criteria["velocity"])
        da = at_least(amin, criteria["acceleration"])
        notes3 += [f"{n} at the threshold (within float64 rounding, {RTOL:g} relative)"
                   for n, d in (("velocity", dv), ("acceleration", da)) if d is None]
        held3 = (False if dv is False or da is False or not full else
                 None if dv is None or da is None else True)
        # a failure on part of the workspace is one; a pass decides nothing unless the
        # grid covers it
        held3 = held3 if covers or held3 is False else None
    out.append({"number": 3, "criterion": "minimum velocity >= 1 m/s and acceleration "
                                          ">= 9.81 m/s²",
                "held": held3,
                "value": {"velocity_m_s": vmin, "acceleration_m_s2": amin,
                          "velocity_set": "true set {ẋ: |Jẋ|∞ <= q̇max}"
                          if vkey == "velocity_true" else "J# zonotope, eq. (5)",
                          "note": "; ".join(notes3) or None},
                "required": {"velocity_m_s": criteria["velocity"],
                             "acceleration_m_s2": criteria["acceleration"]},
                "test": "worst cases over every grid pose, all positions reachable, the grid "
                        "covering the cube and ±30° (None when it passes on a smaller grid, "
                        f"or is at a threshold within float64 rounding, {RTOL:g} relative)"})
    free = bool(full and np.all(f > 0) and regular and certified != "singular")
    held4 = (None if not some else free if covers else (False if not free else None))
    out.append({"number": 4, "criterion": "singularity-free dexterous workspace, 150 mm cube, "
                                          "±30°",
                "held": held4,
                "value": {"cube_edge_m": float(min(ext)), "rotation_deg": math.degrees(rot),
                          "all_reachable": full, "sigma_min": sigma_min,
                          "det_sign_changes": bool(det_sign_changes),
                          "certificate_zero_rotation": certified,
                          "note": None if some else "undecided: no reachable pose"},
                "required": {"cube_edge_m": criteria["cube_m"],
                             "rotation_deg": math.degrees(criteria["rotation_rad"])},
                "test": "grid covers the cube and ±30°; every pose reachable, σmin > 0, det J "
                        "of one sign (L = 6), no certified singular box"})
    compared = {k: g for k, g in (gii_others or {}).items() if g is not None}
    note5 = None
    if gii_value is None or not some:
        held5, note5 = None, "undecided: no reachable pose"
    elif not compared:
        held5 = None
    else:
        top = max(compared.values())
        d5 = at_least(gii_value, top)
        held5 = bool(gii_value > 0 and d5 is True) if d5 is not None else None
        if d5 is None:
            note5 = "equal to the best other GII within float64 rounding"
    out.append({"number": 5, "criterion": "mechanical isotropy optimised (GII)",
                "held": held5,
                "value": {"gii": gii_value, "others": dict(gii_others or {}),
                          "more_legs": dict(gii_more_legs or {}), "note": note5},
                "required": "GII > 0 and not below any compared kinematics with at most as "
                            "many legs",
                "test": "GII over the Table II orientations against the other devices"})
    finite = sensitivities_max is not None and all(
        s is not None and math.isfinite(s) for s in sensitivities_max)
    out.append({"number": 6, "criterion": "maximum sensitivities quantifiable",
                "held": (None if sensitivities_max is None or not some else
                         bool(finite and regular)),
                "value": {"max_sensitivities": list(sensitivities_max or []),
                          "note": None if some else "undecided: no reachable pose"},
                "required": "bounded over the workspace",
                "test": "the four maximum sensitivities finite at every grid pose and no "
                        "singularity sampled (they are unbounded at one)"})
    return out


def inner_covered(grid, inner) -> float:
    """The largest r (rad) such that every rotation axis of ``grid`` has -r and +r among
    its values of magnitude <= ``inner`` (None: the whole axis): the range the inner
    reduction (Table IV's ±20°) actually covers."""
    lim = math.inf if inner is None else inner + 1e-9

    def reach(a):
        neg = max((-v for v in a if v <= 0 and -v <= lim), default=0.0)
        pos = max((v for v in a if v >= 0 and v <= lim), default=0.0)
        return min(neg, pos)
    # max with 0.0 first: a grid of zero rotation gave -0.0 ("±-0°"; QA V)
    return max(0.0, min(reach(a) for a in (grid.rx, grid.ry, grid.rz)))
