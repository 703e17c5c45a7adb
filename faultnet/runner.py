"""Long runs straight to a Parquet catalog, checkpointed so a kill loses nothing.

:func:`simulate_to_parquet` runs a model with one :class:`~faultnet.Simulator`
and writes the events in checkpoint chunks (the protocol is in
:mod:`faultnet.checkpoint`).  When all events are done the chunks are
streamed into the output file (atomic rename) and the checkpoint folder is
removed.  Memory stays O(N + chunk).  This module decides, under the output's
lock, whether a call starts, resumes or is refused; the loop itself is in
``faultnet._run_loop``, and runs named by a graph spec (what ``faultnet
simulate`` runs) in :mod:`faultnet.spec_run`.

>>> import faultnet, tempfile, os
>>> model = faultnet.CarlsonLanger(faultnet.graphs.ring(30))
>>> out = os.path.join(tempfile.mkdtemp(), "run.parquet")
>>> rep = simulate_to_parquet(model, 300, out, rng=5, chunk_events=100, progress=False)
>>> rep.metadata["n_events"], sorted(os.listdir(os.path.dirname(out)))
(300, ['run.parquet'])
>>> from faultnet.io import read_catalog
>>> read_catalog(out).events.equals(
...     faultnet.simulate(model, 300, rng=5, progress=False).events)
True
"""

from __future__ import annotations

import os
import shutil

import numpy as np

from faultnet._run_loop import RunReport, run_loop
from faultnet._validate import check_int, check_memory, seed_sequence
from faultnet.atomic import atomic_write_json
from faultnet.checkpoint import (
    CHECKPOINT_SUFFIX,
    IDENTITY,
    RUN_FORMAT,
    Checkpoint,
    checkpoint_dir,
    checkpoint_status,
    chunk_path,
    discard_tmp_outputs,
    mismatch,
    prepare_resume,
    read_run_json,
    remove_checkpoint_dir,
    run_identity,
    save_checkpoint,
    sha256_file,
)
from faultnet.exceptions import InvalidParameterError, OutputExistsError
from faultnet.io import check_catalog_path, read_metadata, read_state, verify_catalog
from faultnet.lock import LOCK_SUFFIX, output_lock

__all__ = [
    "CHECKPOINT_SUFFIX",
    "RunReport",
    "checkpoint_dir",
    "checkpoint_status",
    "simulate_to_parquet",
    "stored_request",
]


def simulate_to_parquet(
    model,
    n_events,
    out,
    *,
    rng=None,
    dt=None,
    options=None,
    chunk_events=100_000,
    checkpoint_interval=60.0,
    resume=False,
    force=False,
    extend=False,
    progress=None,
    transient=0,
    metadata=None,
    desc=None,
    on_commit=None,
) -> RunReport:
    """Run ``n_events`` events of ``model`` into the Parquet catalog ``out``.

    Parameters
    ----------
    model : CarlsonLanger
    n_events : int
    out : str, os.PathLike or None
        Catalog file to write, a name ending in ``.parquet``.  None runs without
        writing (only magnitudes are kept, in :attr:`RunReport.magnitudes`).
    rng : None, int, SeedSequence or Generator
        Seed of the initial state (SPEC 7), recorded in the metadata.  On
        ``resume`` None means "the seed of the checkpoint".
    dt : float, optional
        Integration step (shortcut for ``options.dt``).
    options : RunOptions, dict or None
        The run's numerical choices; part of the run's identity, so a resume
        with other options is refused.
    chunk_events : int
        Events per checkpoint chunk: memory is O(N + chunk_events).
    checkpoint_interval : float
        Seconds between checkpoints; a chunk is also committed whenever
        ``chunk_events`` events are waiting.  0 commits after every call.
    resume : bool
        Continue from ``out``'s checkpoint if there is one (else start).
    force : bool
        Discard an existing checkpoint or replace an existing ``out``.
    extend : bool
        ``out`` is a finished catalog of fewer than ``n_events`` events (run on ``model``):
        continue it from its final state to ``n_events``.  The catalog equals one run of
        ``n_events``, bit for bit; ``out`` keeps the shorter catalog until the longer one
        replaces it, and a killed extension resumes with ``resume=True`` (or ``extend``).
    progress : bool or None
        Progress bar with events and plate time (None: on a terminal).
    transient : int or None
        Events to leave out of b-value fits; recorded in the metadata.  None applies the
        default rule of ``faultnet simulate``: the events before plate time 2, at most half
        the run (:func:`faultnet.summary.default_transient`), counted when the run ends and
        recorded with the rule (``transient_rule``).
    metadata : dict, optional
        Extra metadata stored in ``run.json`` and the catalog.
    desc : str, optional
        Label of the progress bar (default: the graph's name).
    on_commit : callable, optional
        Called as ``on_commit(n_chunks)`` after each chunk and the checkpoint
        covering it are written (file outputs only).  An exception it raises
        stops the run as a kill after that commit would: the checkpoint is
        kept and ``resume=True`` continues.

    Returns
    -------
    RunReport
    """
    job = _job(model, n_events, dt, options, chunk_events, checkpoint_interval, transient)
    job.update(progress=progress, extra=metadata, desc=desc, on_commit=on_commit)
    step = job["options"].step(model)
    if out is None:  # the magnitudes and plate times are kept for the summary
        check_memory(
            f"n_events={job['n_events']:,} without an output file",
            16 * job["n_events"],
            "give an output file (out=..., --out FILE): it is written in chunks",
        )
        seq = seed_sequence(rng)
        identity = run_identity(model, job["n_events"], step, job["options"], seq)
        return run_loop(out=None, wd=None, seq=seq, resume_point=None, identity=identity, **job)
    out = check_catalog_path(out, "out")
    wd = checkpoint_dir(out)
    folder = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(folder):
        raise InvalidParameterError(f"output folder {folder} does not exist")
    if os.path.isdir(out):
        raise OutputExistsError(f"{out} is a folder; give a file name for the catalog")
    with output_lock(out + LOCK_SUFFIX, what=out):
        if extend:
            resume = _prepare_extension(out, wd, job["n_events"])
        return _start_or_resume(out, wd, rng, resume, force, step, job)


def _job(model, n_events, dt, options, chunk_events, checkpoint_interval, transient):
    """The checked arguments of :func:`simulate_to_parquet`, as keywords of the run loop."""
    from faultnet.engine import run_options
    from faultnet.model import CarlsonLanger

    if not isinstance(model, CarlsonLanger):
        raise InvalidParameterError(f"model must be a CarlsonLanger; got {type(model).__name__}")
    n_events = check_int("n_events", n_events)
    chunk_events = check_int("chunk_events", chunk_events)
    if transient is not None:
        transient = check_int("transient", transient, minimum=0)
    interval = float(checkpoint_interval)
    if not (interval >= 0.0):
        raise InvalidParameterError(
            f"checkpoint_interval must be >= 0 s; got {checkpoint_interval!r}"
        )
    return dict(
        model=model,
        n_events=n_events,
        options=run_options(options, dt),
        chunk_events=chunk_events,
        interval=interval,
        transient=transient,
    )


def _start_or_resume(out, wd, rng, resume, force, step, job):
    """The body of :func:`simulate_to_parquet` for a file output, run under its lock."""
    model, n_events, options = job["model"], job["n_events"], job["options"]
    if resume and rng is None:
        stored = None if force else stored_request(out)
        if stored is not None and stored.get("seed_entropy") is not None:
            rng = np.random.SeedSequence(
                stored["seed_entropy"], spawn_key=tuple(stored.get("seed_spawn_key") or ())
            )
    seq = seed_sequence(rng)
    identity = run_identity(model, n_events, step, options, seq)
    # an extension in progress: ``out`` holds the shorter run, the checkpoint this one
    extending = (
        resume
        and not force
        and os.path.isdir(wd)
        and _checkpoint_is(wd, identity)
        and os.path.exists(out)
        and bool(mismatch(read_metadata(out), identity))
    )
    if os.path.exists(out) and not extending:
        if resume and not force:
            done = _complete_output(out, identity)
            if os.path.isdir(wd):
                remove_checkpoint_dir(wd)
            return RunReport(out, done, status="already complete", resumed_from=n_events)
        if not force:
            raise OutputExistsError(
                f"{out} exists; refusing to overwrite it (use --force / force=True, or "
                "--resume to check that it is complete)"
            )
    resume_point = None
    if resume or force:
        discard_tmp_outputs(out)
    if os.path.isdir(wd):
        if resume and not force:
            resume_point = prepare_resume(wd, identity)
        elif force:
            remove_checkpoint_dir(wd)
        else:
            st = checkpoint_status(out) or {}
            raise OutputExistsError(
                f"an interrupted run of {out} exists ({st.get('events_done', 0)} of "
                f"{st.get('n_events', '?')} events committed in {wd}); pass --resume / "
                "resume=True to continue it, or --force / force=True to discard it"
            )
    return run_loop(out=out, wd=wd, seq=seq, resume_point=resume_point, identity=identity, **job)


def _checkpoint_is(wd, identity):
    """True if the checkpoint folder ``wd`` is of the run ``identity``."""
    run_json = os.path.join(wd, "run.json")
    return os.path.isfile(run_json) and not mismatch(read_run_json(run_json), identity)


def _prepare_extension(out, wd, n_events):
    """Turn the finished catalog ``out`` into the first committed chunk of a run of
    ``n_events``; return True (the run then resumes).  ``out`` itself stays as it is."""
    if os.path.isdir(wd):
        return True  # an extension (or a run) in progress: resume checks it is this one
    md = verify_catalog(out)
    state = read_state(out)
    missing = [key for key in IDENTITY if key not in md]
    if md.get("first_event") or missing:
        raise InvalidParameterError(
            f"{out} is not a whole run from event 0 (it starts at event "
            f"{md.get('first_event') or 0}{', lacks ' + ', '.join(missing) if missing else ''}): "
            "it cannot be extended in place; continue it in memory with "
            "simulate(model, n, x0=path)"
        )
    if md["n_events"] >= n_events:
        raise InvalidParameterError(
            f"{out} already holds {md['n_events']:,} events; extend it to more than that"
        )
    os.makedirs(wd)
    chunk = chunk_path(wd, 0)
    try:
        os.link(out, chunk)  # the same bytes, no copy (the output is replaced, never edited)
    except OSError:
        shutil.copyfile(out, chunk)
    identity = {key: md[key] for key in IDENTITY} | {"n_events": int(n_events)}
    extra = {key: md[key] for key in ("request", "sweep_point") if key in md}
    if "request" in extra:
        extra["request"] = dict(extra["request"], n_events=int(n_events))
    run = dict(identity, format=RUN_FORMAT, created=md.get("created"), extra=extra)
    run["initial_state"] = md.get("initial_state", "given")
    atomic_write_json(os.path.join(wd, "run.json"), run)
    counters = {key: md.get(key, 0) for key in ("wall_time_s", "n_steps", "block_steps", "runs")}
    ck = Checkpoint(state, md["n_events"], 1, counters, [sha256_file(chunk)])
    save_checkpoint(os.path.join(wd, "checkpoint.npz"), ck)  # the commit point
    return True


def stored_request(out):
    """Seed (and request) of an earlier run of ``out``: from its checkpoint or the file."""
    run_json = os.path.join(checkpoint_dir(out), "run.json")
    if os.path.isfile(run_json):
        return read_run_json(run_json)
    if os.path.isfile(out):
        return read_metadata(out)  # a garbled file: CatalogError naming it
    return None


def _complete_output(out, identity):
    md = verify_catalog(out)  # rows are events 0..n-1, as many as the metadata says
    diffs = mismatch(md, identity)
    if diffs:
        raise OutputExistsError(
            f"{out} exists and holds another run ({'; '.join(diffs)}); refusing to overwrite it "
            "(use --force / force=True)"
        )
    return md
