"""The tier argument of the index functions (README "Three tiers of arithmetic").

Every index of Kühne et al. Sec. II-C (eqs. (4)-(16)) is computed in float64 only:
its entry points take ``method="fast"`` and refuse ``"precise"`` and ``"certified"``
with an :class:`~distkin.errors.InputError` naming ``method`` and saying where those
answers are: certified workspace regions (``certify_workspace``, a scene's
``certify = true``) and the kinematics queries at given poses, whose Jacobian can be
fed back to these functions.  Each function's docstring states how accurate its fast
answer is.  :func:`~.capability.worst_case_output` and
:func:`~.capability.best_case_output` choose their algorithm with ``algorithm=``; their
``method=`` also takes the algorithm names, as before (QA Z2 7).
"""

from __future__ import annotations

from ..errors import InputError

__all__ = ["fast_only", "TIERS"]

TIERS = ("fast", "precise", "certified")


def fast_only(method, what: str, also=()) -> None:
    """Accept ``method="fast"`` (or a name in ``also``); an InputError naming
    ``method`` otherwise, pointing to the certified routes for the other tiers."""
    if method == "fast" or (isinstance(method, str) and method in also):
        return
    expected = "'fast'" + "".join(f", {a!r}" for a in also)
    if method in TIERS:
        raise InputError(
            f"expected method {expected} ({what} is computed in float64 only), got "
            f"{method!r}", field="method",
            hint="certified answers: the certify_workspace query (or certify = true in a "
                 "study scene) for workspace regions; the jacobian, inverse_kinematics and "
                 "forward_kinematics queries at given poses")
    raise InputError(f"expected method {expected}, got {method!r}", field="method")
