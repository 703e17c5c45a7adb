"""Parquet catalogs (faultnet.io.parquet): round trips, node labels, atomic writes, bad files."""

import os

import networkx as nx
import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import faultnet
from faultnet.exceptions import CatalogError, InvalidParameterError, OutputExistsError
from faultnet.io import parquet as fio
from faultnet.io.atomic import atomic_path
from faultnet.model.identity import graph_hash


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


def _encodings(path):
    meta = pq.ParquetFile(path).metadata
    row_group = meta.row_group(meta.num_row_groups - 1)
    return {
        row_group.column(c).path_in_schema: set(row_group.column(c).encodings)
        for c in range(row_group.num_columns)
    }


def test_parts_and_merged_catalog_encode_by_column_kind(tmp_path, ring_result):
    """Floats plain, event numbers delta-coded, repeating integers with dictionaries."""
    events = ring_result.events
    parts = [tmp_path / "a.parquet", tmp_path / "b.parquet"]
    fio.write_part(events.iloc[:150], parts[0])
    fio.write_part(events.iloc[150:], parts[1])
    fio.merge_parts(parts, tmp_path / "all.parquet", {"note": "merged"})
    for path in [*parts, tmp_path / "all.parquet"]:
        enc = _encodings(path)
        for name in ("t", "duration", "S", "M"):
            assert "RLE_DICTIONARY" not in enc[name] and "PLAIN" in enc[name], (path, name)
        assert "DELTA_BINARY_PACKED" in enc["event"], path
        for name in ("n_blocks", "hypocenter", "n_steps"):
            assert "RLE_DICTIONARY" in enc[name], (path, name)
    back = pd.read_parquet(tmp_path / "all.parquet")
    pd.testing.assert_frame_equal(back, events, check_exact=True)


def test_string_and_tuple_node_labels(tmp_path):
    g = nx.relabel_nodes(faultnet.graphs.ring(12), {i: f"b{i}" for i in range(12)})
    res = faultnet.simulate(faultnet.CarlsonLanger(g), 60, rng=1, progress=False)
    fio.write_catalog(res, tmp_path / "s.parquet")
    back = fio.read_catalog(tmp_path / "s.parquet").events
    pd.testing.assert_frame_equal(back, res.events, check_exact=True)
    # labels Parquet cannot hold in one column (tuples) come back as tuples
    events = res.events.copy()
    events["hypocenter"] = pd.Series([(i, i + 1) for i in range(len(events))], dtype=object)
    fio.write_catalog(events, tmp_path / "t.parquet")
    cat = fio.read_catalog(tmp_path / "t.parquet")
    assert cat.metadata["labels"] == {"hypocenter": "json"}
    pd.testing.assert_frame_equal(cat.events, events, check_exact=True)


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


def test_catalog_names_end_in_parquet(tmp_path, ring_result):
    """A catalog is Parquet whatever its name: a .csv name is refused, before anything runs."""
    for name in ("cat.csv", "cat", "cat.parquet.tmp"):
        with pytest.raises(InvalidParameterError, match=r"path must name a \.parquet file"):
            fio.write_catalog(ring_result, tmp_path / name)
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10))
    with pytest.raises(InvalidParameterError, match=r"out must name a \.parquet file.*cat\.csv"):
        faultnet.simulate_to_parquet(model, 10, tmp_path / "cat.csv", rng=1, progress=False)
    assert os.listdir(tmp_path) == []


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
