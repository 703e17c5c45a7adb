"""Checkpoint and resume: a killed run continues to the same catalog, bit for bit."""

import os
import random
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest
from crash_hooks import Crash, crash_after

import faultnet
from faultnet.io.lock import alive
from faultnet.io.parquet import CatalogError, OutputExistsError, read_catalog
from faultnet.runs import chunks as _run_loop
from faultnet.runs import long_run
from faultnet.runs.checkpoint import checkpoint_dir, checkpoint_status
from faultnet.runs.long_run import simulate_to_parquet

# enough events that the run is still writing at the last kill, which lands up to about
# 1.6 s after the first (40,000 events were written in less on a fast machine)
N_BLOCKS, N_EVENTS, SEED = 200, 100_000, 11


def _committed(out):
    try:
        st = checkpoint_status(out)
    except (OSError, ValueError, KeyError):  # caught mid-rename: try again later
        return -1
    if st is None:
        return N_EVENTS if os.path.exists(out) else 0
    return st["events_done"]


def test_sigkill_at_random_moments_then_resume(tmp_path):
    """Kill a real `faultnet simulate` with SIGKILL 4 times, resume, compare to one clean run."""
    out = str(tmp_path / "ring.parquet")
    cmd = [
        sys.executable,
        "-m",
        "faultnet",
        "simulate",
        f"ring:{N_BLOCKS}",
        "--events",
        str(N_EVENTS),
        "--seed",
        str(SEED),
        "--chunk",
        "500",
        "--checkpoint-every",
        "0",
        "--out",
        out,
        "--resume",
        "--no-progress",
    ]
    rng = random.Random(2024)
    kills = []  # events committed when each SIGKILL landed
    killed = []
    for attempt in range(4):
        before = _committed(out)
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        if attempt == 0:
            time.sleep(rng.uniform(0.05, 1.0))  # during start-up, before any checkpoint
        else:
            deadline = time.monotonic() + 60
            while _committed(out) <= before and proc.poll() is None:
                assert time.monotonic() < deadline, "the run made no progress"
                time.sleep(0.01)
            time.sleep(rng.uniform(0.0, 0.4))  # somewhere inside the writing loop
        if proc.poll() is not None:
            break  # finished before we could kill it
        proc.send_signal(signal.SIGKILL)
        # the next run starts at once, while the killed one is a zombie (not reaped yet, as
        # in a container without an init): its lock must not block the resume
        deadline = time.monotonic() + 10
        while alive(proc.pid):
            assert time.monotonic() < deadline, "SIGKILL did not end the run"
            time.sleep(0.005)
        killed.append(proc)
        kills.append(_committed(out))
    assert len(kills) >= 3, kills
    assert kills[-1] > 0 and kills == sorted(kills), kills  # progress survives every kill
    assert kills[-1] < N_EVENTS
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert [p.wait() for p in killed] == [-signal.SIGKILL] * len(killed)
    assert "resumed at event" in done.stdout or "already complete" in done.stdout
    assert not os.path.exists(checkpoint_dir(out))
    assert sorted(os.listdir(tmp_path)) == ["ring.parquet"]  # no temporary files left
    cat = read_catalog(out)
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(N_BLOCKS))
    ref = faultnet.simulate(model, N_EVENTS, rng=SEED, progress=False)
    pd.testing.assert_frame_equal(cat.events, ref.events, check_exact=True)
    assert cat.metadata["n_steps"] == ref.metadata["n_steps"]
    assert cat.metadata["runs"] >= 2
    print(f"events committed at the {len(kills)} kills: {kills}")


@pytest.fixture(scope="module")
def small():
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(60), alpha=1.5)
    ref = faultnet.simulate(model, 3000, rng=5, progress=False)
    return model, ref


def _run(model, out, **kw):
    kw = {"rng": 5, "chunk_events": 250, "checkpoint_interval": 0, "progress": False, **kw}
    return simulate_to_parquet(model, 3000, out, **kw)


@pytest.mark.parametrize(
    "where", ["after_commit", "after_part", "in_checkpoint", "in_merge", "in_cleanup"]
)
def test_crash_windows(tmp_path, monkeypatch, small, where):
    """A crash between any two steps of the commit protocol still resumes exactly.

    Between two commits the run's ``on_commit`` hook stops it.  A crash inside
    a step (after a chunk is written but before its checkpoint, while the
    checkpoint, the merged catalog or the cleanup is being written) needs the
    step itself to fail: there the run loop's I/O function is replaced.
    """
    model, ref = small
    out = tmp_path / "cat.parquet"
    calls = {"n": 0}
    kw = {}
    if where == "after_commit":
        kw["on_commit"] = crash_after(5)
    elif where in ("after_part", "in_checkpoint"):
        real = _run_loop.save_checkpoint

        def save(path, *args):
            calls["n"] += 1
            if calls["n"] == 5:
                if where == "in_checkpoint":  # leave a half-written temporary file
                    with open(
                        os.path.join(os.path.dirname(path), ".checkpoint.npz.tmp-1-x"), "wb"
                    ) as fh:
                        fh.write(b"PK")
                raise Crash
            return real(path, *args)

        monkeypatch.setattr(_run_loop, "save_checkpoint", save)
    elif where == "in_merge":

        def merge(parts, out_, md, overwrite=False, state=None):
            with open(os.path.join(tmp_path, ".cat.parquet.tmp-1-x"), "wb") as fh:
                fh.write(b"PAR1")
            raise Crash

        monkeypatch.setattr(long_run, "merge_parts", merge)
    else:

        def remove(wd):
            os.remove(os.path.join(wd, "run.json"))
            raise Crash

        monkeypatch.setattr(long_run, "remove_checkpoint_dir", remove)
    with pytest.raises(Crash):
        _run(model, out, **kw)
    monkeypatch.undo()
    if where == "after_part":  # a part beyond the checkpoint is on disk
        wd = checkpoint_dir(out)
        assert "chunk-000004.parquet" in os.listdir(wd)
        assert checkpoint_status(out)["chunks"] == 4
    if where == "after_commit":  # the checkpoint covers every chunk on disk
        wd = checkpoint_dir(out)
        assert "chunk-000005.parquet" not in os.listdir(wd)
        assert checkpoint_status(out)["chunks"] == 5
    with pytest.raises(OutputExistsError, match="resume"):
        _run(model, out)  # never silently restarted or overwritten
    rep = _run(model, out, resume=True)
    pd.testing.assert_frame_equal(read_catalog(out).events, ref.events, check_exact=True)
    assert sorted(os.listdir(tmp_path)) == ["cat.parquet"]
    if where == "in_cleanup":
        assert rep.status == "already complete"
    elif where == "in_merge":
        assert rep.resumed_from == 3000
    elif where == "after_commit":
        assert rep.resumed_from == 5 * 250
    else:
        assert 0 < rep.resumed_from < 3000


def test_resume_checks_parameters(tmp_path, small):
    model, ref = small
    out = tmp_path / "cat.parquet"
    with pytest.raises(Crash):
        _run(model, out, on_commit=crash_after(3))
    with pytest.raises(faultnet.InvalidParameterError, match="alpha|graph_hash"):
        _run(model.with_params(alpha=2.0), out, resume=True)
    with pytest.raises(faultnet.InvalidParameterError, match="seed_entropy"):
        _run(model, out, resume=True, rng=6)
    # a committed part that went missing cannot be resumed exactly
    wd = checkpoint_dir(out)
    os.rename(os.path.join(wd, "chunk-000001.parquet"), os.path.join(wd, "moved"))
    with pytest.raises(CatalogError, match="force"):
        _run(model, out, resume=True)
    with pytest.raises(OutputExistsError, match="did not write"):
        _run(model, out, force=True)  # foreign file in the checkpoint folder
    os.remove(os.path.join(wd, "moved"))
    _run(model, out, force=True)
    pd.testing.assert_frame_equal(read_catalog(out).events, ref.events, check_exact=True)


def test_checkpoint_with_the_former_counter_name_loads(tmp_path):
    """A checkpoint that counts its runs under ``sessions`` (faultnet 0.2) still loads."""
    import numpy as np

    from faultnet.model.state import State
    from faultnet.runs.checkpoint import Checkpoint, load_checkpoint, save_checkpoint

    ck = Checkpoint(State(z=np.zeros(3), offset=0.0, w=0.0, n_events=5), 5, 1, None, ["0" * 64])
    ck.counters["runs"] = 3
    path = tmp_path / "checkpoint.npz"
    save_checkpoint(path, ck)
    with np.load(path) as data:
        fields = {k: data[k] for k in data.files}
    fields["sessions"] = fields.pop("runs")
    np.savez(path, **fields)
    assert load_checkpoint(path).counters["runs"] == 3


# ------------------------------------------------------------ extending a finished catalog


def test_a_finished_catalog_is_extended_as_one_longer_run(tmp_path, small, capsys):
    model, ref = small
    out = tmp_path / "x.parquet"
    simulate_to_parquet(
        model, 1000, out, rng=5, chunk_events=250, checkpoint_interval=0, progress=False
    )
    short = read_catalog(out)
    # in memory: x0 is the catalog (or its path)
    more = faultnet.simulate(model, 2000, x0=out, progress=False)
    joined = pd.concat([short.events, more.events], ignore_index=True)
    pd.testing.assert_frame_equal(joined, ref.events, check_exact=True)
    assert more.events["event"].iloc[0] == 1000
    # on disk: the file itself grows to 3000 events, killed once on the way
    with pytest.raises(Crash):
        _run(model, out, extend=True, on_commit=crash_after(2))
    assert len(read_catalog(out).events) == 1000  # the shorter catalog is kept meanwhile
    report = _run(model, out, extend=True)
    assert report.status == "resumed" and report.resumed_from > 1000
    pd.testing.assert_frame_equal(read_catalog(out).events, ref.events, check_exact=True)
    assert sorted(os.listdir(tmp_path)) == ["x.parquet"]
    assert read_catalog(out).state.n_events == 3000
    with pytest.raises(faultnet.InvalidParameterError, match="already holds 3,000 events"):
        _run(model, out, extend=True)


def test_extending_refuses_another_model_and_a_catalog_without_state(tmp_path, small):
    import pyarrow.parquet as pq

    model, _ = small
    out = tmp_path / "x.parquet"
    _run(model, out)
    with pytest.raises(faultnet.InvalidParameterError, match="another graph or other param"):
        faultnet.simulate(model.with_params(alpha=2.0), 10, x0=out, progress=False)
    table = pq.read_table(out)
    md = {k: v for k, v in table.schema.metadata.items() if k != b"faultnet_state"}
    pq.write_table(table.replace_schema_metadata(md), out)
    with pytest.raises(CatalogError, match="holds no final state"):
        faultnet.simulate(model, 10, x0=out, progress=False)


def test_the_cli_continues_a_finished_run(tmp_path):
    from faultnet.__main__ import main

    args = ["simulate", "ring:60", "--alpha", "1.5", "--seed", "5", "--no-progress"]
    ref, out = tmp_path / "ref.parquet", tmp_path / "x.parquet"
    assert main([*args, "-n", "3000", "--out", str(ref)]) == 0
    assert main([*args, "-n", "1200", "--out", str(out)]) == 0
    assert main(["simulate", "--continue", "--out", str(out), "-n", "3000", "--no-progress"]) == 0
    pd.testing.assert_frame_equal(
        read_catalog(out).events, read_catalog(ref).events, check_exact=True
    )


def test_only_a_whole_run_is_extended_in_place(tmp_path, small):
    model, _ = small
    first = faultnet.simulate(model, 300, rng=5, progress=False)
    later = faultnet.simulate(model, 300, x0=first, progress=False)  # events 300..599
    out = tmp_path / "later.parquet"
    faultnet.write_catalog(later, out)
    with pytest.raises(faultnet.InvalidParameterError, match="starts at event 300"):
        _run(model, out, extend=True)
    more = faultnet.simulate(model, 100, x0=out, progress=False)  # in memory it continues
    assert more.events["event"].iloc[0] == 600
