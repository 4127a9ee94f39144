"""Numbers in messages: a value beside the bound it is compared with, printed with
enough digits that the printed pair says what the comparison said.

A value 1e-7 mm beyond a stroke end of 550 mm printed with ``:.6g`` reads "550 mm
outside its range [350, 550] mm" (QA): both round to the same text, and the refusal
looks wrong.  :func:`apart` prints the two with the fewest significant digits (at least
``digits``) that tell them apart, up to the 17 that tell any two float64 apart.
"""

from __future__ import annotations

__all__ = ["apart", "MAX_DIGITS", "sig", "fixed"]

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


def sig(value, digits: int = 4) -> str:
    """``value`` with ``digits`` significant digits (``g`` format), never rounded to a
    misleading "0.00": 6.182e-05 stays 6.182e-05 (QA: a force-polytope title said
    "worst case 0.00 N" beside a table's 6.182e-05 N).  None and non-finite numbers print
    "—" and "inf"/"nan".

    >>> sig(6.18217e-05), sig(40.3412), sig(1.0), sig(15168.2)
    ('6.182e-05', '40.34', '1', '1.517e+04')
    """
    if value is None:
        return "—"
    return f"{float(value):.{max(1, int(digits))}g}"


def fixed(value, digits: int = 4) -> str:
    """``value`` with ``digits`` significant digits in fixed notation, trailing zeros
    kept, so that a column of numbers reads alike (Tables III-V; QA 24: Table V mixed
    "10.3", "9.921" and "2.346e+04"); exponent form at 1e5 and above and below 1e-3
    (``digits`` decimals below 1).  A value that rounds up into the next decade is
    printed as that rounded value, so that one ulp below 1 and 1 itself print alike
    (QA: "1.0000 (1.000)" for min = max).  None and non-finite numbers print "—".

    >>> fixed(10.3), fixed(9.921), fixed(23456.7), fixed(0.51123), fixed(1.2, 3)
    ('10.30', '9.921', '23457', '0.5112', '1.20')
    >>> fixed(0.9999999999999999), fixed(123456.0), fixed(float("nan"))
    ('1.000', '1.235e+05', '—')
    """
    import math
    x = value
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    r = float(f"{x:.{digits}g}")
    if x and r and math.floor(math.log10(abs(r))) != math.floor(math.log10(abs(x))):
        x = r
    ax = abs(x)
    if ax != 0 and (ax >= 1e5 or ax < 1e-3):
        return f"{x:.{digits - 1}e}"
    return f"{x:.{max(0, digits - 1 - int(math.floor(math.log10(ax))) if ax else 2)}f}" \
        if ax >= 1 else f"{x:.{digits}f}"
