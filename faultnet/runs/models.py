"""What a long run needs to know of each model: its simulator, options, work and transient.

A long run (:mod:`faultnet.runs.long_run`) drives the simulator of its model chunk after
chunk: a :class:`~faultnet.Simulator` for the Carlson-Langer model, an
:class:`~faultnet.solver.ofc.OFCSimulator` for the OFC automaton.  The two differ in a few
places, all here:

- the options: a Carlson-Langer run has :class:`~faultnet.RunOptions` and a step ``dt``; an
  automaton has neither (its identity records ``dt = 0`` and no options);
- the work counters summed over the chunks: integration steps and block-steps, or topplings
  and generations;
- the default transient of ``faultnet simulate``: the events before plate time 2 for the
  Carlson-Langer model; for the automaton, the events before the drive ``20 sqrt(N)`` (on a
  lattice of side L, ``20 L``: about twice the drive after which the avalanche sizes of the
  256², 128² and 64² fixed lattices at alpha = 0.2 stop drifting, ``benchmarks/README.md``).
"""

from __future__ import annotations

import math

import numpy as np

from faultnet._validate import check_int
from faultnet.exceptions import InvalidParameterError
from faultnet.model.carlson_langer import CarlsonLanger
from faultnet.model.ofc import OFC

__all__ = [
    "check_job",
    "check_model",
    "compiling_label",
    "job_options",
    "model_metadata",
    "new_simulator",
    "options_record",
    "random_start",
    "run_step",
    "time_name",
    "transient_time",
    "work_counters",
]

_NO_SLIPS = (
    "record_slips does not apply to an OFC model (the automaton's topplings are not slips of "
    "an integration); leave it out"
)
#: the work counters of each model's chunks, summed into the catalog's metadata
_WORK = {CarlsonLanger: ("n_steps", "block_steps"), OFC: ("n_topplings", "n_generations")}


def check_model(model):
    """Refuse anything but a model faultnet runs."""
    if not isinstance(model, CarlsonLanger | OFC):
        raise InvalidParameterError(
            f"model must be a CarlsonLanger or an OFC; got {type(model).__name__}"
        )
    return model


def job_options(model, options, dt, record_slips=False):
    """The run's options: :class:`~faultnet.RunOptions` with the ``dt`` shortcut applied, or
    None for an automaton (which refuses both, and ``record_slips``)."""
    from faultnet.solver.engine import run_options

    if isinstance(model, OFC):
        if record_slips:
            raise InvalidParameterError(_NO_SLIPS)
        given = [name for name, value in (("options", options), ("dt", dt)) if value is not None]
        if given:
            raise InvalidParameterError(
                f"{' and '.join(given)} do not apply to an OFC model (an automaton has no "
                "integration); leave them out"
            )
        return None
    return run_options(options, dt)


def options_record(model, options) -> dict:
    """The options as a run's identity and metadata record them."""
    if isinstance(model, OFC):
        return {"max_topplings": None}  # the long runs of an automaton set no limit
    return options.to_dict()


def run_step(model, options) -> float:
    """The integration step of a run (0.0 for an automaton)."""
    return 0.0 if options is None else options.step(model)


def work_counters(model) -> tuple:
    """The names of the work counters in the metadata of ``model``'s chunks."""
    return _WORK[type(model)]


def new_simulator(model, *, x0=None, rng=None, options=None, record_slips=False, max_slip_rows):
    """The simulator of a run of ``model``, from ``x0`` (a state) or from ``rng``."""
    if isinstance(model, OFC):
        from faultnet.solver.ofc import OFCSimulator

        if record_slips:
            raise InvalidParameterError(_NO_SLIPS)
        return OFCSimulator(model, x0=x0, rng=rng)
    from faultnet.solver.simulator import Simulator

    return Simulator(
        model, x0=x0, rng=rng, options=options, record_slips=record_slips,
        max_slip_rows=max_slip_rows,
    )  # fmt: skip


def model_metadata(model, options, dt, seq) -> dict:
    """What defines a run of ``model``: its parameters, options, step, seed and version."""
    if isinstance(model, OFC):
        from faultnet.solver.ofc import ofc_metadata

        return dict(ofc_metadata(model, seq), dt=dt)
    from faultnet.solver.wrap import run_metadata

    return run_metadata(model, options, dt, seq)


def time_name(model) -> str:
    """What the ``t`` of ``model``'s catalog is: the plate position, or an automaton's drive."""
    return "drive" if isinstance(model, OFC) else "plate time"


def random_start(model) -> str:
    """How a run of ``model`` from a seed starts (recorded as ``initial_state``)."""
    return "random U[0, 1)" if isinstance(model, OFC) else "random U[0, 0.01)"


def compiling_label(model) -> str:
    """The line a first run prints while it compiles the kernels of ``model``."""
    if isinstance(model, OFC):
        from faultnet.solver.ofc import COMPILING_LABEL
    else:
        from faultnet.solver.simulator import COMPILING_LABEL
    return COMPILING_LABEL


def transient_time(model) -> float:
    """The plate time (drive) before which ``faultnet simulate`` leaves events out of fits."""
    if isinstance(model, OFC):
        return 20.0 * math.sqrt(model.n)
    return 2.0


def check_job(model, n_events, *, dt=None, options=None, chunk_events=100_000,
              checkpoint_interval=60.0, transient=0, progress=None, metadata=None, desc=None,
              on_commit=None, record_slips=False):  # fmt: skip
    """The checked arguments of :func:`~faultnet.runs.long_run.simulate_to_parquet`, as
    keywords of the run loop."""
    check_model(model)
    if transient is not None:
        transient = check_int("transient", transient, minimum=0)
    interval = float(checkpoint_interval)
    if not (interval >= 0.0):
        raise InvalidParameterError(
            f"checkpoint_interval must be >= 0 s; got {checkpoint_interval!r}"
        )
    return dict(
        model=model,
        n_events=check_int("n_events", n_events),
        options=job_options(model, options, dt, record_slips),
        chunk_events=check_int("chunk_events", chunk_events),
        interval=interval,
        transient=transient,
        progress=progress,
        extra=metadata,
        desc=desc,
        on_commit=on_commit,
        record_slips=_flag("record_slips", record_slips),
    )


def _flag(name, value):
    if not isinstance(value, bool | np.bool_):
        raise InvalidParameterError(f"{name} must be True or False; got {value!r}")
    return bool(value)
