"""The loop of a long run: advance one Simulator and commit its events in chunks.

:func:`run_loop` is the engine room of a :class:`~faultnet.runs.long_run.LongRun`
(and of :func:`~faultnet.simulate_to_parquet` with ``out=None``).  The events go
into a sink (:class:`ChunkSink`): checkpoint chunks in the checkpoint folder
(the protocol is in :mod:`faultnet.runs.checkpoint`), or for ``out=None`` only
the magnitudes and plate times.  The LongRun then verifies the chunks and
merges them into the output.

``on_commit``, if given, is called with the number of committed chunks after
each chunk and the checkpoint covering it are on disk (file outputs only).
Whatever it raises ends the run as a kill at that instant would, after the
commit: tests use it to interrupt a run between two commits.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import sys
import time
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
from tqdm.auto import tqdm

from faultnet.exceptions import CatalogError
from faultnet.io.atomic import atomic_write_json
from faultnet.io.parquet import (
    CATALOG_FORMAT,
    FORMAT_VERSION,
    provenance,
    utc_now,
    write_part,
)
from faultnet.runs.checkpoint import (
    CHECKPOINT_SUFFIX,
    RUN_FORMAT,
    Checkpoint,
    chunk_path,
    save_checkpoint,
    sha256_file,
    side_chunk_path,
)
from faultnet.runs.identity import side_tables
from faultnet.runs.models import (
    compiling_label,
    model_metadata,
    new_simulator,
    random_start,
    time_name,
    transient_time,
    work_counters,
)

__all__ = ["ChunkSink", "RunReport", "run_loop", "write_failure"]

#: target wall time of one advance of the Simulator (smooth progress, bounded memory)
_CALL_SECONDS = 0.25
#: side-table rows (per-block slips) that commit a chunk however few its events: memory
SIDE_ROWS_PER_CHUNK = 4_000_000
#: the Simulator's ``max_slip_rows`` in a run: no limit
_ALL_ROWS = 2**62


@dataclass
class RunReport:
    """What a long run (:func:`~faultnet.simulate_to_parquet`) did.

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


class ChunkSink:
    """Where the events of a run go: checkpoint chunks in ``wd``, or magnitudes only.

    ``tables`` names the side tables (:data:`~faultnet.runs.checkpoint.SIDE_TABLES`) the run
    writes next to its events, each a chunk part of its own.
    """

    def __init__(self, wd, first_md, committed, tables=()):
        self.wd, self.first_md = wd, first_md
        self.committed = committed  # rows in committed chunks
        self.tables = tuple(tables)
        self.buffer, self.buffered = [], 0
        self.sides, self.side_rows = {name: [] for name in self.tables}, 0
        self.mags, self.times, self.seen = [], [], {}

    def add(self, result):
        """Buffer a :class:`~faultnet.SimulationResult`'s events and side tables."""
        self.buffer.append(result.events)
        self.buffered += len(result.events)
        for name in self.tables:
            frame = getattr(result, name)
            self.sides[name].append(frame)
            self.side_rows += len(frame)

    @property
    def full(self) -> bool:
        """Whether the buffered side-table rows call for a commit (bounded memory)."""
        return self.side_rows >= SIDE_ROWS_PER_CHUNK

    def flush(self, ck: Checkpoint) -> bool:
        """Commit the buffered events: a chunk file, then the checkpoint covering it.

        The buffer is emptied first: a commit that fails is not retried, and a
        chunk written without its checkpoint is discarded on resume.  Returns
        True when a chunk was committed to disk.
        """
        if not self.buffered:
            return False
        if self.committed + self.buffered != ck.rows or ck.state.n_events != ck.rows:
            raise CatalogError("internal: the buffered events do not match the state")
        buf, n = self.buffer, self.buffered
        events = _joined(buf)
        sides = {name: _joined(frames) for name, frames in self.sides.items()}
        self.buffer, self.buffered = [], 0
        self.sides, self.side_rows = {name: [] for name in self.tables}, 0
        if self.wd is None:
            self._see(events)
        else:
            self._commit(events, sides, ck)
        self.committed += n
        return self.wd is not None

    def _commit(self, events, sides, ck):
        chunk_md = {"chunk": ck.n_chunks}
        if self.first_md.get("initial_state"):
            chunk_md["initial_state"] = self.first_md["initial_state"]
        ck_path = os.path.join(self.wd, "checkpoint.npz")
        files = {None: chunk_path(self.wd, ck.n_chunks)}
        files.update((name, side_chunk_path(self.wd, name, ck.n_chunks)) for name in sides)
        shas = {}
        for name, path in files.items():
            with write_failure(path, ck_path, self.committed):
                write_part(events if name is None else sides[name], path, chunk_md)
                shas[name] = sha256_file(path)
        sha = [*ck.sha256, shas.pop(None)]
        covering_sides = {name: [*ck.sides[name], shas[name]] for name in sides}
        covering = Checkpoint(ck.state, ck.rows, ck.n_chunks + 1, ck.counters, sha,
                              covering_sides)  # fmt: skip
        with write_failure(ck_path, ck_path, self.committed):
            save_checkpoint(ck_path, covering)
        ck.n_chunks, ck.sha256, ck.sides = ck.n_chunks + 1, sha, covering_sides

    def _see(self, events):
        self.mags.append(events["M"].to_numpy(copy=True))
        self.times.append(events["t"].to_numpy(copy=True))
        self.seen.setdefault("t_first", float(events["t"].iloc[0]))
        self.seen["t_last"] = float(events["t"].iloc[-1])
        self.seen["largest_n_blocks"] = max(
            self.seen.get("largest_n_blocks", 0), int(events["n_blocks"].max())
        )
        self.seen["sum_n_blocks"] = self.seen.get("sum_n_blocks", 0) + int(events["n_blocks"].sum())
        if "duration" in events:
            total = self.seen.get("sum_duration", 0.0) + float(events["duration"].sum())
            self.seen["sum_duration"] = total


def _joined(frames):
    return pd.concat(frames, ignore_index=True) if len(frames) > 1 else frames[0]


@contextlib.contextmanager
def write_failure(path, ck_path, committed, what="write"):
    """Turn an OSError (a full disk, say) into a message naming the file and what is safe."""
    try:
        yield
    except CatalogError:
        raise
    except OSError as exc:
        out = os.path.dirname(ck_path)[: -len(CHECKPOINT_SUFFIX)]
        if not os.path.isfile(ck_path):  # its folder was deleted or moved during the run
            kept = "nothing was kept" if committed == 0 else "the events computed so far are lost"
            raise CatalogError(
                f"cannot {what} {path}: {exc.strerror or exc}. The checkpoint {ck_path} is "
                f"gone too (was the output folder deleted or moved?), so {kept}; run "
                f"'faultnet simulate' again into an existing folder"
            ) from exc
        raise CatalogError(
            f"cannot {what} {path}: {exc.strerror or exc}. The checkpoint {ck_path} is intact "
            f"({committed:,} events committed); free space (or fix the cause) and run "
            f"'faultnet simulate --resume --out {out}' to continue"
        ) from exc


def _open_run(wd, identity, extra, stored):
    """Create the checkpoint folder and its run.json; a resumed run keeps its ``stored`` one."""
    if wd is None:
        return {}, False
    created = not os.path.isdir(wd)
    os.makedirs(wd, exist_ok=True)
    if stored is not None and os.path.isfile(os.path.join(wd, "run.json")):
        return dict(stored), created
    run_json = os.path.join(wd, "run.json")
    first_md = dict(identity, format=RUN_FORMAT, created=utc_now(), extra=extra or {})
    atomic_write_json(run_json, first_md)
    return first_md, created


def _final_metadata(model, options, identity, first_md, counters, extra, transient, chunk_events):
    seq = np.random.SeedSequence(identity["seed_entropy"], spawn_key=identity["seed_spawn_key"])
    md = model_metadata(model, options, identity["dt"], seq)
    md.update(
        format=CATALOG_FORMAT,
        format_version=FORMAT_VERSION,
        first_event=0,
        n_events=identity["n_events"],
        initial_state=first_md.get("initial_state", "random"),
        record_slips=bool(identity.get("record_slips", False)),
        wall_time_s=counters["wall_time_s"],
        **{key: counters[key] for key in work_counters(model)},
        graph_hash=identity["graph_hash"],
        transient=int(transient[0]),
        chunk_events=int(chunk_events),
        runs=counters["runs"],
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
    if transient[1]:
        md["transient_rule"] = transient[1]
    md.update(extra or {})
    return md


def _transient(transient, n_events, sink, wd, n_chunks, model):
    """``(events, rule)`` left out of b fits: as given, or by the default rule (None)."""
    if transient is not None:
        return int(transient), None
    from faultnet.io.summary import default_transient

    rule = dict(t_min=transient_time(model), what=time_name(model))
    if wd is None:
        return default_transient(sink.times, n_events, **rule)
    columns = (pq.read_table(chunk_path(wd, i), columns=["t"]) for i in range(n_chunks))
    try:
        return default_transient((c.column(0).to_numpy() for c in columns), n_events, **rule)
    except (OSError, pa.ArrowException) as exc:
        raise CatalogError(f"cannot read the plate times of the chunks in {wd}: {exc}") from exc


def _simulator(model, seq, options, ck, first_md, wd, record_slips):
    """The simulator of the run: from the seed, or from the checkpoint's state.  Every
    per-block slip is kept (the chunks bound the memory), never truncated."""
    slips = dict(record_slips=record_slips, max_slip_rows=_ALL_ROWS)
    if ck.state is not None:
        return new_simulator(model, x0=ck.state, options=options, **slips)
    sim = new_simulator(model, rng=seq, options=options, **slips)
    first_md["initial_state"] = random_start(model)
    if wd is not None:
        atomic_write_json(os.path.join(wd, "run.json"), first_md)
    return sim


def _advance(sim, ck, sink, bar, *, n_events, chunk_events, interval, on_commit):
    """Advance ``sim`` to ``n_events`` events, committing a chunk when one is due."""
    last_ck = time.monotonic()
    call = 256
    while ck.rows < n_events:
        n_call = min(call, n_events - ck.rows, chunk_events - sink.buffered)
        res = sim.advance(n_call, progress=False)
        sink.add(res)
        ck.state, ck.rows = sim.state, ck.rows + n_call
        loop_s = float(res.metadata["wall_time_s"])
        for key in work_counters(sim.model):
            ck.counters[key] += int(res.metadata[key])
        ck.counters["wall_time_s"] += loop_s
        bar.update(n_call)
        bar.set_postfix(t=f"{ck.state.u:.6g}", refresh=False)
        # the next call takes about _CALL_SECONDS at the rate just measured
        rate = n_call / max(loop_s, 1e-6)
        call = int(min(max(rate * _CALL_SECONDS, 1), chunk_events, 2 * call))
        due = time.monotonic() - last_ck >= interval
        if sink.buffered >= chunk_events or ck.rows >= n_events or due or sink.full:
            committed = sink.flush(ck)
            last_ck = time.monotonic()
            if committed and on_commit is not None:
                on_commit(ck.n_chunks)


def run_loop(*, model, n_events, wd, identity, seq, options, chunk_events, interval,
             progress, transient, extra, desc, resume_point, stored, on_commit,
             record_slips=False):  # fmt: skip
    """Run to ``n_events``, committing chunks to ``wd`` (None: keep magnitudes only).

    Returns ``(ck, md, sink)``: the checkpoint after the last commit, the final
    metadata and the sink (whose magnitudes and plate times an ``out=None`` run reports).
    ``resume_point`` is the checkpoint a resumed run continues and ``stored`` its run.json.
    """
    tables = side_tables(model, record_slips) if wd is not None else ()
    ck = resume_point or Checkpoint(None, sides={name: [] for name in tables})
    ck.counters["runs"] += 1
    first_md, created = _open_run(wd, identity, extra, stored)
    sink = ChunkSink(wd, first_md, ck.rows, tables)
    sim = _simulator(model, seq, options, ck, first_md, wd, record_slips and wd is not None)
    if progress is not False and sim.compiles:  # a pause of seconds that must not look hung
        tqdm.write(compiling_label(model), file=sys.stderr)
    bar = tqdm(total=n_events, initial=ck.rows, unit="ev", desc=desc or model.params["graph"],
               disable=(None if progress is None else not progress), dynamic_ncols=True,
               smoothing=0.1)  # fmt: skip
    try:
        _advance(sim, ck, sink, bar, n_events=n_events, chunk_events=chunk_events,
                 interval=interval, on_commit=on_commit)  # fmt: skip
    except BaseException:
        with contextlib.suppress(Exception):
            sink.flush(ck)  # keep what was computed before the failure (if consistent)
        bar.close()
        if created and ck.n_chunks == 0:  # nothing committed: leave no checkpoint behind
            with contextlib.suppress(OSError):
                shutil.rmtree(wd)
        raise
    bar.close()
    transient = _transient(transient, n_events, sink, wd, ck.n_chunks, model)
    md = _final_metadata(
        model, options, identity, first_md, ck.counters, extra, transient, chunk_events
    )
    return ck, md, sink
