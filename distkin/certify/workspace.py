"""Certified workspace of an RSS mechanism: branch-and-prune of a region of poses,
run as resumable chunks on any executor (:mod:`distkin.runstore`).

The region ``[lower, upper]`` (m, rad; six coordinates, a zero width fixes one) is cut
into ``split`` parts along every varying coordinate; each part is one chunk of
:func:`distkin.runstore.run_chunks` (stored on disk as soon as it is done, skipped
when a run resumes, run on a local process pool or a dask cluster) and is classified
by :func:`.boxes.branch_and_prune`.  :class:`WorkspaceCertificate` gathers the boxes
and their volumes.

Volumes are over the varying coordinates only: m^3 for a translational region at a fixed
orientation, m^3 rad^3 for the 6-D region of positions and rotation parameters (the
product of the widths of x, y, z in m and rx, ry, rz in rad, no metric on rotations).
The fractions are of the region's volume.
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass

import numpy as np

from ..argcheck import choice, positive_int
from ..errors import InputError
from .batch import branch_and_prune_batched
from .boxes import (REASONS, REGULAR, STATUS_NAMES, UNDECIDED, branch_and_prune, check_box,
                    check_mechanism, check_resolution)
from .intervals import FORMS
from .tighten import tighten_sigma

__all__ = ["WorkspaceCertificate", "certify_workspace", "initial_boxes", "volume_unit",
           "WORKSPACE_FORMS"]


def volume_unit(vary) -> str:
    """"m^3", "m^3 rad^3", ... for the varying coordinates ``vary`` (indices 0..5)."""
    npos = sum(1 for k in vary if k < 3)
    nrot = sum(1 for k in vary if k >= 3)
    parts = []
    if npos:
        parts.append("m" if npos == 1 else f"m^{npos}")
    if nrot:
        parts.append("rad" if nrot == 1 else f"rad^{nrot}")
    return " ".join(parts) or "1"


def initial_boxes(lower, upper, split: int):
    """The region cut into ``split`` equal parts along every varying coordinate.

    Returns
    -------
    list of (lo, hi) arrays (6,)
    """
    lower = np.asarray(lower, dtype=float)
    upper = np.asarray(upper, dtype=float)
    vary = [k for k in range(6) if upper[k] > lower[k]]
    edges = {k: np.linspace(lower[k], upper[k], split + 1) for k in vary}
    for k in vary:                       # exact corners of the region
        edges[k][0], edges[k][-1] = lower[k], upper[k]
    out = []
    for idx in itertools.product(range(split), repeat=len(vary)):
        lo, hi = lower.copy(), upper.copy()
        for k, i in zip(vary, idx):
            lo[k], hi[k] = edges[k][i], edges[k][i + 1]
        out.append((lo, hi))
    return out


#: the enclosure forms certify_workspace takes (``auto``: :func:`.boxes.branch_and_prune`)
WORKSPACE_FORMS = ("quadratic64",) + FORMS + ("auto",)


def _chunk_task(spec):
    """One chunk (module level, picklable): ``spec = (mech, lo, hi, min_width, form,
    max_boxes)``."""
    mech, lo, hi, minw, form, max_boxes = spec
    if form == "quadratic64":
        return branch_and_prune_batched(mech, lo, hi, minw, max_boxes=max_boxes)
    return branch_and_prune(mech, lo, hi, minw, form=form, max_boxes=max_boxes)


@dataclass
class WorkspaceCertificate:
    """The classified boxes of a region.

    Attributes
    ----------
    mechanism : RSSMechanism
    lower, upper : ndarray (6,)
        The region (m, rad).
    min_width : ndarray (6,)
        The resolution (m, rad).
    form : str
        Enclosure form (:data:`.intervals.FORMS` or ``quadratic64``).
    lo, hi : ndarray (n, 6)
        Box corners.
    status : ndarray (n,) int8
        :data:`.boxes.STATUS_NAMES`.
    sigma_lower : ndarray (n,)
        Certified lower bounds of σmin(Jx) in the regular boxes (0 elsewhere).
    det_sign : ndarray (n,) int8
        L = 6: sign of det Jx in each regular box.
    evaluated : int
        Boxes evaluated in the chunks computed or loaded.
    seconds : float
        Sum of the chunks' computing times (their own clocks; the chunks of a resumed
        run count with the time they took then).
    wall_seconds : float
        Wall-clock time of this call, the σmin tightening apart (its time is in
        :attr:`sigma_bound`).
    chunks : int
    sigma_bound : SigmaBound or None
        The σmin bound over all regular boxes raised by bisecting the weakest
        (:func:`.tighten.tighten_sigma`); None when not run.
    resumed : int
        Chunks loaded from the store (computed by an earlier run); their boxes count in
        :attr:`evaluated` but took none of :attr:`wall_seconds`.
    store : str or None
        The folder the chunks are kept in (the sub-folder of the store that
        :func:`distkin.runstore.run_chunks` keyed by this region's definition); None
        when they were kept in memory.
    budget : ndarray (n,) bool or None
        The undecided boxes left unsplit (or unevaluated) because a chunk's box budget
        ``max_boxes`` ran out: not undecided at the resolution (QA F4).  None: no box.
    max_boxes : int or None
        That budget (box evaluations per chunk).
    reason : ndarray (n,) int8 or None
        Why each box is undecided at the resolution (:data:`.boxes.REASONS` codes: 1
        reach, 2 jq, 3 rank; 0 decided or left by the budget; -1 not recorded, a chunk
        stored before reasons were kept).  None: not recorded.
    """

    mechanism: object
    lower: np.ndarray
    upper: np.ndarray
    min_width: np.ndarray
    form: str
    lo: np.ndarray
    hi: np.ndarray
    status: np.ndarray
    sigma_lower: np.ndarray
    det_sign: np.ndarray
    evaluated: int
    seconds: float
    wall_seconds: float
    chunks: int
    sigma_bound: object = None
    resumed: int = 0
    store: str | None = None
    budget: np.ndarray | None = None
    max_boxes: int | None = None
    reason: np.ndarray | None = None

    def budget_mask(self) -> np.ndarray:
        """(n,) bool: the boxes left undecided because the box budget ran out."""
        if self.budget is None:
            return np.zeros(len(self.status), dtype=bool)
        return np.asarray(self.budget, dtype=bool)

    def undecided_reasons(self) -> dict:
        """The boxes undecided at the resolution (the budget's apart), by the first test
        their enclosures did not decide (boxes, volume in :attr:`volume_unit`, fraction
        of the region; :data:`.boxes.REASONS`): ``reach`` (the edge of the reachable set
        may cross them), ``jq`` (a serial singularity may), ``rank`` (a parallel
        singularity may, or the enclosure is too wide), ``other``, ``not_recorded``
        (chunks stored before reasons were kept).  A diagnosis: what the box holds is
        not proved."""
        und = (self.status == UNDECIDED) & ~self.budget_mask()
        why = (np.full(len(self.status), -1, np.int8) if self.reason is None
               else np.asarray(self.reason))
        vols, tot = self.volumes(), self.total_volume()
        names = {**{code: name for name, code in REASONS.items() if name},
                 -1: "not_recorded", 0: "other"}
        out = {}
        for code, name in names.items():
            sel = und & (why == code)
            if sel.any():
                prev = out.get(name, {"boxes": 0, "volume": 0.0})
                v = prev["volume"] + float(vols[sel].sum())
                out[name] = {"boxes": prev["boxes"] + int(sel.sum()), "volume": v,
                             "fraction": v / tot if tot else 0.0}
        return out

    @property
    def vary(self) -> tuple:
        return tuple(k for k in range(6) if self.upper[k] > self.lower[k])

    @property
    def volume_unit(self) -> str:
        return volume_unit(self.vary)

    def volumes(self) -> np.ndarray:
        """(n,) box volumes over the varying coordinates (:attr:`volume_unit`)."""
        v = list(self.vary)
        if not v:
            return np.ones(len(self.status))
        return np.prod(self.hi[:, v] - self.lo[:, v], axis=1)

    def total_volume(self) -> float:
        v = list(self.vary)
        return float(np.prod(self.upper[v] - self.lower[v])) if v else 1.0

    def volume(self, status: int) -> float:
        return math.fsum(self.volumes()[self.status == status])

    def summary(self) -> dict:
        """Volumes (in :attr:`volume_unit`), fractions, counts, σ bound, timing.

        Two rates: ``boxes_per_second`` is boxes per wall second of the whole call (all
        processes together: :attr:`evaluated` over :attr:`wall_seconds`; a resumed run
        counts the boxes of the chunks it loaded, so its rate is not a speed:
        ``chunks_resumed`` says how many);
        ``boxes_per_process_second`` is per process (boxes over the sum of the chunks' own
        computing times, whatever ran them in parallel).
        """
        tot = self.total_volume()
        out = {"volume_unit": self.volume_unit, "total_volume": tot}
        # fractions of the leaves' own (correctly rounded) sum, which tile the region:
        # a region entirely of one status reads exactly 1 (QA X4: 0.9999999999999999)
        leaves_tot = math.fsum(self.volumes())
        for code, name in STATUS_NAMES.items():
            vol = self.volume(code)
            out[f"{name}_volume"] = vol
            out[f"{name}_fraction"] = vol / leaves_tot if leaves_tot else 0.0
        out["counts"] = {name: int(np.sum(self.status == code))
                         for code, name in STATUS_NAMES.items()}
        spent = self.budget_mask()
        vb = float(self.volumes()[spent].sum()) if spent.any() else 0.0
        # undecided because a chunk's budget ran out, not at the resolution (QA F4)
        out["budget_exhausted"] = bool(spent.any())
        out["undecided_budget"] = {"boxes": int(spent.sum()), "volume": vb,
                                   "fraction": vb / tot if tot else 0.0}
        out["max_boxes"] = self.max_boxes
        out["undecided_reasons"] = self.undecided_reasons()
        reg = self.status == REGULAR
        leaves = float(self.sigma_lower[reg].min()) if reg.any() else None
        tb = self.sigma_bound
        # the certified bound over every regular box (tightened: never below the
        # classification's own, the minimum over its boxes, given beside it)
        out["sigma_lower_min"] = leaves if tb is None else tb.value
        out["sigma_lower_min_boxes"] = leaves
        if tb is not None:
            out["sigma_tightening"] = {"boxes": tb.evaluated, "seconds": tb.seconds}
        if self.mechanism.L == 6 and reg.any():
            out["det_signs"] = sorted({int(s) for s in self.det_sign[reg]})
        out["boxes_evaluated"] = self.evaluated
        out["seconds"] = self.seconds
        out["wall_seconds"] = self.wall_seconds
        out["boxes_per_second"] = (self.evaluated / self.wall_seconds
                                   if self.wall_seconds > 0 else None)
        out["boxes_per_process_second"] = (self.evaluated / self.seconds
                                           if self.seconds > 0 else None)
        out["chunks"] = self.chunks
        out["chunks_resumed"] = self.resumed
        return out

    def at_zero_rotation(self) -> np.ndarray:
        """(n,) bool: the boxes that contain a pose of zero rotation (rx = ry = rz = 0)."""
        return self.at_rotation(np.zeros(3))

    def slice_rotation(self) -> np.ndarray:
        """(3,) rad: the rotation of the region nearest to zero (zero when the region
        contains it; its fixed rotation when the rotation is fixed): the rotation of the
        Fig. 3 slice (QA F3: a region at rx = 10° had an empty "zero rotation" slice)."""
        return np.clip(0.0, self.lower[3:], self.upper[3:])

    def at_rotation(self, rotation) -> np.ndarray:
        """(n,) bool: the boxes that contain a pose of the rotation (3,) rad."""
        r = np.asarray(rotation, dtype=float)
        return np.all((self.lo[:, 3:] <= r) & (self.hi[:, 3:] >= r), axis=1)


def certify_workspace(mech, lower, upper, min_width, *, form: str = "quadratic64",
                      split: int = 2, store=None, executor=None, progress: bool = False,
                      max_boxes: int = 200_000, definition_extra=None,
                      tighten: int = 4096) -> WorkspaceCertificate:
    """Certify a region of poses of ``mech`` (:mod:`.boxes`).

    Parameters
    ----------
    mech : RSSMechanism
    lower, upper : array (6,)
        The region (m, rad): x, y, z, rx, ry, rz (:mod:`distkin.spatial`).
    min_width : float or array (6,)
        Resolution (m, rad), positive: boxes are bisected along a coordinate only while
        wider.
    form : {"quadratic64", "quadratic", "affine", "centred", "plain", "auto"}
        ``quadratic64`` (the default): the quadratic form with binary64 coefficients,
        boxes evaluated in batches (:mod:`.batch`), the arb ``quadratic`` form on the
        boxes it leaves undecided at the resolution; the others: :mod:`.boxes`.
    split : int
        Parts per varying coordinate of the initial chunks (split ** d chunks).
    store : path, optional
        Directory of the resumable chunks; None keeps them in memory (no resume).
    executor : concurrent.futures.Executor or None
        None runs in this process.
    progress : bool
        Progress bar of the chunks with the ETA (stderr), with or without a store.
    max_boxes : int
        Budget of box evaluations per chunk (boxes left over are undecided).
    tighten : int
        Budget of box evaluations, in this process after the chunks, to raise the
        certified σmin bound over the regular boxes (:func:`.tighten.tighten_sigma`: the
        boxes with the weakest bounds bisected and certified again); 0: the minimum of
        the classification's own bounds.

    Returns
    -------
    WorkspaceCertificate

    Raises
    ------
    InputError
        Bounds not (6,) finite numbers or lower > upper (:func:`.boxes.check_box`), a
        rotation span above 2π, a
        resolution <= 0 or a boolean (:func:`.boxes.check_resolution`), an unknown
        form, ``split`` or ``max_boxes`` < 1, ``tighten`` < 0.
    """
    from ..runstore import run_chunks
    t0 = time.perf_counter()
    check_mechanism(mech)
    lower, upper = check_box(lower, upper, ("lower", "upper"))
    for k in range(3, 6):                # QA: ±1e12° counted orientations 1e10 times
        if upper[k] - lower[k] > 2 * np.pi * (1 + 1e-12):
            raise InputError(f"expected a span of r{'xyz'[k - 3]} (upper[{k}] - lower[{k}]) "
                             f"of at most 2π rad (a wider span counts orientations more "
                             f"than once), got {upper[k] - lower[k]:.6g} rad", field="upper")
    minw = check_resolution(min_width)
    form = choice(form, "form", WORKSPACE_FORMS)
    split = positive_int(split, "split")
    max_boxes = positive_int(max_boxes, "max_boxes")
    tighten = positive_int(tighten, "tighten", minimum=0)
    boxes = initial_boxes(lower, upper, split)
    specs = [(mech, lo, hi, minw, form, int(max_boxes)) for lo, hi in boxes]
    stats: dict = {}
    definition = {"certify_workspace": 1, "mechanism": repr(mech.geometry_key()),
                  "lower": lower.tolist(), "upper": upper.tolist(),
                  "min_width": minw.tolist(), "form": form, "split": split,
                  "max_boxes": int(max_boxes), "extra": definition_extra}
    results = run_chunks(_chunk_task, specs, store, definition=definition,
                         executor=executor, progress=progress,
                         desc=f"certify {mech.name}", stats=stats)
    cat = {k: np.concatenate([r[k] for r in results]) for k in
           ("lo", "hi", "status", "sigma_lower", "det_sign")}
    blo, bhi = cat["lo"].reshape(-1, 6), cat["hi"].reshape(-1, 6)
    spent = np.concatenate([_budget_flags(r, minw) for r in results])
    why = np.concatenate([np.asarray(r["reason"], np.int8).reshape(-1) if "reason" in r
                          else np.full(len(r["status"]), -1, np.int8) for r in results])
    reg = cat["status"] == REGULAR
    wall = time.perf_counter() - t0           # the classification's (tightening apart)
    bound = None
    if tighten > 0 and reg.any():
        bound = tighten_sigma(mech, blo[reg], bhi[reg], cat["sigma_lower"][reg],
                              scale=upper - lower, budget=int(tighten))
    return WorkspaceCertificate(
        mech, lower, upper, minw, form, blo, bhi,
        cat["status"], cat["sigma_lower"], cat["det_sign"],
        int(sum(int(r["evaluated"]) for r in results)),
        float(sum(float(r["seconds"]) for r in results)), wall, len(specs), bound,
        stats["loaded"], stats.get("store"), spent, int(max_boxes), why)


def _budget_flags(chunk, minw) -> np.ndarray:
    """A chunk's ``budget`` flags; for a chunk stored before they were kept, the
    undecided boxes still wider than the resolution (the ones left unsplit)."""
    if "budget" in chunk:
        return np.asarray(chunk["budget"], dtype=bool).reshape(-1)
    lo, hi = chunk["lo"].reshape(-1, 6), chunk["hi"].reshape(-1, 6)
    return (chunk["status"] == UNDECIDED) & np.any(hi - lo > minw, axis=1)

