"""The five RSS presets of Kühne et al. and the rules that fill what the paper leaves open.

What the paper gives (Sec. III-B.2 and III-D, Table I; DESIGN.md §5):

* every preset: l0 = 152 mm (base radius), l1 = 157 mm (crank), lp = 55 mm
  (end-effector radius), workspace centre at z0 = 0.30 m;
* Hunt-type: l2 = 0, beta = 0, gamma = 0 (the GII optimum of Table I: ld = 20 mm);
* HEXA: gamma != 0; Ergin's device: beta, gamma and l2 != 0 (values not printed);
* Octopod: the Hunt-type kinematics with four symmetric pairs of legs (L = 8);
* Octo (the prototype): l2 = 25.6 mm, beta = 0, gamma = 13.18 deg, ld = 20 mm,
  l0 = 160 mm, L = 8;
* mass m = 0.17 kg, inertia I = 3e-4 kg m^2 (Sec. III-B.3).

Our reading of Fig. 2 (the figure's exact definitions are not in the text; one rule,
used everywhere in distkin).  Legs come in L/2 mirror-symmetric pairs; pair k
(k = 0 .. L/2-1) sits at azimuth theta_k = 2 pi k / (L/2); leg i belongs to pair
i // 2 with side s = -1 (even i) or +1 (odd i).  With e = (cos theta_k, sin theta_k, 0),
t = (-sin theta_k, cos theta_k, 0) and z = (0, 0, 1):

* **ld** -- distance between the two legs of a pair, both at the base (crank pivots
  ``B = l0 e + s ld/2 t``) and at the end effector (before the gamma rotation).
* **beta** -- "angle at the base": each actuator axis of a pair is turned about the
  vertical by s*beta from the radial direction, ``a = Rz(s beta) e`` (beta = 0: the
  two axes of a pair are parallel and radial).  The crank swings in the plane normal
  to ``a``; at q = 0 it is horizontal and points away from the pair's centre,
  ``u = s z x a`` (= s t at beta = 0): the two cranks of a pair point in opposite
  directions, tangentially to the base circle.
* **l1** -- crank: tip ``C = B + l1 (cos q u + sin q z)``; q = 0 is horizontal, q > 0
  lifts the crank.
* **l2** -- the RRRS offset: the two passive revolute joints at the crank tip are
  l2 apart along the actuator axis, so the centre of the equivalent universal joint is
  ``D = C + l2 a`` (outwards, away from the base centre).  l2 = 0 gives the RSS leg.
* **gamma** -- "angle at the end effector": the two spherical joints of a pair are
  turned apart about the end-effector axis by ±gamma,
  ``p = Rz(s gamma) (lp e + s ld/2 t)`` in the end-effector frame.
* **l3** -- the distal link ``|P - D| = l3`` with ``P = x + R p``.  Not given in the
  paper; our rule (DESIGN.md §5): **at the workspace centre (0, 0, z0) with R = I each
  crank is horizontal** (q = 0), which fixes l3 (for beta = l2 = gamma = 0:
  l3 = sqrt((l0 - lp)^2 + l1^2 + z0^2) = 352.2 mm).  It is recomputed whenever a
  parameter is overridden, unless l3 itself is given.
* **IK branch**: of the two crank angles that close a leg, the one that is 0 at the
  workspace centre (sigma = +1 in :mod:`.symbolic`).

Why this reading.  The rule "crank horizontal at the centre" leaves the crank's
horizontal direction open.  Sec. II-A requires the whole 150 mm cube with rotations to
be reachable, and Table III reports finite capabilities over the whole Table II grid
(16^3 positions x 9^3 orientations, +-75 mm about z0, +-20 deg).  Of the readings we
measured that keep the cranks horizontal at the centre, only this one closes every
leg at every pose of that grid for all five presets (minimum reach margin > 0, cranks
within -78 .. +72 deg):

* actuator axes tangent to the base circle (``a = t``), cranks radially outwards
  (``u = e``, l3 = 393 mm): 85-92 % of the grid; at z0 - 75 mm the spherical joints
  come closer to the pivots than l3 - l1;
* the same axes, cranks radially inwards (``u = -e``, l3 = 306 mm, nearly vertical
  distal links): misses 70 poses of ``hexa`` and 4 of ``octo``;
* radial axes with the cranks of a pair pointing towards each other: misses poses of
  ``hexa``, ``ergin`` and ``octo`` at z0 - 75 mm.

The choice rests on that design requirement only, never on agreement with the numbers
of Tables III-IV.

Limitation.  distkin models the links as lines and checks no collisions.  With L = 8
and these dimensions (l1 + ld/2 > l0) the tangential cranks of neighbouring pairs
cross near the corners of the base square (at the centre pose the crank segments of
legs 0 and 7 of ``octopod`` and legs 1 and 2 of ``octo`` meet), so for the Octopod
and the Octo this reading is a kinematic model, not a buildable layout; for L = 6
the cranks are 20 mm or more apart at the centre pose.  The radially outward reading
is buildable and reaches a 50,000-pose sample of the grid with every preset for l3 of
about 313-357 mm, but its cranks are then not horizontal at the centre (the rule of
DESIGN.md §5).

Preset values the paper does not print, and our choice:

* ``hexa``  -- gamma = 30 deg (the upper end of Table I's range), beta = l2 = 0.
* ``ergin`` -- Ergin's device, which the Octo is based on (Sec. III-D): the Octo's
  l2 = 25.6 mm and gamma = 13.18 deg, with beta = 10 deg (the first non-zero step of
  Table I), l0 = 152 mm, L = 6.
* ``hunt``, ``octopod`` -- beta = gamma = l2 = 0, ld = 20 mm (Table I optimum).
* ``octo`` -- as printed (Sec. III-D).  ``octo`` and ``octopod`` differ from the
  paper's hardware in whatever Fig. 2 means differently from the rule above.
"""

from __future__ import annotations

import math

from ..errors import InputError
from .rss import RSSMechanism

__all__ = ["PRESETS", "preset", "PRESET_NAMES"]

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


def preset(name: str, **overrides) -> RSSMechanism:
    """The mechanism named ``name``, with parameters optionally overridden.

    Parameters
    ----------
    name : {"hexa", "hunt", "ergin", "octopod", "octo"}
    **overrides
        Any of ``legs, l0, l1, l2, l3, lp, ld, z0, beta, gamma, mass, inertia`` in SI
        units (m, rad, kg, kg m^2).  Unless ``l3`` is given it follows the
        horizontal-crank rule (module docstring).

    Returns
    -------
    RSSMechanism
        Frozen; ``name`` is the preset's name if nothing was overridden, else
        ``"<name>*"``.
    """
    if name not in PRESETS:
        raise InputError(f"expected a preset in {', '.join(map(repr, PRESETS))}, got {name!r}",
                         field="preset")
    allowed = set(PRESETS[name]) | {"l3"}
    bad = sorted(set(overrides) - allowed)
    if bad:
        raise InputError(f"unknown parameter(s) {', '.join(map(repr, bad))}; expected some of "
                         f"{', '.join(sorted(allowed))}", field="preset")
    params = dict(PRESETS[name])
    changed = {k: v for k, v in overrides.items() if k not in params or params[k] != v}
    params.update(overrides)
    label = name if not changed else f"{name}*"
    return RSSMechanism(name=label, **params)


def description(name: str) -> str:
    """One line describing a preset."""
    return _DESCRIPTIONS[name]
