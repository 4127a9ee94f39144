"""Leg descriptions: any parallel mechanism as a table of legs (model layer).

One frozen :class:`Leg` per actuator and a :class:`LegsDescription` (name, legs, home
pose, mass, inertia) describe every mechanism distkin models: the RSS/RUS/RRRS devices of
Kühne et al. (Fig. 2; a revolute actuator with crank, optional offset and distal link)
and the SPS/UPS platforms of Rojas et al. (a prismatic actuator between a base and a
platform joint).  The symbolic model (:mod:`.symbolic`), the code generator
(:mod:`distkin.codegen.rss`) and the numeric route (:mod:`.reference`) read this table;
:meth:`distkin.mechanisms.description.RSSDescription.leg_description` writes a preset
in it.  Nothing here imports sympy.

Revolute leg (``type`` "RSS", "RUS" or "RRRS"; all lengths m, angles rad)::

    D(q) = B + offset + l1 (cos q u + sin q v)     distal joint centre (U of RRRS/RUS)
    P    = x + R p                                 platform joint (S)
    |P - D(q)| = l3                                closure

``base`` B is the crank pivot, ``axis`` a the actuator axis (unit), ``crank0`` u and
``crank90`` v the unit crank directions at q = 0 and q = 90 deg (orthogonal to a and to
each other), ``crank`` l1, ``offset`` the constant vector crank tip -> distal joint
centre (along a: the RRRS offset; zero for RSS/RUS), ``distal`` l3, ``platform`` p the
platform joint in the end-effector frame, ``branch`` sigma = ±1 the IK solution
(:mod:`.symbolic`; ``None``: the one nearer q = 0 at the home pose).

The closure every tier solves (Kühne et al., eqs. (1)-(2); :mod:`.symbolic`) is the one
above expanded with |cos q u + sin q v| = 1: with w = P - B - offset,
``(|w|^2 - 2 l1 w.(cos q u + sin q v) + l1^2 - l3^2) / (2 l3) = 0`` (m).  For an
orthonormal (u, v) it is |P - D(q)| = l3; a table's u and v are accepted orthonormal
within 1e-9 (float vectors are so only to their rounding), and the mechanism then is
this closure, the one the certified tier's balls enclose exactly, not |P - D(q)| = l3
with the vectors as given: the two differ by l1^2 (c^2 (|u|^2 - 1) + s^2 (|v|^2 - 1)
+ 2 c s u.v) in the squared closure (c, s = cos q, sin q), at the 1e-9 tolerance about
4e-10 rad in q on the Hunt preset (tests/mechanisms/test_closure_definition.py).
``points()`` draws D(q) with the vectors as given.

Prismatic leg (``type`` "SPS" or "UPS"): q = |P - B| (m), ``base`` B the base joint,
``platform`` p; its Jacobian row is the normalised Plücker line of the leg, Rojas et
al. eq. (5).

Limits: ``range`` (qmin, qmax) of the joint (rad, or m for a prismatic stroke; for a
prismatic leg the reach margin is (q - qmin)(qmax - q)); ``limit`` (min, max) of the
actuator effort (N m or N).  A crank angle is an angle: it is in a revolute ``range``
when some q + 2πk lies in [qmin, qmax] (:func:`in_revolute_range`; [270, 450] deg is the
arc of [-90, 90] deg), and a range of width 2π or more (up to the rounding of a
conversion from degrees, :func:`full_turn`) is the full turn, every angle inside.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace

import numpy as np

from ..argcheck import LENGTH_RANGE, length_in_range, no_booleans
from ..errors import DistkinError, GeometryWarning, InputError, warn as _warn
from ..numfmt import apart
from .leg_architecture import check_concurrent, check_distinct, check_line_span

__all__ = ["Leg", "LegsDescription", "REVOLUTE_TYPES", "PRISMATIC_TYPES", "LEG_TYPES",
           "LEG_FIELDS", "full_turn", "in_revolute_range", "ranged_legs", "GeometryWarning"]


REVOLUTE_TYPES = ("RSS", "RUS", "RRRS")
PRISMATIC_TYPES = ("SPS", "UPS")
LEG_TYPES = REVOLUTE_TYPES + PRISMATIC_TYPES

#: the fields of a leg, in table order (the CSV columns of :mod:`distkin.app.legs_scene`)
LEG_FIELDS = ("type", "base", "platform", "axis", "crank0", "crank90", "crank", "offset",
              "distal", "branch", "range", "limit")

_TOL = 1e-9          # unit length and orthogonality of the revolute frame vectors


def _vec(v, fld, *, unit=False):
    no_booleans(v, fld)
    try:
        arr = tuple(float(x) + 0.0 for x in v)       # + 0.0: no -0.0 in keys
    except (TypeError, ValueError):
        raise InputError(f"expected 3 numbers, got {v!r}", field=fld) from None
    if len(arr) != 3 or not all(math.isfinite(x) for x in arr):
        raise InputError(f"expected 3 finite numbers, got {v!r}", field=fld)
    if not unit and max(abs(x) for x in arr) > LENGTH_RANGE[1]:
        raise InputError(f"expected coordinates within ±{LENGTH_RANGE[1]:g} m (the "
                         f"kernels' powers of lengths leave float64's range beyond), got "
                         f"{v!r}", field=fld)
    if unit and abs(math.sqrt(sum(x * x for x in arr)) - 1.0) > _TOL:
        raise InputError(f"expected a unit vector, got {arr!r} (norm "
                         f"{math.sqrt(sum(x * x for x in arr)):.12g})", field=fld)
    return arr


def _pos(v, fld, unit):
    no_booleans(v, fld)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
        raise InputError(f"expected a positive finite number, got {v!r} {unit}", field=fld)
    return float(v)


def _pair(v, fld, unit, *, symmetric=False):
    if v is None:
        return None
    no_booleans(v, fld)
    if symmetric and isinstance(v, (int, float)) and not isinstance(v, bool):
        v = (-abs(float(v)), abs(float(v)))
    try:
        lo, hi = (float(x) for x in v)
    except (TypeError, ValueError):
        raise InputError(f"expected [min, max], got {v!r}", field=fld) from None
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise InputError(f"expected finite min < max, got ({lo!r}, {hi!r}) {unit}", field=fld,
                         hint=("a revolute range is an arc from min up to max, modulo one "
                               "turn: the arc from 90 deg through 180 deg to -90 deg is "
                               "written [90, 270]") if unit == "rad" and lo > hi else None)
    return (lo, hi)


_TWO_PI = 2 * math.pi


def full_turn(lo, hi):
    """A revolute range [lo, hi] (rad, floats or arrays; ±inf allowed) that is the full
    turn: width at least 2π, up to the rounding of its ends (8 ulps of the larger of
    |lo|, |hi| and 2π: [0, 360] deg converted to rad is one whatever the rounding of the
    conversion, [0, 359.9999999997] deg is not, QA Q 1).  The same decision in every
    tier: it is a property of the range as written, not a numerical question."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    with np.errstate(invalid="ignore"):
        scale = np.maximum(np.maximum(np.abs(lo), np.abs(hi)), _TWO_PI)
        return hi - lo >= _TWO_PI - 8 * np.finfo(float).eps * scale


def ranged_legs(legs) -> list[int]:
    """The legs (0-based) of a leg table (:class:`Leg` sequence) that are revolute with a
    ``range`` that is not the full turn (:func:`full_turn`): the rows of the arb kernel
    ``ranges`` (:mod:`.symbolic`), which the certified workspace encloses."""
    return [i for i, leg in enumerate(legs) if not leg.prismatic and leg.range is not None
            and not bool(full_turn(*leg.range))]


def in_revolute_range(q, lo, hi):
    """Bool array: the crank angles ``q`` (rad, any shape; e.g. atan2's (-π, π]) lie in
    the ranges [``lo``, ``hi``] (broadcast; ±inf where none) modulo 2π: some q + 2πk is
    in [lo, hi] (module docstring; k = ceil((lo - q) / 2π), the smallest shift reaching
    lo).  NaN is never in range."""
    q = np.asarray(q, dtype=float)
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    with np.errstate(invalid="ignore"):
        k = np.ceil((lo - q) / _TWO_PI)
        inside = q + _TWO_PI * k <= hi
        return np.where(full_turn(lo, hi), np.isfinite(q), inside)


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


@dataclass(frozen=True)
class Leg:
    """One leg: its actuator, joints and limits (module docstring; SI units).

    Parameters
    ----------
    type : {"RSS", "RUS", "RRRS", "SPS", "UPS"}
    base, platform : 3 floats
        Crank pivot (revolute) or base joint (prismatic), base frame (m); platform joint
        in the end-effector frame (m).
    axis, crank0, crank90 : 3 floats (revolute only)
        Unit actuator axis; unit crank directions at q = 0 and q = 90 deg.
    crank, distal : float (revolute only)
        l1 and l3 (m).
    offset : 3 floats
        Crank tip -> distal joint centre (m), parallel to ``axis`` (revolute only).
    branch : +1, -1 or None
        IK solution of a revolute leg (None: chosen at the home pose).
    range : (min, max) or None
        Joint range (rad; m for prismatic).
    limit : (min, max), a number (±) or None
        Actuator effort (N m; N for prismatic).
    """

    type: str
    base: tuple
    platform: tuple
    axis: tuple | None = None
    crank0: tuple | None = None
    crank90: tuple | None = None
    crank: float | None = None
    offset: tuple = (0.0, 0.0, 0.0)
    distal: float | None = None
    branch: int | None = None
    range: tuple | None = None
    limit: tuple | None = None

    def __post_init__(self):
        if self.type not in LEG_TYPES:
            raise InputError(f"expected a leg type in {LEG_TYPES}, got {self.type!r}",
                             field="type")
        s = lambda k, v: object.__setattr__(self, k, v)  # noqa: E731
        s("base", _vec(self.base, "base"))
        s("platform", _vec(self.platform, "platform"))
        s("range", _pair(self.range, "range", "m" if self.prismatic else "rad"))
        s("limit", _pair(self.limit, "limit", "N" if self.prismatic else "N·m",
                         symmetric=True))
        if self.prismatic:
            for k in ("axis", "crank0", "crank90", "crank", "distal", "branch"):
                if getattr(self, k) is not None:
                    raise InputError(f"expected no {k} on a prismatic {self.type} leg, got "
                                     f"{getattr(self, k)!r}", field=k)
            if any(self.offset):
                raise InputError(f"expected no offset on a prismatic {self.type} leg, got "
                                 f"{self.offset!r}", field="offset")
            s("offset", (0.0, 0.0, 0.0))
            if self.range is not None and self.range[0] < 0:
                raise InputError(f"expected a stroke range of lengths >= 0 m, got "
                                 f"{self.range!r}", field="range")
            return
        for k in ("axis", "crank0", "crank90", "crank", "distal"):
            if getattr(self, k) is None:
                raise InputError(f"expected {k} on a revolute {self.type} leg, got nothing",
                                 field=k)
        a = _vec(self.axis, "axis", unit=True)
        u = _vec(self.crank0, "crank0", unit=True)
        v = _vec(self.crank90, "crank90", unit=True)
        for name, x, y in (("crank0", u, a), ("crank90", v, a), ("crank90", v, u)):
            if abs(_dot(x, y)) > _TOL:
                other = "axis" if y is a else "crank0"
                raise InputError(f"expected {name} orthogonal to {other}, got a dot product "
                                 f"of {_dot(x, y):.3g}", field=name)
        o = _vec(self.offset, "offset")
        along = _dot(o, a)
        if max(abs(oi - along * ai) for oi, ai in zip(o, a)) > _TOL * max(1.0, abs(along)):
            raise InputError(f"expected an offset along the axis {a!r}, got {o!r}",
                             field="offset")
        if self.type != "RRRS" and any(o):
            raise InputError(f"expected no offset on an {self.type} leg (an RRRS leg has one),"
                             f" got {o!r}", field="offset")
        s("axis", a), s("crank0", u), s("crank90", v), s("offset", o)
        s("crank", length_in_range(_pos(self.crank, "crank", "m"), "crank"))
        s("distal", length_in_range(_pos(self.distal, "distal", "m"), "distal"))
        no_booleans(self.branch, "branch")
        if self.branch is not None and self.branch not in (1, -1):
            raise InputError(f"expected branch +1 or -1, got {self.branch!r}", field="branch")
        if self.branch is not None:
            s("branch", int(self.branch))

    @property
    def prismatic(self) -> bool:
        """The actuator is prismatic (SPS, UPS)."""
        return self.type in PRISMATIC_TYPES

    def key(self) -> tuple:
        """The kinematic data (everything but ``limit``) as a tuple of plain values: the
        identity of the generated kernels."""
        return tuple((f, getattr(self, f)) for f in LEG_FIELDS if f != "limit")

    def as_dict(self) -> dict:
        """The fields with values (``None`` left out)."""
        return {f: getattr(self, f) for f in LEG_FIELDS if getattr(self, f) is not None}


@dataclass(frozen=True)
class LegsDescription:
    """A parallel mechanism as a table of L >= 6 legs (module docstring).

    Parameters
    ----------
    name : str
    leg_table : sequence of :class:`Leg` or of dicts of its fields
    home : 6 floats
        The home pose (x, y, z) m, (rx, ry, rz) rad (workspace centre, IK branches,
        FK start).
    mass, inertia : float
        End-effector mass (kg) and principal inertia (kg m^2) of M̂.
    scale : float or None
        The length (m) that turns rotations into displacements in forward kinematics'
        steps; None: the mean distance of the platform joints from the end-effector
        centre (an RSS description gives its lp).
    """

    name: str
    leg_table: tuple
    home_pose: tuple = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    mass: float = 1.0
    inertia: float = 1e-3
    scale: float | None = None
    kind = "legs"

    def __post_init__(self):
        if isinstance(self.leg_table, (str, bytes, Mapping)) or not hasattr(self.leg_table,
                                                                            "__iter__"):
            got = repr(self.leg_table)
            raise InputError(f"expected a sequence of legs (Leg or tables of its fields), got "
                             f"{type(self.leg_table).__name__} "
                             f"{got if len(got) <= 80 else got[:77] + '...'}", field="leg")
        legs = []
        for i, leg in enumerate(self.leg_table):
            if not isinstance(leg, (Leg, Mapping)):
                raise InputError(f"expected a Leg or a table of its fields, got "
                                 f"{type(leg).__name__} {leg!r}", field=f"leg[{i}]")
            missing = [k for k in ("type", "base", "platform")
                       if not isinstance(leg, Leg) and k not in leg]
            if missing:
                raise InputError(f"expected {missing[0]} on every leg, got nothing (fields "
                                 f"given: {sorted(leg)})", field=f"leg[{i}].{missing[0]}")
            try:
                legs.append(leg if isinstance(leg, Leg) else Leg(**dict(leg)))
            except DistkinError as exc:
                raise exc.with_field(f"leg[{i}]") from None
            except TypeError as exc:
                raise InputError(f"expected fields among {LEG_FIELDS}, got {sorted(leg)}: {exc}",
                                 field=f"leg[{i}]") from None
        if len(legs) < 6:
            raise InputError(f"expected at least 6 legs, got {len(legs)}", field="leg")
        no_booleans(self.home_pose, "home")
        try:
            home = tuple(float(x) for x in self.home_pose)
        except (TypeError, ValueError):
            home = ()
        if len(home) != 6 or not all(math.isfinite(x) for x in home):
            raise InputError(f"expected 6 finite numbers (x, y, z, rx, ry, rz), got "
                             f"{self.home_pose!r}", field="home")
        object.__setattr__(self, "home_pose", home)
        object.__setattr__(self, "mass", _pos(self.mass, "mass", "kg"))
        object.__setattr__(self, "inertia", _pos(self.inertia, "inertia", "kg m^2"))
        if self.scale is not None:
            object.__setattr__(self, "scale", _pos(self.scale, "scale", "m"))
        check_concurrent(legs)
        self._check_home(legs)
        legs = [self._resolve_branch(i, leg) for i, leg in enumerate(legs)]
        check_distinct(legs)
        object.__setattr__(self, "leg_table", tuple(legs))
        check_line_span(self)              # lines that cannot span 6 DOF: a warning

    def _check_home(self, legs):
        """Refuse a home pose at which a revolute leg whose ``branch`` is to be chosen
        there does not close (its reach margin rho^2 - C^2 < 0 beyond rounding): its IK
        branch would be chosen from a meaningless angle.  :class:`InputError` naming
        ``home``, the legs (1-based) and their margins (m^2).  A leg with its own
        ``branch`` that does not close at home, and a prismatic leg whose length there
        is outside its range, give a :class:`~.description.GeometryWarning` instead
        (home is then only the FK's default start; mostly it is a unit slip, QA)."""
        from ..spatial import rotation_matrix
        X = np.array(self.home_pose)
        R = rotation_matrix(X[3:])
        bad = []
        for i, leg in enumerate(legs):
            if not leg.prismatic and leg.branch is None:
                P = X[:3] + R @ np.array(leg.platform)
                m = _revolute_margin(leg, P)
                if m < -_margin_rounding(leg, P):
                    bad.append((i + 1, m))
        if bad:
            listed = ", ".join(f"leg {i} margin {m:.3g} m^2" for i, m in bad[:6])
            raise InputError(f"expected a home pose at which every revolute leg without its "
                             f"own branch closes (reach margin rho^2 - C^2 >= 0: its IK "
                             f"branch is chosen there), got {len(bad)} leg(s) that do not: "
                             f"{listed}{' ...' if len(bad) > 6 else ''}", field="home",
                             hint="home is the workspace centre, where the IK branches are "
                                  "chosen and forward kinematics starts: a reachable pose "
                                  "(or give each leg its branch, +1 or -1)")
        far = []
        for i, leg in enumerate(legs):
            P = X[:3] + R @ np.array(leg.platform)
            if leg.prismatic and leg.range is not None:
                n = float(np.linalg.norm(P - np.array(leg.base)))
                if not leg.range[0] <= n <= leg.range[1]:
                    t = apart(n, *leg.range, digits=4)     # visibly outside
                    far.append(f"leg {i + 1} length {t[0]} m outside its range "
                               f"[{t[1]}, {t[2]}] m")
            elif not leg.prismatic and leg.branch is not None:
                m = _revolute_margin(leg, P)
                if m < -_margin_rounding(leg, P):
                    far.append(f"leg {i + 1} margin {m:.3g} m^2")
        if far:
            shown = ", ".join(f"{v:.6g}" for v in self.home_pose)
            _warn(f"home: expected a home pose that every leg reaches (the workspace "
                          f"centre, forward kinematics' default start), got ({shown}) "
                          f"(m, rad), which {len(far)} of {len(legs)} legs do not reach: "
                          f"{', '.join(far[:4])}{' ...' if len(far) > 4 else ''}; lengths "
                          f"in another unit? (a leg table in m read as mm is 1000x too "
                          f"small)", GeometryWarning)

    def _resolve_branch(self, i, leg):
        if leg.prismatic or leg.branch is not None:
            return leg
        from ..spatial import rotation_matrix
        X = np.array(self.home_pose)
        P = X[:3] + rotation_matrix(X[3:]) @ np.array(leg.platform)
        qs = [_revolute_q(leg, P, b) for b in (1, -1)]
        return replace(leg, branch=1 if abs(qs[0]) <= abs(qs[1]) else -1)

    # ------------------------------------------------------------------ interface
    @property
    def L(self) -> int:
        """Number of legs and actuators."""
        return len(self.leg_table)

    @property
    def legs(self) -> int:
        """Number of legs (the name :class:`RSSDescription` uses)."""
        return len(self.leg_table)

    @property
    def home(self) -> np.ndarray:
        """The home pose (6,)."""
        return np.array(self.home_pose)

    @property
    def z0(self) -> float:
        """Height of the home pose (m)."""
        return self.home_pose[2]

    @property
    def length_scale(self) -> float:
        """``scale``, else the mean distance of the platform joints from the end-effector
        centre (m): the length that turns rotations into displacements (FK steps)."""
        if self.scale is not None:
            return self.scale
        if "_ls" not in self.__dict__:                  # once per description, as key()
            self.__dict__["_ls"] = float(np.mean(np.linalg.norm(self.arrays()["p"], axis=1)))
        return self.__dict__["_ls"]

    @property
    def l1(self) -> float:
        """The crank length (m) the analyses of :mod:`distkin.indices.study` normalise
        |Jq_ii| by (``transmission_min``, the sine of the worst transmission angle of an
        RSS device): the revolute legs' common crank length, their largest if they
        differ (then an approximation), 1.0 for an all-prismatic table (|Jq_ii| = 1 there:
        full transmission).  A per-leg normalisation belongs in the analysis."""
        cranks = [leg.crank for leg in self.leg_table if not leg.prismatic]
        return max(cranks) if cranks else 1.0

    def leg_description(self) -> "LegsDescription":
        """Itself (the common interface with :class:`RSSDescription`)."""
        return self

    def key(self) -> tuple:
        """The kinematic identity: the legs' :meth:`Leg.key` (the kernel cache key), once
        per (frozen) description: ~37 µs, ten times in a single FK (review 2026-11-29)."""
        if "_key" not in self.__dict__:
            self.__dict__["_key"] = tuple(leg.key() for leg in self.leg_table)
        return self.__dict__["_key"]

    def geometry_key(self) -> tuple:
        """Same as :meth:`key` (the name :class:`RSSDescription` uses)."""
        return self.key()

    def cartesian_mass_matrix(self) -> np.ndarray:
        """M̂ = diag(m, m, m, I, I, I), (6, 6) in kg and kg m^2."""
        return np.diag([self.mass] * 3 + [self.inertia] * 3)

    def limits(self) -> tuple[np.ndarray, np.ndarray] | None:
        """Actuator effort limits (min (L,), max (L,)) in N m / N, or None if a leg has none."""
        if any(leg.limit is None for leg in self.leg_table):
            return None
        arr = np.array([leg.limit for leg in self.leg_table])
        return arr[:, 0], arr[:, 1]

    def octahedral(self):
        """The octahedral topology of Rojas et al. (Fig. 4), if this table has it: six
        prismatic legs on three base points and three platform points, each point on two
        legs, the legs forming one cycle.  Returns None, or a dict ``base`` (3, 3) P1 P2
        P3, ``platform`` (3, 3) P4 P5 P6 (end-effector frame) and ``order`` (6,): our
        leg index of legs 1..6 = P1P4, P2P4, P2P5, P3P5, P3P6, P1P6 (docs/design.md §3)."""
        legs = self.leg_table
        if len(legs) != 6 or not all(leg.prismatic for leg in legs):
            return None
        bases = sorted({leg.base for leg in legs})
        plats = sorted({leg.platform for leg in legs})
        if len(bases) != 3 or len(plats) != 3:
            return None
        edges = {(bases.index(leg.base), plats.index(leg.platform)): i
                 for i, leg in enumerate(legs)}
        if len(edges) != 6 or any(sum(e[k] == v for e in edges) != 2
                                  for k in (0, 1) for v in range(3)):
            return None
        b, p = 0, min(pp for bb, pp in edges if bb == 0)       # P1 and P4
        B, P, order = [b], [p], [edges[(b, p)]]
        for step in range(5):                                  # walk the hexagon
            if step % 2 == 0:
                b = next(bb for bb, pp in edges if pp == p and bb != b)
                B.append(b) if step < 4 else None
            else:
                p = next(pp for bb, pp in edges if bb == b and pp != p)
                P.append(p)
            order.append(edges[(b, p)])
        if len(set(order)) != 6 or len(set(B)) != 3 or len(set(P)) != 3:
            return None
        return {"base": np.array([bases[i] for i in B]), "platform": np.array([plats[i] for i in P]),
                "order": np.array(order)}

    def arrays(self) -> dict:
        """The table as arrays: ``B, p, a, u, v, offset`` (L, 3) (zeros where a leg has
        no such vector), ``l1, l3, branch`` (L,) and ``prismatic`` (L,) bool."""
        z3 = (0.0, 0.0, 0.0)
        t = self.leg_table
        return {
            "B": np.array([leg.base for leg in t]), "p": np.array([leg.platform for leg in t]),
            "a": np.array([leg.axis or z3 for leg in t]),
            "u": np.array([leg.crank0 or z3 for leg in t]),
            "v": np.array([leg.crank90 or z3 for leg in t]),
            "offset": np.array([leg.offset for leg in t]),
            "l1": np.array([leg.crank or 0.0 for leg in t]),
            "l3": np.array([leg.distal or 0.0 for leg in t]),
            "branch": np.array([leg.branch or 1 for leg in t], dtype=float),
            "prismatic": np.array([leg.prismatic for leg in t]),
        }

    def parameters(self) -> dict:
        """Name, legs (as dicts), home, mass and inertia (SI)."""
        return {"name": self.name, "legs": [leg.as_dict() for leg in self.leg_table],
                "home": list(self.home_pose), "mass": self.mass, "inertia": self.inertia,
                "scale": self.scale}

    def __getstate__(self):
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def __setstate__(self, state):
        for k, v in state.items():
            object.__setattr__(self, k, v)


def _revolute_margin(leg, P):
    """Reach margin rho^2 - C^2 (m^2) of a revolute leg reaching joint position P
    (numpy, :mod:`.symbolic`'s formula)."""
    w = np.asarray(P) - np.array(leg.base) - np.array(leg.offset)
    A, Bz = float(w @ np.array(leg.crank0)), float(w @ np.array(leg.crank90))
    C = (float(w @ w) + leg.crank ** 2 - leg.distal ** 2) / (2 * leg.crank)
    return A * A + Bz * Bz - C * C


def _margin_rounding(leg, P):
    """A bound on the float rounding of :func:`_revolute_margin` (m^2): a home exactly
    at a leg's reach boundary (margin 0 in exact arithmetic) is not refused."""
    w = np.asarray(P) - np.array(leg.base) - np.array(leg.offset)
    s = float(w @ w) + leg.crank ** 2 + leg.distal ** 2
    return 64 * np.finfo(float).eps * (s + s * s / (2 * leg.crank) ** 2)


def _revolute_q(leg, P, branch):
    """Crank angle of a revolute leg reaching joint position P (numpy, :mod:`.symbolic`'s
    formula): A cos q + Bz sin q = C."""
    w = np.asarray(P) - np.array(leg.base) - np.array(leg.offset)
    A, Bz = float(w @ np.array(leg.crank0)), float(w @ np.array(leg.crank90))
    C = (float(w @ w) + leg.crank ** 2 - leg.distal ** 2) / (2 * leg.crank)
    h = math.sqrt(abs(A * A + Bz * Bz - C * C))
    return math.atan2(Bz * C - branch * A * h, A * C + branch * Bz * h)

