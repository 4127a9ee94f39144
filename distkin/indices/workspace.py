"""Workspace grids, the dexterous workspace (eq. (17)) and the design criteria of
Sec. II-A (Kühne et al.).

A :class:`PoseGrid` is the product of a translational grid (x, y, z in m, the z values
absolute, i.e. offset by z0) and an orientational grid (rx, ry, rz in rad, the
mechanism's R = Rz Ry Rx).  Table II: 16³ positions (±75 mm, step 10 mm) × 9³
orientations (±20°, step 5°) = 2,985,984 poses, centred at z0 = 0.30 m.

The dexterous workspace (eq. (17)) is the set of grid positions at which every
orientation of the grid is reachable and the minimum velocity, acceleration and force
hold; its volume counts one grid cell (step_x · step_y · step_z) per such position.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["PoseGrid", "axis_values", "table2_grid", "dexterous_workspace",
           "design_criteria", "CRITERIA"]


def axis_values(lo: float, hi: float, step: float, field: str = "grid") -> np.ndarray:
    """``lo, lo+step, ..., hi`` (inclusive; hi must be reached to 1e-9 of a step)."""
    if not step > 0:
        raise InputError(f"expected a positive step, got {step!r}", field=field)
    if hi < lo:
        raise InputError(f"expected min <= max, got {lo!r} > {hi!r}", field=field)
    n = (hi - lo) / step
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
    """

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
    """The Table II grid (defaults): ±75 mm step 10 mm about (0, 0, z0), ±20° step 5°."""
    t = axis_values(-half, half, step)
    r = np.deg2rad(axis_values(-rot_deg, rot_deg, rot_step_deg))
    return PoseGrid(tuple(t), tuple(t), tuple(z0 + t), tuple(r), tuple(r), tuple(r))


def dexterous_workspace(grid: PoseGrid, reachable_all, minima: dict, thresholds: dict):
    """Dexterous workspace of eq. (17) on a grid.

    Parameters
    ----------
    grid : PoseGrid
    reachable_all : ndarray (n_positions,) bool
        Every orientation of the grid reachable at that position.
    minima : dict name -> ndarray (n_positions,)
        The worst case over the orientations at each position (e.g. ``"velocity"``).
    thresholds : dict name -> float
        Required minimum of each (same unit).

    Returns
    -------
    dict
        ``mask`` (n_positions,) bool, ``count``, ``volume_m3`` (count · cell volume) and
        ``fraction`` of the grid's positions.
    """
    mask = np.asarray(reachable_all, bool).copy()
    for name, lim in thresholds.items():
        if name not in minima:
            raise InputError(f"expected a minimum for {name!r}, got only "
                             f"{sorted(minima)}", field="thresholds")
        mask &= np.asarray(minima[name]) >= lim
    count = int(mask.sum())
    return {"mask": mask, "count": count, "volume_m3": count * grid.cell_volume,
            "fraction": count / max(1, grid.n_positions)}


#: Sec. II-A design criteria (values in SI)
CRITERIA = {"cube_m": 0.150, "rotation_rad": math.radians(30.0), "velocity": 1.0,
            "acceleration": 9.81}


def design_criteria(L: int, grid: PoseGrid, reachable_all, minima: dict,
                    gii_value: float | None = None, criteria=CRITERIA):
    """Check the design criteria of Sec. II-A on the result of a sweep over ``grid``.

    Parameters
    ----------
    L : int
        Number of actuated legs.
    grid : PoseGrid
        The grid the sweep covered.
    reachable_all : ndarray (n_positions,) bool
    minima : dict
        Worst cases over orientations per position: ``velocity`` [m/s],
        ``acceleration`` [m/s²], ``force`` [N] (0 marks a singular pose).
    gii_value : float, optional

    Returns
    -------
    list of dict
        One entry per criterion: ``{"criterion", "held", "value", "required"}``;
        ``held`` is None where the grid cannot decide (e.g. it is smaller than the
        150 mm cube or the ±30° range).
    """
    out = []
    out.append({"criterion": "1) six actuated DOF (d = 6)", "held": True, "value": 6,
                "required": 6})
    out.append({"criterion": "2) rotary non-floating actuators, L >= d", "held": L >= 6,
                "value": L, "required": ">= 6"})
    reach = np.asarray(reachable_all, bool)
    v = np.asarray(minima["velocity"])[reach]
    a = np.asarray(minima["acceleration"])[reach]
    vmin = float(v.min()) if v.size else 0.0
    amin = float(a.min()) if a.size else 0.0
    out.append({"criterion": "3) minimum velocity >= 1 m/s", "held": bool(vmin >= criteria[
        "velocity"]) and bool(reach.all()), "value": vmin, "required": criteria["velocity"],
        "unit": "m/s"})
    out.append({"criterion": "3) minimum acceleration >= 9.81 m/s²",
                "held": bool(amin >= criteria["acceleration"]) and bool(reach.all()),
                "value": amin, "required": criteria["acceleration"], "unit": "m/s^2"})
    ext = [max(a_) - min(a_) for a_ in (grid.x, grid.y, grid.z)]
    rot = min(min(abs(min(r)), abs(max(r))) for r in (grid.rx, grid.ry, grid.rz))
    covers = (min(ext) >= criteria["cube_m"] - 1e-12
              and rot >= criteria["rotation_rad"] - 1e-12)
    f = np.asarray(minima["force"])
    singular_free = bool(reach.all() and np.all(f > 0))
    held = (singular_free and covers) if covers else (False if not singular_free else None)
    out.append({"criterion": "4) singularity-free dexterous workspace, 150 mm cube, ±30°",
                "held": held, "value": {"cube_edge_m": min(ext),
                                        "rotation_deg": math.degrees(rot),
                                        "all_reachable": bool(reach.all()),
                                        "singular_free": singular_free},
                "required": {"cube_edge_m": criteria["cube_m"],
                             "rotation_deg": math.degrees(criteria["rotation_rad"])}})
    out.append({"criterion": "5) mechanical isotropy (GII, reported)",
                "held": None if gii_value is None else bool(gii_value > 0),
                "value": gii_value, "required": "> 0, maximised"})
    out.append({"criterion": "6) maximum sensitivities quantified", "held": True,
                "value": "see the sensitivity rows", "required": "reported"})
    return out
