"""Scene queries of the performance indices (mechanism kind ``rss``).

``performance`` — the study of Kühne et al., Sec. III-B/C (Tables III and IV, Figs. 5-7)::

    [units]
    length = "mm"
    angle = "deg"

    [[query]]
    type = "performance"
    devices = [                                  # default: the scene's mechanism
      { label = "Hunt-type", preset = "hunt", rotation = 20 },
      { label = "Octopod", preset = "octopod", rotation = 30, inner_rotation = 20 },
    ]
    grid = { half = 75, step = 10, rotation_step = 5 }   # Table II (the default)
    actuators = { nominal_torque = 2.5, stall_torque = 34.2, velocity = 51 }  # SI
    # prismatic legs: nominal_force, stall_force (N), speed (m/s); a leg's own effort
    # limit is its nominal effort (distkin.indices.actuators).  The figures of an
    # actuator type are given all together (the revolute ones default to the paper's
    # only when none is given) and only for a type some leg has
    scaling = [15, 15, 15, 1, 1, 1]              # ST (N, N, N, N·m, N·m, N·m)
    thresholds = { velocity = 1.0, acceleration = 9.81, force = 0.0 }          # SI
    sensitivity = "slice"                        # the paper's eqs. (14)/(16) | "projection" (Cardou)
    certify = true                               # Fig. 3: certify the 150 mm cube (rss; legs: the
                                                 # grid's cube) about home at its rotation
    certify_width = 18.75                        # its resolution (scene length unit)
    chunk_positions = 32                         # positions per resumable chunk (at most:
                                                 # a small grid gets 16 chunks or more)
    workers = 2                                  # local processes (1: in process)
    scheduler = "tcp://host:8786"                # optional: a dask.distributed cluster
    store = "sweeps/study"                       # chunk store (default: the cache)
    method = "fast"                              # the only tier of a sampled study (float64)

A grid is counted before anything is allocated: one device's grid of more than
:data:`MAX_GRID_POSES` (10⁸) poses or :data:`MAX_GRID_POSITIONS` (10⁶) positions is
refused (a ``design_sweep``'s: :data:`MAX_SWEEP_POSES`, 10⁷ poses, all in memory at
once), naming the grid, its counts and the limit; a long sweep shows a line with its
size and a progress bar.

A device without ``preset`` is the scene's own mechanism (``rss`` or ``legs``; e.g.
``{ label = "mine", rotation = 10 }`` beside the presets).
Each preset device takes any ``rss`` mechanism parameter (``l2 = 25.6``, ``gamma = 13.18``...)
in the scene's units, ``rotation`` (the ± range of the grid about every axis),
``inner_rotation`` (a smaller range also reduced separately: Table IV's GII is over
Table II's ±20°) and ``paper`` (the Table III/IV column to compare with; default the
preset's own, ``false`` for none).

``design_sweep`` — the GII optimisation over Table I with Stocco's culling::

    [[query]]
    type = "design_sweep"
    base = "hunt"
    l2 = [0, 30, 5]          # min, max, step (scene units); Table I by default
    beta = [0, 30, 10]
    gamma = [0, 30, 10]
    ld = [20, 40, 5]
    grid = { half = 75, step = 25, rotation = 20, rotation_step = 10 }
    algorithm = "both"       # culling | brute_force | both (and check they agree)
    unreachable = "zero"     # a pose a design misses scores σmin = 0 (the default: every
                             # design on the whole grid, Sec. III-B-2's "chosen workspace");
                             # "skip": each design on the poses it reaches (an optimum
                             # covering less than another design is flagged)
    scaling = [15, 15, 15, 1, 1, 1]   # ST (N, N, N, N·m, N·m, N·m), positive
    max_evaluations = 2000000000      # designs × poses allowed (the default limit)

The designs are applied to the ``base`` preset (its legs, l0, l1, lp, z0), never to the
scene's [mechanism] table: a [mechanism] other than the stock ``base`` preset gets a
warning saying what differs, and the report and its JSON ``mechanism`` block (SI, with a
``unit`` table) say which mechanism was swept.  The designs are counted before anything
is allocated: more than :data:`MAX_SWEEP_DESIGNS` (10⁴) designs, or more (design, pose)
evaluations than :data:`MAX_SWEEP_EVALUATIONS` (2·10⁹, above Table I × Table II) or the
query's ``max_evaluations``, is refused (exit 2) with the counts; a design with
coincident legs (l2 = β = γ = ld = 0) is refused, naming it.  The culling and the brute
force each show a progress bar.  "Table I optimum: reproduced" is only said when the
sweep's design (0, 0°, 0°, 20 mm) is the ``hunt`` preset and the grid holds it beside
other designs; otherwise "not applicable" with the reason (JSON: null and
``optimum_reproduced_reason``).

A sweep in which no design reaches any pose of the grid, or every design scores GII 0,
has no optimum: it is refused (exit 2) with the counts; equal GIIs at the optimum are
reported as a tie, never decided by the order of the designs.

``distkin sweep SCENE --scheduler ADDRESS`` runs a scene with its sweeps on a dask
cluster (or ``--workers N`` locally); the scene's own fields are the defaults.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...argcheck import (as_table, check_keys, choice, executor_fields, fast_only, positive_int,
                         require, scheduler_address)
from ...errors import InputError
from ...exact import parse_float
from ..mechanism_scene import length_slips, warn_slips
from ..query import register
from ..units import DEG, angle_value, degrees_hint, length_value, warn_radians
from ...indices.isotropy import ST_DEFAULT
from ...indices.study import ACTUATORS, PAPER_TABLE3
from ..design_report import (MAX_SWEEP_DESIGNS, MAX_SWEEP_EVALUATIONS,  # noqa: F401 (doc)
                             check_design_corners, check_design_count, check_range, grid_spec,
                             scene_mechanism_note, sweep_scaling)

__all__ = ["PerformanceQuery", "DesignSweepQuery"]


_RSS_KEYS = ("legs", "l0", "l1", "l2", "l3", "lp", "ld", "z0", "beta", "gamma", "mass",
             "inertia", "layout")


# ---------------------------------------------------------------------- parsing
def _num(value, field):
    return parse_float(value, field)


def _si_table(raw, field, defaults, extra=(), *, positive: bool = False):
    """A table of SI numbers, >= 0 (``positive``: > 0, as the actuator limits, whose
    zero makes every capability 0: the study refuses it too)."""
    t = as_table(raw, field)
    check_keys(t, set(defaults) | set(extra), field)
    out = dict(defaults)
    for k, v in t.items():
        x = _num(v, f"{field}.{k}")
        if not (x > 0 if positive else x >= 0):
            raise InputError(f"expected a {'positive' if positive else 'non-negative'} "
                             f"number, got {v!r}", field=f"{field}.{k}")
        out[k] = x
    return out


#: the largest pose grid of one device of a ``performance`` query: poses (the sweep's
#: time, about 10-50 µs each on one core) and positions (its memory: a hundred float64
#: per position, its chunk files)
MAX_GRID_POSES = 100_000_000
MAX_GRID_POSITIONS = 1_000_000
#: the largest pose grid of a ``design_sweep`` (its poses are held in memory at once, 48
#: bytes each, and every design is evaluated at each)
MAX_SWEEP_POSES = 10_000_000


def _show(value_si, units, angle):
    """An SI length or angle in the scene's unit, as text with the unit."""
    if angle:
        f = angle_value(1, units, "units")
        return f"{value_si / f:.6g} {units.angle}"
    return f"{value_si / length_value(1, units, 'units'):.6g} {units.length}"


def _check_rotation(rotation, units, field):
    """A grid's ± rotation range: finite, >= 0 and at most 180° (the Euler angles of a
    larger range wrap: -200° is 160°, the same orientations counted twice)."""
    if not (math.isfinite(rotation) and rotation >= 0):
        raise InputError(f"expected a non-negative rotation (the grid spans ±rotation), got "
                         f"{_show(rotation, units, True)}", field=field)
    if rotation > math.pi * (1 + 1e-12):
        raise InputError(f"expected a rotation of at most {_show(math.pi, units, True)} (the "
                         f"grid spans ±rotation about each axis; beyond it the Euler angles "
                         f"wrap onto the same orientations), got {_show(rotation, units, True)}",
                         field=field, hint=degrees_hint(rotation, units,
                                                        lambda a: a <= math.pi))


def _axis_count(half, step, units, field, half_key, step_key, angle=False):
    """The number of values -half, -half + step, ..., half of one grid axis (SI values),
    checked, before anything is allocated, in the scene's units and naming the key."""
    if not (math.isfinite(half) and half >= 0):
        raise InputError(f"expected a non-negative {half_key} (the grid spans ±{half_key}), "
                         f"got {_show(half, units, angle)}", field=f"{field}.{half_key}")
    if not (math.isfinite(step) and step > 0):
        raise InputError(f"expected a positive {step_key}, got {_show(step, units, angle)}",
                         field=f"{field}.{step_key}")
    n = 2 * half / step
    if not math.isfinite(n):               # a subnormal step: 2 half / step overflows
        raise InputError(f"expected a {step_key} with 2 × {half_key} / {step_key} finite, "
                         f"got 2 × {_show(half, units, angle)} / {_show(step, units, angle)}"
                         " (beyond float64)",
                         field=f"{field}.{step_key}")
    k = round(n)
    if abs(n - k) > 1e-9 * max(1.0, n):
        raise InputError(f"expected 2 × {half_key} to be a multiple of {step_key}, got 2 × "
                         f"{_show(half, units, angle)} / {_show(step, units, angle)} = {n:.6g}",
                         field=f"{field}.{step_key}")
    return int(k) + 1


def _grid(raw, units, field, centre, rotation, scale, *, max_poses=MAX_GRID_POSES,
          max_positions=MAX_GRID_POSITIONS):
    """The pose grid of a device: ``half``/``step`` about ``centre`` (the mechanism's
    home pose (6,), m and rad; a number: (0, 0, z0, 0, 0, 0)).  Its size is counted
    before anything is allocated: more than ``max_poses`` poses or ``max_positions``
    positions is refused, naming the grid, its counts and the limit; a ``half`` beyond
    :data:`~distkin.mechanisms.description.MAX_REACH` times the mechanism's length
    ``scale`` (m) too, as a pose query's translation (QA R 8)."""
    from ...mechanisms.description import MAX_REACH
    from ...indices.workspace import axis_values, PoseGrid
    c = np.zeros(6)
    if np.ndim(centre) == 0:
        c[2] = centre
    else:
        c[:] = centre
    t = as_table(raw if raw is not None else {}, field)
    check_keys(t, {"half", "step", "rotation", "rotation_step"}, field)
    half = length_value(t["half"], units, f"{field}.half") if "half" in t else 0.075
    step = length_value(t["step"], units, f"{field}.step") if "step" in t else 0.010
    rstep = angle_value(t["rotation_step"], units, f"{field}.rotation_step") \
        if "rotation_step" in t else 5 * DEG
    if "rotation" in t:
        rotation = angle_value(t["rotation"], units, f"{field}.rotation")
    _check_rotation(rotation, units, f"{field}.rotation")
    written = [k for k in ("rotation", "rotation_step") if k in t]
    warn_radians([rotation / angle_value(1, units, field) if k == "rotation" else
                  rstep / angle_value(1, units, field) for k in written], units,
                 f"{field}.{' and '.join(written)}")
    if half > MAX_REACH * scale:          # first: 2 half / step may overflow to inf
        raise InputError(f"expected a half of at most {_show(MAX_REACH * scale, units, False)} "
                         f"({MAX_REACH:g} x the mechanism's length scale; no pose of the "
                         f"device lies farther), got {_show(half, units, False)}",
                         field=f"{field}.half",
                         hint=f"a unit slip? the scene's [units] length is \"{units.length}\"")
    nt = _axis_count(half, step, units, field, "half", "step")
    nr = _axis_count(rotation, rstep, units, field, "rotation", "rotation_step", angle=True) \
        if rotation > 0 else 1
    positions, orientations = nt ** 3, nr ** 3
    if positions * orientations > max_poses or positions > max_positions:
        what = ("poses" if positions * orientations > max_poses else "positions")
        limit = max_poses if what == "poses" else max_positions
        raise InputError(
            f"expected at most {limit:,} {what} in the grid, got {nt}³ = {positions:,} "
            f"positions × {nr}³ = {orientations:,} orientations = "
            f"{positions * orientations:,} poses (half {_show(half, units, False)}, step "
            f"{_show(step, units, False)}, rotation ±{_show(rotation, units, True)}, "
            f"rotation_step {_show(rstep, units, True)})", field=field,
            hint="a larger step or rotation_step, or a smaller half or rotation")
    tr = axis_values(-half, half, step, f"{field}.step")
    rr = axis_values(-rotation, rotation, rstep, f"{field}.rotation_step") if rotation > 0 \
        else np.zeros(1)
    return PoseGrid(*(tuple(c[i] + (tr if i < 3 else rr)) for i in range(6)))


def grid_slips(raw, units, field, scale) -> list[str]:
    """A grid's ``half`` and ``step`` as written that are more than
    :data:`~distkin.mechanisms.presets.SLIP_RATIO` times off the device's length scale
    ``scale`` (m; ``mech.length_scale``, lp = 55 mm for the presets): likely unit
    slips, one line each (:func:`~distkin.app.mechanism_scene.length_slips`, the test and
    words of the mechanism overrides).  A grid of ``half = 0.025, step = 0.025`` in a mm
    scene (25 mm meant) ran silently and reported a dexterous workspace of 0 cm³.  Call
    it after :func:`_grid` has checked the values; the step of a one-position grid
    (half 0) is not used and not checked."""
    t = as_table(raw if raw is not None else {}, field)
    checks = []
    half = length_value(t["half"], units, f"{field}.half") if "half" in t else None
    for key in ("half", "step"):
        if key in t and not (key == "step" and half == 0):
            checks.append((f"{field}.{key}", t[key],
                           half if key == "half" else length_value(t[key], units,
                                                                   f"{field}.{key}"),
                           scale, "the device's length scale"))
    return length_slips(checks, units)




def _check_actuators(given, devices, field):
    """The keys of the ``actuators`` table against the devices' legs: a key of an
    actuator type that no device has would be ignored (refused, naming it); a type whose
    figures are given in part would be completed silently (refused, naming the missing
    key).  The revolute figures default to the paper's (Sec. III-B-3) only when none is
    given; a leg's own ``limit`` stands for its nominal effort."""
    from ...indices.actuators import KEY_UNITS, PRISMATIC_KEYS, REVOLUTE_KEYS
    present, own = set(), {False: True, True: True}   # own: every leg of the type has a limit
    for d in devices:
        legs = getattr(d.mech, "leg_table", None)
        for i in range(d.mech.L):
            pris = bool(legs[i].prismatic) if legs is not None else False
            present.add(pris)
            own[pris] &= legs is not None and legs[i].limit is not None
    labels = ", ".join(d.label for d in devices)
    for pris, keys in ((False, REVOLUTE_KEYS), (True, PRISMATIC_KEYS)):
        kind, other = ("prismatic", "revolute") if pris else ("revolute", "prismatic")
        mine = [k for k in keys if k in given]
        if not mine:
            continue
        if pris not in present:
            raise InputError(f"expected only figures of the legs' actuators ("
                             f"{', '.join(PRISMATIC_KEYS if not pris else REVOLUTE_KEYS)}), "
                             f"got {mine[0]}: a {kind} actuator's figure, and every leg of "
                             f"{labels} is {other}", field=f"{field}.{mine[0]}")
        need = [k for k in keys if not (k == keys[0] and own[pris])]
        missing = [k for k in need if k not in given]
        if missing:
            default = (" (the paper's figures, 2.5 N·m, 34.2 N·m and 51 rad/s, are the "
                       "defaults only when no revolute figure is given)" if not pris else "")
            raise InputError(f"expected {missing[0]} ({KEY_UNITS[missing[0]]}) beside "
                             f"{', '.join(mine)} for the {kind} legs, got nothing{default}",
                             field=f"{field}.{missing[0]}")


@dataclass(frozen=True)
class _DeviceSpec:
    label: str
    mech: object
    rotation: float
    inner: float | None
    paper: str | None


@dataclass(frozen=True)
class _PerfParams:
    devices: tuple
    grid_raw: object
    units: object
    actuators: tuple
    scaling: tuple
    thresholds: tuple
    chunk_positions: int
    workers: int | None
    scheduler: str | None
    store: str | None
    route: str
    plot_device: str | None
    sensitivity: str = "slice"
    certify: bool = False
    certify_width: float = 0.01875


def _parse_device(d, mechanism, units, field):
    from ..mechanism_scene import parse_rss
    from ...mechanisms.presets import PRESETS
    d = as_table(d, field)
    check_keys(d, {"label", "preset", "rotation", "inner_rotation", "paper", *_RSS_KEYS},
               field)
    label = require(d, "label", field)
    if not isinstance(label, str) or not label:
        raise InputError(f"expected a non-empty label, got {label!r}", field=f"{field}.label")
    if "preset" not in d:                      # the scene's own mechanism (rss or legs)
        extra = sorted(k for k in _RSS_KEYS if k in d)
        if extra:
            raise InputError(f"expected a preset with the parameters {extra} (without one "
                             "the device is the scene's mechanism, as it is)",
                             field=f"{field}.preset")
        mech, mtable = mechanism, {}
    else:
        mtable = {"kind": "rss", "preset": d["preset"]}
        mtable.update({k: d[k] for k in _RSS_KEYS if k in d})
        mech = parse_rss(mtable, units, field)
    rotation = angle_value(d["rotation"], units, f"{field}.rotation") if "rotation" in d \
        else 20 * DEG
    _check_rotation(rotation, units, f"{field}.rotation")
    inner = angle_value(d["inner_rotation"], units, f"{field}.inner_rotation") \
        if "inner_rotation" in d else (20 * DEG if rotation > 20 * DEG + 1e-12 else None)
    written = [k for k in ("rotation", "inner_rotation") if k in d]
    warn_radians([(rotation if k == "rotation" else inner) / angle_value(1, units, field)
                  for k in written], units, f"{field}.{' and '.join(written)}")
    if inner is not None and inner > rotation + 1e-12:
        raise InputError(f"expected inner_rotation <= rotation, got {d.get('inner_rotation')!r}",
                         field=f"{field}.inner_rotation")
    paper = d.get("paper", mtable["preset"] if len(mtable) == 2 else None)
    if not mtable and "paper" not in d:
        paper = mechanism.name if mechanism.name in PRESETS else None
    if paper is False:
        paper = None
    if paper is not None and paper not in PRESETS:
        raise InputError(f"expected a Table III column ({', '.join(PRESETS)}) or false, got "
                         f"{paper!r}", field=f"{field}.paper")
    return _DeviceSpec(label, mech, rotation, inner, paper)


def _check_legs_cost(L, field):
    """The study's exact enumerations per pose, counted before the sweep: C(L, 5) facet
    normals (worst cases), C(L, 3)·2^(L−3) slice-vertex candidates (sensitivities) and
    2^L box vertices (the velocity set's best case), each at most
    :data:`~distkin.indices.zonotope.MAX_CANDIDATES`; above it an InputError names L."""
    from math import comb

    from ...indices.zonotope import check_enumeration, vertex_candidates
    for count, what in ((comb(L, 5), "facet normals (C(L, 5))"),
                        (vertex_candidates(L, 3), "slice-vertex candidates (C(L, 3)·2^(L−3))"),
                        (2 ** L, "box vertices (2^L)")):
        check_enumeration(count, L, what, field=field)


@register("performance", mechanisms=("rss", "legs"),
          summary="worst-case output capabilities, sensitivities, GII and dexterous "
                  "workspace over a pose grid (Kühne et al., Tables III-IV)")
class PerformanceQuery:
    @staticmethod
    def parse(table, mechanism, units, field):
        check_keys(table, {"type", "devices", "grid", "actuators", "scaling", "thresholds",
                           "chunk_positions", "workers", "scheduler", "store", "route",
                           "plot_device", "sensitivity", "certify", "certify_width", "method"},
                   field)
        fast_only(table, field, "the sampled study of Tables III-IV",
                  "certify = true adds the certified singularity-free workspace (Fig. 3), "
                  "the certify_workspace query proves regions, and the jacobian and "
                  "inverse_kinematics queries take method = 'precise' or 'certified' at "
                  "given poses")
        if "devices" in table:
            raw = table["devices"]
            if not isinstance(raw, list) or not raw:
                raise InputError(f"expected a non-empty list of device tables, got {raw!r}",
                                 field=f"{field}.devices")
            devices = tuple(_parse_device(d, mechanism, units, f"{field}.devices[{i}]")
                            for i, d in enumerate(raw))
        else:
            name = mechanism.name
            devices = (_DeviceSpec(name, mechanism, 20 * DEG, None,
                                   name if name in PAPER_TABLE3 else None),)
        labels = [d.label for d in devices]
        if len(set(labels)) != len(labels):
            raise InputError(f"expected distinct device labels, got {labels}",
                             field=f"{field}.devices")
        for d in devices:                      # validate the grid now
            _grid(table.get("grid"), units, f"{field}.grid", d.mech.home, d.rotation,
                  d.mech.length_scale)
        warn_slips(line for d in devices for line in grid_slips(
            table.get("grid"), units, f"{field}.grid", d.mech.length_scale))
        from ...indices.actuators import PRISMATIC_KEYS, leg_limits
        act = _si_table(table.get("actuators", {}), f"{field}.actuators", ACTUATORS,
                        PRISMATIC_KEYS, positive=True)
        _check_actuators(table.get("actuators", {}), devices, f"{field}.actuators")
        for i, d in enumerate(devices):        # every leg has its limits, in its units
            leg_limits(d.mech, act, f"{field}.actuators")
            _check_legs_cost(d.mech.L, f"{field}.devices[{i}]" if "devices" in table
                             else "mechanism")
        thr = _si_table(table.get("thresholds", {}), f"{field}.thresholds",
                        {"velocity": 1.0, "acceleration": 9.81, "force": 0.0})
        sc = table.get("scaling", list(ST_DEFAULT))
        if not isinstance(sc, list) or len(sc) != 6:
            raise InputError(f"expected 6 scaling factors, got {sc!r}", field=f"{field}.scaling")
        sc = tuple(_num(v, f"{field}.scaling[{i}]") for i, v in enumerate(sc))
        if not all(v > 0 for v in sc):
            raise InputError(f"expected positive scaling factors, got {sc}",
                             field=f"{field}.scaling")
        cp = positive_int(table.get("chunk_positions", 32), f"{field}.chunk_positions")
        workers, sched, store = executor_fields(table, field)
        if sched is not None:
            scheduler_address(sched, f"{field}.scheduler")
        route = choice(table.get("route", "kernels"), f"{field}.route", ("kernels", "numpy"))
        pd = table.get("plot_device")
        if pd is not None and pd not in labels:
            raise InputError(f"expected one of the device labels {labels}, got {pd!r}",
                             field=f"{field}.plot_device")
        from ...indices.sensitivity import SENSITIVITY_MODES
        sens = choice(table.get("sensitivity", "slice"), f"{field}.sensitivity",
                      SENSITIVITY_MODES)
        cert = table.get("certify", False)
        if not isinstance(cert, bool):
            raise InputError(f"expected true or false, got {cert!r}", field=f"{field}.certify")
        cw = length_value(table["certify_width"], units, f"{field}.certify_width") \
            if "certify_width" in table else 0.01875
        if not cw > 0:
            raise InputError(f"expected a positive width, got {table.get('certify_width')!r}",
                             field=f"{field}.certify_width")
        return _PerfParams(devices, table.get("grid"), units, tuple(act.items()), sc,
                           tuple(thr.items()), cp, workers, sched, store, route, pd, sens,
                           cert, cw)

    @staticmethod
    def run(p, scene, ctx):
        from ..study_report import performance_report
        return performance_report(p, scene, ctx, grid_of=lambda d: _grid(
            p.grid_raw, p.units, "grid", d.mech.home, d.rotation, d.mech.length_scale),
            store_of=lambda label: ctx.store_dir(p.store, scene, "performance") / _slug(label),
            executor=lambda: ctx.executor(p.workers, p.scheduler))


def _slug(s):
    return "".join(ch if ch.isalnum() else "_" for ch in s).strip("_").lower() or "device"


# ----------------------------------------------------------------- design sweep
_TABLE1 = {"l2": (0.0, 0.030, 0.005), "beta": (0.0, 30 * DEG, 10 * DEG),
           "gamma": (0.0, 30 * DEG, 10 * DEG), "ld": (0.020, 0.040, 0.005)}


@dataclass(frozen=True)
class _SweepParams:
    space: object
    grid: object
    algorithm: str
    unreachable: str
    scaling: tuple
    workers: int | None
    scheduler: str | None
    store: str | None
    designs_per_chunk: int
    grid_spec: dict | None = None      # half, step, rotation, rotation_step (SI) as given
    scene_mechanism: str | None = None  # why the scene's [mechanism] is not the swept one


@register("design_sweep", mechanisms=("rss",),
          summary="GII design sweep over Table I with Stocco's culling (and brute force)")
class DesignSweepQuery:
    @staticmethod
    def parse(table, mechanism, units, field):
        from ...mechanisms.presets import PRESETS
        from ...indices.design import DesignSpace
        from ...indices.workspace import axis_values
        check_keys(table, {"type", "base", "l2", "beta", "gamma", "ld", "grid", "algorithm",
                           "leg_length", "baseline", "unreachable", "scaling", "workers",
                           "scheduler", "store", "designs_per_chunk", "method",
                           "max_evaluations"}, field)
        fast_only(table, field, "the GII design sweep of Table I",
                  "the certify_workspace query proves the regularity of one design's region")
        base = choice(table.get("base", "hunt"), f"{field}.base", tuple(PRESETS))
        baseline = choice(table.get("baseline", "ergin"), f"{field}.baseline", tuple(PRESETS))
        ranges, slips = {}, []
        for name, default in _TABLE1.items():
            if name in table:
                r = table[name]
                if not isinstance(r, list) or len(r) != 3:
                    raise InputError(f"expected [min, max, step], got {r!r}",
                                     field=f"{field}.{name}")
                conv = length_value if name in ("l2", "ld") else angle_value
                lo, hi, st = (conv(v, units, f"{field}.{name}[{i}]") for i, v in enumerate(r))
                check_range(name, lo, hi, st, units, f"{field}.{name}")
                if name in ("l2", "ld"):           # its largest value against Table I's
                    slips += length_slips([(f"{field}.{name}[1]", r[1], hi, default[1],
                                            f"Table I's largest {name}")], units)
            else:
                lo, hi, st = default
            ranges[name] = (lo, hi, st)
        max_eval = positive_int(table.get("max_evaluations", MAX_SWEEP_EVALUATIONS),
                                f"{field}.max_evaluations")
        check_design_count(ranges, units, field)      # before any value is allocated
        values = [(name, tuple(float(v) for v in (
            axis_values(lo, hi, st, f"{field}.{name}") if hi > lo else np.array([lo]))))
            for name, (lo, hi, st) in ranges.items()]
        leg = choice(table.get("leg_length", "constant_sum"), f"{field}.leg_length",
                     ("constant_sum", "reading"))
        space = DesignSpace(base, tuple(values), leg, baseline)
        check_design_corners(space, units, field)
        g = as_table(table.get("grid", {}), f"{field}.grid")
        rot = angle_value(g["rotation"], units, f"{field}.grid.rotation") if "rotation" in g \
            else 20 * DEG
        from ...mechanisms import preset
        grid = _grid(g, units, f"{field}.grid", preset(base).z0, rot,
                     preset(base).length_scale, max_poses=MAX_SWEEP_POSES,
                     max_positions=MAX_SWEEP_POSES)
        warn_slips(slips + grid_slips(g, units, f"{field}.grid", preset(base).length_scale))
        n_designs = math.prod(len(v) for _, v in values)
        if n_designs * grid.size > max_eval:
            limit = ("the default limit MAX_SWEEP_EVALUATIONS"
                     if "max_evaluations" not in table else "max_evaluations")
            raise InputError(
                f"expected at most {max_eval:,} (design, pose) evaluations ({limit}), got "
                f"{n_designs:,} designs × {grid.size:,} poses = {n_designs * grid.size:,} "
                f"({' × '.join(f'{len(v)} {n}' for n, v in values)} designs; brute force "
                "evaluates every design at every pose)", field=field,
                hint=f"larger steps in the ranges or the grid, or max_evaluations = "
                     f"{n_designs * grid.size} in the query to run it (about 6 µs per "
                     "evaluation and core)")
        gspec = grid_spec(g, units, f"{field}.grid", rot)
        algorithm = choice(table.get("algorithm", "both"), f"{field}.algorithm",
                           ("culling", "brute_force", "both"))
        unreachable = choice(table.get("unreachable", "zero"), f"{field}.unreachable",
                             ("skip", "zero"))
        sc = sweep_scaling(table.get("scaling", list(ST_DEFAULT)), f"{field}.scaling")
        workers, sched, store = executor_fields(table, field)
        if sched is not None:
            scheduler_address(sched, f"{field}.scheduler")
        dpc = positive_int(table.get("designs_per_chunk", 8), f"{field}.designs_per_chunk")
        return _SweepParams(space, grid, algorithm, unreachable, sc, workers, sched, store,
                            dpc, gspec, scene_mechanism_note(mechanism, base, units))

    @staticmethod
    def run(p, scene, ctx):
        from ..study_report import design_sweep_report
        return design_sweep_report(p, scene, ctx,
                                   store=ctx.store_dir(p.store, scene, "design_sweep"),
                                   executor=lambda: ctx.executor(p.workers, p.scheduler))
