r"""How much command delay the joint PD loop takes: the sampled closed loop, linearised.

Kühne et al., Sec. III-D: the cranks are servoed at 1 kHz by a position-level PD with
KP = 110 N·m/rad, KD = 0.4 N·m·s/rad and the error derivative low-pass filtered with
time constant T = 700 ms by the forward Euler method.  At the loop's own frequencies
(tens of Hz) that filter leaves the derivative term almost no phase lead: for
:math:`\omega T \gg 1`, :math:`K_D\,i\omega/(1 + i\omega T) \approx K_D/T`, a small
extra stiffness.  The damping of the servo then comes mostly from the drives' viscous
friction, and every period of delay between a reading and the torque it causes acts as
negative damping (:math:`K e^{-s\tau} \approx K - K\tau s`).  A host that answers late
(a loaded machine, a device on its own clock, ``[simulator] lockstep = false``) can
therefore drive the loop into a growing oscillation that ends at the torque limit.

This module states that margin.  About an equilibrium (a pose, the set point at it,
gravity compensated, no hand), the loop of :mod:`.controller` and :mod:`.plant` is,
exactly as they compute it, up to first order in the deviation
(:math:`h` the device period, :math:`n` the extra delay in periods):

.. math::

   e_k &= -J x_k, \qquad d_k = (e_k - e_{k-1})/h, \qquad
   f_k = f_{k-1} + (h/T)(d_{k-1} - f_{k-1}),\\
   s_k &= s_{k-1} + h\,e_k = -J\sigma_k, \quad \sigma_k = \sigma_{k-1} + h\,x_k, \qquad
   \tau_k = \Pi\,(K_P e_k + K_I s_k + K_D f_k), \qquad \Pi = J(J^TJ)^{-1}J^T
   \ \text{(``projected'', L > 6; otherwise } I),\\
   V_{k+1} &= V_k + h\,M_{\mathrm{eff}}^{-1} J^T(\tau_{k-n} - b\,J V_k), \qquad
   x_{k+1} = x_k + h\,V_{k+1},

with :math:`M_{\mathrm{eff}} = \hat M + J_r J^TJ` (:mod:`.plant`, semi-implicit Euler),
:math:`x` the pose deviation (translation, small rotation vector), :math:`V` the twist,
:math:`b` the viscous friction and :math:`J_r` the reflected rotor inertia at the joint.
It is a linear recurrence :math:`z_{k+1} = A_n z_k`; the loop is asymptotically stable
iff the spectral radius :math:`\rho(A_n) < 1`.  Neglected, and stated: the torque limit
and the drives' speed-torque envelope (saturation), the clamp of the integral ``s`` (it
holds :math:`K_I s` within the torque limit; the integral state enters only when
:math:`K_I > 0`: the paper's KI = 0), encoder quantisation, sensor noise,
the velocity-product terms and the change of :math:`J` with the pose.  The admittance
model does not enter: its set point follows the measured wrench only, never the pose.

:func:`delay_margin` sweeps :math:`n` and returns the largest delay with
:math:`\rho < 1`; tests/control/test_delay_margin.py checks the prediction against the
nonlinear in-process loop (:func:`.loopback.run_loopback` with ``delay_periods``): the
growth rate and frequency of the oscillation it shows.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["closed_loop_matrix", "DelayMargin", "delay_margin", "MAX_PERIODS", "MARGINAL",
           "format_ms"]

#: the longest sweep :func:`delay_margin` takes: the matrix grows by L rows a period and
#: its eigenvalues cost its size cubed, so the sweep's cost grows as N^4 (N = 50, the
#: Octo: about 5 s; N = 100: minutes)
MAX_PERIODS = 50
#: a spectral radius within this of 1 is marginal: float64's eigenvalues cannot say on
#: which side of 1 it lies (an undamped loop has exactly 1)
MARGINAL = 1e-9


def format_ms(ms: float) -> str:
    """A duration in ms with at least 3 significant digits and no exponent (``1.00``,
    ``20.0``, ``250``, ``0.000300``): a fixed number of decimals hides the periods of a
    fast loop (0.0003 ms is not 0.00)."""
    if ms == 0 or not np.isfinite(ms):
        return f"{ms:.2f}"
    return f"{ms:.{max(0, 2 - int(np.floor(np.log10(abs(ms)))))}f}"


def _loop_data(scene, model, pose):
    """J (L, 6), M_eff (6, 6), friction b, joint inertia, the projection Π (L, L)."""
    pose = np.asarray(model.home if pose is None else pose, dtype=float)
    if pose.shape != (6,) or not np.all(np.isfinite(pose)):
        raise InputError(f"expected a pose of 6 finite numbers (m, rad), got {pose!r}",
                         field="pose")
    J = np.asarray(model.jacobian(pose), dtype=float)
    if not np.all(np.isfinite(J)) or np.linalg.matrix_rank(J) < 6:
        raise InputError("expected a pose where the Jacobian has rank 6, got a singular "
                         f"or unreachable pose {pose.tolist()}", field="pose")
    mo = scene.simulator.motors
    Meff = np.asarray(model.mass, dtype=float) + mo.joint_inertia * (J.T @ J)
    if scene.pd.distribution == "projected":
        P = J @ np.linalg.solve(J.T @ J, J.T)
    else:
        P = np.eye(J.shape[0])
    return J, Meff, float(mo.friction), P


def closed_loop_matrix(scene, model, delay_periods: int = 0, pose=None) -> np.ndarray:
    r"""The transition matrix :math:`A_n` of the linearised sampled loop (module doc).

    State :math:`z_k = (x_k, V_k, e_{k-1}, d_{k-1}, f_{k-1}, [\sigma_{k-1},]
    \tau_{k-1}, \dots, \tau_{k-n})`, size :math:`12 + 3L + nL`, plus 6 for the
    integral when ``pd.ki > 0`` (review: the integral was left out, and a loop whose
    KI destabilises it was reported stable).  The integral of the joint errors, which
    starts at 0 and sums :math:`e = -Jx`, stays in the range of :math:`J`, so it is
    carried as :math:`s = -J\sigma` with :math:`\sigma` the integral of the pose
    deviation: its :math:`L - 6` components outside that range would be eigenvalues
    of exactly 1 (marginal) that no motion excites and that exert no wrench.

    Parameters
    ----------
    scene : ControlScene
    model : KinematicModel
    delay_periods : int
        Extra delay ``n`` (device periods) between the torque computed from reading
        ``k`` and the period it acts in (0: the lock-stepped loop, which applies it
        during the period right after the reading).
    pose : (6,) m, rad, optional
        The equilibrium (default: the device's home).
    """
    n = -1 if isinstance(delay_periods, bool) else int(delay_periods)
    if n != delay_periods or n < 0:
        raise InputError(f"expected delay_periods a whole number >= 0, got {delay_periods!r}",
                         field="delay_periods")
    J, Meff, b, P = _loop_data(scene, model, pose)
    L = J.shape[0]
    h = 1.0 / scene.rate_hz
    pd = scene.pd
    T = pd.derivative_filter_s
    iX, iV, iE, iD, iF, iS = 0, 6, 12, 12 + L, 12 + 2 * L, 12 + 3 * L
    iT = iS + (6 if pd.ki else 0)
    N = iT + n * L
    # each block row: a linear map of the state at k, as an (rows, N) matrix
    e = np.zeros((L, N))
    e[:, iX:iX + 6] = -J                                   # e_k = -J x_k
    d = e / h
    d[:, iE:iE + L] -= np.eye(L) / h                       # d_k = (e_k - e_{k-1}) / h
    if T > 0:
        f = np.zeros((L, N))
        f[:, iF:iF + L] = (1.0 - h / T) * np.eye(L)
        f[:, iD:iD + L] += (h / T) * np.eye(L)             # f_k from f_{k-1}, d_{k-1}
    else:
        f = d
    tau = pd.kp * e + pd.kd * f
    if pd.ki:
        sig = np.zeros((6, N))
        sig[:, iX:iX + 6] = h * np.eye(6)
        sig[:, iS:iS + 6] += np.eye(6)                     # sigma_k = sigma_{k-1} + h x_k
        tau = tau - pd.ki * (J @ sig)                      # s_k = -J sigma_k
    tau = P @ tau
    if n == 0:
        u = tau
    else:
        u = np.zeros((L, N))
        u[:, iT + (n - 1) * L:iT + n * L] = np.eye(L)       # tau_{k-n}
    Mi = np.linalg.inv(Meff)
    V = np.zeros((6, N))
    V[:, iV:iV + 6] = np.eye(6) - h * b * (Mi @ J.T @ J)
    V += h * (Mi @ J.T) @ u
    x = np.zeros((6, N))
    x[:, iX:iX + 6] = np.eye(6)
    x += h * V
    rows = [x, V, e, d, f] + ([sig] if pd.ki else [])
    if n:
        rows.append(tau)
        shift = np.zeros(((n - 1) * L, N))
        shift[:, iT:iT + (n - 1) * L] = np.eye((n - 1) * L)
        rows.append(shift)
    return np.vstack(rows)


@dataclass(frozen=True)
class DelayMargin:
    """Result of :func:`delay_margin`.

    Attributes
    ----------
    period_s : float
        The device period h (s).
    delays : (m,) int
        The extra delays swept (device periods).
    spectral_radius : (m,) float
        :math:`\\rho(A_n)` per delay (< 1: asymptotically stable).
    growth_per_s : (m,) float
        :math:`\\ln\\rho / h` (1/s): the least-damped mode's exponential rate,
        negative when it decays.
    frequency_hz : (m,) float
        That mode's frequency (Hz).
    stable_periods : int
        The largest n with :math:`\\rho(A_m) < 1 -` :data:`MARGINAL` for every m ≤ n;
        -1 when the lock-stepped loop itself is not proved stable (:attr:`lockstep`
        says whether it is unstable or marginal).
    marginal : (m,) bool
        :math:`|\\rho - 1| \\le` :data:`MARGINAL`: stability not decided by float64.
    """

    period_s: float
    delays: np.ndarray
    spectral_radius: np.ndarray
    growth_per_s: np.ndarray
    frequency_hz: np.ndarray
    stable_periods: int
    marginal: np.ndarray | None = None

    @property
    def margin_s(self) -> float:
        """The extra delay the loop takes and stays stable (s); -h when it is unstable
        without delay."""
        return self.stable_periods * self.period_s

    @property
    def lockstep(self) -> str:
        """The lock-stepped loop (no extra delay): "stable", "unstable" (spectral radius
        above 1 + :data:`MARGINAL`: it grows at ``growth_per_s[0]``) or "marginal"."""
        if self.marginal is not None and self.marginal[0]:
            return "marginal"
        return "stable" if self.stable_periods >= 0 else "unstable"

    def lines(self) -> list[str]:
        """The sweep as text, one line per delay."""
        marg = (np.zeros(len(self.delays), bool) if self.marginal is None
                else self.marginal)
        h = self.period_s * 1e3
        dec = len(format_ms(h).partition(".")[2])     # one column: the period's decimals
        w = len(f"{max(self.delays) * h:.{dec}f}")
        out = [f"extra delay {n:3d} period{'s' if n != 1 else ' '} ({n * h:{w}.{dec}f} ms): "
               f"spectral radius {r:.6f}, least-damped mode {f:7.2f} Hz, "
               + (f"marginal (spectral radius within {MARGINAL:g} of 1: float64 cannot "
                  "say whether it grows)" if mg else
                  f"{'grows' if g > 0 else 'decays'} at {abs(g):8.2f} 1/s")
               for n, r, g, f, mg in zip(self.delays, self.spectral_radius,
                                         self.growth_per_s, self.frequency_hz, marg)]
        n, h = self.stable_periods, self.period_s * 1e3
        first = n + 1 < len(self.delays) and marg[n + 1]
        if first:
            out.append(f"stable with up to {n} period{'s' if n != 1 else ''} of extra delay "
                       f"({format_ms(max(n, 0) * h)} ms); with {n + 1} the loop is marginal, not "
                       "decided (linearised: distkin.control.delay_margin)"
                       if n >= 0 else "marginal without extra delay: an undamped loop, "
                       "not decided (linearised: distkin.control.delay_margin)")
        elif n < 0:
            out.append(f"unstable even without extra delay, lock-stepped (spectral "
                       f"radius {self.spectral_radius[0]:.4g}: grows at "
                       f"{self.growth_per_s[0]:.4g} 1/s, {self.frequency_hz[0]:.4g} Hz; "
                       "linearised: distkin.control.delay_margin)")
        elif n == len(self.delays) - 1:
            out.append(f"stable with every extra delay swept, up to {n} periods "
                       f"({format_ms(n * h)} ms)")
        else:
            out.append(f"stable with up to {n} period{'s' if n != 1 else ''} "
                       f"({format_ms(n * h)} ms) of extra delay, unstable with {n + 1} "
                       f"({format_ms((n + 1) * h)} ms) (linearised: distkin.control.delay_margin)")
        return out


def delay_margin(scene, model, *, max_periods: int = 40, pose=None) -> DelayMargin:
    """Sweep the extra command delay n = 0 .. ``max_periods`` (device periods) and find
    the largest with a stable linearised loop (module doc)."""
    m = -1 if isinstance(max_periods, bool) else int(max_periods)
    if m != max_periods or not 0 <= m <= MAX_PERIODS:
        raise InputError(f"expected max_periods a whole number in 0..{MAX_PERIODS} (the "
                         f"sweep's cost grows as its fourth power), got {max_periods!r}",
                         field="max_periods")
    h = 1.0 / scene.rate_hz
    rad, grow, freq = [], [], []
    for n in range(m + 1):
        lam = np.linalg.eigvals(closed_loop_matrix(scene, model, n, pose))
        i = int(np.argmax(np.abs(lam)))
        r = float(abs(lam[i]))
        rad.append(r)
        grow.append(np.log(r) / h if r > 0 else -np.inf)
        freq.append(abs(float(np.angle(lam[i]))) / (2 * np.pi * h))
    rad = np.array(rad)
    marginal = np.abs(rad - 1.0) <= MARGINAL
    bad = np.flatnonzero(rad >= 1.0 - MARGINAL)
    stable = (m if bad.size == 0 else int(bad[0]) - 1)
    return DelayMargin(h, np.arange(m + 1), rad, np.array(grow), np.array(freq), stable,
                       marginal)
