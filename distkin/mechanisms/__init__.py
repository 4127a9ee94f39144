"""RSS/RRRS parallel mechanisms: the HEXA, Hunt-type and Ergin hexapods and the Octopod.

Kühne et al., *Design and Evaluation of a Haptic Interface With Octopod Kinematics*
(IEEE/ASME Trans. Mechatronics), Sec. II-C, III-A, Fig. 2, Tables I-IV.

Public API (stable; other modules code against it)
--------------------------------------------------
>>> from distkin.mechanisms import preset, RSSMechanism
>>> mech = preset("octopod")                  # hexa | hunt | ergin | octopod | octo
>>> mech = preset("octo", l0=0.165)           # any parameter overridden (SI: m, rad)
>>> mech.L                                    # legs (= actuators): 6, or 8 here
8

Poses are arrays ``(N, 6)`` (or ``(6,)``): ``(x, y, z)`` of the end-effector centre
in metres in the base frame, then ``(rx, ry, rz)`` in radians, the rotation
``R = Rz(rz) @ Ry(ry) @ Rx(rx)`` (rotations about the fixed base axes x, then y, then
z; :mod:`distkin.spatial`).  The home pose (workspace centre) is ``(0, 0, z0, 0, 0, 0)``.

``q, valid = mech.inverse_kinematics(poses)``
    q ``(N, L)`` crank angles in rad (0 = crank horizontal, positive = tip up);
    valid ``(N, L)`` bool.  Unreachable legs give ``valid=False`` and a finite q
    (never NaN).  ``mech.reachable(poses)`` -> ``(N,)`` bool (all legs valid).
``J = mech.jacobian(poses)``
    ``(N, L, 6)`` with ``qdot = J @ (v, omega)``: v the velocity of the end-effector
    centre (m/s), omega its angular velocity (rad/s) in the base frame.  J = Jq^-1 Jx
    of eqs. (1)-(2); the wrench is ``(f, tau) = J.T @ tau_actuators`` (eq. (3)).
    ``mech.jq_jx(poses)`` -> (Jq ``(N, L)`` diagonal, Jx ``(N, L, 6)``).
    ``mech.pose_jacobian(poses)`` -> ``(N, L, 6)`` dq/d(pose parameters)
    (= J @ blockdiag(I, E), E from :func:`distkin.spatial.omega_map`).
``mech.cartesian_mass_matrix()``
    M̂ = diag(m, m, m, I, I, I) ``(6, 6)`` (kg, kg m^2; Sec. III-B.3).
``mech.joint_mass_matrix(poses)``
    Mq ``(N, L, L)`` = J#ᵀ M̂ J# (the paper's "Mq = Jᵀ M̂ J" with its J the map
    q̇ -> ẋ, which is our J# = pinv(J)); rank 6, so singular for L = 8.
``mech.acceleration_map(poses)``
    ``(N, 6, L)`` = J# Mq⁺ = M̂⁻¹ Jᵀ: ẍ = A τ at q̇ = 0, f = 0 (eq. (7)).
``res = mech.forward_kinematics(q, guess)``
    numeric FK (:mod:`.forward`): Gauss-Newton on the leg closures using the generated
    kernels, warm-started at ``guess``; q ``(L,)`` or ``(N, L)``, guess ``(6,)`` or
    ``(N, 6)``.  Returns :class:`FKResult` (``pose``, ``converged``, ``iterations``,
    ``residual`` [m, rms leg-length error], ``sigma_min``, ``condition``,
    ``near_singular``, ``message``; ``res.ok`` = converged and not near-singular);
    ``strict=True`` raises instead of returning a non-converged or near-singular
    answer.  One pose (1-D q) runs on the scalar kernels (the control-loop path).
``mech.reach_margin(poses)``
    ``(N, L)`` margin (m^2) of the IK equation; >= 0 iff the leg closes.
``mech.points(poses, q=None)``
    joint positions B, C, D, P ``(N, L, 3)`` each (plots, independent checks).
``k = mech.kernels("scalar")`` / ``mech.kernels("batched")``
    the generated kernels as attributes (plain Python functions; no sympy):
    ``k.ik(pose) -> q (L,)``, ``k.reach(pose) -> margin (L,)`` (>= 0 iff reachable),
    ``k.jacobian(pose) -> J (L, 6)``, ``k.jq_jx(pose) -> (L, 7)`` (column 0 Jq, 1..6 Jx),
    ``k.closure(q, pose) -> (L, 7)`` (column 0 the closure residual in m, 1..6 its
    derivative w.r.t. (v, omega)).  Scalar kernels take and return plain floats/lists;
    batched ones take ``(..., 6)`` arrays.  For the five presets these are the committed
    modules ``distkin._generated.rss_<name>`` (functions ``ik``, ``jacobian``, ... batched
    and ``ik_scalar``, ``jacobian_scalar``, ... scalar); other parameters are generated
    on first use and cached (:mod:`distkin.sourcecache`).

Any mechanism as a table of legs (RSS, RUS, RRRS revolute; SPS, UPS prismatic; any
L >= 6): :class:`LegsDescription` / :class:`LegMechanism` (:mod:`.legs`), with the same
methods as above (``route="numpy"``: the plain-numpy kernels, no derivation); every RSS
description gives its leg table (``preset("octo").leg_description()``), and a leg table
equal to a preset's loads the preset's committed kernels.  Poses may also be 4x4
homogeneous matrices (:func:`distkin.spatial.pose_from`).

Code generation: ``distkin codegen SCENE.toml -o MODULE.py`` writes the kernels a scene's
queries need (same function names) as a module that imports only math and numpy.

Modules
-------
description  the frozen :class:`RSSDescription`: parameters, leg geometry, l3 rules
legs       the frozen leg table (:class:`Leg`, :class:`LegsDescription`): the model the code
           generator reads
leg_architecture  architecture singularities of a leg table: identical or concurrent
           legs refused, lines that cannot span 6 DOF warned of
kinematics the numeric methods on kernels (``KernelMethods``) and :class:`LegMechanism`
rss        :class:`RSSMechanism`, the description with its numeric methods; ``preset``
presets    the five presets as data and the documented parameter rules
symbolic   the sympy model (leg closure, closed-form IK, Jq, Jx) -- imports sympy
reference  the plain-numpy reference model (IK and Jacobian from the leg geometry; the
           design sweeps' route and the tests' independent second route) and
           ``NumericKernels`` (the kernel interface in numpy from a leg table)
kernel_names  the names and flavours of the generated kernels
kernels    loading the kernels: the committed modules, one cache
forward    numeric forward kinematics
fk_failure what the fast forward kinematics warns when it returns no answer
interference  link interference (segment distances between the links)
plot       a drawing of the mechanism at a pose (matplotlib)

Elsewhere: rotations are :mod:`distkin.spatial`; deriving the kernels is
:mod:`distkin.codegen.rss`; the ``kind = "rss"`` scene parser and the scene queries are
:mod:`distkin.app.mechanism_scene` and :mod:`distkin.app.queries.mechanisms`.
"""

from __future__ import annotations

from .forward import FKResult
from .description import GeometryWarning, RSSDescription
from .kinematics import LegMechanism
from .legs import Leg, LegsDescription
from .presets import PRESETS
from .rss import RSSMechanism, preset

__all__ = ["RSSMechanism", "RSSDescription", "preset", "PRESETS", "FKResult", "Leg",
           "LegsDescription", "LegMechanism", "GeometryWarning"]
