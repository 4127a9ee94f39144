"""Scene query ``certify_workspace`` (mechanism kind ``rss``): the certified
singularity-free workspace of :mod:`.boxes` over a region of poses::

    [units]
    length = "mm"
    angle = "deg"

    [[query]]
    type = "certify_workspace"
    method = "certified"                   # the only method: every box is a proof
    region = { lower = [-75, -75, 225, 0, 0, 0], upper = [75, 75, 375, 0, 0, 0] }
    min_width = 9.375                      # resolution of x, y, z (length unit)
    min_angle = 5                          # resolution of rx, ry, rz (angle unit)
    form = "quadratic64"                   # | quadratic | affine | centred | plain | auto
    split = 2                              # initial chunks per varying coordinate
    max_boxes = 200000                     # box evaluations per chunk
    tighten = 4096                         # box evaluations for a sharper σmin bound (0: off)
    workers = 2                            # local processes (default 1: in process)
    scheduler = "tcp://host:8786"          # optional: a dask.distributed cluster
    store = "sweeps/certify"               # chunk store (default: the cache)

``region`` holds x, y, z (absolute, length unit) and the rotation parameters rx, ry, rz
(angle unit, R = Rz Ry Rx); a coordinate with ``lower == upper`` is fixed; a rotation
span is at most 360° (2π rad).  Default: the
paper's 150 mm cube about (0, 0, z0) at zero rotation (Kühne et al., Table II, Fig. 3)
for an ``rss`` mechanism; a ``legs`` mechanism must give its region.
``min_width`` defaults to 1/16 of the largest positional extent, ``min_angle`` to 1/8 of
the largest rotational extent.

Like the indices sweeps (:mod:`distkin.app.queries.indices`), the region runs as resumable
chunks (an interrupted run continues where it stopped), on a local process pool or a dask
cluster, with a progress bar; ``distkin sweep SCENE --workers N --scheduler ADDRESS
--store DIR`` overrides the scene's fields.

``sigma_lower_min`` is a certified lower bound of σmin(Jx) over every regular box: the
boxes of the classification with the weakest bounds are bisected and certified again
(:mod:`distkin.certify.tighten`, at most ``tighten`` boxes; ``sigma_lower_min_boxes`` is
the minimum of the classification's own bounds).

The JSON result is in SI (the text is in the scene's units, volumes too: cm^3 deg^3 for
a 6-D region of a cm, deg scene, :func:`scene_volume`): volumes over the varying
coordinates in ``volume_unit`` (m^3, or m^3 rad^3 for the 6-D region), with fractions of ``total_volume``, and
``boxes`` (corners in m and rad, a status code per box, see ``boxes.legend``), and
``store``, the chunk store's folder (the default one, under the user cache, holds a
sub-folder per region definition: :func:`distkin.runstore.keyed_store`).  A single pose
(no coordinate varies) has no volume: ``single_pose`` is true, ``verdict`` its status,
and the volumes, fractions and ``volume_unit`` are null (``verdict`` is null for a
region).  ``warnings`` holds the report's warnings (a region entirely unreachable and
tiny or huge against the mechanism: a likely unit slip).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...argcheck import (as_table, check_keys, choice, executor_fields, positive_int,
                        positive_number, scheduler_address)
from ...errors import InputError
from ...exact import parse_float
from ..query import Outcome, register
from ..units import display_length
from ...certify.boxes import STATUS_NAMES, UNREACHABLE

__all__ = ["CertifyWorkspaceQuery", "certificate_text", "certificate_json", "scene_volume",
           "single_pose_verdict", "unit_slip_warning", "ROTATION_SPAN_MAX"]

_FIELDS = {"type", "method", "region", "min_width", "min_angle", "form", "split",
           "max_boxes", "tighten", "workers", "scheduler", "store"}


def _vector(value, field):
    if not isinstance(value, list) or len(value) != 6:
        raise InputError(f"expected 6 numbers [x, y, z, rx, ry, rz], got {value!r}", field=field)
    return [parse_float(v, f"{field}[{i}]") for i, v in enumerate(value)]


@dataclass(frozen=True)
class _Params:
    lower: tuple
    upper: tuple
    min_width: tuple
    form: str
    split: int
    max_boxes: int
    tighten: int
    workers: int | None
    scheduler: str | None
    store: str | None
    length_unit: str
    angle_unit: str


def _check_rotation_span(lower, upper, units, af, field):
    """Refuse a rotation span above 2π (QA: rx over ±1e12° was accepted, its "volume"
    counting every orientation billions of times), naming the coordinate and giving the
    span in the scene's angle unit."""
    for k in range(3, 6):
        span = float(upper[k] - lower[k])
        if span > ROTATION_SPAN_MAX:
            raise InputError(
                f"expected a span of r{'xyz'[k - 3]} (upper[{k}] - lower[{k}]) of at most "
                f"{2 * math.pi / af:.6g} {units.angle} (2π rad: "
                f"a wider span counts orientations more than once), got "
                f"{span / af:.6g} {units.angle} ({lower[k] / af:.6g}..{upper[k] / af:.6g} "
                f"{units.angle})", field=f"{field}.region.upper[{k}]")


#: the widest rotation span of a region (rad): 2π, with room for the rounding of 360°
ROTATION_SPAN_MAX = 2 * math.pi * (1 + 1e-12)


@register("certify_workspace", mechanisms=("rss", "legs"),
          summary="certified singularity-free workspace: interval branch-and-prune of a "
                  "region of poses (regular / singular / undecided boxes, Fig. 3 analogue)")
class CertifyWorkspaceQuery:
    @staticmethod
    def parse(table, mechanism, units, field):
        from ..units import angle_factor, length_factor
        from ...certify.workspace import WORKSPACE_FORMS
        check_keys(table, _FIELDS, field)
        method = table.get("method", "certified")
        if method != "certified":
            raise InputError(f"expected method = 'certified' (certify_workspace only proves; "
                             f"for sampled indices use the 'performance' query), got {method!r}",
                             field=f"{field}.method")
        lf, af = length_factor(units, field), angle_factor(units)
        scale = np.array([lf] * 3 + [af] * 3)
        if "region" in table:
            reg = as_table(table["region"], f"{field}.region")
            check_keys(reg, {"lower", "upper"}, f"{field}.region")
            for k in ("lower", "upper"):
                if k not in reg:
                    raise InputError(f"missing required field {k!r}", field=f"{field}.region.{k}")
            lower = np.array(_vector(reg["lower"], f"{field}.region.lower")) * scale
            upper = np.array(_vector(reg["upper"], f"{field}.region.upper")) * scale
        else:
            if mechanism.kind != "rss":
                raise InputError("expected a region for a legs mechanism (the default, the "
                                 "paper's 150 mm cube, belongs to its devices), got none",
                                 field=f"{field}.region")
            h = 0.075
            lower = np.array([-h, -h, mechanism.z0 - h, 0, 0, 0])
            upper = np.array([h, h, mechanism.z0 + h, 0, 0, 0])
        if not np.all(np.isfinite(lower)) or not np.all(np.isfinite(upper)) or \
                np.any(upper < lower):
            raise InputError(f"expected finite bounds with lower <= upper, got lower="
                             f"{(lower / scale).tolist()}, upper={(upper / scale).tolist()} "
                             f"(x, y, z in {units.length}, rx, ry, rz in {units.angle})",
                             field=f"{field}.region")
        from .mechanisms import check_pose_units      # float64-meaningless corners (QA R 8)
        check_pose_units(np.vstack([lower, upper]), units,
                         [f"{field}.region.lower", f"{field}.region.upper"],
                         mechanism.length_scale)
        _check_rotation_span(lower, upper, units, af, field)
        ext = upper - lower
        pos_ext, rot_ext = float(ext[:3].max()), float(ext[3:].max())
        if "min_width" in table:
            mw = positive_number(table["min_width"], f"{field}.min_width") * lf
        else:
            mw = pos_ext / 16 if pos_ext > 0 else 1.0
        if "min_angle" in table:
            ma = positive_number(table["min_angle"], f"{field}.min_angle") * af
        else:
            ma = rot_ext / 8 if rot_ext > 0 else 1.0
        form = choice(table.get("form", "quadratic64"), f"{field}.form", WORKSPACE_FORMS)
        split = positive_int(table.get("split", 2), f"{field}.split")
        max_boxes = positive_int(table.get("max_boxes", 200_000), f"{field}.max_boxes")
        tighten = positive_int(table.get("tighten", 4096), f"{field}.tighten", minimum=0)
        nvary = int(np.sum(ext > 0))
        if split ** nvary > 100_000:
            raise InputError(f"expected at most 100000 initial chunks, got split**{nvary} = "
                             f"{split ** nvary}", field=f"{field}.split")
        workers, sched, store = executor_fields(table, field)
        if sched is not None:
            scheduler_address(sched, f"{field}.scheduler")
        return _Params(tuple(lower), tuple(upper), (mw,) * 3 + (ma,) * 3, form, split,
                       max_boxes, tighten, workers, sched, store, units.length, units.angle)

    @staticmethod
    def run(p, scene, ctx):
        from ...certify.workspace import certify_workspace
        mech = scene.mechanism
        store = ctx.store_dir(p.store, scene, "certify_workspace")
        with ctx.executor(p.workers if p.workers is not None else 1, p.scheduler) as ex:
            cert = certify_workspace(mech, p.lower, p.upper, p.min_width, form=p.form,
                                     split=p.split, store=store, executor=ex,
                                     progress=ctx.progress, max_boxes=p.max_boxes,
                                     tighten=p.tighten)
        result = certificate_json(cert, p.length_unit)
        result["store"] = cert.store
        for line in result["warnings"]:
            ctx.warn(line)
        text = certificate_text(cert, p.length_unit, p.angle_unit)

        def plot(stem):
            from ...certify.plot import plot_certificate
            return [plot_certificate(cert, Path(stem), length_unit=p.length_unit,
                                     angle_unit=p.angle_unit)]
        return Outcome(result, text, plot)



#: what a certificate of a mechanism with revolute joint ranges covers (QA Q 2 said they
#: were not part of it; since the arb kernel ``ranges`` they are: a box is reachable only
#: where every crank is inside its range, :func:`distkin.certify.intervals.margins`)
RANGES_CHECKED = ("revolute joint ranges (a leg's `range`) are part of this certificate: "
                  "a box is reachable only where every crank angle is strictly inside its "
                  "range (range margin rho^2 (cos(q - m) - cos w) > 0 over the box, m and "
                  "w the range's middle and half-width; a full turn is no limit)")
#: what it does cover: a prismatic leg's stroke is its reach margin (QA V 7: the note
#: above was printed for prismatic strokes too, which decide the classification)
STROKES_CHECKED = ("prismatic strokes (a leg's `range`) are part of this certificate: a "
                   "box is reachable only where every stroke holds (reach margin "
                   "(q - qmin)(qmax - q) >= 0 over the box)")


def _ranges_note(mech) -> str | None:
    """What the certificate says about the legs' joint ranges (None: no leg has one)."""
    legs = [leg for leg in (getattr(mech, "leg_table", None) or ())
            if getattr(leg, "range", None) is not None]
    said = ([RANGES_CHECKED] if any(not leg.prismatic for leg in legs) else []) + \
        ([STROKES_CHECKED] if any(leg.prismatic for leg in legs) else [])
    return "; ".join(said) or None


def single_pose_verdict(cert) -> str:
    """The status of a region that is a single pose (its one box): ``regular``, ...
    (``a / b`` should a pose ever lie in boxes of two statuses; ``no box``)."""
    names = [name for code, name in STATUS_NAMES.items() if np.any(cert.status == code)]
    return " / ".join(names) or "no box"


def _mechanism_size(mech) -> float:
    """The mechanism's size (m): the larger of its length scale and the distance of its
    home pose from the base origin."""
    home = getattr(mech, "home", None)
    far = float(np.linalg.norm(np.asarray(home, dtype=float)[:3])) if home is not None else 0.0
    return max(float(mech.length_scale), far)


def unit_slip_warning(cert, length_unit: str = "m") -> str | None:
    """A warning when every box of the region is unreachable and the region lies within
    1/:data:`~distkin.app.mechanism_scene.SLIP_RATIO` of the mechanism's size of the base
    origin, or farther than that many times its size (QA: a region written in m in a mm
    scene was "unreachable 100 %" without a word); None otherwise."""
    from ..mechanism_scene import SLIP_RATIO
    if not len(cert.status) or not np.all(cert.status == UNREACHABLE):
        return None
    size = _mechanism_size(cert.mechanism)
    lo, hi = cert.lower[:3], cert.upper[:3]
    far = float(np.linalg.norm(np.maximum(np.abs(lo), np.abs(hi))))
    near = float(np.linalg.norm(np.clip(0.0, lo, hi)))
    lf, lu = display_length(length_unit)
    if far < size / SLIP_RATIO:
        where = (f"lies within {far * lf:.3g} {lu} of the base origin, under "
                 f"1/{SLIP_RATIO:g} of the mechanism's size")
    elif near > size * SLIP_RATIO:
        where = (f"lies {near * lf:.3g} {lu} or farther from the base origin, over "
                 f"{SLIP_RATIO:g} x the mechanism's size")
    else:
        return None
    return (f"every box is unreachable and the region {where} ({size * lf:.3g} {lu}: the "
            f"larger of its length scale and its home's distance from the base origin): "
            f"a region written in another unit? the scene's [units] length is \"{lu}\"")


def _range_text(a: float, b: float) -> str:
    """``a..b`` with enough significant digits (4 at least) to tell a from b (QA: a z
    range 300..300.001 mm was printed 300..300)."""
    for d in range(4, 18):
        sa, sb = f"{a:.{d}g}", f"{b:.{d}g}"
        if a == b or sa != sb:
            return f"{sa}..{sb}"
    return f"{a!r}..{b!r}"


def certificate_json(cert, length_unit: str = "m") -> dict:
    """The JSON result of a :class:`.workspace.WorkspaceCertificate` (SI; ``length_unit``,
    the scene's, is the unit of the words of ``warnings``, as in the text)."""
    s = cert.summary()
    out = {"mechanism": cert.mechanism.name, "legs": cert.mechanism.L,
           "method": "certified", "form": cert.form,
           "region": {"lower": cert.lower.tolist(), "upper": cert.upper.tolist(),
                      "units": "m, m, m, rad, rad, rad"},
           "min_width": cert.min_width.tolist(),
           # QA F9: units on every number of the result
           "unit": {"region": "m, m, m, rad, rad, rad",
                     "min_width": "m, m, m, rad, rad, rad (the entries of a coordinate the "
                                  "region holds fixed are not used)",
                     "volumes": "volume_unit",
                     "sigma_lower": "as Jx (L x 6: force columns 1-3 dimensionless, moment "
                                    "columns 4-6 in m); sigma_lower_min, "
                                    "sigma_lower_min_boxes and boxes.sigma_lower",
                     "boxes": "lower, upper: m, m, m, rad, rad, rad; det_sign: sign of det "
                              "Jx in a regular box (L = 6), 0 elsewhere; budget: left "
                              "undecided by a spent box budget; reason: the test that "
                              "failed in an undecided box (reason_legend), none"}}
    out.update(s)
    # QA: a single pose has no volume: its volumes and fractions are null, not 1.0 of "1"
    out["single_pose"] = not cert.vary
    out["verdict"] = single_pose_verdict(cert) if not cert.vary else None
    if not cert.vary:
        out["unit"]["volumes"] = "null: a single pose (no coordinate varies) has no volume"
        for key in ("volume_unit", "total_volume",
                    *(f"{n}_{w}" for n in STATUS_NAMES.values() for w in ("volume", "fraction"))):
            out[key] = None
        for part in (out["undecided_budget"], *out["undecided_reasons"].values()):
            part["volume"] = part["fraction"] = None
    out["warnings"] = [w for w in (unit_slip_warning(cert, length_unit),) if w]
    zr = cert.at_zero_rotation()
    out["zero_rotation_slice"] = {
        name: int(np.sum(zr & (cert.status == code))) for code, name in STATUS_NAMES.items()}
    r0 = cert.slice_rotation()              # the plot's slice (QA F3)
    sl = cert.at_rotation(r0)
    out["rotation_slice"] = {"rotation": r0.tolist(), "units": "rad",
                             **{name: int(np.sum(sl & (cert.status == code)))
                                for code, name in STATUS_NAMES.items()}}
    note = _ranges_note(cert.mechanism)
    out["certificate"] = (
        "regular: every leg closes (reach margin > 0" + ("; and is inside its joint range, "
                                                        "see joint_ranges" if note else "")
        + "), Jq_ii != 0 and rank Jx = 6 for "
        "every pose of the box (the IK branch of the presets, or of each leg's `branch`); "
        "singular (L = 6): det Jx "
        "certified > 0 and < 0 at two poses of a reachable box (a zero inside); "
        "unreachable: some leg cannot close" + (" (or stays outside its joint range)"
                                                if note else "") + " anywhere in "
        "the box; undecided: none of these "
        "at the resolution" + (", or (boxes.budget true) left unsplit when the budget of "
                               f"{cert.max_boxes} box evaluations per chunk ran out"
                               if s["budget_exhausted"] else ""))
    if note:
        out["joint_ranges"] = note
    out["boxes"] = {"legend": {str(k): v for k, v in STATUS_NAMES.items()},
                    "lower": cert.lo, "upper": cert.hi, "status": cert.status,
                    "sigma_lower": cert.sigma_lower, "det_sign": cert.det_sign,
                    "budget": cert.budget_mask(),
                    "reason": (cert.reason if cert.reason is not None
                               else np.full(len(cert.status), -1, np.int8)),
                    "reason_legend": {"0": "decided, or left by the budget", "1": "reach",
                                      "2": "jq", "3": "rank", "-1": "not recorded"},
                    "units": "m, m, m, rad, rad, rad"}
    return out


def scene_volume(cert, length_unit: str = "m", angle_unit: str = "rad") -> tuple:
    """``(factor, unit)``: a volume of the certificate in its SI ``volume_unit`` (m^3,
    m^3 rad^3, ...) times ``factor`` is in ``unit``, the scene's units to the powers of
    the region's varying coordinates (cm^3 deg^3 for a 6-D region of a cm, deg scene).
    The JSON keeps SI (docs/design.md §4); the text speaks the scene's units."""
    lf, lu = display_length(length_unit)
    af, au = (180 / math.pi, "deg") if angle_unit == "deg" else (1.0, "rad")
    npos = sum(1 for k in cert.vary if k < 3)
    nrot = len(cert.vary) - npos
    parts = [f"{u}^{n}" if n > 1 else u for u, n in ((lu, npos), (au, nrot)) if n]
    return lf ** npos * af ** nrot, " ".join(parts) or "1"


def certificate_text(cert, length_unit: str = "m", angle_unit: str = "rad") -> str:
    """A readable summary with units on every number, in the scene's units (lengths,
    angles and volumes; σmin(Jx) in SI, :data:`~distkin.certify.plot.SIGMA_UNITS`)."""
    from ...certify.plot import SIGMA_UNITS
    s = cert.summary()
    lf, lu = display_length(length_unit)
    af = 180 / math.pi if angle_unit == "deg" else 1.0
    au = "°" if angle_unit == "deg" else " rad"
    parts = []
    for k, n in enumerate(("x", "y", "z", "rx", "ry", "rz")):
        f = lf if k < 3 else af
        parts.append(f"{n} {_range_text(cert.lower[k] * f, cert.upper[k] * f)}"
                     f"{(' ' + lu) if k < 3 else au}")
    reg = ", ".join(parts)
    vf, unit = scene_volume(cert, length_unit, angle_unit)
    lines = [f"Certified workspace of {cert.mechanism.name} (L = {cert.mechanism.L}), "
             f"{cert.form} form, method certified",
             f"  region: {reg}",
             "  resolution: " + (f"{cert.min_width[0] * lf:.4g} {lu} (position), "
                                 if np.any(cert.upper[:3] > cert.lower[:3]) else
                                 "position fixed, ")
             + (f"{cert.min_width[3] * af:.4g}{au} (rotation)"
                if np.any(cert.upper[3:] > cert.lower[3:]) else "rotation fixed")]
    if not cert.vary:                   # a single pose: a status, no volume to speak of
        lines.append(f"  a single pose (no coordinate varies, so no volume): "
                     f"{single_pose_verdict(cert)}")
    for name in ("regular", "singular", "undecided", "unreachable"):
        if not cert.vary:
            break
        lines.append(f"  {name:<11} {s[name + '_volume'] * vf:.4g} {unit}  "
                     f"({100 * s[name + '_fraction']:.2f} % of {s['total_volume'] * vf:.4g} "
                     f"{unit}; "
                     f"{s['counts'][name]} boxes)")
    note = _ranges_note(cert.mechanism)
    if note:
        lines.append(f"  note: {note}")
    slip = unit_slip_warning(cert, length_unit)
    if slip:
        lines.append(f"  warning: {slip}")
    why = s["undecided_reasons"]
    if why:
        from ...mechanisms.kernels import range_legs
        ranged = hasattr(cert.mechanism, "leg_description") and range_legs(cert.mechanism)
        said = {"reach": "a leg's reach margin" + (" or joint range margin" if ranged else "")
                         + " not enclosed away from 0 (the workspace edge may cross the "
                         "box)",
                "jq": "a Jq diagonal entry not enclosed away from 0 (a serial singularity "
                      "may cross the box)",
                "rank": "the rank test of Jx failed (a parallel singularity may cross the "
                        "box, or the enclosure is too wide at the resolution)",
                "other": "other", "not_recorded": "not recorded (stored chunks)"}
        lines.append("  undecided at the resolution, by why: " + "; ".join(
            f"{said[k]}: {v['boxes']} boxes"
            + (f", {100 * v['fraction']:.2f} %" if cert.vary else "")
            for k, v in why.items()))
    ub = s["undecided_budget"]
    if s["budget_exhausted"]:
        lines.append(f"  warning: the box budget ran out (max_boxes = {s['max_boxes']} "
                     f"evaluations per chunk): {ub['boxes']} of the undecided boxes"
                     + (f" ({100 * ub['fraction']:.2f} % of the region)" if cert.vary else "")
                     + " were left unsplit, wider than the resolution -- undecided for want "
                     "of budget, not at the resolution; raise max_boxes")
    if s["sigma_lower_min"] is not None:
        lines.append(f"  σmin(Jx) >= {s['sigma_lower_min']:.3g} (certified, every regular box; "
                     f"Jx is L x 6: {SIGMA_UNITS})")
        if "sigma_tightening" in s:
            t = s["sigma_tightening"]
            lines.append(f"    (the classification's boxes alone: >= "
                         f"{s['sigma_lower_min_boxes']:.3g}; the weakest bisected: "
                         f"{t['boxes']} boxes in {t['seconds']:.1f} s)")
    if "det_signs" in s:
        lines.append(f"  det Jx sign(s) over the regular boxes: {s['det_signs']}")
    bps, bpp = s["boxes_per_second"], s["boxes_per_process_second"]
    resumed = s.get("chunks_resumed", 0)
    if resumed == s["chunks"]:          # nothing computed now: no wall rate to speak of
        lines.append(f"  {s['boxes_evaluated']} boxes, all {s['chunks']} chunks loaded from "
                     f"the store (computed earlier in {s['seconds']:.1f} s of chunk time"
                     + (f", {bpp:.0f} boxes/s per process)" if bpp else ")"))
    else:
        lines.append(f"  {s['boxes_evaluated']} boxes evaluated in {s['wall_seconds']:.1f} s "
                     f"wall ({bps:.0f} boxes per wall second), {s['seconds']:.1f} s of chunk "
                     f"time ({bpp:.0f} boxes/s per process), {s['chunks']} chunks"
                     if bps and bpp else
                     f"  {s['boxes_evaluated']} boxes evaluated, {s['chunks']} chunks")
        if resumed:
            lines.append(f"    ({resumed} of the {s['chunks']} chunks loaded from the store: "
                         "their boxes count in the wall rate but were computed earlier)")
    return "\n".join(lines)
