"""Formulas printed in Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*,
Sec. VI, transcribed for the tests (the reference, not our code)."""

import sympy as sp

__all__ = ["printed_det"]

R = sp.Rational


def printed_det(D1, D2):
    """det(A) of the Griffis-Duffy example as printed in Sec. VI (offsets Δ1, Δ2)."""
    return (-R(1, 20736) * D1**3 * D2**2 - R(1, 10368) * D1**2 * D2**3 + R(1, 3456) * D1**3 * D2
            + R(1, 576) * D1**2 * D2**2 + R(1, 864) * D1 * D2**3 - R(1, 1728) * D1**3
            - R(1, 96) * D1**2 * D2 - R(1, 48) * D1 * D2**2 - R(1, 216) * D2**3 + R(1, 48) * D1**2
            + R(1, 8) * D1 * D2 + R(1, 12) * D2**2 - R(1, 4) * D1 - R(1, 2) * D2 + 1)
