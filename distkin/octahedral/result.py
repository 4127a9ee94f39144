r"""The results of the octahedral forward kinematics, shared by every tier.

:class:`Pose` (one assembly mode), :class:`RootInfo` (one real root of the octic),
:class:`AssemblyResult` (one problem, any tier) and :class:`BatchResult` (many problems,
the batched fast tier), with the helpers that build them from the fast tiers' arrays.
They live apart from :mod:`.forward` (the dispatcher) so that the tiers
(:mod:`.certified`, :mod:`.precise`, :mod:`.auto`) import their result types without
importing the dispatcher that imports them (docs/design.md, "Import direction").
Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from .problem import REASONS as _REASONS
from .scaling import rescale_octic

__all__ = ["Pose", "RootInfo", "AssemblyResult", "BatchResult"]

_SPURIOUS_NOTE = ("squaring eq. (3) twice gives degree 16 = (D(5,4,1) D(3,5,1))^2 x octic; "
                  "the spurious factor is removed analytically (octic = G^2 - 4 R1 R2)")


_FAST_ACCURACY = "float64; roots polished by Newton on eq. (3); see max_leg_error"


@dataclass(frozen=True)
class Pose:
    r"""One assembly mode: the platform pose in the base frame.

    Attributes
    ----------
    s15 : float
        The root :math:`s_{15}` (squared length).
    side : int
        +1 / -1: the side of P5 relative to the oriented base plane
        :math:`(P_2-P_1)\times(P_3-P_1)`; the two sides are mirror images.
    rotation : (3, 3) float64, proper rotation
    translation : (3,) float64; a platform-frame point q maps to ``rotation @ q +
        translation``.
    points : (3, 3) float64, rows P4 P5 P6 in base coordinates.
    max_leg_error : float
        Largest :math:`|\,\|P_iP_j\| - l_k|` over the six legs, length units (the
        certified tier gives a rigorous upper bound).
    max_leg_error_relative : float
        The same divided by each leg's length.
    native : dict or None
        Tier-native values ``{"s15", "points", "rotation", "translation"}``:
        ``mpf`` (precise) or ``arb`` balls (certified); None for fast.
    radius : float
        Certified tier: the exact points lie within ``radius`` of ``points`` (each
        coordinate; the largest radius of the point enclosures about their floats,
        :func:`~distkin.exact.float_ball`); else 0.

    Two poses are equal when their float fields are (arrays element by element);
    ``native`` is not compared (two arb balls are "equal" only when both are exact).
    """

    s15: float
    side: int
    rotation: np.ndarray
    translation: np.ndarray
    points: np.ndarray
    max_leg_error: float
    max_leg_error_relative: float
    native: dict | None = field(default=None, repr=False, compare=False)
    radius: float = 0.0

    def __post_init__(self):
        # a proved pose must not be editable after the fact (QA T 8); the fast tier's
        # poses (:func:`_pose`) are read-only views or copies made so where built
        for a in (self.rotation, self.translation, self.points):
            if isinstance(a, np.ndarray):
                a.flags.writeable = False

    def __eq__(self, other):
        if not isinstance(other, Pose):
            return NotImplemented
        return (self.s15 == other.s15 and self.side == other.side
                and all(np.array_equal(getattr(self, f), getattr(other, f))
                        for f in ("rotation", "translation", "points"))
                and self.max_leg_error == other.max_leg_error
                and self.max_leg_error_relative == other.max_leg_error_relative
                and self.radius == other.radius)

    __hash__ = None             # mutable arrays inside: not hashable

    def __getstate__(self):
        return _state(self)

    def __setstate__(self, state):
        _set(self, "__dict__", _restored(state))
        self.__post_init__()                # read-only arrays again, as built


def _short(v) -> str:
    """A root for :meth:`AssemblyResult.__repr__`: 6 digits (exact and ball values too)."""
    try:
        return f"{float(v):.6g}"
    except (TypeError, ValueError, OverflowError):
        return str(v)[:24]


def _state(obj):
    """Pickle and deepcopy state of a :class:`Pose` or :class:`RootInfo`: the certified
    tier's ``arb`` balls in ``native``, which python-flint cannot pickle, as their exact
    binary state (QA: a certified or escalated result raised TypeError in pickle,
    multiprocessing and copy.deepcopy)."""
    from ..exact_roots import pickle_balls
    return {**obj.__dict__, "native": pickle_balls(obj.__dict__["native"])}


def _restored(state):
    from ..exact_roots import unpickle_balls
    return {**state, "native": unpickle_balls(state["native"])}


@dataclass(frozen=True)
class RootInfo:
    """A real root of the octic and what became of it.

    ``status`` is ``"assembly"`` (two mirror poses) or ``"spurious"``/``"rejected"``
    with the ``reason``.  ``radius`` is, by ``radius_kind``:

    - ``"certified"`` (certified tier): the exact root lies within ``radius`` of the
      float ``value`` (the arb ball's radius plus the rounding of its midpoint to
      ``value``, rounded up; ``native`` is the ball itself);
    - ``"proved"`` (fast tier, where its proof vouches for the answer,
      :attr:`.conditioning.Conditioning.root_radii`): the same guarantee, in float64
      with rigorous rounding bounds (:mod:`.descartes`); for a root outside the feasible
      interval (spurious, no pose) it says that a real root of the exact octic lies
      within ``radius``, a different one for each root, but not that there are no
      others there: that count is float64's (step 8 of :mod:`.descartes`);
    - ``"estimate"`` (fast tier elsewhere: the bare tier, a problem the proof refused,
      a root around which the proof found no radius): the size of the last Newton
      steps, at least half an ulp of ``value``; (precise tier) its last Newton step
      plus the rounding of its root to ``value``: an estimate of the convergence, not
      an error bound.  On the 240 problems of :func:`.hardset.hard_families` (against
      the certified roots; ``python -m benchmarks accuracy``, BENCHMARKS.md) the bare
      tier's estimates are exceeded for about half of the roots (median factor 7),
      while none of the proved radii is.

    A batched ``result(i)`` gives the single solve's tight proved radii (the batched
    proof's own, ``raw["radii"]``, are the pieces of its subdivision: median 8e-8
    relative on those problems, against 3e-10).
    """

    value: float
    radius: float
    multiplicity: int
    status: str
    reason: str
    native: object = field(default=None, repr=False, compare=False)
    radius_kind: str = "estimate"

    def __getstate__(self):
        return _state(self)

    def __setstate__(self, state):
        _set(self, "__dict__", _restored(state))


@dataclass(frozen=True)
class AssemblyResult(Sequence):
    """The assembly modes of one octahedral manipulator: a sequence of :class:`Pose`.

    An empty result means the manipulator cannot be assembled with these legs;
    :attr:`reason` says why.  Indexing and iteration give the poses.

    Attributes
    ----------
    poses : tuple of Pose, by increasing s15, side +1 first
    method : str
    octic : tuple
        Coefficients highest degree first: Fractions when exact, else floats.
    octic_exact : bool
    roots : tuple of RootInfo, every real root of the octic found, increasing
    certified : bool
        The real-root count and the rejections are proved (certified tier).
    reason : str
        Why there are no poses (empty when there are).
    accuracy : str
    notes : tuple of str
    tier : str
        The tier that produced the answer (``method`` itself, except for
        ``method="auto"``: the tier it settled on).
    tier_reason : str
        ``method="auto"``: why that tier answered.
    conditioning : :class:`~.conditioning.Conditioning` or None
        The fast tier's proof of its own assembly roots, or why there is none (fast
        and auto).

    A single fast solve builds :attr:`poses` and :attr:`roots` on their first reading
    (from the compiled solver's buffer, :func:`_buffer_result`; issue 17: the objects
    cost more than the solve): the same objects, built once, when they are read.
    """

    poses: tuple
    method: str
    octic: tuple
    octic_exact: bool
    roots: tuple
    certified: bool
    reason: str
    accuracy: str
    notes: tuple = ()
    tier: str = ""
    tier_reason: str = ""
    conditioning: object = None

    def __len__(self):
        lazy = self.__dict__.get("_lazy")
        return len(self.poses) if lazy is None else lazy[3]

    def __getitem__(self, i):
        return self.poses[i]

    def __iter__(self):
        return iter(self.poses)

    def __getattr__(self, name):
        # reached only when the instance has no such attribute: the lazy fields
        # ``poses`` and ``roots`` of a single fast solve (:func:`_buffer_result`)
        if name in ("poses", "roots"):
            d = object.__getattribute__(self, "__dict__")
            lazy = d.get("_lazy")
            if lazy is not None:
                roots, poses = _from_buffer(*lazy, d.get("conditioning"))
                d.setdefault("roots", roots)        # (two threads: the first one's)
                d.setdefault("poses", poses)
                d.pop("_lazy", None)
                return d[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __repr__(self):
        """A summary: tier, poses, roots, what is proved (the fields in full are the
        attributes).  The dataclass's own repr printed every pose and the exact octic,
        ~8000 characters for the Griffis-Duffy example, and raised ``ValueError`` where
        a Fraction of the certified octic has more than Python's 4300 digits (legs of
        1e-150: QA 23b, 9)."""
        s15 = ", ".join(_short(r.value) for r in self.assembly_roots)
        parts = [f"method={self.method!r}"]
        if self.tier and self.tier != self.method:
            parts.append(f"tier={self.tier!r}")
        parts.append(f"{len(self)} poses")
        parts.append(f"s15 of the assembly roots [{s15}]")
        parts.append(f"{len(self.roots)} real roots of the octic")
        if self.certified:
            parts.append("certified")
        elif self.conditioning is not None:
            c = self.conditioning
            parts.append("proved" if c.trusted else f"not proved: {c.reason}")
        if self.reason:
            parts.append(f"reason={self.reason!r}")
        if self.notes:
            parts.append(f"{len(self.notes)} notes")
        return "AssemblyResult(" + ", ".join(parts) + ")"

    @property
    def degree(self) -> int:
        """The octic's true degree: 8 unless leading coefficients vanish (exactly, in the
        exact tiers; exactly zero floats in the fast tier)."""
        k = 0
        while k < len(self.octic) and self.octic[k] == 0:
            k += 1
        return len(self.octic) - 1 - k

    @property
    def real_root_count(self) -> int:
        return len(self.roots)

    @property
    def assembly_roots(self) -> tuple:
        return tuple(r for r in self.roots if r.status == "assembly")


@dataclass(frozen=True)
class BatchResult:
    """Results of N problems as arrays (padded with NaN): the fast tier, or ``auto``.

    Attributes
    ----------
    count : (N,) number of poses of each problem (twice its assembly roots)
    s15 : (N, 8) assembly roots, increasing, NaN padded
    points : (N, 16, 3, 3) rows P4 P5 P6; rotation (N, 16, 3, 3); translation (N, 16, 3)
    max_leg_error, max_leg_error_relative : (N, 16)
    valid : (N, 16) bool mask of real poses
    raw : dict, the arrays of :func:`.batched.solve_fast` (scaled back to the given units),
        with the kernel's inputs ``sides2``, ``legs2`` (normalised) and their exponent
        ``exponent`` (lengths divided by ``2**exponent``, :mod:`.scaling`), and with the
        proof: ``verdict``, ``radii`` (the batched proof's, per root), ``eta``,
        ``recovered``
    trusted : (N,) bool
        The fast tier proved the problem's assembly roots (:mod:`.descartes`); False
        flags every problem it cannot vouch for (every problem when the proof was
        skipped: ``prove=False``).
    verdict : (N,) int
        The key of :data:`.descartes.VERDICTS` (0: proved), for the fast tier's answer
        (:data:`.descartes.NOT_CHECKED` when the proof was skipped).
    tier : (N,) str
        The tier that answered each problem: ``"fast"``, or with ``method="auto"``
        ``"certified"`` (``"precise"`` for data that cannot be made exact) for the
        problems the fast tier did not prove.
    escalated : dict
        ``method="auto"``: problem index -> the :class:`AssemblyResult` of the tier that
        answered it instead of the fast one.
    unresolved : dict
        ``method="auto"``: problem index -> why the certified tier could not decide it
        (its :class:`~distkin.errors.UncertifiedError`, e.g. a multiple root in a
        symmetric configuration).  Such a problem keeps the fast answer, flagged
        (``trusted`` False, ``tier`` "fast"), and the call warns; the other problems
        keep their answers.

    Every array (and every array of ``raw``) is read-only, as the arrays of a single
    solve's :class:`Pose` are: an answer marked proved cannot be edited in place.
    """

    count: np.ndarray
    s15: np.ndarray
    points: np.ndarray
    rotation: np.ndarray
    translation: np.ndarray
    max_leg_error: np.ndarray
    max_leg_error_relative: np.ndarray
    valid: np.ndarray
    raw: dict = field(repr=False)
    trusted: np.ndarray = None
    verdict: np.ndarray = None
    tier: np.ndarray = None
    escalated: dict = field(default_factory=dict, repr=False)
    unresolved: dict = field(default_factory=dict, repr=False)

    def __post_init__(self):
        # read-only, as a single solve's Pose arrays are (QA T 8): a flag per array, no
        # copies; the poses of .result(i) are views of these arrays, read-only with them
        for a in (self.count, self.s15, self.points, self.rotation, self.translation,
                  self.max_leg_error, self.max_leg_error_relative, self.valid, self.trusted,
                  self.verdict, self.tier, *self.raw.values()):
            if isinstance(a, np.ndarray):
                a.flags.writeable = False

    def __len__(self):
        return self.count.shape[0]

    def result(self, i: int) -> AssemblyResult:
        """The :class:`AssemblyResult` of problem ``i``."""
        if i in self.escalated:
            return self.escalated[i]
        return _fast_result(self.raw, i)


_new = object.__new__
_set = object.__setattr__


def _pose(s15, side, rotation, translation, points, err, rel):
    """A fast-tier :class:`Pose` without the frozen dataclass's ``__init__`` (one
    ``object.__setattr__`` per field; here the instance dictionary is set at once):
    the same object -- fields, repr, equality, pickling -- at a fifth of the cost
    (issue 17)."""
    p = _new(Pose)
    _set(p, "__dict__", {"s15": s15, "side": side, "rotation": rotation,
                         "translation": translation, "points": points,
                         "max_leg_error": err, "max_leg_error_relative": rel,
                         "native": None, "radius": 0.0})
    return p


def _assembly(poses, octic, roots, reason, notes, conditioning):
    """A fast-tier :class:`AssemblyResult`, as :func:`_pose`."""
    a = _new(AssemblyResult)
    _set(a, "__dict__", {"poses": poses, "method": "fast", "octic": octic,
                         "octic_exact": False, "roots": roots, "certified": False,
                         "reason": reason, "accuracy": _FAST_ACCURACY, "notes": notes,
                         "tier": "fast", "tier_reason": "", "conditioning": conditioning})
    return a


_INF, _ULP = math.inf, math.ulp


def _root(x, step, code, proved=_INF):
    """A fast-tier :class:`RootInfo` (status code of :data:`REASONS`), as :func:`_pose`:
    the ``proved`` radius where the proof gives one, else the estimate ``step`` (at
    least half an ulp of ``x``, which is at most 2^-53 |x|)."""
    r = _new(RootInfo)
    if proved < _INF:
        radius, kind = proved, "proved"
    else:
        radius, kind = abs(step), "estimate"
        if radius < 1.2e-16 * abs(x):
            radius = max(radius, 0.5 * _ULP(x))
    _set(r, "__dict__", {"value": x, "radius": radius, "multiplicity": 1,
                         "status": _STATUS[code], "reason": _REASONS[code], "native": x,
                         "radius_kind": kind})
    return r


def _proved(conditioning, n):
    """The proved radius of each of ``n`` roots (:attr:`.conditioning.Conditioning
    .root_radii`; inf for all without a proof)."""
    radii = () if conditioning is None else conditioning.root_radii
    return radii if len(radii) == n else (math.inf,) * n


def _frozen(a):
    """A read-only copy of ``a`` (a pose's array: QA T 8)."""
    a = a.copy()
    a.flags.writeable = False
    return a


def _fast_result(raw, i):
    """The :class:`AssemblyResult` of problem ``i`` of :func:`.batched.solve_fast`'s arrays."""
    roots, poses = [], []
    R, T, P = raw["rotation"][i], raw["translation"][i], raw["points"][i]
    E, Er = raw["leg_error"][i].tolist(), raw["leg_error_rel"][i].tolist()
    codes = raw["status"][i].tolist()
    n = next((j for j, c in enumerate(codes) if c < 0), len(codes))
    cond = None
    if "verdict" in raw:
        from .conditioning import from_verdict
        cond = from_verdict(int(raw["verdict"][i]), raw["roots"][i][:n], _tight(raw, i, n))
    for x, st, code, slot, pr in zip(raw["roots"][i].tolist(), raw["step"][i].tolist(),
                                     codes, raw["slot"][i].tolist(),
                                     _proved(cond, n)):   # the first n rows are roots
        roots.append(_root(x, st, code, pr))
        for j, side in ((slot, 1), (slot + 1, -1)) if code == 0 else ():
            poses.append(_pose(x, side, _frozen(R[j]), _frozen(T[j]), _frozen(P[j]), E[j],
                               Er[j]))
    reason = "" if poses else _empty_reason(roots, raw["lo"][i], raw["hi"][i],
                                            cond is not None and cond.trusted)
    notes = (_SPURIOUS_NOTE,)
    if "octic_exponent" in raw and raw["octic_exponent"][i]:
        notes += (_overflow_note(int(raw["octic_exponent"][i])),)
    return _assembly(tuple(poses), tuple(raw["coef"][i].tolist()), tuple(roots), reason,
                     notes, cond)


def _tight(raw, i, n):
    """The proved radii of the ``n`` roots of problem ``i`` of the batched arrays, tight:
    the proof of the single solve (:func:`.descartes.vouch_rows`, a bounded evaluation at
    each side of a root) on the same kernel output, squared lengths and roots, so that
    ``result(i)`` says what ``forward_kinematics`` says of the same problem.  The
    batched proof's own radii (``raw["radii"]``, the pieces of its subdivision: up to
    ~1e3 times wider) stand where this one does not prove the problem or without the
    kernel's inputs in ``raw``."""
    loose = raw["radii"][i][:n]
    if raw["verdict"][i] != 0 or "eta" not in raw or not n:
        return loose
    from .conditioning import vouch_tight_row
    radii = np.empty(n)
    v = vouch_tight_row(raw["data"], raw["sides2"], raw["legs2"], raw["eta"], raw["lo"],
                        raw["hi"], raw["roots"], raw["status"], raw["exponent"], i, n, radii)
    return radii if v == 0 else loose


def _VERDICTS():
    from .descartes import VERDICTS
    return VERDICTS


def _overflow_note(k):
    return (f"the octic's coefficients in the given units overflow float64: those shown are "
            f"for the lengths divided by 2^{k} (s15 by 4^{k})")


def _single_result(solve, conditioning=None, k=0):
    """The :class:`AssemblyResult` of :func:`.single.solve_fast_single`'s output
    ``solve`` (a :class:`.single.SingleSolve`; its pose arrays are fresh, owned by the
    poses: rows are views, no copies), for the lengths divided by ``2**k``: scaled back
    (:mod:`.scaling`) on the arrays, before any object is built."""
    coef, lo, hi, roots, poses = solve.coef, solve.lo, solve.hi, solve.roots, solve.poses
    S, side, P, R, T, E, Er = poses
    notes = (_SPURIOUS_NOTE,)
    octic = tuple(coef.tolist())
    if k:
        roots = np.ldexp(roots, [2 * k, 2 * k, 0])
        S, P, T, E = np.ldexp(S, 2 * k), np.ldexp(P, k), np.ldexp(T, k), np.ldexp(E, k)
        lo, hi = math.ldexp(lo, 2 * k), math.ldexp(hi, 2 * k)
        octic, ok = rescale_octic(octic, k)
        if not ok:
            notes += (_overflow_note(k),)
        if conditioning is not None:
            conditioning = conditioning.scaled(k)
    infos = tuple(_root(x, st, int(code), pr) for (x, st, code), pr in
                  zip(roots.tolist(), _proved(conditioning, len(roots))))
    for a in (R, T, P):                     # the poses' rows are views (QA T 8)
        a.flags.writeable = False
    out = tuple(map(_pose, S.tolist(), side.tolist(), R, T, P, E.tolist(), Er.tolist()))
    reason = "" if out else _empty_reason(infos, lo, hi,
                                          conditioning is not None and conditioning.trusted)
    return _assembly(out, octic, infos, reason, notes, conditioning)


_STATUS = {0: "assembly", 1: "spurious", 2: "spurious", 3: "rejected"}
_SIDES = (1, -1) * 8


def _buffer_result(lo, hi, nr, m, buf, conditioning=None, k=0):
    """The :class:`AssemblyResult` of the single solve's compiled output
    (:func:`.batched.scan_single`: the triangle bounds, ``nr`` roots, ``m`` poses and
    the buffer), for the lengths divided by ``2**k``.  Its roots and poses are built
    from the buffer when first read (:meth:`AssemblyResult.__getattr__`,
    :func:`_from_buffer`); with ``k`` (lengths rescaled, :mod:`.scaling`), or without a
    pose (the reason reads the roots), at once, by :func:`_single_result`."""
    if k or not m:
        o = 51 + 3 * nr
        o1, o2, o3, o4, o5 = o + m, o + 10 * m, o + 19 * m, o + 22 * m, o + 23 * m
        poses = (buf[o:o1], np.array(_SIDES[:m], dtype=np.int64),
                 buf[o1:o2].reshape(m, 3, 3), buf[o2:o3].reshape(m, 3, 3),
                 buf[o3:o4].reshape(m, 3), buf[o4:o5], buf[o5:o5 + m])
        solve = _Solve(buf[42:51], lo, hi, buf[51:o].reshape(nr, 3), poses)
        return _single_result(solve, conditioning, k)
    a = _new(AssemblyResult)
    _set(a, "__dict__", {"method": "fast", "octic": tuple(buf[42:51].tolist()),
                         "octic_exact": False, "certified": False, "reason": "",
                         "accuracy": _FAST_ACCURACY, "notes": (_SPURIOUS_NOTE,),
                         "tier": "fast", "tier_reason": "", "conditioning": conditioning,
                         "_lazy": (lo, hi, nr, m, buf)})
    return a


def _evolve(res, **changes):
    """:func:`dataclasses.replace` of an :class:`AssemblyResult` that keeps the roots and
    poses of a single fast solve unbuilt (:func:`_buffer_result`) until they are read."""
    d = res.__dict__
    if "_lazy" not in d:
        return replace(res, **changes)
    a = _new(AssemblyResult)
    new = dict(d)
    new.update(changes)
    _set(a, "__dict__", new)
    return a


def _worst_leg_error(res) -> float:
    """The largest relative leg error over the poses of ``res`` (0 without poses), read
    from the buffer of a single fast solve whose poses are not built yet."""
    lazy = res.__dict__.get("_lazy")
    if lazy is None:
        return max((p.max_leg_error_relative for p in res.poses), default=0.0)
    _, _, nr, m, buf = lazy
    o = 51 + 3 * nr + 23 * m
    return max(buf[o:o + m].tolist(), default=0.0)


class _Solve:
    """The fields of a :class:`.single.SingleSolve` that :func:`_single_result` reads."""

    __slots__ = ("coef", "lo", "hi", "roots", "poses")

    def __init__(self, coef, lo, hi, roots, poses):
        self.coef, self.lo, self.hi, self.roots, self.poses = coef, lo, hi, roots, poses


def _from_buffer(lo, hi, nr, m, buf, conditioning=None):
    """(roots, poses) of :func:`_buffer_result`'s buffer: :class:`RootInfo` and
    :class:`Pose` objects as :func:`_single_result` builds them (pose arrays are views
    of the buffer; the roots' radii proved where ``conditioning`` proves them)."""
    o = 51 + 3 * nr
    buf.flags.writeable = False             # the poses' arrays are its views (QA T 8)
    rows = buf[51:o].tolist()
    proved = _proved(conditioning, nr)
    roots = tuple(_root(rows[j], rows[j + 1], int(rows[j + 2]), proved[j // 3])
                  for j in range(0, 3 * nr, 3))
    o1, o2, o3, o4, o5 = o + m, o + 10 * m, o + 19 * m, o + 22 * m, o + 23 * m
    poses = tuple(map(_pose, buf[o:o1].tolist(), _SIDES[:m], buf[o2:o3].reshape(m, 3, 3),
                      buf[o3:o4].reshape(m, 3), buf[o1:o2].reshape(m, 3, 3),
                      buf[o4:o5].tolist(), buf[o5:o5 + m].tolist()))
    return roots, poses


def _empty_reason(roots, lo=None, hi=None, proved=True):
    """Why a result has no pose (the triangle bounds, the roots' statuses); not
    ``proved`` (a fast answer no proof vouches for): what was found, not a fact (QA 23d
    4: 'the octic has no real root' for a problem with 4 poses)."""
    if lo is not None and lo > hi:
        return (f"cannot be assembled: the triangle inequalities through P1 P5 need "
                f"s15 >= {float(lo):.6g} and s15 <= {float(hi):.6g}")
    head = ("cannot be assembled: " if proved else "no pose found: float64 found ") + \
        ("every real root of the octic is spurious (" + "; ".join(sorted({r.reason for r in roots}))
         + ")" if roots else "no real root of the octic")
    return head + ("" if proved else " (not proved: method='certified' or 'auto' decides)")


def blank_row(raw, i):
    """Row i of the batched arrays (``BatchResult.raw``) emptied: no root, no pose."""
    for name in ("s15", "points", "rotation", "translation", "leg_error", "leg_error_rel",
                 "roots", "step"):
        raw[name][i] = np.nan
    raw["status"][i] = -1
    raw["slot"][i] = -1
    raw["valid"][i] = False
    raw["count"][i] = 0
