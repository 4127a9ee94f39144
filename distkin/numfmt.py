"""Numbers in messages: a value beside the bound it is compared with, printed with
enough digits that the printed pair says what the comparison said.

A value 1e-7 mm beyond a stroke end of 550 mm printed with ``:.6g`` reads "550 mm
outside its range [350, 550] mm" (QA): both round to the same text, and the refusal
looks wrong.  :func:`apart` prints the two with the fewest significant digits (at least
``digits``) that tell them apart, up to the 17 that tell any two float64 apart.
"""

from __future__ import annotations

__all__ = ["apart", "MAX_DIGITS"]

#: significant digits that tell any two distinct float64 apart (repr round trip)
MAX_DIGITS = 17


def apart(value: float, *bounds: float, digits: int = 6) -> tuple[str, ...]:
    """``value`` and ``bounds`` as text (``g`` format, the same number of significant
    digits for all), with the fewest digits >= ``digits`` at which ``value``'s text
    differs from every bound's that it differs from as a float.  Equal numbers stay
    equal; NaN and inf print as Python does.

    Examples
    --------
    >>> apart(550.0000001, 350.0, 550.0)
    ('550.0000001', '350', '550')
    >>> apart(1.5, 0.0, 3.0)
    ('1.5', '0', '3')
    """
    v = float(value)
    bs = [float(b) for b in bounds]
    n = max(1, int(digits))
    while True:
        texts = [f"{x:.{n}g}" for x in (v, *bs)]
        if n >= MAX_DIGITS or all(texts[0] != t for b, t in zip(bs, texts[1:]) if b != v):
            return tuple(texts)
        n += 1
