"""faultnet: Carlson-Langer block-spring earthquake models on networks.

The pipeline reads as the module list: ``graphs`` -> ``model`` ->
``simulate`` -> ``catalog`` (and later statistics and plots).

>>> import faultnet
>>> model = faultnet.CarlsonLanger(faultnet.graphs.ring(50), k=16, sigma=0.01, alpha=1.0)
>>> result = faultnet.simulate(model, n_events=200, rng=1, progress=False)
>>> len(result.events)
200
"""

from importlib.metadata import PackageNotFoundError, version

from faultnet import dynamics, graphs, stats
from faultnet.catalog import SimulationResult
from faultnet.exceptions import (
    EventTooLongError,
    FaultnetError,
    InvalidParameterError,
    NumericalInstabilityError,
    SimulationError,
)
from faultnet.model import CarlsonLanger
from faultnet.simulate import default_dt, simulate, slip_event
from faultnet.stats import BFit, fit_b_lsq, fit_b_mle, irregularity, magnitude_distribution
from faultnet.state import State

try:
    __version__ = version("faultnet")
except PackageNotFoundError:  # running from a source tree
    __version__ = "0+unknown"

__all__ = [
    "BFit",
    "CarlsonLanger",
    "EventTooLongError",
    "FaultnetError",
    "InvalidParameterError",
    "NumericalInstabilityError",
    "SimulationError",
    "SimulationResult",
    "State",
    "default_dt",
    "dynamics",
    "fit_b_lsq",
    "fit_b_mle",
    "graphs",
    "irregularity",
    "magnitude_distribution",
    "simulate",
    "slip_event",
    "stats",
]
