"""The ``table5`` scene query: Table V of Kühne et al. emulated on the simulated device
(:mod:`distkin.control.table5`)."""

from __future__ import annotations

from ...argcheck import check_keys, fast_only, positive_int
from ...control.table5 import run_table5
from ...errors import InputError
from ...exact import parse_float
from ..query import Outcome, register
from ..units import angle_factor, length_factor

__all__ = ["Table5Query"]


@register("table5", mechanisms=("rss",),
          summary="Table V emulated: the worst-case experiments of Sec. III-D on the "
                  "simulated device")
class Table5Query:
    """``type = "table5"``: ``trials`` (5), ``step`` (40, scene length unit),
    ``step_angle`` (0.4 rad or the scene's angle unit), ``grid`` (coarse: 25 mm,
    10°, ±30°)."""

    @staticmethod
    def parse(table, mechanism, units, field):
        check_keys(table, {"type", "trials", "step", "step_angle", "method"}, field)
        fast_only(table, field, "the Table V experiment (the controller's float64 kernels)",
                  "the forward_kinematics query takes method = 'certified' for a proved pose")
        lf, af = length_factor(units, "units"), angle_factor(units)
        trials = positive_int(table.get("trials", 5), f"{field}.trials")
        step = parse_float(table["step"], f"{field}.step") * lf \
            if "step" in table else 0.040
        ang = parse_float(table["step_angle"], f"{field}.step_angle") * af \
            if "step_angle" in table else 0.4
        if not (step > 0 and ang > 0):
            raise InputError(f"expected positive steps, got {step!r} m, {ang!r} rad",
                             field=f"{field}.step")
        if mechanism.name.rstrip("*") not in ("octo", "octopod", "hunt", "hexa", "ergin"):
            raise InputError(f"expected a preset mechanism, got {mechanism.name!r}",
                             field="mechanism.preset")
        return (mechanism.name, trials, step, ang)

    @staticmethod
    def run(p, scene, ctx):
        name, trials, step, ang = p
        if name.endswith("*"):
            raise InputError("expected an unmodified preset for the simulated device, "
                             f"got {name!r}", field="mechanism")
        res = run_table5(name, trials=trials, step_m=step, step_rad=ang)
        lines = [f"Table V emulated on the simulated '{name}' ({trials} trials each; "
                 "distkin.control.table5)", "",
                 "| Output capability | emulated experiment | our analysis (minimum over "
                 "the 25 mm / 10° grid, ±30°) | emulated / analysis | paper experiment | "
                 "paper simulation (its Table III) | emulated / paper experiment |",
                 "|---|---|---|---|---|---|---|"]
        for row, r in res.items():
            u = r["unit"]
            lines.append(f"| {row.replace('_', ' ')} [{u}] | {r['emulated']:.4g} | "
                         f"{r['analysis']:.4g} | {r['emulated'] / r['analysis']:.3g}× | "
                         f"{r['paper_experiment']} | {r['paper_simulation']} | "
                         f"{r['emulated'] / r['paper_experiment']:.3g}× |")
        lines.append("")
        lines.append("Blocked rows (force, torque): nominal torque, the wrench on the "
                     "block along the worst direction; for L = 6 it equals the analysis, "
                     "for L = 8 the controller's minimum-norm torque distribution reaches "
                     "a little less than the zonotope's best distribution.  Free rows: "
                     "stall torque, peak along the worst direction during a 40 mm / "
                     "0.4 rad step that leaves the worst pose at once (so the velocity "
                     "can exceed the analysis); the plant carries the motors' rotor "
                     "inertia, which eq. (7) leaves out (lower accelerations).  The "
                     "paper's experiment stopped short of the velocity and acceleration "
                     "maxima.")
        return Outcome({"rows": res}, "\n".join(lines))
