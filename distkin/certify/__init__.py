"""Certified computations (python-flint).

* :mod:`.roots` -- real roots of exact polynomials;
* :mod:`.boxes` -- certified regular / singular boxes of poses of RSS mechanisms, by
  interval branch-and-prune (:mod:`.intervals`, :mod:`.taylor`, :mod:`.linearize` for the
  enclosures, :mod:`.workspace` for whole regions as resumable chunks, :mod:`.query` for
  the scene query ``certify_workspace``, :mod:`.plot` for the Fig. 3 analogue).
"""

from .boxes import (REGULAR, SINGULAR, STATUS_NAMES, UNDECIDED, UNREACHABLE, Verdict,
                    branch_and_prune, certify_box)
from ..exact_roots import RealRoot, count_real_roots, real_roots, refine_roots, sign_at_root
from .workspace import WorkspaceCertificate, certify_workspace

__all__ = ["RealRoot", "real_roots", "count_real_roots", "refine_roots", "sign_at_root",
           "certify_box", "branch_and_prune", "certify_workspace", "WorkspaceCertificate",
           "Verdict", "REGULAR", "SINGULAR", "UNDECIDED", "UNREACHABLE", "STATUS_NAMES"]
