"""``kind = "legs"`` with ``octahedral``: the prismatic platforms of Rojas et al. as leg
mechanisms (:func:`distkin.mechanisms.platforms.platform_mechanism`), so that every
analysis of a leg mechanism (the Octopod paper's indices, certified workspace, the
singularity tests) runs on them::

    [units]
    length = "cm"               # the Sec. VI example is unitless: cm is a choice
    angle = "deg"

    [mechanism]
    kind = "legs"
    name = "griffis_duffy"
    octahedral = { base = [[0,0,0], [6,"sqrt(108)",0], [12,0,0]],
                   platform = [[0,0,0], [6,0,0], [3,"sqrt(27)",0]] }
    # offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]   # the Δ 6-6 platform
    # approximation = { kind = "standard", delta = 1 }          # Fig. 2 (b) | (c) | (d)
    height = 17                 # home: the symmetric pose at this height (or home = [...])
    stroke = [14, 22]           # every leg's length range (length)
    force = 50                  # every actuator's force limit, N (a number: ±; or [min, max])
    leg_type = "SPS"            # or "UPS"
    mass = "0.17"               # kg
    inertia = "3e-4"            # kg m^2
    # origin = [3, 1.7, 0]      # end-effector origin in the platform frame (default: the
                                # mean of the platform joints)

At most one of ``offsets`` (:func:`distkin.delta.equivalent_platform`, Sec. V-VI) and
``approximation`` (:func:`distkin.delta.approximation`: ``kind`` "standard",
"stoughton_arai" or "griffis_duffy", ``delta`` a length); neither: the octahedral
manipulator itself (its FK then comes from the exact octic).  Leg k joins the base and
platform joints of the platform's leg k (docs/design.md §3 for the octahedral labels).
"""

from __future__ import annotations

from ..argcheck import as_table, check_keys, choice, exact_matrix, parse_vector, require
from ..errors import DistkinError, InputError
from ..exact import parse_float
from .legs_scene import parse_home
from .units import length_factor

__all__ = ["parse_platform_legs"]

_KEYS = {"kind", "name", "home", "height", "mass", "inertia", "route", "octahedral",
         "offsets", "approximation", "stroke", "force", "leg_type", "origin"}


def _float(v, fld):
    return parse_float(v, fld)


def _platform(table, field):
    octa = as_table(table["octahedral"], f"{field}.octahedral")
    check_keys(octa, {"base", "platform"}, f"{field}.octahedral")
    fo = f"{field}.octahedral"
    base = exact_matrix(require(octa, "base", fo), f"{fo}.base", rows=3, cols=3)
    plat = exact_matrix(require(octa, "platform", fo), f"{fo}.platform", rows=3, cols=3)
    if "offsets" in table and "approximation" in table:
        raise InputError("expected at most one of offsets and approximation, got both",
                         field=field)
    from ..delta import approximation, equivalent_platform
    try:
        if "offsets" in table:
            offs = parse_vector(table["offsets"], f"{field}.offsets", length=6)
            return equivalent_platform((base, plat), offs)
        if "approximation" in table:
            fa = f"{field}.approximation"
            a = as_table(table["approximation"], fa)
            check_keys(a, {"kind", "delta"}, fa)
            from ..delta.approximations import KINDS
            kind = choice(require(a, "kind", fa), f"{fa}.kind", KINDS)
            delta = parse_vector([require(a, "delta", fa)], f"{fa}.delta", length=1)[0]
            try:
                return approximation((base, plat), kind, delta)
            except DistkinError as exc:      # its own arguments: under approximation
                if exc.field in ("delta", "kind"):
                    raise exc.with_field(fa)
                raise
        from ..delta import octahedral_as_66
        return octahedral_as_66((base, plat))
    except DistkinError as exc:
        raise exc.with_field(field) if not (exc.field or "").startswith(field) else exc


def parse_platform_legs(table, units, field):
    """Parse a ``legs`` table with ``octahedral`` into a
    :class:`~distkin.mechanisms.kinematics.LegMechanism` (SI; module docstring)."""
    from ..mechanisms.platforms import platform_mechanism
    check_keys(table, _KEYS, field)
    unit = length_factor(units, f"{field}.octahedral")
    plat = _platform(table, field)
    if ("home" in table) == ("height" in table):
        raise InputError("expected exactly one of home and height, got "
                         f"{'both' if 'home' in table else 'neither'}", field=field)
    kw = {}
    if "home" in table:
        kw["home"] = parse_home(table["home"], units, f"{field}.home")
    else:
        kw["height"] = _float(table["height"], f"{field}.height")
    if "stroke" in table:
        s = table["stroke"]
        if not isinstance(s, list) or len(s) != 2:
            raise InputError(f"expected [min, max] lengths, got {s!r}", field=f"{field}.stroke")
        kw["stroke"] = tuple(_float(v, f"{field}.stroke[{i}]") for i, v in enumerate(s))
    if "force" in table:
        f = table["force"]
        kw["force"] = (tuple(_float(v, f"{field}.force[{i}]") for i, v in enumerate(f))
                       if isinstance(f, list) else _float(f, f"{field}.force"))
        if not isinstance(f, list) and not kw["force"] > 0:   # a number stands for ±force
            raise InputError(f"expected a positive force limit (a number stands for ±force; "
                             f"[min, max] for asymmetric limits), got {f!r} N",
                             field=f"{field}.force")
    if "origin" in table:
        kw["origin"] = tuple(float(x) for x in parse_vector(table["origin"],
                                                             f"{field}.origin", length=3))
    for k in ("mass", "inertia"):
        if k in table:
            kw[k] = _float(table[k], f"{field}.{k}")
    if "route" in table:
        from ..mechanisms.kinematics import ROUTES
        kw["route"] = choice(table["route"], f"{field}.route", ROUTES)
    kw["leg_type"] = choice(table.get("leg_type", "SPS"), f"{field}.leg_type", ("SPS", "UPS"))
    name = table.get("name", "platform66")
    if not isinstance(name, str):
        raise InputError(f"expected a name (text), got {name!r}", field=f"{field}.name")
    try:
        return platform_mechanism(plat, unit=unit, name=name, **kw)
    except DistkinError as exc:
        fld = exc.field or ""
        if fld.startswith("leg["):
            fld = {"range": "stroke", "limit": "force"}.get(fld.split(".")[-1], fld)
        exc.field = None
        raise exc.with_field(f"{field}.{fld}" if fld else field) from None
