"""The serial-link device controller and a device simulator that speaks the same link.

Kühne et al., *Design and Evaluation of a Haptic Interface With Octopod Kinematics*,
Sec. III-D and Fig. 9: admittance control with a PD loop at position level at 1 kHz
(KP = 110, KI = 0, KD = 0.4), capstans 1:13, actuators ±2.5 N·m nominal.

Modules (one concept each)

==============  ============================================================
protocol        binary frames (COBS, version, length, CRC-32); no I/O
frame_codec     the same frames encoded and decoded by compiled code (numba)
link            the host end over pyserial (the only module importing ``serial``)
kinematics      per-cycle IK, Jacobian and warm-started FK on the generated kernels
cycle_kernels   the control cycle's kinematics compiled (per mechanism)
cycle_wrappers  the template of those per-mechanism kernels
cycle_common    the mechanism-independent parts of the compiled cycle
admittance      virtual mass-damper and environment (spring, wall)
controller      the control cycle, torque distribution, saturation, singular guard
safety          checks of a state frame, the device's status bits, the loop's states
loop            the control loop: frames in, commands out, watchdog, e-stop, recovery
scheduling      SCHED_FIFO and timer slack for the loop and the simulator
delay_margin    how much command delay the joint PD loop takes (linearised)
plant           simulated physics: platform, motors + capstan, encoders, F/T, hand
end_stops       the simulated end stops and reach limits (inelastic contacts)
faults          fault injection (corrupt, garbage, truncate, drop, stall, disconnect)
simulator       the device serving the protocol on a pty or TCP socket
loopback        controller and plant in one process (no I/O; design, benchmarks)
config          the controller scene (TOML), the built-in scene
scene_fields    the value checks of the scene's fields (numbers, units)
scene_checks    the scene's values against each other and the device (unit slips)
runlog          CSV / JSON-lines logs and the plot of a run
table5          Table V of Kühne et al. emulated on the simulated device
stiffness       the servo stiffness KP JᵀJ at the paper's 27 positions (Sec. III-D)
==============  ============================================================

A run from Python (README, "Device control")::

    scene = load_control_scene("examples/control_octo.toml")   # or builtin_scene()
    model = model_of(scene)
    out = run_loopback(scene, model, 0.5)      # in one process: poses, torques, ...
    with open_link(url) as link:               # a device, or ``distkin sim``'s port
        summary = Controller(scene, model).run(link, 5.0)

``distkin sim`` and ``distkin control`` are :mod:`distkin.app.control_commands`; the
``table5`` scene query is :mod:`distkin.app.queries.control`.

``import distkin.control`` imports neither sympy nor pyserial; the mechanism's kernels
are loaded when a controller or simulator is built.
"""

from __future__ import annotations

from .. import _jitcache  # noqa: F401  (drops numba caches older than the sources)
from .admittance import Admittance, Spring, Wall
from .config import ControlScene, builtin_scene, load_control_scene, loads_control_scene
from .controller import Controller
from .faults import Fault, FaultInjector, parse_faults
from .kinematics import KinematicModel, load_model, model_of
from .link import Link, open_link
from .loopback import run_loopback
from .plant import HandScript, Motors, Plant
from .protocol import CommandFrame, FrameDecoder, StateFrame, encode_command, encode_state

__all__ = [
    # protocol
    "StateFrame", "CommandFrame", "FrameDecoder", "encode_state", "encode_command",
    # scene and models
    "ControlScene", "load_control_scene", "loads_control_scene", "builtin_scene",
    "KinematicModel", "load_model", "model_of",
    # controller, its link and the in-process loop
    "Controller", "Admittance", "Spring", "Wall", "Link", "open_link", "run_loopback",
    # simulator
    "Plant", "Motors", "HandScript", "Fault", "FaultInjector", "parse_faults",
]
