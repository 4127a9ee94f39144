"""Forward kinematics of a leg table with the octahedral topology: the exact octic.

A 6-SPS/UPS table whose legs join three base points and three platform points in one
cycle (:meth:`~.legs.LegsDescription.octahedral`) is the octahedral manipulator of
Rojas, Borràs, Thomas (ICRA 2012): its forward kinematics is the octic of eq. (3), every
assembly mode at once (:func:`distkin.octahedral.forward_kinematics`, ``method="auto"``:
the fast tier when it proves its roots, else the certified one).
:meth:`~.kinematics.KernelMethods.forward_kinematics` chooses this route automatically
for such a table and returns the assembly mode nearest the guess (position error plus
rotation angle times the length scale), with the closure residual and conditioning of
that pose from the generated kernels, as the Gauss-Newton route does.
"""

from __future__ import annotations

import numpy as np

from ..spatial import pose_error, rotation_angles

__all__ = ["octahedral_forward"]


def octahedral_forward(mech, q, guess=None, *, method: str = "auto"):
    """Every assembly mode of an octahedral leg table, and the one nearest ``guess``.

    Parameters
    ----------
    mech : a leg mechanism whose ``octahedral()`` is not None
    q : (6,) or (N, 6)
        Leg lengths (m), in the table's order.
    guess : (6,) or (N, 6), optional
        The pose to be nearest to (default: home).
    method : {"fast", "precise", "certified", "auto"}
        Tier of :func:`distkin.octahedral.forward_kinematics`; for N > 1 leg sets
        "fast" and "auto" solve them in one call of
        :func:`~distkin.octahedral.forward_kinematics_batched` (the same tiers and
        escalations, per problem).

    Returns
    -------
    poses : array (N, 6) (or (6,))
        The nearest assembly mode (NaN where the legs admit none).
    modes : list of arrays (M_n, 6)
        Every assembly mode, per problem.
    tiers : list of str
        The tier that answered each problem.
    """
    from ..octahedral import forward_kinematics, forward_kinematics_batched
    topo = mech.octahedral()
    qa = np.asarray(q, dtype=float)
    single = qa.ndim == 1
    qa = qa.reshape(-1, 6)
    g = np.broadcast_to(np.asarray(mech.home if guess is None else guess, dtype=float),
                        (len(qa), 6))
    legs = qa[:, topo["order"]]
    batch = None
    if len(qa) > 1 and method in ("fast", "auto"):   # one compiled call for every problem
        batch = forward_kinematics_batched(topo["base"], topo["platform"], legs,
                                           method=method)
    poses, modes, tiers = np.full((len(qa), 6), np.nan), [], []
    for n in range(len(qa)):
        if batch is not None and n not in batch.escalated:
            ok = batch.valid[n]
            X = np.concatenate([batch.translation[n][ok],
                                rotation_angles(batch.rotation[n][ok])], axis=1)
            tiers.append(str(batch.tier[n]))
        else:
            res = (batch.escalated[n] if batch is not None else
                   forward_kinematics(topo["base"], topo["platform"], legs[n], method=method))
            X = np.array([np.concatenate([p.translation, rotation_angles(p.rotation)])
                          for p in res]).reshape(-1, 6)
            tiers.append(getattr(res, "tier", method))
        modes.append(X)
        if len(X):
            dp, da = pose_error(X, g[n][None])
            poses[n] = X[int(np.argmin(dp + da * mech.length_scale))]
    return (poses[0] if single else poses), modes, tiers
