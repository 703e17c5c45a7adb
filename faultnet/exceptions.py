"""Domain errors raised by faultnet."""

__all__ = [
    "EventTooLongError",
    "FaultnetError",
    "InvalidParameterError",
    "NumericalInstabilityError",
    "SimulationError",
]


class FaultnetError(Exception):
    """Base class of every faultnet error."""


class InvalidParameterError(FaultnetError, ValueError):
    """A model, graph or run parameter is outside its allowed range."""


class SimulationError(FaultnetError, RuntimeError):
    """A run stopped because the numerics failed; the message says what to change."""


class NumericalInstabilityError(SimulationError):
    """The integration produced a non-finite or runaway velocity."""


class EventTooLongError(SimulationError):
    """A slip event lasted longer than the allowed duration."""
