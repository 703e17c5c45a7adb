"""Nothing lost, nothing silently wrong: identity, checksums, event numbering, clear errors."""

import builtins
import errno
import json
import os
import subprocess
import sys

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from faultnet import _run_loop
from faultnet.__main__ import main
from faultnet.checkpoint import checkpoint_dir, chunk_path
from faultnet.exceptions import CatalogError, OutputLockedError
from faultnet.io import read_catalog
from faultnet.lock import _me, _start_ticks, is_stale
from faultnet.spec_run import run_from_spec
from faultnet.sweep_summary import summarize

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


def _one_line(capsys):
    err = capsys.readouterr().err.strip()
    assert "Traceback" not in err
    assert len(err.splitlines()) == 1, err
    return err


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("ref") / "ref.parquet"
    run_from_spec(out=out, alpha=1.5, progress=False, **SPEC)
    return read_catalog(out).events


# ---------------------------------------------------------------- identity (defect 2)


def test_resume_without_run_json_is_refused(tmp_path, capsys, reference):
    out = tmp_path / "x.parquet"
    wd = _interrupted(out)
    os.remove(os.path.join(wd, "run.json"))
    with pytest.raises(CatalogError, match=r"run\.json.*missing.*--force"):
        run_from_spec(out=out, resume=True, alpha=3.0, progress=False, **SPEC)
    rc = main(["simulate", "--resume", "--out", str(out), "ring:30", "-n", str(EVENTS),
               "--alpha", "3"])  # fmt: skip
    assert rc == 1 and "run.json" in _one_line(capsys)
    # nothing was mixed in: --force restarts cleanly
    run_from_spec(out=out, resume=True, force=True, alpha=1.5, progress=False, **SPEC)
    pd.testing.assert_frame_equal(read_catalog(out).events, reference)


# ---------------------------------------------------------------- checksums (defect 3)


def _damage(path, n=64):
    size = os.path.getsize(path)
    with open(path, "r+b") as fh:
        fh.seek(size // 3)
        fh.write(bytes(range(n)))


def test_damaged_chunk_is_refused_on_resume_and_by_info(tmp_path, capsys):
    out = tmp_path / "x.parquet"
    wd = _interrupted(out)
    bad = chunk_path(wd, 1)
    _damage(bad)
    with pytest.raises(CatalogError, match=r"chunk-000001\.parquet does not match its checksum"):
        run_from_spec(out=out, resume=True, progress=False, **SPEC)
    assert main(["simulate", "--resume", "--out", str(out)]) == 1
    msg = _one_line(capsys)
    assert "chunk-000001.parquet" in msg and "--force" in msg
    assert main(["info", str(out)]) == 1
    assert "checksum" in _one_line(capsys)


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
def test_complete_but_wrong_catalog_is_never_accepted(tmp_path, reference, capsys, damage):
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
    assert "x.parquet" in _one_line(capsys)
    table = summarize(tmp_path)  # a folder of catalogs
    assert table["status"].iloc[0].startswith("corrupt")


# ---------------------------------------------------------------- one-line errors (defect 4)


@pytest.mark.parametrize("damage", ["truncated npz", "empty npz", "garbled run.json", "[1,2]"])
@pytest.mark.parametrize("command", ["simulate", "info"])
def test_broken_checkpoint_files_give_one_line(tmp_path, capsys, damage, command):
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
    msg = _one_line(capsys)
    name = "checkpoint.npz" if "npz" in damage else "run.json"
    assert name in msg and "--force" in msg
    if command == "simulate":  # --force recovers
        capsys.readouterr()
        assert main([*argv, "ring:30", "-n", str(EVENTS), "--seed", "3", "--force"]) == 0


def test_ctrl_c_while_loading_the_command_line(monkeypatch, capsys):
    real_import = builtins.__import__

    def interrupted(name, *args, **kwargs):
        if name == "faultnet.cli":
            raise KeyboardInterrupt
        return real_import(name, *args, **kwargs)

    monkeypatch.delitem(sys.modules, "faultnet.cli")
    monkeypatch.setattr(builtins, "__import__", interrupted)
    assert main(["info", "x.parquet"]) == 130
    assert "interrupted" in _one_line(capsys)


# ---------------------------------------------------------------- full disk (defect 10)


@pytest.mark.parametrize("where", ["chunk", "merge"])
def test_full_disk_names_the_file_and_the_way_on(tmp_path, monkeypatch, capsys, where, reference):
    out = tmp_path / "x.parquet"
    # the disk fills inside a write: the run loop's writer itself must fail
    real_part, real_merge, calls = _run_loop.write_part, _run_loop.merge_parts, {"n": 0}

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    def part(*args, **kwargs):
        calls["n"] += 1
        return full() if calls["n"] == 4 else real_part(*args, **kwargs)

    if where == "chunk":
        monkeypatch.setattr(_run_loop, "write_part", part)
    else:
        monkeypatch.setattr(_run_loop, "merge_parts", full)
    argv = ["simulate", "ring:30", "-n", str(EVENTS), "--alpha", "1.5", "--seed", "3",
            "--chunk", "250", "--checkpoint-every", "0", "--out", str(out)]  # fmt: skip
    assert main(argv) == 1
    msg = _one_line(capsys)
    target = "chunk-000003.parquet" if where == "chunk" else "x.parquet"
    assert target in msg and "No space left on device" in msg
    assert "is intact" in msg and "--resume" in msg
    monkeypatch.setattr(_run_loop, "write_part", real_part)
    monkeypatch.setattr(_run_loop, "merge_parts", real_merge)
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


def test_lock_released_on_interrupt_and_stale_lock_taken_over(tmp_path, reference):
    out = tmp_path / "x.parquet"
    _interrupted(out)
    lock = str(out) + ".lock"
    assert not os.path.exists(lock)
    # a lock left by a killed process: same host, pid gone
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    holder = _me() | {"pid": dead.pid, "start_ticks": 1}
    with open(lock, "w") as fh:
        json.dump(holder, fh)
    run_from_spec(out=out, resume=True, progress=False, **SPEC)
    pd.testing.assert_frame_equal(read_catalog(out).events, reference)
    assert not os.path.exists(lock)


def test_live_lock_of_another_process_is_respected(tmp_path):
    out = tmp_path / "x.parquet"
    lock = str(out) + ".lock"
    holder = _me() | {"pid": os.getppid(), "command": "faultnet simulate other"}
    holder["start_ticks"] = _start_ticks(os.getppid())
    with open(lock, "w") as fh:
        json.dump(holder, fh)
    with pytest.raises(OutputLockedError, match=rf"pid {os.getppid()} .*faultnet simulate other"):
        run_from_spec(out=out, progress=False, **SPEC)
    # the same pid with another start time is a reused pid: stale
    holder["start_ticks"] = (holder["start_ticks"] or 0) + 12345
    with open(lock, "w") as fh:
        json.dump(holder, fh)
    assert is_stale(holder)
    run_from_spec(out=out, progress=False, **SPEC)
    assert not os.path.exists(lock)
