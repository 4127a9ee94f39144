"""Admittance model and virtual environment of the haptic controller.

Kühne et al., Sec. III-D and Fig. 9: the Octo is governed by an admittance scheme --
the measured hand wrench drives a virtual mass-damper, whose pose becomes the set point
of the position-level PD loop.  Per axis (base frame, diagonal model)

.. math:: M_v \\dot V = w_h + w_e(x, V) - D_v V,

with ``V = (v, omega)`` the virtual twist, ``w_h`` the hand wrench from the
force/torque sensor, and ``w_e`` the wrench of the virtual environment that the scene
declares (:class:`Spring`, :class:`Wall`).  Integrated with semi-implicit Euler at the
loop period; the orientation is updated on SO(3) (``R <- exp(omega dt) R``).

Static predictions used by the tests: a constant hand force ``f`` against a spring
``k`` settles at ``f / k`` with time constant ``D / k`` (for ``M << D^2 / k``);
pressing into a wall of stiffness ``k_w`` adds ``k_w`` to the slope of force versus
position beyond the wall.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..spatial import rotate_pose_scalar as rotate_pose
from .kinematics import _rot

__all__ = ["Spring", "Wall", "Admittance", "rotation_log"]


def rotation_log(R) -> np.ndarray:
    """Rotation vector (3,) rad of a rotation matrix (the inverse of Rodrigues' formula)."""
    sk = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    s = 0.5 * math.sqrt(float(sk @ sk))
    c = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    th = math.atan2(s, c)
    if s < 1e-12:
        return 0.5 * sk
    return sk * (th / (2.0 * s))


@dataclass(frozen=True)
class Spring:
    """A virtual spring-damper pulling the pose towards ``anchor``.

    ``anchor`` (6,) pose (m, rad); ``stiffness`` (6,) N/m x3 then N·m/rad x3;
    ``damping`` (6,) N·s/m x3 then N·m·s/rad x3 (added to the admittance damping).
    """

    anchor: tuple
    stiffness: tuple
    damping: tuple = (0.0,) * 6

    kind = "spring"

    def __post_init__(self):
        # work arrays derived once (the dataclass stays frozen for its users)
        object.__setattr__(self, "_k", np.asarray(self.stiffness, dtype=float))
        object.__setattr__(self, "_d", np.asarray(self.damping, dtype=float))
        object.__setattr__(self, "_p0", np.asarray(self.anchor[:3], dtype=float))
        object.__setattr__(self, "_R0t", _rot(self.anchor[3:]).T)

    def wrench(self, pose, twist) -> np.ndarray:
        """Spring-damper wrench (6,) at ``pose`` (6,) with ``twist`` (6,): N, N·m."""
        e = np.empty(6)
        e[:3] = pose[:3] - self._p0
        e[3:] = rotation_log(_rot(pose[3:]) @ self._R0t)
        return -self._k * e - self._d * twist


@dataclass(frozen=True)
class Wall:
    """A unilateral virtual wall: the half-space ``normal . p <= offset`` is free.

    Beyond it (penetration ``delta = normal . p - offset > 0``, p the end-effector
    centre, m) the wall pushes back along ``-normal`` with ``stiffness * delta +
    damping * max(normal . v, 0)`` (N), never pulling.
    """

    normal: tuple
    offset: float
    stiffness: float
    damping: float = 0.0

    kind = "wall"

    def penetration(self, pose) -> float:
        n = self.normal
        return n[0] * pose[0] + n[1] * pose[1] + n[2] * pose[2] - self.offset

    def wrench(self, pose, twist) -> np.ndarray:
        out = np.zeros(6)
        d = self.penetration(pose)
        if d > 0.0:
            n = np.asarray(self.normal)
            f = self.stiffness * d + self.damping * max(float(n @ twist[:3]), 0.0)
            out[:3] = -max(f, 0.0) * n
        return out


class Admittance:
    """The virtual mass-damper and its environment (Kühne et al., Fig. 9).

    Parameters
    ----------
    mass : array (6,)
        Virtual mass (kg) x3 and inertia (kg·m²) x3.
    damping : array (6,)
        Virtual damping, N·s/m x3 and N·m·s/rad x3.
    environment : sequence of Spring / Wall
    kernels : CycleKernels, optional
        Springs and the SO(3) step by the same functions compiled by numba
        (:mod:`.cycle_kernels`, for the control cycle); None: plain Python and numpy.
    """

    def __init__(self, mass, damping, environment=(), *, kernels=None):
        self.mass = np.asarray(mass, dtype=float)
        self.damping = np.asarray(damping, dtype=float)
        self.environment = tuple(environment)
        self.pose = np.zeros(6)
        self.twist = np.zeros(6)
        self.kernels = kernels

    def reset(self, pose) -> None:
        """Start at rest at ``pose`` (the measured pose; no jump in the set point)."""
        self.pose = np.array(pose, dtype=float)
        self.twist = np.zeros(6)

    def environment_wrench(self, pose, twist) -> np.ndarray:
        w = np.zeros(6)
        for e in self.environment:
            if self.kernels is not None and e.kind == "spring":
                out = np.empty(6)
                self.kernels.spring_wrench(pose, twist, e._p0, e._R0t, e._k, e._d, out)
                w += out
            else:
                w += e.wrench(pose, twist)
        return w

    def propose(self, hand_wrench, dt):
        """One semi-implicit Euler step; returns the candidate ``(pose, twist)``.

        Nothing is committed: the caller checks the candidate (reachability,
        singularity guard) and calls :meth:`commit` or :meth:`refuse`.
        """
        w = hand_wrench + self.environment_wrench(self.pose, self.twist)
        twist = self.twist + dt * (w - self.damping * self.twist) / self.mass
        if self.kernels is not None:
            return self.kernels.rotate_pose(self.pose, twist[:3] * dt, twist[3:] * dt), twist
        pose = rotate_pose(self.pose, twist[:3] * dt, twist[3:] * dt)
        return pose, twist

    def commit(self, pose, twist) -> None:
        self.pose, self.twist = pose, twist

    def refuse(self) -> None:
        """The candidate was refused: stay at the last accepted pose, at rest."""
        self.twist = np.zeros(6)
