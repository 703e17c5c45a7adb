"""faultnet: Carlson-Langer block-spring earthquake models on networks.

The pipeline reads as the module list: ``graphs`` -> ``model`` ->
``simulate`` -> ``catalog`` (and later statistics and plots).

>>> import faultnet
>>> model = faultnet.CarlsonLanger(faultnet.graphs.ring(50), k=16, sigma=0.01, alpha=1.0)
>>> result = faultnet.simulate(model, n_events=200, rng=1, progress=False)
>>> len(result.events)
200
"""

from faultnet import dynamics, graphs, stats
from faultnet._version import __version__
from faultnet.catalog import SimulationResult
from faultnet.engine import Simulator, simulate, slip_event
from faultnet.exceptions import (
    EventTooLongError,
    FaultnetError,
    InvalidParameterError,
    NumericalInstabilityError,
    SimulationError,
)
from faultnet.model import CarlsonLanger, SparseGraph
from faultnet.options import RunOptions, default_dt
from faultnet.state import State
from faultnet.stats import BFit, fit_b_lsq, fit_b_mle, irregularity, magnitude_distribution

# Parquet I/O, long runs and sweeps import pyarrow and friends: load on first use
# so that ``import faultnet`` stays fast.
_LAZY = {
    "read_catalog": "faultnet.io",
    "read_metadata": "faultnet.io",
    "write_catalog": "faultnet.io",
    "simulate_to_parquet": "faultnet.runner",
    "build_model": "faultnet.specs",
    "graph_hash": "faultnet.specs",
    "summarize": "faultnet.sweep_summary",
    "sweep": "faultnet.sweep",
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'faultnet' has no attribute {name!r}")


__all__ = [
    "__version__",
    "BFit",
    "CarlsonLanger",
    "SparseGraph",
    "EventTooLongError",
    "FaultnetError",
    "InvalidParameterError",
    "NumericalInstabilityError",
    "SimulationError",
    "SimulationResult",
    "Simulator",
    "RunOptions",
    "build_model",
    "graph_hash",
    "read_catalog",
    "read_metadata",
    "simulate_to_parquet",
    "summarize",
    "sweep",
    "write_catalog",
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
