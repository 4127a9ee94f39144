"""Numeric kinematics on generated kernels, shared by every mechanism description.

:class:`KernelMethods` adds inverse kinematics, the Jacobian J = Jq^-1 Jx (Kühne et al.,
eqs. (1)-(2); for a prismatic leg its normalised Plücker line, Rojas et al. eq. (5)), the
mass matrices of eq. (7) and numeric forward kinematics to a frozen description that has
``L``, ``home``, ``leg_description()``, ``geometry_key()`` and
``cartesian_mass_matrix()``: :class:`~.rss.RSSMechanism` and :class:`LegMechanism`.
Everything runs on :func:`~.kernels.load_kernels` (the committed or cached generated
modules).  Nothing here imports sympy.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ConditioningWarning, InputError, warn as _warn
from .description import _poses
from .legs import LegsDescription

__all__ = ["KernelMethods", "LegMechanism", "ROUTES"]

#: the leg arrays of :meth:`KernelMethods.leg_arrays`, one per geometry, the
#: :data:`_ARRAYS_KEPT` most recently made (a sweep over geometries must not grow it
#: without bound)
_ARRAYS: dict = {}
_ARRAYS_KEPT = 512
#: the screen of :meth:`KernelMethods._row_limit`: a revolute leg whose reach margin is
#: below this times (l1 + l3)^3 / l1 (m^2) gets the fast tier's error estimate
_SCREEN = 1e-6


def _keep(key, value):
    """Keep ``value`` in :data:`_ARRAYS`, the oldest dropped beyond :data:`_ARRAYS_KEPT`."""
    while len(_ARRAYS) >= _ARRAYS_KEPT:
        _ARRAYS.pop(next(iter(_ARRAYS)))                    # the oldest
    _ARRAYS[key] = value


def _first_flagged(flag):
    """For a (N, L) bool array of flagged legs: how many poses have one, the first
    such pose, and its flagged legs as text (1-based: "2, 5")."""
    poses = np.flatnonzero(flag.any(axis=-1))
    first = int(poses[0])
    return len(poses), first, ", ".join(str(j + 1) for j in np.flatnonzero(flag[first]))


class KernelMethods:
    """The numeric methods of a mechanism on its kernels (module docstring)."""

    def points(self, poses, q=None):
        """Joint positions for drawings and checks (plain numpy), arrays (N, L, 3) (or
        (L, 3) for one pose): ``B`` crank pivot / base joint, ``C`` crank tip, ``D``
        distal joint centre (C = D = B for a prismatic leg), ``P`` platform joint; and
        ``q`` (N, L) (given: (L,) or (N, L), rad or m, one row for every pose or one per
        pose, else :class:`InputError` naming ``q``; default: the inverse kinematics of
        ``poses``).  One implementation for every mechanism, on its leg table
        (:meth:`leg_description`)."""
        from ..spatial import rotation_matrix
        X, single = _poses(poses, scale=self.length_scale)
        if q is None:
            q, _ = self.inverse_kinematics(X)
        elif not (isinstance(q, np.ndarray) and q.dtype == float
                  and q.shape == (len(X), self.L)):   # (L,) or (N, L) checked (QA)
            from ..argcheck import as_floats
            from .description import _rows
            what = "joint values (rad, or m for prismatic legs)"
            q, _ = _rows(as_floats(q, "q", what), "q", self.L, what)
            if len(q) not in (1, len(X)):
                raise InputError(f"expected {len(X)} rows of joint values (one per pose) or "
                                 f"one, got {len(q)}", field="q")
            q = np.broadcast_to(q, (len(X), self.L))
        d = self.leg_arrays()
        P = X[:, None, :3] + np.einsum("nij,lj->nli", rotation_matrix(X[:, 3:]), d["p"])
        qr = np.where(d["prismatic"][None], 0.0, q)
        C = d["B"][None] + d["l1"][None, :, None] * (np.cos(qr)[..., None] * d["u"][None]
                                                     + np.sin(qr)[..., None] * d["v"][None])
        D = C + d["offset"][None]
        B = np.broadcast_to(d["B"], C.shape)
        out = {"B": B, "C": C, "D": D, "P": P, "q": q}
        return {k: v[0] for k, v in out.items()} if single else out

    def leg_arrays(self) -> dict:
        """``leg_description().arrays()`` (:meth:`~.legs.LegsDescription.arrays`),
        computed once per geometry and kept, read-only, in one cache outside this frozen
        description (keyed as the kernels: kind and :meth:`geometry_key`)."""
        key = (type(self).kind, self.geometry_key())
        d = _ARRAYS.get(key)
        if d is None:
            d = self.leg_description().arrays()
            for v in d.values():
                v.setflags(write=False)
            _keep(key, d)
        return d

    def _row_limit(self):
        """(L,) and a float: the squared norm of the translational part of a row of J above which
        :meth:`_fast` runs the fast tier's error estimate on that leg (inf for a
        prismatic leg, whose row is a unit line), and the largest entry of J below which
        no row exceeds it (a first pass over the contiguous J).  That part is 1 / |Jq_ii|
        = l3 / (l1 h) for a revolute leg that closes (h = sqrt(reach margin)); the
        estimate flags a row (:data:`~.kinematics_tiers.J_REL_USEFUL`) at a margin of
        about 4e-9 (l1 + l3)^2 on the presets, the screen starts at a margin of
        1e-6 (l1 + l3)^3 / l1 (over 100x further out; tests/mechanisms/
        test_jacobian_resolution.py checks it is a superset)."""
        key = (type(self).kind, self.geometry_key(), "row_limit")
        lim = _ARRAYS.get(key)
        if lim is None:
            d = self.leg_arrays()
            l1 = np.where(d["prismatic"], 1.0, d["l1"])
            with np.errstate(divide="ignore", invalid="ignore"):
                margin = _SCREEN * (l1 + d["l3"]) ** 3 / l1
                lim = np.where(d["prismatic"] | ~(l1 > 0), np.inf,
                               d["l3"] ** 2 / (l1 ** 2 * margin))
            lim.setflags(write=False)
            # the largest entry of J below which no row can exceed its limit
            lim = (lim, float(np.sqrt(lim.min() / 3.0)))
            _keep(key, lim)
        return lim

    def _check_resolution(self, X, J, margin):
        """The fast tier's resolution check (:func:`~.kinematics_tiers.jacobian_tier`'s
        ``inaccurate``) on the rows of J (N, L, 6) at poses X that the cheap screen of
        :meth:`_row_limit` lets through: a :class:`~distkin.errors.ConditioningWarning`
        naming the poses and legs (1-based) whose row of J float64 does not resolve (a
        leg that closes next to its reach boundary), suggesting method='precise'.
        ``margin``: the reach margins (N, L) at X (:meth:`_check_closes`)."""
        lim, gate = self._row_limit()
        top = np.abs(J).max(initial=0.0)                   # NaN: the rows below decide
        if top <= gate or not J.size:           # no row's |J[:3]|^2 can exceed its lim
            return
        big = np.einsum("nli,nli->nl", J[..., :3], J[..., :3]) > lim
        if not big.any():
            return
        rows = np.flatnonzero(big.any(axis=-1))
        Xs, Js = X[rows], J[rows]
        margin = margin[rows]
        if not (big[rows] & (margin >= 0.0)).any():       # only legs that do not close
            return
        from .kinematics_tiers import J_REL_USEFUL, _fast_jacobian_error
        out = self._fast("jq_jx", Xs, warn=False)
        q = self.kernels("batched").ik(Xs)
        _, _, err, _ = _fast_jacobian_error(self, Xs, q, Js, out[..., 0], out[..., 1:])
        with np.errstate(divide="ignore", invalid="ignore"):
            rel = np.max(err, axis=-1) / np.max(np.abs(Js), axis=-1)
        flag = ~(rel <= J_REL_USEFUL) & (margin >= 0.0) & np.all(np.isfinite(Js), axis=-1)
        if not flag.any():
            return
        count, first, legs = _first_flagged(flag)
        _warn(f"jacobian: at {count} of {len(X)} pose(s) a row of J is not "
                      f"resolved in float64 (first: pose {int(rows[first])}, leg(s) {legs}: "
                      f"estimated error above {J_REL_USEFUL:g} of the row; the leg closes "
                      f"next to its reach boundary, a serial singularity); use "
                      f"method='precise' (jacobian_tier(..., 'fast') gives the estimates)",
                      ConditioningWarning)

    def kernels(self, flavour: str = "batched"):
        """The generated kernels (:mod:`.kernels`), ``flavour`` "batched" or "scalar".

        Loaded once per geometry into the one kernel cache of :mod:`.kernels` (keyed by
        :meth:`geometry_key`), outside this frozen description."""
        from .kernels import load_kernels
        return load_kernels(self, flavour)

    def inverse_kinematics(self, poses, method: str = "fast", dps: int | None = None,
                           bits: int | None = None):
        """Closed-form inverse kinematics, one crank angle per leg.

        Parameters
        ----------
        poses : array (N, 6) or (6,)
            m and rad (:mod:`distkin.spatial`).
        method : {"fast", "precise", "certified"}
            float64 kernels; mpmath at ``dps`` digits (default 30); python-flint balls
            from the pose's exact binary value (:mod:`.kinematics_tiers`, which also
            gives the error estimates and radii: :func:`~.kinematics_tiers.ik_tier`).
        dps, bits : int, optional
            The precise tier's digits (5..1233, default 30) and the certified tier's
            working precision (53..4096 bits, default 128); each refused with another
            tier (:class:`~distkin.errors.InputError`).

        Returns
        -------
        q : array (N, L), rad (m for a prismatic leg)
            Crank elevation (0 = horizontal), branch of :mod:`.presets`; finite even
            where a leg cannot close.  precise: an object array of mpmath ``mpf``;
            certified: of flint ``arb`` balls.
        valid : array (N, L) of bool
            The leg closes (the reach margin is >= 0) and, for a leg table with joint
            ranges, q lies in its range; a prismatic leg of zero length is not valid
            (its line, its row of J, is undefined; the certified tier refuses it too).

        Raises
        ------
        UncertifiedError
            certified: a leg at its reach boundary (the reach margin's ball contains 0,
            the branch point of the IK), on the ±π cut, or at an end of its joint range.
        InfeasibleError
            certified: a leg that certainly does not close.
        """
        _check_dps(dps, method, bits)
        if method != "fast":
            return self._tiered("ik", poses, method, dps, bits)
        X, single = _poses(poses, scale=self.length_scale)
        k = self.kernels("batched")
        q = k.ik(X)
        valid = self._valid(q, k.reach(X))
        return (q[0], valid[0]) if single else (q, valid)

    def _valid(self, q, margin):
        """(N, L) bool: the leg closes (``margin`` >= 0) and, for a leg table with
        revolute joint ranges, ``q`` (floats) lies in its range modulo 2π
        (:func:`.legs.in_revolute_range`)."""
        valid = margin >= 0.0
        lo, hi = self._joint_ranges()
        if lo is not None:                 # revolute ranges (a prismatic stroke is in reach)
            from .legs import in_revolute_range
            valid &= in_revolute_range(q, lo, hi)         # modulo 2π
        legs = getattr(self, "leg_table", None)
        if legs and any(leg.prismatic for leg in legs):
            pris = np.array([leg.prismatic for leg in legs])
            valid &= ~(pris & (q == 0.0))  # zero length: no line (q = |P - B| >= 0)
        return valid

    def _fast(self, name, X, warn=True):
        """The batched kernel ``name`` ("jacobian" or "jq_jx") at poses X (N, 6) without
        numpy's RuntimeWarnings: where a row is not finite (a revolute leg at a serial
        singularity, Jq_ii = 0; a prismatic leg of zero length, whose line is 0/0) a
        :class:`~distkin.errors.ConditioningWarning` naming the first pose and leg
        (``warn``)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            out = getattr(self.kernels("batched"), name)(X)
        if warn and not np.isfinite(out).all():
            bad = ~np.isfinite(out).all(axis=-1)                      # (N, L)
            i, j = np.argwhere(bad)[0]
            _warn(f"{name}: at {int(bad.any(axis=-1).sum())} of {len(X)} pose(s) a "
                          f"row is not finite (first: pose {i}, leg {j + 1}): a revolute leg "
                          f"at a serial singularity (Jq_ii = 0, its reach boundary) or a "
                          f"prismatic leg of zero length (its line is undefined; not valid "
                          f"in inverse_kinematics): J is unbounded or undefined there",
                          ConditioningWarning)
        # a prismatic leg always closes (its row is its line) and is never screened by
        # the resolution check: a table of them needs no reach margins
        if warn and not self.leg_arrays()["prismatic"].all():
            margin = self._check_closes(X, name)
            if name == "jacobian":
                self._check_resolution(X, out, margin)
        return out

    def _check_closes(self, X, name="jacobian"):
        """The reach margins (N, L) at poses X, and a
        :class:`~distkin.errors.ConditioningWarning` where a revolute leg does not close
        (margin < 0: its IK has no real angle, so its row of J, computed from the
        kernels' reflected angle, means nothing; QA).  One pose goes through the scalar
        kernel (~11 µs on the Octopod; the batched one costs ~120 µs of numpy calls at
        N = 1), more through the batched one (~0.3 µs per pose).  Not called for a table
        of prismatic legs only (:meth:`_fast`)."""
        if len(X) == 1:
            margin = np.array([self.kernels("scalar").reach(X[0])], dtype=float)
        else:
            with np.errstate(invalid="ignore"):
                margin = self.kernels("batched").reach(X)
        bad = (margin < 0.0) & ~self.leg_arrays()["prismatic"][None]
        if bad.any():
            count, first, legs = _first_flagged(bad)
            rows = "rows of J" if name == "jacobian" else "entries of Jq and rows of Jx"
            _warn(f"{name}: at {count} of {len(X)} pose(s) a revolute leg does not "
                  f"close (first: pose {first}, leg(s) {legs}: reach margin "
                  f"{float(margin[first][bad[first]].min()):.3g} m^2 < 0, the pose is not "
                  f"reachable): those {rows} are not defined and the values given for "
                  f"them mean nothing (inverse_kinematics' valid flags say which)",
                  ConditioningWarning)
        return margin

    def _tiered(self, what, poses, method, dps, bits=None):
        """The precise or certified tier of :meth:`inverse_kinematics` ("ik"),
        :meth:`jacobian` ("jacobian") or :meth:`jq_jx` ("jq_jx")
        (:mod:`.kinematics_tiers`); certified raises for an uncertified leg."""
        from .kinematics_tiers import ik_tier, jacobian_tier, raise_uncertified
        _, single = _poses(poses, scale=self.length_scale)
        if what == "ik":
            res = ik_tier(self, poses, method, dps, bits)
            raise_uncertified(res, "inverse kinematics")
            out = (res.values, res.valid)
        else:
            res = jacobian_tier(self, poses, method, dps, bits)
            raise_uncertified(res, "Jacobian")
            out = (res.values,) if what == "jacobian" else (res.jq_values, res.jx_values)
        out = tuple(v[0] for v in out) if single else out
        return out[0] if what == "jacobian" else out

    def _joint_ranges(self):
        """(lo, hi) arrays (L,) of the revolute legs' ranges (rad; ±inf where none), or
        (None, None) when no revolute leg has one."""
        from .joint_values import joint_ranges
        return joint_ranges(self, revolute=True) or (None, None)

    def reachable(self, poses):
        """(N,) bool: every leg of the pose closes (and is within its joint range; a
        prismatic leg has a non-zero length): ``inverse_kinematics(poses)[1]`` all True."""
        X, single = _poses(poses, scale=self.length_scale)
        if self._joint_ranges()[0] is not None or self.leg_arrays()["prismatic"].any():
            ok = np.all(self.inverse_kinematics(X)[1], axis=-1)
            return ok[0] if single else ok
        ok = np.all(self.kernels("batched").reach(X) >= 0.0, axis=-1)
        return ok[0] if single else ok

    def reach_margin(self, poses):
        """(N, L) reach margin (m^2): rho^2 - C^2 of the IK equation A cos q + B sin q = C
        for a revolute leg (>= 0: the leg closes; a declared crank range is not in it,
        :meth:`inverse_kinematics` flags that), and (q - qmin)(qmax - q) of its length q
        for a prismatic leg with a stroke (>= 0: within the stroke; :mod:`.legs`)."""
        X, single = _poses(poses, scale=self.length_scale)
        m = self.kernels("batched").reach(X)
        return m[0] if single else m

    def jacobian(self, poses, method: str = "fast", dps: int | None = None,
                 bits: int | None = None):
        """J = Jq^-1 Jx (eqs. (1)-(2)), shape (N, L, 6), with qdot = J @ (v, omega).

        v in m/s, omega in rad/s (base frame), qdot in rad/s.  Revolute legs that do not
        close give finite but meaningless rows, fast or precise: the fast tier says so
        with a :class:`~distkin.errors.ConditioningWarning` naming the poses and legs
        (their reach margins: on the Octopod ~10-20 µs at one pose, 270-290 µs in all,
        and +0.32 µs per pose batched, 0.65 -> 0.97 µs; nothing for a table of
        prismatic legs, which always close); :meth:`inverse_kinematics` flags them
        (``valid``), and
        :func:`~.kinematics_tiers.jacobian_tier` gives them ``valid`` False and an
        infinite error; certified raises InfeasibleError.  A leg
        at a serial singularity (Jq_ii = 0) or a prismatic leg of zero length gives a
        row of inf or NaN, with a :class:`~distkin.errors.ConditioningWarning` naming it;
        so does a leg that closes next to its reach boundary, where float64 does not
        resolve its row (the fast tier's check, ``jacobian_tier(...).inaccurate``; also
        in :meth:`pose_jacobian`, :meth:`joint_mass_matrix`, :meth:`acceleration_map`):
        use ``method="precise"`` there.  The check costs about 3 us per call at one pose.
        ``method``, ``dps`` and ``bits`` as :meth:`inverse_kinematics` (object arrays of
        mpf or arb; certified also refuses a leg whose Jq_ii ball contains 0, a serial
        singularity; radii and estimates: :func:`~.kinematics_tiers.jacobian_tier`).
        """
        _check_dps(dps, method, bits)
        if method != "fast":
            return self._tiered("jacobian", poses, method, dps, bits)
        X, single = _poses(poses, scale=self.length_scale)
        J = self._fast("jacobian", X)
        return J[0] if single else J

    def jq_jx(self, poses, method: str = "fast", dps: int | None = None,
              bits: int | None = None, *, warn: bool = True):
        """Jq (N, L) (the diagonal of eq. (1)'s Jq) and Jx (N, L, 6): Jq qdot = Jx xdot.

        Jq_ii = dPhi_i/dq_i and Jx = -dPhi/d(v, omega) for the closures Phi_i
        = (|P_i - D_i|^2 - l3^2) / (2 l3) (m).  ``method``, ``dps`` and ``bits`` as
        :meth:`jacobian`; so are the fast tier's warnings where a revolute leg does not
        close or a row is not finite (QA 23b 7: the rows of an unreachable pose were
        given without a word); ``warn=False`` leaves them to a caller that filters such
        poses itself (:meth:`reachable`).
        """
        _check_dps(dps, method, bits)
        if method != "fast":
            return self._tiered("jq_jx", poses, method, dps, bits)
        X, single = _poses(poses, scale=self.length_scale)
        out = self._fast("jq_jx", X, warn=warn)
        Jq, Jx = out[..., 0], out[..., 1:]
        return (Jq[0], Jx[0]) if single else (Jq, Jx)

    def pose_jacobian(self, poses):
        """dq/d(x, y, z, rx, ry, rz) = J @ blockdiag(I, E(r)), shape (N, L, 6)."""
        from ..spatial import omega_map
        X, single = _poses(poses, scale=self.length_scale)
        J = self._fast("jacobian", X)
        out = J.copy()
        out[..., 3:] = J[..., 3:] @ omega_map(X[:, 3:])
        return out[0] if single else out

    def joint_mass_matrix(self, poses):
        """Mq = J#ᵀ M̂ J# (eq. (7)), shape (N, L, L), kg m^2.

        The paper writes Mq = Jᵀ M̂ J with J the map q̇ -> ẋ; in our convention
        (q̇ = J ẋ) that map is J# = pinv(J).  Mq gives the kinetic energy
        ½ q̇ᵀ Mq q̇ = ½ ẋᵀ M̂ ẋ; it has rank 6, so for L = 8 it is singular.
        """
        X, single = _poses(poses, scale=self.length_scale)
        Jp = np.linalg.pinv(self._fast("jacobian", X))   # (N, 6, L)
        Mq = np.swapaxes(Jp, -1, -2) @ self.cartesian_mass_matrix() @ Jp
        return Mq[0] if single else Mq

    def acceleration_map(self, poses):
        """ẍ = A τ at q̇ = 0, f = 0 (eq. (7)); A = J# Mq⁺ = M̂⁻¹ Jᵀ, shape (N, 6, L).

        For L = 6, Mq⁺ = Mq⁻¹ and this is eq. (7) verbatim; for L = 8 eq. (7) needs the
        pseudo-inverse of the singular Mq, and J# Mq⁺ = M̂⁻¹ Jᵀ still holds.
        """
        X, single = _poses(poses, scale=self.length_scale)
        J = self._fast("jacobian", X)
        A = np.linalg.inv(self.cartesian_mass_matrix()) @ np.swapaxes(J, -1, -2)
        return A[0] if single else A

    def forward_kinematics(self, q, guess=None, *, octic: bool = True, method: str = "fast",
                           dps: int | None = None, bits: int | None = None, legs=None,
                           **options):
        """Numeric forward kinematics; see :func:`.forward.forward_kinematics`.

        A leg table with the octahedral topology (``octahedral()``, Rojas et al. Fig. 4)
        is solved by the exact octic first (:mod:`.octahedral_fk`, every assembly mode,
        proved or certified) and Gauss-Newton starts at the mode nearest ``guess``; the
        result's ``modes`` holds every mode.  ``octic=False`` skips this.

        ``method`` "precise" (mpmath at ``dps`` digits) or "certified" (Krawczyk's test
        on arb balls: a proved box of poses, or :class:`~distkin.errors.UncertifiedError`)
        takes one set of joint values and returns a
        :class:`~.forward_tiers.TieredFK` (:func:`.forward_tiers.forward_tier`, which
        starts from this method's fast answer; ``legs``: six legs of the square system
        when L > 6; ``bits``: the balls' precision); "fast" (default) the
        :class:`~.forward.FKResult` of before.  ``dps`` only with "precise" and ``bits``
        only with "certified" (:class:`~distkin.errors.InputError` otherwise)."""
        if dps is not None:
            _check_dps(dps, method)
        from .joint_values import check_joint_values
        check_joint_values(self, q)        # every route: a prismatic length > 0 (QA R 1)
        if method != "fast" or legs is not None or bits is not None:
            from ..errors import InputError
            from .forward_tiers import forward_tier
            from ..argcheck import as_floats        # text, ragged lists: InputError
            shape = as_floats(q, "q", f"{self.legs} joint values (rad, or m for prismatic "
                                      f"legs)").shape
            if len(shape) != 1:
                raise InputError(f"expected one set of {self.legs} joint values for method "
                                 f"{method!r}, got an array of shape {shape}", field="q")
            # the tier refuses or answers for itself: no warning of its start
            start = self.forward_kinematics(q, guess, octic=octic,
                                            **{**options, "warn": False})
            return forward_tier(self, q, method=method, dps=dps, bits=bits, legs=legs,
                                fast=start)
        from .forward import forward_kinematics
        if guess is not None:                 # (6,) or (N, 6), from 4x4 matrices too
            g, one = _poses(guess, "guess", self.length_scale)
            guess = g[0] if one else g
        topo = getattr(self, "octahedral", None)
        if octic and topo is not None and topo() is not None:
            import dataclasses

            from .octahedral_fk import octahedral_forward
            start, modes, tiers = octahedral_forward(self, q, guess)
            ok = np.all(np.isfinite(start), axis=-1)
            res = forward_kinematics(self, q, np.where(ok[..., None], start, self.home
                                                       if guess is None else guess), **options)
            n = sum(len(m) for m in modes)
            none = sum(len(m) == 0 for m in modes)
            return dataclasses.replace(res, modes=modes if np.ndim(q) > 1 else modes[0],
                                       message=f"exact octic (Rojas et al. eq. (3); tier "
                                       f"{', '.join(sorted(set(tiers))) or 'none'}): {n} assembly mode(s), "
                                       + (f"{none} leg set(s) with none (proved: no pose "
                                          f"exists; the Gauss-Newton pose there is no "
                                          f"answer), " if none else "")
                                       + f"the nearest to the guess polished: {res.message}")
        return forward_kinematics(self, q, guess, **options)


def _check_dps(dps, method, bits=None):
    """``method``, ``dps`` (only with "precise") and ``bits`` (only with "certified")
    at the entry points (:func:`.kinematics_tiers.check_dps`, ``check_bits``: an
    :class:`InputError` naming the field, QA T 9), before any tier runs."""
    if dps is None and bits is None and method == "fast":
        return
    from ..exact import check_method
    from .kinematics_tiers import check_bits, check_dps
    check_method(method)
    if dps is not None:
        check_dps(dps, method)
    if bits is not None:
        check_bits(bits, method)


#: where a leg mechanism's kernels come from: "generated" (the committed module or a
#: derivation, cached) or "numpy" (:class:`~.reference.NumericKernels`, no derivation)
ROUTES = ("generated", "numpy")


@dataclass(frozen=True)
class LegMechanism(KernelMethods, LegsDescription):
    """A :class:`~.legs.LegsDescription` with the numeric methods of
    :class:`KernelMethods` (same parameters; any L >= 6, any mix of leg types).

    ``route`` (not part of the description's identity): "generated" kernels (the
    default; derived once per leg table and cached) or "numpy" (the same formulas in plain
    numpy, :class:`~.reference.NumericKernels`: no sympy, no derivation, no arb flavour).

    >>> from distkin.mechanisms import preset
    >>> m = LegMechanism.from_description(preset("hunt").leg_description())
    >>> m.L, m.leg_table[0].type
    (6, 'RSS')
    """

    route: str = field(default="generated", compare=False)

    def __post_init__(self):
        super().__post_init__()
        if self.route not in ROUTES:
            raise InputError(f"expected a route in {ROUTES}, got {self.route!r}", field="route")

    @classmethod
    def from_description(cls, description, *, route: str = "generated") -> "LegMechanism":
        """The mechanism of a leg description (or of anything with
        ``leg_description()``, such as an RSS description)."""
        d = description.leg_description()
        return cls(d.name, d.leg_table, d.home_pose, d.mass, d.inertia, d.scale, route)
