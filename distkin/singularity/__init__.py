"""Singularities of the octahedral manipulator and its 6-6 equivalents (Rojas, Borràs,
Thomas, ICRA 2012, Sec. IV): the Plücker Jacobian (eq. (5)), the Cayley-Menger pure
condition, the four-planes test (:mod:`.conditions`), poses, paths and the nearest
singularity (:mod:`.paths`), and the certified zero exclusion of det J along a path
(:mod:`.enclosure`)."""

from .conditions import (OCTAHEDRAL_LEGS, octahedral_joints, plucker_jacobian,
                         jacobian_det, cm_pure_condition, signed_cm_condition,
                         volume_factors, four_planes, FourPlanes, certified_sign,
                         RATIO_CONSTANT, PLANES)
from .paths import (rotation_from_vector, pose_points, PosePath, Crossing, SignChange,
                    path_crossings, path_sign_changes, certify_crossing, NearestSingularity,
                    nearest_singularity)
from .enclosure import ZeroExclusion, det_series, exclude_zeros, monotone_on

__all__ = [
    "OCTAHEDRAL_LEGS",
    "octahedral_joints",
    "plucker_jacobian",
    "jacobian_det",
    "cm_pure_condition",
    "signed_cm_condition",
    "volume_factors",
    "four_planes",
    "FourPlanes",
    "certified_sign",
    "RATIO_CONSTANT",
    "PLANES",
    "rotation_from_vector",
    "pose_points",
    "PosePath",
    "Crossing",
    "SignChange",
    "path_crossings",
    "path_sign_changes",
    "certify_crossing",
    "NearestSingularity",
    "nearest_singularity",
    "ZeroExclusion",
    "det_series",
    "exclude_zeros",
    "monotone_on",
]
