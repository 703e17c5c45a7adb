"""faultnet: Carlson-Langer block-spring earthquake models on networks.

The pipeline reads as the subpackage list: ``graphs`` -> ``model`` -> ``solver``
-> ``io`` -> ``runs``, and the catalogs go to ``stats``, ``seismicity`` and ``plotting``.

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
    "BFit": "faultnet.stats.magnitudes",
    "CarlsonLanger": "faultnet.model.carlson_langer",
    "EventTooLongError": "faultnet.exceptions",
    "FaultnetError": "faultnet.exceptions",
    "FitWarning": "faultnet.exceptions",
    "InvalidParameterError": "faultnet.exceptions",
    "NumericalInstabilityError": "faultnet.exceptions",
    "OFC": "faultnet.model.ofc",
    "RunOptions": "faultnet.solver.options",
    "SimulationError": "faultnet.exceptions",
    "SimulationResult": "faultnet.solver.result",
    "Simulator": "faultnet.solver.simulator",
    "SparseGraph": "faultnet.model.carlson_langer",
    "State": "faultnet.model.state",
    "build_model": "faultnet.runs.specs",
    "default_dt": "faultnet.solver.step_size",
    "fit_b_lsq": "faultnet.stats.magnitudes",
    "fit_b_mle": "faultnet.stats.magnitudes",
    "irregularity": "faultnet.stats.irregularity",
    "magnitude_distribution": "faultnet.stats.magnitudes",
    "read_catalog": "faultnet.io.parquet",
    "read_metadata": "faultnet.io.catalog_file",
    "read_slips": "faultnet.io.slips",
    "iter_slips": "faultnet.io.slips",
    "simulate": "faultnet.solver.engine",
    "simulate_to_parquet": "faultnet.runs.long_run",
    "slip_event": "faultnet.solver.engine",
    "summarize": "faultnet.runs.sweep.summary",
    "sweep": "faultnet.runs.sweep.driver",
    "write_catalog": "faultnet.io.parquet",
}
#: the public subpackages and modules, reachable as attributes of the package
_SUBMODULES = {
    "dynamics": "faultnet.solver.dynamics",
    "graphs": "faultnet.graphs",
    "plotting": "faultnet.plotting",
    "seismicity": "faultnet.seismicity",
    "stats": "faultnet.stats",
}


def __getattr__(name):
    import importlib

    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
    elif name in _SUBMODULES:
        value = importlib.import_module(_SUBMODULES[name])
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
    "OFC",
    "SimulationError",
    "SimulationResult",
    "Simulator",
    "RunOptions",
    "build_model",
    "read_catalog",
    "read_metadata",
    "read_slips",
    "iter_slips",
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
    "plotting",
    "simulate",
    "slip_event",
    "seismicity",
    "stats",
]
