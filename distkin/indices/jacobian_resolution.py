"""Poses of the performance study whose Jacobian float64 does not resolve (QA 25a F4).

Next to a leg's reach boundary (a serial singularity: :math:`J_{q,ii} = \\mp l_1 h / l_3
\\to 0`, h the square root of the reach margin) the fast J loses digits like
:math:`\\delta m / (2h^2)`, δm the margin's rounding: the study's σ and GII at the
Octopod's pose (0, 0, 0.49732875444719654 m) were 15 % off the certified J's, without a
word, where :meth:`~distkin.mechanisms.kinematics.KernelMethods.jacobian` warns.  The
study now asks the same question as that method, with the same two steps:

1. the mechanism's cheap screen (``_row_limit``): a row of J whose translational part
   has :math:`|J_{l,1:3}|^2` above a per-leg limit, the limit met at a reach margin
   of :math:`10^{-6}(l_1+l_3)^3/l_1` (that part is :math:`1/|J_{q,ii}| = l_3/(l_1 h)`),
   a hundred times further out than where the estimate below flags a row
   (tests/mechanisms/test_jacobian_resolution.py checks the screen is a superset); and
   before it one comparison of max|J| with the largest entry no row below its limit can
   have (on the presets' Table II grids no pose passes even that: the cost is one pass
   over J, well under 1 % of the study's per-pose work);
2. on the poses it lets through, the fast tier's first-order error estimate of J
   (:func:`~distkin.mechanisms.kinematics_tiers.jacobian_tier` ``"fast"``, its
   ``inaccurate``: a row of a leg that closes whose estimated error exceeds
   :data:`~distkin.mechanisms.kinematics_tiers.J_REL_USEFUL` = 1e-6 of the row).

The flagged poses are the study's *unresolved* poses: :func:`~.study.evaluate_poses`
warns (:class:`~distkin.errors.ConditioningWarning`) and marks them, and the sweep leaves
them out of every extreme and counts them (``n_unresolved``, ``unresolved_poses``).
"""

from __future__ import annotations

import numpy as np

from ..errors import ConditioningWarning, warn

__all__ = ["unresolved_poses", "warn_unresolved"]


def unresolved_poses(mech, poses, J) -> np.ndarray:
    """(N,) bool: at pose n a row of J (the study's, of a leg that closes) is not
    resolved in float64 (module docstring).

    Parameters
    ----------
    mech : RSSMechanism or LegMechanism
        A mechanism without the fast tier's screen (no ``_row_limit``) gives all False.
    poses : ndarray (N, 6)
        m and rad, every leg closing.
    J : ndarray (N, L, 6)
        The study's J at ``poses`` (finite).
    """
    n = len(J)
    out = np.zeros(n, bool)
    row_limit = getattr(mech, "_row_limit", None)
    if not n or row_limit is None:
        return out
    lim, gate = row_limit()
    if not np.abs(J).max() > gate:              # no row can exceed its limit
        return out
    big = np.einsum("nli,nli->nl", J[..., :3], J[..., :3]) > lim
    rows = np.flatnonzero(big.any(axis=1))
    if len(rows):
        # the steps of the mechanism's own check (KernelMethods._check_resolution),
        # without its warning (evaluate_poses says it once) or the global warning
        # filters (the sweep may run in threads)
        from ..mechanisms.kinematics_tiers import _fast_jacobian_error
        Xs = np.ascontiguousarray(np.asarray(poses, dtype=float)[rows])
        jq_jx = mech._fast("jq_jx", Xs, warn=False)
        q = mech.kernels("batched").ik(Xs)
        out[rows] = _fast_jacobian_error(mech, Xs, q, J[rows], jq_jx[..., 0],
                                         jq_jx[..., 1:])[3]
    return out


def warn_unresolved(ok, flag, poses) -> None:
    """One :class:`~distkin.errors.ConditioningWarning` when ``flag`` (ok.sum(),),
    over the reachable poses ``ok`` (N,) of ``poses`` (N, 6), flags any: how many,
    and the first one by its index in ``poses``."""
    if not flag.any():
        return
    i = int(np.flatnonzero(ok)[np.argmax(flag)])
    warn(f"evaluate_poses: at {int(flag.sum())} of {len(flag)} reachable pose(s) a row "
         f"of J is not resolved in float64 (first: pose {i}, ("
         + ", ".join(f"{x:.17g}" for x in np.asarray(poses)[i]) + ") m, rad; "
         "a leg within rounding of its reach boundary, a serial singularity): every "
         f"index there, sigma and GII included, is inaccurate; values['J_unresolved'] "
         f"marks those poses, and the study sweep leaves them out of its extremes and "
         f"counts them (unresolved_poses); jacobian_tier(mech, poses, 'precise') gives J "
         f"there", ConditioningWarning)
