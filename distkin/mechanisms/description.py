"""The RSS/RRRS parallel mechanism's description: parameters, leg geometry, rules.

Kühne et al., *Design and Evaluation of a Haptic Interface With Octopod Kinematics*,
Sec. II-C (eqs. (1)-(3), (7)), Fig. 2.  The parametrisation (what l0, l1, l2, l3, lp,
ld, beta, gamma, z0 mean) is stated in :mod:`.presets`; poses in :mod:`distkin.spatial`.

This is the model layer (docs/design.md, "Import direction"): the code generator derives
kernels from an :class:`RSSDescription`, and :class:`distkin.mechanisms.rss.RSSMechanism`
(the numeric analysis layer) adds the methods that run on those kernels.  Nothing here
imports sympy or loads a kernel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from ..argcheck import as_floats, float_array, length_in_range, no_booleans
from ..errors import InputError, warn as _warn
from .legs import GeometryWarning

__all__ = ["RSSDescription", "read_only", "GEOMETRY_FIELDS", "LAYOUTS", "LEG_LENGTH",
           "SI_UNITS", "MAX_ROTATION", "MAX_REACH", "check_pose_range", "GeometryWarning"]

#: the parameters that define the kinematics (mass and inertia do not)
GEOMETRY_FIELDS = ("legs", "l0", "l1", "l2", "l3", "lp", "ld", "z0", "beta", "gamma", "layout")

#: readings of Fig. 2 (:mod:`.presets`): "tangential" (the default: actuator axes of a
#: pair on one tangential line, cranks radially outwards), "radial" (axes radial,
#: cranks tangential away from the pair; the reading used before issue 15) and
#: "tangential_in" (tangential axes, cranks radially inwards; documented, not buildable)
LAYOUTS = ("tangential", "radial", "tangential_in")

#: the SI unit of each numeric parameter (what error messages print)
SI_UNITS = {**dict.fromkeys(("l0", "l1", "l2", "l3", "lp", "ld", "z0"), "m"),
            "beta": "rad", "gamma": "rad", "mass": "kg", "inertia": "kg m^2"}

#: l2 + l3 (m) of every leg in the "tangential" reading: the centre of the interval of
#: leg lengths that close every leg of every preset over its study box
#: (:func:`distkin.mechanisms.presets.leg_length_rule`; Sec. III-B-2 keeps l2 + l3
#: constant)
LEG_LENGTH = 0.3497


def _rows(arr, field, width, what, also=""):
    """The float array ``arr`` as rows (N, ``width``) (a 1-d ``arr`` as one row), and
    whether it was one row; :class:`InputError` naming ``field`` for another shape (the
    message says ``(N, width)``) or a NaN or inf."""
    single = arr.ndim == 1
    rows = arr.reshape(1, -1) if single else arr
    if rows.ndim != 2 or rows.shape[1] != width:
        raise InputError(f"expected shape ({width},) or (N, {width}) ({what}){also}, got "
                         f"shape {arr.shape}", field=field)
    return float_array(rows, field, (None, width)), single


#: the largest rotation component of a pose (rad): float64 spaces numbers above it
#: 0.125 rad or more apart, so an angle there has no digits left modulo 2π (QA R 8)
MAX_ROTATION = 1e15
#: the largest translation component of a pose, in units of the mechanism's length
#: scale: a pose farther away is no pose of the device, and squares of coordinates near
#: 1e154 m overflow the kernels' float64 into NaN (QA R 3)
MAX_REACH = 1e9


def _poses(poses, field="poses", scale=None):
    """Poses (N, 6) from (6,), (N, 6), a 4x4 homogeneous matrix or (N, 4, 4) matrices
    (:func:`distkin.spatial.pose_from`), and whether one pose was given.  A boolean
    anywhere is refused (:func:`~distkin.argcheck.no_booleans`; free for a numeric
    array), and so is a rotation component beyond :data:`MAX_ROTATION` rad and, given
    the mechanism's length ``scale`` (m), a translation component beyond
    :data:`MAX_REACH` times it (:func:`check_pose_range`)."""
    what = "poses (x, y, z, rx, ry, rz) in m and rad or 4x4 matrices"
    arr = as_floats(poses, field, what)
    if arr.ndim >= 2 and arr.shape[-2:] == (4, 4):
        from ..spatial import matrix_to_pose
        arr = matrix_to_pose(arr)
    X, single = _rows(arr, field, 6, "x, y, z, rx, ry, rz in m and rad",
                      ", or 4x4 matrices (4, 4) or (N, 4, 4)")
    check_pose_range(X, field, scale, single)
    return X, single


def check_pose_range(X, field="poses", scale=None, single=False):
    """Refuse poses (N, 6) (m, rad) whose numbers mean nothing in float64: a rotation
    component above :data:`MAX_ROTATION` rad, and given ``scale`` (m, the mechanism's
    length scale) a translation component above :data:`MAX_REACH` x ``scale``.  Two
    flat reductions (the largest and the smallest number) unless one is beyond a bound.

    Raises
    ------
    InputError
        naming ``field[i][k]`` (``field[k]`` for one pose), the bound and the value.
    """
    X = np.asarray(X, dtype=float)
    if not X.size:
        return
    reach = np.inf if scale is None else MAX_REACH * float(scale)
    if max(-X.min(), X.max()) <= min(reach, MAX_ROTATION):   # flat: ~1 ns per number
        return
    rot = np.abs(X[:, 3:]) > MAX_ROTATION
    far = np.abs(X[:, :3]) > reach
    bad = np.concatenate([far, rot], axis=1)
    if not bad.any():                      # a rotation above the reach bound: fine
        return
    i, k = (int(v) for v in np.argwhere(bad)[0])
    where = field + (f"[{k}]" if single else f"[{i}][{k}]")
    if k >= 3:
        raise InputError(
            f"expected a rotation component of magnitude at most {MAX_ROTATION:g} rad (float64 "
            f"keeps no digit of a larger angle modulo 2π), got {X[i, k]:.6g} rad",
            field=where, hint="a unit slip? rotations are rx, ry, rz in rad (a scene's in its "
                              "[units] angle)")
    raise InputError(
        f"expected a translation component of magnitude at most {MAX_REACH:g} x the "
        f"mechanism's length scale ({reach:.6g} m; no pose of the device lies farther), "
        f"got {X[i, k]:.6g} m", field=where,
        hint="a unit slip? express the pose in m (a scene's in its [units] length)")


@dataclass(frozen=True)
class RSSDescription:
    """A parallel mechanism with L rotary-actuated RRRS legs in mirror-symmetric pairs:
    its parameters and leg geometry, without numeric methods (those are
    :class:`distkin.mechanisms.rss.RSSMechanism`, a subclass).

    Parameters (SI units)
    ---------------------
    name : str
    legs : int
        L, 6 or 8.
    l0, l1, l2, lp, ld : float
        Base radius, crank, RRRS offset, end-effector radius, pair spacing (m).
    z0 : float
        Height of the workspace centre above the base plane (m).
    beta, gamma : float
        Base and end-effector pair angles (rad).
    l3 : float or None
        Distal link (m); ``None`` applies the reading's rule (:mod:`.presets`):
        ``LEG_LENGTH - l2`` for "tangential", the horizontal-crank rule for "radial".
    mass, inertia : float
        End-effector mass (kg) and principal inertia (kg m^2) of M̂ (Sec. III-B.3).
    layout : {"tangential", "radial", "tangential_in"}
        The reading of Fig. 2 (:data:`LAYOUTS`, :mod:`.presets`).
    """

    name: str = "custom"
    legs: int = 6
    l0: float = 0.152
    l1: float = 0.157
    l2: float = 0.0
    l3: float | None = None
    lp: float = 0.055
    ld: float = 0.020
    z0: float = 0.30
    beta: float = 0.0
    gamma: float = 0.0
    mass: float = 0.17
    inertia: float = 3e-4
    layout: str = "tangential"

    #: the scene's mechanism kind
    kind = "rss"

    def __post_init__(self):
        if not isinstance(self.legs, int) or isinstance(self.legs, bool) or self.legs not in (6, 8):
            raise InputError(f"expected legs = 6 or 8, got {self.legs!r}", field="legs")
        for f in ("l0", "l1", "l2", "l3", "lp", "ld", "z0", "beta", "gamma", "mass",
                  "inertia"):
            no_booleans(getattr(self, f), f)
        for f in ("l0", "l1", "lp", "z0", "mass", "inertia"):
            v = getattr(self, f)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"expected a positive finite number, got {v!r} {SI_UNITS[f]}",
                                 field=f)
            object.__setattr__(self, f, float(v))
        for f in ("l2", "ld", "beta", "gamma"):
            v = getattr(self, f)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise InputError(f"expected a finite number >= 0, got {v!r} {SI_UNITS[f]}",
                                 field=f)
            object.__setattr__(self, f, float(v))
        for f in ("l0", "l1", "lp", "z0", "l2", "ld"):
            length_in_range(getattr(self, f), f, zero_ok=f in ("l2", "ld"))
        if self.ld == 0 and self.beta == self.gamma == self.l2 == 0:
            # each pair's crank pivots l0 e -+ ld/2 t: with beta = gamma = l2 = 0 as well,
            # the two legs of a pair are one leg (with beta or gamma != 0 their axes
            # differ, with l2 != 0 their offsets: distinct legs, a regular J; review)
            raise InputError(f"expected ld > 0 m (the two legs of a pair apart), got ld = 0 m: "
                             f"the legs of each pair coincide, legs 1 and 2 with their crank "
                             f"pivots at one point ({self.l0:.6g}, 0, 0) m and spherical "
                             f"joints (beta = gamma = l2 = 0: the same leg twice, J singular "
                             f"at every pose)", field="ld",
                             hint="ld is the distance between the two legs of a pair "
                                  "(distkin.mechanisms.presets; 20 mm in the presets)")
        if self.layout not in LAYOUTS:
            raise InputError(f"expected layout in {LAYOUTS}, got {self.layout!r}",
                             field="layout")
        if self.beta >= math.pi / 2 or self.gamma >= math.pi / 2:
            raise InputError(f"expected beta and gamma below 90 deg, got beta={self.beta!r}, "
                             f"gamma={self.gamma!r} rad", field="beta")
        if self.l3 is None:
            object.__setattr__(self, "l3", self._l3_rule())
        else:
            v = self.l3
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"expected a positive finite number, got {v!r} m", field="l3")
            object.__setattr__(self, "l3", length_in_range(float(v), "l3"))
        self._warn_home()

    def home_margins(self) -> np.ndarray:
        """(L,) reach margins rho^2 - C^2 (m^2) of the legs at the home pose (>= 0: the
        leg closes; the plain-numpy route's closure, :func:`.reference.home_reach_margins`)."""
        from .reference import home_reach_margins
        return home_reach_margins(self)

    def _warn_home(self):
        """A :class:`GeometryWarning` when a leg does not close at the home pose (the
        workspace centre, the IK branches' and forward kinematics' reference; mostly a
        unit slip, ``preset("octo", z0=300)``); refusing would stop the design sweeps,
        which score such designs (GII 0)."""
        m = self.home_margins()
        size = (self.l0 + self.ld + self.lp + self.z0 + self.l1 + self.l2 + self.l3) ** 2
        bad = np.flatnonzero(m < -1e-12 * size)
        if bad.size:
            legs = ", ".join(f"leg {i + 1} margin {m[i]:.3g} m^2" for i in bad[:4])
            _warn(f"home: expected a home pose (0, 0, z0) that every leg reaches, got "
                          f"z0 = {self.z0:.6g} m, where {bad.size} of {self.legs} legs do not "
                          f"close ({legs}{' ...' if bad.size > 4 else ''}; l0 = {self.l0:.6g} "
                          f"m, l1 = {self.l1:.6g} m, l3 = {self.l3:.6g} m): a length in "
                          f"another unit? (SI: m)", GeometryWarning)

    def __getstate__(self):
        # pickle the description only (pool workers), not the loaded kernel modules
        return {f.name: getattr(self, f.name) for f in fields(self)}

    # ------------------------------------------------------------------ geometry
    @property
    def L(self) -> int:
        """Number of legs and actuators."""
        return self.legs

    @property
    def home(self) -> np.ndarray:
        """The workspace centre (0, 0, z0, 0, 0, 0)."""
        return np.array([0.0, 0.0, self.z0, 0.0, 0.0, 0.0])

    @property
    def length_scale(self) -> float:
        """lp (m): the length that turns rotations into displacements (FK steps)."""
        return self.lp

    def geometry(self) -> dict:
        """Constant leg vectors of the parametrisation (:mod:`.presets`), arrays (L, 3).

        Keys: ``B`` crank pivots, ``a`` actuator axes, ``u`` horizontal crank
        directions (the crank at q = 0), ``offset`` (crank tip -> universal joint,
        length l2 along the axis), ``p`` spherical joints in the end-effector frame;
        ``theta`` (L,) pair azimuths, ``side`` (L,).
        """
        L = self.legs
        k = np.arange(L) // 2
        side = np.where(np.arange(L) % 2 == 0, -1.0, 1.0)
        theta = 2.0 * np.pi * k / (L // 2)
        e = np.stack([np.cos(theta), np.sin(theta), np.zeros(L)], axis=-1)
        t = np.stack([-np.sin(theta), np.cos(theta), np.zeros(L)], axis=-1)
        z = np.array([0.0, 0.0, 1.0])
        B = self.l0 * e + (side * self.ld / 2)[:, None] * t

        def rotz(ang, v):
            c, s = np.cos(ang), np.sin(ang)
            return np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1], v[:, 2]],
                            axis=-1)

        if self.layout in ("tangential", "tangential_in"):
            a = rotz(side * self.beta, t)                # the pair's axes on one tangent
            u = np.cross(a, z)                           # cranks: horizontal, radially out
            if self.layout == "tangential_in":
                u = -u                                   # ... or radially in
            offset = (side * self.l2)[:, None] * a       # away from the pair's centre
        else:
            a = rotz(side * self.beta, e)                # actuator axes radial
            u = side[:, None] * np.cross(z, a)           # cranks: tangential, away from the pair
            offset = self.l2 * a                         # outwards along the axis
        p = rotz(side * self.gamma, self.lp * e + (side * self.ld / 2)[:, None] * t)
        return {"B": B, "a": a, "u": u, "offset": offset, "p": p, "theta": theta,
                "side": side}

    def _l3_rule(self) -> float:
        if self.layout == "tangential":
            if self.l2 >= LEG_LENGTH:
                raise InputError(f"expected l2 below the leg length {LEG_LENGTH} m (l3 = "
                                 f"{LEG_LENGTH} - l2), got {self.l2:.6g} m", field="l2",
                                 hint="a smaller l2, or l3 given with it")
            return LEG_LENGTH - self.l2
        return self.horizontal_crank_l3()

    def horizontal_crank_l3(self) -> float:
        """The distal length (m) that puts every crank horizontal (q = 0) at the workspace
        centre (docs/design.md §5's first rule; the rule of the "radial" and
        "tangential_in" readings)."""
        g = self.geometry()
        P = g["p"][0] + np.array([0.0, 0.0, self.z0])
        D = g["B"][0] + g["offset"][0] + self.l1 * g["u"][0]
        return float(np.linalg.norm(P - D))

    def parameters(self) -> dict:
        """All parameters as a dict (SI)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def geometry_key(self) -> tuple:
        """The kinematic parameters as a tuple (identity of the generated kernels), once
        per (frozen) description: nine calls in a single FK (review 2026-11-29)."""
        if "_key" not in self.__dict__:
            self.__dict__["_key"] = tuple((f, getattr(self, f)) for f in GEOMETRY_FIELDS)
        return self.__dict__["_key"]

    def l3_interval(self, poses, *, batch: int = 50000):
        """The distal-link lengths that close every leg at every pose: ``(lo, hi)`` (m).

        Leg i closes at a pose iff l3 lies between the smallest and the largest distance
        from its spherical joint P to the circle of its universal-joint centre D(q)
        (radius l1 about ``B + offset`` in the plane normal to the axis a):
        ``sqrt(w_a^2 + (w_r -+ l1)^2)`` with w = P - B - offset split into its axial
        part w_a and radial part w_r.  Independent of ``self.l3``; ``lo > hi`` means no
        single l3 closes them all.

        Parameters
        ----------
        poses : array (N, 6) or (6,)
        batch : int
            Poses per vectorised block.
        """
        from ..spatial import rotation_matrix
        X, _ = _poses(poses, scale=self.length_scale)
        g = self.geometry()
        lo, hi = -np.inf, np.inf
        for a in range(0, len(X), batch):
            Y = X[a:a + batch]
            P = Y[:, None, :3] + np.einsum("nij,lj->nli", rotation_matrix(Y[:, 3:]), g["p"])
            w = P - (g["B"] + g["offset"])[None]
            wa = np.einsum("nli,li->nl", w, g["a"])
            wr = np.linalg.norm(w - wa[..., None] * g["a"][None], axis=-1)
            lo = max(lo, float(np.sqrt(wa ** 2 + (wr - self.l1) ** 2).max()))
            hi = min(hi, float(np.sqrt(wa ** 2 + (wr + self.l1) ** 2).min()))
        return lo, hi

    def leg_description(self):
        """This mechanism as a leg table (:class:`~.legs.LegsDescription`): per leg the
        vectors of :meth:`geometry` (crank direction at q = 90 deg: z), l1, l3, the IK
        branch sigma = +1 (:mod:`.symbolic`), type RSS (l2 = 0) or RRRS, and the nominal
        actuator torque ±2.5 N m (Sec. III-B.3); FK's length scale lp.  The kernels of an RSS mechanism are
        generated from this table (:mod:`distkin.codegen.rss`).  Built once per (frozen)
        description: a certified IK asked for it twice, and each build checks the legs'
        lines (:mod:`.leg_architecture`, ~0.4 ms)."""
        if "_legs" not in self.__dict__:
            self.__dict__["_legs"] = self._leg_description()
        return self.__dict__["_legs"]

    def _leg_description(self):
        from .legs import Leg, LegsDescription
        g = self.geometry()
        z = (0.0, 0.0, 1.0)
        legs = tuple(
            Leg(type="RRRS" if self.l2 > 0 else "RSS", base=tuple(g["B"][i]),
                platform=tuple(g["p"][i]), axis=tuple(g["a"][i]), crank0=tuple(g["u"][i]),
                crank90=z, crank=self.l1, offset=tuple(g["offset"][i]), distal=self.l3,
                branch=1, limit=(-2.5, 2.5))
            for i in range(self.legs))
        import warnings
        with warnings.catch_warnings():    # an unreachable home: said when this was built
            warnings.simplefilter("ignore", GeometryWarning)
            return LegsDescription(self.name, legs, tuple(self.home), self.mass,
                                   self.inertia, self.lp)

    # ------------------------------------------------------------------ dynamics
    def cartesian_mass_matrix(self) -> np.ndarray:
        """M̂ = diag(m, m, m, I, I, I) (Sec. III-B.3), (6, 6) in kg and kg m^2."""
        return np.diag([self.mass] * 3 + [self.inertia] * 3)


def read_only(result) -> None:
    """Make the numpy arrays of a frozen result dataclass ``result`` read-only (QA T 8),
    in place of its fields: each array field (and each array in a list or tuple field)
    becomes a read-only view of it, so neither the caller's arrays nor the package's are
    frozen, and ``result.pose[0] = 5`` raises ``ValueError``."""
    names = _FIELD_NAMES.get(type(result))
    if names is None:
        names = _FIELD_NAMES[type(result)] = tuple(f.name for f in fields(result))
    for name in names:
        v = getattr(result, name)
        if isinstance(v, np.ndarray):
            v = v.view()
            v.setflags(write=False)
        elif isinstance(v, (list, tuple)) and any(isinstance(x, np.ndarray) for x in v):
            v = type(v)(_read_only_array(x) for x in v)
        else:
            continue
        object.__setattr__(result, name, v)


#: the field names of each result class :func:`read_only` has seen
_FIELD_NAMES: dict = {}


def _read_only_array(v):
    if isinstance(v, np.ndarray):
        v = v.view()
        v.setflags(write=False)
    return v
