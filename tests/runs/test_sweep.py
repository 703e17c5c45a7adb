"""Sweeps (faultnet.runs.sweep): seeds, skipping, recomputing and resuming points, executors."""

import os
import textwrap

import numpy as np
import pandas as pd
import pytest

import faultnet
from faultnet.exceptions import OutputExistsError, SweepError
from faultnet.io.parquet import read_catalog, read_metadata
from faultnet.runs.sweep.driver import SerialExecutor, summarize, sweep

SMALL = {
    "graph": ["ring:40", "chain:30"],
    "alpha": [1.0, 2.5],
    "events": 600,
    "seed": 3,
    "transient": 100,
}
TOML = """\
[sweep]
graph = ["ring:40", "chain:30"]
alpha = [1.0, 2.5]
events = 600
seed = 3
transient = 100
"""


def _write(path, text):
    path.write_text(textwrap.dedent(text))
    return path


def _point_files(out):
    return sorted(n for n in os.listdir(out) if n.startswith("part-"))


def _frames(out):
    return {n: read_catalog(os.path.join(out, n)).events for n in _point_files(out)}


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The small sweep run in this process: the result every executor must reproduce."""
    out = tmp_path_factory.mktemp("ref")
    table = sweep(SMALL, out=out, workers=1, progress=False)
    return out, table, _frames(out)


def test_grid_and_seeds(reference):
    out, table, frames = reference
    assert list(table["point"]) == [0, 1, 2, 3]
    assert list(table["graph"]) == ["ring:40", "ring:40", "chain:30", "chain:30"]
    assert list(table["alpha"]) == [1.0, 2.5, 1.0, 2.5]
    assert (table["status"] == "done").all() and (table["events"] == 600).all()
    assert table["b_mle"].notna().all() and table["b_lsq_err"].notna().all()
    assert (table["wall_time_s"] > 0).all()
    # each point is the child SeedSequence(3, spawn_key=(i,)): reproducible by hand
    md = read_metadata(os.path.join(out, "part-00003.parquet"))
    assert md["seed_entropy"] == 3 and md["seed_spawn_key"] == (3,)
    model = faultnet.CarlsonLanger(faultnet.graphs.chain(30), alpha=2.5)
    ref = faultnet.simulate(
        model, 600, rng=np.random.SeedSequence(3, spawn_key=(3,)), progress=False
    )
    pd.testing.assert_frame_equal(frames["part-00003.parquet"], ref.events, check_exact=True)
    # the same table comes back from the folder
    again = summarize(out)
    pd.testing.assert_frame_equal(
        again.drop(columns=["wall_time_s", "events_per_s"]),
        table.drop(columns=["wall_time_s", "events_per_s"]),
    )


def test_rerun_skips_finished_and_recomputes_truncated(tmp_path, reference):
    _, _, frames = reference
    path = _write(tmp_path / "s.toml", TOML)
    out = tmp_path / "s"
    sweep(path, workers=1, progress=False)
    stamps = {n: os.stat(out / n).st_mtime_ns for n in _point_files(out)}
    # truncate one point's catalog, delete another
    point1 = out / "part-00001.parquet"
    data = point1.read_bytes()
    point1.write_bytes(data[: len(data) // 3])
    os.remove(out / "part-00002.parquet")
    messages = []
    table = sweep(path, workers=1, progress=False, log=messages.append)
    assert (table["status"] == "done").all()
    assert any("recomputing part-00001.parquet (corrupt)" in m for m in messages), messages
    assert any("running 2 points" in m for m in messages), messages
    for name in ("part-00000.parquet", "part-00003.parquet"):
        assert os.stat(out / name).st_mtime_ns == stamps[name]  # untouched
    for name, frame in _frames(out).items():
        pd.testing.assert_frame_equal(frame, frames[name], check_exact=True)
    # an interrupted point shows up in the summary and is resumed
    assert summarize(out)["status"].tolist() == ["done"] * 4


def test_refuses_foreign_files_and_changed_settings(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    cfg = dict(SMALL, graph="ring:40", alpha=1.0, events=200)
    with pytest.raises(OutputExistsError, match=r"notes\.txt.*force"):
        sweep(cfg, out=out, workers=1, progress=False)
    assert os.listdir(out) == ["notes.txt"]  # nothing written
    sweep(cfg, out=out, workers=1, progress=False, force=True)
    assert (out / "notes.txt").read_text() == "mine"
    (out / "stray.csv").write_text("x")
    with pytest.raises(OutputExistsError, match="stray.csv"):
        sweep(cfg, out=out, workers=1, progress=False)
    os.remove(out / "stray.csv")
    os.remove(out / "notes.txt")
    before = read_catalog(out / "part-00000.parquet").events
    with pytest.raises(OutputExistsError, match=r"alpha: \[1\.0\] -> \[1\.0, 2\.0\]"):
        sweep(dict(cfg, alpha=[1.0, 2.0]), out=out, workers=1, progress=False)
    # forced: point 0 is the same point and is kept, point 1 is new
    table = sweep(dict(cfg, alpha=[1.0, 2.0]), out=out, workers=1, progress=False, force=True)
    assert len(table) == 2
    pd.testing.assert_frame_equal(read_catalog(out / "part-00000.parquet").events, before)
    # analysis settings may change freely
    table = sweep(dict(cfg, alpha=[1.0, 2.0], transient=50), out=out, workers=1, progress=False)
    assert (table["transient"] == 50).all()


def test_failed_points_are_reported_and_others_kept(tmp_path):
    cfg = {"graph": "ring:30", "alpha": 1.0, "events": 100, "seed": 1, "dt": [0.01, 0.5]}
    with pytest.raises(SweepError, match=r"1 of 2 points failed.*point 1.*dt=0\.5") as info:
        sweep(cfg, out=tmp_path / "f", workers=1, progress=False)
    table = info.value.summary
    assert table["status"].tolist()[0] == "done"
    assert table["status"].tolist()[1].startswith("failed: InvalidParameterError")
    assert _point_files(tmp_path / "f") == ["part-00000.parquet"]


def test_local_processes_and_dask_cluster_agree(tmp_path, reference):
    distributed = pytest.importorskip("distributed")
    _, table, frames = reference
    local = sweep(SMALL, out=tmp_path / "local", workers=2, progress=False)
    with distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
    ) as cluster:
        with distributed.Client(cluster) as client:
            via_executor = sweep(
                SMALL,
                out=tmp_path / "dask",
                progress=False,
                executor=client.get_executor(pure=False),
            )
            ran_on = set(client.run(os.getpid).values())
        from faultnet.cli.commands import main

        assert (
            main(
                [
                    "sweep",
                    str(_write(tmp_path / "s.toml", TOML)),
                    "--out",
                    str(tmp_path / "sched"),
                    "--scheduler",
                    cluster.scheduler_address,
                    "--quiet",
                ]
            )
            == 0
        )
    assert len(ran_on) == 2
    for out, result in (
        (tmp_path / "local", local),
        (tmp_path / "dask", via_executor),
        (tmp_path / "sched", summarize(tmp_path / "sched")),
    ):
        got = _frames(out)
        assert got.keys() == frames.keys()
        for name, frame in frames.items():
            pd.testing.assert_frame_equal(got[name], frame, check_exact=True)
        cols = ["point", "graph", "alpha", "events", "b_mle", "b_mle_err", "b_lsq", "b_lsq_err"]
        pd.testing.assert_frame_equal(result[cols], table[cols], check_exact=True)


class Crash(BaseException):
    """A kill at a chosen instant."""


class KillPoint(SerialExecutor):
    """Runs the points in this process; point ``index`` is killed after ``chunks`` commits."""

    def __init__(self, index, chunks):
        self.index, self.chunks = index, chunks

    def _kill(self, n_chunks):
        if n_chunks == self.chunks:
            raise Crash

    def submit(self, fn, /, *args, **kwargs):
        if args[0]["index"] == self.index:  # run_point(point, path, ...)
            kwargs["on_commit"] = self._kill
        return super().submit(fn, *args, **kwargs)


def test_interrupted_point_is_resumed(tmp_path):
    cfg = {
        "graph": "ring:30",
        "alpha": [1.0, 2.0],
        "events": 1000,
        "seed": 5,
        "chunk": 200,
        "checkpoint_interval": 0,
    }
    with pytest.raises(Crash):  # point 0 finishes (5 chunks), point 1 dies after 2 chunks
        sweep(cfg, out=tmp_path / "x", executor=KillPoint(1, 2), progress=False)
    assert summarize(tmp_path / "x")["status"].tolist() == ["done", "partial 400/1000"]
    messages = []
    sweep(cfg, out=tmp_path / "x", workers=1, progress=False, log=messages.append)
    assert any("point 1: resuming" in m for m in messages), messages
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(30), alpha=2.0)
    ref = faultnet.simulate(
        model, 1000, rng=np.random.SeedSequence(5, spawn_key=(1,)), progress=False
    )
    got = read_catalog(tmp_path / "x" / "part-00001.parquet")
    pd.testing.assert_frame_equal(got.events, ref.events, check_exact=True)
    assert got.metadata["runs"] == 2
