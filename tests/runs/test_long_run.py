"""Long runs to Parquet (faultnet.runs.long_run): chunked runs are bit-identical and memory-bounded.

Interrupted runs and their resume are in test_resume.py; the command line's
runs in test_cli.py.
"""

import os
import tracemalloc

import pandas as pd
import pyarrow.parquet as pq
import pytest

import faultnet
from faultnet.exceptions import InvalidParameterError, OutputExistsError
from faultnet.io import parquet as fio
from faultnet.runs.long_run import simulate_to_parquet


def test_chunked_run_is_bit_identical(tmp_path):
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(40), alpha=2.0)
    out = tmp_path / "run.parquet"
    rep = simulate_to_parquet(
        model,
        2500,
        out,
        rng=9,
        chunk_events=333,
        checkpoint_interval=0,
        progress=False,
        transient=100,
    )
    ref = faultnet.simulate(model, 2500, rng=9, progress=False)
    cat = fio.read_catalog(out)
    pd.testing.assert_frame_equal(cat.events, ref.events, check_exact=True)
    md = cat.metadata
    assert md == rep.metadata
    for key in (
        "graph",
        "k",
        "sigma",
        "alpha",
        "dt",
        "seed_entropy",
        "seed_spawn_key",
        "n_events",
        "first_event",
        "initial_state",
        "n_steps",
        "block_steps",
    ):
        assert md[key] == ref.metadata[key], key
    assert md["transient"] == 100 and md["runs"] == 1
    assert pq.ParquetFile(out).metadata.num_row_groups >= 8  # written in parts
    assert sorted(os.listdir(tmp_path)) == ["run.parquet"]  # checkpoint folder removed
    # iter_catalog streams the same rows
    streamed = pd.concat(fio.iter_catalog(out, batch_size=700), ignore_index=True)
    pd.testing.assert_frame_equal(streamed, ref.events, check_exact=True)


def _peak_bytes(model, n, out, chunk):
    tracemalloc.start()
    tracemalloc.reset_peak()
    simulate_to_parquet(
        model, n, out, rng=4, chunk_events=chunk, checkpoint_interval=3600, progress=False
    )
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak


def _row_group_sizes(path):
    meta = pq.ParquetFile(path).metadata
    return [meta.row_group(i).num_rows for i in range(meta.num_row_groups)]


def test_memory_stays_within_one_chunk(tmp_path):
    """Peak memory of a long run does not grow with its length (O(N + chunk))."""
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(50))
    # warm up: compile the kernel, import the writers
    simulate_to_parquet(
        model, 1500, tmp_path / "warm.parquet", rng=1, chunk_events=1000, progress=False
    )
    chunk = 1000
    short = _peak_bytes(model, 8_000, tmp_path / "short.parquet", chunk)
    long = _peak_bytes(model, 100_000, tmp_path / "long.parquet", chunk)
    full = fio.read_catalog(tmp_path / "long.parquet").events.memory_usage(deep=True).sum()
    # each chunk file becomes one row group of the merged catalog: no chunk held more
    assert _row_group_sizes(tmp_path / "short.parquet") == [chunk] * 8
    assert _row_group_sizes(tmp_path / "long.parquet") == [chunk] * 100
    # far below the whole catalog (6.4 MB): the peak, 0.3-0.8 MB with the chunk's buffers
    # (the most with the oldest declared versions, in the whole suite), is the chunk's
    assert long < 0.25 * full, (long, full)
    # independent of the run length, but for Numba's: its dispatcher keeps some of what it
    # allocates typing the kernel's arguments, call after call (0.1 MB more for the long run
    # than the short one with Numba 0.68, 0.25-0.4 MB with Numba 0.60), against the 6.4 MB
    # that holding the catalog would add
    assert long - short < 0.1 * full, (short, long, full)


class Stop(BaseException):
    """Raised by an ``on_commit`` hook: a kill right after a commit."""


def test_on_commit_sees_every_chunk_and_can_stop_the_run(tmp_path):
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(30), alpha=1.5)
    kw = dict(rng=2, chunk_events=200, checkpoint_interval=0, progress=False)
    seen = []
    simulate_to_parquet(model, 1000, tmp_path / "a.parquet", on_commit=seen.append, **kw)
    assert seen == [1, 2, 3, 4, 5]  # one call per committed chunk, before the merge
    seen.clear()
    simulate_to_parquet(model, 1000, None, on_commit=seen.append, **kw)
    assert seen == []  # nothing is committed without an output file

    def stop_after_two(n_chunks):
        if n_chunks == 2:
            raise Stop

    out = tmp_path / "b.parquet"
    with pytest.raises(Stop):
        simulate_to_parquet(model, 1000, out, on_commit=stop_after_two, **kw)
    assert not out.exists()
    rep = simulate_to_parquet(model, 1000, out, resume=True, **kw)
    assert rep.status == "resumed" and rep.resumed_from == 400
    ref = fio.read_catalog(tmp_path / "a.parquet").events
    pd.testing.assert_frame_equal(fio.read_catalog(out).events, ref, check_exact=True)


def test_bad_arguments_are_named(tmp_path):
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10))
    out = tmp_path / "x.parquet"
    with pytest.raises(InvalidParameterError, match="must be a CarlsonLanger or an OFC; got Graph"):
        simulate_to_parquet(model.graph, 10, out)
    with pytest.raises(InvalidParameterError, match="checkpoint_interval must be >= 0 s"):
        simulate_to_parquet(model, 10, out, checkpoint_interval=-1)
    with pytest.raises(InvalidParameterError, match="output folder .*missing does not exist"):
        simulate_to_parquet(model, 10, tmp_path / "missing" / "x.parquet")
    os.mkdir(out)
    with pytest.raises(OutputExistsError, match="is a folder; give a file name"):
        simulate_to_parquet(model, 10, out)
    assert os.listdir(tmp_path) == ["x.parquet"]  # nothing written next to it
