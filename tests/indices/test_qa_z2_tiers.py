"""QA Z2 7: the index functions take method="fast" (the README's tier argument) and
refuse "precise"/"certified" with an InputError naming ``method`` and the certified
route; worst/best_case_output choose their algorithm with ``algorithm=`` and still
take the algorithm names as ``method=``."""

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.indices import (best_case_output, condition_number, gii, max_sensitivities,
                             scaled_singular_values, true_velocity_worst,
                             worst_case_output)

G = np.random.default_rng(4).normal(size=(6, 6))
J = G.T

CALLS = {
    "worst_case_output": lambda m: worst_case_output(G, -1, 1, method=m),
    "best_case_output": lambda m: best_case_output(G, -1, 1, method=m),
    "max_sensitivities": lambda m: max_sensitivities(J, method=m),
    "true_velocity_worst": lambda m: true_velocity_worst(J, 1.0, [0, 1, 2], method=m),
    "gii": lambda m: gii([0.5], [1.0], method=m),
    "scaled_singular_values": lambda m: scaled_singular_values(J, method=m),
    "condition_number": lambda m: condition_number(J, method=m),
}


@pytest.mark.parametrize("name", sorted(CALLS))
def test_fast_accepted_other_tiers_refused(name):
    CALLS[name]("fast")
    for tier in ("precise", "certified"):
        with pytest.raises(InputError) as exc:
            CALLS[name](tier)
        assert exc.value.field == "method" and repr(tier) in str(exc.value)
        assert "certify_workspace" in str(exc.value)


def test_algorithm_keyword_and_old_method_names():
    # the vertices of a box under an invertible G: Ueberle's worst case is the
    # smallest |1/||row_i(G⁻¹)|| (the facet distances), an analytic reference
    ref = np.min(1.0 / np.linalg.norm(np.linalg.inv(G), axis=1))
    for kw in ({}, {"method": "fast"}, {"algorithm": "ueberle"}, {"method": "ueberle"},
               {"method": "hull"}, {"algorithm": "hull", "method": "fast"}):
        assert worst_case_output(G, -1, 1, **kw) == pytest.approx(ref, rel=1e-9)
    with pytest.raises(InputError) as exc:
        worst_case_output(G, -1, 1, method="hull", algorithm="ueberle")
    assert exc.value.field == "method"
    with pytest.raises(InputError) as exc:
        worst_case_output(G, -1, 1, algorithm="lp")
    assert exc.value.field == "algorithm"


@pytest.mark.parametrize("arg", ["algorithm", "method"])
def test_ueberle_with_more_legs_names_the_argument_the_caller_used(arg):
    """Ueberle's method needs L = d: the refusal names the argument that chose it."""
    G = np.random.default_rng(1).normal(size=(6, 8))
    with pytest.raises(InputError) as exc:
        worst_case_output(G, -1.0, 1.0, **{arg: "ueberle"})
    assert exc.value.field == arg and f"{arg}='zonotope'" in str(exc.value)
