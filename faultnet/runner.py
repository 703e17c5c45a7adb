"""Long runs straight to a Parquet catalog, checkpointed so a kill loses nothing.

:func:`simulate_to_parquet` runs a model with one :class:`~faultnet.Simulator`
and writes the events in checkpoint chunks (the protocol is in
:mod:`faultnet.checkpoint`).  When all events are done the chunks are
streamed into the output file (atomic rename) and the checkpoint folder is
removed.  Memory stays O(N + chunk).

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

import contextlib
import math
import os
import shutil
import time
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from tqdm.auto import tqdm

from faultnet._validate import check_int, seed_sequence
from faultnet.atomic import atomic_write_json
from faultnet.checkpoint import (
    CHECKPOINT_SUFFIX,
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
    verify_chunks,
)
from faultnet.exceptions import CatalogError, InvalidParameterError, OutputExistsError
from faultnet.io import (
    CATALOG_FORMAT,
    FORMAT_VERSION,
    merge_parts,
    provenance,
    read_metadata,
    utc_now,
    verify_catalog,
    write_part,
)
from faultnet.lock import LOCK_SUFFIX, output_lock
from faultnet.options import RunOptions

__all__ = [
    "CHECKPOINT_SUFFIX",
    "RunReport",
    "checkpoint_dir",
    "checkpoint_status",
    "run_from_spec",
    "simulate_to_parquet",
]

#: target wall time of one advance of the Simulator (smooth progress, bounded memory)
_CALL_SECONDS = 0.25


@dataclass
class RunReport:
    """What :func:`simulate_to_parquet` did.

    Attributes
    ----------
    path : str or None
        The catalog written (None for ``out=None``).
    metadata : dict
        The catalog's metadata.
    status : str
        ``"completed"`` (run from the start), ``"resumed"`` or ``"already complete"``.
    resumed_from : int
        Events committed before this call (0 for a fresh run).
    magnitudes : numpy.ndarray or None
        ``M`` of every event, only for ``out=None``.
    plate_times : numpy.ndarray or None
        ``t`` (plate position) of every event, only for ``out=None``.
    seen : dict
        For ``out=None``: ``t_first``, ``t_last`` and ``largest_n_blocks``.
    """

    path: str | None
    metadata: dict = field(default_factory=dict)
    status: str = "completed"
    resumed_from: int = 0
    magnitudes: np.ndarray | None = field(default=None, repr=False)
    plate_times: np.ndarray | None = field(default=None, repr=False)
    seen: dict = field(default_factory=dict, repr=False)


def _final_metadata(model, options, identity, first_md, counters, extra, transient, chunk_events):
    from faultnet.results import run_metadata

    seq = np.random.SeedSequence(identity["seed_entropy"], spawn_key=identity["seed_spawn_key"])
    md = run_metadata(model, options, identity["dt"], seq)
    md.update(
        format=CATALOG_FORMAT,
        format_version=FORMAT_VERSION,
        first_event=0,
        n_events=identity["n_events"],
        initial_state=first_md.get("initial_state", "random"),
        wall_time_s=counters["wall_time_s"],
        n_steps=counters["n_steps"],
        block_steps=counters["block_steps"],
        graph_hash=identity["graph_hash"],
        transient=int(transient),
        chunk_events=int(chunk_events),
        sessions=counters["sessions"],
        created=first_md.get("created", utc_now()),
        finished=utc_now(),
        provenance=provenance(),
    )
    spec = model.graph.graph.get("spec")
    if spec:
        md["graph_spec"] = spec
    for key in ("seed_entropy", "seed_spawn_key"):
        if key in model.graph.graph:
            md[f"graph_{key}"] = model.graph.graph[key]
    md.update(extra or {})
    return md


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
    progress=None,
    transient=0,
    metadata=None,
    desc=None,
) -> RunReport:
    """Run ``n_events`` events of ``model`` into the Parquet catalog ``out``.

    Parameters
    ----------
    model : CarlsonLanger
    n_events : int
    out : str, os.PathLike or None
        Catalog file to write.  None runs without writing (only magnitudes
        are kept, in :attr:`RunReport.magnitudes`).
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
    progress : bool or None
        Progress bar with events and plate time (None: on a terminal).
    transient : int
        Events to leave out of b-value fits; recorded in the metadata.
    metadata : dict, optional
        Extra metadata stored in ``run.json`` and the catalog.

    Returns
    -------
    RunReport
    """
    from faultnet.engine import run_options
    from faultnet.model import CarlsonLanger

    if not isinstance(model, CarlsonLanger):
        raise InvalidParameterError(f"model must be a CarlsonLanger; got {type(model).__name__}")
    n_events = check_int("n_events", n_events)
    chunk_events = check_int("chunk_events", chunk_events)
    transient = check_int("transient", transient, minimum=0)
    interval = float(checkpoint_interval)
    if not (interval >= 0.0):
        raise InvalidParameterError(
            f"checkpoint_interval must be >= 0 s; got {checkpoint_interval!r}"
        )
    options = run_options(options, dt)
    step = options.step(model)
    job = dict(
        model=model,
        n_events=n_events,
        options=options,
        chunk_events=chunk_events,
        interval=interval,
        progress=progress,
        transient=transient,
        extra=metadata,
        desc=desc,
    )
    if out is None:
        seq = seed_sequence(rng)
        return _run(out=None, wd=None, seq=seq, resume_point=None,
                    identity=run_identity(model, n_events, step, options, seq), **job)  # fmt: skip
    out = os.fspath(out)
    wd = checkpoint_dir(out)
    folder = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(folder):
        raise InvalidParameterError(f"output folder {folder} does not exist")
    if os.path.isdir(out):
        raise OutputExistsError(f"{out} is a folder; give a file name for the catalog")
    with output_lock(out + LOCK_SUFFIX, what=out):
        return _start_or_resume(out, wd, rng, resume, force, step, job)


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
    if os.path.exists(out):
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
    return _run(out=out, wd=wd, seq=seq, resume_point=resume_point, identity=identity, **job)


def stored_request(out):
    """Seed (and request) of an earlier run of ``out``: from its checkpoint or the file."""
    run_json = os.path.join(checkpoint_dir(out), "run.json")
    if os.path.isfile(run_json):
        return read_run_json(run_json)
    if os.path.isfile(out):
        try:
            return read_metadata(out)
        except CatalogError:
            return None
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


class _Catalog:
    """Where the events of a run go: checkpoint chunks in ``wd``, or magnitudes only."""

    def __init__(self, wd, first_md, committed):
        self.wd, self.first_md = wd, first_md
        self.committed = committed  # rows in committed chunks
        self.buffer, self.buffered = [], 0
        self.mags, self.times, self.seen = [], [], {}

    def add(self, events):
        self.buffer.append(events)
        self.buffered += len(events)

    def flush(self, ck: Checkpoint):
        """Commit the buffered events: a chunk file, then the checkpoint covering it.

        The buffer is emptied first: a commit that fails is not retried, and a
        chunk written without its checkpoint is discarded on resume.
        """
        if not self.buffered:
            return
        if self.committed + self.buffered != ck.rows or ck.state.n_events != ck.rows:
            raise CatalogError("internal: the buffered events do not match the state")
        buf, n = self.buffer, self.buffered
        events = pd.concat(buf, ignore_index=True) if len(buf) > 1 else buf[0]
        self.buffer, self.buffered = [], 0
        if self.wd is None:
            self._see(events)
        else:
            chunk_md = {"chunk": ck.n_chunks}
            if self.first_md.get("initial_state"):
                chunk_md["initial_state"] = self.first_md["initial_state"]
            path = chunk_path(self.wd, ck.n_chunks)
            ck_path = os.path.join(self.wd, "checkpoint.npz")
            with _write_failure(path, ck_path, self.committed):
                write_part(events, path, chunk_md)
                sha = [*ck.sha256, sha256_file(path)]
            covering = Checkpoint(ck.state, ck.rows, ck.n_chunks + 1, ck.counters, sha)
            with _write_failure(ck_path, ck_path, self.committed):
                save_checkpoint(ck_path, covering)
            ck.n_chunks, ck.sha256 = ck.n_chunks + 1, sha
        self.committed += n

    def _see(self, events):
        self.mags.append(events["M"].to_numpy(copy=True))
        self.times.append(events["t"].to_numpy(copy=True))
        self.seen.setdefault("t_first", float(events["t"].iloc[0]))
        self.seen["t_last"] = float(events["t"].iloc[-1])
        self.seen["largest_n_blocks"] = max(
            self.seen.get("largest_n_blocks", 0), int(events["n_blocks"].max())
        )


@contextlib.contextmanager
def _write_failure(path, ck_path, committed, what="write"):
    """Turn an OSError (a full disk, say) into a message naming the file and what is safe."""
    try:
        yield
    except CatalogError:
        raise
    except OSError as exc:
        out = os.path.dirname(ck_path)[: -len(CHECKPOINT_SUFFIX)]
        raise CatalogError(
            f"cannot {what} {path}: {exc.strerror or exc}. The checkpoint {ck_path} is intact "
            f"({committed:,} events committed); free space (or fix the cause) and run "
            f"'faultnet simulate --resume --out {out}' to continue"
        ) from exc


def _open_run(wd, identity, extra):
    """Create the checkpoint folder and its run.json (or read the existing one)."""
    if wd is None:
        return {}, False
    created = not os.path.isdir(wd)
    os.makedirs(wd, exist_ok=True)
    run_json = os.path.join(wd, "run.json")
    if os.path.isfile(run_json):
        return read_run_json(run_json), created
    first_md = dict(identity, format=RUN_FORMAT, created=utc_now(), extra=extra or {})
    atomic_write_json(run_json, first_md)
    return first_md, created


def _run(*, model, n_events, out, wd, identity, seq, options, chunk_events, interval,
         progress, transient, extra, desc, resume_point):  # fmt: skip
    from faultnet.engine import Simulator

    ck = resume_point or Checkpoint(None)
    resumed_from = ck.rows
    ck.counters["sessions"] += 1
    first_md, created = _open_run(wd, identity, extra)
    sink = _Catalog(wd, first_md, ck.rows)
    if ck.state is None:
        sim = Simulator(model, rng=seq, options=options)
        first_md["initial_state"] = "random U[0, 0.01)"
        if wd is not None:
            atomic_write_json(os.path.join(wd, "run.json"), first_md)
    else:
        sim = Simulator(model, x0=ck.state, options=options)
    last_ck = time.monotonic()
    call = 256
    bar = tqdm(total=n_events, initial=ck.rows, unit="ev", desc=desc or model.params["graph"],
               disable=(None if progress is None else not progress), dynamic_ncols=True,
               smoothing=0.1)  # fmt: skip
    try:
        while ck.rows < n_events:
            n_call = min(call, n_events - ck.rows, chunk_events - sink.buffered)
            res = sim.advance(n_call, progress=False)
            sink.add(res.events)
            ck.state, ck.rows = sim.state, ck.rows + n_call
            loop_s = float(res.metadata["wall_time_s"])
            for key in ("n_steps", "block_steps"):
                ck.counters[key] += int(res.metadata[key])
            ck.counters["wall_time_s"] += loop_s
            bar.update(n_call)
            bar.set_postfix(t=f"{ck.state.u:.6g}", refresh=False)
            # the next call takes about _CALL_SECONDS at the rate just measured
            rate = n_call / max(loop_s, 1e-6)
            call = int(min(max(rate * _CALL_SECONDS, 1), chunk_events, 2 * call))
            due = time.monotonic() - last_ck >= interval
            if sink.buffered >= chunk_events or ck.rows >= n_events or due:
                sink.flush(ck)
                last_ck = time.monotonic()
    except BaseException:
        with contextlib.suppress(Exception):
            sink.flush(ck)  # keep what was computed before the failure (if consistent)
        bar.close()
        if created and ck.n_chunks == 0:  # nothing committed: leave no checkpoint behind
            with contextlib.suppress(OSError):
                shutil.rmtree(wd)
        raise
    bar.close()
    md = _final_metadata(
        model, options, identity, first_md, ck.counters, extra, transient, chunk_events
    )
    status = "resumed" if resumed_from else "completed"
    if out is None:
        mags = np.concatenate(sink.mags) if sink.mags else np.zeros(0)
        times = np.concatenate(sink.times) if sink.times else np.zeros(0)
        return RunReport(
            None, md, status=status, magnitudes=mags, plate_times=times, seen=sink.seen
        )
    chunks = [chunk_path(wd, i) for i in range(ck.n_chunks)]
    ck_path = os.path.join(wd, "checkpoint.npz")
    verify_chunks(wd, ck)  # checksums and event numbers of every chunk before the merge
    with _write_failure(out, ck_path, ck.rows, what="merge the chunks into"):
        merge_parts(chunks, out, md, overwrite=True)
    remove_checkpoint_dir(wd)
    return RunReport(out, md, status=status, resumed_from=resumed_from)


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
    progress=None,
    extra=None,
) -> RunReport:
    """:func:`simulate_to_parquet` for a graph spec (what ``faultnet simulate`` runs).

    With ``resume=True`` the values not given (graph, events, k, sigma,
    alpha, dt, options, seed, transient) are taken from the interrupted run's
    ``run.json``; values that are given must agree with it.
    """
    from faultnet.specs import build_model

    given = {
        "graph": graph,
        "n_events": n_events,
        "k": k,
        "sigma": sigma,
        "alpha": alpha,
        "dt": dt,
        "transient": transient,
    }
    stored = None
    if resume and out is not None:
        try:
            stored = stored_request(os.fspath(out))
        except CatalogError:
            if not force:
                raise
    if stored is not None:
        request = dict(stored.get("extra", {}).get("request") or stored.get("request") or {})
        conflicts = [
            f"{key}: checkpoint has {request[key]!r}, this call {value!r}"
            for key, value in given.items()
            if value is not None
            and key in request
            and request[key] is not None
            and key != "transient"
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
        if options is None and isinstance(stored.get("options"), dict):
            options = RunOptions.from_dict(stored["options"])
        if seed is None and stored.get("seed_entropy") is not None:
            seed = np.random.SeedSequence(
                stored["seed_entropy"], spawn_key=tuple(stored.get("seed_spawn_key") or ())
            )
    if given["graph"] is None:
        raise InvalidParameterError("a graph spec is required (e.g. ring:200)")
    if given["n_events"] is None:
        raise InvalidParameterError("the number of events is required (--events N)")
    seq = seed_sequence(seed)
    model = build_model(
        given["graph"], k=given["k"], sigma=given["sigma"], alpha=given["alpha"], rng=seq
    )
    request = {key: given[key] for key in ("graph", "n_events", "k", "sigma", "alpha", "dt")}
    request["transient"] = given["transient"] or 0
    md = {"request": request}
    md.update(extra or {})
    return simulate_to_parquet(
        model,
        int(given["n_events"]),
        out,
        rng=seq,
        dt=given["dt"],
        options=options,
        chunk_events=chunk_events,
        checkpoint_interval=checkpoint_interval,
        resume=resume,
        force=force,
        progress=progress,
        transient=int(given["transient"] or 0),
        metadata=md,
    )


def _differs(key, a, b):
    if key in ("k", "sigma", "alpha", "dt"):
        try:
            return not math.isclose(float(a), float(b), rel_tol=0.0, abs_tol=0.0)
        except (TypeError, ValueError):
            return True
    if key == "n_events":
        return int(a) != int(b)
    return str(a) != str(b)
