"""The model behind the scene query ``singularity`` (:mod:`.singularity`, and its path
part :mod:`.singularity_path`): an octahedral manipulator (or its Δ-transformed 6-6
platform) as points and poses, and the three tests of Rojas, Borràs, Thomas, *The
Octahedral Manipulator Revisited*, Sec. IV (det J of eq. (5), the Cayley-Menger pure
condition, the four-planes test) evaluated at poses, with the checks both parts share.
"""

from __future__ import annotations

import numpy as np

from ...errors import DegenerateGeometryError
from ...exact import to_tier

__all__ = ["OctahedralModel"]


class OctahedralModel:
    """Octahedral geometry (float and arb) and, optionally, its 6-6 Δ-transform."""

    def __init__(self, base_f, plat_f, base_x, plat_x, L, deg, platform66=None):
        self.base_f, self.plat_f = base_f, plat_f
        self._exact = (base_x, plat_x)      # the scene's exact values
        self._arb = {}                      # flint.ctx.prec -> (base_a, plat_a)
        self.L = L
        self.angle = (np.pi / 180) if deg else 1.0
        self.deg = deg
        self.platform66 = platform66

    @classmethod
    def build(cls, mech, offsets=None, length_scale=None, deg=False):
        base_f = np.array([[float(x) for x in r] for r in mech.base])
        plat_f = np.array([[float(x) for x in r] for r in mech.platform])
        L = length_scale or float(np.max(np.linalg.norm(plat_f - plat_f.mean(0), axis=1)))
        p66 = None
        if offsets is not None:
            from ...delta import equivalent_platform
            p66 = equivalent_platform(mech, offsets)
        return cls(base_f, plat_f, mech.base, mech.platform, L, deg, p66)

    # -- arb points at the working precision (flint.ctx.prec) of the caller: an
    # irrational coordinate ("sqrt(108)") is a ball of that precision, not of the
    # precision at build time
    @property
    def base_a(self):
        return self._arb_points()[0]

    @property
    def plat_a(self):
        return self._arb_points()[1]

    def _arb_points(self):
        import flint
        prec = flint.ctx.prec
        if prec not in self._arb:
            self._arb[prec] = tuple(
                np.array([[to_tier(x, "certified") for x in r] for r in rows], dtype=object)
                for rows in self._exact)
        return self._arb[prec]

    # -- float, batched over poses
    def points(self, R, t):
        P = np.einsum("...ij,nj->...ni", R, self.plat_f) + t[..., None, :]
        return np.concatenate([np.broadcast_to(self.base_f, P.shape), P], axis=-2)

    def det_j(self, R, t):
        from ...singularity import jacobian_det, octahedral_joints
        return jacobian_det(*octahedral_joints(self.points(R, t)), length_scale=self.L,
                            warn=False)

    # -- arb, one pose
    def det_j_arb(self, R, t):
        from ...singularity import jacobian_det, octahedral_joints, pose_points
        P = pose_points(self.plat_a, R, t)
        X = np.concatenate([self.base_a, P], axis=0)
        return jacobian_det(*octahedral_joints(X), normalised=False, method="certified")

    # -- mpmath, one pose (the scene's exact points at dps digits)
    def det_j_precise(self, R, t, dps):
        """``(det J, its rounding-error estimate)`` at an mpmath pose R (3,3), t (3,),
        at ``dps`` digits (moments over L, as :meth:`det_j`)."""
        import mpmath

        from ...singularity import jacobian_det, octahedral_joints, pose_points
        with mpmath.workdps(dps):
            base, plat = (np.array([[to_tier(x, "precise") for x in r] for r in rows],
                                   dtype=object) for rows in self._exact)
            X = np.concatenate([base, pose_points(plat, R, t)], axis=0)
        return jacobian_det(*octahedral_joints(X), length_scale=self.L, method="precise",
                            with_error=True, dps=dps)

    def pose_path(self, a, b):
        from ...singularity import PosePath
        return PosePath(a.translation, a.rotation, b.translation, b.rotation, self.deg)

    def reference_point(self, about: str = "origin", unit: str = ""):
        """The point the nearest-singularity search turns the platform about (QA 25a F3):
        ``(c, text)``, c (3,) in the platform frame (scene length units) and the words
        the report prints, naming the platform point it coincides with (P4, P5, P6);
        ``unit`` (" mm", or "" for a unitless scene) follows a coordinate the words give
        (QA 25b F6: "the centroid is at (…)" had none)."""
        mean = self.plat_f.mean(axis=0)
        if about == "centroid":
            return mean, "the platform centroid"
        c = np.zeros(3)
        at = [f"P{4 + i}" for i, q in enumerate(self.plat_f) if not np.any(q)]
        size = float(np.max(np.abs(self.plat_f)))
        where = (f"{at[0]} here" if at else "the platform centroid here"
                 if np.linalg.norm(mean) <= 1e-12 * size else
                 "not a joint; the centroid is at (" + ", ".join(f"{x:.6g}" for x in mean)
                 + f"){unit}")
        return c, f"the platform frame's origin ({where})"

    def rotation(self, pose):
        from ...singularity import rotation_from_vector
        return rotation_from_vector(np.array([float(x) for x in pose.rotation]) * self.angle)


def _check_legs(model, R, t, field):
    """A zero-length leg (its line undefined) at float poses R (n,3,3), t (n,3):
    :class:`DegenerateGeometryError` naming the leg by its joints (P1–P4, ...)."""
    from ...singularity import OCTAHEDRAL_LEGS, octahedral_joints
    b, q = octahedral_joints(model.points(R, t))
    zero = ~(np.linalg.norm(q - b, axis=-1) > 0)
    if zero.any():
        n, k = (int(i) for i in np.argwhere(zero)[0])
        i, j = OCTAHEDRAL_LEGS[k]
        where = f" at pose {n} of the path" if len(zero) > 1 else ""
        raise DegenerateGeometryError(
            f"expected legs of non-zero length, got leg {k + 1} (P{i}–P{j}) of length 0"
            f"{where}: P{j} coincides with P{i}, the leg's line is undefined", field=field)


def _guarded(f):
    """``f()``, or ``(None, reason)`` where a test is undefined (a degenerate plane or
    tetrahedron, :class:`DegenerateGeometryError`)."""
    try:
        return f(), None
    except DegenerateGeometryError as exc:
        # the queries evaluate one pose as a batch of one: its index says nothing
        return None, exc.message.replace(" at batch index (0,)", "")


def _guarded_relative(f):
    """A fast relative Cayley-Menger condition: ``(values, None)``, or ``(None, reason)``
    where it is undefined: exactly 0/0 (:class:`DegenerateGeometryError`), or both
    products within their rounding error estimate of 0 (NaN with a
    :class:`~distkin.geometry.cm_float.CancellationWarning`: QA V 2).  Other samples of a
    batch keep their values (NaN where undefined, and where the value's error estimate
    exceeds 1e-6: :func:`_tests` asks the precise tier there)."""
    import warnings
    from ...geometry.cm_float import CancellationWarning
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", CancellationWarning)
        out, why = _guarded(f)
    if why:
        return None, why
    val, err = out
    val = np.asarray(val, dtype=float)
    if np.isnan(val).all():
        msg = next((str(w.message) for w in caught if "undefined" in str(w.message)), "")
        return None, msg.replace(" at batch index (0,) (1 of 1)", "").split("; returned NaN")[0]
    # a value float64 cannot vouch for to 1e-6 is NaN here, for the precise tier to decide
    # (QA W 11: its CancellationWarning was dropped and the value printed bare)
    from ...geometry.cm_float import CANCELLATION_THRESHOLD
    return np.where(np.asarray(err, dtype=float) > CANCELLATION_THRESHOLD, np.nan, val), None


def _tests(model, R, t, escalate: bool = True):
    """All characterisations at float poses R (n,3,3), t (n,3).  A test that is
    undefined there (a flat tetrahedron, three collinear points of a plane) is None,
    with the reason in ``undefined``.  ``escalate``: a relative CM condition float64
    cannot vouch for goes to the precise tier (False where the caller computes them in
    arb anyway)."""
    from ...singularity import (cm_pure_condition, four_planes, plucker_jacobian,
                              octahedral_joints, signed_cm_condition)
    X = model.points(R, t)
    J = plucker_jacobian(*octahedral_joints(X))
    J[..., 3:] /= model.L
    out = {"det_J": np.linalg.det(J), "sigma_min": np.linalg.svd(J, compute_uv=False)[..., -1]}
    undefined, escalated = {}, {}
    for key, f in (("cm_condition_relative", cm_pure_condition),
                   ("signed_cm_relative", signed_cm_condition)):
        out[key], why = _guarded_relative(lambda: f(X, relative=True, with_error=True))
        # where float64 cannot vouch (NaN: its rounding-error estimate does not rule out
        # 0/0) the precise tier decides (QA W 2: the a priori estimate is far above the
        # actual error next to a small platform); an exact 0/0 stays undefined
        if escalate and ((why and "rounding error estimate" in why) or
                         (out[key] is not None and np.isnan(out[key]).any())):
            out[key], why, n = _escalate(f, X, out[key])
            if n:
                escalated[key] = (f"precise (mpmath, 30 digits) at {n} of {len(X)} "
                                  f"pose(s): float64's rounding-error estimate could not "
                                  f"rule out 0/0 there, or exceeded 1e-6")
        if why:
            undefined[key] = why
    # no warning: whether float64 resolves F's sign is a field of the result (QA 24)
    fp, why = _guarded(lambda: four_planes(X, length_scale=model.L, warn=False))
    if why:
        undefined["four_planes"] = why
    out.update({"four_planes_resolved": None if fp is None else
                np.asarray(np.asarray(fp.det_error) < np.abs(np.asarray(fp.det))),
                "four_planes_relative": None if fp is None else np.asarray(fp.relative),
                "four_planes_spread": None if fp is None else np.asarray(fp.spread),
                "four_planes_point": None if fp is None else fp.point,
                "undefined": undefined, "escalated": escalated})
    return out


def _escalate(f, X, fast):
    """The relative condition ``f`` at the poses of ``X`` (n, 6, 3) where the fast value
    is undefined (NaN, or ``fast`` None: all), in the precise tier: (values, reason or
    None, how many were escalated).  Where precise cannot rule out 0/0 either, the value
    stays NaN and the reason is its warning."""
    import warnings
    from ...geometry.cm_float import CancellationWarning
    vals = np.full(len(X), np.nan) if fast is None else np.array(fast, dtype=float)
    why, n = None, 0
    for i in np.flatnonzero(np.isnan(vals)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", CancellationWarning)
            try:
                v = float(f(X[i], relative=True, method="precise"))
            except DegenerateGeometryError as exc:
                v, why = float("nan"), exc.message
        if v == v:
            vals[i], n = v, n + 1
        elif why is None:
            why = next((str(w.message).split("; returned NaN")[0] for w in caught),
                       "undefined in the precise tier too")
    if np.isnan(vals).all():
        return None, why, n
    return vals, None, n


def _opt(v):
    return None if v is None else float(v)


def _sampled(f, what, notes):
    """``f`` over a grid of s, NaN at the samples where the test is undefined (one
    note naming them and why); batched when no sample is."""
    def g(s):
        try:
            return f(s)
        except DegenerateGeometryError:
            vals = np.array([_guarded(lambda: f(np.array([x])))[0] for x in s], dtype=object)
            bad = [float(x) for x, v in zip(s, vals) if v is None]
            why = _guarded(lambda: f(np.array([bad[0]])))[1]
            notes.append(f"  {what} undefined at s = {', '.join(f'{x:.6g}' for x in bad)}: {why}")
            return np.array([np.nan if v is None else float(np.asarray(v)[0]) for v in vals])
    return g


def _first(d):
    return {k: (v[0] if v is not None and np.ndim(v) >= 1 else v) for k, v in d.items()}


def _exact_pose_arb(model, pose):
    from ...singularity import PosePath
    path = PosePath(pose.translation, pose.rotation, pose.translation, pose.rotation, model.deg)
    return path.at_certified(0)


def _check66(model, R, t):
    """det(AJ) = det(A) det(J) on the built 6-6 platform (Rojas et al., eq. (6)).

    The 6-6 platform's own unnormalised Plücker matrix (from its joints) is compared
    with A times the octahedral one: ``identity_error`` = max|Jhat66 - A Jhat| /
    max|Jhat66| (a matrix identity, well conditioned also at singular poses).
    """
    from ...singularity import octahedral_joints, plucker_jacobian
    tr = model.platform66.transform
    A = np.array([[float(x) for x in row] for row in tr.A.tolist()])
    bj, qj = model.platform66.joints("fast")
    pj = np.einsum("...ij,nj->...ni", R, qj) + t[..., None, :]
    J66 = plucker_jacobian(np.broadcast_to(bj, pj.shape), pj, normalised=False)
    Jo = plucker_jacobian(*octahedral_joints(model.points(R, t)), normalised=False)
    err = np.max(np.abs(J66 - A @ Jo)) / np.max(np.abs(J66))
    return {"det_A": str(tr.det), "det_J66_hat": float(np.linalg.det(J66)[0]),
            "det_A_det_Jhat": float(tr.det) * float(np.linalg.det(Jo)[0]),
            "identity_error": float(err),
            "identity": "Jhat66 = A Jhat, so det(Jhat66) = det(A) det(Jhat)"}
