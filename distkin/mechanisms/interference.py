"""Link interference of leg mechanisms (RSS/RRRS presets and any leg table):
segment-segment distances between the links.

Kühne et al. draw the legs of Fig. 2 as lines; whether a reading of that figure can be
*built* depends on whether its links stay apart.  Every link is modelled as the segment
between its joint centres (a rod of zero thickness), and the rigid bodies by their
minimal frames:

* per revolute leg i: the crank ``B_i -> C_i``, the offset ``C_i -> D_i`` (RRRS, a
  non-zero ``offset``) and the distal link ``D_i -> P_i``; per prismatic leg the leg
  ``B_i -> P_i`` (joint points of :meth:`~.kinematics.KernelMethods.points`);
* the end effector: spokes from its centre to each spherical joint ``x -> P_i``;
* the base: spokes from the base centre to each crank pivot ``0 -> B_i``.

Two segments are checked when they share no joint: every pair of segments of different
legs, every leg segment against every spoke not attached to that leg (the distal link
i against the end-effector spokes j != i, the crank i against the base spokes j != i,
the other combinations all).  A joint is a point of a body (base or end effector, by
its coordinates in the table): legs that share one (the octahedral manipulator, Rojas
et al. Fig. 4) or a joint at a frame's origin are attached there, not touching.  A pose
*interferes* when the smallest distance is below ``clearance`` (default 5 mm: two rods
of 5 mm diameter touch; the pair spacing of the presets is ld = 20 mm).  Motor housings
and joint bodies are not modelled.

The distance of two segments is the closest-point computation of Ericson [1], Sec.
5.1.9, batched with numpy (parallel segments included).

References
----------
.. [1] C. Ericson, *Real-Time Collision Detection*, Morgan Kaufmann, 2005, Sec. 5.1.9.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["segment_distance", "link_segments", "interference", "Interference",
           "CLEARANCE"]

#: default clearance between link axes (m)
CLEARANCE = 0.005


def segment_distance(p1, q1, p2, q2):
    """Smallest distance between segments ``p1-q1`` and ``p2-q2``, batched.

    Parameters
    ----------
    p1, q1, p2, q2 : array (..., 3)
        End points (any unit); broadcast together.

    Returns
    -------
    array (...)
        Distance in the unit of the input; exact up to rounding, also for parallel or
        degenerate (point) segments (Ericson [1], Sec. 5.1.9).
    """
    p1, q1, p2, q2 = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (p1, q1, p2, q2)))
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a = np.einsum("...i,...i->...", d1, d1)
    e = np.einsum("...i,...i->...", d2, d2)
    f = np.einsum("...i,...i->...", d2, r)
    c = np.einsum("...i,...i->...", d1, r)
    b = np.einsum("...i,...i->...", d1, d2)
    tiny = 1e-300
    denom = a * e - b * b
    # s on the first segment: closest point of the infinite lines, clamped; parallel -> 0
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(denom > 1e-14 * a * e + tiny, np.clip((b * f - c * e) / denom, 0, 1), 0.0)
        t = np.where(e > tiny, (b * s + f) / e, 0.0)
        # t outside [0, 1]: clamp it and recompute s for the clamped t
        s = np.where(t < 0, np.where(a > tiny, np.clip(-c / a, 0, 1), 0.0), s)
        s = np.where(t > 1, np.where(a > tiny, np.clip((b - c) / a, 0, 1), 0.0), s)
    t = np.clip(t, 0, 1)
    diff = (p1 + d1 * s[..., None]) - (p2 + d2 * t[..., None])
    return np.sqrt(np.einsum("...i,...i->...", diff, diff))


def link_segments(mech, poses, q=None):
    """The segments of :mod:`interference <.interference>` at each pose.

    Parameters
    ----------
    mech : RSSMechanism or LegMechanism
        Any leg table: a revolute leg has a crank, an offset (when its ``offset`` is not
        zero: the RRRS offset l2) and a distal link; a prismatic leg one segment
        ``leg`` from its base joint to its platform joint.
    poses : array (N, 6)
    q : array (N, L), optional
        Joint values (rad, m); default the inverse kinematics.

    Returns
    -------
    start, end : arrays (N, S, 3) (m)
    leg : array (S,) of int
        Leg of each segment; -1 for the end-effector and base spokes.
    joint : array (S,) of int
        The leg whose joint a spoke is attached to (-1 for leg segments).
    kind : list of S str
        ``crank``, ``offset``, ``distal``, ``leg`` (prismatic), ``effector spoke``,
        ``base spoke``.
    """
    st, en, leg, joint, kind, _ = _segments(mech, poses, q)
    return st, en, leg, joint, kind


def _segments(mech, poses, q=None):
    """:func:`link_segments` and the joints (a, b) at each segment's ends: a joint is
    named by its body and its point in that body's frame (``("base", B)``,
    ``("effector", p)``; a spoke starts at its frame's origin), so legs that share a
    joint (the octahedral manipulator's, Rojas et al. Fig. 4), or a joint at a frame's
    origin, are attached there, not touching; a crank tip or offset end is its leg's own
    (``("leg", i, "C")``)."""
    X = np.atleast_2d(np.asarray(poses, dtype=float))
    pts = mech.points(X, q)
    B, C, D, P = pts["B"], pts["C"], pts["D"], pts["P"]
    d = mech.leg_arrays()
    N, L, _ = B.shape
    starts, ends, leg, joint, kind, ends_at = [], [], [], [], [], []
    base = [("base", tuple(b)) for b in d["B"]]
    eff = [("effector", tuple(p)) for p in d["p"]]
    for i in range(L):
        if d["prismatic"][i]:
            segs = [("leg", B, P, base[i], eff[i])]
        else:
            segs = [("crank", B, C, base[i], ("leg", i, "C"))]
            if np.any(d["offset"][i] != 0):
                segs.append(("offset", C, D, ("leg", i, "C"), ("leg", i, "D")))
            segs.append(("distal", D, P, segs[-1][4], eff[i]))
        for name, a, b, ja, jb in segs:
            starts.append(a[:, i])
            ends.append(b[:, i])
            leg.append(i)
            joint.append(-1)
            kind.append(name)
            ends_at.append((ja, jb))
    for name, a, pts_, joints in (("effector", X[:, :3], P, eff),
                                  ("base", np.zeros((N, 3)), B, base)):
        for i in range(L):                  # from the frame's origin, a point of the body
            starts.append(a)
            ends.append(pts_[:, i])
            leg.append(-1)
            joint.append(i)
            kind.append(name + " spoke")
            ends_at.append(((name, (0.0, 0.0, 0.0)), joints[i]))
    return (np.stack(starts, axis=1), np.stack(ends, axis=1), np.array(leg), np.array(joint),
            kind, ends_at)


def _pairs(leg, ends_at):
    """Index pairs (a, b) of segments that share no joint (``ends_at``, of
    :func:`_segments`), of different legs or a leg and a spoke (not two spokes: the
    frames are one body each)."""
    S = len(leg)
    out = []
    for a in range(S):
        for b in range(a + 1, S):
            la, lb = leg[a], leg[b]
            if (la >= 0 and la == lb) or (la < 0 and lb < 0):
                continue                    # one leg, or spokes of the frames
            if set(ends_at[a]) & set(ends_at[b]):
                continue                    # attached at a joint
            out.append((a, b))
    return np.array(out, dtype=np.intp).reshape(-1, 2)


@dataclass(frozen=True)
class Interference:
    """Result of :func:`interference` for N poses.

    Attributes
    ----------
    distance : array (N,)
        Smallest distance between two checked segments (m).
    pair : list of N str
        Which two segments, e.g. ``"crank 0 / crank 7"``.
    clearance : float
        Required distance (m).
    """

    distance: np.ndarray
    pair: list
    clearance: float

    @property
    def ok(self) -> np.ndarray:
        """(N,) bool: every checked distance is at least the clearance."""
        return self.distance >= self.clearance


def _name(kind, leg, joint, k):
    return f"{kind[k]} {leg[k] if leg[k] >= 0 else joint[k]}"


def interference(mech, poses, *, clearance: float = CLEARANCE, q=None,
                 batch: int = 4096) -> Interference:
    """Smallest link-to-link distance of ``mech`` at each pose (module docstring).

    Parameters
    ----------
    mech : RSSMechanism or LegMechanism
    poses : array (N, 6) or (6,), or 4x4 matrices
        m and rad.
    clearance : float
        Required distance between link axes (m), >= 0.
    q : array (N, L), optional
        Crank angles (rad); default the inverse kinematics (legs that cannot close are
        drawn at their clipped angle: check reachability separately).
    batch : int
        Poses per vectorised block.

    Returns
    -------
    Interference
    """
    if not (isinstance(clearance, (int, float)) and not isinstance(clearance, bool)
            and clearance >= 0):
        raise InputError(f"expected a clearance >= 0 (m), got {clearance!r}", field="clearance")
    if not (isinstance(batch, (int, np.integer)) and not isinstance(batch, bool) and batch > 0):
        raise InputError(f"expected a positive integer batch (poses per block), got "
                         f"{batch!r}", field="batch")
    from .description import _poses, _rows
    X, _ = _poses(poses, scale=mech.length_scale)        # (6,), (N, 6), 4x4; finite
    qq = None
    if q is not None:
        from ..argcheck import as_floats
        what = "joint values (rad, or m for prismatic legs)"
        qq, _ = _rows(as_floats(q, "q", what), "q", mech.L, what)
        if len(qq) != len(X):
            raise InputError(f"expected {len(X)} rows of joint values (one per pose), got "
                             f"{len(qq)}", field="q")
    dist = np.empty(len(X))
    which = np.empty(len(X), dtype=np.intp)
    pairs = None
    for lo in range(0, len(X), batch):
        sl = slice(lo, min(len(X), lo + batch))
        st, en, leg, joint, kind, ends_at = _segments(mech, X[sl],
                                                      None if qq is None else qq[sl])
        if pairs is None:
            pairs = _pairs(leg, ends_at)
        dd = segment_distance(st[:, pairs[:, 0]], en[:, pairs[:, 0]],
                              st[:, pairs[:, 1]], en[:, pairs[:, 1]])      # (n, K)
        which[sl] = np.argmin(dd, axis=1)
        dist[sl] = dd[np.arange(len(dd)), which[sl]]
    names = [f"{_name(kind, leg, joint, pairs[k, 0])} / {_name(kind, leg, joint, pairs[k, 1])}"
             for k in which]
    return Interference(dist, names, float(clearance))
