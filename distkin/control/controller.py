"""The device controller: admittance control with a position-level joint PD at 1 kHz.

Kühne et al., Sec. III-D and Fig. 9.  Each cycle, on the arrival of a state frame:

1. check the reading (finite, in range, device status) -- :func:`.safety.check_reading`;
2. forward kinematics, warm-started Gauss-Newton on the generated kernels
   (:meth:`~.kinematics.KinematicModel.forward`);
3. rotate the force/torque reading into the base frame and step the admittance model
   with the scene's virtual environment (:mod:`.admittance`);
4. refuse a candidate set point that is unreachable or near-singular (keep the last
   one, at rest);
5. inverse kinematics of the set point;
6. joint PD(I) at position level, ``tau = KP e + KI ∫e + KD ė_f`` with KP = 110,
   KI = 0, KD = 0.4 and the error derivative low-pass filtered with time constant
   T = 700 ms, discretised by the forward Euler method as the paper says:
   ``d_f[k] = d_f[k-1] + (dt/T) (d[k-1] - d_f[k-1])`` with ``d[k] = (e[k] - e[k-1])/dt``
   (stable for dt < 2T; :meth:`Controller.filter_derivative`);
7. for L > 6, the torque distribution: the PD torques are projected onto the range of
   ``J`` (``tau = J (JᵀJ)⁻¹ Jᵀ tau_pd``), which removes the internal-force component
   that redundant independent joint controllers fight over and keeps the wrench
   ``Jᵀ tau`` they exert on the platform (Kühne et al. Sec. III-C, the projection
   method of their ref. [27]); gravity compensation adds the minimum-norm torques
   ``J (JᵀJ)⁻¹ (0, 0, m g, 0, 0, 0)``, and the optional hand feed-forward
   ``-J (JᵀJ)⁻¹ w_h`` balances the measured hand wrench;
8. saturation at the torque limit, by one common factor (the direction of the wrench
   is kept); efforts that are not all finite are not scaled: the loop sends zero
   torque and enters the fault state (:mod:`.loop`, event ``nonfinite_torque``);
9. the command frame.

Safety: a watchdog (no *valid* frame within ``watchdog_ms`` -> zero torque and the fault
state; the window is measured in wall time and, while rejected frames keep arriving, also
in device time ``t_us``: a device that only sends rejected readings trips it like a silent
one, and so does one that only repeats old frames, which the link drops), the fault
state at once on a frame with the ``ESTOP`` bit (zero torque from that frame on), the
fault state left after ``recover_frames`` *consecutive* valid frames at poses inside
the safe workspace (``workspace_m``, ``workspace_rad`` about home: a rejected frame, an
empty read or a pose outside starts the count again; a run whose first pose is outside
starts in the fault state) with the set point re-initialised at the measured pose, a
stop near singular poses (also when the forward kinematics fails to converge and the
last estimate is near-singular), rejection of NaN or out-of-range readings, and zero torque on every way out of :meth:`Controller.run`.  The device's
``DEVICE_WATCHDOG`` and ``SATURATED`` bits are counted (summary) and logged as events,
at most one per bit per second of device time.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .admittance import Admittance, substeps
from .cycle_kernels import CYCLE_OUT, cycle_params
from .kinematics import _rot
from .loop import run_loop
from .protocol import MODE_HOLD, MODE_RUN, MODE_ZERO_TORQUE, float32_floor
from .runlog import CsvLog, EventLog
from .safety import FAULT, RUN, STOPPED, DeviceStatus, check_limits, check_reading

__all__ = ["Controller", "CycleResult", "GRAVITY", "SCALING", "RUN", "FAULT", "STOPPED"]

#: gravitational acceleration assumed by the gravity compensation, m/s²
GRAVITY = 9.81
#: Stocco's scaling S = diag(15 N, 15 N, 15 N, 1 N·m, 1 N·m, 1 N·m) (Kühne et al.
#: Sec. III-B-2); J S^-1 is the dimensionally homogeneous Jacobian whose smallest
#: singular value the guard watches
SCALING = np.array([15.0, 15.0, 15.0, 1.0, 1.0, 1.0])



class CycleResult:
    """What one control cycle decided (a work buffer)."""

    __slots__ = ("mode", "torques", "accepted", "reason", "pose", "desired", "wrench",
                 "fk_iterations", "fk_residual", "saturated")

    def __init__(self):
        self.mode, self.torques, self.accepted, self.reason = MODE_ZERO_TORQUE, None, True, ""
        self.pose = self.desired = self.wrench = None
        self.fk_iterations, self.fk_residual, self.saturated = 0, 0.0, False


class Controller:
    """Admittance + PD controller of one device: the scheme of Kühne et al. [1]_,
    Sec. III-D and Fig. 9 (the hand wrench drives a virtual mass-damper whose pose is
    the set point of a joint PD at position level, 1 kHz; the module docstring lists
    the cycle's steps).

    Parameters
    ----------
    scene : distkin.control.config.ControlScene
        Its ``pd.torque_limit`` a number > 0 and its ``safety.saturation_ms`` >= 0 and
        ``saturation_share`` in (0, 1], finite (InputError otherwise, as the scene
        loader's: :func:`.safety.check_limits`).
    model : distkin.control.kinematics.KinematicModel
    log_prefix : str or None
        Write ``PREFIX.cycles.csv`` and ``PREFIX.events.jsonl``.
    fused : bool
        With a compiled model (default), run steps 2-8 of a cycle as one compiled call;
        False: the Python methods below (on the model's kernels), the reference.

    Examples
    --------
    >>> from distkin.control import builtin_scene, model_of, run_loopback
    >>> scene = builtin_scene()
    >>> out = run_loopback(scene, model_of(scene), 0.05)   # doctest: +SKIP
    >>> # over a serial link: Controller(scene, model).run(open_link(url), 5.0)

    References
    ----------
    .. [1] M. Kühne, J. Potzy, R. García-Rochín, P. van der Smagt, A. Peer, *Design and
       Evaluation of a Haptic Interface With Octopod Kinematics*, IEEE/ASME
       Transactions on Mechatronics (README's reference [2]).
    """

    #: consecutive forward-kinematics failures tolerated (the last command is repeated)
    #: before the fault state (zero torque)
    MAX_FK_FAILURES = 10
    #: wall time to wait for the first valid state frame, s
    STARTUP_TIMEOUT_S = 10.0

    def __init__(self, scene, model, *, log_prefix=None, fused: bool = True):
        # the loader's checks of the saturation, for a scene made in Python
        check_limits(scene.pd, scene.safety, scene.effort_unit)
        self.scene = scene
        self.model = model
        self.L = model.L
        self.dt_nominal = 1.0 / scene.rate_hz
        self.adm = Admittance(scene.mass, scene.damping, scene.environment,
                              kernels=model.compiled)
        self.pd = scene.pd
        self.safety = scene.safety
        # prismatic legs: readings are leg lengths, checked against each leg's range
        self._lo = self._hi = None
        if scene.joint_range is not None:
            r = np.asarray(scene.joint_range, dtype=float)
            self._lo, self._hi = r[:, 0].copy(), r[:, 1].copy()
        self.weight = float(model.mass[0, 0]) * GRAVITY
        self.pose = np.array(model.home, dtype=float)
        self.state = RUN
        self.started = False
        self._fused = None
        if fused and model.compiled is not None:
            # the fused cycle (steps 2-8 in one compiled call): its parameters, and the
            # PD state as one (5, L) buffer (rows e_prev, d_prev, d_f, ∫e; flag)
            self._fused = cycle_params(self.pd, self.safety, self.adm, self.weight, SCALING,
                                       period=self.dt_nominal,
                                       revolute=bool(np.all(model.revolute)))
            self._pd_state = np.zeros((5, self.L))
            # the revolute legs' ranges for the candidate's test (check_pose)
            inf = np.full(self.L, np.inf)   # (full turns are ±inf: KinematicModel)
            self._ranges = (np.array([-inf, inf]) if model.joint_lo is None else
                            np.array([model.joint_lo, model.joint_hi], dtype=float))
        self._reset_pd()
        self.refusing = False
        self.refused = 0
        self.saturated_cycles = 0
        #: cycles whose computed efforts were not all finite (sent as zero torque)
        self.nonfinite_cycles = 0
        #: device time (µs) of the last run spent in fault or hold (:func:`.loop.run_loop`)
        self.fault_us = 0
        self.max_abs_torque = 0.0
        self.device_status = DeviceStatus()     # the device's own status bits
        self.rejected_frames = 0
        self.last_rejection = ""
        cols = (["t_wall", "t_dev", "seq", "status", "state", "mode", "compute_s", "period_s",
                 "fk_iter", "fk_res", "refused", "saturated"]
                + [f"x_{n}" for n in ("x", "y", "z", "rx", "ry", "rz")]
                + [f"xd_{n}" for n in ("x", "y", "z", "rx", "ry", "rz")]
                + [f"{a}_{n}" for a in ("f", "m") for n in "xyz"]
                + [f"tau_{i}" for i in range(self.L)])
        self.prefix = log_prefix
        self.log = CsvLog(f"{log_prefix}.cycles.csv" if log_prefix else None, cols)
        self.events = EventLog(f"{log_prefix}.events.jsonl" if log_prefix else None)

    # -- the per-cycle computation (no I/O) ---------------------------------------------
    def _reset_pd(self):
        self.e_prev = None
        self.d_prev = np.zeros(self.L)
        self.de_f = np.zeros(self.L)
        self.e_int = np.zeros(self.L)
        if self._fused is not None:
            self._pd_state[:] = 0.0

    def filter_derivative(self, e, dt):
        """One step of the error-derivative low-pass of Sec. III-D, forward Euler.

        The filter ``T ḋ_f = d - d_f`` (T = ``derivative_filter_s``) stepped explicitly:
        ``d_f[k] = d_f[k-1] + (dt/T) (d[k-1] - d_f[k-1])``, where ``d[k] = (e[k] -
        e[k-1]) / dt`` is the raw difference quotient; T = 0 passes ``d[k]`` through.
        The step is ``min(dt, max(T, h))/T`` (h the nominal period; review: the loop
        steps with the measured gap, up to 5 periods, and ``1 - dt/T`` below -1 made the
        filter diverge for a T >= h that the load check accepts): a late frame moves the
        filter at most all the way to ``d[k-1]``; for dt <= h nothing changes (the
        delay-margin analysis' model).  Returns the filtered derivative (L,) in rad/s.
        """
        pd = self.pd
        d_raw = np.zeros(self.L) if self.e_prev is None else (e - self.e_prev) / dt
        if pd.derivative_filter_s > 0:
            T = pd.derivative_filter_s
            self.de_f = self.de_f + (min(dt, max(T, self.dt_nominal)) / T) * (
                self.d_prev - self.de_f)
        else:
            self.de_f = d_raw
        self.d_prev = d_raw
        self.e_prev = e
        return self.de_f

    def singular_values(self, J):
        """Smallest and largest singular value of the scaled Jacobian ``J S^-1``."""
        ck = self.model.compiled
        if ck is not None:
            return ck.singular_values(J, SCALING)
        Js = J / SCALING
        ev = np.linalg.eigvalsh(Js.T @ Js)
        return math.sqrt(max(float(ev[0]), 0.0)), math.sqrt(max(float(ev[-1]), 0.0))

    def sigma_min(self, J) -> float:
        """Smallest singular value of the scaled Jacobian ``J S^-1``."""
        return self.singular_values(J)[0]

    def near_singular(self, J) -> bool:
        """``J`` (L, 6) is near a singularity: ``sigma_min(J S^-1) < safety.sigma_min``
        (a parallel singularity: the platform can move without the cranks) or its
        condition number exceeds ``safety.max_condition`` (near a serial singularity at
        the reach boundary)."""
        if self.model.compiled is None and not np.all(np.isfinite(J)):
            return True
        lo, hi = self.singular_values(J)          # compiled: NaN where J is not finite
        if lo != lo:
            return True
        return lo < self.safety.sigma_min or hi > self.safety.max_condition * lo

    def check_pose(self, pose, current=None):
        """Why a commanded pose must be refused ("" if it is acceptable).

        Returns
        -------
        reason : str
            "unreachable" (a leg cannot close, or a joint lies outside its leg's
            range, modulo 2π, further than at the set point ``current`` if given),
            "singular" (:meth:`near_singular`),
            "" otherwise.
        q : ndarray (L,) or None
            The crank angles of the pose, when reachable.
        """
        q, ok = self.model.ik(pose)
        if not ok or not np.all(np.isfinite(q)):
            return "unreachable", None
        excess = self.model.range_excess(q)
        if np.any(excess > 0.0):
            # a joint outside its range: refused where its excess grows over the current
            # set point's (none: over 0), so that a set point that starts past a limit
            # (a pose estimated from quantised encoders, review) can move back
            before = (np.zeros(self.L) if current is None else
                      self.model.range_excess(self.model.ik(current)[0]))
            before = np.where(np.isfinite(before), before, 0.0)
            if np.any(excess > before):
                return "unreachable", None
        if self.near_singular(self.model.jacobian(pose)):
            return "singular", None
        return "", q

    def outside_workspace(self, pose) -> str:
        """Why ``pose`` lies outside the safe workspace (``safety.workspace_m`` and
        ``workspace_rad`` about the home pose; "" inside it)."""
        d = np.asarray(pose, dtype=float) - self.model.home
        i = int(np.argmax(np.abs(d[:3])))
        if not abs(d[i]) <= self.safety.workspace_m:
            return (f"{'xyz'[i]} {d[i] * 1e3:+.1f} mm from home, beyond the safe workspace "
                    f"±{self.safety.workspace_m * 1e3:g} mm")
        i = int(np.argmax(np.abs(d[3:])))
        if not abs(d[3 + i]) <= self.safety.workspace_rad:
            return (f"r{'xyz'[i]} {np.degrees(d[3 + i]):+.1f}° from home, beyond the safe "
                    f"workspace ±{np.degrees(self.safety.workspace_rad):.4g}°")
        return ""

    def check_reading(self, frame) -> str:
        """Why a state frame must be rejected ("" if it is acceptable;
        :func:`.safety.check_reading`)."""
        return check_reading(frame, self.L, self.safety, self._lo, self._hi)

    def start_at(self, pose) -> None:
        """(Re)initialise at a measured pose: set point = pose, at rest, filters reset."""
        self.pose = np.array(pose, dtype=float)
        self.adm.reset(self.pose)
        self._reset_pd()
        self.refusing = False

    def base_wrench(self, ws):
        """The sensor's wrench ``ws`` (6,) rotated from the platform frame into the base
        frame at the current pose estimate (N, N·m)."""
        ck = self.model.compiled
        if ck is not None:
            w = np.empty(6)
            ck.rotate_wrench(self.pose[3:], ws, w)
            return w
        R = _rot(self.pose[3:])
        return np.concatenate([R @ ws[:3], R @ ws[3:]])

    def estimate(self, angles):
        """Forward kinematics warm-started at the last estimate (cold start: home)."""
        fk = self.model.forward(angles, self.pose, max_iter=8 if self.started else 40)
        return fk

    def joint_torques(self, q_des, angles, J, w, dt: float):
        """Steps 6-8 of the module doc: joint PD(I) on ``q_des - angles`` (rad, modulo 2π) with the
        forward-Euler filtered derivative, the torque distribution and gravity
        compensation, and the saturation by one common factor.

        ``J`` (L, 6) at the measured pose, ``w`` (6,) the measured wrench in the base
        frame (for the hand feed-forward).  Returns ``(tau (L,) N·m, saturated)``.
        """
        # PD(I) at position level with a low-pass filtered derivative (forward Euler)
        e = self.model.joint_step(q_des, angles)    # cranks: modulo 2π (review)
        pd = self.pd
        limit = float32_floor(pd.torque_limit)       # the wire's float32 keeps it
        tau = pd.kp * e + pd.kd * self.filter_derivative(e, dt)
        if pd.ki:
            self.e_int = np.clip(self.e_int + e * dt, -limit / pd.ki, limit / pd.ki)
            tau = tau + pd.ki * self.e_int
        # torque distribution (L > 6: remove internal forces) and gravity compensation
        w_ff = -w if pd.hand_feedforward else np.zeros(6)
        if pd.gravity_compensation:
            w_ff[2] += self.weight
        ck = self.model.compiled
        if pd.distribution == "projected" and ck is not None:
            out = np.empty(self.L)
            if not ck.project(J, tau, w_ff, out):
                raise np.linalg.LinAlgError("Singular matrix")
            tau = out
        elif pd.distribution == "projected":
            tau = J @ np.linalg.solve(J.T @ J, J.T @ tau + w_ff)
        elif pd.gravity_compensation or pd.hand_feedforward:
            tau = tau + J @ np.linalg.solve(J.T @ J, w_ff)
        saturated = False
        peak = float(np.max(np.abs(tau)))
        if not math.isfinite(peak):
            return tau, False    # NaN/inf: not scaled; the loop sends zero torque, faults
        if peak > limit:
            tau = tau * (limit / peak)
            saturated = True
        return tau, saturated

    def compute(self, frame, dt: float) -> CycleResult:
        """One control cycle on a *checked* state frame (steps 2-8 of the module doc).

        With compiled kinematics the steps run as one compiled call
        (:meth:`_compute_fused`, ``cycle`` of :mod:`.cycle_kernels`); without, as the
        Python methods of this class (the reference route; tests/control holds the
        two together).  ``dt`` (s, the gap since the last frame) must be positive, finite
        and at most :data:`.admittance.MAX_SUBSTEPS` nominal periods, on both routes
        (InputError, before anything changes; the loop clamps it to 5 periods).
        """
        substeps(dt, self.dt_nominal)
        if self._fused is not None:
            return self._compute_fused(frame, dt)
        r = CycleResult()
        fk = self.estimate(frame.angles)
        r.fk_iterations, r.fk_residual = fk.iterations, fk.residual
        if not fk.converged or fk.residual > self.safety.max_fk_residual:
            if self.started and self.near_singular(self.model.jacobian(self.pose)):
                # near a singularity the FK cannot converge: the singular stop, at the
                # last estimate (not a repeated command)
                r.pose, r.wrench = self.pose, self.base_wrench(frame.wrench)
                r.reason, r.accepted, r.mode = "singular_stop", False, MODE_HOLD
                r.torques = np.zeros(self.L)
                return r
            r.reason = "fk_failed"         # no decision: the loop repeats its last command
            r.accepted = False
            r.mode = None
            return r
        self.pose = fk.pose
        if not self.started:
            self.start_at(fk.pose)
            self.started = True
        w = self.base_wrench(frame.wrench)
        r.pose, r.wrench = self.pose, w
        J = self.model.jacobian(self.pose)
        if self.near_singular(J):
            r.reason = "singular_stop"
            r.accepted = False
            r.mode = MODE_HOLD
            r.torques = np.zeros(self.L)
            return r
        if self.state != RUN:
            r.torques = np.zeros(self.L)
            return r
        cand_pose, cand_twist = self.adm.propose(w, dt, max_step=self.dt_nominal)
        why, q_des = self.check_pose(cand_pose, current=self.adm.pose)
        if why:
            self.adm.refuse()
            self.refused += 1
            r.accepted, r.reason = False, why
            q_des, _ = self.model.ik(self.adm.pose)
        else:
            self.adm.commit(cand_pose, cand_twist)
        r.desired = self.adm.pose
        tau, r.saturated = self.joint_torques(q_des, frame.angles, J, w, dt)
        r.mode, r.torques = MODE_RUN, tau
        return r

    _REASONS = ("", "fk_failed", "singular_stop", "", "unreachable", "singular", "")

    def _compute_fused(self, frame, dt: float) -> CycleResult:
        """:meth:`compute` by the fused compiled cycle: the same decisions and state."""
        r = CycleResult()
        L = self.L
        prm, env = self._fused
        adm = self.adm
        out = np.empty(CYCLE_OUT + L)
        code = self.model.compiled.cycle(frame.angles, frame.wrench, float(dt),
                                         bool(self.started), self.state == RUN, self.pose,
                                         adm.pose, adm.twist, self._pd_state, prm, env,
                                         self._ranges, out)
        r.fk_residual, r.fk_iterations = float(out[24 + L]), int(out[25 + L])
        r.reason = self._REASONS[code]
        if code == 1:
            r.accepted = False
            r.mode = None
            return r
        self.pose = r.pose = out[0:6]
        r.wrench = out[6:12]
        if not self.started:                                # start_at (in the kernel)
            self.refusing = False
            self.started = True
        adm.pose, adm.twist = out[12:18], out[18:24]
        r.torques = out[24:24 + L]
        if code == 2:
            r.accepted = False
            r.mode = MODE_HOLD
            return r
        if code == 3:
            return r
        if code in (4, 5):
            self.refused += 1
            r.accepted = False
        r.desired = adm.pose
        if code == 6:
            raise np.linalg.LinAlgError("Singular matrix")
        r.mode, r.saturated = MODE_RUN, bool(out[26 + L])
        return r

    # -- the loop ---------------------------------------------------------------------
    def _event(self, name, t0, frame=None, **info):
        t_dev = None if frame is None else frame.t_us * 1e-6
        self.events.add(time.perf_counter() - t0, name,
                        **({"t_dev": t_dev} if t_dev is not None else {}), **info)

    def run(self, link, seconds: float, *, wall_limit: float | None = None) -> dict:
        """Run the loop over ``link`` for ``seconds`` of device time.

        The cycle allocates no reference cycles, so the cyclic garbage collector has
        nothing to do during a run; the summary's ``gc_collections`` counts the
        collections that happened anyway (0 in the runs of BENCHMARKS.md), and its
        ``loop_cpu_share`` the CPU time the loop's thread took over the loop's wall time
        (near 1 when ``[device] busy_wait_us`` keeps it polling the port).

        The run ends when the device clock has advanced by ``seconds`` since the first
        frame, when the wall clock reaches ``wall_limit`` (default ``2 seconds + 10``),
        when no valid frame arrives within :attr:`STARTUP_TIMEOUT_S` (``no_device``;
        ``no_valid_frames`` when frames came but all were rejected, the error naming the
        last reason, e.g. "device reports e-stop"), when the first
        state frame holds another number of joint angles than the model has legs
        (``device_mismatch``, exit code 2: the scene is not the device's), on a
        disconnect, on SIGINT/SIGTERM, or on an internal error.  Every way out
        sends zero torque (best effort if the link is gone).  The exit code of each
        reason is :data:`.runlog.EXIT_CODES`: 0 ``completed``; 2 ``device_mismatch``;
        2 also when the device or the link ended the run (``no_device``, ``no_valid_frames``,
        ``disconnect``, ``wall_limit``); 130 ``interrupted``; 1 ``internal_error``.

        Returns
        -------
        dict
            The summary printed by ``distkin control`` (``cycles``, ``seconds``,
            ``rate_hz``, ``cycle_p50_ms``, ``cycle_p99_ms``, ``bad_frames``,
            ``watchdog_trips``, ``safety_events``, ``final_state``, ``fault_seconds``,
            ``nonfinite_cycles``, ``exit_reason``, ...; :func:`.runlog.run_summary`) with
            ``exit_code`` and, after a disconnect or a failure, ``error``.
        """
        return run_loop(self, link, seconds, wall_limit)
