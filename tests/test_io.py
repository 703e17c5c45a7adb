"""Parquet catalogs (faultnet.io): round trips, bad files, chunked runs and their memory bound."""

import os
import tracemalloc

import networkx as nx
import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import faultnet
from faultnet import io as fio
from faultnet import runner
from faultnet.atomic import atomic_path
from faultnet.exceptions import CatalogError, OutputExistsError
from faultnet.specs import graph_hash


@pytest.fixture(scope="module")
def ring_result():
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(30), alpha=1.5)
    return faultnet.simulate(
        model, 400, rng=np.random.SeedSequence(77, spawn_key=(3,)), progress=False
    )


def test_round_trip_dataframe_and_metadata(tmp_path, ring_result):
    path = tmp_path / "cat.parquet"
    fio.write_catalog(ring_result, path, metadata={"note": "hello", "big": 2**100})
    cat = fio.read_catalog(path)
    pd.testing.assert_frame_equal(cat.events, ring_result.events, check_exact=True)
    md = cat.metadata
    for key, value in ring_result.metadata.items():
        assert md[key] == value, key  # spawn keys come back as tuples, floats exactly
    assert md["seed_entropy"] == 77 and md["seed_spawn_key"] == (3,)
    assert md["graph_hash"] == graph_hash(ring_result.model)
    assert md["big"] == 2**100 and md["note"] == "hello"
    assert md["provenance"]["faultnet"] == faultnet.__version__
    assert fio.read_metadata(path) == md
    # any Parquet reader sees the plain table
    pd.testing.assert_frame_equal(pd.read_parquet(path), ring_result.events, check_exact=True)
    # the full dict round-trips: writing it again gives the same dict back
    fio.write_part(cat.events, tmp_path / "again.parquet", md)
    assert fio.read_metadata(tmp_path / "again.parquet") == md


def test_string_and_tuple_node_labels(tmp_path):
    g = nx.relabel_nodes(faultnet.graphs.ring(12), {i: f"b{i}" for i in range(12)})
    res = faultnet.simulate(faultnet.CarlsonLanger(g), 60, rng=1, progress=False)
    fio.write_catalog(res, tmp_path / "s.parquet")
    back = fio.read_catalog(tmp_path / "s.parquet").events
    pd.testing.assert_frame_equal(back, res.events, check_exact=True)
    # labels Parquet cannot hold in one column (tuples) are kept as their repr
    events = res.events.copy()
    events["hypocenter"] = pd.Series([(i, i + 1) for i in range(len(events))], dtype=object)
    fio.write_catalog(events, tmp_path / "t.parquet")
    cat = fio.read_catalog(tmp_path / "t.parquet")
    assert cat.metadata["hypocenter_labels"] == "repr"
    assert list(cat.events["hypocenter"]) == [repr(h) for h in events["hypocenter"]]


def test_never_overwrites_and_atomic(tmp_path, ring_result):
    path = tmp_path / "cat.parquet"
    fio.write_catalog(ring_result, path)
    before = path.read_bytes()
    with pytest.raises(OutputExistsError, match="refusing to overwrite"):
        fio.write_catalog(ring_result, path)
    # a writer that dies half-way leaves the old file and no temporary file
    with pytest.raises(RuntimeError), atomic_path(path) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(b"half a file")
        raise RuntimeError("killed")
    assert path.read_bytes() == before
    assert sorted(os.listdir(tmp_path)) == ["cat.parquet"]
    fio.write_catalog(ring_result, path, metadata={"v": 2}, overwrite=True)
    assert fio.read_metadata(path)["v"] == 2


def test_bad_files_are_reported(tmp_path, ring_result):
    path = tmp_path / "cat.parquet"
    fio.write_catalog(ring_result, path)
    data = path.read_bytes()
    (tmp_path / "trunc.parquet").write_bytes(data[: len(data) // 2])
    with pytest.raises(CatalogError, match="truncated or corrupt"):
        fio.read_catalog(tmp_path / "trunc.parquet")
    pq.write_table(pa.table({"x": [1, 2]}), tmp_path / "other.parquet")
    with pytest.raises(CatalogError, match="without faultnet metadata"):
        fio.read_metadata(tmp_path / "other.parquet")
    with pytest.raises(CatalogError, match="does not exist"):
        fio.read_catalog(tmp_path / "missing.parquet")


def test_chunked_run_is_bit_identical(tmp_path):
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(40), alpha=2.0)
    out = tmp_path / "run.parquet"
    rep = runner.simulate_to_parquet(
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
    assert md["transient"] == 100 and md["sessions"] == 1
    assert pq.ParquetFile(out).metadata.num_row_groups >= 8  # written in parts
    assert sorted(os.listdir(tmp_path)) == ["run.parquet"]  # checkpoint folder removed
    # iter_catalog streams the same rows
    streamed = pd.concat(fio.iter_catalog(out, batch_size=700), ignore_index=True)
    pd.testing.assert_frame_equal(streamed, ref.events, check_exact=True)


def _peak_bytes(model, n, out, chunk):
    tracemalloc.start()
    tracemalloc.reset_peak()
    runner.simulate_to_parquet(
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
    runner.simulate_to_parquet(
        model, 1500, tmp_path / "warm.parquet", rng=1, chunk_events=1000, progress=False
    )
    chunk = 1000
    short = _peak_bytes(model, 8_000, tmp_path / "short.parquet", chunk)
    long = _peak_bytes(model, 40_000, tmp_path / "long.parquet", chunk)
    full = fio.read_catalog(tmp_path / "long.parquet").events.memory_usage(deep=True).sum()
    # each chunk file becomes one row group of the merged catalog: no chunk held more
    assert _row_group_sizes(tmp_path / "short.parquet") == [chunk] * 8
    assert _row_group_sizes(tmp_path / "long.parquet") == [chunk] * 40
    assert long < 0.25 * full, (long, full)  # far below the whole catalog (2.6 MB)
    assert long < 1.5 * short + 100_000, (short, long)  # independent of the run length
