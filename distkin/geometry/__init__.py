"""Distance geometry: Cayley-Menger determinants, trilateration, poses."""

from .cayley_menger import (CancellationWarning, FloatRangeWarning, cayley_menger, parse_label,
                            squared_distances, tetrahedron_volume_squared,
                            triangle_area_squared)
from .trilateration import trilaterate, trilaterate_both, trilateration_parts
from .poses import points_from_pose, pose_from_points, triangle_frame

__all__ = [
    # Cayley-Menger determinants (Rojas et al., eq. (1))
    "cayley_menger", "squared_distances", "triangle_area_squared",
    "tetrahedron_volume_squared", "parse_label", "FloatRangeWarning", "CancellationWarning",
    # trilateration (Thomas & Ros 2005)
    "trilaterate", "trilaterate_both", "trilateration_parts",
    # rigid poses from three points, and back
    "pose_from_points", "points_from_pose", "triangle_frame",
]
