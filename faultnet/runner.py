"""Long runs straight to a Parquet catalog, checkpointed so a kill loses nothing.

:func:`simulate_to_parquet` runs a model in short calls of
:func:`faultnet.simulate`, each continuing exactly from the previous state,
and writes the events in parts.  Next to the output ``catalog.parquet`` it
keeps a folder ``catalog.parquet.checkpoint/`` holding

``run.json``
    what is being run: graph hash, dt, number of events, seed, request;
``part-000000.parquet``, ...
    the committed events, one file per chunk;
``checkpoint.npz``
    the model state after the last committed part (``z``, ``offset``, ``w``,
    ``n_events``) and how many parts and rows it covers.

A part is written atomically first, then the checkpoint that covers it; a
part beyond the checkpoint (a kill between the two steps) is discarded on
resume, so the resumed run continues from a state that matches its catalog
exactly and the final catalog equals an uninterrupted run bit for bit.  When
all events are done the parts are streamed into ``catalog.parquet`` (atomic
rename) and the folder is removed.  Memory stays O(N + chunk).

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
import json
import math
import os
import re
import shutil
import time
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from tqdm.auto import tqdm

from faultnet.exceptions import InvalidParameterError
from faultnet.io import (
    CATALOG_FORMAT,
    FORMAT_VERSION,
    CatalogError,
    OutputExistsError,
    atomic_path,
    atomic_write_json,
    is_tmp_name,
    merge_parts,
    provenance,
    read_metadata,
    utc_now,
    write_part,
)

__all__ = [
    "CHECKPOINT_SUFFIX",
    "RunReport",
    "checkpoint_dir",
    "checkpoint_status",
    "run_from_spec",
    "seed_sequence",
    "simulate_to_parquet",
]

CHECKPOINT_SUFFIX = ".checkpoint"
RUN_FORMAT = "faultnet-run"
_PART_RE = re.compile(r"part-(\d{6})\.parquet$")
#: run.json fields that must agree for a resume to continue the same run
_IDENTITY = ("n_events", "dt", "seed_entropy", "seed_spawn_key", "graph_hash")
#: target wall time of one call of simulate (smooth progress, bounded memory)
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


def checkpoint_dir(out) -> str:
    """The checkpoint folder of an output catalog: ``out + ".checkpoint"``."""
    return os.fspath(out) + CHECKPOINT_SUFFIX


def seed_sequence(rng) -> np.random.SeedSequence:
    """A recordable SeedSequence from a SPEC 7 ``rng`` argument.

    None draws fresh entropy; an int or SeedSequence is used as is; a
    Generator spawns a child (``Generator.spawn``), so the run is
    reproducible from the recorded entropy and spawn key.
    """
    if rng is None or (isinstance(rng, (int, np.integer)) and not isinstance(rng, bool)):
        return np.random.SeedSequence(None if rng is None else int(rng))
    if isinstance(rng, np.random.SeedSequence):
        return rng
    if isinstance(rng, np.random.Generator):
        seq = getattr(rng.bit_generator, "seed_seq", None)
        if isinstance(seq, np.random.SeedSequence):
            return seq.spawn(1)[0]
        return np.random.SeedSequence(rng.integers(0, 2**63, size=4).tolist())
    raise InvalidParameterError(
        f"rng must be None, an int, a SeedSequence or a Generator; got {type(rng).__name__}"
    )


def _part_name(i):
    return f"part-{i:06d}.parquet"


def _run_identity(model, n_events, dt, seq):
    from faultnet.specs import graph_hash

    return {
        "n_events": int(n_events),
        "dt": float(dt),
        "seed_entropy": seq.entropy,
        "seed_spawn_key": list(seq.spawn_key),
        "graph_hash": graph_hash(model),
    }


def _mismatch(stored, wanted, keys=_IDENTITY):
    diffs = []
    for key in keys:
        a, b = stored.get(key), wanted.get(key)
        if isinstance(a, (list, tuple)) or isinstance(b, (list, tuple)):
            a, b = list(a or []), list(b or [])
        if a != b:
            diffs.append(
                f"{key}: checkpoint has {stored.get(key)!r}, this call {wanted.get(key)!r}"
            )
    return diffs


def _read_json(path):
    with open(path, encoding="utf-8") as fh:
        return json.load(fh)


def _save_checkpoint(path, state, rows, n_parts, counters):
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        np.savez(
            fh,
            z=np.asarray(state.z, dtype=np.float64),
            offset=np.float64(state.offset),
            w=np.float64(state.w),
            n_events=np.int64(state.n_events),
            rows=np.int64(rows),
            n_parts=np.int64(n_parts),
            wall_time_s=np.float64(counters["wall_time_s"]),
            n_steps=np.int64(counters["n_steps"]),
            block_steps=np.int64(counters["block_steps"]),
            sessions=np.int64(counters["sessions"]),
        )


def _load_checkpoint(path):
    from faultnet.state import State

    with np.load(path) as data:
        state = State(
            z=data["z"].copy(),
            offset=float(data["offset"]),
            w=float(data["w"]),
            n_events=int(data["n_events"]),
        )
        counters = {
            "wall_time_s": float(data["wall_time_s"]),
            "n_steps": int(data["n_steps"]),
            "block_steps": int(data["block_steps"]),
            "sessions": int(data["sessions"]),
        }
        return state, int(data["rows"]), int(data["n_parts"]), counters


def checkpoint_status(out) -> dict | None:
    """Progress of an interrupted run of ``out`` (None if there is no checkpoint).

    Returns ``{"events_done", "n_events", "parts", "run"}`` where ``run`` is the
    content of ``run.json``.
    """
    wd = checkpoint_dir(out)
    if not os.path.isdir(wd):
        return None
    run = (
        _read_json(os.path.join(wd, "run.json"))
        if os.path.isfile(os.path.join(wd, "run.json"))
        else {}
    )
    done = parts = 0
    ck = os.path.join(wd, "checkpoint.npz")
    if os.path.isfile(ck):
        _, done, parts, _ = _load_checkpoint(ck)
    return {"events_done": done, "n_events": run.get("n_events"), "parts": parts, "run": run}


def _own_entries(wd):
    """Names in a checkpoint folder that the runner did not write (foreign files)."""
    ok = {"run.json", "checkpoint.npz"}
    return [
        n
        for n in os.listdir(wd)
        if n not in ok and not _PART_RE.fullmatch(n) and not is_tmp_name(n)
    ]


def _remove_checkpoint_dir(wd):
    foreign = _own_entries(wd)
    if foreign:
        raise OutputExistsError(
            f"{wd} holds files faultnet did not write ({', '.join(sorted(foreign)[:5])}); "
            "remove them by hand"
        )
    shutil.rmtree(wd)
    fsync_parent(wd)


def fsync_parent(path):
    from faultnet.io import fsync_dir

    fsync_dir(os.path.dirname(os.path.abspath(path)))


def _prepare_resume(wd, identity):
    """Load and verify a checkpoint; discard parts and temp files it does not cover."""
    run_json = os.path.join(wd, "run.json")
    if os.path.isfile(run_json):
        stored = _read_json(run_json)
        diffs = _mismatch(stored, identity)
        if diffs:
            raise InvalidParameterError(
                f"cannot resume {wd}: it is another run ({'; '.join(diffs)}). Rerun with the "
                "original parameters, or pass force to discard the checkpoint"
            )
    ck = os.path.join(wd, "checkpoint.npz")
    if not os.path.isfile(ck):
        _discard_uncommitted(wd, 0)
        return None, 0, 0, None
    try:
        state, rows, n_parts, counters = _load_checkpoint(ck)
    except (OSError, ValueError, KeyError) as exc:
        raise CatalogError(f"checkpoint {ck} is unreadable ({exc}); pass force to restart") from exc
    import pyarrow.parquet as pq

    total = 0
    for i in range(n_parts):
        part = os.path.join(wd, _part_name(i))
        try:
            total += pq.read_metadata(part).num_rows
        except (OSError, Exception) as exc:
            raise CatalogError(
                f"committed part {part} is missing or corrupt ({exc}); the run cannot resume "
                "exactly: pass force to restart it"
            ) from exc
    if total != rows:
        raise CatalogError(
            f"checkpoint {ck} covers {rows} events but its parts hold {total}; "
            "pass force to restart the run"
        )
    _discard_uncommitted(wd, n_parts)
    return state, rows, n_parts, counters


def _discard_uncommitted(wd, n_parts):
    """Remove parts the checkpoint does not cover and temporary files of killed writers."""
    for name in os.listdir(wd):
        m = _PART_RE.fullmatch(name)
        if (m and int(m.group(1)) >= n_parts) or is_tmp_name(name):
            os.remove(os.path.join(wd, name))


def _discard_tmp_outputs(out):
    """Remove temporary files of a merge into ``out`` that was killed."""
    folder, name = os.path.split(os.path.abspath(out))
    for entry in os.listdir(folder):
        if is_tmp_name(entry) and entry.startswith(f".{name}.tmp-"):
            with contextlib.suppress(OSError):
                os.remove(os.path.join(folder, entry))


def _final_metadata(model, identity, first_md, counters, extra, transient, chunk_events):
    from faultnet import __version__

    md = dict(model.params)
    md.update(
        format=CATALOG_FORMAT,
        format_version=FORMAT_VERSION,
        dt=identity["dt"],
        faultnet_version=__version__,
        first_event=0,
        n_events=identity["n_events"],
        seed_entropy=identity["seed_entropy"],
        seed_spawn_key=tuple(identity["seed_spawn_key"]),
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


def _check_positive_int(name, value, minimum=1):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InvalidParameterError(f"{name} must be an integer >= {minimum}; got {value!r}")
    return int(value)


def simulate_to_parquet(
    model,
    n_events,
    out,
    *,
    rng=None,
    dt=None,
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
        Integration step (default :func:`faultnet.default_dt`).
    chunk_events : int
        Events per part file: memory is O(N + chunk_events).
    checkpoint_interval : float
        Seconds between checkpoints; a part is also committed whenever
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
    from faultnet.model import CarlsonLanger
    from faultnet.simulate import default_dt

    if not isinstance(model, CarlsonLanger):
        raise InvalidParameterError(f"model must be a CarlsonLanger; got {type(model).__name__}")
    n_events = _check_positive_int("n_events", n_events)
    chunk_events = _check_positive_int("chunk_events", chunk_events)
    transient = _check_positive_int("transient", transient, minimum=0)
    interval = float(checkpoint_interval)
    if not (interval >= 0.0):
        raise InvalidParameterError(
            f"checkpoint_interval must be >= 0 s; got {checkpoint_interval!r}"
        )
    dt = default_dt(model) if dt is None else float(dt)
    if out is None:
        seq = seed_sequence(rng)
        return _run(
            model,
            n_events,
            None,
            None,
            _run_identity(model, n_events, dt, seq),
            seq,
            chunk_events,
            interval,
            progress,
            transient,
            metadata,
            desc,
            None,
        )
    out = os.fspath(out)
    wd = checkpoint_dir(out)
    folder = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(folder):
        raise InvalidParameterError(f"output folder {folder} does not exist")
    if os.path.isdir(out):
        raise OutputExistsError(f"{out} is a folder; give a file name for the catalog")
    if resume and rng is None:
        stored = _stored_request(out)
        if stored is not None:
            rng = np.random.SeedSequence(
                stored["seed_entropy"], spawn_key=tuple(stored["seed_spawn_key"])
            )
    seq = seed_sequence(rng)
    identity = _run_identity(model, n_events, dt, seq)
    if os.path.exists(out):
        if resume and not force:
            done = _complete_output(out, identity)
            if os.path.isdir(wd):
                _remove_checkpoint_dir(wd)
            return RunReport(out, done, status="already complete", resumed_from=n_events)
        if not force:
            raise OutputExistsError(
                f"{out} exists; refusing to overwrite it (use --force / force=True, or "
                "--resume to check that it is complete)"
            )
    resume_point = None
    if resume or force:
        _discard_tmp_outputs(out)
    if os.path.isdir(wd):
        if resume and not force:
            resume_point = _prepare_resume(wd, identity)
        elif force:
            _remove_checkpoint_dir(wd)
        else:
            st = checkpoint_status(out) or {}
            raise OutputExistsError(
                f"an interrupted run of {out} exists ({st.get('events_done', 0)} of "
                f"{st.get('n_events', '?')} events committed in {wd}); pass --resume / "
                "resume=True to continue it, or --force / force=True to discard it"
            )
    return _run(
        model,
        n_events,
        out,
        wd,
        identity,
        seq,
        chunk_events,
        interval,
        progress,
        transient,
        metadata,
        desc,
        resume_point,
    )


def _stored_request(out):
    """Seed (and request) of an earlier run of ``out``: from its checkpoint or the file."""
    run_json = os.path.join(checkpoint_dir(out), "run.json")
    if os.path.isfile(run_json):
        return _read_json(run_json)
    if os.path.isfile(out):
        try:
            return read_metadata(out)
        except CatalogError:
            return None
    return None


def _complete_output(out, identity):
    md = read_metadata(out)
    diffs = _mismatch(md, identity)
    if diffs:
        raise OutputExistsError(
            f"{out} exists and holds another run ({'; '.join(diffs)}); refusing to overwrite it "
            "(use --force / force=True)"
        )
    return md


def _run(
    model,
    n_events,
    out,
    wd,
    identity,
    seq,
    chunk_events,
    interval,
    progress,
    transient,
    extra,
    desc,
    resume_point,
):
    from faultnet.simulate import simulate

    state, rows, n_parts, counters = resume_point or (None, 0, 0, None)
    resumed_from = rows
    if counters is None:
        counters = {"wall_time_s": 0.0, "n_steps": 0, "block_steps": 0, "sessions": 0}
    counters["sessions"] += 1
    first_md = {}
    created = False
    if wd is not None:
        created = not os.path.isdir(wd)
        os.makedirs(wd, exist_ok=True)
        run_json = os.path.join(wd, "run.json")
        if os.path.isfile(run_json):
            first_md = _read_json(run_json)
        else:
            first_md = dict(identity, format=RUN_FORMAT, created=utc_now(), extra=extra or {})
            atomic_write_json(run_json, first_md)
        ck_path = os.path.join(wd, "checkpoint.npz")
        if state is None and rows == 0 and os.path.isfile(ck_path):
            os.remove(ck_path)  # pragma: no cover - defensive
    mags = [] if out is None else None
    times = [] if out is None else None
    seen = {}
    buffer, buffered = [], 0
    last_ck = time.monotonic()
    call = 256
    bar = tqdm(
        total=n_events,
        initial=rows,
        unit="ev",
        desc=desc or model.params["graph"],
        disable=(None if progress is None else not progress),
        dynamic_ncols=True,
        smoothing=0.1,
    )

    def flush():
        nonlocal buffer, buffered, n_parts, last_ck
        if not buffered:
            return
        events = pd.concat(buffer, ignore_index=True) if len(buffer) > 1 else buffer[0]
        buffer, buffered = [], 0
        if out is None:
            mags.append(events["M"].to_numpy(copy=True))
            times.append(events["t"].to_numpy(copy=True))
            if "t_first" not in seen:
                seen["t_first"] = float(events["t"].iloc[0])
            seen["t_last"] = float(events["t"].iloc[-1])
            seen["largest_n_blocks"] = max(
                seen.get("largest_n_blocks", 0), int(events["n_blocks"].max())
            )
        else:
            write_part(
                events,
                os.path.join(wd, _part_name(n_parts)),
                {
                    "part": n_parts,
                    **(
                        {"initial_state": first_md.get("initial_state")}
                        if first_md.get("initial_state")
                        else {}
                    ),
                },
            )
            _save_checkpoint(os.path.join(wd, "checkpoint.npz"), state, rows, n_parts + 1, counters)
            n_parts += 1
        last_ck = time.monotonic()

    try:
        while rows < n_events:
            n_call = min(call, n_events - rows, chunk_events - buffered)
            tic = time.perf_counter()
            if state is None:
                res = simulate(model, n_call, rng=seq, dt=identity["dt"], progress=False)
                if "initial_state" not in first_md and wd is not None:
                    first_md["initial_state"] = res.metadata.get("initial_state")
                    atomic_write_json(os.path.join(wd, "run.json"), first_md)
                elif out is None:
                    first_md["initial_state"] = res.metadata.get("initial_state")
            else:
                res = simulate(model, n_call, x0=state, dt=identity["dt"], progress=False)
            elapsed = time.perf_counter() - tic
            state = res.state
            buffer.append(res.events)
            buffered += n_call
            rows += n_call
            loop_s = float(res.metadata.get("wall_time_s", elapsed))
            counters["wall_time_s"] += loop_s
            counters["n_steps"] += int(res.metadata.get("n_steps", 0))
            counters["block_steps"] += int(res.metadata.get("block_steps", 0))
            del res
            bar.update(n_call)
            bar.set_postfix(t=f"{state.offset + state.w:.6g}", refresh=False)
            # size calls by the time spent in events, not by the fixed set-up
            # cost of a call (O(N): ~0.1 s at 10^6 blocks)
            if loop_s < _CALL_SECONDS / 2:
                call = min(call * 2, chunk_events)
            elif loop_s > 2 * _CALL_SECONDS:
                call = max(call // 2, 1)
            if (
                buffered >= chunk_events
                or rows >= n_events
                or time.monotonic() - last_ck >= interval
            ):
                flush()
    except BaseException:
        consistent = (
            state is not None and state.n_events == rows and sum(len(b) for b in buffer) == buffered
        )
        if consistent:
            with contextlib.suppress(Exception):
                flush()  # keep what was computed before the failure
        bar.close()
        if created and n_parts == 0:  # nothing committed: leave no checkpoint behind
            with contextlib.suppress(OSError):
                shutil.rmtree(wd)
        raise
    bar.close()
    md = _final_metadata(model, identity, first_md, counters, extra, transient, chunk_events)
    status = "resumed" if resumed_from else "completed"
    if out is None:
        return RunReport(
            None,
            md,
            status=status,
            magnitudes=np.concatenate(mags) if mags else np.zeros(0),
            plate_times=np.concatenate(times) if times else np.zeros(0),
            seen=seen,
        )
    parts = [os.path.join(wd, _part_name(i)) for i in range(n_parts)]
    merge_parts(parts, out, md, overwrite=True)
    _remove_checkpoint_dir(wd)
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
    alpha, dt, seed, transient) are taken from the interrupted run's
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
        stored = _stored_request(os.fspath(out))
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
