"""Kühne et al.'s published reference values: Table III (the worst-case output
capabilities and maximum sensitivities, min and max over the workspace) and Table IV
(GII, σmin, σmax of the isotropy index) per kinematics, in the study's row names
(:data:`~.study.CAPABILITIES`, :data:`~.study.SENSITIVITIES`)."""

from __future__ import annotations

__all__ = ["TABLE3_ROWS", "PAPER_TABLE3", "PAPER_TABLE4"]

#: the rows of Table III in its order: the six capabilities, the four sensitivities
TABLE3_ROWS = ("force", "torque", "velocity", "angular_velocity", "acceleration",
               "angular_acceleration", "sens_translational", "sens_rotational",
               "sens_force", "sens_torque")

_T3 = {  # Table III: min (max) of each row, in the order of TABLE3_ROWS
    "ergin": [(0.00, 12.72), (0.00, 0.59), (2.78, 7.85), (67.99, 182.63), (0.00, 1023.37),
              (0.00, 26685.08), (0.16, 0.31), (4.56, 14.83), (11.96, 38.15), (0.36, 0.87)],
    "hexa": [(0.57, 26.25), (0.03, 1.17), (2.78, 8.01), (69.06, 175.17), (45.78, 2112.64),
             (1239.99, 53511.95), (0.18, 0.38), (3.68, 9.22), (16.37, 35.37), (0.62, 1.25)],
    "hunt": [(1.89, 40.16), (0.05, 1.75), (2.86, 7.98), (64.57, 150.46), (152.02, 3231.29),
             (2381.37, 79653.37), (0.18, 0.34), (3.67, 6.13), (19.08, 32.64), (1.12, 2.18)],
    "octopod": [(21.68, 63.19), (0.86, 2.80), (2.74, 10.06), (75.57, 214.71),
                (1744.46, 5085.15), (39388.53, 125632.59), (0.17, 0.32), (2.93, 6.35),
                (22.34, 43.83), (1.04, 2.41)],
    "octo": [(16.02, 44.11), (0.75, 2.14), (2.93, 10.18), (84.44, 225.28), (1289.19, 3631.16),
             (34341.13, 100646.94), (0.17, 0.34), (3.58, 8.18), (18.08, 43.88), (0.77, 1.78)],
}
#: Kühne et al., Table III (min, max) per preset and row
PAPER_TABLE3 = {k: dict(zip(TABLE3_ROWS, v)) for k, v in _T3.items()}
#: Kühne et al., Table IV: (GII, σmin, σmax)
PAPER_TABLE4 = {"hunt": (0.0006, 0.0127, 20.0052), "octopod": (0.0080, 0.2230, 27.8186),
                "octo": (0.0072, 0.1910, 26.6404)}
