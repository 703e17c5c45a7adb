"""The checkpoint protocol of long runs: what is on disk, and how a resume trusts it.

Next to an output ``catalog.parquet`` an unfinished run keeps a folder
``catalog.parquet.checkpoint/`` holding

``run.json``
    the run's identity (graph hash, events, step, options, seed) and request;
``chunk-000000.parquet``, ...
    the committed events, one file per checkpoint *chunk*;
``slips-000000.parquet``, ``fault_slips-000000.parquet``, ...
    the chunk's side tables (:data:`SIDE_TABLES`), where the run writes them: the
    per-block slips (``record_slips``) and, on a network of faults, the per-fault slips;
``checkpoint.npz``
    the model state after the last committed chunk (``z``, ``offset``, ``w``,
    ``n_events``), how many chunks and rows it covers, the work counters and the
    SHA-256 of every committed file.

The finished run is the catalog ``out`` and, next to it, one file per side table
(:func:`side_path`: ``catalog.slips.parquet``, ``catalog.fault_slips.parquet``).

A chunk is written atomically first, then the checkpoint that covers it; a
chunk beyond the checkpoint (a kill between the two steps) is discarded on
resume, so the resumed run continues from a state that matches its catalog
exactly and the final catalog equals an uninterrupted run bit for bit.

Guarantees
----------
What is atomic
    every file (chunk, ``checkpoint.npz``, ``run.json``, the catalog) is
    written to a temporary name, fsynced and renamed (:mod:`faultnet.io.atomic`):
    a kill leaves it as it was or complete.  A chunk counts only once the
    checkpoint covering it is written; the checkpoint folder is removed only
    after the catalog is in place.
What is checked
    ``run.json`` must exist and match the call (else the resume is refused);
    ``checkpoint.npz`` records the SHA-256 of every chunk, verified with the
    event numbers on resume, before the merge and by ``faultnet info``
    (:func:`verify_chunks`); every reader and every "already done" decision
    checks a catalog's row count against ``n_events`` and its event numbers
    (:func:`faultnet.io.parquet.verify_catalog`).  Unreadable files are one
    :class:`~faultnet.exceptions.CatalogError` naming the file and ``--force``.
What a lock protects
    one writer per output (``out.parquet.lock``) and per sweep folder
    (``sweep.lock``), see :mod:`faultnet.io.lock`; a second writer is refused
    naming the holder; the operating system releases the lock of a process
    that dies.
What a user must not do
    edit or delete files inside a checkpoint or sweep folder by hand, delete a
    lock whose holder may be alive, or share an output between hosts on a
    file system that does not carry ``flock`` between them.  The full list:
    ``docs/guide/guarantees.rst``.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
import shutil
import zipfile

import numpy as np

from faultnet.exceptions import CatalogError, InvalidParameterError, OutputExistsError
from faultnet.io.atomic import atomic_path, fsync_dir, is_tmp_name
from faultnet.io.slips import SIDE_TABLES
from faultnet.model.state import State
from faultnet.runs.identity import mismatch

__all__ = [
    "CHECKPOINT_SUFFIX",
    "Checkpoint",
    "checkpoint_dir",
    "checkpoint_status",
    "chunk_path",
    "discard_tmp_outputs",
    "prepare_resume",
    "read_json",
    "read_run_json",
    "remove_checkpoint_dir",
    "save_checkpoint",
    "sha256_file",
    "side_chunk_path",
    "verify_chunks",
]

CHECKPOINT_SUFFIX = ".checkpoint"
RUN_FORMAT = "faultnet-run"
_CHUNK_RE = re.compile(r"(chunk|slips|fault_slips)-(\d{6})\.parquet$")
_COUNTERS = {
    "wall_time_s": float,
    "n_steps": int,
    "block_steps": int,
    "n_topplings": int,
    "n_generations": int,
    "runs": int,
}
#: counters that checkpoints written before them lack (read as 0)
_NEWER_COUNTERS = ("n_topplings", "n_generations")
#: a counter's name in checkpoints written by faultnet 0.2 and 0.3.0 development versions
_FORMER_NAMES = {"runs": "sessions"}


def checkpoint_dir(out) -> str:
    """The checkpoint folder of an output catalog: ``out + ".checkpoint"``."""
    return os.fspath(out) + CHECKPOINT_SUFFIX


def chunk_path(wd, i) -> str:
    """Path of committed chunk ``i`` in the checkpoint folder ``wd``."""
    return os.path.join(wd, f"chunk-{i:06d}.parquet")


def side_chunk_path(wd, name, i) -> str:
    """Path of side table ``name``'s part of committed chunk ``i``."""
    return os.path.join(wd, f"{name}-{i:06d}.parquet")


def read_json(path):
    with open(path, encoding="utf-8") as fh:
        return json.load(fh)


def _restart_hint(path):
    out = os.path.dirname(os.path.abspath(path))
    if out.endswith(CHECKPOINT_SUFFIX):
        out = out[: -len(CHECKPOINT_SUFFIX)]
    return f"rerun with --force (force=True) to discard the checkpoint and restart {out}"


def read_run_json(path) -> dict:
    """The run identity in ``run.json``; a garbled or non-object file is a CatalogError."""
    try:
        run = read_json(path)
    except (OSError, ValueError) as exc:
        raise CatalogError(
            f"{path} is unreadable or garbled ({exc}); {_restart_hint(path)}"
        ) from None
    if not isinstance(run, dict):
        raise CatalogError(
            f"{path} holds {type(run).__name__} {str(run)[:40]}, not a run identity; "
            f"{_restart_hint(path)}"
        )
    return run


def sha256_file(path, block=1 << 16) -> str:
    """Hex SHA-256 of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        while chunk := fh.read(block):
            h.update(chunk)
    return h.hexdigest()


class Checkpoint:
    """The contents of ``checkpoint.npz``: the state after ``rows`` committed events.

    ``sha256`` holds the SHA-256 of each committed chunk file, in order, and ``sides``
    those of each side table's parts: ``{name: [sha256 per chunk]}``.
    """

    def __init__(self, state, rows=0, n_chunks=0, counters=None, sha256=None, sides=None):
        self.state = state
        self.rows = rows
        self.n_chunks = n_chunks
        self.counters = counters or {name: kind(0) for name, kind in _COUNTERS.items()}
        self.sha256 = list(sha256 or [])
        self.sides = {name: list(shas) for name, shas in (sides or {}).items()}


def _sha_array(shas):
    return np.array(shas, dtype="U64").reshape(len(shas))


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
            chunk_sha256=_sha_array(ck.sha256),
            **{f"{name}_sha256": _sha_array(shas) for name, shas in ck.sides.items()},
            **{name: np.asarray(ck.counters[name]) for name in _COUNTERS},
        )


def load_checkpoint(path) -> Checkpoint:
    """Read ``checkpoint.npz``; a truncated, empty or incomplete file is a CatalogError."""
    try:
        with np.load(path, allow_pickle=False) as data:
            state = State(
                z=data["z"].copy(),
                offset=float(data["offset"]),
                w=float(data["w"]),
                n_events=int(data["n_events"]),
            )
            counters = {
                name: kind(data[name if name in data.files else _FORMER_NAMES.get(name, name)])
                for name, kind in _COUNTERS.items()
                if name in data.files or name not in _NEWER_COUNTERS
            }
            counters.update({name: 0 for name in _NEWER_COUNTERS if name not in counters})
            sha = [str(h) for h in data["chunk_sha256"]]
            sides = {
                name: [str(h) for h in data[f"{name}_sha256"]]
                for name in SIDE_TABLES
                if f"{name}_sha256" in data.files
            }
            ck = Checkpoint(state, int(data["rows"]), int(data["n_chunks"]), counters, sha, sides)
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as exc:
        reason = (
            "is empty"
            if os.path.isfile(path) and os.path.getsize(path) == 0
            else (f"is truncated or corrupt ({type(exc).__name__}: {exc})")
        )
        raise CatalogError(f"checkpoint {path} {reason}; {_restart_hint(path)}") from None
    uneven = any(len(shas) != ck.n_chunks for shas in ck.sides.values())
    if len(ck.sha256) != ck.n_chunks or ck.rows != ck.state.n_events or uneven:
        raise CatalogError(
            f"checkpoint {path} is inconsistent ({ck.n_chunks} chunks, {len(ck.sha256)} "
            f"checksums, {ck.rows} rows, state after {ck.state.n_events} events); "
            f"{_restart_hint(path)}"
        )
    return ck


def _check_sha(path, recorded):
    try:
        digest = sha256_file(path)
    except OSError as exc:
        raise CatalogError(
            f"committed chunk {path} is missing or unreadable ({exc}); the run cannot "
            f"resume exactly: {_restart_hint(path)}"
        ) from None
    if digest != recorded:
        raise CatalogError(
            f"committed chunk {path} does not match its checksum (sha256 {digest[:12]}..., "
            f"recorded {recorded[:12]}...): it was changed or damaged after it was "
            f"written; {_restart_hint(path)}"
        )


def _event_column(path):
    import pyarrow.parquet as pq

    try:
        return pq.read_table(path, columns=["event"]).column("event").to_numpy()
    except Exception as exc:
        raise CatalogError(f"committed chunk {path} is unreadable ({exc})") from None


def verify_chunks(wd, ck: Checkpoint, tables=None) -> int:
    """Check every committed chunk against its checksum, row count and event numbers, and
    each side table's parts against theirs and the chunk's events.

    ``tables`` are the side tables the run writes (None: those the checkpoint records).
    Returns the total number of rows; raises CatalogError naming the first bad file.
    """
    tables = tuple(ck.sides) if tables is None else tuple(tables)
    if set(tables) != set(ck.sides):
        path = os.path.join(wd, "checkpoint.npz")
        raise CatalogError(
            f"checkpoint {path} records the tables {sorted(ck.sides) or 'none'} besides the "
            f"events, but this run writes {sorted(tables) or 'none'}; {_restart_hint(path)}"
        )
    total = 0
    for i in range(ck.n_chunks):
        path = chunk_path(wd, i)
        _check_sha(path, ck.sha256[i])
        events = _event_column(path)
        if not np.array_equal(events, np.arange(total, total + events.size)):
            raise CatalogError(
                f"committed chunk {path} does not hold events {total}..{total + events.size - 1}"
                f" in order; {_restart_hint(path)}"
            )
        for name in tables:
            side = side_chunk_path(wd, name, i)
            _check_sha(side, ck.sides[name][i])
            rows = _event_column(side)
            inside = rows.size == 0 or (rows[0] >= total and rows[-1] < total + events.size)
            if not inside or np.any(np.diff(rows) < 0):
                raise CatalogError(
                    f"committed chunk {side} does not hold rows of events "
                    f"{total}..{total + events.size - 1} in order; {_restart_hint(side)}"
                )
        total += events.size
    if total != ck.rows:
        raise CatalogError(
            f"checkpoint in {wd} covers {ck.rows} events but its chunks hold {total}; "
            f"{_restart_hint(chunk_path(wd, 0))}"
        )
    return total


def checkpoint_status(out, verify=False) -> dict | None:
    """Progress of an interrupted run of ``out`` (None if there is no checkpoint).

    Returns ``{"events_done", "n_events", "chunks", "run"}`` where ``run`` is the
    content of ``run.json``.  A garbled ``run.json`` or ``checkpoint.npz`` is a
    CatalogError; ``verify=True`` also checks the chunks (:func:`verify_chunks`).
    """
    wd = checkpoint_dir(out)
    if not os.path.isdir(wd):
        return None
    run_json = os.path.join(wd, "run.json")
    run = read_run_json(run_json) if os.path.isfile(run_json) else {}
    done = chunks = 0
    ck = os.path.join(wd, "checkpoint.npz")
    if os.path.isfile(ck):
        loaded = load_checkpoint(ck)
        done, chunks = loaded.rows, loaded.n_chunks
        if verify:
            verify_chunks(wd, loaded)
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


def prepare_resume(wd, identity, run, tables=()) -> Checkpoint | None:
    """Load and verify a checkpoint; discard chunks and temp files it does not cover.

    ``run`` is the content of the folder's ``run.json`` (None where it has none) and
    ``tables`` the side tables the run writes.
    """
    run_json = os.path.join(wd, "run.json")
    ck = os.path.join(wd, "checkpoint.npz")
    if run is not None:
        diffs = mismatch(run, identity)
        if diffs:
            raise InvalidParameterError(
                f"cannot resume {wd}: it is another run ({'; '.join(diffs)}). Rerun with the "
                "original parameters, or pass force to discard the checkpoint"
            )
    elif os.path.isfile(ck) or any(_CHUNK_RE.fullmatch(n) for n in os.listdir(wd)):
        raise CatalogError(
            f"cannot resume {wd}: its run.json (the run's identity) is missing, so the "
            f"committed events cannot be checked against this call; {_restart_hint(run_json)}"
        )
    if not os.path.isfile(ck):
        _discard_uncommitted(wd, 0)
        return None
    loaded = load_checkpoint(ck)
    verify_chunks(wd, loaded, tables)
    _discard_uncommitted(wd, loaded.n_chunks)
    return loaded


def _discard_uncommitted(wd, n_chunks):
    """Remove chunks the checkpoint does not cover and temporary files of killed writers."""
    for name in os.listdir(wd):
        m = _CHUNK_RE.fullmatch(name)
        if (m and int(m.group(2)) >= n_chunks) or is_tmp_name(name):
            os.remove(os.path.join(wd, name))


def discard_tmp_outputs(out):
    """Remove temporary files of a merge into ``out`` that was killed."""
    folder, name = os.path.split(os.path.abspath(out))
    for entry in os.listdir(folder):
        if is_tmp_name(entry) and entry.startswith(f".{name}.tmp-"):
            with contextlib.suppress(OSError):
                os.remove(os.path.join(folder, entry))
