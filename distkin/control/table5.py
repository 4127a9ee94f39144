"""Table V emulated: the paper's validation experiments on the simulated Octo.

Kühne et al., Sec. III-D: "The end effector was positioned in the poses of its worst
case output capabilities, as indicated by our theoretical analysis.  Then, smoothed
position step inputs were commanded in the respective directions.  For each output
capability five trials were executed and the mean was computed. [...] To validate worst
case forces and torques, the end effector was blocked."  Table V lists the measured
minima beside the analysis.

Here the device is the simulated plant of :mod:`.plant` (rigid platform, motors with
the reflected rotor inertia and the torque-speed line, encoders, F/T noise) driven by
the controller's own joint PD, torque distribution and saturation
(:meth:`.controller.Controller.joint_torques`; KP = 110, KI = 0, KD = 0.4, derivative
filter 700 ms, forward Euler):

1. the worst-case poses and directions come from the study's analysis
   (:func:`distkin.indices.study.evaluate_poses` over a grid; the direction of a worst
   case is the normal of the nearest facet of the sliced zonotope, eqs. (14)-(15));
2. **force, torque** -- the end effector is blocked at the worst pose; the set point
   takes a smoothed step (raised cosine, ``rise_s``) along ``(JᵀJ)⁻¹ w``, the pose
   increment whose joint-PD torques push the block along the worst wrench direction
   ``w`` at zero torque (force) or zero force (torque), applied to the joint set point
   as its first-order image ``J (JᵀJ)⁻¹ w`` (the block holds the pose); the torques
   saturate at the
   nominal ±2.5 N·m (continuous); the reading is the wrench ``Jᵀ τ`` on the block plus
   the sensor noise, averaged over the last ``hold_s`` (gravity compensation off: the
   block carries the platform);
3. **velocity, acceleration** -- the end effector is free at the worst pose; the set
   point takes a smoothed step of ``step_m`` (``step_rad`` for the angular rows) along
   the worst direction, towards the workspace centre; the torques may reach the stall
   torque ±34.2 N·m (eq. (7)'s limit) and the drives follow their torque-speed line;
   the result is the peak velocity (the velocity rows) and the peak acceleration (the
   acceleration rows) of the platform along the direction;
4. five trials of the blocked rows (different sensor-noise seeds), the mean; the free
   rows are deterministic (encoders quantise, nothing is random) and run once.

What differs from the analysis, on purpose: the plant carries the motors' reflected
rotor inertia (Maxon RE 40, ``13² × 1.42e-5 kg·m²`` per crank) that eq. (7) leaves out,
the redundant Octo's controller distributes torques by the minimum-norm projection (the
worst case of the zonotope assumes the best distribution), and the drives' speed limit
is a torque-speed line (no-load 55 rad/s), not a box.  The paper's experiment also
stopped short of the velocity and acceleration maxima ("to avoid excessive wear").

What the free rows measure, and why their velocity can exceed the analysis: the
analysis' worst-case velocity is that of its slice (the platform translating at zero
angular velocity, at the worst pose); the emulated platform is free, leaves the worst
pose at once, and the joint PD (about 10 Hz, lightly damped: KD = 0.4 behind a 700 ms
filter, :mod:`.delay_margin`) at the stall torque does not hold its orientation.  In
the Octo's velocity row (40 mm step) it turns at 43 rad/s when its speed along the
worst direction peaks at 4.4 m/s, twice the analysis' 2.24 m/s (which the cranks'
speed limit allows only together with such a rotation), and at up to 87 rad/s within
the 150 ms.  The rows report that
rotation (``off_slice_peak``); a figure that exceeds the analysis is not a capability
of the slice.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..errors import InputError, NotFoundError
from ..spatial import rotate_pose_scalar as rotate_pose
from .controller import Controller
from .kinematics import load_model
from .plant import Plant
from .protocol import MODE_RUN

__all__ = ["ROWS", "PAPER_TABLE5", "worst_cases", "run_table5"]

#: row, unit, generator, slice, kind (blocked / free)
ROWS = (("force", "N", "wrench", (0, 1, 2), "blocked"),
        ("torque", "N·m", "wrench", (3, 4, 5), "blocked"),
        ("velocity", "m/s", "twist", (0, 1, 2), "free"),
        ("angular_velocity", "rad/s", "twist", (3, 4, 5), "free"),
        ("acceleration", "m/s²", "acceleration", (0, 1, 2), "free"),
        ("angular_acceleration", "rad/s²", "acceleration", (3, 4, 5), "free"))

#: Kühne et al., Table V: (experiment, simulation) of the Octo's minimum capabilities
PAPER_TABLE5 = {"force": (15.27, 16.02), "torque": (0.68, 0.75), "velocity": (1.12, 2.93),
                "angular_velocity": (24.02, 84.44), "acceleration": (459.52, 1289.19),
                "angular_acceleration": (7051.21, 34341.13)}


def _direction(G, limit, keep):
    """Unit direction (6,) of the worst case of ``G·box`` in the slice ``keep`` and its
    value: the nearest facet's normal restricted to the slice (eqs. (14)-(15))."""
    from ..indices.zonotope import _facets
    L = G.shape[1]
    n, h, _ = _facets(G[None], np.zeros((1, L)), np.full((1, L), float(limit)))
    nS = n[0][:, list(keep)]
    den = np.linalg.norm(nS, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(den > 1e-12 * den.max(), h[0] / den, np.inf)
    k = int(np.argmin(ratio))
    d = np.zeros(6)
    d[list(keep)] = nS[k] / den[k]
    return d, float(ratio[k])


def worst_cases(mech, poses, actuators):
    """Worst pose, direction and analysis value of every row of :data:`ROWS`.

    Parameters
    ----------
    mech : RSSMechanism
    poses : ndarray (N, 6)
        The grid searched (m, rad).
    actuators : dict
        ``nominal_torque``, ``stall_torque`` (N·m), ``velocity`` (rad/s).

    Returns
    -------
    dict row -> {"pose" (6,), "direction" (6,), "analysis" (float)}
    """
    from ..indices.capability import output_generators
    from ..indices.study import evaluate_poses
    ok, vals = evaluate_poses(mech, poses, actuators=actuators, warn=False)
    P = np.asarray(poses)[ok]
    # the study's rule (:func:`distkin.indices.study.study_chunk`): a pose whose J float64
    # does not resolve, or whose value is NaN (a flagged near-flat pose), is no worst
    # case; np.argmin would pick the first NaN
    usable = ~np.asarray(vals["J_unresolved"], dtype=bool)
    lim = {"wrench": actuators["nominal_torque"], "twist": actuators["velocity"],
           "acceleration": actuators["stall_torque"]}
    out = {}
    for row, _, gen, keep, _ in ROWS:
        v = np.where(usable & np.isfinite(vals[row]), vals[row], np.inf)
        if not np.isfinite(v).any():
            raise NotFoundError(f"expected a pose of the grid with a finite, resolved "
                                f"{row} value, got none of {len(v)} reachable poses",
                                field="poses")
        i = int(np.argmin(v))
        J = mech.jacobian(P[i][None])
        G = output_generators(J, mass=np.diag(mech.cartesian_mass_matrix()))[gen][0]
        d, v = _direction(G, lim[gen], keep)
        centre = mech.home - P[i]
        part = slice(0, 3) if keep[0] == 0 else slice(3, 6)
        if np.dot(d[part], centre[part]) < 0:       # move towards the workspace centre
            d = -d
        out[row] = {"pose": P[i], "direction": d, "analysis": float(vals[row][i]),
                    "analysis_facet": v}
    return out


def _smooth(t, rise):
    """Raised-cosine step from 0 to 1 over ``rise`` seconds."""
    return 1.0 if t >= rise else 0.5 - 0.5 * math.cos(math.pi * t / rise)


def _blocked(ctl, model, pose, w_dir, motors, *, rise, hold, dt, rng, trace=None):
    """Blocked end effector: the mean wrench (6,) on the block over the last ``hold`` s.

    ``trace``: a dict filled, when given, with every cycle's time ``t`` (s), the wrench
    ``Jᵀτ`` on the block (``wrench``, (n, 6), N and N·m; no sensor noise) and the sensor
    reading averaged (``reading``: ``Jᵀτ`` plus the noise, NaN before the last ``hold``
    s); the noise is drawn as without it (the mean is the same to the bit)."""
    q_block, _ = model.ik(pose)
    J = model.jacobian(pose)
    step = np.linalg.solve(J.T @ J, w_dir)
    # twice what saturates the nominal torque (KP e = 2 tau_nom for the largest joint
    # error); the set point moves by the first-order image J·Δx of the pose step Δx (the
    # block keeps the pose: (JᵀJ)⁻¹ w can be a large pose step whose joint image is small,
    # where the exact IK of the stepped pose would be far from linear)
    e_step = J @ step
    e_step *= 2 * ctl.pd.torque_limit / ctl.pd.kp / np.max(np.abs(e_step))
    ctl._reset_pd()
    acc, n = np.zeros(6), 0
    t, total = 0.0, rise + 2 * hold
    while t < total:
        q_des = q_block + _smooth(t, rise) * e_step
        tau, _ = ctl.joint_torques(q_des, q_block, J, np.zeros(6), dt)
        tau = np.clip(tau, -motors.stall_torque, motors.stall_torque)   # at rest
        wrench = J.T @ tau
        reading = np.full(6, np.nan)
        if t >= total - hold:
            reading = wrench + np.r_[rng.normal(0, motors.force_noise, 3),
                                     rng.normal(0, motors.torque_noise, 3)]
            acc += reading
            n += 1
        if trace is not None:
            trace.setdefault("t", []).append(t)
            trace.setdefault("wrench", []).append(wrench)
            trace.setdefault("reading", []).append(reading)
        t += dt
    return acc / n


def _free(ctl, model, pose, direction, motors, *, angular, amplitude, rise, seconds, dt,
          trace=None):
    """Free end effector: peak speed and peak acceleration along ``direction``, the end
    stops hit, and the peak speed of the other slice (rad/s during a translation, m/s
    during a rotation).

    ``trace``: a dict filled, when given, with every cycle's time ``t`` (s), the speed
    (``velocity``) and the acceleration (``acceleration``) along ``direction`` whose
    maxima are the peaks returned (m/s and m/s², or rad/s and rad/s² for ``angular``)."""
    plant = Plant(model, motors, seed=0)
    plant.pose = np.array(pose, dtype=float)
    plant.q, _ = model.ik(plant.pose)
    ctl._reset_pd()
    part = slice(3, 6) if angular else slice(0, 3)
    other = slice(0, 3) if angular else slice(3, 6)
    off_peak = 0.0
    d = direction[part]
    step = amplitude * d
    v_peak = a_peak = 0.0
    prev = np.zeros(3)
    t = 0.0
    while t < seconds:
        s = _smooth(t, rise)
        target = rotate_pose(pose, (0 if angular else s) * step, (s if angular else 0) * step)
        q_des, _ = model.ik(target)
        J = model.jacobian(plant.pose)
        tau, _ = ctl.joint_torques(q_des, plant.q, J, np.zeros(6), dt)
        plant.step(tau, MODE_RUN, dt)
        vel = plant.twist[part]
        v_along, a_along = float(np.dot(vel, d)), float(np.dot(vel - prev, d)) / dt
        v_peak = max(v_peak, v_along)
        a_peak = max(a_peak, a_along)
        if trace is not None:
            for key, v in (("t", t), ("velocity", v_along), ("acceleration", a_along)):
                trace.setdefault(key, []).append(v)
        off_peak = max(off_peak, float(np.linalg.norm(plant.twist[other])))
        prev = vel.copy()
        t += dt
    return v_peak, a_peak, plant.end_stop_hits, off_peak


def _reachable_step(model, row, w, angular, amplitude, units):
    """InputError unless every leg closes along the step of row ``row`` from its worst
    pose ``w["pose"]`` along ``w["direction"]`` (eight points of it, the last the
    target): :func:`_free` drives the controller towards those targets."""
    part = slice(3, 6) if angular else slice(0, 3)
    step = amplitude * np.asarray(w["direction"])[part]
    for s in np.linspace(0.125, 1.0, 8):
        target = rotate_pose(w["pose"], (0 if angular else s) * step,
                             (s if angular else 0) * step)
        if not model.ik(target)[1]:
            key = "step_angle" if angular else "step"
            field, unit, f = (units or {}).get(key, ("step_rad" if angular else "step_m",
                                                     "rad" if angular else "m", 1.0))
            legs = [int(j) + 1 for j in np.flatnonzero(~(model.margins(target) >= 0.0))]
            raise InputError(
                f"expected a {key.replace('_', ' ')} whose targets the device reaches, got "
                f"{amplitude * f:.6g} {unit}: the {row.replace('_', ' ')} row's step from "
                f"its worst pose leaves the workspace {100 * s:.0f} % of the way"
                + (f" (legs {legs} do not close)" if legs else ""), field=field,
                hint="a smaller step (Table V: 40 mm and 0.4 rad)")


def _row_trace(raw, kind, gen, keep, direction) -> dict:
    """The trace of one trial of a row, along its worst direction, in the row's unit:
    ``t`` (s, from the start of the smoothed step) and ``value``: for a blocked row
    the wrench ``Jᵀτ`` on the block (no sensor noise) and ``reading``, the sensor's
    (``Jᵀτ`` plus its noise) over the last ``hold_s`` that the row averages (NaN
    before); for a free row the speed (twist rows) or the acceleration (acceleration
    rows) whose peak is the row's value."""
    t = np.asarray(raw["t"], dtype=float)
    if kind == "blocked":
        k, d = list(keep), np.asarray(direction)[list(keep)]
        return {"t": t, "value": np.asarray(raw["wrench"])[:, k] @ d,
                "reading": np.asarray(raw["reading"])[:, k] @ d}
    return {"t": t, "value": np.asarray(raw["velocity" if gen == "twist"
                                            else "acceleration"], dtype=float)}


def run_table5(mech_name: str = "octo", *, poses=None, scene=None, trials: int = 5,
               step_m: float = 0.040, step_rad: float = 0.4, rise_s: float = 0.020,
               hold_s: float = 0.100, free_s: float = 0.150, actuators=None, units=None,
               traces: bool = False):
    """The emulated experiments of Table V (module docstring).

    Parameters
    ----------
    mech_name : str
        Preset of the device (the paper's Table V is the Octo's).
    poses : ndarray (N, 6), optional
        The grid searched for the worst cases (m, rad); default a coarse Table II grid at
        ±30° (25 mm, 10°).
    scene : ControlScene, optional
        PD gains and motors (default the built-in ``control_octo.toml``).
    trials : int
        Repetitions of the blocked rows (sensor-noise seeds) averaged.
    units : dict, optional
        {"step": (field, unit, factor from m), "step_angle": (field, unit, factor from
        rad)}: the names and units a refused step is given in (default SI).
    traces : bool
        Also return the time trace of the first trial of every row ("trace"; default
        off: the numbers of the table are the same to the bit either way).

    Raises
    ------
    InputError
        A free row's step whose targets the device does not reach (every leg closes at
        eight points of the smoothed step, :func:`_reachable_step`): the controller was
        driven towards an unreachable pose and the row reported a velocity of it (QA
        2026-11-29: step = 1000 mm gave 17.3 m/s, 7.7 times the analysis, no warning).

    Returns
    -------
    dict row -> {"unit", "emulated", "analysis", "paper_experiment", "paper_simulation",
    "pose", "direction", "end_stop_hits", "kind", "trial_values"} ("trial_values": each
    trial's value, the row's unit, whose mean is "emulated"); the free rows also
    "off_slice_peak" (the peak angular speed, rad/s, during a translational step; the
    peak linear speed, m/s, during a rotational one: "off_slice_unit") -- the analysis'
    velocity is that of its slice (zero angular velocity), and the free platform does
    not stay in it (module docstring).  With ``traces``, every row also "trace"
    (:func:`_row_trace`: numpy arrays, not JSON; the ``table5`` query keeps them out of
    its result and draws them).
    """
    from ..indices.study import ACTUATORS
    from ..indices.workspace import table2_grid
    from .config import builtin_scene
    # review: trials = 0 averaged an empty list into NaN rows (a RuntimeWarning only)
    if isinstance(trials, bool) or not isinstance(trials, (int, np.integer)) or trials < 1:
        raise InputError(f"expected trials a whole number >= 1, got {trials!r}",
                         field="trials")
    for name, v in (("step_m", step_m), ("step_rad", step_rad), ("rise_s", rise_s),
                    ("hold_s", hold_s), ("free_s", free_s)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)) \
                or not 0 < v < math.inf:
            raise InputError(f"expected {name} a positive finite number, got {v!r}",
                             field=name)
    actuators = dict(ACTUATORS if actuators is None else actuators)
    scene = scene or builtin_scene()
    model = load_model(mech_name)
    mech = model.mech
    if poses is None:
        g = table2_grid(mech.z0, step=0.025, rot_deg=30.0, rot_step_deg=10.0)
        poses = g.poses(np.arange(g.n_positions))
    wc = worst_cases(mech, poses, actuators)
    dt = 1.0 / scene.rate_hz
    motors = scene.simulator.motors
    nominal = replace(scene, pd=replace(scene.pd, torque_limit=actuators["nominal_torque"],
                                        gravity_compensation=False, hand_feedforward=False))
    stall = replace(scene, pd=replace(scene.pd, torque_limit=actuators["stall_torque"],
                                      hand_feedforward=False))
    out = {}
    for row, unit, gen, keep, kind in ROWS:
        w = wc[row]
        vals, hits, off, raw = [], 0, None, {}
        for k in range(trials if kind == "blocked" else 1):
            tr = raw if traces and k == 0 else None       # the first trial's trace
            if kind == "blocked":
                ctl = Controller(nominal, model)
                wr = _blocked(ctl, model, w["pose"], w["direction"], motors, rise=rise_s,
                              hold=hold_s, dt=dt, rng=np.random.default_rng(k), trace=tr)
                vals.append(float(np.dot(wr[list(keep)], w["direction"][list(keep)])))
            else:
                ctl = Controller(stall, model)
                angular = keep[0] == 3
                _reachable_step(model, row, w, angular, step_rad if angular else step_m,
                                units)
                vp, ap, h, off = _free(ctl, model, w["pose"], w["direction"], motors,
                                       angular=angular,
                                       amplitude=step_rad if angular else step_m,
                                       rise=rise_s, seconds=free_s, dt=dt, trace=tr)
                hits += h
                vals.append(vp if gen == "twist" else ap)
        exp, sim = PAPER_TABLE5[row]
        out[row] = {"unit": unit, "emulated": float(np.mean(vals)),
                    "analysis": w["analysis"], "paper_experiment": exp,
                    "paper_simulation": sim, "pose": w["pose"].tolist(),
                    "direction": w["direction"].tolist(), "end_stop_hits": hits,
                    "kind": kind, "trial_values": vals}
        if traces:
            out[row]["trace"] = _row_trace(raw, kind, gen, keep, w["direction"])
        if off is not None:       # the free rows: how far the motion left the slice
            out[row]["off_slice_peak"] = off
            out[row]["off_slice_unit"] = "m/s" if keep[0] == 3 else "rad/s"
    return out
