r"""A rigorous bound on the float64 rounding of the leg map of eq. (8), Rojas, Borràs,
Thomas, *The Octahedral Manipulator Revisited*: :math:`l^2 = \mathbf A^{-1}(m^2 +
\mathbf b) = \mathbf A^{-1} m^2 + c` evaluated in float64 from float m-legs
(:meth:`.transform.DeltaTransform.map_legs_float`), which the fast 6-6 tier's proof must
cover (QA J 1).
"""

from __future__ import annotations

import numpy as np

__all__ = ["leg_map_error"]


def leg_map_error(Ainv, c, m_legs, l_sq) -> float:
    r"""A rigorous bound :math:`\rho` on the relative error of
    :meth:`.transform.DeltaTransform.map_legs_float`'s
    ``l_sq`` against the exact :math:`l^2 = \mathbf A^{-1}(m^2 + \mathbf b)` (eq. (8))
    of the exact m-legs, when each float m-leg is within :math:`u = 2^{-53}` relative
    of its exact value (floats exactly, parsed strings rounded once).

    Each entry of :math:`\mathbf A^{-1}`, :math:`c` and :math:`m_k^2` is rounded once
    and the dot product of 6 terms plus :math:`c` adds :math:`\gamma_7` (Higham,
    *Accuracy and Stability of Numerical Algorithms*, Sec. 3.1), so
    :math:`|\hat l_k^2 - l_k^2| \le E_k = 12u\,(|\mathbf A^{-1}|\,m^2 + |c|)_k`;
    :math:`\rho = \max_k E_k / (\hat l_k^2 - E_k)`, inf when some
    :math:`\hat l_k^2 \le E_k`.  Near an architectural singularity
    (:math:`\det\mathbf A \to 0`) :math:`|\mathbf A^{-1}|`, and so :math:`\rho`, grow
    like cond(A)·u: the error the fast tier's proof must cover (QA J 1).

    Parameters
    ----------
    Ainv : array (6, 6) float64, :math:`\mathbf A^{-1}` rounded entry by entry
    c : array (6,) float64, :math:`\mathbf A^{-1}\mathbf b` rounded, squared length units
    m_legs : array (6,) float64, length units
    l_sq : array (6,) float64, squared length units (from ``map_legs_float``)

    Returns
    -------
    float (dimensionless)
    """
    m = np.asarray(m_legs, dtype=float)
    E = (12.0 * 2.0 ** -53) * (np.abs(Ainv) @ (m * m) + np.abs(c)) * (1.0 + 2.0 ** -40)
    gap = np.asarray(l_sq, dtype=float) - E
    if not np.all(gap > 0):
        return float("inf")
    return float(np.max(E / gap))
