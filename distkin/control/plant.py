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

A device with prismatic legs (SPS/UPS; Rojas et al.'s platforms) has the same motor on
a ball screw instead (:class:`LinearDrives`): the joint is the leg length (m), the
effort a force (N), the transmission ``2π / lead`` rad per m, so that the motor's
stall torque, rotor inertia, speed and encoder counts appear at the leg as a force,
a reflected mass ``(2π/lead)² J_rotor``, a speed and a length quantum.  The equations
below hold for either, in joint units (rad and N·m, or m and N).

The equations of motion, with ``V = (v, omega)`` and the crank rates ``q̇ = J V``,

.. math:: (\\hat M + J^T J_r J)\\dot V = J^T(\\tau - b\\,\\dot q - J_r \\dot J V)
          + w_h + w_g,

the platform's (isotropic inertia: no gyroscopic term) and the rotors' (``J_r q̈`` with
``q̈ = J V̇ + J̇ V``): the kinetic energy ``½ Vᵀ M̂ V + ½ J_r |q̇|²`` changes only by the
power of the efforts.  They neglect the mass of the legs (a stated simplification of
the simulator, not of the controller).  Integrated with semi-implicit Euler at the
device period; ``J̇ V`` by central differences of J along V (:meth:`Plant.jdot_v`: from
the pose and twist of the step alone, so that the rounding of one step's pose does not
feed the next step's velocity, as a rate taken from the last step's crank angles did).
Review: without the term an unforced, undamped platform coasted at a constant twist
while its reflected inertia changed, and its kinetic energy drifted by 167 % in 0.4 s
at any step size (tests/control/test_plant_energy.py); with it the drift is first
order in h.  The hand is a scripted force source on the
end-effector centre.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..spatial import rotate_pose_scalar as rotate_pose
from .end_stops import (NEAR_FLOORS, ReachApproach, load_solver, passive_twist, reach_floor,
                        slide)
from .kinematics import _rot, apparent_mass
from .protocol import MODE_HOLD, MODE_RUN, STATUS_SATURATED

__all__ = ["Motors", "LinearDrives", "drives_for", "HandScript", "Plant"]


def _check(obj, lower: dict, *, above: tuple = ()) -> None:
    """Refuse drive parameters that make no drive: each ``name`` of ``lower`` must be a
    finite real number ``> 0`` (``"positive"``) or ``>= 0`` (``"nonneg"``) or any finite
    (``"finite"``); each ``(big, small)`` of ``above`` needs ``big > small`` (the stall
    effort above the nominal one: the torque-speed line's no-load speed divides by their
    difference).  InputError naming the field, the expected and the received value."""
    for name, kind in lower.items():
        v = getattr(obj, name)
        if kind == "count":
            if not isinstance(v, (int, np.integer)) or isinstance(v, bool) or v < 1:
                raise InputError(f"expected an integer >= 1, got {v!r}", field=name)
            continue
        ok = (isinstance(v, (int, float, np.integer, np.floating))
              and not isinstance(v, bool) and math.isfinite(v))
        want = {"positive": "a finite number > 0", "nonneg": "a finite number >= 0",
                "finite": "a finite number"}[kind]
        if not ok or (kind == "positive" and not v > 0) or (kind == "nonneg" and not v >= 0):
            raise InputError(f"expected {want}, got {v!r}", field=name)
    for big, small in above:
        if not getattr(obj, big) > getattr(obj, small):
            raise InputError(f"expected {big} above {small} = {getattr(obj, small)!r} (the "
                             f"torque-speed line falls from the stall effort to the nominal "
                             f"one at the nominal speed), got {getattr(obj, big)!r}",
                             field=big)


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

    def __post_init__(self):
        _check(self, {"gear": "positive", "rotor_inertia": "nonneg",
                      "stall_torque": "positive", "nominal_torque": "positive",
                      "nominal_speed": "positive", "friction": "nonneg",
                      "counts_per_rev": "count", "force_noise": "nonneg",
                      "torque_noise": "nonneg", "gravity": "finite"},
               above=(("stall_torque", "nominal_torque"),))

    #: the unit of the effort at the joint: a torque at the crank
    effort_unit = "N·m"
    #: the device's own position hold (MODE_HOLD): the paper's KP = 110 N·m/rad and
    #: KD = 0.4 N·m·s/rad (Sec. III-D)
    hold_gains = (110.0, 0.4)

    @property
    def stall_effort(self) -> float:
        """Stall torque at the crank, N·m."""
        return self.stall_torque

    @property
    def nominal_effort(self) -> float:
        """Nominal (continuous) torque at the crank, N·m."""
        return self.nominal_torque

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
class LinearDrives:
    """Motor + ball screw + encoder + sensor parameters of prismatic legs.

    The same Maxon RE 40 as :class:`Motors`, given motor side (stall torque 34.2/13 =
    2.63 N·m, nominal torque 2.5/13 = 0.192 N·m at 51 x 13 = 663 rad/s, rotor inertia,
    encoder), on a lossless ball screw of ``lead`` m per revolution (our choice, 10 mm:
    a transmission of 2π/lead = 628 rad/m).  At the leg (the properties) that is a
    stall force of 1653 N, a nominal force of 121 N at 1.06 m/s, a reflected mass of
    5.6 kg, viscous friction of 23 N·s/m (the Octo's 0.01 N·m·s/rad at the crank,
    brought to the motor and through the screw; ``friction`` overrides it, N·s/m at
    the leg) and a length quantum of 5 µm.  Screw efficiency and backdriving losses
    are not modelled (a stated simplification).
    """

    lead: float = 0.01                                                 # m/rev
    rotor_inertia: float = Motors.rotor_inertia                        # kg·m², motor side
    motor_stall_torque: float = Motors.stall_torque / Motors.gear      # N·m, motor side
    motor_nominal_torque: float = Motors.nominal_torque / Motors.gear  # N·m, motor side
    motor_nominal_speed: float = Motors.nominal_speed * Motors.gear    # rad/s, motor side
    motor_friction: float = Motors.friction / Motors.gear ** 2         # N·m·s/rad, motor
    counts_per_rev: int = Motors.counts_per_rev                        # motor side
    force_noise: float = Motors.force_noise                            # N
    torque_noise: float = Motors.torque_noise                          # N·m
    gravity: float = Motors.gravity                                    # m/s²
    friction: float | None = None                                      # N·s/m at the leg

    def __post_init__(self):
        _check(self, {"lead": "positive", "rotor_inertia": "nonneg",
                      "motor_stall_torque": "positive", "motor_nominal_torque": "positive",
                      "motor_nominal_speed": "positive", "motor_friction": "nonneg",
                      "counts_per_rev": "count", "force_noise": "nonneg",
                      "torque_noise": "nonneg", "gravity": "finite"},
               above=(("motor_stall_torque", "motor_nominal_torque"),))
        if not 1e-6 <= self.lead <= 10.0:     # (1e-200 overflowed the ratio's square)
            raise InputError(f"expected a screw lead of 1e-6 .. 10 m per revolution, got "
                             f"{self.lead!r} m", field="lead")
        if self.friction is None:
            object.__setattr__(self, "friction", self.motor_friction * self.ratio ** 2)
        _check(self, {"friction": "nonneg"})

    #: the unit of the effort at the joint: a force along the leg
    effort_unit = "N"

    @property
    def ratio(self) -> float:
        """Motor angle per leg length, rad/m."""
        return 2.0 * math.pi / self.lead

    @property
    def hold_gains(self) -> tuple:
        """The device's position hold: the rotary hold gains at the motor (110/13²
        N·m/rad, 0.4/13² N·m·s/rad) through the screw, N/m and N·s/m."""
        kp, kd = Motors.hold_gains
        s = (self.ratio / Motors.gear) ** 2
        return (kp * s, kd * s)

    @property
    def stall_effort(self) -> float:
        """Stall force at the leg, N."""
        return self.motor_stall_torque * self.ratio

    @property
    def nominal_effort(self) -> float:
        """Nominal (continuous) force at the leg, N."""
        return self.motor_nominal_torque * self.ratio

    @property
    def nominal_speed(self) -> float:
        """Leg speed at the nominal force, m/s."""
        return self.motor_nominal_speed / self.ratio

    @property
    def no_load_speed(self) -> float:
        """Leg speed at which the available force falls to zero, m/s."""
        return self.nominal_speed / (1.0 - self.motor_nominal_torque / self.motor_stall_torque)

    @property
    def joint_inertia(self) -> float:
        """Rotor inertia reflected to the leg, kg."""
        return self.ratio ** 2 * self.rotor_inertia

    @property
    def resolution(self) -> float:
        """Encoder step at the leg, m."""
        return self.lead / self.counts_per_rev


def drives_for(joint: str):
    """The default drives of a device whose legs are ``joint`` ("revolute" or
    "prismatic")."""
    return LinearDrives() if joint == "prismatic" else Motors()


@dataclass(frozen=True)
class HandScript:
    """A scripted hand: piecewise-linear force (N, base frame) on the end-effector centre.

    ``points`` is a sorted tuple of ``(t, fx, fy, fz)`` knots (s, N); before the first
    knot and after the last the force is that of the nearest knot.
    """

    points: tuple = ()

    def __post_init__(self):
        pts = self.points
        if not isinstance(pts, (tuple, list)):
            raise InputError(f"expected a tuple of (t, fx, fy, fz) knots (s, N), got "
                             f"{pts!r}", field="hand")
        for i, p in enumerate(pts):
            if (not isinstance(p, (tuple, list)) or len(p) != 4
                    or not all(isinstance(v, (int, float, np.integer, np.floating))
                               and not isinstance(v, bool) and math.isfinite(v) for v in p)):
                raise InputError(f"expected a knot (t, fx, fy, fz) of 4 finite numbers (s, "
                                 f"N), got {p!r}", field=f"hand[{i}]")
        ts = [p[0] for p in pts]
        if any(b < a for a, b in zip(ts, ts[1:])):
            raise InputError(f"expected knots sorted by time, got times {ts}", field="hand")

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
    hold_gains : (kp, kd) or None
        The device's own position hold in MODE_HOLD, joint units (None: the drives').

    With :class:`LinearDrives` the joint values are leg lengths (m) and the efforts
    forces (N); the methods' "torque" and "crank angle" read so.
    """

    model: object
    motors: object = field(default_factory=Motors)
    hand: HandScript = field(default_factory=HandScript)
    seed: int = 0
    hold_gains: tuple | None = None

    #: sensor readings whose noise is drawn at a time
    NOISE_BLOCK = 512

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
        #: steps whose command held a NaN or ±inf (those joints got zero effort)
        self.nonfinite_commands = 0
        self._q_hold = None
        #: crank legs have reach limits, contacts as the end stops (.end_stops)
        self._reach_contacts = bool(np.any(getattr(self.model, "revolute", False)))
        self._approach = ReachApproach()     # turned back before the floor: a contact too
        #: the least reach margin (L,) a step may end at: :func:`.end_stops.reach_floor`
        #: for a crank leg, -inf for a prismatic one (its stroke is its end stop)
        self.reach_floor = (reach_floor(self.model, self.pose) if self._reach_contacts
                            else np.full(self.model.L, -np.inf))
        if (getattr(self.model, "joint_lo", None) is not None or self._reach_contacts
                or getattr(self.model, "stroke_lo", None) is not None):
            load_solver()              # the end stops' solver: imported now, not mid-loop
        if self.hold_gains is None:
            self.hold_gains = tuple(self.motors.hold_gains)
        # compiled drives and dynamics when the model has compiled kernels (the same
        # equations; the numpy route below is the reference)
        self._ck = getattr(self.model, "compiled", None)
        mo = self.motors
        self._w_nl = mo.no_load_speed
        Meff = apparent_mass(self.M, mo.joint_inertia, self.model.jacobian(self.pose))
        try:
            ok = bool(np.all(np.isfinite(Meff))) and bool(np.all(np.linalg.eigvalsh(
                0.5 * (Meff + Meff.T)) > 0)) and np.allclose(self.M, self.M.T)
        except np.linalg.LinAlgError:
            ok = False
        if not ok:
            raise InputError(f"expected a symmetric mass matrix (kg, kg·m²) whose sum with "
                             f"the reflected rotor inertia J_r JᵀJ is positive definite at "
                             f"home (a body the drives can accelerate), got diag "
                             f"{np.diag(self.M).tolist()} and J_r = {mo.joint_inertia!r}",
                             field="mass")
        # (the last: 1.0 where a displaced pose is in reach for J̇V by its leg lengths
        # alone: a stroke is an end stop, not the edge of J; review: J̇V cut to zero at
        # a stroke end made a sliding platform gain 12 W)
        closes = getattr(self.model, "closes", None)
        self._lengths = 1.0 if closes is not None and closes(self.q) else 0.0
        # (and: 1.0 where the compiled step takes every joint rate modulo 2π; a device
        # mixing cranks and legs gets its rates from joint_step in _advance)
        rev = np.asarray(getattr(self.model, "revolute", np.ones(self.model.L, bool)))
        self._rates = bool(rev.all() or not rev.any())
        self._dyn = np.array([mo.friction, self.m * mo.gravity, mo.joint_inertia, 0.0,
                              self.JDOT_STEP, self._lengths, float(rev.all()), NEAR_FLOORS])
        self._noise = np.repeat([mo.force_noise, mo.torque_noise], 3)
        self._z = np.empty((0, 6))        # sensor noise drawn ahead (see _next_noise)
        self._zi = 0

    def drive(self, tau_cmd) -> np.ndarray:
        """The effort the drives deliver for ``tau_cmd`` at the current speed (N·m; N for
        prismatic legs)."""
        mo = self.motors
        tau = np.asarray(tau_cmd, dtype=float)
        if self._ck is not None:
            out = np.empty(tau.shape[0])
            self.saturated = bool(self._ck.drive(tau, self.qdot, mo.stall_effort,
                                                 self._w_nl, out))
            return out
        motoring = np.sign(tau) == np.sign(self.qdot)
        avail = np.where(motoring,
                         mo.stall_effort * np.clip(1.0 - np.abs(self.qdot) / mo.no_load_speed,
                                                   0.0, 1.0),
                         mo.stall_effort)
        out = np.clip(tau, -avail, avail)
        self.saturated = bool(np.any(out != tau))
        return out

    def step(self, tau_cmd, mode: int, dt: float) -> None:
        """Advance the physics by ``dt`` (s) under the command (joint side: N·m, or N for
        prismatic legs).

        ``dt`` must be a positive finite number and ``tau_cmd`` hold L numbers
        (InputError otherwise: dt = 0 made q̇ = 0/0, a negative dt ran the physics
        backwards, a short command was read past its end by the compiled dynamics).  A
        command that is not finite (NaN, ±inf) is no torque a drive can deliver: its
        amplifier outputs zero for that joint (counted in :attr:`nonfinite_commands`;
        it used to stop the platform dead in the air as if at an end stop).  A step
        that would take a joint past its range (the mechanism's ``range``) meets that
        joint's end stop: the joint stops and the platform moves on with what the other
        legs allow (:func:`.end_stops.slide`); a step that would take a crank leg
        beyond its reach limit (closer than :attr:`reach_floor`) meets it the same way;
        a step that no such slide saves ends where the platform stays, at rest.
        :attr:`end_stop_hits` counts the contacts, and the steps that turn a leg back
        within a few floors of its reach limit (:class:`.end_stops.ReachApproach`).
        """
        if (isinstance(dt, bool) or not isinstance(dt, (int, float, np.integer, np.floating))
                or not 0.0 < dt < math.inf):
            raise InputError(f"expected a time step dt > 0 finite (s), got {dt!r}",
                             field="dt")
        try:
            raw = np.asarray(tau_cmd)
        except (TypeError, ValueError):
            raw = np.array(None)
        if raw.dtype.kind not in "iuf":          # no text, bools, dates, complex
            raise InputError(f"expected {self.model.L} joint efforts "
                             f"({self.motors.effort_unit}) as real numbers, got "
                             f"{tau_cmd!r}", field="tau_cmd")
        tau_cmd = raw.astype(float, copy=False)
        if tau_cmd.shape != (self.model.L,):
            raise InputError(f"expected {self.model.L} joint efforts ({self.motors.effort_unit}),"
                             f" got shape {tau_cmd.shape}", field="tau_cmd")
        finite = np.isfinite(tau_cmd)
        if not finite.all():
            self.nonfinite_commands += 1
            tau_cmd = np.where(finite, tau_cmd, 0.0)
        mo = self.motors
        if mode == MODE_RUN:
            self._q_hold = None
            tau = self.drive(tau_cmd)
        elif mode == MODE_HOLD:
            if self._q_hold is None:
                self._q_hold = self.q.copy()
            kp, kd = self.hold_gains
            tau = self.drive(kp * self.model.joint_step(self._q_hold, self.q)
                             - kd * self.qdot)
        else:
            self._q_hold = None
            self.saturated = False
            tau = np.zeros(self.model.L)
        self.tau = tau
        f = self.hand.force(self.t)
        self.hand_wrench = np.concatenate([f, np.zeros(3)])
        if self._ck is not None:
            # the rotors' -J_r J̇ V too (:meth:`jdot_v`, compiled), in the same call
            self._dyn[3], self._dyn[4] = dt, self.JDOT_STEP
            L = self.model.L
            out = np.empty(13 + 2 * L)
            ok = self._ck.plant_dynamics(self.pose, self.twist, self.q, self.qdot,
                                         tau, self.hand_wrench, self.M, self._dyn,
                                         self.reach_floor, out)
            self._advance(bool(ok), out[0:6], out[6:12], out[12:12 + L], dt,
                          out[12 + L:12 + 2 * L] if self._rates else None, out[-1] > 0.0)
            return
        rotor = -mo.joint_inertia * self.jdot_v()      # the rotors' -J_r J̇ V
        J = self.model.jacobian(self.pose)
        w = J.T @ (tau + rotor - mo.friction * self.qdot) + self.hand_wrench
        w[2] -= self.m * mo.gravity
        Meff = apparent_mass(self.M, mo.joint_inertia, J)
        ok = bool(np.all(np.isfinite(Meff)) and np.all(np.isfinite(w)))
        pose = twist = q = None
        near = False
        if ok:
            twist = self.twist + dt * np.linalg.solve(Meff, w)
            pose = rotate_pose(self.pose, twist[:3] * dt, twist[3:] * dt)
            q, ok = self.model.ik(pose)
            marg, band = self.model.margins(pose), NEAR_FLOORS * self.reach_floor
            ok = ok and bool(np.all(np.isfinite(q))) and not np.any(~(marg >= self.reach_floor))
            near = bool(np.any(marg < band) or np.any(self.model.margins(self.pose) < band))
        self._advance(ok, pose, twist, q, dt, near=near)

    #: the pose step (m, rad) of the central difference of :meth:`jdot_v`
    JDOT_STEP = 1e-4

    def jdot_v(self) -> np.ndarray:
        """``J̇ V`` (L,) at the current pose and twist (rad/s², or m/s² for prismatic
        legs): the derivative of J along the twist, by central differences of the
        Jacobian over pose steps of :data:`JDOT_STEP` (m and rad) either side along
        ``V``; one-sided on the reachable side within a step of the reach boundary, zero
        only where neither displaced pose is in reach (the mechanical end stop of
        :meth:`step` takes over there).  One compiled call where the model is compiled
        (``jdot_v`` of :mod:`.cycle_kernels`: the same kernels, the products summed in
        a fixed order; six calls through the model cost ~30 µs a step)."""
        if self._ck is not None:
            out = np.empty(self.model.L)
            self._ck.jdot_v(self.pose, self.twist, self.JDOT_STEP, self._lengths, out)
            return out
        V = self.twist
        n = math.sqrt(float(V @ V))
        L = self.model.L
        if n == 0.0:
            return np.zeros(L)
        s = self.JDOT_STEP / n
        model = self.model
        dv, dw = V[:3] * s, V[3:] * s
        plus, minus = rotate_pose(self.pose, dv, dw), rotate_pose(self.pose, -dv, -dw)
        # (a displaced pose whose J is not finite, at a reach limit, is out of reach)
        Jp, Jm = (model.jacobian(x) if self._reaches(x) else None for x in (plus, minus))
        ok_p, ok_m = (J is not None and bool(np.all(np.isfinite(J))) for J in (Jp, Jm))
        if ok_p and ok_m:
            return ((Jp - Jm) @ V) / (2.0 * s)
        # within a step of the reach boundary: one-sided on the reachable side (zero let
        # the platform coast while J grew: energy 9-fold before the end stop, review)
        if ok_p:
            return ((Jp - model.jacobian(self.pose)) @ V) / s
        if ok_m:
            return ((model.jacobian(self.pose) - Jm) @ V) / s
        return np.zeros(L)

    def _reaches(self, pose) -> bool:
        """The legs at ``pose`` close: the IK's flag, or on an all-prismatic device with
        strokes every leg length finite and positive (the stroke is an end stop, not
        the edge of the Jacobian: :meth:`~.kinematics.KinematicModel.closes`)."""
        q, ok = self.model.ik(pose)
        return ok or (self._lengths == 1.0 and self.model.closes(q))

    def _advance(self, ok, pose, twist, q, dt, qdot=None, near=False) -> None:
        model = self.model
        pose0, twist0, twist_step = self.pose, self.twist, twist
        stopped = False
        if (not ok and self._lengths == 1.0 and q is not None and model.closes(q)
                and np.all(np.isfinite(pose)) and np.all(np.isfinite(twist))):
            ok = True     # only a stroke refused it: the leg's end stop (below) decides
        # a joint at its range, or a crank leg at its reach limit: an impulse stops it
        # and the platform moves on (.end_stops).  A joint already past its range (a
        # state set from outside) that moves back inward is free (review)
        ex0 = None
        if ok and not model.in_range(q):
            ex0 = model.range_excess(self.q)
            contact = bool(np.any(model.range_excess(q) > ex0))
        else:
            contact = (not ok and self._reach_contacts and pose is not None
                       and np.all(np.isfinite(pose)) and np.all(np.isfinite(twist)))
        if contact:
            self.end_stop_hits += 1
            stopped = True
            slid = slide(model, self.M, self.motors.joint_inertia,
                         rotate_pose if self._ck is None else self._ck.rotate_pose,
                         self.pose, twist, pose, dt,
                         model.range_excess(self.q) if ex0 is None else ex0,
                         self.reach_floor, lengths=self._lengths == 1.0)
            ok = slid is not None
            if ok:
                pose, twist, q = slid
                qdot = None
        if ok and self._reach_contacts and (stopped or near):
            # no energy from nothing near a reach limit (.end_stops.passive_twist)
            twist = passive_twist(model, self.M, self.motors.joint_inertia,
                                  self.m * self.motors.gravity, pose0, twist0, pose, twist,
                                  force=self.hand_wrench[:3], tau=self.tau,
                                  V_step=twist_step, dt=dt)
        if self._approach.turned_back(model, pose0, pose, bool(ok and self._reach_contacts and (
                stopped or near)), self.reach_floor) and not stopped:
            self.end_stop_hits += 1
        if ok:
            self.pose, self.twist = pose, twist
            # the short way round: a crank passing ±180° is no 2π/dt rate (review)
            self.qdot = model.joint_step(q, self.q) / dt if qdot is None else qdot
            self.q = q
        else:  # a mechanical end stop: the platform stops where it was
            if not stopped:
                self.end_stop_hits += 1
            self.twist = np.zeros(6)
            self.qdot = np.zeros(model.L)
        self.t += dt

    def encoders(self) -> np.ndarray:
        """Quantised joint readings (L,): crank angles (rad) or leg lengths (m)."""
        r = self.motors.resolution
        return np.round(self.q / r) * r

    def _next_noise(self) -> np.ndarray:
        """The sensor noise of the next reading (6,): six standard normals scaled by
        σ_f, σ_f, σ_f, σ_t, σ_t, σ_t.  Drawn ``NOISE_BLOCK`` readings at a time: the
        generator draws element by element, so the readings get the same numbers as
        one draw of six per reading."""
        if self._zi == self._z.shape[0]:
            self._z = self.rng.standard_normal((self.NOISE_BLOCK, 6)) * self._noise
            self._zi = 0
        self._zi += 1
        return self._z[self._zi - 1]

    def sensor(self) -> np.ndarray:
        """F/T reading (6,) in the sensor (platform) frame: the hand wrench plus noise."""
        Rt = _rot(self.pose[3:]).T
        noise = self._next_noise()
        out = np.empty(6)
        out[:3] = Rt @ self.hand_wrench[:3] + noise[:3]
        out[3:] = Rt @ self.hand_wrench[3:] + noise[3:]
        return out

    def readings(self) -> np.ndarray:
        """What the device sends (L + 6,): :meth:`encoders`, then :meth:`sensor`; by
        one compiled call when the model has compiled kernels (the same encoder
        values; the sensor's within an ulp of float64: its 3 x 3 products are summed
        in a fixed order instead of numpy's)."""
        if self._ck is None:
            return np.concatenate([self.encoders(), self.sensor()])
        out = np.empty(self.model.L + 6)
        self._ck.readings(self.q, self.motors.resolution, self.pose, self.hand_wrench,
                          self._next_noise(), out)
        return out

    def status(self) -> int:
        return STATUS_SATURATED if self.saturated else 0
