"""Certified computations (python-flint): real roots of exact polynomials."""

from .roots import RealRoot, count_real_roots, real_roots, refine_roots, sign_at_root

__all__ = ["RealRoot", "real_roots", "count_real_roots", "refine_roots", "sign_at_root"]
