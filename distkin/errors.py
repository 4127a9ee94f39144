"""The distkin exception family.

Modelled on python-flint's ``FlintError > DomainError, UnableError``: a computation
that cannot decide says so with :class:`UncertifiedError` instead of guessing.

Every message names what was expected and what was received; where the error comes
from a scene file, :attr:`DistkinError.field` names the offending field
(for example ``query[2].legs``).
"""

from __future__ import annotations

__all__ = [
    "DistkinError",
    "InputError",
    "InfeasibleError",
    "NotFoundError",
    "DegenerateGeometryError",
    "SingularConfigurationError",
    "UncertifiedError",
    "LinkError",
    "ConditioningWarning",
    "CancellationWarning",
    "FloatRangeWarning",
    "GeometryWarning",
    "is_input_error",
    "warn",
]


class DistkinError(Exception):
    """Base class of every error distkin raises on purpose.

    Parameters
    ----------
    message : str
        One line, naming the expected and the received values.
    field : str, optional
        The scene field or argument the error comes from.
    hint : str, optional
        What to do about it.
    """

    #: short machine-readable kind used in the JSON contract
    kind = "distkin_error"

    def __init__(self, message: str, *, field: str | None = None, hint: str | None = None):
        self.message = message
        self.field = field
        self.hint = hint
        super().__init__(self.one_line())

    def one_line(self) -> str:
        text = self.message
        if self.field:
            text = f"{self.field}: {text}"
        if self.hint:
            text = f"{text} (hint: {self.hint})"
        return text

    def with_field(self, field: str) -> "DistkinError":
        """Return the same error, re-anchored at ``field`` (outermost name first)."""
        if self.field and not self.field.startswith(field):
            self.field = f"{field}.{self.field}"
        elif not self.field:
            self.field = field
        self.args = (self.one_line(),)
        return self


class InputError(DistkinError, ValueError):
    """Malformed input: wrong type, wrong shape, unknown name, unparsable number."""

    kind = "input"


class InfeasibleError(DistkinError, ValueError):
    """The data describe no real configuration (distances that cannot close, ...).

    Attributes
    ----------
    margin : float or None
        By how much the data fail (for trilateration: the negative squared height, in
        squared length units).
    """

    kind = "infeasible"

    def __init__(self, message: str, *, margin=None, field=None, hint=None):
        self.margin = margin
        super().__init__(message, field=field, hint=hint)


class NotFoundError(DistkinError, ArithmeticError):
    """A local method (Newton or Gauss-Newton from a start) found no answer from its
    start: not a proof that none exists (that is :class:`InfeasibleError`, or an empty
    answer where a global method proves it); another start may find one.  ``field``
    names the start (``guess``) where the caller gave one.

    Attributes
    ----------
    margin : float or None
        By how much the answer found misses (its units in the message).
    """

    kind = "not_found"

    def __init__(self, message: str, *, margin=None, field=None, hint=None):
        self.margin = margin
        super().__init__(message, field=field, hint=hint)


class DegenerateGeometryError(DistkinError, ValueError):
    """Coincident, collinear or coplanar points where a proper simplex is needed."""

    kind = "degenerate_geometry"


class SingularConfigurationError(DistkinError, ArithmeticError):
    """A pose at (or numerically at) a singularity where a regular one is required."""

    kind = "singular_configuration"


class UncertifiedError(DistkinError, ArithmeticError):
    """A certified computation could not decide the question at the precision allowed."""

    kind = "uncertified"


class LinkError(DistkinError, OSError):
    """Serial-link failure: cannot open, disconnected, or the peer stopped answering."""

    kind = "link"


class ConditioningWarning(UserWarning):
    """A fast (float64) answer that the tier could not prove (its count may be wrong).

    Raised as a warning, not an error: the answer is returned, with the reason, and
    ``method="auto"`` (or ``"certified"``) is the way to a trustworthy one.
    """


class CancellationWarning(ConditioningWarning):
    """A float64 Cayley-Menger determinant that may have lost most of its digits to
    cancellation (a nearly flat simplex, or a determinant that is 0 in exact
    arithmetic).  ``estimate`` is the relative error estimate (the largest of a batch),
    ``index`` the batch index it belongs to (``()`` unbatched).  Raised by
    :mod:`distkin.geometry.cm_float` (importable from there too)."""

    def __init__(self, message, estimate=float("inf"), index=()):
        super().__init__(message)
        self.estimate = estimate
        self.index = index


class FloatRangeWarning(RuntimeWarning):
    """A value computed in float64 (a Cayley-Menger determinant, a singularity
    condition, a capability or sensitivity index) beyond float64's normal range: a
    non-zero value below the smallest normal float64 (2.2e-308, returned subnormal or
    0.0) or above the largest (returned inf).  ``value`` holds the value as a decimal
    string (mantissa and exponent).  Raised by
    :func:`distkin.geometry.pow2_scale.scale_back`, for
    :mod:`distkin.geometry.cm_float`, :mod:`distkin.singularity.float_range` and
    :mod:`distkin.indices.float_scale`."""

    def __init__(self, message, value=""):
        super().__init__(message)
        self.value = value


class GeometryWarning(UserWarning):
    """A mechanism description that builds but is likely not the one meant: a home pose
    its legs do not reach, a preset override 100x or more off the preset's value (a
    length in another unit).  A warning, not an error: a design may be that far off on
    purpose (``warnings.simplefilter("error", GeometryWarning)`` refuses it).  Raised by
    :mod:`distkin.mechanisms` (importable from there too)."""


def is_input_error(exc: BaseException) -> bool:
    """True for errors caused by the user's data (CLI exit code 2)."""
    return isinstance(exc, (InputError, InfeasibleError, NotFoundError, DegenerateGeometryError,
                            SingularConfigurationError, UncertifiedError))


def warn(message, category=None) -> None:
    """:func:`warnings.warn` at the first frame outside the distkin package: the
    warning names the user's line whatever the depth of the kernel below the public
    function (Python 3.12's ``skip_file_prefixes``, by hand for 3.11).  A frame is
    inside when its module is distkin or below it (which also covers code that
    dataclasses generate for distkin's classes, whose file is ``<string>``); the
    import machinery's frames are not counted, as :func:`warnings.warn` skips them
    too.  ``message`` a warning instance, or a string with ``category``."""
    import sys
    import warnings
    level, frame = 1, sys._getframe(1)
    while frame is not None:
        if not _import_machinery(frame.f_code.co_filename):
            if not _in_distkin(frame.f_globals.get("__name__", "")):
                break
            level += 1
        frame = frame.f_back
    warnings.warn(message, category, stacklevel=level + 1)


def _in_distkin(module: str) -> bool:
    return module == "distkin" or module.startswith("distkin.")


def _import_machinery(filename: str) -> bool:
    """The frames that :func:`warnings.warn` does not count (CPython's
    ``_is_internal_frame``)."""
    return "importlib" in filename and "_bootstrap" in filename
