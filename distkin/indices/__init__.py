"""Performance indices of parallel robots (Kühne et al., Sec. II-C and III-B/C).

Modules
-------
zonotope       the exact half-space kernel of DESIGN.md §6 (worst case = nearest facet,
               best case = farthest vertex), batched over poses
capability     public ``worst_case_output`` / ``best_case_output`` with the three methods
               (zonotope, the paper's Qhull polytope algorithm, Ueberle's method) and the
               generator matrices of eqs. (5)-(7)
sensitivity    Cardou's maximum sensitivities
isotropy       κ (eq. (4)) with the scaling matrix ST, the GII, Stocco's culling
workspace      pose grids (Table II), the dexterous workspace (eq. (17)), the design
               criteria of Sec. II-A
rss_jacobian   plain-numpy IK and Jacobian of RSS legs (design sweeps, no codegen)
study          per-pose evaluation and per-position reduction of a study sweep
design         GII design sweeps over Table I
sweep          chunked, resumable runs on any concurrent.futures executor or dask
study_report   Table III/IV analogues, findings, criteria; plots: Figs. 5-7
query          the scene queries ``performance`` and ``design_sweep`` (kind ``rss``) and
               the ``distkin sweep`` subcommand
"""

from .capability import (CAPABILITY_METHODS, best_case_output, output_generators,
                         worst_case_output)
from .isotropy import (ST_DEFAULT, brute_force_sweep, condition_number, culling_sweep, gii,
                       scaled_singular_values)
from .sensitivity import max_sensitivities
from .workspace import PoseGrid, dexterous_workspace, design_criteria, table2_grid
from .zonotope import facet_normals

__all__ = [
    # output capabilities, eqs. (5)-(16)
    "worst_case_output", "best_case_output", "output_generators", "CAPABILITY_METHODS",
    "facet_normals",
    # maximum sensitivities (Cardou)
    "max_sensitivities",
    # isotropy, eq. (4), GII, culling
    "scaled_singular_values", "condition_number", "gii", "culling_sweep",
    "brute_force_sweep", "ST_DEFAULT",
    # workspace, eq. (17), Sec. II-A
    "PoseGrid", "table2_grid", "dexterous_workspace", "design_criteria",
]
