"""Architecture singularities of a leg table: legs that cannot constrain the platform's
six degrees of freedom, whatever the pose (model layer; checked when a
:class:`~.legs.LegsDescription` is built).

Every row of J = Jq⁻¹ Jx is, up to its factor 1/Jq_ii, the Plücker line of a leg: a
prismatic leg's own line, Rojas et al. eq. (5), and a revolute leg's distal link (the
line through the distal joint centre D(q) and the platform joint P, Kühne et al.
eqs. (1)-(2)).  J has full rank 6 exactly when the L lines span the six-dimensional
space of wrenches.  Three refusals and one warning:

* :func:`check_distinct` -- two legs with the same constraint have equal rows at every
  pose (:class:`~distkin.errors.InputError`);
* :func:`check_concurrent` -- every platform joint at one point (or every base joint of
  an all-prismatic table): all lines through one point at every pose, rank at most 3
  (:class:`~distkin.errors.DegenerateGeometryError`);
* :func:`check_line_span` -- the span test of any other table (six parallel legs of a
  platform congruent to its base, legs whose lines all meet one line, ...), a
  :class:`~distkin.errors.GeometryWarning` (below).

The span test (:func:`line_span`).  At a pose X the normalised line matrix is

.. math:: N_i = (\\hat s_i,\\; (R p_i) \\times \\hat s_i / \\ell), \\qquad i = 1..L

with ŝ_i the unit direction of leg i's line, R p_i its platform joint relative to the
end-effector centre and ℓ the mechanism's length scale (``length_scale``): each row is
dimensionless and of norm between 1 and about 2, so the ratio σ6/σ1 of N's singular values
is the same for the mechanism drawn in mm or in km (scale-invariant), unchanged by a
leg's row factor (J's rank is N's) and free of J's mixed units.  N is evaluated at the
home pose and at :data:`PROBES` (three fixed nearby poses: translations of a few
percent of ℓ along every axis, rotations of a few degrees about every axis), one numpy
batch of the plain-numpy kernels (:class:`~.reference.NumericKernels`; ~0.2 ms).  The
singular poses of a mechanism that is not architecturally singular are the zero set of
det J, a hypersurface of the pose space: a pose chosen independently of the geometry
lies on it with probability zero.  So σ6/σ1 <= :data:`LINE_SPAN_TOL` at home *and* at
every probe means that J is rank-deficient on a neighbourhood of home, hence (det J is
analytic in the pose) on the whole connected workspace: the architecture singularity
warned of.  Singular at home only: home is a singular pose (the workspace centre and the
forward kinematics' default start), a separate warning.  A probe where a revolute leg
does not close is skipped (no line); with every probe skipped only the home test is
made.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import DegenerateGeometryError, GeometryWarning, InputError, warn as _warn

__all__ = ["check_distinct", "check_concurrent", "check_line_span", "line_span",
           "LineSpan", "LINE_SPAN_TOL", "PROBES"]

#: σ6/σ1 of the normalised line matrix at or below which the lines are taken not to span
#: 6 DOF: sqrt(eps), the ratio at which a float64 solve with that matrix keeps less than
#: half of float64's digits (healthy tables: 1e-2 ... 0.5 at home)
LINE_SPAN_TOL = float(np.sqrt(np.finfo(float).eps))

#: the probe poses of :func:`line_span`, offsets from home: (x, y, z) in units of the
#: length scale, (rx, ry, rz) in rad; fixed, independent of any geometry, every
#: coordinate non-zero and no two rows alike (no symmetry of a table maps one onto another)
PROBES = np.array([[0.0413, -0.0271, 0.0337, 0.0529, 0.0311, -0.0447],
                   [-0.0359, 0.0467, -0.0223, -0.0383, 0.0491, 0.0293],
                   [0.0251, 0.0389, 0.0457, 0.0347, -0.0419, 0.0521]])


@dataclass(frozen=True)
class LineSpan:
    """What :func:`line_span` found.

    Attributes
    ----------
    ratio : float
        σ6/σ1 of the normalised line matrix at home (NaN where a leg does not close).
    rank : int
        Its numerical rank there (singular values above ``LINE_SPAN_TOL`` σ1).
    probe_ratios : tuple of float
        σ6/σ1 at each probe pose that every leg reaches (the others left out).
    probe_ranks : tuple of int
    """

    ratio: float
    rank: int
    probe_ratios: tuple
    probe_ranks: tuple

    @property
    def singular_home(self) -> bool:
        """The lines do not span 6 DOF at home."""
        return bool(self.ratio <= LINE_SPAN_TOL)

    @property
    def architectural(self) -> bool:
        """Singular at home and at every probe evaluated (at least one): J is
        rank-deficient at every pose (module docstring)."""
        return (self.singular_home and len(self.probe_ratios) > 0
                and all(r <= LINE_SPAN_TOL for r in self.probe_ratios))


def line_span(desc) -> LineSpan | None:
    """The span test of a :class:`~.legs.LegsDescription` (module docstring), once per
    (frozen) description; None when a leg does not close at home (no line there: the
    home checks of the description say so)."""
    if "_line_span" in desc.__dict__:
        return desc.__dict__["_line_span"]
    from .reference import NumericKernels
    ls = float(desc.length_scale)
    X = desc.home + np.concatenate([np.zeros((1, 6)), PROBES]) * np.array([ls] * 3 + [1.0] * 3)
    k = NumericKernels(desc)
    pris = desc.arrays()["prismatic"]
    with np.errstate(divide="ignore", invalid="ignore"):
        rows = -k.jq_jx(X)[..., 1:]                               # (5, L, 6): s/den, Rp x s/den
        closes = (pris | (k.reach(X) >= 0.0)).all(axis=-1)
        norm = np.linalg.norm(rows[..., :3], axis=-1, keepdims=True)
        lines = rows / norm * np.array([1.0] * 3 + [1.0 / ls] * 3)
    good = closes & np.isfinite(lines).all(axis=(-1, -2))
    out = None
    if good[0]:
        sv = np.linalg.svd(lines[good], compute_uv=False)          # (n, 6)
        ratios = sv[:, -1] / sv[:, 0]
        ranks = (sv > LINE_SPAN_TOL * sv[:, :1]).sum(axis=-1)
        out = LineSpan(float(ratios[0]), int(ranks[0]), tuple(float(r) for r in ratios[1:]),
                       tuple(int(r) for r in ranks[1:]))
    desc.__dict__["_line_span"] = out
    return out


def check_line_span(desc):
    """Warn (:class:`~distkin.errors.GeometryWarning`) of a leg table whose lines do not
    span the platform's 6 DOF at home: architecturally singular (at every probe too,
    module docstring), or singular at the home pose only.  Nothing for a table that
    spans them, or that does not close at home."""
    span = line_span(desc)
    if span is None or not span.singular_home:
        return
    if span.architectural:
        _warn(f"leg: expected leg lines that span the platform's 6 degrees of freedom, got "
              f"lines of rank {span.rank} at the home pose and of rank at most "
              f"{max(span.probe_ranks)} at {len(span.probe_ranks)} nearby poses "
              f"(normalised Plücker line matrix, sigma_min/sigma_max "
              f"{max(span.ratio, *span.probe_ratios):.2g} <= {LINE_SPAN_TOL:.2g}): the "
              f"mechanism is architecturally singular, J is rank-deficient at every pose "
              f"(the platform moves with the actuators locked; forward kinematics has no "
              f"isolated answer); e.g. six parallel legs, or a platform congruent to its "
              f"base", GeometryWarning)
        return
    _warn(f"home: expected a home pose where the leg lines span the platform's 6 degrees "
          f"of freedom, got lines of rank {span.rank} there (normalised Plücker line "
          f"matrix, sigma_min/sigma_max {span.ratio:.2g} <= {LINE_SPAN_TOL:.2g}): home is a "
          f"singular pose (J is rank-deficient there; forward kinematics starts there by "
          f"default and cannot step), though nearby poses are not", GeometryWarning)


def _constraint(leg) -> tuple:
    """What fixes a leg's row of J: a prismatic leg's line (base and platform joints),
    a revolute leg's joints, crank frame, lengths and branch (not its type, range or
    effort limit)."""
    if leg.prismatic:
        return ("prismatic", leg.base, leg.platform)
    return ("revolute", leg.base, leg.platform, leg.axis, leg.crank0, leg.crank90,
            leg.crank, leg.offset, leg.distal, leg.branch)


def _m(v):
    """A point (m) as text with its unit: ``(0.152, 0, 0) m``."""
    return "(" + ", ".join(f"{float(x):.6g}" for x in v) + ") m"


def check_distinct(legs):
    """Refuse two legs with the same constraint (:func:`_constraint`): their rows of J
    are equal at every pose, so the mechanism is architecturally singular
    (:class:`InputError` naming both)."""
    seen = {}
    for i, leg in enumerate(legs):
        j = seen.setdefault(_constraint(leg), i)
        if j != i:
            what = "line" if leg.prismatic else "joints, crank, lengths and branch"
            raise InputError(f"expected distinct legs, got leg[{i}] with the same {what} as "
                             f"leg[{j}] (base {_m(leg.base)}, platform {_m(leg.platform)}): the same "
                             f"constraint twice, J is singular at every pose",
                             field=f"leg[{i}]")


def check_concurrent(legs):
    """Refuse a table whose legs' lines all pass through one point at every pose: every
    platform joint at one point (any leg types: prismatic lines and distal links all
    meet there), or an all-prismatic table with every base joint at one point.  Such a
    mechanism is architecturally singular (J has rank at most 3 at every pose: the
    platform turns freely about that point) and has no length scale.
    :class:`DegenerateGeometryError` naming the field (``leg``, the joints of every leg)."""
    P = np.array([leg.platform for leg in legs])
    B = np.array([leg.base for leg in legs])
    size = max(float(np.abs(P).max()), float(np.abs(B).max()), 1e-300)
    tol = 16 * np.finfo(float).eps * size
    for name, pts, applies in (("platform", P, True),
                               ("base", B, all(leg.prismatic for leg in legs))):
        if applies and float(np.ptp(pts, axis=0).max()) <= tol:
            raise DegenerateGeometryError(
                f"expected the {name} joints of the legs not all at one point, got every "
                f"leg's {name} at {tuple(float(v) for v in pts[0])} m: every leg's line passes "
                f"through it, so J has rank at most 3 at every pose (architecturally "
                f"singular: the platform turns freely about that point)", field="leg",
                hint=f"spread the {name} joints (at least three not on one line)")
