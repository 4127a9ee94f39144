"""The controller scene: a TOML file naming the device, the admittance model, the
virtual environment, the PD gains, the safety limits and the simulator's hand.

Everything is SI (m, rad, N, N·m, kg, s); there is no ``[units]`` table.  Example
(``examples/control_octo.toml``)::

    [device]
    preset = "octo"                 # a distkin.mechanisms preset, or instead:
    # mechanism = "rus8_device.toml"  # the [mechanism] of a distkin scene (rss, or legs
    #                                 # all revolute or all prismatic), path relative to
    #                                 # this file
    rate_hz = 1000
    realtime = false                # true: SCHED_FIFO for the loop and the simulator
    busy_wait_us = 0                # poll the port this long before sleeping (µs)

    [admittance]                    # Kühne et al. Fig. 9: admittance scheme
    mass = [1.0, 1.0, 1.0, 0.005, 0.005, 0.005]      # kg x3, kg·m² x3
    damping = [15, 15, 15, 0.1, 0.1, 0.1]            # N·s/m x3, N·m·s/rad x3

    [[environment]]
    kind = "spring"                 # anchored at the home pose unless "anchor" is given
    stiffness = [100, 100, 100, 2, 2, 2]             # N/m x3, N·m/rad x3

    [[environment]]
    kind = "wall"                   # free where normal . p <= offset
    normal = [1, 0, 0]
    offset = 0.02                   # m
    stiffness = 300                 # N/m

    [pd]                            # Sec. III-D: KP = 110, KI = 0, KD = 0.4
    kp = 110
    ki = 0
    kd = 0.4

    [safety]
    watchdog_ms = 20

    [simulator]
    hand = [[0.0, 0, 0, 0], [0.3, 0, 2, 0]]         # (t s, fx, fy, fz N) knots

Unknown keys are rejected (a typo must not be silently ignored).

**Prismatic legs** (SPS/UPS, e.g. ``examples/control_gough6.toml``): the joint values
are leg lengths (m) and the efforts forces (N), so ``[pd]`` reads ``kp`` N/m, ``kd``
N·s/m, ``ki`` N/(m·s) and ``torque_limit`` N (:meth:`PDGains.for_drives`); the drives are
:class:`~.plant.LinearDrives` (``[simulator] lead`` m/rev, ``friction`` N·s/m at the
leg); ``safety.sigma_min`` is in m (:meth:`SafetyLimits.for_joint`); and the readings are
checked against each leg's ``range`` in the mechanism scene (required), not against
``safety.max_angle``.  A device mixing revolute and prismatic legs is refused: one set
of gains cannot carry both units.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from ..argcheck import as_table, check_keys, choice, positive_int, require
from ..errors import InputError
from ..toml_syntax import toml_syntax_error
from .admittance import check_step
from .plant import HandScript, LinearDrives, Motors, drives_for
from .scene_checks import (check_busy_wait, check_filter_period, check_safety_at_home,
                           gravity_warnings, hand_range_warnings, unit_slip_warnings)
from .scene_fields import bool_field as _bool
from .scene_fields import environment as _environment
from .scene_fields import hand_script as _hand
from .scene_fields import num as _num
from .scene_fields import pd_units
from .scene_fields import share as _share
from .scene_fields import vec as _vec

#: the built-in controller scene (package data; also examples/control_octo.toml)
BUILTIN_SCENE = "control_octo.toml"

__all__ = ["builtin_scene", "BUILTIN_SCENE", "PDGains", "SafetyLimits", "SimulatorConfig", "ControlScene", "load_control_scene",
           "loads_control_scene", "default_scene", "MAX_RATE_HZ", "MIN_RATE_HZ",
           "MIN_WATCHDOG_PERIODS", "MAX_GAIN_PER_LIMIT"]

#: the highest ``[device] rate_hz`` a scene may ask for.  A serial link carries one
#: state frame up and one command frame down per period: an 8-leg device's state frame
#: is 81 bytes on the wire (docs/protocol.md), 810 bits at 8N1, so 10 kHz needs
#: 8.1 Mbaud, beyond
#: the 3 Mbaud of common USB-serial bridges and near the 12 Mbaud of the fastest; USB
#: high speed moves data once per 125 µs microframe (8 kHz).  The loop itself keeps
#: 4 kHz over a pty (BENCHMARKS.md).  A higher rate cannot be met, and the run's timing
#: (the watchdog, the delay margin in periods) would describe a loop that never ran.
MAX_RATE_HZ = 10_000.0
#: the lowest ``[device] rate_hz``: the controller waits 10 s for the first frame and a
#: run gives up after 2 seconds + 10 s of wall time, both of which must hold many periods
MIN_RATE_HZ = 1.0
#: ``safety.watchdog_ms`` and ``simulator.device_watchdog_ms`` must span at least this
#: many device periods: a frame (a command) comes once a period, so a shorter window
#: trips on every frame, or on one frame a little late, and the run sits at zero torque
MIN_WATCHDOG_PERIODS = 2.0
#: ``[pd]`` kp, kd, ki at most this times ``torque_limit``: the whole limit for an error
#: of 1e-12 rad (m, or per s) or less, a millionth of any encoder count, is no servo;
#: 1.7e308 overflowed the PD products and the linearisation (QA X1 D4)
MAX_GAIN_PER_LIMIT = 1e12


@dataclass(frozen=True)
class PDGains:
    """Joint PD(I) at position level (Kühne et al., Sec. III-D).

    ``kp`` N·m/rad, ``ki`` N·m/(rad·s), ``kd`` N·m·s/rad; ``derivative_filter_s`` the
    time constant of the first-order low-pass (forward Euler) on the error derivative,
    0 (no filter) or at least one period ``1/rate_hz`` (shorter is refused: the step's
    eigenvalue ``1 - h/T`` is negative, below -1 for T < h/2, a diverging filter);
    ``torque_limit`` N·m the saturation of each command (the nominal ±2.5 N·m by
    default); ``distribution`` "projected" (remove the internal-force component of the
    redundant L = 8 torques) or "independent"; ``gravity_compensation`` adds the
    minimum-norm torques that carry the platform weight; ``hand_feedforward`` adds the
    minimum-norm torques that balance the measured hand wrench, so that the PD only
    has to move the platform and its finite stiffness does not soften what the
    admittance renders (not in the paper's scheme; off by default).  With KP = 110 (read
    as N·m/rad at the crank: the paper prints no unit) the Octo's servo stiffness
    ``KP JᵀJ`` (:mod:`.stiffness`, pushing along an axis with the other directions free)
    is 1.30 N/mm along x and y at the workspace centre; over the paper's 27 positions it
    is 0.86 N/mm at least (along y, on the upper facet, where the paper found its minima
    too; x gives the same there by symmetry), 22.6 at most (along z), 3.69 on average,
    against the prototype's measured 1.6, 7.9 and 4.7 N/mm (Sec. III-D): 0.54×, 2.9×
    and 0.79×.  The model is the servo alone, with a rigid structure and rigid gears.
    Compliance in series can only lower a stiffness, so it can explain our maximum
    above the measured one, not our minimum below it: that gap is not explained.  A
    rigid model softer than the device needs a gain at the crank at least 1.85× ours, or
    something the model leaves out that stiffens a dial-indicator reading (friction in
    the capstans and bearings); KP's unit and the side of the 1:13 capstan it acts on
    are not printed (KP on the crank angle giving motor torque would be 13× ours at the
    crank).  The Fig. 2 readings we tried give 0.13-0.88 N/mm at least (radial,
    tangential_in, l3 from 0.30 to 0.35 m).  None of these is tested against the
    prototype.  The servo acts in series with the rendered environment, so without the
    feed-forward a wall renders softer than its stiffness.
    """

    kp: float = 110.0
    ki: float = 0.0
    kd: float = 0.4
    derivative_filter_s: float = 0.7
    torque_limit: float = 2.5
    distribution: str = "projected"
    gravity_compensation: bool = True
    hand_feedforward: bool = False

    @classmethod
    def for_drives(cls, drives) -> "PDGains":
        """The defaults for a device with ``drives``: their position-hold gains and
        their nominal effort as the limit.  :class:`~.plant.Motors`: the paper's KP =
        110, KD = 0.4, ±2.5 N·m (the defaults above).  :class:`~.plant.LinearDrives`:
        the same servo at the motor (0.651 N·m/rad and 2.37e-3 N·m·s/rad) through the
        ball screw, with the 10 mm lead kp = 2.57e5 N/m, kd = 934 N·s/m and 121 N.
        Our transfer, not tuned."""
        kp, kd = drives.hold_gains
        return cls(kp=kp, kd=kd, torque_limit=drives.nominal_effort)


@dataclass(frozen=True)
class SafetyLimits:
    """Safety thresholds.

    ``watchdog_ms`` wall time without a valid frame before zero torque and the fault
    state; ``recover_frames`` consecutive valid frames needed to leave it;
    ``sigma_min`` the smallest singular value of the scaled Jacobian ``J S^-1``
    (``S = diag(15 N, 15 N, 15 N, 1 N·m, 1 N·m, 1 N·m)``, Kühne et al. Sec. III-B-2)
    below which a pose counts as
    near-singular, and ``max_condition`` the largest condition number of that matrix
    (it grows near the reach boundary, where a crank and its distal link align; in
    the Table II workspace it stays below about 111); ``max_force`` N and ``max_torque`` N·m the sensor range;
    ``max_angle`` rad the encoder range; ``max_fk_residual`` m.
    ``workspace_m`` m and ``workspace_rad`` rad: the safe workspace, the box
    ``|x_i - home_i| <= workspace_m`` (x, y, z) and ``|r_i - home_i| <= workspace_rad``
    (rx, ry, rz) about the home pose, by default ±75 mm (Kühne et al.'s Table II,
    translational) and ±30° (design criterion 4, Sec. II-A, the range of Table III's
    Octo column; Table II's own rotations are ±20°).  Torque control starts, and resumes after a fault, only at a
    measured pose inside it: a platform that swung away while its torques were zero
    (e.g. under gravity during a stall) is not pulled back at the torque limit; it
    stays at zero torque until it is brought back by hand.
    ``saturation_ms`` and ``saturation_share``: a loop oscillating at the torque limit
    (over the last ``saturation_ms`` of device time at least ``saturation_share`` of
    the cycles saturated, in (0, 1], and the commands reversing sign;
    :class:`.safety.SaturationWatch`) is a fault, zero torque; ``saturation_ms = 0``
    switches the rule off.
    ``recover_speed_m_s`` and ``recover_rate_rad_s``: the fault state is left only
    when the platform is nearly at rest, its mean speed over the last
    ``recover_frames`` valid frames at most these (translation, rotation): the set
    point is re-initialised at the measured pose at rest, so the servo must stop
    whatever motion is left.  At the Octo's home the undamped servo (KP JᵀJ of Kühne et
    al. Sec. III-D with the drives' reflected inertia) stopping 0.81 m/s or 16 rad/s
    peaks at the torque limit (our computation, modal, from the linear servo); the
    defaults 0.25 m/s and 5 rad/s need under a third of it each.
    Checked at load (:mod:`.scene_checks`): ``workspace_rad`` above π is refused, and
    so are a ``sigma_min`` above and a ``max_condition`` below the device's own values
    at its home pose (the guard would hold it the whole run); a ``workspace_m`` beyond
    10 times the device's size is a warning.
    """

    watchdog_ms: float = 20.0
    recover_frames: int = 50
    sigma_min: float = 0.02
    max_condition: float = 1000.0
    max_force: float = 100.0
    max_torque: float = 5.0
    max_angle: float = 3.2
    max_fk_residual: float = 2e-4
    workspace_m: float = 0.075
    workspace_rad: float = 0.5235987755982988
    saturation_ms: float = 250.0
    saturation_share: float = 0.5
    recover_speed_m_s: float = 0.25
    recover_rate_rad_s: float = 5.0

    @classmethod
    def for_joint(cls, joint: str) -> "SafetyLimits":
        """The defaults for a device whose legs are ``joint``.  For prismatic legs
        ``J S^-1`` is in m (leg length per S-scaled platform motion) and
        ``sigma_min`` = 0.02 rad x 0.157 m = 3.14e-3 m: the revolute threshold at the
        Octo's crank length (our transfer, not tuned)."""
        if joint != "prismatic":
            return cls()
        return cls(sigma_min=0.02 * 0.157)


@dataclass(frozen=True)
class SimulatorConfig:
    """The simulated device: motors and sensors, the scripted hand, pacing.

    ``lockstep``: the simulator waits (up to ``reply_timeout_ms`` of wall time) for
    the answer to each state frame before it advances its physics, so that a loaded
    machine slows the simulation down instead of changing it.
    ``device_watchdog_ms``: the device zeroes its torques when no command arrives.
    ``catch_up_ms``: the device's clock keeps its schedule when the simulator process
    is held up (the host's scheduler, a virtual machine's stall) for up to this long of
    wall time: the late ticks follow back to back (lock-stepped, each still waits for
    its answer) until the schedule is met, as the frames of a device with its own
    clock would; a longer hold re-bases the schedule (a *slip*).  0: never catch up.
    """

    #: :class:`~.plant.Motors` (revolute legs) or :class:`~.plant.LinearDrives` (prismatic)
    motors: object = field(default_factory=Motors)
    hand: HandScript = field(default_factory=HandScript)
    seed: int = 0
    lockstep: bool = True
    reply_timeout_ms: float = 100.0
    device_watchdog_ms: float = 100.0
    catch_up_ms: float = 50.0


@dataclass(frozen=True)
class ControlScene:
    """A loaded controller scene (immutable)."""

    path: str
    preset: str
    rate_hz: float
    mass: tuple
    damping: tuple
    environment: tuple
    pd: PDGains
    safety: SafetyLimits
    simulator: SimulatorConfig
    title: str = ""
    #: run the control loop and the simulator under SCHED_FIFO (:mod:`.scheduling`)
    realtime: bool = False
    #: the controller polls the port for up to this long (µs) before it sleeps until a
    #: frame arrives (:class:`.link.Link` ``busy_wait_s``); 0: it sleeps at once; at
    #: most one period (refused beyond)
    busy_wait_us: float = 0.0
    #: the device's mechanism when ``[device] mechanism`` names a scene (``preset`` is
    #: then its name); None for a preset
    mechanism: object = field(default=None, compare=False, repr=False)
    #: "revolute" (crank angles in rad, torques in N·m) or "prismatic" (leg lengths in
    #: m, forces in N)
    joint: str = "revolute"
    #: prismatic legs: each leg's (min, max) length, m, shape (L, 2); None otherwise
    joint_range: tuple | None = None
    #: ``(field, message)`` pairs of values that load but look wrong (the commands print
    #: each as one ``distkin: warning:`` line)
    warnings: tuple = field(default=(), compare=False)

    @property
    def joint_unit(self) -> str:
        return "m" if self.joint == "prismatic" else "rad"

    @property
    def effort_unit(self) -> str:
        """"N·m" (torques at the cranks) or "N" (forces along the legs): the drives'."""
        return self.simulator.motors.effort_unit


def _simulator(t, joint="revolute"):
    fld = "simulator"
    keys = {"hand", "seed", "lockstep", "reply_timeout_ms", "device_watchdog_ms",
            "catch_up_ms", "counts_per_rev", "force_noise", "torque_noise", "friction", "gravity",
            "rotor_inertia"}
    if joint == "prismatic":
        keys.add("lead")
    elif "lead" in t:
        raise InputError(f"expected no lead (m/rev: the ball screw of prismatic legs) on a "
                         f"device with revolute legs, got {t['lead']!r}", field=f"{fld}.lead")
    check_keys(t, keys, fld)
    m = drives_for(joint)
    common = dict(
        counts_per_rev=positive_int(t.get("counts_per_rev", m.counts_per_rev),
                                    f"{fld}.counts_per_rev"),
        force_noise=_num(t, "force_noise", fld, m.force_noise, nonneg=True),
        torque_noise=_num(t, "torque_noise", fld, m.torque_noise, nonneg=True),
        gravity=_num(t, "gravity", fld, m.gravity, nonneg=True),
        rotor_inertia=_num(t, "rotor_inertia", fld, m.rotor_inertia, positive=True))
    if joint == "prismatic":        # friction N·s/m at the leg; None: through the screw
        motors = LinearDrives(
            lead=_num(t, "lead", fld, m.lead, positive=True),
            friction=(_num(t, "friction", fld, None, nonneg=True, unit="N·s/m") if "friction" in t
                      else None), **common)
    else:
        motors = Motors(friction=_num(t, "friction", fld, m.friction, nonneg=True,
                                      unit=pd_units(joint)["friction"]), **common)
    seed = t.get("seed", 0)
    if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
        raise InputError(f"expected an integer >= 0, got {seed!r}", field=f"{fld}.seed")
    return SimulatorConfig(
        motors=motors,
        hand=_hand(t["hand"], f"{fld}.hand") if "hand" in t else HandScript(),
        seed=seed,
        lockstep=_bool(t, "lockstep", fld, True),
        reply_timeout_ms=_num(t, "reply_timeout_ms", fld, 100.0, positive=True),
        device_watchdog_ms=_num(t, "device_watchdog_ms", fld, 100.0, positive=True),
        catch_up_ms=_num(t, "catch_up_ms", fld, 50.0, nonneg=True))


def _kinematics_of(preset_name: str, mechanism):
    """``(kin, length_scale)``: the device's kinematics on the Python route (no
    compilation at load) and its mechanism's length scale (m): the home pose, and the
    Jacobian there for the checks of :func:`.scene_checks.check_safety_at_home`."""
    from ..mechanisms import preset
    from .kinematics import KinematicModel
    mech = mechanism if mechanism is not None else preset(preset_name)
    return KinematicModel(mech, compiled=False), float(mech.length_scale)


def _device_mechanism(dev, path, mechanism_loader):
    """The mechanism of ``[device] mechanism`` (a distkin scene's ``[mechanism]``, loaded
    by ``mechanism_loader(path)``: the application's scene parser), checked for what the
    controller and the simulator model: torque motors on revolute legs."""
    rel = dev["mechanism"]
    if not isinstance(rel, str) or not rel:
        raise InputError(f"expected the path of a distkin scene, got {rel!r}",
                         field="device.mechanism")
    if "preset" in dev:
        raise InputError(f"expected either device.preset or device.mechanism, got both "
                         f"({dev['preset']!r}, {rel!r})", field="device.mechanism")
    if mechanism_loader is None:
        raise InputError("expected the scene to be loaded by distkin control / distkin sim "
                         "(a device.mechanism needs the scene parser), got no loader",
                         field="device.mechanism")
    base = Path(path).parent if path not in ("", "<string>") else Path(".")
    try:
        mech = mechanism_loader(base / rel)
    except InputError as exc:            # name the place in this scene, and the inner one
        inner = f" ({exc.field})" if exc.field and exc.field != "scene" else ""
        raise InputError(f"in {rel!r}{inner}: {exc.message}", field="device.mechanism",
                         hint=exc.hint) from None
    if not hasattr(mech, "leg_description"):
        raise InputError(f"expected a mechanism with legs (kind rss or legs), got "
                         f"{type(mech).__name__}", field="device.mechanism")
    legs = mech.leg_description().leg_table
    prismatic = [i + 1 for i, leg in enumerate(legs) if leg.prismatic]
    if not prismatic:
        return mech, "revolute", None
    if len(prismatic) < len(legs):
        revolute = [i + 1 for i, leg in enumerate(legs) if not leg.prismatic]
        raise InputError(f"expected legs all revolute or all prismatic (one set of PD gains "
                         f"cannot carry N·m/rad and N/m), got revolute legs {revolute} and "
                         f"prismatic legs {prismatic} in {rel!r}", field="device.mechanism")
    no_range = [i + 1 for i, leg in enumerate(legs) if leg.range is None]
    if no_range:
        raise InputError(f"expected a range = [min, max] (leg length) on every prismatic leg "
                         f"(the controller checks the readings against it and the simulator's "
                         f"end stops are there), got none on legs {no_range} in {rel!r}",
                         field="device.mechanism")
    return mech, "prismatic", tuple(tuple(float(v) for v in leg.range) for leg in legs)


def _effort_limit(pd, drives, mechanism):
    """Refuse a PD saturation beyond the drives' stall effort or the legs' own actuator
    limits (the ``limit`` of each leg, when every leg of the mechanism declares one),
    and gains beyond :data:`MAX_GAIN_PER_LIMIT` times it."""
    unit = drives.effort_unit
    units = pd_units("prismatic" if unit == "N" else "revolute")
    for name in ("kp", "kd", "ki"):
        if getattr(pd, name) > MAX_GAIN_PER_LIMIT * pd.torque_limit:
            raise InputError(f"expected at most {MAX_GAIN_PER_LIMIT:g} x torque_limit = "
                             f"{MAX_GAIN_PER_LIMIT * pd.torque_limit:.4g} {units[name]} (the "
                             f"whole limit for an error of 1e-12, far below an encoder "
                             f"count), got {getattr(pd, name)!r} {units[name]}",
                             field=f"pd.{name}")
    stall = drives.stall_effort
    if pd.torque_limit > stall:
        raise InputError(f"expected at most the stall {'force' if unit == 'N' else 'torque'} "
                         f"{stall:.4g} {unit}, got {pd.torque_limit:g} {unit}",
                         field="pd.torque_limit")
    legs = () if mechanism is None else mechanism.leg_description().leg_table
    if legs and all(leg.limit is not None for leg in legs):
        cap = min(min(abs(v) for v in leg.limit) for leg in legs)
        if pd.torque_limit > cap:
            raise InputError(f"expected at most the legs' actuator limit {cap:.4g} {unit}, got "
                             f"{pd.torque_limit:g} {unit}", field="pd.torque_limit")


def _timing(rate_hz, safety, sim):
    """Refuse watchdog windows that a loop at ``rate_hz`` cannot keep: both the host's
    (``safety.watchdog_ms``, no valid frame) and the device's
    (``simulator.device_watchdog_ms``, no command) must span
    :data:`MIN_WATCHDOG_PERIODS` periods of ``1000 / device.rate_hz`` ms."""
    period_ms = 1e3 / rate_hz
    need = MIN_WATCHDOG_PERIODS * period_ms
    for fld, v, what in (("safety.watchdog_ms", safety.watchdog_ms, "state frame"),
                         ("simulator.device_watchdog_ms", sim.device_watchdog_ms,
                          "command")):
        if v < need:
            raise InputError(
                f"expected {fld} at least {MIN_WATCHDOG_PERIODS:g} periods of "
                f"1000/device.rate_hz = {period_ms:.6g} ms, i.e. >= {need:.6g} ms (a "
                f"{what} comes once a period: a shorter window trips on every one and "
                f"the run sits at zero torque), got {v:g} ms", field=fld,
                hint=f"raise {fld} or device.rate_hz")


def loads_control_scene(text: str, path: str = "<string>", *,
                        mechanism_loader=None) -> ControlScene:
    """Parse a controller scene from TOML text (see the module docstring).

    ``mechanism_loader(path) -> mechanism`` loads the ``[mechanism]`` of a distkin scene
    for ``[device] mechanism`` (the application passes its scene parser; the control
    layer does not import it)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise toml_syntax_error(text, exc, path) from None
    if "query" in data or "mechanism" in data:
        raise InputError("expected a controller scene ([device], [pd], ...), got a distkin "
                         "run scene ([mechanism], [[query]])", field="scene",
                         hint="run it with 'distkin run'; a controller scene takes its "
                              "mechanism with [device] mechanism = \"FILE.toml\"")
    check_keys(data, {"title", "description", "device", "admittance", "environment", "pd",
                      "safety", "simulator"}, "scene")
    dev = as_table(data.get("device", {}), "device")
    check_keys(dev, {"preset", "mechanism", "rate_hz", "realtime", "busy_wait_us"}, "device")
    mechanism, joint, joint_range = None, "revolute", None
    if "mechanism" in dev:
        mechanism, joint, joint_range = _device_mechanism(dev, path, mechanism_loader)
        preset_name = mechanism.name
    else:
        preset_name = dev.get("preset", "octo")
        if not isinstance(preset_name, str):
            raise InputError(f"expected a preset name, got {preset_name!r}",
                             field="device.preset")
        from ..mechanisms import PRESETS
        choice(preset_name, "device.preset", tuple(PRESETS))
    rate = _num(dev, "rate_hz", "device", 1000.0, positive=True)
    if rate < MIN_RATE_HZ:
        raise InputError(f"expected rate_hz at least {MIN_RATE_HZ:g} Hz (the controller "
                         f"waits 10 s for the first frame), got {dev['rate_hz']!r} Hz",
                         field="device.rate_hz")
    if rate > MAX_RATE_HZ:
        raise InputError(f"expected rate_hz at most {MAX_RATE_HZ:g} Hz (what a serial link "
                         f"carries: an 8-leg state frame is 810 bits at 8N1, 8.1 Mbaud at "
                         f"10 kHz), got {dev['rate_hz']!r} Hz", field="device.rate_hz",
                         hint="the loop keeps 4 kHz over a pty (BENCHMARKS.md)")
    rt = _bool(dev, "realtime", "device", False)
    busy = _num(dev, "busy_wait_us", "device", 0.0, nonneg=True)
    if busy > 1e6:
        raise InputError(f"expected busy_wait_us (µs) in 0 .. 1e6 (a second of polling at "
                         f"most), got {dev['busy_wait_us']!r} µs", field="device.busy_wait_us")
    check_busy_wait(busy, rate)

    adm = as_table(require(data, "admittance", ""), "admittance")
    check_keys(adm, {"mass", "damping"}, "admittance")
    mass = _vec(adm, "mass", "admittance", 6, positive=True)
    damping = _vec(adm, "damping", "admittance", 6, nonneg=True)

    kin, length_scale = _kinematics_of(preset_name, mechanism)
    home = kin.home
    env = _environment(data.get("environment", []), home)

    pdt = as_table(data.get("pd", {}), "pd")
    check_keys(pdt, {"kp", "ki", "kd", "derivative_filter_s", "torque_limit", "distribution",
                     "gravity_compensation", "hand_feedforward"}, "pd")
    sim = _simulator(as_table(data.get("simulator", {}), "simulator"), joint)
    d, u = PDGains.for_drives(sim.motors), pd_units(joint)
    pd = PDGains(kp=_num(pdt, "kp", "pd", d.kp, nonneg=True, unit=u["kp"]),
                 ki=_num(pdt, "ki", "pd", d.ki, nonneg=True, unit=u["ki"]),
                 kd=_num(pdt, "kd", "pd", d.kd, nonneg=True, unit=u["kd"]),
                 derivative_filter_s=_num(pdt, "derivative_filter_s", "pd",
                                          d.derivative_filter_s, nonneg=True),
                 torque_limit=_num(pdt, "torque_limit", "pd", d.torque_limit, positive=True,
                                   unit=u["torque_limit"]),
                 distribution=choice(pdt.get("distribution", d.distribution),
                                     "pd.distribution", ("projected", "independent")),
                 gravity_compensation=_bool(pdt, "gravity_compensation", "pd",
                                            d.gravity_compensation),
                 hand_feedforward=_bool(pdt, "hand_feedforward", "pd", d.hand_feedforward))
    _effort_limit(pd, sim.motors, mechanism)
    check_filter_period(pd, rate)

    st = as_table(data.get("safety", {}), "safety")
    if joint == "prismatic" and "max_angle" in st:
        raise InputError(f"expected no max_angle (rad, the encoder range of revolute legs): "
                         f"the leg lengths are checked against each leg's range in the "
                         f"mechanism scene, got {st['max_angle']!r}", field="safety.max_angle")
    check_keys(st, {"watchdog_ms", "recover_frames", "sigma_min", "max_condition",
                    "max_force", "max_torque", "max_angle", "max_fk_residual",
                    "workspace_m", "workspace_rad", "saturation_ms", "saturation_share",
                    "recover_speed_m_s", "recover_rate_rad_s"}, "safety")
    s = SafetyLimits.for_joint(joint)
    safety = SafetyLimits(
        watchdog_ms=_num(st, "watchdog_ms", "safety", s.watchdog_ms, positive=True),
        recover_frames=positive_int(st.get("recover_frames", s.recover_frames),
                                    "safety.recover_frames"),
        sigma_min=_num(st, "sigma_min", "safety", s.sigma_min, nonneg=True),
        max_condition=_num(st, "max_condition", "safety", s.max_condition, positive=True),
        max_force=_num(st, "max_force", "safety", s.max_force, positive=True),
        max_torque=_num(st, "max_torque", "safety", s.max_torque, positive=True),
        max_angle=_num(st, "max_angle", "safety", s.max_angle, positive=True),
        max_fk_residual=_num(st, "max_fk_residual", "safety", s.max_fk_residual,
                             positive=True),
        workspace_m=_num(st, "workspace_m", "safety", s.workspace_m, positive=True),
        workspace_rad=_num(st, "workspace_rad", "safety", s.workspace_rad, positive=True),
        saturation_ms=_num(st, "saturation_ms", "safety", s.saturation_ms, nonneg=True),
        saturation_share=_share(st, "saturation_share", s.saturation_share),
        recover_speed_m_s=_num(st, "recover_speed_m_s", "safety", s.recover_speed_m_s,
                               positive=True),
        recover_rate_rad_s=_num(st, "recover_rate_rad_s", "safety", s.recover_rate_rad_s,
                                positive=True))
    _timing(rate, safety, sim)
    # the virtual model must be stable at the scene's rate (a mass of 1 g with damping
    # 15 N s/m gave a spectral radius of 14 at 1 kHz and loaded silently)
    check_step(mass, damping, env, rate, field="admittance")
    warn = (check_safety_at_home(safety, kin, joint, length_scale)
            + hand_range_warnings(sim.hand, safety) + gravity_warnings(sim.motors, pd)
            + unit_slip_warnings(rate, pd, mass, env, kin, length_scale, sim.motors))
    title = data.get("title", "")
    if not isinstance(title, str):
        raise InputError(f"expected a string, got {title!r}", field="title")
    return ControlScene(str(path), preset_name, rate, mass, damping, env, pd, safety, sim,
                        str(title), rt, busy, mechanism, joint, joint_range, warn)


def load_control_scene(path, *, mechanism_loader=None) -> ControlScene:
    """Load a controller scene file; InputError (naming the file) if unreadable.
    ``mechanism_loader``: see :func:`loads_control_scene`."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"expected a readable scene file, got {exc.strerror}",
                         field=str(path)) from None
    return loads_control_scene(text, str(path), mechanism_loader=mechanism_loader)


def default_scene() -> ControlScene:
    """The built-in scene used by ``distkin sim`` without ``--scene``: the Octo, a
    centring spring, no hand."""
    return loads_control_scene(
        '[admittance]\nmass = [1, 1, 1, 0.005, 0.005, 0.005]\n'
        'damping = [15, 15, 15, 0.1, 0.1, 0.1]\n'
        '[[environment]]\nkind = "spring"\nstiffness = [100, 100, 100, 2, 2, 2]\n',
        "<default>")


def builtin_scene():
    """The built-in example scene (the Octo pushed by a scripted hand into a wall)."""
    text = resources.files("distkin.control").joinpath(BUILTIN_SCENE).read_text(encoding="utf-8")
    return loads_control_scene(text, f"distkin/control/{BUILTIN_SCENE}")
