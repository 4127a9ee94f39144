"""The verdicts of the fast tier's proof (:mod:`.descartes`) and what they mean.

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III: the
real roots of the octic (eq. (3) squared twice) in the feasible interval are the
assembly modes; a verdict says whether the float64 count and classification of them is
proved, and if not, why.
"""

from __future__ import annotations

__all__ = ["VERDICTS", "SPLIT_STEPS", "NOT_CHECKED", "THIN_TRIANGLE"]

#: verdict codes of :func:`vouch` and what they mean
VERDICTS = {
    0: "proved: every assembly root is counted and classified right",
    1: "the inputs are out of the range the bounds cover (a squared length below 2^-1000 "
       "of the largest after normalisation, or a rounding bound beyond 10 % relative)",
    2: "the octic's sign at an end of the feasible interval is within its rounding bound: "
       "a root at the edge of assemblability",
    3: "the octic's sign between two roots found is within its rounding bound: two roots "
       "closer than float64 can separate (two assembly modes about to merge)",
    4: "a piece of the feasible interval holds more real roots than the fast tier found "
       "there, or cannot be resolved (close or multiple roots, or a complex pair next to "
       "the real axis)",
    5: "a piece of the feasible interval around a root found holds no real root of the "
       "exact octic (a root found twice, or a complex pair taken for real roots)",
    6: "a root's status (assembly or spurious) cannot be decided: a face or a banana "
       "tetrahedron is flat within the rounding bound there",
    7: "a root's proved status differs from the fast tier's",
    8: "the fast tier has an assembly root outside the feasible interval",
    9: "not checked: the proof was skipped (forward_kinematics_batched(..., "
       "prove=False), the bare fast tier)",
    10: "two real roots outside the feasible interval (spurious, outside what the proof "
        "covers) lie within 1e-4 relative of each other: float64's count of the real "
        "roots is not reliable there (a multiple root split by rounding?); the assembly "
        "roots may be right",
    11: "not solved: the base or the platform triangle is thinner than float64 resolves "
        "(16 area^2 / (sum of squared sides)^2 <= 1e-12); method='auto' hands it to the "
        "certified tier, which refuses only a collinear one",
}
#: the verdict of a batched problem with a thin triangle (never returned by :func:`vouch`)
THIN_TRIANGLE = 11
#: why :func:`_vouch_split` left a problem to :func:`_vouch_bisect` (its return codes)
SPLIT_STEPS = {
    14: "the sign of H at an end of the feasible interval is not proved",
    15: "two roots found too close for a cut between them",
    16: "a piece not decided by subdivision (a sign at a cut, the budget, the width)",
    17: "a piece with no root or more than one",
    18: "a status differs from the fast tier's",
    19: "a status not decided",
}
#: the verdict of the problems of a batched solve that skipped the proof (never
#: returned by :func:`vouch`)
NOT_CHECKED = 9
