"""faultnet: Carlson-Langer block-spring earthquake models on networks.

The pipeline reads as the module list: ``graphs`` -> ``model`` ->
``options`` -> ``engine`` -> ``catalog`` -> ``stats``, ``seismicity`` and ``plots``.

>>> import faultnet
>>> model = faultnet.CarlsonLanger(faultnet.graphs.ring(50), k=16, sigma=0.01, alpha=1.0)
>>> result = faultnet.simulate(model, n_events=200, rng=1, progress=False)
>>> len(result.events)
200
"""

from faultnet._version import __version__

# Every public name is loaded on first use: ``import faultnet`` costs almost
# nothing, and a Ctrl-C while the command line starts lands in its own handler
# (``faultnet.__main__``) instead of in the middle of this file's imports.
_LAZY = {
    "AccuracyWarning": "faultnet.exceptions",
    "BFit": "faultnet.stats",
    "CarlsonLanger": "faultnet.model",
    "EventTooLongError": "faultnet.exceptions",
    "FaultnetError": "faultnet.exceptions",
    "FitWarning": "faultnet.exceptions",
    "InvalidParameterError": "faultnet.exceptions",
    "NumericalInstabilityError": "faultnet.exceptions",
    "RunOptions": "faultnet.options",
    "SimulationError": "faultnet.exceptions",
    "SimulationResult": "faultnet.catalog",
    "Simulator": "faultnet.engine",
    "SparseGraph": "faultnet.model",
    "State": "faultnet.state",
    "build_model": "faultnet.specs",
    "default_dt": "faultnet.options",
    "fit_b_lsq": "faultnet.stats",
    "fit_b_mle": "faultnet.stats",
    "graph_hash": "faultnet.specs",
    "irregularity": "faultnet.stats",
    "magnitude_distribution": "faultnet.stats",
    "read_catalog": "faultnet.io",
    "read_metadata": "faultnet.io",
    "simulate": "faultnet.engine",
    "simulate_to_parquet": "faultnet.runner",
    "slip_event": "faultnet.engine",
    "summarize": "faultnet.sweep_summary",
    "sweep": "faultnet.sweep",
    "write_catalog": "faultnet.io",
}
#: submodules reachable as attributes of the package
_SUBMODULES = ("dynamics", "graphs", "seismicity", "stats")


def __getattr__(name):
    import importlib

    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
    elif name in _SUBMODULES:
        value = importlib.import_module(f"faultnet.{name}")
    else:
        raise AttributeError(f"module 'faultnet' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))


__all__ = [
    "__version__",
    "AccuracyWarning",
    "BFit",
    "CarlsonLanger",
    "SparseGraph",
    "EventTooLongError",
    "FaultnetError",
    "FitWarning",
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
    "seismicity",
    "stats",
]
