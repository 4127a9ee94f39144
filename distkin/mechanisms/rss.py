"""The RSS/RRRS parallel mechanism with its numeric methods, and the presets as mechanisms.

Kühne et al., *Design and Evaluation of a Haptic Interface With Octopod Kinematics*,
Sec. II-C (eqs. (1)-(3), (7)), Fig. 2.  The description (parameters, leg geometry, the
rules for l3) is :class:`distkin.mechanisms.description.RSSDescription`; this module is
the numeric analysis layer on top of it (docs/design.md, "Import direction").

The numeric methods run on generated kernels (:mod:`.kernels`): the committed modules
``distkin._generated.rss_<preset>`` for the presets, a cached generated module
otherwise.  Nothing here imports sympy.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .description import GEOMETRY_FIELDS, LAYOUTS, LEG_LENGTH, RSSDescription, _poses
from .presets import preset_description

__all__ = ["RSSMechanism", "preset", "GEOMETRY_FIELDS", "LAYOUTS", "LEG_LENGTH"]


@dataclass(frozen=True)
class RSSMechanism(RSSDescription):
    """An :class:`RSSDescription` with numeric methods on its generated kernels.

    Same parameters (SI units) as :class:`RSSDescription`; see there.
    """

    @classmethod
    def from_description(cls, description: RSSDescription) -> "RSSMechanism":
        """The mechanism of a description (the same parameters)."""
        return cls(**description.parameters())

    def points(self, poses, q=None):
        """Joint positions for drawings and independent checks (plain numpy).

        Parameters
        ----------
        poses : array (N, 6) or (6,)
        q : array (N, L) or (L,), optional
            Crank angles (rad); by default the inverse kinematics of ``poses``.

        Returns
        -------
        dict of arrays (N, L, 3) (or (L, 3) for one pose)
            ``B`` crank pivot, ``C`` crank tip, ``D`` universal-joint centre, ``P``
            spherical joint, plus ``q`` (N, L).
        """
        from ..spatial import rotation_matrix
        X, single = _poses(poses)
        if q is None:
            q, _ = self.inverse_kinematics(X)
        q = np.asarray(q, dtype=float).reshape(len(X), self.legs)
        g = self.geometry()
        z = np.array([0.0, 0.0, 1.0])
        R = rotation_matrix(X[:, 3:])
        P = X[:, None, :3] + np.einsum("nij,lj->nli", R, g["p"])
        C = (g["B"][None] + self.l1 * (np.cos(q)[..., None] * g["u"][None]
                                       + np.sin(q)[..., None] * z))
        D = C + g["offset"][None]
        B = np.broadcast_to(g["B"], C.shape)
        out = {"B": B, "C": C, "D": D, "P": P, "q": q}
        return {k: v[0] for k, v in out.items()} if single else out


    def kernels(self, flavour: str = "batched"):
        """The generated kernels (:mod:`.kernels`), ``flavour`` "batched" or "scalar".

        Loaded once per geometry into the one kernel cache of :mod:`.kernels` (keyed by
        :meth:`geometry_key`), outside this frozen description."""
        from .kernels import load_kernels
        return load_kernels(self, flavour)


    def inverse_kinematics(self, poses):
        """Closed-form inverse kinematics, one crank angle per leg.

        Parameters
        ----------
        poses : array (N, 6) or (6,)
            m and rad (:mod:`distkin.spatial`).

        Returns
        -------
        q : array (N, L), rad
            Crank elevation (0 = horizontal), branch of :mod:`.presets`; finite even
            where a leg cannot close.
        valid : array (N, L) of bool
            The leg closes (the reach margin is >= 0).
        """
        X, single = _poses(poses)
        k = self.kernels("batched")
        q = k.ik(X)
        valid = k.reach(X) >= 0.0
        return (q[0], valid[0]) if single else (q, valid)


    def reachable(self, poses):
        """(N,) bool: every leg of the pose closes."""
        X, single = _poses(poses)
        ok = np.all(self.kernels("batched").reach(X) >= 0.0, axis=-1)
        return ok[0] if single else ok


    def reach_margin(self, poses):
        """(N, L) reach margin rho^2 - C^2 (m^2) of the IK equation A cos q + B sin q = C."""
        X, single = _poses(poses)
        m = self.kernels("batched").reach(X)
        return m[0] if single else m


    def jacobian(self, poses):
        """J = Jq^-1 Jx (eqs. (1)-(2)), shape (N, L, 6), with qdot = J @ (v, omega).

        v in m/s, omega in rad/s (base frame), qdot in rad/s.  Legs that do not close
        give finite but meaningless rows; check :meth:`inverse_kinematics`.
        """
        X, single = _poses(poses)
        J = self.kernels("batched").jacobian(X)
        return J[0] if single else J


    def jq_jx(self, poses):
        """Jq (N, L) (the diagonal of eq. (1)'s Jq) and Jx (N, L, 6): Jq qdot = Jx xdot.

        Jq_ii = dPhi_i/dq_i and Jx = -dPhi/d(v, omega) for the closures Phi_i
        = (|P_i - D_i|^2 - l3^2) / (2 l3) (m).
        """
        X, single = _poses(poses)
        out = self.kernels("batched").jq_jx(X)
        Jq, Jx = out[..., 0], out[..., 1:]
        return (Jq[0], Jx[0]) if single else (Jq, Jx)


    def pose_jacobian(self, poses):
        """dq/d(x, y, z, rx, ry, rz) = J @ blockdiag(I, E(r)), shape (N, L, 6)."""
        from ..spatial import omega_map
        X, single = _poses(poses)
        J = self.kernels("batched").jacobian(X)
        out = J.copy()
        out[..., 3:] = J[..., 3:] @ omega_map(X[:, 3:])
        return out[0] if single else out


    def joint_mass_matrix(self, poses):
        """Mq = J#ᵀ M̂ J# (eq. (7)), shape (N, L, L), kg m^2.

        The paper writes Mq = Jᵀ M̂ J with J the map q̇ -> ẋ; in our convention
        (q̇ = J ẋ) that map is J# = pinv(J).  Mq gives the kinetic energy
        ½ q̇ᵀ Mq q̇ = ½ ẋᵀ M̂ ẋ; it has rank 6, so for L = 8 it is singular.
        """
        X, single = _poses(poses)
        Jp = np.linalg.pinv(self.kernels("batched").jacobian(X))   # (N, 6, L)
        Mq = np.swapaxes(Jp, -1, -2) @ self.cartesian_mass_matrix() @ Jp
        return Mq[0] if single else Mq


    def acceleration_map(self, poses):
        """ẍ = A τ at q̇ = 0, f = 0 (eq. (7)); A = J# Mq⁺ = M̂⁻¹ Jᵀ, shape (N, 6, L).

        For L = 6, Mq⁺ = Mq⁻¹ and this is eq. (7) verbatim; for L = 8 eq. (7) needs the
        pseudo-inverse of the singular Mq, and J# Mq⁺ = M̂⁻¹ Jᵀ still holds.
        """
        X, single = _poses(poses)
        J = self.kernels("batched").jacobian(X)
        A = np.linalg.inv(self.cartesian_mass_matrix()) @ np.swapaxes(J, -1, -2)
        return A[0] if single else A


    def forward_kinematics(self, q, guess=None, **options):
        """Numeric forward kinematics; see :func:`.forward.forward_kinematics`."""
        from .forward import forward_kinematics
        return forward_kinematics(self, q, guess, **options)


def preset(name: str, **overrides) -> RSSMechanism:
    """The mechanism named ``name``, with parameters optionally overridden.

    The numeric mechanism of :func:`distkin.mechanisms.presets.preset_description`
    (which states the parameters, the overrides and the naming rule).
    """
    return RSSMechanism.from_description(preset_description(name, **overrides))
