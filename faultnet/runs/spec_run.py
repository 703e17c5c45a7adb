"""Long runs named by a graph spec: what ``faultnet simulate`` and each sweep point run.

:func:`run_from_spec` builds the model of a graph spec (:mod:`faultnet.runs.specs`)
and runs it with :func:`faultnet.runs.long_run.simulate_to_parquet`.  The request
(graph, events, k, sigma, alpha, dt, transient, and nu and eta where not 0) is stored in the run's
``run.json`` and in the catalog, so a resume needs only the output: the values
not given are taken from the stored request, and values that are given must
agree with it.

>>> import os, tempfile
>>> out = os.path.join(tempfile.mkdtemp(), "ring.parquet")
>>> rep = run_from_spec("ring:30", 300, out, alpha=2.0, seed=1, progress=False)
>>> rep.metadata["request"]["graph"], rep.metadata["alpha"]
('ring:30', 2.0)
>>> run_from_spec(None, None, out, resume=True, progress=False).status
'already complete'
"""

from __future__ import annotations

import math

from faultnet._validate import seed_sequence
from faultnet.exceptions import InvalidParameterError
from faultnet.runs.long_run import LongRun, RunReport, simulate_to_parquet
from faultnet.runs.specs import build_model
from faultnet.solver.options import RunOptions

__all__ = ["run_from_spec"]

# the values of a run that run_from_spec records and a resume takes over
_REQUEST_KEYS = (
    "graph",
    "n_events",
    "k",
    "sigma",
    "alpha",
    "dt",
    "transient",
    "model",
    "ofc_alpha",
    "nu",
    "eta",
)
#: the Carlson-Langer model's parameters that the graph spec's model leaves at 0
_KELVIN = ("nu", "eta")


def run_from_spec(
    graph,
    n_events,
    out,
    *,
    k=None,
    sigma=None,
    alpha=None,
    dt=None,
    options=None,
    seed=None,
    chunk_events=100_000,
    checkpoint_interval=60.0,
    transient=0,
    resume=False,
    force=False,
    extend=False,
    progress=None,
    extra=None,
    on_commit=None,
    record_slips=None,
    model=None,
    ofc_alpha=None,
    nu=None,
    eta=None,
) -> RunReport:
    """:func:`~faultnet.runs.long_run.simulate_to_parquet` for a graph spec.

    Parameters
    ----------
    graph : str or None
        Graph spec or graph file (:func:`faultnet.runs.specs.parse_graph_spec`);
        None on ``resume`` takes the stored one.
    n_events : int or None
        Events to run; None on ``resume`` takes the stored number.
    out : str, os.PathLike or None
        Catalog to write (None: run without writing).
    k, sigma, alpha, dt : float, optional
        Model parameters and step (defaults: :func:`faultnet.runs.specs.build_model`'s).
    options : RunOptions, dict or None
        Run options; None on ``resume`` takes the stored ones.
    seed : None, int or SeedSequence
        Seed of the run (and of a random graph); None on ``resume`` takes the stored one.
    extra : dict, optional
        More metadata for ``run.json`` and the catalog, next to ``request``.
    record_slips : bool or None
        Write the per-block slips next to the catalog (:func:`faultnet.read_slips`); None
        is False, or on ``resume`` the stored choice.
    model : {"carlson-langer", "ofc"} or None
        The model to build (:func:`faultnet.runs.specs.build_model`); None is the
        Carlson-Langer model, or on ``resume`` the stored one.
    ofc_alpha : float, optional
        The OFC automaton's conservation parameter (:meth:`faultnet.OFC.from_alpha`).
    nu, eta : float, optional
        The plate's velocity during events and the springs' viscous coupling of the
        Carlson-Langer model (:class:`faultnet.CarlsonLanger`; default 0, or on ``resume``
        the stored ones); refused with ``model="ofc"``.
    chunk_events, checkpoint_interval, transient, resume, force, extend, progress, on_commit
        As for :func:`~faultnet.runs.long_run.simulate_to_parquet`.

    Returns
    -------
    RunReport

    Raises
    ------
    InvalidParameterError
        When a value given on ``resume`` differs from the stored request, or a
        graph or the number of events is missing.
    """
    values = (graph, n_events, k, sigma, alpha, dt, transient, model, ofc_alpha, nu, eta)
    given = dict(zip(_REQUEST_KEYS, values, strict=True))
    job = dict(options=options, seed=seed, extra=extra, progress=progress, on_commit=on_commit)
    job.update(chunk_events=chunk_events, checkpoint_interval=checkpoint_interval)
    job["record_slips"] = record_slips
    if out is None:
        job["record_slips"] = bool(record_slips)
        return _run(None, given, **job)
    with LongRun(out, resume=resume, force=force, extend=extend) as run:
        if run.stored is not None:
            job["options"], job["seed"] = _take_stored(given, options, seed, run, extend)
            if record_slips is None:
                job["record_slips"] = bool(run.stored.get("record_slips", False))
        elif record_slips is None:
            job["record_slips"] = False
        return _run(run, given, **job)


def _run(run, given, *, options, seed, extra, **job):
    """Build the model of the request ``given`` and run it (``run``: the LongRun, or None)."""
    if given["graph"] is None:
        raise InvalidParameterError("a graph spec is required (e.g. ring:200)")
    if given["n_events"] is None:
        raise InvalidParameterError("the number of events is required (--events N)")
    kelvin = {name: given[name] for name in _KELVIN if given[name] is not None}
    if kelvin and given["model"] == "ofc":
        raise InvalidParameterError(
            f"{' and '.join(kelvin)} (--{' and --'.join(kelvin)}) "
            f"{'belong' if len(kelvin) > 1 else 'belongs'} to the Carlson-Langer model (the "
            "plate's velocity during events, the springs' viscous coupling): the OFC automaton "
            "has neither; leave them out"
        )
    seq = seed_sequence(seed)
    model = build_model(
        given["graph"], k=given["k"], sigma=given["sigma"], alpha=given["alpha"], rng=seq,
        model=given["model"], ofc_alpha=given["ofc_alpha"],
    )  # fmt: skip
    if kelvin:
        model = model.with_params(**kelvin)
    request = {key: given[key] for key in ("graph", "n_events", "k", "sigma", "alpha", "dt")}
    request["transient"] = given["transient"]
    # recorded where not 0 (the requests of other runs stay as they were)
    request.update((name, getattr(model, name)) for name in kelvin if getattr(model, name))
    if given["model"] not in (None, "carlson-langer"):  # requests of 0.2 name no model
        request.update(model=given["model"], ofc_alpha=given["ofc_alpha"])
    md = {"request": request}
    md.update(extra or {})
    args = dict(dt=given["dt"], options=options, transient=given["transient"], metadata=md)
    if run is None:
        return simulate_to_parquet(model, int(given["n_events"]), None, rng=seq, **args, **job)
    return run.run(model, int(given["n_events"]), rng=seq, **args, **job)


def _take_stored(given, options, seed, run, extend=False):
    """Fill ``given`` from the stored request; return the options and seed to run with.

    A value given that differs from the stored one is refused (transient may change, and
    the number of events when the run is extended).
    """
    stored, out = run.stored, run.out
    request = dict(stored.get("extra", {}).get("request") or stored.get("request") or {})
    conflicts = [
        f"{key}: checkpoint has {request[key]!r}, this call {value!r}"
        for key, value in given.items()
        if value is not None
        and key in request
        and request[key] is not None
        and key != "transient"
        and not (extend and key == "n_events")
        and _differs(key, request[key], value)
    ]
    if conflicts:
        raise InvalidParameterError(
            f"cannot resume {out}: {'; '.join(conflicts)}. Leave these out to use the "
            "checkpoint's values, or pass --force to start over"
        )
    for key, value in request.items():
        if given.get(key) is None:
            given[key] = value
    automaton = (given.get("model") or request.get("model")) == "ofc"  # it has no RunOptions
    if options is None and isinstance(stored.get("options"), dict) and not automaton:
        options = RunOptions.from_dict(stored["options"])
    if seed is None:
        seed = run.stored_seed()
    return options, seed


def _differs(key, a, b):
    if key in ("k", "sigma", "alpha", "dt", "ofc_alpha", *_KELVIN):
        try:
            return not math.isclose(float(a), float(b), rel_tol=0.0, abs_tol=0.0)
        except (TypeError, ValueError):
            return True
    if key == "n_events":
        return int(a) != int(b)
    return str(a) != str(b)
