"""Long runs straight to a Parquet catalog: one :class:`LongRun` owns a run with an output.

A :class:`LongRun` takes the output's lock, reads the stored request (the
checkpoint's ``run.json``, or the finished catalog) once, and then starts or
resumes the run, commits its chunks (:mod:`faultnet.runs.chunks`, protocol in
:mod:`faultnet.runs.checkpoint`), verifies them and merges them into the
output (atomic rename), and removes the checkpoint folder.  Memory stays
O(N + chunk).  :func:`simulate_to_parquet` is its public face for a model;
runs named by a graph spec (``faultnet simulate``) go through
:func:`faultnet.runs.spec_run.run_from_spec`.

>>> import faultnet, tempfile, os
>>> model = faultnet.CarlsonLanger(faultnet.graphs.ring(30))
>>> out = os.path.join(tempfile.mkdtemp(), "run.parquet")
>>> rep = simulate_to_parquet(model, 300, out, rng=5, chunk_events=100, progress=False)
>>> rep.metadata["n_events"], sorted(os.listdir(os.path.dirname(out)))
(300, ['run.parquet'])
>>> faultnet.read_catalog(out).events.equals(
...     faultnet.simulate(model, 300, rng=5, progress=False).events)
True
"""

from __future__ import annotations

import os
import shutil

import numpy as np

from faultnet._validate import check_memory, seed_sequence
from faultnet.exceptions import CatalogError, InvalidParameterError, OutputExistsError
from faultnet.io.atomic import atomic_write_json
from faultnet.io.catalog_file import read_metadata, read_state, verify_catalog
from faultnet.io.labels import check_labels
from faultnet.io.lock import LOCK_SUFFIX, output_lock
from faultnet.io.parquet import check_catalog_path, merge_parts
from faultnet.io.slips import SIDE_TABLES, check_side_table, side_metadata, side_path
from faultnet.runs.checkpoint import (
    RUN_FORMAT,
    Checkpoint,
    checkpoint_dir,
    checkpoint_status,
    chunk_path,
    discard_tmp_outputs,
    prepare_resume,
    read_run_json,
    remove_checkpoint_dir,
    save_checkpoint,
    sha256_file,
    side_chunk_path,
    verify_chunks,
)
from faultnet.runs.chunks import RunReport, run_loop, write_failure
from faultnet.runs.identity import IDENTITY, IDENTITY_DEFAULTS, mismatch, run_identity, side_tables
from faultnet.runs.models import check_job, run_step

__all__ = ["LongRun", "RunReport", "simulate_to_parquet"]


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
    record_slips=False,
) -> RunReport:
    """Run ``n_events`` events of ``model`` into the Parquet catalog ``out``.

    Parameters
    ----------
    model : CarlsonLanger or OFC
    n_events : int
    out : str, os.PathLike or None
        Catalog file to write, a name ending in ``.parquet``.  None runs without
        writing (only magnitudes are kept, in :attr:`RunReport.magnitudes`).
    rng : None, int, SeedSequence or Generator
        Seed of the initial state (SPEC 7), recorded in the metadata.  On
        ``resume`` None means "the seed of the checkpoint".
    dt : float, optional
        Integration step (shortcut for ``options.dt``; not for an OFC model).
    options : RunOptions, dict or None
        The run's numerical choices; part of the run's identity, so a resume
        with other options is refused.  An OFC model takes none.
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
        default rule of ``faultnet simulate``: the events before plate time 2 (an OFC
        automaton: before the drive ``20 sqrt(N)``, :mod:`faultnet.runs.models`), at most half
        the run (:func:`faultnet.io.summary.default_transient`), counted when the run ends and
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
    record_slips : bool
        Also write the per-block slips of every event, ``out`` with ``.slips.parquet`` for
        ``.parquet`` (:func:`faultnet.read_slips`), in chunks with the events: a resumed
        run's slips equal an uninterrupted run's, bit for bit.  Part of the run's identity.
        A network of faults always writes each event's slip per fault
        (``.fault_slips.parquet``, ``read_slips(out, per="fault")``).

    Returns
    -------
    RunReport
    """
    run = dict(rng=rng, dt=dt, options=options, chunk_events=chunk_events,
               checkpoint_interval=checkpoint_interval, progress=progress, transient=transient,
               metadata=metadata, desc=desc, on_commit=on_commit,
               record_slips=record_slips)  # fmt: skip
    if out is not None:
        with LongRun(out, resume=resume, force=force, extend=extend) as long_run:
            return long_run.run(model, n_events, **run)
    rng = run.pop("rng")
    job = check_job(model, n_events, **run)
    if job["record_slips"]:
        raise InvalidParameterError(
            "record_slips=True writes the slips next to the catalog: give an output file "
            "(out=..., --out FILE), or use simulate(..., record_slips=True) in memory"
        )
    check_memory(  # the magnitudes and plate times are kept for the summary
        f"n_events={job['n_events']:,} without an output file",
        16 * job["n_events"],
        "give an output file (out=..., --out FILE): it is written in chunks",
    )
    seq = seed_sequence(rng)
    step = run_step(model, job["options"])
    identity = run_identity(model, job["n_events"], step, job["options"], seq)
    _, md, sink = run_loop(wd=None, seq=seq, resume_point=None, stored=None, identity=identity,
                           **job)  # fmt: skip
    mags = np.concatenate(sink.mags) if sink.mags else np.zeros(0)
    times = np.concatenate(sink.times) if sink.times else np.zeros(0)
    return RunReport(None, md, magnitudes=mags, plate_times=times, seen=sink.seen)


class LongRun:
    """One run with an output file, from its first event to the verified catalog.

    Used as a context manager: entering takes the output's lock and reads the
    stored request once (:attr:`stored`); :meth:`run` then starts, resumes or
    extends the run, commits its chunks, verifies and merges them.

    Parameters
    ----------
    out : str or os.PathLike
        The catalog to write, a name ending in ``.parquet`` in an existing folder.
    resume, force, extend : bool
        As for :func:`simulate_to_parquet`.

    Attributes
    ----------
    stored : dict or None
        The stored request of ``out`` (its checkpoint's ``run.json``, else the
        finished catalog's metadata), read on entering when resuming or
        extending; None otherwise, or where ``force`` discards an unreadable one.
    """

    def __init__(self, out, *, resume=False, force=False, extend=False):
        self.out = check_catalog_path(out, "out")
        self.wd = checkpoint_dir(self.out)
        folder = os.path.dirname(os.path.abspath(self.out))
        if not os.path.isdir(folder):
            raise InvalidParameterError(f"output folder {folder} does not exist")
        if os.path.isdir(self.out):
            raise OutputExistsError(f"{self.out} is a folder; give a file name for the catalog")
        self.resume, self.force, self.extend = bool(resume), bool(force), bool(extend)
        self.stored, self._from_checkpoint, self._lock = None, False, None
        self.tables = ()  # the side tables of the run (set by :meth:`run`)

    def __enter__(self):
        self._lock = output_lock(self.out + LOCK_SUFFIX, what=self.out)
        self._lock.__enter__()
        try:
            if self.resume or self.extend:
                self._read_stored()
        except BaseException:
            self._lock.__exit__(None, None, None)
            raise
        return self

    def __exit__(self, *exc):
        return self._lock.__exit__(*exc)

    def _read_stored(self):
        run_json = os.path.join(self.wd, "run.json")
        try:
            if os.path.isfile(run_json):
                self.stored, self._from_checkpoint = read_run_json(run_json), True
            elif os.path.isfile(self.out):
                self.stored = read_metadata(self.out)  # a garbled file: CatalogError naming it
        except CatalogError:
            if not self.force:
                raise

    def stored_seed(self):
        """The SeedSequence of the stored run (None: none stored)."""
        if self.stored is None or self.stored.get("seed_entropy") is None:
            return None
        key = tuple(self.stored.get("seed_spawn_key") or ())
        return np.random.SeedSequence(self.stored["seed_entropy"], spawn_key=key)

    def run(self, model, n_events, *, rng=None, **arguments) -> RunReport:
        """Start, resume or extend the run of ``n_events`` of ``model``, then verify and merge
        its chunks into the output.  ``rng`` and the other arguments are those of
        :func:`simulate_to_parquet`; on resume, ``rng=None`` takes the stored seed."""
        job = check_job(model, n_events, **arguments)
        if not isinstance(model.nodes, range):  # refused now rather than at the first chunk
            check_labels(model.nodes, f"{self.out}: the graph's node labels")
        resume = self.resume or self.extend
        self.tables = side_tables(model, job["record_slips"])
        if self.extend:
            self._prepare_extension(job["n_events"], job["record_slips"])
        if rng is None and resume and not self.force:
            rng = self.stored_seed()
        seq = seed_sequence(rng)
        model, n_events, options = job["model"], job["n_events"], job["options"]
        identity = run_identity(model, n_events, run_step(model, options), options, seq,
                                job["record_slips"])  # fmt: skip
        start = self._start_or_resume(identity, resume)
        if isinstance(start, RunReport):
            return start
        stored = self.stored if self._from_checkpoint and os.path.isdir(self.wd) else None
        resumed_from = start.rows if start is not None else 0
        ck, md, _ = run_loop(wd=self.wd, seq=seq, resume_point=start, stored=stored,
                             identity=identity, **job)  # fmt: skip
        self.merge(ck, md)
        status = "resumed" if resumed_from else "completed"
        return RunReport(self.out, md, status=status, resumed_from=resumed_from)

    def _start_or_resume(self, identity, resume):
        """The checkpoint to continue (None: start), or the report of a finished output."""
        out, wd, force = self.out, self.wd, self.force
        extending = (  # an extension in progress: ``out`` holds the shorter run
            resume
            and not force
            and self._from_checkpoint
            and not mismatch(self.stored, identity)
            and os.path.exists(out)
            and bool(mismatch(read_metadata(out), identity))
        )
        if os.path.exists(out) and not extending:
            if resume and not force:
                done = self._complete_output(identity)
                if os.path.isdir(wd):
                    remove_checkpoint_dir(wd)
                return RunReport(
                    out, done, status="already complete", resumed_from=identity["n_events"]
                )
            if not force:
                raise OutputExistsError(
                    f"{out} exists; refusing to overwrite it (use --force / force=True, or "
                    "--resume to check that it is complete)"
                )
        if resume or force:
            discard_tmp_outputs(out)
        if not os.path.isdir(wd):
            return None
        if resume and not force:
            stored = self.stored if self._from_checkpoint else None
            return prepare_resume(wd, identity, stored, self.tables)
        if force:
            remove_checkpoint_dir(wd)
            return None
        st = checkpoint_status(out) or {}
        raise OutputExistsError(
            f"an interrupted run of {out} exists ({st.get('events_done', 0)} of "
            f"{st.get('n_events', '?')} events committed in {wd}); pass --resume / "
            "resume=True to continue it, or --force / force=True to discard it"
        )

    def merge(self, ck, md):
        """Verify the committed chunks, stream them into the output (the side tables first,
        the catalog last), remove the checkpoint."""
        chunks = [chunk_path(self.wd, i) for i in range(ck.n_chunks)]
        ck_path = os.path.join(self.wd, "checkpoint.npz")
        verify_chunks(self.wd, ck, self.tables)  # checksums and event numbers of every chunk
        for name in SIDE_TABLES:
            target = side_path(self.out, name)
            with write_failure(target, ck_path, ck.rows, what="merge the chunks into"):
                if name in self.tables:
                    parts = [side_chunk_path(self.wd, name, i) for i in range(ck.n_chunks)]
                    merge_parts(parts, target, side_metadata(name, md), overwrite=True)
                elif os.path.exists(target):  # another run's, replaced with its catalog
                    os.remove(target)
        with write_failure(self.out, ck_path, ck.rows, what="merge the chunks into"):
            merge_parts(chunks, self.out, md, overwrite=True, state=ck.state)
        remove_checkpoint_dir(self.wd)

    def _complete_output(self, identity):
        md = verify_catalog(self.out)  # rows are events 0..n-1, as many as the metadata says
        diffs = mismatch(md, identity)
        if diffs:
            raise OutputExistsError(
                f"{self.out} exists and holds another run ({'; '.join(diffs)}); refusing to "
                "overwrite it (use --force / force=True)"
            )
        self._check_sides(md)
        return md

    def _check_sides(self, md):
        """Refuse a finished output whose side tables are missing or another run's."""
        for name in self.tables:
            check_side_table(self.out, name)

    def _prepare_extension(self, n_events, record_slips):
        """Turn the finished output into the first committed chunk of a run of ``n_events``,
        which then resumes.  The output itself stays as it is until the merge."""
        out, wd = self.out, self.wd
        if os.path.isdir(wd):
            return  # an extension (or a run) in progress: resume checks it is this one
        md = verify_catalog(out)
        state = read_state(out)
        missing = [key for key in IDENTITY if key not in md and key not in IDENTITY_DEFAULTS]
        if md.get("first_event") or missing:
            lacks = ", lacks " + ", ".join(missing) if missing else ""
            raise InvalidParameterError(
                f"{out} is not a whole run from event 0 (it starts at event "
                f"{md.get('first_event') or 0}{lacks}): "
                "it cannot be extended in place; continue it in memory with "
                "simulate(model, n, x0=path)"
            )
        if md["n_events"] >= n_events:
            raise InvalidParameterError(
                f"{out} already holds {md['n_events']:,} events; extend it to more than that"
            )
        if record_slips and not md.get("record_slips"):
            raise InvalidParameterError(
                f"{out} was run without record_slips: its extension cannot record them (the "
                "slips of its events are not on disk); extend it without record_slips, or "
                "run anew"
            )
        sides = {name: side_path(out, name) for name in self.tables}
        for name in sides:
            check_side_table(out, name)
        os.makedirs(wd)
        files = {chunk_path(wd, 0): out}
        files.update((side_chunk_path(wd, name, 0), path) for name, path in sides.items())
        for chunk, source in files.items():
            try:
                os.link(source, chunk)  # the same bytes, no copy (outputs are replaced, never
            except OSError:  # edited)
                shutil.copyfile(source, chunk)
        identity = {key: md.get(key, IDENTITY_DEFAULTS.get(key)) for key in IDENTITY}
        identity["n_events"] = int(n_events)
        extra = {key: md[key] for key in ("request", "sweep_point") if key in md}
        if "request" in extra:
            extra["request"] = dict(extra["request"], n_events=int(n_events))
        run = dict(identity, format=RUN_FORMAT, created=md.get("created"), extra=extra)
        run["initial_state"] = md.get("initial_state", "given")
        atomic_write_json(os.path.join(wd, "run.json"), run)
        counters = {key: md.get(key, 0) for key in Checkpoint(None).counters}
        shas = {name: [sha256_file(side_chunk_path(wd, name, 0))] for name in sides}
        ck = Checkpoint(state, md["n_events"], 1, counters, [sha256_file(chunk_path(wd, 0))],
                        shas)  # fmt: skip
        save_checkpoint(os.path.join(wd, "checkpoint.npz"), ck)  # the commit point
        self.stored, self._from_checkpoint = run, True
