"""Every error class faultnet raises, in one place.

All derive from :class:`FaultnetError`; each also derives from the built-in
exception a caller would expect (``ValueError`` for a bad argument,
``OSError`` for a bad file, ``RuntimeError`` for a failed run), so
``except ValueError`` keeps working.

>>> issubclass(InvalidParameterError, ValueError), issubclass(CatalogError, OSError)
(True, True)
"""

__all__ = [
    "AccuracyWarning",
    "CatalogError",
    "ConfigError",
    "EventTooLongError",
    "FaultnetError",
    "FitWarning",
    "GraphSpecError",
    "InvalidParameterError",
    "NumericalInstabilityError",
    "OutputExistsError",
    "OutputLockedError",
    "SimulationError",
    "SweepError",
]


class FaultnetError(Exception):
    """Base class of every faultnet error."""


class InvalidParameterError(FaultnetError, ValueError):
    """A model, graph or run parameter is outside its allowed range."""


class GraphSpecError(InvalidParameterError):
    """A graph spec could not be parsed or built; the message lists the valid forms."""


class ConfigError(InvalidParameterError):
    """A sweep configuration is malformed; the message names the field and the allowed values."""


class OutputExistsError(InvalidParameterError, FileExistsError):
    """Refusing to overwrite an existing output (pass force / overwrite)."""


class OutputLockedError(FaultnetError, RuntimeError):
    """Another process holds the lock of an output; the message names it."""


class CatalogError(FaultnetError, OSError):
    """A file is missing, truncated, corrupt or not a faultnet catalog."""


class SimulationError(FaultnetError, RuntimeError):
    """A run stopped because the numerics failed; the message says what to change."""


class NumericalInstabilityError(SimulationError):
    """The integration produced a non-finite or runaway velocity."""


class EventTooLongError(SimulationError):
    """A slip event lasted longer than the allowed duration."""


class SweepError(FaultnetError, RuntimeError):
    """Some points of a sweep failed; ``summary`` holds the table of all points."""

    def __init__(self, message, summary=None):
        super().__init__(message)
        self.summary = summary


class AccuracyWarning(UserWarning):
    """A run whose accuracy faultnet cannot vouch for (for example ``rtol`` outside the
    parameters its calibration was measured at)."""


class FitWarning(UserWarning):
    """A fit returned numbers that do not pin its model down: a parameter at its search bound,
    one larger than its window, or an error larger than the value (the numbers are returned
    all the same)."""
