"""The summary repr of :class:`distkin.octahedral.AssemblyResult` (QA 23b, 9)."""

import re

import pytest

from distkin.octahedral import forward_kinematics

#: Rojas et al., Sec. VI (the Griffis-Duffy example): the six real roots of the octic (11)
PAPER_S15 = (269.2, 328.7, 359.5, 463.6, 497.9, 513.0)
LEGS = (19.8, 18, 18, 17, 14.9, 17.8)


def _problem(scale, text):
    base = [[0, 0, 0], [6 * scale, f"{text}*sqrt(108)", 0], [12 * scale, 0, 0]]
    plat = [[0, 0, 0], [6 * scale, 0, 0], [3 * scale, f"{text}*sqrt(27)", 0]]
    return base, plat, [x * scale for x in LEGS]


def _printed_s15(text):
    inner = re.search(r"assembly roots \[([^\]]*)\]", text).group(1)
    return [float(v) for v in inner.split(",")] if inner.strip() else []


@pytest.mark.parametrize("method", ["fast", "certified"])
def test_repr_summarises_the_griffis_duffy_answer(method):
    r = forward_kinematics(*_problem(1, "1"), method=method)
    text = repr(r)
    assert len(text) < 400                        # the dataclass's repr was ~8000 characters
    assert f"method={method!r}" in text and "12 poses" in text and len(r) == 12
    assert _printed_s15(text) == pytest.approx(PAPER_S15, abs=0.051)
    assert ("certified" if method == "certified" else "proved") in text


def test_repr_of_a_certified_answer_at_1e_150():
    """The certified octic's Fractions have more than Python's 4300 digits here: the
    dataclass's repr raised ValueError."""
    r = forward_kinematics(*_problem(1e-150, "1e-150"), method="certified")
    s15 = _printed_s15(repr(r))
    assert [v / 1e-300 for v in s15] == pytest.approx(PAPER_S15, abs=0.051)


def test_repr_of_an_empty_answer_says_why():
    base, plat, _ = _problem(1, "1")
    r = forward_kinematics(base, plat, [100, 1, 1, 1, 1, 1], method="certified")
    assert len(r) == 0 and "0 poses" in repr(r) and r.reason and repr(r.reason) in repr(r)
