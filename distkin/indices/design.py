"""GII design sweeps over the parameters of Table I (Kühne et al., Sec. III-B-2).

Table I: l2 = 0..30 mm (step 5), β = 0..30° (10), γ = 0..30° (10), ld = 20..40 mm (5),
7·4·4·5 = 560 designs, each scored by its GII over a workspace grid (Table II or a
coarser grid the scene names).  "The total length of each leg remains constant, which
is ensured by keeping l2 + l3 constant.  Baseline geometric characteristics were taken
from Ergin's device": ``leg_length="constant_sum"`` sets l3 = (l2 + l3 of the baseline
preset) − l2; ``"reading"`` applies the l3 rule of the mechanisms' reading of Fig. 2 to
every design instead.  Under the presets' (tangential) reading both give l3 =
LEG_LENGTH − l2, so the sweep's Hunt-type (l2 = β = γ = 0, ld = 20 mm) is the ``hunt``
preset (:mod:`distkin.mechanisms.presets`).

Designs are evaluated with :mod:`distkin.mechanisms.reference` (plain numpy from the leg geometry), so
a sweep needs no symbolic derivation per design.  :func:`sweep_designs` runs Stocco's
culling (:func:`~distkin.indices.isotropy.culling_sweep`), brute force (chunked,
resumable, on any executor) or both, and checks that they agree exactly.
"""

from __future__ import annotations

import hashlib
import itertools
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InfeasibleError, InputError
from .isotropy import ST_DEFAULT, culling_sweep
from ..mechanisms.reference import ik_jacobian

__all__ = ["DesignSpace", "design_sigmas", "design_chunk", "sweep_designs"]

PARAMS = ("l2", "beta", "gamma", "ld")


@dataclass(frozen=True)
class DesignSpace:
    """The product of parameter values (SI: m, rad) applied to a base preset."""

    base: str
    values: tuple                    # ((name, (v, ...)), ...) in PARAMS order
    leg_length: str = "constant_sum"
    baseline: str = "ergin"

    def designs(self) -> list[dict]:
        names = [n for n, _ in self.values]
        return [dict(zip(names, combo)) for combo in
                itertools.product(*[v for _, v in self.values])]

    def mechanism(self, params: dict):
        """The design's mechanism.  preset()'s GeometryWarnings (an override 100x off
        the preset's value, a home some leg misses) are not given: a design is far off
        on purpose, and the sweep scores what each design reaches (review: every
        design of a sweep warned, up to three times)."""
        from ..mechanisms import GeometryWarning, preset
        over = dict(params)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", GeometryWarning)
            if self.leg_length == "constant_sum":
                b = preset(self.baseline)
                l3 = b.l2 + b.l3 - over.get("l2", preset(self.base).l2)
                rule = preset(self.base, **over)
                if abs(rule.l3 - l3) > 1e-12:   # the reading's rule already keeps the sum
                    over["l3"] = l3
            return preset(self.base, **over)


def design_sigmas(mech, poses, ST=ST_DEFAULT, unreachable: str = "zero"):
    """Scaled (σmin, σmax) of ``mech`` at ``poses`` (N,).

    ``unreachable="zero"`` (the default): a pose that some leg cannot reach gives
    σmin = 0 (σmax = 0), so a design that misses part of the workspace gets GII = 0 and
    every design is scored on the same grid (Sec. III-B-2: the GII over "the chosen
    ... workspace", Table II); ``"skip"``: the pose is left out of the GII (σmin = +inf,
    σmax = 0, neutral for min and max).
    """
    from ..argcheck import choice
    from .isotropy import scaled_singular_values
    choice(unreachable, "unreachable", ("skip", "zero"))
    _, valid, J = ik_jacobian(mech, poses)
    ok = valid.all(axis=1) & np.all(np.isfinite(J), axis=(1, 2))
    smin = np.full(len(poses), np.inf if unreachable == "skip" else 0.0)
    smax = np.zeros(len(poses))
    if ok.any():
        smin[ok], smax[ok] = scaled_singular_values(J[ok], ST)
    return smin, smax


def design_chunk(spec: dict) -> dict:
    """Brute-force chunk: designs ``spec["designs"]`` (list of dicts) at every pose of
    ``spec["poses"]``; returns ``min_smin``, ``max_smax`` per design."""
    space, poses, ST = spec["space"], spec["poses"], spec["ST"]
    lo, hi, cover = [], [], []
    for params in spec["designs"]:
        mech = space.mechanism(params)
        smin, smax = design_sigmas(mech, poses, ST, spec.get("unreachable", "zero"))
        lo.append(smin.min())
        hi.append(smax.max())
        cover.append(float(np.mean(smax > 0)))
    return {"min_smin": np.array(lo), "max_smax": np.array(hi), "coverage": np.array(cover)}


def sweep_designs(space: DesignSpace, poses, *, algorithm="both", ST=ST_DEFAULT, store=None,
                  executor=None, progress=True, designs_per_chunk: int = 8,
                  block: int = 4096, unreachable: str = "zero", stats: dict | None = None):
    """GII of a design space over ``poses`` (N, 6) (``unreachable``: "zero", the
    default, or "skip", as :func:`design_sigmas`).

    ``"zero"`` scores every design on the whole grid (a pose it misses gives σmin = 0):
    the GII of Sec. III-B-2 is over "the chosen ... workspace" (Table II), the same for
    every design; ``"skip"`` scores each design on the poses it reaches, which can rank
    designs on different subsets (the result then flags an optimum whose coverage is
    below another design's, ``coverage_flag``, when brute force gave the coverage).

    Returns a dict: ``designs`` (list of parameter dicts), ``best`` (index), ``ties``
    (every design whose GII equals the optimum's, ``best`` first), ``gii``,
    ``sigma_min``, ``sigma_max``, ``parameters`` of the optimum, and per algorithm its
    seconds and evaluation count; ``agree`` (culling == brute force, bit for bit) when
    both ran.  ``stats`` (brute force with a store) is filled as
    :func:`distkin.runstore.run_chunks` fills it (``loaded``: chunks resumed).

    Raises
    ------
    InfeasibleError
        No design reaches any pose of the grid, or every design scores GII 0 (a tie at
        0 has no optimum; with ``"zero"``: none reaches every pose with a regular J).
    """
    if algorithm not in ("culling", "brute_force", "both"):
        raise InputError(f"expected 'culling', 'brute_force' or 'both', got {algorithm!r}",
                         field="algorithm")
    designs = space.designs()
    poses = np.asarray(poses, dtype=float)
    mechs: dict = {}

    def mech(i):
        if i not in mechs:
            mechs[i] = space.mechanism(designs[i])
        return mechs[i]

    out = {"designs": designs, "n_designs": len(designs), "n_poses": len(poses),
           "unreachable": unreachable}
    folder = None
    if store is not None and algorithm in ("brute_force", "both"):
        # a store the brute force would refuse is refused before the culling runs
        from ..runstore import check_store, sweep_key
        definition = _store_definition(space, poses, ST, designs_per_chunk, unreachable)
        folder = Path(store) / sweep_key(definition)
        check_store(folder, definition, -(-len(designs) // designs_per_chunk))
    if algorithm in ("culling", "both"):
        bar = _CullingProgress(len(designs) * len(poses), progress)

        def evaluate(ds, ps):
            P = poses[ps]
            lo = np.empty((len(ds), len(ps)))
            hi = np.empty((len(ds), len(ps)))
            for k, i in enumerate(ds):
                lo[k], hi[k] = design_sigmas(mech(int(i)), P, ST, unreachable)
                bar.advance(len(ps))
            return lo, hi
        t0 = time.perf_counter()
        try:
            res = culling_sweep(evaluate, len(designs), len(poses), block=block)
        finally:
            bar.close()
        out["culling"] = {"seconds": time.perf_counter() - t0, **res.as_dict()}
        # a design tying the optimum is never culled (its bound is not below it)
        ties = sorted(k for k, v in res.exact.items() if v == res.gii)
        out["culling"]["ties"] = ties
        out.update(best=res.best, gii=res.gii, sigma_min=res.smin, sigma_max=res.smax,
                   ties=ties)
        reached_any = bool(np.any(res.smax_all > 0))
    if algorithm in ("brute_force", "both"):
        g, lo, hi = _brute_force(space, designs, poses, ST, unreachable, folder, executor,
                                 progress, designs_per_chunk, out, stats)
        b = int(np.argmax(g))
        ties = np.flatnonzero(g == g[b]).tolist()
        out["brute_force"].update(best=b, gii=float(g[b]), sigma_min=float(lo[b]),
                                  sigma_max=float(hi[b]), ties=ties)
        if "best" not in out:
            out.update(best=b, gii=float(g[b]), sigma_min=float(lo[b]),
                       sigma_max=float(hi[b]), ties=ties)
        reached_any = bool(np.any(hi > 0))
    if algorithm == "both":
        c, bf = out["culling"], out["brute_force"]
        out["agree"] = bool(c["best"] == bf["best"] and c["gii"] == bf["gii"]
                            and c["sigma_min"] == bf["sigma_min"]
                            and c["sigma_max"] == bf["sigma_max"] and c["ties"] == bf["ties"])
    counts = f"{len(designs):,} designs × {len(poses):,} poses"
    if not reached_any:
        raise InfeasibleError(f"no design of the sweep reaches any pose of the grid ({counts})",
                              field="grid", hint="a grid about the designs' home pose, or a "
                              "smaller half or rotation")
    if out["gii"] == 0 and len(out["ties"]) == len(designs):
        why = ("none reaches every pose of the grid with a regular J (unreachable = 'zero' "
               "scores a missed pose σmin = 0)" if unreachable == "zero" else
               "each is singular at a pose it reaches (unreachable = 'skip' already leaves "
               "out the poses it misses)")
        hint = ("a smaller grid, or unreachable = 'skip' to score each design on the poses "
                "it reaches" if unreachable == "zero" else
                "a smaller grid about the home pose, or ranges whose designs are regular "
                "there")
        raise InfeasibleError(f"every design of the sweep scores GII 0 ({counts}), so none is "
                              f"an optimum: {why}", field="grid", hint=hint)
    out["parameters"] = designs[out["best"]]
    cov = out.get("coverage")
    if unreachable == "skip" and cov is not None:
        top = int(np.argmax(cov))
        if cov[top] > cov[out["best"]]:
            out["coverage_flag"] = {"optimum_coverage": cov[out["best"]],
                                    "other_design": top, "other_coverage": cov[top]}
    return out


class _CullingProgress:
    """The culling's progress bar on stderr (rich): its (design, pose) evaluations
    against brute force's count, a ceiling it stops short of when designs are culled;
    nothing when not ``enabled``."""

    def __init__(self, ceiling, enabled):
        self.bar = None
        if enabled and ceiling:
            from rich.console import Console
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
            self.bar = Progress(TextColumn("design sweep, culling"), BarColumn(),
                                TextColumn("{task.completed:,} of at most {task.total:,} "
                                           "(design, pose) evaluations · elapsed"),
                                TimeElapsedColumn(), console=Console(stderr=True))
            self.bar.start()
            self.task = self.bar.add_task("culling", total=ceiling)

    def advance(self, n):
        if self.bar is not None:
            self.bar.advance(self.task, n)

    def close(self):
        if self.bar is not None:
            self.bar.stop()


def _store_definition(space, poses, ST, designs_per_chunk, unreachable) -> dict:
    """What defines a brute-force sweep's chunk store (:func:`distkin.runstore.sweep_key`)."""
    return {"kind": "design_sweep", "space": repr(space), "poses": int(len(poses)),
            "poses_sha256": hashlib.sha256(poses.tobytes()).hexdigest(),
            "ST": list(ST), "per_chunk": designs_per_chunk, "unreachable": unreachable}


def _brute_force(space, designs, poses, ST, unreachable, store, executor, progress,
                 designs_per_chunk, out, stats):
    """Every design at every pose, in resumable chunks (``store``: the sweep's keyed
    folder, or None); fills ``out["brute_force"]`` and ``out["coverage"]``, returns
    (GII, min σmin, max σmax) per design."""
    from ..runstore import run_chunks
    t0 = time.perf_counter()
    specs = [{"space": space, "poses": poses, "ST": tuple(ST), "unreachable": unreachable,
              "designs": designs[a:a + designs_per_chunk]}
             for a in range(0, len(designs), designs_per_chunk)]
    if store is None:
        chunks = [design_chunk(s) for s in specs]
        if stats is not None:
            stats["loaded"] = 0
    else:
        definition = _store_definition(space, poses, ST, designs_per_chunk, unreachable)
        chunks = run_chunks(design_chunk, specs, store, definition=definition,
                            executor=executor, progress=progress,
                            desc=f"design sweep, brute force ({len(designs)} designs)",
                            stats=stats)
    lo = np.concatenate([c["min_smin"] for c in chunks])
    hi = np.concatenate([c["max_smax"] for c in chunks])
    out["coverage"] = np.concatenate([c["coverage"] for c in chunks]).tolist()
    out["chunks"] = len(specs)
    g = np.divide(lo, hi, out=np.zeros(len(designs)), where=hi > 0)
    out["brute_force"] = {"seconds": time.perf_counter() - t0,
                          "evaluations": len(designs) * len(poses), "gii_all": g.tolist(),
                          "sigma_min_all": lo.tolist(), "sigma_max_all": hi.tolist()}
    return g, lo, hi
