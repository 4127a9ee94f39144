"""Δ-transforms of the octahedral manipulator (Rojas, Borràs, Thomas, *The Octahedral
Manipulator Revisited*, ICRA 2012, Sec. V, eqs. (7)-(9)): :mod:`.transform` (offsets ->
(A, b), the transform itself) and the equivalent 6-6 platforms with their forward
kinematics; the approximations of Fig. 2 (b)-(d) and what their offsets cost
(:mod:`.approximations`, :mod:`.offset_study`, the singular locus in
:mod:`.singular_locus`).  Their inputs are checked and made exact in :mod:`.exact_input`
(a bare float is its exact binary value); the true poses of the study are checked in
:mod:`.pose_input`."""

from .transform import (RowSpec, ROWS, SIDE_NAMES, Eq7, derive_eq7, delta_matrices,
                        side_lengths, DeltaTransform, delta_transform)
from .platform66 import (Platform66, equivalent_platform, check_offsets,
                         forward_kinematics66, Pose66, FK66Result)
from .approximations import (KINDS, octahedral_as_66, standard_approximation,
                             stoughton_arai_approximation, griffis_duffy_approximation,
                             approximation, joint_offsets)
from .offset_study import (PoseError, neglected_offset_error, PoseLine, normal_line,
                           singularity_shift, Comparison, compare_approximations)

__all__ = [
    "RowSpec",
    "ROWS",
    "SIDE_NAMES",
    "Eq7",
    "derive_eq7",
    "delta_matrices",
    "side_lengths",
    "DeltaTransform",
    "delta_transform",
    "Platform66",
    "equivalent_platform",
    "check_offsets",
    "forward_kinematics66",
    "Pose66",
    "FK66Result",
    "KINDS",
    "octahedral_as_66",
    "standard_approximation",
    "stoughton_arai_approximation",
    "griffis_duffy_approximation",
    "approximation",
    "joint_offsets",
    "PoseError",
    "neglected_offset_error",
    "PoseLine",
    "normal_line",
    "singularity_shift",
    "Comparison",
    "compare_approximations",
]
