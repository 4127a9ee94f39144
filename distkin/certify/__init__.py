"""Certified computations (python-flint).

* real roots of exact polynomials: :mod:`distkin.exact_roots` (re-exported here);
* :mod:`.boxes` -- certified regular / singular boxes of poses of RSS mechanisms, by
  interval branch-and-prune (:mod:`.intervals`, :mod:`.taylor`, :mod:`.linearize` for the
  enclosures, :mod:`.workspace` for whole regions as resumable chunks of
  :mod:`distkin.runstore`, :mod:`.tighten` for a sharper σmin bound over a certified
  region, :mod:`.plot` for the Fig. 3 analogue); the scene query
  ``certify_workspace`` is :mod:`distkin.app.queries.certify`;
* :mod:`.krawczyk` -- a unique zero of a square system in a proved box (Krawczyk's test),
  for the certified forward kinematics of RSS and leg mechanisms
  (:mod:`distkin.mechanisms.forward_tiers`).
"""

from .boxes import (REGULAR, SINGULAR, STATUS_NAMES, UNDECIDED, UNREACHABLE, Verdict,
                    branch_and_prune, certify_box)
from ..exact_roots import RealRoot, count_real_roots, real_roots, refine_roots, sign_at_root
from .tighten import SigmaBound, tighten_sigma
from .workspace import WorkspaceCertificate, certify_workspace

__all__ = ["RealRoot", "real_roots", "count_real_roots", "refine_roots", "sign_at_root",
           "certify_box", "branch_and_prune", "certify_workspace", "WorkspaceCertificate",
           "tighten_sigma", "SigmaBound",
           "Verdict", "REGULAR", "SINGULAR", "UNDECIDED", "UNREACHABLE", "STATUS_NAMES"]
