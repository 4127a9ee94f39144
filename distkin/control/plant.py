"""Simulated device physics: rigid platform, motors with capstan, encoders, F/T sensor, hand.

Kühne et al., Sec. III-B.3 and III-D:

* the platform is a rigid body with the Cartesian mass matrix
  ``M̂ = diag(m, m, m, I, I, I)`` (m = 0.17 kg, I = 3e-4 kg·m²), driven through the
  actuator torques as the wrench ``Jᵀ tau`` (eq. (3));
* each crank is driven by a Maxon RE 40 through a capstan of ratio 1:13.  The motor
  rotor inertia (1.42e-5 kg·m², Maxon RE 40 datasheet -- not in the paper) reflects to
  the crank as ``13² J_rotor`` and to the platform as ``Jᵀ (13² J_rotor) J``;
* the drive delivers at most the stall torque (±34.2 N·m at the crank) falling
  linearly with speed to zero at the no-load speed ``w_nl``, chosen so that the nominal
  torque ±2.5 N·m is available at the nominal speed ±51 rad/s:
  ``w_nl = 51 / (1 - 2.5/34.2) = 55.0 rad/s``;
* encoders are quantised (``counts`` per motor revolution, times 13 at the crank) and
  the six-axis force/torque sensor adds white noise.

The equations of motion, with ``V = (v, omega)``,

.. math:: (\\hat M + J^T J_r J)\\dot V = J^T(\\tau - b\\,\\dot q) + w_h + w_g,

neglect the velocity-product terms and the mass of the legs (stated simplifications of
the simulator, not of the controller).  Integrated with semi-implicit Euler at the
device period.  The hand is a scripted force source on the end-effector centre.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..spatial import rotate_pose_scalar as rotate_pose
from .kinematics import _rot
from .protocol import MODE_HOLD, MODE_RUN, STATUS_SATURATED

__all__ = ["Motors", "HandScript", "Plant"]


@dataclass(frozen=True)
class Motors:
    """Motor + capstan + encoder + sensor parameters (joint side unless stated).

    Defaults: Kühne et al. Sec. III-B.3/III-D (ratio, stall and nominal torque, nominal
    speed); Maxon RE 40 datasheet (rotor inertia); our choices (encoder resolution,
    friction, noise), stated here.
    """

    gear: float = 13.0
    rotor_inertia: float = 1.42e-5          # kg·m², motor side
    stall_torque: float = 34.2              # N·m at the crank
    nominal_torque: float = 2.5             # N·m
    nominal_speed: float = 51.0             # rad/s at the crank
    friction: float = 0.01                  # N·m·s/rad viscous, at the crank
    counts_per_rev: int = 2000              # motor side (500-line encoder, quadrature)
    force_noise: float = 0.02               # N, standard deviation
    torque_noise: float = 0.0005            # N·m, standard deviation
    gravity: float = 9.81                   # m/s², along -z of the base frame

    @property
    def no_load_speed(self) -> float:
        return self.nominal_speed / (1.0 - self.nominal_torque / self.stall_torque)

    @property
    def joint_inertia(self) -> float:
        return self.gear ** 2 * self.rotor_inertia

    @property
    def resolution(self) -> float:
        """Encoder step at the crank, rad."""
        return 2.0 * math.pi / (self.counts_per_rev * self.gear)


@dataclass(frozen=True)
class HandScript:
    """A scripted hand: piecewise-linear force (N, base frame) on the end-effector centre.

    ``points`` is a sorted tuple of ``(t, fx, fy, fz)`` knots (s, N); before the first
    knot and after the last the force is that of the nearest knot.
    """

    points: tuple = ()

    def force(self, t: float) -> np.ndarray:
        pts = self.points
        if not pts:
            return np.zeros(3)
        if t <= pts[0][0]:
            return np.array(pts[0][1:], dtype=float)
        for a, b in zip(pts, pts[1:]):
            if t <= b[0]:
                s = (t - a[0]) / (b[0] - a[0]) if b[0] > a[0] else 1.0
                return np.array([a[i] + s * (b[i] - a[i]) for i in (1, 2, 3)])
        return np.array(pts[-1][1:], dtype=float)


@dataclass
class Plant:
    """State and integrator of the simulated device.

    Parameters
    ----------
    model : distkin.control.kinematics.KinematicModel
    motors : Motors
    hand : HandScript
    seed : int
        Seed of the sensor noise.
    """

    model: object
    motors: Motors = field(default_factory=Motors)
    hand: HandScript = field(default_factory=HandScript)
    seed: int = 0
    hold_gains: tuple = (110.0, 0.4)

    def __post_init__(self):
        self.rng = np.random.default_rng(self.seed)
        self.M = np.asarray(self.model.mass, dtype=float)
        self.m = float(self.M[0, 0])
        self.t = 0.0
        self.pose = np.array(self.model.home, dtype=float)
        self.twist = np.zeros(6)
        self.q, _ = self.model.ik(self.pose)
        self.qdot = np.zeros(self.model.L)
        self.tau = np.zeros(self.model.L)
        self.hand_wrench = np.zeros(6)
        self.saturated = False
        self.end_stop_hits = 0
        self._q_hold = None
        # compiled drives and dynamics when the model has compiled kernels (the same
        # equations; the numpy route below is the reference)
        self._ck = getattr(self.model, "compiled", None)
        mo = self.motors
        self._w_nl = mo.no_load_speed
        self._dyn = np.array([mo.friction, self.m * mo.gravity, mo.joint_inertia, 0.0])
        self._noise = np.repeat([mo.force_noise, mo.torque_noise], 3)

    def drive(self, tau_cmd) -> np.ndarray:
        """The torque the drives deliver for ``tau_cmd`` at the current speed (N·m)."""
        mo = self.motors
        tau = np.asarray(tau_cmd, dtype=float)
        if self._ck is not None:
            out = np.empty(tau.shape[0])
            self.saturated = bool(self._ck.drive(tau, self.qdot, mo.stall_torque,
                                                 self._w_nl, out))
            return out
        motoring = np.sign(tau) == np.sign(self.qdot)
        avail = np.where(motoring,
                         mo.stall_torque * np.clip(1.0 - np.abs(self.qdot) / mo.no_load_speed,
                                                   0.0, 1.0),
                         mo.stall_torque)
        out = np.clip(tau, -avail, avail)
        self.saturated = bool(np.any(out != tau))
        return out

    def step(self, tau_cmd, mode: int, dt: float) -> None:
        """Advance the physics by ``dt`` (s) under the command (N·m, crank side)."""
        mo = self.motors
        if mode == MODE_RUN:
            self._q_hold = None
            tau = self.drive(tau_cmd)
        elif mode == MODE_HOLD:
            if self._q_hold is None:
                self._q_hold = self.q.copy()
            kp, kd = self.hold_gains
            tau = self.drive(kp * (self._q_hold - self.q) - kd * self.qdot)
        else:
            self._q_hold = None
            self.saturated = False
            tau = np.zeros(self.model.L)
        self.tau = tau
        f = self.hand.force(self.t)
        self.hand_wrench = np.concatenate([f, np.zeros(3)])
        if self._ck is not None:
            self._dyn[3] = dt
            L = self.model.L
            out = np.empty(12 + L)
            ok = self._ck.plant_dynamics(self.pose, self.twist, self.q, self.qdot, tau,
                                         self.hand_wrench, self.M, self._dyn, out)
            self._advance(bool(ok), out[0:6], out[6:12], out[12:], dt)
            return
        J = self.model.jacobian(self.pose)
        w = J.T @ (tau - mo.friction * self.qdot) + self.hand_wrench
        w[2] -= self.m * mo.gravity
        Meff = self.M + mo.joint_inertia * (J.T @ J)
        ok = bool(np.all(np.isfinite(Meff)) and np.all(np.isfinite(w)))
        if ok:
            twist = self.twist + dt * np.linalg.solve(Meff, w)
            pose = rotate_pose(self.pose, twist[:3] * dt, twist[3:] * dt)
            q, ok = self.model.ik(pose)
            ok = ok and bool(np.all(np.isfinite(q)))
        self._advance(ok, pose if ok else None, twist if ok else None,
                      q if ok else None, dt)

    def _advance(self, ok, pose, twist, q, dt) -> None:
        if ok:
            self.pose, self.twist = pose, twist
            self.qdot = (q - self.q) / dt
            self.q = q
        else:  # a mechanical end stop: the platform stops where it was
            self.end_stop_hits += 1
            self.twist = np.zeros(6)
            self.qdot = np.zeros(self.model.L)
        self.t += dt

    def encoders(self) -> np.ndarray:
        """Quantised crank angles (L,), rad."""
        r = self.motors.resolution
        return np.round(self.q / r) * r

    def sensor(self) -> np.ndarray:
        """F/T reading (6,) in the sensor (platform) frame: the hand wrench plus noise."""
        Rt = _rot(self.pose[3:]).T
        # six standard normals scaled: the numbers of normal(0, σ_f, 3) then
        # normal(0, σ_t, 3) (the generator draws element by element; 0 + σ z = σ z)
        noise = self.rng.standard_normal(6) * self._noise
        out = np.empty(6)
        out[:3] = Rt @ self.hand_wrench[:3] + noise[:3]
        out[3:] = Rt @ self.hand_wrench[3:] + noise[3:]
        return out

    def status(self) -> int:
        return STATUS_SATURATED if self.saturated else 0
