"""Performance indices of parallel robots (Kühne et al., Sec. II-C and III-B/C).

Modules
-------
zonotope       the exact half-space kernel of docs/design.md §6 (worst case = nearest facet,
               best case = farthest vertex), batched over poses
capability     public ``worst_case_output`` / ``best_case_output`` with the three methods
               (zonotope, the paper's Qhull polytope algorithm, Ueberle's method) and the
               generator matrices of eqs. (5)-(7)
sensitivity    maximum sensitivities: the paper's slice (eqs. (14), (16)) or Cardou's
               projection
slice_farthest the compiled farthest point of a sliced zonotope (the paper's
               sensitivities)
constraint_basis  the orthonormal basis of a slice's removed rows that both farthest-
               point enumerations work on (compiled)
velocity_set   the true velocity set {ẋ : |Jẋ|∞ <= q̇max} of a redundant device
isotropy       κ (eq. (4)) with the scaling matrix ST (every reading), the GII,
               Stocco's culling
workspace      pose grids (Table II), the dexterous workspace (eq. (17)), the design
               criteria of Sec. II-A
study          per-pose evaluation and per-position reduction of a study sweep
design         GII design sweeps over Table I
study_findings the paper's findings held / not held / not comparable
plots          the study's figures (matplotlib)

Elsewhere: the plain-numpy RSS model of the design sweeps is
:mod:`distkin.mechanisms.reference`; chunked, resumable runs are :mod:`distkin.runstore`;
the Table III/IV and Table I reports and the scene queries ``performance`` and
``design_sweep`` are in :mod:`distkin.app` (``study_report``, ``design_report``,
``queries.indices``).
"""

from .. import _jitcache  # noqa: F401  (drops numba caches older than the sources)
from .capability import (CAPABILITY_METHODS, best_case_output, output_generators,
                         worst_case_output)
from .isotropy import (SCALING_READINGS, ST_DEFAULT, brute_force_sweep, condition_number,
                       culling_sweep, gii, reading_singular_values, scaled_singular_values)
from .sensitivity import SENSITIVITY_MODES, max_sensitivities
from .velocity_set import true_velocity_worst
from .workspace import PoseGrid, dexterous_workspace, design_criteria, table2_grid
from .zonotope import facet_normals

__all__ = [
    # output capabilities, eqs. (5)-(16)
    "worst_case_output", "best_case_output", "output_generators", "CAPABILITY_METHODS",
    "facet_normals",
    # the true velocity set of a redundant device
    "true_velocity_worst",
    # maximum sensitivities (the paper's slice; Cardou's projection)
    "max_sensitivities", "SENSITIVITY_MODES",
    # isotropy, eq. (4), GII, culling, readings of the scaling
    "scaled_singular_values", "condition_number", "gii", "culling_sweep",
    "brute_force_sweep", "ST_DEFAULT", "SCALING_READINGS", "reading_singular_values",
    # workspace, eq. (17), Sec. II-A
    "PoseGrid", "table2_grid", "dexterous_workspace", "design_criteria",
]
