"""Nothing lost, nothing silently wrong: identity, checksums, event numbering, clear errors."""

import builtins
import errno
import json
import os
import subprocess
import sys
import time

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from faultnet.__main__ import main
from faultnet.exceptions import CatalogError, OutputLockedError
from faultnet.io.lock import _me, alive
from faultnet.io.parquet import read_catalog
from faultnet.runs import chunks as _run_loop
from faultnet.runs import long_run
from faultnet.runs.checkpoint import checkpoint_dir, chunk_path
from faultnet.runs.spec_run import run_from_spec
from faultnet.runs.sweep.summary import summarize

EVENTS = 2000
SPEC = dict(graph="ring:30", n_events=EVENTS, seed=3, chunk_events=250, checkpoint_interval=0)


class Crash(KeyboardInterrupt):
    pass


def _interrupted(out, after=3, alpha=1.5):
    """A run of SPEC into ``out`` killed after ``after`` committed chunks."""

    def on_commit(n_chunks):
        if n_chunks == after:
            raise Crash

    with pytest.raises(Crash):
        run_from_spec(out=out, alpha=alpha, progress=False, on_commit=on_commit, **SPEC)
    return checkpoint_dir(out)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("ref") / "ref.parquet"
    run_from_spec(out=out, alpha=1.5, progress=False, **SPEC)
    return read_catalog(out).events


# ---------------------------------------------------------------- identity (defect 2)


def test_resume_without_run_json_is_refused(tmp_path, capsys, reference, one_line):
    out = tmp_path / "x.parquet"
    wd = _interrupted(out)
    os.remove(os.path.join(wd, "run.json"))
    with pytest.raises(CatalogError, match=r"run\.json.*missing.*--force"):
        run_from_spec(out=out, resume=True, alpha=3.0, progress=False, **SPEC)
    rc = main(["simulate", "--resume", "--out", str(out), "ring:30", "-n", str(EVENTS),
               "--alpha", "3"])  # fmt: skip
    assert rc == 1 and "run.json" in one_line()
    # nothing was mixed in: --force restarts cleanly
    run_from_spec(out=out, resume=True, force=True, alpha=1.5, progress=False, **SPEC)
    pd.testing.assert_frame_equal(read_catalog(out).events, reference)


# ---------------------------------------------------------------- checksums (defect 3)


def _damage(path, n=64):
    size = os.path.getsize(path)
    with open(path, "r+b") as fh:
        fh.seek(size // 3)
        fh.write(bytes(range(n)))


def test_damaged_chunk_is_refused_on_resume_and_by_info(tmp_path, capsys, one_line):
    out = tmp_path / "x.parquet"
    wd = _interrupted(out)
    bad = chunk_path(wd, 1)
    _damage(bad)
    with pytest.raises(CatalogError, match=r"chunk-000001\.parquet does not match its checksum"):
        run_from_spec(out=out, resume=True, progress=False, **SPEC)
    assert main(["simulate", "--resume", "--out", str(out)]) == 1
    msg = one_line()
    assert "chunk-000001.parquet" in msg and "--force" in msg
    assert main(["info", str(out)]) == 1
    assert "checksum" in one_line()


def test_chunk_damaged_during_the_run_is_refused_at_the_merge(tmp_path):
    out = tmp_path / "x.parquet"

    def on_commit(n_chunks):
        if n_chunks == 2:
            _damage(chunk_path(checkpoint_dir(out), 0))

    with pytest.raises(CatalogError, match=r"chunk-000000\.parquet does not match its checksum"):
        run_from_spec(out=out, progress=False, on_commit=on_commit, **SPEC)
    assert not out.exists()


# ------------------------------------------------- row count and event numbering (defect 1)


def _rewrite(path, events):
    """Replace a catalog's rows, keeping its metadata (what two writers at once leave)."""
    schema_md = pq.read_schema(path).metadata
    table = pa.Table.from_pandas(events, preserve_index=False)
    pq.write_table(table.replace_schema_metadata(schema_md), path)


@pytest.mark.parametrize("damage", ["short", "duplicated"])
def test_complete_but_wrong_catalog_is_never_accepted(
    tmp_path, reference, capsys, damage, one_line
):
    out = tmp_path / "x.parquet"
    run_from_spec(out=out, alpha=1.5, progress=False, **SPEC)
    ev = read_catalog(out).events
    if damage == "short":
        ev = ev.drop(index=range(500, 700)).reset_index(drop=True)
    else:
        ev = pd.concat([ev.iloc[:1000], ev.iloc[900:1900]], ignore_index=True)
    _rewrite(out, ev)
    match = r"holds \d+ events but its metadata says 2000|event number"
    with pytest.raises(CatalogError, match=match):  # resume of a "complete" output
        run_from_spec(out=out, resume=True, progress=False, **SPEC)
    assert main(["info", str(out)]) == 1
    assert "x.parquet" in one_line()
    table = summarize(tmp_path)  # a folder of catalogs
    assert table["status"].iloc[0].startswith("corrupt")


# ---------------------------------------------------------------- one-line errors (defect 4)


@pytest.mark.parametrize("damage", ["truncated npz", "empty npz", "garbled run.json", "[1,2]"])
@pytest.mark.parametrize("command", ["simulate", "info"])
def test_broken_checkpoint_files_give_one_line(tmp_path, capsys, damage, command, one_line):
    out = tmp_path / "x.parquet"
    wd = _interrupted(out)
    npz, run_json = os.path.join(wd, "checkpoint.npz"), os.path.join(wd, "run.json")
    if damage == "truncated npz":
        data = open(npz, "rb").read()
        open(npz, "wb").write(data[: len(data) // 2])
    elif damage == "empty npz":
        open(npz, "wb").close()
    elif damage == "garbled run.json":
        open(run_json, "w").write('{"n_events": 20')
    else:
        open(run_json, "w").write("[1,2]")
    argv = (
        ["simulate", "--resume", "--out", str(out)] if command == "simulate" else ["info", str(out)]
    )
    assert main(argv) == 1
    msg = one_line()
    name = "checkpoint.npz" if "npz" in damage else "run.json"
    assert name in msg and "--force" in msg
    if command == "simulate":  # --force recovers
        capsys.readouterr()
        assert main([*argv, "ring:30", "-n", str(EVENTS), "--seed", "3", "--force"]) == 0


def test_ctrl_c_while_loading_the_command_line(monkeypatch, capsys, one_line):
    real_import = builtins.__import__

    def interrupted(name, *args, **kwargs):
        if name == "faultnet.cli.commands":
            raise KeyboardInterrupt
        return real_import(name, *args, **kwargs)

    monkeypatch.delitem(sys.modules, "faultnet.cli.commands")
    monkeypatch.setattr(builtins, "__import__", interrupted)
    assert main(["info", "x.parquet"]) == 130
    assert "interrupted" in one_line()


# ---------------------------------------------------------------- full disk (defect 10)


@pytest.mark.parametrize("where", ["chunk", "merge"])
def test_full_disk_names_the_file_and_the_way_on(
    tmp_path, monkeypatch, capsys, where, reference, one_line
):
    out = tmp_path / "x.parquet"
    # the disk fills inside a write: the run loop's writer itself must fail
    real_part, real_merge, calls = _run_loop.write_part, long_run.merge_parts, {"n": 0}

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    def part(*args, **kwargs):
        calls["n"] += 1
        return full() if calls["n"] == 4 else real_part(*args, **kwargs)

    if where == "chunk":
        monkeypatch.setattr(_run_loop, "write_part", part)
    else:
        monkeypatch.setattr(long_run, "merge_parts", full)
    argv = ["simulate", "ring:30", "-n", str(EVENTS), "--alpha", "1.5", "--seed", "3",
            "--chunk", "250", "--checkpoint-every", "0", "--out", str(out)]  # fmt: skip
    assert main(argv) == 1
    msg = one_line()
    target = "chunk-000003.parquet" if where == "chunk" else "x.parquet"
    assert target in msg and "No space left on device" in msg
    assert "is intact" in msg and "--resume" in msg
    monkeypatch.setattr(_run_loop, "write_part", real_part)
    monkeypatch.setattr(long_run, "merge_parts", real_merge)
    assert main(["simulate", "--resume", "--out", str(out)]) == 0
    pd.testing.assert_frame_equal(read_catalog(out).events, reference)


# ---------------------------------------------------------------- lock (defect 1)


def test_second_writer_is_refused_naming_the_holder(tmp_path, capsys):
    out = tmp_path / "x.parquet"
    seen = {}

    def on_commit(n_chunks):
        if "rc" not in seen:  # while the first run holds the lock, a second one starts
            seen["rc"] = main(["simulate", "--resume", "--out", str(out)])
            seen["err"] = capsys.readouterr().err

    run_from_spec(out=out, alpha=1.5, progress=False, on_commit=on_commit, **SPEC)
    assert seen["rc"] == 1
    assert f"pid {os.getpid()}" in seen["err"] and "is being written by" in seen["err"]
    assert not os.path.exists(str(out) + ".lock")  # released


HOLD_LOCK = """
import sys, time
from faultnet.io.lock import output_lock
with output_lock(sys.argv[1]):
    print("locked", flush=True)
    time.sleep(600)
"""


@pytest.mark.parametrize(
    "leftover",
    [b"", b'{"pid": 12', b"[1, 2]", b'{"pid": 999999999999, "host": "x"}', None],
    ids=["empty", "garbled", "list", "huge-pid", "dead-pid"],
)
def test_lock_released_on_interrupt_and_leftover_lock_file_taken(tmp_path, reference, leftover):
    out = tmp_path / "x.parquet"
    _interrupted(out)
    lock = str(out) + ".lock"
    assert not os.path.exists(lock)
    if leftover is None:  # the record of a process that is gone
        dead = subprocess.Popen([sys.executable, "-c", "pass"])
        dead.wait()
        leftover = json.dumps(_me() | {"pid": dead.pid}).encode()
    with open(lock, "wb") as fh:  # what a killed start or a full disk leaves: nobody holds it
        fh.write(leftover)
    run_from_spec(out=out, resume=True, progress=False, **SPEC)
    pd.testing.assert_frame_equal(read_catalog(out).events, reference)
    assert not os.path.exists(lock)


def test_live_lock_is_respected_and_a_sigkilled_holder_blocks_nothing(tmp_path, reference):
    out = tmp_path / "x.parquet"
    lock = str(out) + ".lock"
    holder = subprocess.Popen([sys.executable, "-c", HOLD_LOCK, lock], stdout=subprocess.PIPE)
    try:
        assert holder.stdout.readline() == b"locked\n"
        with pytest.raises(OutputLockedError, match=rf"being written by pid {holder.pid} "):
            run_from_spec(out=out, alpha=1.5, progress=False, **SPEC)
        holder.kill()
        # not reaped yet: a zombie, as a killed process is in a container without an init;
        # the operating system has released its lock all the same
        deadline = time.monotonic() + 10
        while alive(holder.pid) and time.monotonic() < deadline:
            time.sleep(0.01)
        assert os.path.exists(f"/proc/{holder.pid}") and not alive(holder.pid)
        run_from_spec(out=out, alpha=1.5, progress=False, **SPEC)
    finally:
        holder.kill()
        holder.wait()
    pd.testing.assert_frame_equal(read_catalog(out).events, reference)
    assert not os.path.exists(lock)


def test_a_full_disk_at_the_lock_leaves_nothing_that_blocks(
    tmp_path, monkeypatch, capsys, one_line
):
    out = tmp_path / "x.parquet"

    def full(*args):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    with monkeypatch.context() as m:
        m.setattr(os, "pwrite", full)
        rc = main(["simulate", "ring:30", "-n", "200", "--out", str(out)])
        assert rc == 1
        err = one_line()
        assert f"cannot write the lock file {out}.lock" in err and "No space left" in err
    run_from_spec(out=out, progress=False, **SPEC)
    assert len(read_catalog(out).events) == EVENTS


def test_a_lock_file_that_cannot_be_opened_is_named(tmp_path, monkeypatch):
    out = tmp_path / "x.parquet"
    lock = str(out) + ".lock"
    real_open = os.open

    def refused(path, *args, **kwargs):
        if os.fspath(path) == lock:  # another user's file in a sticky folder
            raise PermissionError(errno.EPERM, os.strerror(errno.EPERM), path)
        return real_open(path, *args, **kwargs)

    monkeypatch.setattr(os, "open", refused)
    with pytest.raises(OutputLockedError, match=rf"cannot open the lock file {lock} \(Operation"):
        run_from_spec(out=out, progress=False, **SPEC)
