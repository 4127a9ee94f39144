"""The control cycle's kinematics compiled: the generated scalar kernels under numba, and
the warm-started Gauss-Newton forward kinematics, the scaled-Jacobian guard and the
torque projection around them, without a Python call per operation.

:class:`~.kinematics.KinematicModel` calls the generated scalar kernels (plain Python,
:mod:`distkin.codegen`) and numpy on 6-vectors and 8 × 6 matrices; each numpy call costs
1-5 µs of dispatch and a cycle makes a few dozen.  Here the same generated functions are
compiled by numba (``numba.njit`` of the functions of ``distkin/_generated``, so the
formulas keep their one source), and the loops around them are plain compiled code
writing into preallocated arrays:

* :func:`build` -> :class:`CycleKernels`: ``ik(pose, q) -> ok``, ``jacobian(pose, J)``,
  ``closure(q, pose, C)``, ``forward(q, guess, tol, max_iter, pose_out) -> (residual,
  iterations, converged)``, ``singular_values(J, S) -> (σmin, σmax)`` of ``J S⁻¹``,
  ``project(J, tau, w, out)``: ``J (JᵀJ)⁻¹ (Jᵀ tau + w)`` (the torque distribution of
  :mod:`.controller`), ``rotate_pose`` (:func:`distkin.spatial.rotate_pose_scalar` itself
  compiled), ``rotate_wrench(r, w, out)`` (the sensor wrench into the base frame by
  :func:`.kinematics._rot`), ``spring_wrench(pose, twist, p0, R0t, k, d, out)``
  (:meth:`.admittance.Spring.wrench` by the compiled :func:`.admittance.rotation_log`);
  the rotation formulas keep their one source;
* ``cycle(...)``: steps 2-8 of :meth:`.controller.Controller.compute` in one call (FK,
  the wrench into the base frame, the guard, the admittance step with the scene's
  springs and walls, the refusal of a candidate, IK, the PD with its forward-Euler
  derivative filter, the distribution, the saturation), parameters laid out by
  :func:`cycle_params`;
* ``drive``, ``plant_dynamics`` and ``jdot_v``: :meth:`.plant.Plant.step` of the
  simulator (its drives, its equations of motion and the rotors' ``J̇ V``), and
  ``readings``: its :meth:`.plant.Plant.readings`;
* :func:`reading_extremes`: the checks of a state frame in one call (the frames
  themselves are encoded and decoded by :mod:`.frame_codec`).

The kernels give the same bits as the generated Python functions (the same float
operations in the same order); the Gauss-Newton step and the 6 × 6 solves use a
Gaussian elimination with partial pivoting instead of LAPACK and agree with the Python
route to rounding (tests/control/test_cycle_kernels.py).  The wrappers
(:mod:`.cycle_wrappers`) call one mechanism's kernels; so that numba can keep their
machine code on disk, :func:`build` writes them with a header naming the kernels into a
file of the derivation cache (:mod:`distkin.sourcecache`, keyed by the template, the
kernels' source and the modules whose functions they inline) and compiles them there: a few seconds on the first start on a
machine, well under one afterwards.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from .protocol import float32_floor

__all__ = ["CycleKernels", "build", "kernel_module", "jitted", "reading_extremes",
           "cycle_params", "CYCLE_OUT"]

_BUILT: dict = {}


@dataclass(frozen=True)
class CycleKernels:
    """Compiled per-cycle kinematics of one mechanism (see the module docstring)."""

    L: int
    ik: object
    jacobian: object
    closure: object
    forward: object
    singular_values: object
    project: object
    rotate_pose: object
    rotate_wrench: object
    spring_wrench: object
    cycle: object
    drive: object
    plant_dynamics: object
    readings: object
    jdot_v: object
    reach: object
    reach_gradient: object


def _solve_into(A, b, x):                                    # pragma: no cover (compiled)
    """x = A⁻¹ b for a small square A by Gaussian elimination with partial pivoting;
    False if a pivot is 0 (A and b are overwritten)."""
    n = A.shape[0]
    for c in range(n):
        p = c
        for i in range(c + 1, n):
            if abs(A[i, c]) > abs(A[p, c]):
                p = i
        if A[p, c] == 0.0 or not math.isfinite(A[p, c]):
            return False
        if p != c:
            for j in range(n):
                t = A[c, j]
                A[c, j] = A[p, j]
                A[p, j] = t
            t = b[c]
            b[c] = b[p]
            b[p] = t
        for i in range(c + 1, n):
            f = A[i, c] / A[c, c]
            for j in range(c, n):
                A[i, j] -= f * A[c, j]
            b[i] -= f * b[c]
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= A[i, j] * x[j]
        x[i] = s / A[i, i]
    return True


def _reading_extremes(a, w):                                 # pragma: no cover (compiled)
    finite = True
    ma = 0.0
    for i in range(a.shape[0]):
        if not math.isfinite(a[i]):
            finite = False
        ma = max(ma, abs(a[i]))
    mf = 0.0
    mm = 0.0
    for i in range(3):
        if not (math.isfinite(w[i]) and math.isfinite(w[3 + i])):
            finite = False
        mf = max(mf, abs(w[i]))
        mm = max(mm, abs(w[3 + i]))
    return finite, ma, mf, mm


_COMPILED: dict = {}


def _jit(name, func):
    """``func`` (of this module, calling nothing of another module) compiled once per
    process, kept in numba's disk cache."""
    f = _COMPILED.get(name)
    if f is None:
        import numba
        f = _COMPILED[name] = numba.njit(cache=True)(func)
    return f


#: entries of the fused cycle's ``out`` besides the L torques: pose, base-frame wrench,
#: admittance pose and twist (6 each), FK residual, FK iterations, saturated
CYCLE_OUT = 27


def cycle_params(pd, safety, adm, weight: float, scaling, *, fk_tol: float = 1e-4,
                 fk_iter: tuple = (8, 40), period: float = 0.0, revolute: bool = True):
    """The parameter vector ``prm`` and environment table ``env`` of the fused cycle
    (``cycle`` of :func:`build`), from a controller's gains, limits and admittance.

    ``prm`` (36,): FK tolerance, FK iterations (warm, cold), max FK residual, σmin,
    max condition, kp, kd, ki, derivative filter T, torque limit (the largest float32
    not above it: :func:`.protocol.float32_floor`), projected (0/1),
    gravity compensation (0/1), hand feed-forward (0/1), weight (N), S (6), virtual
    mass (6), virtual damping (6), the derivative filter's largest step
    ``max(T, period)`` (s; :meth:`.controller.Controller.filter_derivative`), and 1
    where the joints are crank angles (``revolute``: the PD error is taken modulo 2π,
    :meth:`.kinematics.KinematicModel.joint_step`), 0 for leg lengths, and the
    admittance's largest step (s; ``period``, 0: none; a longer measured gap is taken
    as equal steps, :func:`.admittance.substeps`).
    ``env`` (n, 25), one row per element in the scene's order: a Spring
    ``0, p0 (3), R0ᵀ (9, row-major), k (6), d (6)``; a Wall
    ``1, normal (3), offset, stiffness, damping`` (zero padded).
    """
    prm = np.array([fk_tol, fk_iter[0], fk_iter[1], safety.max_fk_residual,
                    safety.sigma_min, safety.max_condition, pd.kp, pd.kd, pd.ki,
                    pd.derivative_filter_s, float32_floor(pd.torque_limit),
                    float(pd.distribution == "projected"), float(pd.gravity_compensation),
                    float(pd.hand_feedforward), weight, *scaling, *adm.mass, *adm.damping,
                    max(pd.derivative_filter_s, period), float(bool(revolute)), period],
                   dtype=float)
    env = np.zeros((len(adm.environment), 25))
    for r, e in enumerate(adm.environment):
        if e.kind == "spring":
            env[r, 1:4], env[r, 4:13] = e._p0, np.ravel(e._R0t)
            env[r, 13:19], env[r, 19:25] = e._k, e._d
        else:
            env[r, 0] = 1.0
            env[r, 1:4] = np.asarray(e.normal, dtype=float)
            env[r, 4:7] = e.offset, e.stiffness, e.damping
    return prm, env


def reading_extremes(a, w):
    """``(finite, max|a|, max|f|, max|m|)`` of encoder angles ``a`` (L,) rad and the
    wrench ``w`` (6,) N, N·m (NaN or inf anywhere: ``finite`` False)."""
    return _jit("reading_extremes", _reading_extremes)(a, w)


_HEADER = """# GENERATED BY distkin.control.cycle_kernels.build -- DO NOT EDIT
# the control cycle's compiled kinematics: distkin/control/cycle_wrappers.py over the
# generated kernels of {name} (source sha256 {kernels}...)
import numba

from distkin.control import cycle_common as _cc
from distkin.control import cycle_kernels as _ck

_kmod = _ck.kernel_module({name!r}, {path!r})
_ik, _reach, _jac, _clo = (getattr(_kmod, n) for n in {names!r})
"""

_FOOTER = """

# (numpy's error model: a zero divisor gives inf or NaN, which the callers test, not a
# ZeroDivisionError out of the cycle -- J at a leg's reach limit divides by zero)
_kjit = numba.njit(cache=True, error_model="numpy")
ik_k, reach_k, jac_k, clo_k = _kjit(_ik), _kjit(_reach), _kjit(_jac), _kjit(_clo)
# what the template calls that is compiled once for every mechanism (.cycle_common)
solve, rotate, rotate_wrench, project = _cc.solve, _cc.rotate, _cc.rotate_wrench, _cc.project
normal_equations = _cc.normal_equations
_near_singular, _environment = _cc.near_singular, _cc.environment
_excess = _cc.excess_k
# this mechanism's
ik = numba.njit(cache=True)(ik)
reach = numba.njit(cache=True)(reach)
reach_gradient = numba.njit(cache=True)(reach_gradient)
jacobian = numba.njit(cache=True)(jacobian)
closure = numba.njit(cache=True)(closure)
forward = numba.njit(cache=True)(forward)
cycle = numba.njit(cache=True)(cycle)
plant_dynamics = numba.njit(cache=True)(plant_dynamics)
_reaches = numba.njit(cache=True)(_reaches)
_finite = numba.njit(cache=True)(_finite)
jdot_v = numba.njit(cache=True)(jdot_v)
"""


def kernel_module(name: str, path: str):
    """The generated kernel module of a cycle-wrapper file: imported by name (a preset's
    module in ``distkin._generated``) or loaded from its cached file."""
    import importlib
    import sys
    if name in sys.modules or name.startswith("distkin."):
        return importlib.import_module(name)
    from ..sourcecache import load_module_file
    # registered under its name: numba's disk cache records the module of the kernels it
    # compiled and imports it by that name when another process loads the cache (a
    # derived geometry's module is not importable otherwise; numba would record
    # "<dynamic>" and the next process fail to load the cycle)
    mod = load_module_file(path, name)
    sys.modules[name] = mod
    return mod


def jitted(name: str):
    """``"solve"``: :func:`_solve_into` compiled (numba's disk cache)."""
    return _jit(name, {"solve": _solve_into}[name])


def _rotation_files():
    """The source files whose compiled functions the cycle wrappers call (their text
    keys the cached wrappers): read as files, not imported (kinematics and admittance
    import this module, and cycle_common imports numba)."""
    here = os.path.dirname(os.path.abspath(__file__))
    return (os.path.join(here, "kinematics.py"), os.path.join(here, "admittance.py"),
            os.path.join(here, "cycle_common.py"),
            os.path.join(os.path.dirname(here), "spatial.py"))


def _register(path):
    """Import a cycle-wrapper file as a module registered in ``sys.modules`` under a
    name fixed by its path (numba's disk cache finds a module by that name)."""
    import importlib.util
    import sys
    name = f"distkin_cycle_{os.path.splitext(os.path.basename(path))[0]}"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    try:
        spec.loader.exec_module(mod)
    except BaseException:
        sys.modules.pop(name, None)
        raise
    return mod


def build(kernels, L: int) -> CycleKernels:
    """Compile the cycle kernels of one mechanism.

    Parameters
    ----------
    kernels : KernelSet
        ``mech.kernels("scalar")`` (functions ``ik``, ``reach``, ``jacobian``,
        ``closure`` of a generated module).
    L : int
        Number of legs.
    """
    key = (kernels.ik, kernels.jacobian, kernels.closure, int(L))
    got = _BUILT.get(key)
    if got is not None:
        return got
    from ..sourcecache import cached_source, source_key
    from . import cycle_wrappers
    _jit("reading_extremes", _reading_extremes)
    mod = kernels.module
    kname = getattr(mod, "__name__", "")
    kpath = str(getattr(mod, "__file__", ""))
    ktext = open(kpath, encoding="utf-8").read() if os.path.isfile(kpath) else kname
    tmpl = open(cycle_wrappers.__file__, encoding="utf-8").read()
    # what the wrappers inline besides the kernels: this module's solve, the rotation of
    # .kinematics and the functions of .cycle_common (numba's cache would not notice
    # their change)
    deps = [open(f, encoding="utf-8").read() for f in (__file__, *_rotation_files())]
    names = [f.__name__ for f in (kernels.ik, kernels.reach, kernels.jacobian,
                                  kernels.closure)]
    header = _HEADER.format(name=kname, path=kpath, names=names,
                            kernels=source_key(ktext)[:16])
    path, _ = cached_source("cycle", source_key(header, tmpl, _FOOTER, *deps),
                            lambda: header + tmpl + _FOOTER)
    w = _register(path)
    cc = w._cc          # .cycle_common, as the wrappers' header imports it
    ik, jacobian, closure = w.ik, w.jacobian, w.closure
    forward, singular_values, project = w.forward, cc.singular_values, cc.project
    ck = CycleKernels(int(L), ik, jacobian, closure, forward, singular_values, project,
                      cc.rotate, cc.rotate_wrench, cc.spring_wrench, w.cycle,
                      cc.drive, w.plant_dynamics, cc.readings, w.jdot_v, w.reach,
                      w.reach_gradient)
    # compile now: the first control cycle must not wait for the compiler
    pose = np.zeros(6)
    q = np.zeros(L)
    Jb = np.zeros((L, 6))
    ik(pose, q)
    w.reach(pose, q)
    w.reach_gradient(pose, 1e-6, Jb)
    jacobian(pose, Jb)
    closure(q, pose, np.zeros((L, 7)))
    forward(q, pose, 1e-4, 1, np.zeros(6))
    singular_values(np.ones((L, 6)), np.ones(6))
    project(np.ones((L, 6)), np.zeros(L), np.zeros(6), np.zeros(L))
    reading_extremes(np.zeros(L), np.zeros(6))
    ck.rotate_wrench(np.zeros(3), np.zeros(6), np.zeros(6))
    for R0t in (np.eye(3), np.eye(3).T):        # Spring._R0t is a transpose (F order)
        ck.spring_wrench(np.zeros(6), np.zeros(6), np.zeros(3), R0t, np.zeros(6),
                         np.zeros(6), np.zeros(6))
    ck.rotate_pose(np.zeros(6), np.zeros(3), np.zeros(3))
    env = np.zeros((2, 25))
    env[1, 0] = 1.0
    prm = np.zeros(36)
    prm[15:21] = 1.0                               # the scaling S (a divisor)
    for started in (False, True):
        ck.cycle(np.zeros(L), np.zeros(6), 1e-3, started, True, np.zeros(6), np.zeros(6),
                 np.zeros(6), np.zeros((5, L)), prm, env,
                 np.array([[-np.inf] * L, [np.inf] * L]), np.zeros(CYCLE_OUT + L))
    ck.drive(np.zeros(L), np.zeros(L), 1.0, 1.0, np.zeros(L))
    ck.readings(np.zeros(L), 1.0, np.zeros(6), np.zeros(6), np.zeros(6), np.zeros(L + 6))
    ck.plant_dynamics(np.zeros(6), np.zeros(6), np.zeros(L), np.zeros(L), np.zeros(L),
                      np.zeros(6), np.eye(6), np.array([0, 0, 0, 1e-3, 1e-4, 0, 1.0, 1.0]),
                      np.zeros(L), np.zeros(13 + 2 * L))
    for lengths in (0.0, 1.0):
        ck.jdot_v(np.zeros(6), np.ones(6), 1e-4, lengths, np.zeros(L))
    _BUILT[key] = ck
    return ck
