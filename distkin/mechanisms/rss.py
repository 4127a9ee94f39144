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
from .kinematics import KernelMethods
from .presets import preset_description

__all__ = ["RSSMechanism", "preset", "GEOMETRY_FIELDS", "LAYOUTS", "LEG_LENGTH"]


@dataclass(frozen=True)
class RSSMechanism(KernelMethods, RSSDescription):
    """An :class:`RSSDescription` with numeric methods on its generated kernels
    (:class:`~.kinematics.KernelMethods`: IK, J, Jq/Jx, mass matrices, FK).

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


def preset(name: str, **overrides) -> RSSMechanism:
    """The mechanism named ``name``, with parameters optionally overridden.

    The numeric mechanism of :func:`distkin.mechanisms.presets.preset_description`
    (which states the parameters, the overrides and the naming rule).
    """
    return RSSMechanism.from_description(preset_description(name, **overrides))
