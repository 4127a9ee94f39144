"""Performance indices: the zonotope kernel against the paper's hull algorithm and
pycapacity's hyperplane shifting on the same Jacobians; the study pipeline per pose
(compiled kernel against the numpy route) with its memory; scaling in N, in grid
resolution and in processes; the full Table II grid for the Octopod; the GII culling
speed-up over brute force (issues 6, 17)."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from .harness import fmt_time, interleaved, ratio_table

__all__ = ["TITLE", "DEFAULT", "REQUIRES", "run", "scale_probe"]

TITLE = "Performance indices: zonotope kernel, Table II sweep, GII culling"
DEFAULT = True           # 277 s in BENCHMARKS.md's run (46) (the N = 1e7 probe 81 s of it)
#: the comparison needs these installed (extra ``bench``); the run refuses without them
REQUIRES = ("pycapacity",)

_SLICES = ((0, 1, 2, 3, 4, 5), (0, 1, 2), (3, 4, 5))


def _poses(mech, n, rot_deg, seed=0):
    rng = np.random.default_rng(seed)
    out = []
    while sum(len(o) for o in out) < n:
        P = np.c_[rng.uniform(-0.075, 0.075, (2 * n, 3)) + [0, 0, mech.z0],
                  np.deg2rad(rng.uniform(-rot_deg, rot_deg, (2 * n, 3)))]
        out.append(P[mech.reachable(P)])
    return np.concatenate(out)[:n]


def _kernels_section(data):
    from distkin.indices.capability import hull_multi
    from distkin.indices.zonotope import zonotope_worst
    from distkin.mechanisms import preset
    mech = preset("octopod")
    poses = _poses(mech, 2000, 30)
    G = np.swapaxes(mech.jacobian(poses), 1, 2)              # wrench map Jᵀ, (N, 6, 8)
    N, d, L = G.shape
    lim = 2.5
    c, r = np.zeros((N, L)), np.full((N, L), lim)
    lo, hi = np.full(L, -lim), np.full(L, lim)
    n_hull, n_pyc = 4, 40
    from pycapacity.algorithms import hyper_plane_shift_method   # extra "bench" (REQUIRES)

    def zono():
        return zonotope_worst(G, c, r, _SLICES)

    def hull():
        return [hull_multi(G[i], lo, hi, _SLICES) for i in range(n_hull)]

    def pyc():
        out = []
        for i in range(n_pyc):
            H, dd = hyper_plane_shift_method(G[i], lo, hi)
            dd = np.ravel(dd)
            out.append([np.min(dd / np.linalg.norm(H[:, list(S)], axis=1)) for S in _SLICES])
        return out
    comps = {"zonotope kernel (batched, 2000 poses)": zono,
             f"paper's hull algorithm (Qhull, {n_hull} poses)": hull,
             f"pycapacity hyperplane shifting ({n_pyc} poses)": pyc}
    med = interleaved(comps, rounds=5)
    per = {}
    names = list(comps)
    per[names[0]] = med[names[0]] / N
    per[names[1]] = med[names[1]] / n_hull
    per[names[2]] = med[names[2]] / n_pyc
    # the three agree on the poses they share
    z = zono()
    h = np.array([[w for w, _ in res] for res in hull()]).T
    agree = {"hull_max_rel": float(np.max(np.abs(z[:, :n_hull] - h) / h))}
    p = np.array(pyc()).T
    agree["pycapacity_max_rel"] = float(np.max(np.abs(z[:, :n_pyc] - p) / p))
    base = names[0]
    text = ["### Worst-case wrench capabilities, Octopod (L = 8), the same Jacobians",
            "", "Whole set, force at zero torque and torque at zero force, per pose "
            "(±2.5 N·m; random reachable poses in the Table II box, ±30°).", "",
            ratio_table(per, base, per="pose"), "",
            f"Speed-up of the zonotope kernel: {per[names[1]] / per[base]:,.0f}× over the "
            f"hull algorithm (target >= 1000×), {per[names[2]] / per[base]:,.0f}× over "
            f"pycapacity {_version('pycapacity')} (installed by the extra `bench`; the "
            "run refuses to start without it).",
            f"Agreement on the shared poses: hull {agree['hull_max_rel']:.1e} relative, "
            f"pycapacity {agree['pycapacity_max_rel']:.1e}."]
    data["kernels"] = {"per_pose_s": per, "agreement": agree,
                       "speedup_vs_hull": per[names[1]] / per[base]}
    return "\n".join(text)


def _version(dist: str) -> str:
    from importlib.metadata import version
    return version(dist)


def _load() -> str:
    one, five, _ = os.getloadavg()
    return f"{one:.2f} (1 min) / {five:.2f} (5 min)"


# ------------------------------------------------------------- study pipeline per pose
#: the tree measured as "before" in the study section: the branch point of perf-study-2
#: (main after run (8) of BENCHMARKS.md: lane kernels, 11.32 µs per pose there)
BASELINE_REV = "b654a07"

_BASELINE_SCRIPT = """
import json, time
import numpy as np
import distkin
from distkin.indices.study import evaluate_poses
from distkin.indices.workspace import table2_grid
from distkin.mechanisms import preset
P = table2_grid().poses(np.arange(0, 28))
out = {}
for name in ("octopod", "hunt"):
    mech = preset(name)
    evaluate_poses(mech, P[:50])                              # compile or load
    best = float("inf")
    for _ in range(5):
        t0 = time.process_time()
        evaluate_poses(mech, P)
        best = min(best, (time.process_time() - t0) / len(P))
    out[name] = best
out["tree"] = distkin.__file__
print(json.dumps(out))
"""


def _chunk_costs(mech):
    """CPU per pose of a sweep's per-position reductions (``study_chunk`` minus the
    ``evaluate_poses`` of its poses) and of writing its chunk (``runstore._save``), on a
    chunk of 16 positions × 729 orientations."""
    from distkin.indices.isotropy import ST_DEFAULT
    from distkin.indices.study import ACTUATORS, evaluate_poses, study_chunk
    from distkin.indices.workspace import table2_grid
    from distkin.runstore import _save
    grid = table2_grid()
    spec = {"mech": mech, "grid": grid, "lo": 0, "hi": 16, "actuators": dict(ACTUATORS),
            "ST": tuple(ST_DEFAULT), "inner": None, "route": "kernels", "batch": 20000,
            "sensitivity": "slice"}
    P = grid.poses(np.arange(0, 16))
    res = study_chunk(spec)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "chunk.npz")
        from pathlib import Path
        t = interleaved({"chunk": lambda: study_chunk(spec),
                         "evaluate": lambda: evaluate_poses(mech, P),
                         "save": lambda: _save(Path(path), res)}, rounds=5, cpu=True)
    n = len(P)
    return {"reductions": (t["chunk"][1] - t["evaluate"][1]) / n, "save": t["save"][1] / n,
            "save_per_chunk": t["save"][1]}


def _study_section(data):
    """The study's per-pose pipeline (IK, J, six capabilities, true velocities, four
    sliced sensitivities, σ of four readings, transmission): compiled against the numpy
    route, interleaved, CPU time; before (:data:`BASELINE_REV`) and after in fresh
    processes; stages in isolation."""
    from distkin.indices.capability import output_generators
    from distkin.indices.facets_lanes import capabilities_lanes
    from distkin.indices.isotropy import ST_DEFAULT, reading_singular_values
    from distkin.indices.jacobi_lanes import jacobi_lanes
    from distkin.indices.sensitivity import max_sensitivities
    from distkin.indices.study import ACTUATORS, QUANTITIES, _worst_cases, evaluate_poses
    from distkin.indices.study_compiled import reach_jq_jx
    from distkin.indices.workspace import table2_grid
    from distkin.mechanisms import preset
    from .harness import before_after
    mech = preset("octopod")
    P = table2_grid().poses(np.arange(0, 28))                # 28 positions x 729 = 20,412
    N = len(P)
    evaluate_poses(mech, P[:50])
    evaluate_poses(mech, P[:50], compiled=False)
    load0 = _load()
    med = interleaved({"compiled (study_compiled, SIMD kernels)":
                       lambda: evaluate_poses(mech, P),
                       "numpy route (reference; the code before issue 17)":
                       lambda: evaluate_poses(mech, P, compiled=False)},
                      rounds=5, cpu=True)
    names = list(med)
    per = {n: (w / N, c / N) for n, (w, c) in med.items()}
    ok, a = evaluate_poses(mech, P)
    _, b = evaluate_poses(mech, P, compiled=False)
    worst = max(float(np.max(np.abs(a[q] - b[q]) / np.maximum(np.abs(b[q]), 1e-300)))
                for q in QUANTITIES)
    # an L = 6 device (Hunt) on the same poses, for the five-device extrapolation
    hunt = preset("hunt")
    evaluate_poses(hunt, P[:50])
    cpu6 = interleaved({"hunt": lambda: evaluate_poses(hunt, P)}, rounds=5, cpu=True)
    cpu6 = cpu6["hunt"][1] / N
    # stages in isolation (CPU time per pose)
    _, Jq, J = reach_jq_jx(mech, P)
    M = np.array([mech.mass] * 3 + [mech.inertia] * 3)
    gens = output_generators(J, mass=M)
    st6 = np.asarray(ST_DEFAULT, float)
    sig, tw, flag = np.empty((N, 8)), np.empty((N, 6, 8)), np.zeros(N, bool)
    Z = jacobi_lanes(J, Jq, st6, sig, tw, flag)
    lims = np.array([ACTUATORS["nominal_torque"], ACTUATORS["stall_torque"],
                     ACTUATORS["velocity"]])
    caps = np.empty((N, 6))
    # σmin/σmax of Jᵀ from the Jacobi stage, as the pipeline passes it (without it
    # max_sensitivities runs an SVD of its own for its singular-J test)
    kap = np.divide(sig[:, 2], sig[:, 3], out=np.zeros(N), where=sig[:, 3] > 0)
    stages = {
        "kinematics: reach, Jq, Jx, J (compiled loop kernels)": lambda: reach_jq_jx(mech, P),
        "QR of J, Jacobi σ of 4 readings, J#, null space of Jᵀ":
            lambda: jacobi_lanes(J, Jq, st6, sig, tw, flag, Z),
        "6 capabilities (facets from the null space)":
            lambda: capabilities_lanes(J, tw, Z, M, lims, caps),
        "4 sliced sensitivities, split-sign (L = 8)":
            lambda: max_sensitivities(J, twist=tw, kappa=kap),
        "before: reach + Jq, Jx (batched numpy kernels)":
            lambda: (mech.reachable(P), mech.jq_jx(P)),
        "before: 4 sliced sensitivities, Gray-code walk":
            lambda: max_sensitivities(J, twist=tw, walk=True, kappa=kap),
        "before: generators (numpy pinv)": lambda: output_generators(J, mass=M),
        "before: 6 capabilities (numpy facets)": lambda: _worst_cases(J, gens, M, ACTUATORS),
        "before: σ of 4 readings (numpy SVD)":
            lambda: reading_singular_values(J, ST_DEFAULT, Jq=Jq),
    }
    st = interleaved(stages, rounds=3, cpu=True)
    stage = {k: v[1] / N for k, v in st.items()}
    chunk = _chunk_costs(mech)
    load1 = _load()
    ba = before_after(_BASELINE_SCRIPT, BASELINE_REV, rounds=3)
    load2 = _load()
    cpu_new, cpu_old = per[names[0]][1], per[names[1]][1]
    own = [k for k in stage if not k.startswith("before")]
    rest = cpu_new - sum(stage[k] for k in own)
    data["study"] = {"poses": N, "per_pose_wall_cpu_s": per, "speedup_cpu": cpu_old / cpu_new,
                     "max_rel_diff": worst, "stages_cpu_per_pose_s": stage,
                     "rest_cpu_per_pose_s": rest, "hunt_cpu_per_pose_s": cpu6,
                     "chunk_costs": chunk, "before_after_cpu_per_pose_s": ba,
                     "load": [load0, load1, load2]}
    lines = ["### Study pipeline per pose, Octopod (L = 8)", "",
             f"{N:,} poses of the Table II grid (28 positions × 729 orientations): IK, J, "
             "the six worst-case capabilities, the two true-velocity worst cases, the "
             "four sliced maximum sensitivities (eqs. (14), (16)), σmin/σmax of four "
             "readings of the scaling, the transmission and det J "
             "(`distkin.indices.study.evaluate_poses`).  Interleaved rounds, medians, "
             f"one process.  Load average {load0} at the start, {load1} at the end, on "
             "2 cores (other processes included); CPU time is what the target is judged on.",
             "",
             "| route | wall per pose | CPU per pose | CPU ratio to compiled |",
             "|---|---|---|---|"]
    for n, (w, c) in per.items():
        lines.append(f"| {n} | {fmt_time(w)} | {fmt_time(c)} | {c / cpu_new:.2f}× |")
    lines += ["", f"Speed-up {cpu_old / cpu_new:.2f}× in CPU time; target ≤ 8 µs per pose: "
              f"{'met' if cpu_new <= 8e-6 else f'not met ({cpu_new / 8e-6:.2f}× the target)'}."
              f"  Largest relative difference between the routes over all "
              f"{len(QUANTITIES)} quantities: {worst:.1e} (tests/indices/"
              "test_study_compiled.py holds it below 1e-10).  The same pipeline for an "
              f"L = 6 device (Hunt, the same poses): {fmt_time(cpu6)} per pose."]
    if ba:
        lines += ["", f"Before and after in this run: main at `{BASELINE_REV}` (the "
                  "lane kernels of run (8), extracted with `git archive`, its own numba "
                  "cache) and this tree, the same script in fresh processes, alternated "
                  "three times, best of five calls each, CPU time per pose of "
                  f"`evaluate_poses` on these {N:,} poses (load {load1} before, {load2} "
                  "after):", "",
                  "| device | before | after | before / after |", "|---|---|---|---|"]
        for k in ("octopod", "hunt"):
            lines.append(f"| {k} (L = {8 if k == 'octopod' else 6}) | "
                         f"{fmt_time(ba['before'][k])} | {fmt_time(ba['after'][k])} | "
                         f"{ba['before'][k] / ba['after'][k]:.2f}× |")
    lines += ["", "Stages in isolation (CPU per pose; \"before\" = the stages they replaced: "
              "the batched numpy kinematics and the numpy route's stages):", "",
              "| stage | CPU per pose |", "|---|---|"]
    for k, c in stage.items():
        lines.append(f"| {k} | {fmt_time(c)} |")
    lines += [f"| the rest of `evaluate_poses` (array handling between the kernels, "
              f"true velocities, transmission; the pipeline minus the four stages above) | "
              f"{fmt_time(rest)} |",
              f"| in a sweep, besides: per-position minima, maxima, worst orientations "
              f"(`study_chunk`) | {fmt_time(chunk['reductions'])} |",
              f"| in a sweep, besides: writing the chunk (`runstore._save`, "
              f"{chunk['save_per_chunk'] * 1e3:.2f} ms per chunk of 11,664 poses) | "
              f"{fmt_time(chunk['save'])} |"]
    sens = stage["4 sliced sensitivities, split-sign (L = 8)"]
    lines += ["", f"Of the {fmt_time(cpu_new)} per pose: the four sliced sensitivities "
              f"{fmt_time(sens)} ({100 * sens / cpu_new:.0f} %: 56 free sets × 16 sign "
              "vectors each, exact vertex enumeration, four poses per vector "
              "instruction); one Householder QR of J serving the σ of three readings, "
              "J# = R⁻¹Q₁ᵀ and the null space of Jᵀ, a second QR for Jx, and one-sided "
              "Jacobi on the 6 × 6 triangular factors; the facets from the null space; "
              "the kinematics compiled from the generated loop kernels."]
    return "\n".join(lines)


def scale_probe(n: int, compiled: bool, chunk: int, memory: bool = True) -> dict:
    """One measurement in a fresh process (``python -m benchmarks`` runs it by
    subprocess) on the first ``n`` poses of a 5 mm / 5° grid (±75 mm, ±20°; 21.7 million
    poses): CPU time of ``evaluate_poses`` and the growth of the peak resident set,
    then (``memory``) a second call under ``tracemalloc`` for its peak traced memory
    (tracemalloc slows the call by about a third, so it is not timed)."""
    import resource
    import tracemalloc

    from distkin.indices.study import QUANTITIES, evaluate_poses
    from distkin.indices.workspace import table2_grid
    from distkin.mechanisms import preset
    mech = preset("octopod")
    grid = table2_grid(step=0.005)
    P = grid.poses(np.arange(-(-n // grid.n_orientations)))[:n]
    evaluate_poses(mech, P[:100], compiled=compiled)
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    c0, w0 = time.process_time(), time.perf_counter()
    ok, vals = evaluate_poses(mech, P, compiled=compiled, chunk=chunk)
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    rss1 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    outputs = ok.nbytes + sum(vals[q].nbytes for q in QUANTITIES)
    peak = None
    if memory:
        del ok, vals
        tracemalloc.start()
        tracemalloc.reset_peak()
        ok, vals = evaluate_poses(mech, P, compiled=compiled, chunk=chunk)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return {"n": n, "compiled": compiled, "chunk": chunk, "cpu_s": cpu, "wall_s": wall,
            "peak_traced_bytes": peak, "output_bytes": outputs,
            "maxrss_growth_bytes": rss1 - rss0, "input_bytes": P.nbytes,
            "reachable": int(ok.sum())}


def _probe(n, compiled=True, chunk=2048, memory=True):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    code = ("import json, benchmarks.bench_indices as b; "
            f"print(json.dumps(b.scale_probe({n}, {compiled}, {chunk}, {memory})))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=env, check=True, cwd=os.path.dirname(os.path.dirname(
                             os.path.abspath(__file__))))
    r = json.loads(out.stdout.strip().splitlines()[-1])
    r["load"] = _load()
    return r


def _mib(b):
    return f"{b / 2 ** 20:,.1f} MiB"


def _scaling_section(data):
    """Cost per pose and peak memory against N (fresh process per row)."""
    rows = [_probe(n) for n in (10 ** 3, 10 ** 4, 10 ** 5, 10 ** 6)]
    rows.append(_probe(10 ** 7, memory=False))          # tracemalloc would add 7 minutes
    rows += [_probe(10 ** 4, False, 10 ** 4), _probe(10 ** 5, False, 10 ** 5),
             _probe(10 ** 5, False, 2048)]
    data["scaling"] = rows
    lines = ["### Scaling in N, and memory", "",
             "`evaluate_poses` on the first N poses of a 5 mm / 5° grid (±75 mm, ±20°), "
             "Octopod, one fresh process per row (OPENBLAS_NUM_THREADS=1): CPU time of "
             "the call and the growth of the process's peak resident set during it "
             "(0 where it stayed below the peak of the imports and warm-up, about "
             "0.5 GiB); "
             "then, in a second call not timed (tracemalloc slows it by about a third), "
             "the peak memory traced by `tracemalloc` (numpy reports its buffers to "
             "it), and that minus the results (22 float64 arrays and the `ok` mask, "
             "177 bytes per pose), which is the work memory.  Chunk = poses evaluated "
             "together.", "",
             "| route | N | chunk | CPU | CPU per pose | peak RSS growth | peak traced "
             "| results | work memory | load (1 / 5 min) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        route = "compiled" if r["compiled"] else "numpy (reference)"
        chunk = "N (unchunked)" if r["chunk"] == r["n"] else f"{r['chunk']:,}"
        pk = r["peak_traced_bytes"]
        lines.append(f"| {route} | {r['n']:,} | {chunk} | {r['cpu_s']:.2f} s | "
                     f"{fmt_time(r['cpu_s'] / r['n'])} | {_mib(r['maxrss_growth_bytes'])} | "
                     f"{_mib(pk) if pk is not None else 'not run'} | "
                     f"{_mib(r['output_bytes'])} | "
                     f"{_mib(pk - r['output_bytes']) if pk is not None else '-'} | "
                     f"{r['load']} |")
    un = [r for r in rows if not r["compiled"] and r["chunk"] == r["n"]]
    if un:
        r = un[-1]
        lines += ["", f"Unchunked, the numpy route needs "
                  f"{(r['peak_traced_bytes'] - r['output_bytes']) / r['n'] / 1024:.1f} KiB "
                  "of work memory per pose (what `zonotope_worst` and `evaluate_poses` did "
                  "before issue 17: 9.4 GiB at N = 1e6); chunked, the work memory of "
                  "either route is that of one chunk, whatever N (at N = 1e7 the peak "
                  "RSS grows by the results and about one chunk's work memory).  N = 1e7 "
                  "fits: 1.7 GiB of results on a 24 GiB machine, about 5 CPU minutes."]
    return "\n".join(lines)


# ------------------------------------------------------- grid resolution, processes
def _grid_run(grid, workers):
    from distkin.indices.study import Device, run_device
    from distkin.runstore import local_executor
    from distkin.mechanisms import preset
    dev = Device("Octopod", preset("octopod"), grid, "octopod")
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        with local_executor(workers) as ex:
            per, _ = run_device(dev, store=tmp, executor=ex, chunk_positions=16,
                                progress=False)
        return time.perf_counter() - t0, int(per["n_ok"].sum())


def _resolution_section(data):
    """Wall time of a whole sweep against the grid resolution (1 worker process), and
    the speed-up of 2 worker processes on one grid."""
    from distkin.indices.workspace import table2_grid
    grids = [("30 mm, 10°", table2_grid(step=0.030, rot_step_deg=10)),
             ("15 mm, 10°", table2_grid(step=0.015, rot_step_deg=10)),
             ("10 mm, 10°", table2_grid(step=0.010, rot_step_deg=10)),
             ("10 mm, 5° (Table II)", table2_grid())]
    rows = []
    for label, g in grids[:3]:
        load = _load()
        w, _ = _grid_run(g, 1)
        rows.append({"grid": label, "poses": g.size, "workers": 1, "wall_s": w, "load": load})
    g = grids[2][1]
    load = _load()
    w2, _ = _grid_run(g, 2)
    rows.append({"grid": grids[2][0], "poses": g.size, "workers": 2, "wall_s": w2,
                 "load": load})
    data["resolution"] = rows
    w1 = rows[2]["wall_s"]
    lines = ["### Time against grid resolution; 2 processes", "",
             "Whole Octopod sweeps (`run_device`, chunks of 16 positions written to disk, "
             "worker processes with OPENBLAS_NUM_THREADS=1; wall time includes starting "
             "the workers and loading the compiled kernels from the numba cache), ±75 mm, "
             "±20°:", "",
             "| grid (position step, orientation step) | poses | workers | wall | wall per "
             "pose | load before (1 / 5 min) |", "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['grid']} | {r['poses']:,} | {r['workers']} | {r['wall_s']:.1f} s "
                     f"| {fmt_time(r['wall_s'] / r['poses'])} | {r['load']} |")
    lines += ["", f"Speed-up of 2 processes over 1 on the 10 mm, 10° grid: {w1 / w2:.2f}× "
              "(the machine has 2 cores; the load is in the table)."]
    return "\n".join(lines)


def _table2_section(data):
    from distkin.indices.study import Device, run_device
    from distkin.runstore import local_executor
    from distkin.indices.workspace import table2_grid
    from distkin.mechanisms import preset
    mech = preset("octopod")
    grid = table2_grid()
    dev = Device("Octopod", mech, grid, "octopod")
    workers = os.cpu_count() or 1
    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        with local_executor(workers) as ex:
            per, _ = run_device(dev, store=tmp, executor=ex, chunk_positions=16,
                                progress=False)
        wall = time.perf_counter() - t0
    load = (load0 + os.getloadavg()[0]) / 2
    reach = int(per["n_ok"].sum())
    cpu = (next(iter(data["study"]["per_pose_wall_cpu_s"].values()))[1]
           if "study" in data else None)
    cpu6 = data["study"]["hunt_cpu_per_pose_s"] if "study" in data else None
    wpp = wall / grid.size
    # the five devices: three L = 6 on this grid (3 x 2,985,984), two L = 8 on a ±30°
    # grid of about 9 million poses each; L = 6 poses at the CPU ratio Hunt / Octopod
    est = 27e6 * wpp if not (cpu and cpu6) else wpp * (18e6 + 9e6 * cpu6 / cpu)
    res = data.get("resolution") or []
    sp = (res[2]["wall_s"] / res[3]["wall_s"]) if len(res) >= 4 else None
    data["table2"] = {"poses": grid.size, "reachable": reach, "seconds": wall,
                      "workers": workers, "us_per_pose": wall / grid.size * 1e6,
                      "load_average": load}
    return "\n".join([
        "### Full Table II grid, Octopod",
        "",
        f"{grid.size:,} poses (16³ positions × 9³ orientations, ±20°): IK, Jacobian, six "
        f"worst-case capabilities with their slices, the two true-velocity worst cases, "
        f"the paper's four sliced maximum sensitivities (compiled vertex enumeration), "
        f"the singular values of four readings of the scaling, the transmission and "
        f"det J; {workers} worker processes (OPENBLAS_NUM_THREADS=1), chunks of 16 "
        f"positions written to disk.",
        "",
        f"Wall time **{wall:.1f} s** ({fmt_time(wall / grid.size)} per pose, "
        f"{reach:,} poses reachable) — target < 10 min: "
        f"{'met' if wall < 600 else 'NOT met'}. Machine load average during the run "
        f"about {load:.1f} on {os.cpu_count()} cores (other processes included).",
        "",
        f"Extrapolated to the whole five-device study (27 million poses: three L = 6 "
        f"devices on this grid, 9.0 million poses, the two L = 8 devices on a ±30° grid "
        f"of about 9 million poses each) from this run's wall time per pose on "
        f"{workers} processes ({fmt_time(wpp)}, L = 8)"
        + (f" and, for the L = 6 poses, that times the ratio of the CPU per pose of "
           f"Hunt and Octopod in the study section ({fmt_time(cpu6)} / {fmt_time(cpu)})"
           if cpu and cpu6 else "")
        + f": **{est / 60:.1f} min** on {workers} processes — target < 4 min: "
        f"{'met' if est < 240 else 'not met'} at this load (upper bound at the L = 8 cost "
        f"for every pose: {27e6 * wpp / 60:.1f} min).  "
        + (f"From CPU time alone (the study section's per-pose costs, "
           f"{(18e6 * cpu + 9e6 * cpu6) / 60:.1f} CPU-minutes) at the measured 2-process "
           f"speed-up of the grid-resolution table ({sp:.2f}×): "
           f"{(18e6 * cpu + 9e6 * cpu6) / sp / 60:.1f} min, without the sweep's "
           f"reductions and start-up."
           if cpu and cpu6 and sp else "")])


def _culling_section(data):
    from distkin.indices.design import DesignSpace, sweep_designs
    from distkin.indices.workspace import table2_grid
    deg = math.pi / 180
    space = DesignSpace("hunt", (("l2", tuple(np.arange(7) * 0.005)),
                                 ("beta", tuple(np.arange(4) * 10 * deg)),
                                 ("gamma", tuple(np.arange(4) * 10 * deg)),
                                 ("ld", tuple(0.020 + np.arange(5) * 0.005))))
    grid = table2_grid(step=0.050, rot_deg=20, rot_step_deg=20)
    poses = grid.poses(np.arange(grid.n_positions))
    r = sweep_designs(space, poses, algorithm="both", progress=False)
    c, b = r["culling"], r["brute_force"]
    data["culling"] = {"designs": r["n_designs"], "poses": r["n_poses"], "agree": r["agree"],
                       "culling_s": c["seconds"], "brute_s": b["seconds"],
                       "culling_evals": c["evaluations"], "brute_evals": b["evaluations"],
                       "best": r["parameters"], "gii": r["gii"]}
    return "\n".join([
        "### GII design sweep: Stocco's culling against brute force",
        "",
        f"Table I's {r['n_designs']} designs × {r['n_poses']:,} poses (4³ positions, 50 mm "
        f"step × 3³ orientations, ±20°), one process, numpy IK/Jacobian.",
        "",
        "| algorithm | (design, pose) evaluations | time |", "|---|---|---|",
        f"| brute force | {b['evaluations']:,} | {b['seconds']:.2f} s |",
        f"| culling | {c['evaluations']:,} | {c['seconds']:.2f} s |",
        "",
        f"Speed-up {b['seconds'] / c['seconds']:.2f}× in time, "
        f"{b['evaluations'] / c['evaluations']:.2f}× in evaluations; same optimum and GII "
        f"bit for bit: {'yes' if r['agree'] else 'NO'} (GII {r['gii']:.4g})."])


def _slice_section(data):
    """The paper's sliced maximum sensitivity (eq. (16) after eq. (14)): the compiled
    vertex enumeration against the numpy one and the Qhull route, same Jacobians."""
    from distkin.indices.capability import hull_multi
    from distkin.indices.slice_farthest import slice_farthest_unit
    from distkin.indices.zonotope import zonotope_best
    from distkin.mechanisms import preset
    mech = preset("octopod")
    poses = _poses(mech, 2000, 30, seed=1)
    G = np.ascontiguousarray(np.linalg.pinv(mech.jacobian(poses)))   # J#, (N, 6, 8)
    N, _, L = G.shape
    c, r = np.zeros((N, L)), np.ones((N, L))
    one = np.ones(L)
    n_hull = 4
    slice_farthest_unit(G[:2], (0, 1, 2))                           # compile outside timing
    comp = {"compiled": lambda: slice_farthest_unit(G, (0, 1, 2)),
            "numpy": lambda: zonotope_best(G, c, r, [(0, 1, 2)]),
            "hull": lambda: [hull_multi(G[i], -one, one, [(0, 1, 2)]) for i in range(n_hull)]}
    med = interleaved(comp, rounds=5)
    per = {"compiled": med["compiled"] / N, "numpy": med["numpy"] / N,
           "hull": med["hull"] / n_hull}
    a = slice_farthest_unit(G, (0, 1, 2))
    b = zonotope_best(G, c, r, [(0, 1, 2)])[0]
    h = np.array([hull_multi(G[i], -one, one, [(0, 1, 2)])[0][1] for i in range(n_hull)])
    data["slice_sensitivity"] = {"per_pose_s": per,
                                 "max_rel_diff_numpy": float(np.max(np.abs(a - b) / b)),
                                 "max_rel_diff_hull": float(np.max(np.abs(a[:n_hull] - h) / h))}
    return "\n".join([
        "### Sliced maximum sensitivity (eq. (16) after the slice (14)), Octopod (L = 8)",
        "",
        f"Translational sensitivity at zero rotation, |δq|∞ <= 1 rad, on {N} reachable "
        f"poses (±75 mm, ±30°): the compiled enumeration of the C(8, 3)·2^5 vertex "
        f"candidates (`distkin.indices.slice_farthest`, numba) against the same "
        f"enumeration in numpy (`zonotope_best`) and the paper's hull route (Qhull, "
        f"{n_hull} poses).",
        "", ratio_table(per, "compiled", per="pose"), "",
        f"Largest relative difference: numpy {data['slice_sensitivity']['max_rel_diff_numpy']:.1e}, "
        f"hull {data['slice_sensitivity']['max_rel_diff_hull']:.1e}."])


def run():
    data = {}
    parts = [_kernels_section(data), _slice_section(data), _study_section(data),
             _culling_section(data), _scaling_section(data), _resolution_section(data),
             _table2_section(data)]
    return "\n\n".join(parts) + "\n", data
