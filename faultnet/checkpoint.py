"""The checkpoint protocol of long runs: what is on disk, and how a resume trusts it.

Next to an output ``catalog.parquet`` an unfinished run keeps a folder
``catalog.parquet.checkpoint/`` holding

``run.json``
    the run's identity (graph hash, events, step, options, seed) and request;
``chunk-000000.parquet``, ...
    the committed events, one file per checkpoint *chunk*;
``checkpoint.npz``
    the model state after the last committed chunk (``z``, ``offset``, ``w``,
    ``n_events``), how many chunks and rows it covers, and the work counters.

A chunk is written atomically first, then the checkpoint that covers it; a
chunk beyond the checkpoint (a kill between the two steps) is discarded on
resume, so the resumed run continues from a state that matches its catalog
exactly and the final catalog equals an uninterrupted run bit for bit.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil

import numpy as np

from faultnet.atomic import atomic_path, fsync_dir, is_tmp_name
from faultnet.exceptions import CatalogError, InvalidParameterError, OutputExistsError
from faultnet.state import State

__all__ = [
    "CHECKPOINT_SUFFIX",
    "Checkpoint",
    "checkpoint_dir",
    "checkpoint_status",
    "chunk_path",
    "discard_tmp_outputs",
    "mismatch",
    "prepare_resume",
    "read_json",
    "remove_checkpoint_dir",
    "run_identity",
    "save_checkpoint",
]

CHECKPOINT_SUFFIX = ".checkpoint"
RUN_FORMAT = "faultnet-run"
_CHUNK_RE = re.compile(r"chunk-(\d{6})\.parquet$")
#: run.json fields that must agree for a resume to continue the same run
IDENTITY = ("n_events", "dt", "options", "seed_entropy", "seed_spawn_key", "graph_hash")
_COUNTERS = {"wall_time_s": float, "n_steps": int, "block_steps": int, "sessions": int}


def checkpoint_dir(out) -> str:
    """The checkpoint folder of an output catalog: ``out + ".checkpoint"``."""
    return os.fspath(out) + CHECKPOINT_SUFFIX


def chunk_path(wd, i) -> str:
    """Path of committed chunk ``i`` in the checkpoint folder ``wd``."""
    return os.path.join(wd, f"chunk-{i:06d}.parquet")


def run_identity(model, n_events, dt, options, seq) -> dict:
    """What makes two runs the same run (compared by :func:`mismatch` on resume)."""
    from faultnet.specs import graph_hash

    return {
        "n_events": int(n_events),
        "dt": float(dt),
        "options": options.to_dict(),
        "seed_entropy": seq.entropy,
        "seed_spawn_key": list(seq.spawn_key),
        "graph_hash": graph_hash(model),
    }


def mismatch(stored, wanted, keys=IDENTITY) -> list:
    """The identity fields in which ``stored`` and ``wanted`` differ, as sentences."""
    diffs = []
    for key in keys:
        a, b = stored.get(key), wanted.get(key)
        if isinstance(a, list | tuple) or isinstance(b, list | tuple):
            a, b = list(a or []), list(b or [])
        if a != b:
            diffs.append(
                f"{key}: checkpoint has {stored.get(key)!r}, this call {wanted.get(key)!r}"
            )
    return diffs


def read_json(path):
    with open(path, encoding="utf-8") as fh:
        return json.load(fh)


class Checkpoint:
    """The contents of ``checkpoint.npz``: the state after ``rows`` committed events."""

    def __init__(self, state, rows=0, n_chunks=0, counters=None):
        self.state = state
        self.rows = rows
        self.n_chunks = n_chunks
        self.counters = counters or {name: kind(0) for name, kind in _COUNTERS.items()}


def save_checkpoint(path, ck: Checkpoint):
    """Write ``checkpoint.npz`` atomically."""
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        np.savez(
            fh,
            z=np.asarray(ck.state.z, dtype=np.float64),
            offset=np.float64(ck.state.offset),
            w=np.float64(ck.state.w),
            n_events=np.int64(ck.state.n_events),
            rows=np.int64(ck.rows),
            n_chunks=np.int64(ck.n_chunks),
            **{name: np.asarray(ck.counters[name]) for name in _COUNTERS},
        )


def load_checkpoint(path) -> Checkpoint:
    with np.load(path) as data:
        state = State(
            z=data["z"].copy(),
            offset=float(data["offset"]),
            w=float(data["w"]),
            n_events=int(data["n_events"]),
        )
        counters = {name: kind(data[name]) for name, kind in _COUNTERS.items()}
        return Checkpoint(state, int(data["rows"]), int(data["n_chunks"]), counters)


def checkpoint_status(out) -> dict | None:
    """Progress of an interrupted run of ``out`` (None if there is no checkpoint).

    Returns ``{"events_done", "n_events", "chunks", "run"}`` where ``run`` is the
    content of ``run.json``.
    """
    wd = checkpoint_dir(out)
    if not os.path.isdir(wd):
        return None
    run_json = os.path.join(wd, "run.json")
    run = read_json(run_json) if os.path.isfile(run_json) else {}
    done = chunks = 0
    ck = os.path.join(wd, "checkpoint.npz")
    if os.path.isfile(ck):
        loaded = load_checkpoint(ck)
        done, chunks = loaded.rows, loaded.n_chunks
    return {"events_done": done, "n_events": run.get("n_events"), "chunks": chunks, "run": run}


def _foreign_entries(wd):
    """Names in a checkpoint folder that the runner did not write."""
    ok = {"run.json", "checkpoint.npz"}
    return [
        n
        for n in os.listdir(wd)
        if n not in ok and not _CHUNK_RE.fullmatch(n) and not is_tmp_name(n)
    ]


def remove_checkpoint_dir(wd):
    """Remove a checkpoint folder, refusing if it holds files faultnet did not write."""
    foreign = _foreign_entries(wd)
    if foreign:
        raise OutputExistsError(
            f"{wd} holds files faultnet did not write ({', '.join(sorted(foreign)[:5])}); "
            "remove them by hand"
        )
    shutil.rmtree(wd)
    fsync_dir(os.path.dirname(os.path.abspath(wd)))


def prepare_resume(wd, identity) -> Checkpoint | None:
    """Load and verify a checkpoint; discard chunks and temp files it does not cover."""
    run_json = os.path.join(wd, "run.json")
    if os.path.isfile(run_json):
        diffs = mismatch(read_json(run_json), identity)
        if diffs:
            raise InvalidParameterError(
                f"cannot resume {wd}: it is another run ({'; '.join(diffs)}). Rerun with the "
                "original parameters, or pass force to discard the checkpoint"
            )
    ck = os.path.join(wd, "checkpoint.npz")
    if not os.path.isfile(ck):
        _discard_uncommitted(wd, 0)
        return None
    try:
        loaded = load_checkpoint(ck)
    except (OSError, ValueError, KeyError) as exc:
        raise CatalogError(f"checkpoint {ck} is unreadable ({exc}); pass force to restart") from exc
    import pyarrow.parquet as pq

    total = 0
    for i in range(loaded.n_chunks):
        path = chunk_path(wd, i)
        try:
            total += pq.read_metadata(path).num_rows
        except Exception as exc:
            raise CatalogError(
                f"committed chunk {path} is missing or corrupt ({exc}); the run cannot resume "
                "exactly: pass force to restart it"
            ) from exc
    if total != loaded.rows:
        raise CatalogError(
            f"checkpoint {ck} covers {loaded.rows} events but its chunks hold {total}; "
            "pass force to restart the run"
        )
    _discard_uncommitted(wd, loaded.n_chunks)
    return loaded


def _discard_uncommitted(wd, n_chunks):
    """Remove chunks the checkpoint does not cover and temporary files of killed writers."""
    for name in os.listdir(wd):
        m = _CHUNK_RE.fullmatch(name)
        if (m and int(m.group(1)) >= n_chunks) or is_tmp_name(name):
            os.remove(os.path.join(wd, name))


def discard_tmp_outputs(out):
    """Remove temporary files of a merge into ``out`` that was killed."""
    folder, name = os.path.split(os.path.abspath(out))
    for entry in os.listdir(folder):
        if is_tmp_name(entry) and entry.startswith(f".{name}.tmp-"):
            with contextlib.suppress(OSError):
                os.remove(os.path.join(folder, entry))
