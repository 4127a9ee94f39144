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

from ..errors import InputError
from ..spatial import rotate_pose_scalar as rotate_pose
from .kinematics import _rot

__all__ = ["Spring", "Wall", "Admittance", "rotation_log", "spring_torque",
           "step_spectral_radius", "check_step", "substeps", "MAX_SUBSTEPS"]


def _vector(value, field: str, n: int, *, nonneg: bool = False, positive: bool = False,
            unit: str = "") -> np.ndarray:
    """``value`` as n finite floats (>= 0 or > 0 if asked); InputError naming ``field``,
    the expected and the received value otherwise."""
    want = (f"{n} finite numbers" + (" > 0" if positive else " >= 0" if nonneg else "")
            + (f" ({unit})" if unit else ""))
    try:
        if isinstance(value, (bool, np.bool_, str, bytes)):
            raise TypeError
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"expected {want}, got {value!r}", field=field) from None
    if a.shape != (n,) or not np.all(np.isfinite(a)) or (positive and not np.all(a > 0)) \
            or (nonneg and not np.all(a >= 0)):
        got = a.tolist() if a.size <= 12 else f"an array of shape {a.shape}"
        raise InputError(f"expected {want}, got {got}", field=field)
    return a


def rotation_log(R) -> np.ndarray:
    """Rotation vector (3,) rad of a rotation matrix (the inverse of Rodrigues' formula).

    Beyond 90° (cos θ < 0) the axis comes from the symmetric part, ``(R + Rᵀ)/2 - cos θ
    I = (1 - cos θ) a aᵀ``, its sign from the skew part: near 180° the skew part
    ``2 sin θ a`` vanishes (review: a rotation by exactly π gave the zero vector, and
    one within 1e-12 rad of π an axis from rounding).  Compiled for the control cycle
    by :mod:`.cycle_common` (plain loops and ``math``)."""
    sk = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    s = 0.5 * math.sqrt(sk[0] * sk[0] + sk[1] * sk[1] + sk[2] * sk[2])
    c = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    th = math.atan2(s, c)
    if c < 0.0:
        j = 0
        for i in range(1, 3):
            if R[i, i] > R[j, j]:
                j = i
        a = np.empty(3)
        for i in range(3):
            a[i] = 0.5 * (R[i, j] + R[j, i]) - (c if i == j else 0.0)
        n = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
        if a[0] * sk[0] + a[1] * sk[1] + a[2] * sk[2] < 0.0:
            n = -n
        return a * (th / n)
    if s < 1e-12:
        return 0.5 * sk
    return sk * (th / (2.0 * s))


def spring_torque(e, k) -> np.ndarray:
    """The torque (3,) N·m of a rotational spring ``U = ½ eᵀ diag(k) e`` at the rotation
    vector ``e = log(R R0ᵀ)`` (rad), for a spatial angular velocity (``R <- exp(ω dt)
    R``): ``τ = -∂U/∂φ = -J_l(e)⁻ᵀ diag(k) e``, with

    .. math:: J_l^{-T}(e) = I + \\tfrac12 [e]_\\times + c\\,[e]_\\times^2,\\qquad
              c = \\frac{1 - (\\theta/2)\\cot(\\theta/2)}{\\theta^2}
              \\;(\\to 1/12 + \\theta^2/720),

    the inverse of SO(3)'s left Jacobian (``de = J_l(e)⁻¹ dφ``; the closed form is
    the standard one of Lie-group texts, e.g. Barfoot, *State Estimation for
    Robotics*, Ch. 7; θ = |e| <= π here, so sin(θ/2) > 0).  For an isotropic ``k`` (the built-in scene's) it is ``-k e``
    bit for bit; ``-diag(k) e`` alone is not a gradient when ``k`` is anisotropic, and
    an undamped spring rendered with it swung its energy by ±25 % (QA).  Compiled for
    the control cycle by :mod:`.cycle_common` (plain loops and ``math``)."""
    t = np.empty(3)
    for i in range(3):
        t[i] = -(k[i] * e[i])
    if k[0] == k[1] and k[1] == k[2]:
        return t
    th2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
    if th2 < 1e-6:
        c = 1.0 / 12.0 + th2 / 720.0
    else:
        h = 0.5 * math.sqrt(th2)
        c = (1.0 - h * math.cos(h) / math.sin(h)) / th2
    # t = -(ke + ½ e × ke + c e × (e × ke)), ke = -t
    a = np.array([e[1] * t[2] - e[2] * t[1], e[2] * t[0] - e[0] * t[2],
                  e[0] * t[1] - e[1] * t[0]])                        # e × t = -(e × ke)
    b = np.array([e[1] * a[2] - e[2] * a[1], e[2] * a[0] - e[0] * a[2],
                  e[0] * a[1] - e[1] * a[0]])                        # e × (e × t)
    for i in range(3):
        t[i] = t[i] + 0.5 * a[i] + c * b[i]
    return t


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
        a = _vector(self.anchor, "spring.anchor", 6, unit="m x3, rad x3")
        object.__setattr__(self, "_k", _vector(self.stiffness, "spring.stiffness", 6,
                                               nonneg=True, unit="N/m x3, N·m/rad x3"))
        object.__setattr__(self, "_d", _vector(self.damping, "spring.damping", 6,
                                               nonneg=True,
                                               unit="N·s/m x3, N·m·s/rad x3"))
        object.__setattr__(self, "_p0", a[:3].copy())
        object.__setattr__(self, "_R0t", _rot(a[3:]).T)

    def wrench(self, pose, twist) -> np.ndarray:
        """Spring-damper wrench (6,) at ``pose`` (6,) with ``twist`` (6,): N, N·m."""
        e = np.empty(6)
        e[:3] = pose[:3] - self._p0
        e[3:] = rotation_log(_rot(pose[3:]) @ self._R0t)
        t = np.empty(6)
        t[:3] = -self._k[:3] * e[:3]
        t[3:] = spring_torque(e[3:], self._k[3:])     # the potential's gradient
        return t - self._d * twist


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

    def __post_init__(self):
        n = _vector(self.normal, "wall.normal", 3)
        if abs(float(np.linalg.norm(n)) - 1.0) > 1e-9:
            raise InputError(f"expected a unit normal (|n| = 1: the penetration is n . p - "
                             f"offset in m), got {n.tolist()} of length "
                             f"{float(np.linalg.norm(n)):.6g}", field="wall.normal")
        _vector([self.offset], "wall.offset", 1, unit="m")
        _vector([self.stiffness], "wall.stiffness", 1, positive=True, unit="N/m")
        _vector([self.damping], "wall.damping", 1, nonneg=True, unit="N·s/m")

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
        self.mass = _vector(mass, "admittance.mass", 6, positive=True,
                            unit="kg x3, kg·m² x3")
        self.damping = _vector(damping, "admittance.damping", 6, nonneg=True,
                               unit="N·s/m x3, N·m·s/rad x3")
        self.environment = tuple(environment)
        for i, e in enumerate(self.environment):
            if not isinstance(e, (Spring, Wall)):
                raise InputError(f"expected a Spring or a Wall, got {e!r}",
                                 field=f"environment[{i}]")
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

    def propose(self, hand_wrench, dt, max_step=None):
        """One semi-implicit Euler step; returns the candidate ``(pose, twist)``.

        Nothing is committed: the caller checks the candidate (reachability,
        singularity guard) and calls :meth:`commit` or :meth:`refuse`.  ``dt`` (s) must
        be positive and finite (InputError).  ``max_step`` (s; the loop's nominal
        period, whose stability :func:`check_step` checked at load): a longer ``dt``
        (a late frame: the loop steps with the measured gap, up to 5 periods) is taken
        as ``ceil(dt / max_step)`` equal steps, the hand's wrench held (review: one
        step of 5 periods multiplies the state of a stiff spring that the nominal step
        keeps stable by up to the spectral radius at 5h, and a few late frames in a row
        made the set point diverge); ``dt <= max_step`` is one step, as before; at most
        :data:`MAX_SUBSTEPS` steps (:func:`substeps` refuses a longer gap).
        """
        n = substeps(dt, max_step)
        h = dt / n
        rot = rotate_pose if self.kernels is None else self.kernels.rotate_pose
        pose, twist = self.pose, self.twist
        for _ in range(n):
            w = hand_wrench + self.environment_wrench(pose, twist)
            twist = twist + h * (w - self.damping * twist) / self.mass
            pose = rot(pose, twist[:3] * h, twist[3:] * h)
        return pose, twist

    def commit(self, pose, twist) -> None:
        self.pose, self.twist = pose, twist

    def refuse(self) -> None:
        """The candidate was refused: stay at the last accepted pose, at rest."""
        self.twist = np.zeros(6)


#: the most equal steps one late frame's gap is cut into (10 s at 1 kHz): a longer gap
#: is refused (review of e5ba69d: a gap of 1e303 periods looped for ever on the Python
#: route, and an infinite one overflowed the compiled route's count into an accepted
#: step; the loop itself clamps a gap to 5 periods)
MAX_SUBSTEPS = 10_000


def substeps(dt: float, max_step) -> int:
    """How many equal steps :meth:`Admittance.propose` takes for ``dt`` (s): 1 up to
    ``max_step`` (None or 0: always 1), else ``ceil(dt / max_step)`` (a relative
    1e-9 of ``dt`` over ``max_step`` is rounding, one step).  ``dt`` must be positive
    and finite, and at most :data:`MAX_SUBSTEPS` steps (InputError)."""
    if not 0.0 < dt < math.inf:
        raise InputError(f"expected a time step dt > 0 finite (s), got {dt!r}", field="dt")
    if not max_step or dt <= max_step * (1.0 + 1e-9):
        return 1
    if dt > MAX_SUBSTEPS * max_step:
        raise InputError(f"expected a gap dt of at most {MAX_SUBSTEPS} periods "
                         f"({MAX_SUBSTEPS * max_step:.6g} s at the period {max_step:.6g} s), "
                         f"got {dt!r} s ({dt / max_step:.6g} periods)", field="dt")
    return int(math.ceil(dt / max_step * (1.0 - 1e-9)))


def step_spectral_radius(mass, damping, environment, period: float) -> tuple:
    """Spectral radius of one :meth:`Admittance.propose` step, linearised at rest at the
    springs' anchor with every wall pressed: ``(translation, rotation)``.

    Per block (translation: M = diag(mass[:3]), K = Σ spring stiffness + Σ wall
    ``k n nᵀ``, D = damping + Σ spring damping + Σ wall ``d n nᵀ``; rotation likewise
    with the springs' rotational parts) semi-implicit Euler is

    .. math:: V' = V + h M^{-1}(-K x - D V), \\qquad x' = x + h V',

    stable iff the radius is below 1; for one axis that is ``h² k/m + 2 h d/m < 4``
    (Jury's test on the trace ``2 - h²k/m - h d/m`` and determinant ``1 - h d/m``).
    A virtual environment rendered at a radius above 1 gains energy every period.
    """
    h = float(period)
    out = []
    for blk in (slice(0, 3), slice(3, 6)):
        m = np.asarray(mass, dtype=float)[blk]
        K = np.zeros((3, 3))
        D = np.diag(np.asarray(damping, dtype=float)[blk])
        for e in environment:
            if e.kind == "spring":
                K += np.diag(e._k[blk])
                D += np.diag(e._d[blk])
            elif blk.start == 0:
                n = np.asarray(e.normal, dtype=float)
                K += e.stiffness * np.outer(n, n)
                D += e.damping * np.outer(n, n)
        Mi = np.diag(1.0 / m)
        A = np.zeros((6, 6))
        A[3:, :3] = -h * Mi @ K                              # V' from x
        A[3:, 3:] = np.eye(3) - h * Mi @ D                   # V' from V
        A[:3, :3] = np.eye(3) + h * A[3:, :3]                # x' = x + h V'
        A[:3, 3:] = h * A[3:, 3:]
        out.append(float(np.max(np.abs(np.linalg.eigvals(A)))))
    return tuple(out)


def check_step(mass, damping, environment, rate_hz: float, field: str = "admittance"):
    """InputError when the virtual model, stepped at ``rate_hz``, is unstable
    (:func:`step_spectral_radius` above 1): it names the block, the radius and the
    rate, and what brings it back (more virtual mass, less stiffness or damping)."""
    rho = step_spectral_radius(mass, damping, environment, 1.0 / rate_hz)
    for name, r in zip(("translation", "rotation"), rho):
        if r > 1.0 + 1e-12:
            raise InputError(
                f"expected a virtual mass-damper and environment that the {rate_hz:g} Hz "
                f"step keeps stable (spectral radius <= 1; per axis h²k/m + 2hd/m < 4), "
                f"got a {name} spectral radius of {r:.6g}", field=field,
                hint="raise the virtual mass or lower the stiffness or damping")
    return rho
