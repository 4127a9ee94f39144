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

from .description import GEOMETRY_FIELDS, LAYOUTS, LEG_LENGTH, RSSDescription
from .kinematics import KernelMethods
from .presets import preset_parameters

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


def preset(name: str, **overrides) -> RSSMechanism:
    """The mechanism named ``name``, with parameters optionally overridden.

    The numeric mechanism of :func:`distkin.mechanisms.presets.preset_description`
    (which states the parameters, the overrides and the naming rule).  Warns
    (:class:`~.description.GeometryWarning`) for an override 100x or more off the
    preset's value (a unit slip: SI here, m and rad) and for a home pose some leg does
    not reach.
    """
    label, params = preset_parameters(name, **overrides)
    return RSSMechanism(name=label, **params)
