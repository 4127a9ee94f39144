"""The ``table5`` scene query: Table V of Kühne et al. emulated on the simulated device
(:mod:`distkin.control.table5`)."""

from __future__ import annotations

from ...argcheck import check_keys, fast_only, positive_int
from ...control.table5 import run_table5
from ...errors import InputError
from ...exact import parse_float
from ...numfmt import fixed
from ..query import Outcome, register
from ..units import angle_factor, length_factor

__all__ = ["Table5Query"]


@register("table5", mechanisms=("rss",),
          summary="Table V emulated: the worst-case experiments of Sec. III-D on the "
                  "simulated device")
class Table5Query:
    """``type = "table5"``: ``trials`` (5), ``step`` (40, scene length unit),
    ``step_angle`` (0.4 rad or the scene's angle unit), ``grid`` (coarse: 25 mm,
    10°, ±30°).

    With ``--plots``: ``q{i}_table5_comparison.png`` (:mod:`.table5_plot`), every row
    beside our analysis and the paper's columns, and the time trace of one trial per
    row (asked of the run only then: ``traces = True``, which changes no number)."""

    @staticmethod
    def parse(table, mechanism, units, field):
        check_keys(table, {"type", "trials", "step", "step_angle", "method"}, field)
        fast_only(table, field, "the Table V experiment (the controller's float64 kernels)",
                  "the forward_kinematics query takes method = 'certified' for a proved pose")
        lf, af = length_factor(units, "units"), angle_factor(units)
        trials = positive_int(table.get("trials", 5), f"{field}.trials")
        # each step in the scene's units, and each refused by its own name in them
        # (QA X1 D5: step_angle = -5 in a deg scene was "step: ... -0.0873 rad")
        step_u = parse_float(table["step"], f"{field}.step") if "step" in table \
            else 0.040 / lf
        ang_u = parse_float(table["step_angle"], f"{field}.step_angle") \
            if "step_angle" in table else 0.4 / af
        for key, v, unit in (("step", step_u, units.length), ("step_angle", ang_u,
                                                              units.angle)):
            if not v > 0:
                raise InputError(f"expected a positive {key.replace('_', ' ')} ({unit}, "
                                 f"the scene's unit), got {v:g} {unit}",
                                 field=f"{field}.{key}")
        step, ang = step_u * lf, ang_u * af
        if mechanism.name.rstrip("*") not in ("octo", "octopod", "hunt", "hexa", "ergin"):
            raise InputError(f"expected a preset mechanism, got {mechanism.name!r}",
                             field="mechanism.preset")
        return (mechanism.name, trials, step, ang, (units.length, lf, units.angle, af))

    @staticmethod
    def run(p, scene, ctx):
        name, trials, step, ang, (lu, lf, au, af) = p
        if name.endswith("*"):
            raise InputError("expected an unmodified preset for the simulated device, "
                             f"got {name!r}", field="mechanism")
        more = {"traces": True} if ctx.plots_dir is not None else {}
        res = run_table5(name, trials=trials, step_m=step, step_rad=ang,
                         units={"step": ("step", lu, 1 / lf),
                                "step_angle": ("step_angle", au, 1 / af)}, **more)
        traces = {row: r.pop("trace") for row, r in res.items() if "trace" in r}
        lines = [f"Table V emulated on the simulated '{name}' ({trials} trials of each "
                 "blocked row, the mean; one of each free row, deterministic; "
                 "distkin.control.table5)", "",
                 "| Output capability | emulated experiment | our analysis (minimum over "
                 "the 25 mm / 10° grid, ±30°) | emulated / analysis | paper experiment | "
                 "paper simulation (its Table III) | emulated / paper experiment |",
                 "|---|---|---|---|---|---|---|"]
        for row, r in res.items():
            u = r["unit"]
            # ours in 4 significant digits, fixed notation; the paper's as printed there
            lines.append(f"| {row.replace('_', ' ')} [{u}] | {fixed(r['emulated'])} | "
                         f"{fixed(r['analysis'])} | {fixed(r['emulated'] / r['analysis'], 3)}× "
                         f"| {r['paper_experiment']} | {r['paper_simulation']} | "
                         f"{fixed(r['emulated'] / r['paper_experiment'], 3)}× |")
        lines.append("")
        lines.append("Blocked rows (force, torque): nominal torque, the wrench on the "
                     "block along the worst direction; for L = 6 it equals the analysis, "
                     "for L = 8 the controller's minimum-norm torque distribution reaches "
                     "a little less than the zonotope's best distribution.  Free rows: "
                     f"stall torque, peak along the worst direction during a "
                     f"{step / lf:g} {lu} / {ang / af:g} {au} step that leaves the worst "
                     "pose at once (so the velocity "
                     "can exceed the analysis); the plant carries the motors' rotor "
                     "inertia, which eq. (7) leaves out (lower accelerations).  The "
                     "paper's experiment stopped short of the velocity and acceleration "
                     "maxima.")
        for r in res.values():       # the worst poses in the scene's units, as written
            r["pose"] = [v / (lf if i < 3 else af) for i, v in enumerate(r["pose"])]
        lines.append(f"Worst poses (x, y, z {lu}; rx, ry, rz {au}): " + "; ".join(
            f"{row.replace('_', ' ')} ({', '.join(f'{v:.4g}' for v in r['pose'])})"
            for row, r in res.items()))
        unit = {"pose": f"{lu}, {lu}, {lu}, {au}, {au}, {au}",
                "direction": "none (a unit vector: the row's three components of "
                             "f, m or v, w; the other three 0)",
                "step": lu, "step_angle": au, "rows": "each row's own unit"}
        result = {"rows": res, "step": step / lf, "step_angle": ang / af, "unit": unit}
        return Outcome(result, "\n".join(lines), _plotter(result, traces, name, lu, au))


def _plotter(result, traces, name, lu, au):
    """The ``--plots`` drawer: :func:`.table5_plot.plot_table5` of the result as the
    JSON has it (poses in the scene's units) and the run's traces."""
    def plot(stem):
        from .table5_plot import plot_table5
        return plot_table5(stem, result, traces or None, name=name, length_unit=lu,
                           angle_unit=au)
    return plot
