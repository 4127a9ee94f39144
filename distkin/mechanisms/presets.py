"""The five RSS presets of Kühne et al. and the rules that fill what the paper leaves open.

What the paper gives (Sec. III-B.2 and III-D, Table I; docs/design.md §5):

* every preset: l0 = 152 mm (base radius), l1 = 157 mm (crank), lp = 55 mm
  (end-effector radius), workspace centre at z0 = 0.30 m;
* Hunt-type: l2 = 0, beta = 0, gamma = 0 (the GII optimum of Table I: ld = 20 mm);
* HEXA: gamma != 0; Ergin's device: beta, gamma and l2 != 0 (values not printed);
* Octopod: the Hunt-type kinematics with four symmetric pairs of legs (L = 8);
* Octo (the prototype): l2 = 25.6 mm, beta = 0, gamma = 13.18 deg, ld = 20 mm,
  l0 = 160 mm, L = 8;
* "The total length of each leg remains constant, which is ensured by keeping l2 + l3
  constant.  Baseline geometric characteristics were taken from Ergin's device"
  (Sec. III-B-2); the Octo "is based on Ergin's device" (Sec. III-D);
* mass m = 0.17 kg, inertia I = 3e-4 kg m^2 (Sec. III-B.3).

Our reading of Fig. 2 (the figure's exact definitions are not in the text; one rule,
used everywhere in distkin: ``layout="tangential"``).  Legs come in L/2 mirror-symmetric
pairs; pair k (k = 0 .. L/2-1) sits at azimuth theta_k = 2 pi k / (L/2); leg i belongs
to pair i // 2 with side s = -1 (even i) or +1 (odd i).  With e = (cos theta_k,
sin theta_k, 0), t = (-sin theta_k, cos theta_k, 0) and z = (0, 0, 1):

* **ld** -- distance between the two legs of a pair, both at the base (crank pivots
  ``B = l0 e + s ld/2 t``) and at the end effector (before the gamma rotation).
* **beta** -- "angle at the base": the two actuator axes of a pair lie on the tangent
  to the base circle (beta = 0: one axis line, as the motor pairs of the HEXA and the
  Delta); each is turned about the vertical by s*beta, ``a = Rz(s beta) t``.  The crank
  swings in the plane normal to ``a``; at q = 0 it is horizontal and points radially
  outwards, ``u = a x z`` (= e at beta = 0).
* **l1** -- crank: tip ``C = B + l1 (cos q u + sin q z)``; q = 0 is horizontal, q > 0
  lifts the crank.
* **l2** -- the RRRS offset: the two passive revolute joints at the crank tip are
  l2 apart along the actuator axis, away from the pair's centre, so the centre of the
  equivalent universal joint is ``D = C + s l2 a``.  l2 = 0 gives the RSS leg.
* **gamma** -- "angle at the end effector": the two spherical joints of a pair are
  turned apart about the end-effector axis by ±gamma,
  ``p = Rz(s gamma) (lp e + s ld/2 t)`` in the end-effector frame.
* **l3** -- the distal link ``|P - D| = l3`` with ``P = x + R p``.  Not given in the
  paper.  Our rule, the paper's own for the design sweep: **every leg has the same
  length l2 + l3 = K** (:data:`~.rss.LEG_LENGTH` = 349.7 mm), so l3 = K - l2 (the
  Hunt-type and Octopod 349.7 mm, Ergin's device and the Octo 324.1 mm) and the
  Hunt-type of the Table I sweep is the ``hunt`` preset.  K is the centre of the
  interval of leg lengths under which every leg of every preset closes at every pose
  of its study box (Table II positions, ±20° for L = 6, ±30° for L = 8, 10 mm / 5°
  grid; :func:`leg_length_rule`): [346.7, 352.7] mm, centre 349.66 mm.  It is chosen
  for reach, not to match any table.  With it the cranks stand at 18.9° (hunt,
  octopod), 22.9° (hexa), 29.0° (ergin) and 32.4° (octo) at the centre.
* **IK branch**: of the two crank angles that close a leg, the one nearer 0 at the
  workspace centre (sigma = +1 in :mod:`.symbolic`).

Why this reading.  Every preset must be buildable (no two links cross) and reach its
study box (Sec. II-A, Table II).  Link interference is checked by
:mod:`.interference` (segment distances, 5 mm clearance).  With this reading every
preset is clear at the centre (>= 19.7 mm between any two links) and reaches its whole
study box.  Over the box (25 mm / 10° grid) the hunt, ergin and octo presets keep
>= 9.7 mm, the octopod comes to 4.2 mm at 0.01 % of its poses (extreme corners), and
the hexa preset (gamma = 30°, our guess) brings a distal link within 5 mm of its
partner's crank at 0.69 % of its poses (extreme corners).  The readings tried, each
with its reach, interference and Table IV figures (``docs/fig2_readings.md``,
``python -m benchmarks readings``):

* radial axes, tangential cranks away from the pair, cranks horizontal at the centre
  (``layout="radial"``, the reading before issue 15): reaches the study boxes, but with
  L = 8 the cranks of neighbouring pairs cross (0 mm at the centre pose, 45-91 % of the
  box below 5 mm): the Octopod and the Octo cannot be built.  Table IV: GII 41×, 9.9×,
  2.2× the paper's (Hunt-type, Octopod, Octo);
* tangential axes, cranks radially outwards, horizontal at the centre (l3 = 393-402 mm,
  :meth:`~.rss.RSSMechanism.horizontal_crank_l3`): reaches only 84-91 % of the study
  boxes (at z0 - 75 mm the spherical joints come closer to the pivots than l3 - l1);
* tangential axes, cranks radially inwards, horizontal at the centre
  (``layout="tangential_in"``, l3 = 304-306 mm): the crank tips meet near the axis
  (l1 > l0): not buildable;
* tangential axes, cranks outwards, one leg length K for all (this reading): Table IV
  GII 1.16×, 3.3×, 11× the paper's, σmin 0.17-0.64×, σmax 0.06-0.16× (the σ depend on
  the reading of the scaling, :mod:`distkin.indices.isotropy`);
* the same with K identified on Table IV (an explicit fit, not used by the presets:
  least squares of the three GIIs' log ratios gives K = 332 mm); with Table III held
  out it does no better than the rule (median |log10 ours/paper| 0.200 against 0.202,
  rows within 2×: 57 % against 62 %).

Preset values the paper does not print, and our choice:

* ``hexa``  -- gamma = 30 deg (the upper end of Table I's range), beta = l2 = 0.
* ``ergin`` -- Ergin's device, which the Octo is based on (Sec. III-D): the Octo's
  l2 = 25.6 mm and gamma = 13.18 deg, with beta = 10 deg (the first non-zero step of
  Table I), l0 = 152 mm, L = 6.
* ``hunt``, ``octopod`` -- beta = gamma = l2 = 0, ld = 20 mm (Table I optimum).
* ``octo`` -- as printed (Sec. III-D).  ``octo`` and ``octopod`` differ from the
  paper's hardware in whatever Fig. 2 means differently from the rule above.

Under this reading the ergin preset has direct singularities inside its ±20° box (the
paper's Ergin device has them, Table III: 0.00 N), but neither it nor the hexa preset
has one in the 150 mm cube at zero rotation (certified, :mod:`distkin.certify`), unlike
Fig. 3: the study report marks comparisons with them accordingly.
"""

from __future__ import annotations

import math

from ..errors import InputError, warn as _warn
from .description import RSSDescription

__all__ = ["PRESETS", "preset_description", "PRESET_NAMES", "description", "leg_length_rule",
           "study_box", "SLIP_RATIO", "slip_ratio", "slip_ratios", "unit_slips",
           "preset_parameters"]

#: an override this many times larger or smaller than the preset's value is said to be
#: a likely unit slip (QA R 8; the scene's check, :mod:`distkin.app.mechanism_scene`): a
#: warning, not an error (a design may differ that much)
SLIP_RATIO = 100.0
_SLIP_UNITS = {**dict.fromkeys(("l0", "l1", "l2", "l3", "lp", "ld", "z0"), "m"),
               "mass": "kg", "inertia": "kg m^2"}

_MM = 1e-3
_DEG = math.pi / 180.0

_COMMON = dict(l0=152 * _MM, l1=157 * _MM, lp=55 * _MM, z0=0.30, ld=20 * _MM,
               l2=0.0, beta=0.0, gamma=0.0, mass=0.17, inertia=3e-4)

#: preset name -> parameters (SI) and a one-line description
PRESETS: dict[str, dict] = {
    "hunt": dict(_COMMON, legs=6),
    "hexa": dict(_COMMON, legs=6, gamma=30 * _DEG),
    "ergin": dict(_COMMON, legs=6, l2=25.6 * _MM, beta=10 * _DEG, gamma=13.18 * _DEG),
    "octopod": dict(_COMMON, legs=8),
    "octo": dict(_COMMON, legs=8, l0=160 * _MM, l2=25.6 * _MM, gamma=13.18 * _DEG),
}

PRESET_NAMES = tuple(PRESETS)

_DESCRIPTIONS = {
    "hunt": "Hunt-type 6-RSS (iFeel6.0), Table I optimum",
    "hexa": "HEXA (Pierrot), 6-RSS with gamma = 30 deg",
    "ergin": "Ergin's 6-RRRS device (l2, beta, gamma non-zero)",
    "octopod": "Octopod: Hunt-type with four leg pairs (8-RSS)",
    "octo": "Octo prototype (8-RRRS, l0 = 160 mm, l2 = 25.6 mm, gamma = 13.18 deg)",
}


def preset_description(name: str, **overrides) -> RSSDescription:
    """The description of the mechanism named ``name``, with parameters optionally
    overridden (:func:`distkin.mechanisms.preset` gives the numeric mechanism).

    Parameters
    ----------
    name : {"hexa", "hunt", "ergin", "octopod", "octo"}
    **overrides
        Any of ``legs, l0, l1, l2, l3, lp, ld, z0, beta, gamma, mass, inertia`` in SI
        units (m, rad, kg, kg m^2), and ``layout`` (the reading of Fig. 2).  Unless
        ``l3`` is given it follows the reading's rule (module docstring):
        ``l3 = LEG_LENGTH - l2``.

    Returns
    -------
    RSSDescription
        Frozen; ``name`` is the preset's name if nothing was overridden, else
        ``"<name>*"``.

    Warns
    -----
    GeometryWarning
        An override of a length, ``mass`` or ``inertia`` more than :data:`SLIP_RATIO`
        times off the preset's value (:func:`unit_slips`: ``l0=160`` for 160 mm; the
        scene path's check), and a home pose some leg does not reach
        (:meth:`~.description.RSSDescription.home_margins`).  Warnings, not errors: a
        design may be that far off on purpose, and the design sweeps score designs
        that miss their workspace (``ld = 0``, coincident legs, is refused).
    """
    label, params = preset_parameters(name, **overrides)
    return RSSDescription(name=label, **params)


def preset_parameters(name: str, **overrides) -> tuple[str, dict]:
    """The name and the parameters (SI) of :func:`preset_description` (which builds
    the description from them); a :class:`~.description.GeometryWarning` per override
    that looks like a unit slip (:func:`unit_slips`)."""
    if name not in PRESETS:
        raise InputError(f"expected a preset in {', '.join(map(repr, PRESETS))}, got {name!r}",
                         field="preset")
    allowed = set(PRESETS[name]) | {"l3", "layout"}
    bad = sorted(set(overrides) - allowed)
    if bad:
        raise InputError(f"unknown parameter(s) {', '.join(map(repr, bad))}; expected some of "
                         f"{', '.join(sorted(allowed))}", field="preset")
    params = dict(PRESETS[name])
    changed = {k: v for k, v in overrides.items() if k not in params or params[k] != v}
    params.update(overrides)
    label = name if not changed else f"{name}*"
    slips = unit_slips(name, overrides)
    if slips:

        from .legs import GeometryWarning
        for line in slips:
            _warn(line, GeometryWarning)
    return label, params


def slip_ratios(name: str, overrides: dict) -> list[tuple[str, float, float, float, str]]:
    """``(key, value, preset_value, ratio, SI unit)`` for each override of a length,
    ``mass`` or ``inertia`` (SI) that differs from the preset ``name``'s value by more
    than :data:`SLIP_RATIO` times either way (both non-zero): what a value in another
    unit looks like (``l0=160`` for 160 mm).  :func:`unit_slips` and the scene path
    (:func:`distkin.app.mechanism_scene.unit_slips`, in the scene's units) word them."""
    base = PRESETS[name]
    out = []
    for k, unit in _SLIP_UNITS.items():
        v, b = overrides.get(k), base.get(k)
        if k == "l3" and v is not None:
            b = RSSDescription(**{**base, "layout": overrides.get("layout", "tangential")}).l3
        ratio = slip_ratio(v, b)
        if ratio is not None:
            out.append((k, v, b, ratio, unit))
    return out


def slip_ratio(value, reference) -> float | None:
    """``|value / reference|`` when it is more than :data:`SLIP_RATIO` times either way
    (what a value in another unit looks like), else None; None too when either is zero
    or not a finite number (nothing to compare; the description refuses such values).
    The one test of a likely unit slip: preset overrides (:func:`slip_ratios`), a study
    grid's half and step against the device's size and a design sweep's ranges
    (:func:`distkin.app.mechanism_scene.length_slips`)."""
    if any(not isinstance(x, (int, float)) or isinstance(x, bool) or not x
           or not math.isfinite(x) for x in (value, reference)):
        return None
    ratio = abs(value / reference)
    return None if 1.0 / SLIP_RATIO <= ratio <= SLIP_RATIO else ratio


def unit_slips(name: str, overrides: dict) -> list[str]:
    """:func:`slip_ratios` as one line each, in SI (what :func:`preset` warns)."""
    lines = []
    for k, v, b, ratio, unit in slip_ratios(name, overrides):
        why = ("a length in another unit? preset() takes SI: m" if unit == "m" else
               f"{k} is in {unit} (SI)")
        lines.append(f"{k}: {v:.6g} {unit} is {ratio:.3g} x the preset's {b:.6g} {unit} ({why})")
    return lines


def description(name: str) -> str:
    """One line describing a preset."""
    return _DESCRIPTIONS[name]


def study_box(mech, *, step: float = 0.010, rot_step_deg: float = 5.0):
    """The poses over which a preset is evaluated (Sec. III-B-3, III-C): the Table II
    positions (±75 mm about z0, ``step``) times rotations of ±20° (L = 6) or ±30°
    (L = 8) about every axis (``rot_step_deg``); array (N, 6), m and rad."""
    import itertools

    import numpy as np
    t = np.arange(-0.075, 0.075 + 1e-9, step)
    rot = 30.0 if mech.L == 8 else 20.0
    r = np.radians(np.arange(-rot, rot + 1e-9, rot_step_deg))
    P = np.array(list(itertools.product(t, t, mech.z0 + t)))
    O = np.array(list(itertools.product(r, r, r)))
    return np.hstack([np.repeat(P, len(O), axis=0), np.tile(O, (len(P), 1))])


def leg_length_rule(*, step: float = 0.010, rot_step_deg: float = 5.0, layout="tangential"):
    """The leg length ``K = l2 + l3`` of the reading (module docstring).

    For every preset, :meth:`RSSDescription.l3_interval` over its :func:`study_box`
    gives the interval of l2 + l3 that closes every leg at every pose; K is the centre
    of the intersection of the five intervals.

    Returns
    -------
    dict
        ``K`` (m), ``interval`` (lo, hi) (m) and ``per_preset`` {name: (lo, hi)} (m).
    """
    per = {}
    for name in PRESETS:
        m = preset_description(name, layout=layout)
        lo, hi = m.l3_interval(study_box(m, step=step, rot_step_deg=rot_step_deg))
        per[name] = (lo + m.l2, hi + m.l2)
    lo = max(v[0] for v in per.values())
    hi = min(v[1] for v in per.values())
    return {"K": (lo + hi) / 2, "interval": (lo, hi), "per_preset": per}
