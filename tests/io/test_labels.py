"""Node and fault labels in catalog files (faultnet.io.labels): types kept, others refused."""

import json

import networkx as nx
import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import faultnet
from faultnet.exceptions import CatalogError, InvalidParameterError
from faultnet.io import parquet as fio
from faultnet.io.catalog_file import METADATA_KEY
from faultnet.io.labels import check_labels, decode_column, encode_column


def _objects(labels):
    out = np.empty(len(labels), dtype=object)
    for i, label in enumerate(labels):
        out[i] = label
    return out


def _events(hypocenters):
    n = len(hypocenters)
    return pd.DataFrame(
        {
            "event": np.arange(n, dtype=np.int64),
            "t": np.linspace(0.0, 1.0, n),
            "M": np.zeros(n),
            "hypocenter": hypocenters,
        }
    )


LABELS = {
    "str": _objects(["a", "b", "é", "a"]),
    "int": np.array([3, -1, 2**62, 3], dtype=np.int64),
    "mixed": _objects(["a", 1, "1", 1, np.int64(7)]),
    "tuple": _objects([("B", 497), ("A", 3), ("B", 497)]),
    "nested": _objects([("A", (1, ("b", 2))), (), ("x",), "top", 5]),
    "int64 objects": _objects([np.int64(5), 6, np.int32(7)]),
    "big int": _objects([2**70, -(2**65), 1]),
}


def _expected(labels):
    """What reading gives back: ints and strs as themselves, NumPy integers as ints."""

    def plain(label):
        if isinstance(label, tuple):
            return tuple(plain(x) for x in label)
        return int(label) if isinstance(label, np.integer) else label

    return [plain(label) for label in labels]


def _same(got, labels):
    if labels.dtype != object:
        assert got.dtype == labels.dtype and list(got) == list(labels)
        return
    want = _expected(labels)
    got = list(got)
    assert got == list(want)
    assert [type(x) for x in got] == [type(x) for x in want]  # 1 is not "1", (1,) not [1]


@pytest.mark.parametrize("kind", sorted(LABELS))
def test_labels_round_trip(tmp_path, kind):
    labels = LABELS[kind]
    events = _events(labels)
    path = tmp_path / "cat.parquet"
    fio.write_catalog(events, path)
    cat = fio.read_catalog(path)
    _same(cat.events["hypocenter"], labels)
    streamed = pd.concat(fio.iter_catalog(path, batch_size=2), ignore_index=True)
    _same(streamed["hypocenter"], labels)
    only = fio.read_catalog(path, columns=["hypocenter"]).events
    _same(only["hypocenter"], labels)
    field = pq.read_schema(path).field("hypocenter")
    if kind in ("str", "int", "int64 objects"):
        assert "labels" not in cat.metadata
        plain = (pa.string(), pa.large_string()) if kind == "str" else (pa.int64(),)
        assert field.type in plain
    else:
        assert pa.types.is_string(field.type)
        assert cat.metadata["labels"] == {"hypocenter": "json"}


def test_native_columns_stay_native(tmp_path):
    fio.write_catalog(_events(LABELS["int"]), tmp_path / "i.parquet")
    fio.write_catalog(_events(LABELS["str"]), tmp_path / "s.parquet")
    assert pq.read_schema(tmp_path / "i.parquet").field("hypocenter").type == pa.int64()
    typ = pq.read_schema(tmp_path / "s.parquet").field("hypocenter").type
    assert typ in (pa.string(), pa.large_string())
    # other readers see the plain values
    back = pd.read_parquet(tmp_path / "s.parquet")["hypocenter"]
    assert list(back) == ["a", "b", "é", "a"]


def test_encoded_text_is_canonical_json(tmp_path):
    fio.write_catalog(_events(LABELS["nested"]), tmp_path / "n.parquet")
    raw = pq.read_table(tmp_path / "n.parquet").column("hypocenter").to_pylist()
    assert raw == ['["A",[1,["b",2]]]', "[]", '["x"]', '"top"', "5"]
    assert [json.loads(x) for x in raw][0] == ["A", [1, ["b", 2]]]


@pytest.mark.parametrize(
    ("labels", "typename"),
    [
        (np.array([1.5, 2.0]), "float"),
        (_objects([1, 2.0]), "float"),
        (np.array([True, False]), "bool"),
        (_objects([1, True]), "bool"),
        (_objects([1, None]), "NoneType"),
        (_objects(["a", None]), "(NoneType|float)"),  # pandas may hold None in strs as nan
        (_objects([frozenset({1}), 2]), "frozenset"),
        (_objects([[1, 2], [3]]), "list"),
        (_objects([("A", 1.5)]), "float"),
        (_objects([("A", [1])]), "list"),
    ],
)
def test_other_labels_are_refused_at_write_time(tmp_path, labels, typename):
    path = tmp_path / "bad.parquet"
    with pytest.raises(InvalidParameterError, match=rf"column 'hypocenter'.*of type {typename}"):
        fio.write_catalog(_events(labels), path)
    assert not path.exists()
    for name in ("node", "fault"):
        frame = pd.DataFrame({"event": np.arange(len(labels)), name: labels})
        with pytest.raises(InvalidParameterError, match=rf"column '{name}'.*{typename}"):
            fio.write_part(frame, tmp_path / f"{name}.parquet")


def test_check_labels_before_a_run():
    graph = faultnet.graphs.ring(5)
    check_labels(graph.nodes, "graph nodes")
    check_labels(nx.relabel_nodes(graph, lambda i: ("A", i)).nodes, "graph nodes")
    bad = nx.relabel_nodes(graph, lambda i: i + 0.5)
    with pytest.raises(InvalidParameterError, match=r"graph nodes: label 0\.5 of type float"):
        check_labels(bad.nodes, "graph nodes")
    with pytest.raises(InvalidParameterError, match="str, int .* or a tuple"):
        check_labels([("A", frozenset())], "graph nodes")


def test_other_label_columns_round_trip(tmp_path):
    """A slips table (event, node, slip) and a fault column use the same codec."""
    nodes = _objects([("A", 1), ("B", 2), ("A", 1)])
    slips = pd.DataFrame({"event": np.arange(3), "node": nodes, "slip": [0.1, 0.2, 0.3]})
    fio.write_part(slips, tmp_path / "slips.parquet")
    cat = fio.read_catalog(tmp_path / "slips.parquet")
    assert cat.metadata["labels"] == {"node": "json"}
    pd.testing.assert_frame_equal(cat.events, slips)
    events = _events(LABELS["tuple"]).assign(fault=_objects(["f1", 2, "f1"]))
    fio.write_part(events, tmp_path / "f.parquet")
    cat = fio.read_catalog(tmp_path / "f.parquet")
    assert cat.metadata["labels"] == {"fault": "json", "hypocenter": "json"}
    pd.testing.assert_frame_equal(cat.events, events)


def _write_v02(events, path):
    """A catalog as faultnet 0.2 wrote it: labels as their repr."""
    md = {"format": "faultnet-catalog", "format_version": 1, "hypocenter_labels": "repr"}
    table = pa.Table.from_pandas(
        events.assign(hypocenter=events["hypocenter"].map(repr).astype(str)),
        preserve_index=False,
    )
    schema_md = dict(table.schema.metadata) | {METADATA_KEY: json.dumps(md).encode()}
    pq.write_table(table.replace_schema_metadata(schema_md), path)


def test_v02_repr_files_read_back_tuples(tmp_path):
    labels = _objects([("B", 497), "a", 3, ("A", (1, "x")), np.int64(4), ("C", np.int64(5))])
    events = _events(labels)
    _write_v02(events, tmp_path / "old.parquet")
    _same(fio.read_catalog(tmp_path / "old.parquet").events["hypocenter"], labels)
    streamed = pd.concat(fio.iter_catalog(tmp_path / "old.parquet", batch_size=4))
    _same(streamed["hypocenter"], labels)
    # a text that is no literal stays text
    assert decode_column(["<object at 0x1>", "('B', 1)"], "repr").tolist() == [
        "<object at 0x1>",
        ("B", 1),
    ]
    # written again, it is in today's form
    cat = fio.read_catalog(tmp_path / "old.parquet")
    fio.write_part(cat.events, tmp_path / "new.parquet", cat.metadata)
    md = fio.read_metadata(tmp_path / "new.parquet")
    assert "hypocenter_labels" not in md and md["labels"] == {"hypocenter": "json"}
    _same(fio.read_catalog(tmp_path / "new.parquet").events["hypocenter"], labels)


def test_merge_makes_label_columns_consistent(tmp_path):
    """Parts of a graph with str and int labels may store them plain or as JSON: the merged
    file holds JSON throughout; a 0.2 part is re-encoded too."""
    pieces = [_objects(["a", "b"]), _objects([1, 2]), _objects(["c", 3]), _objects([("T", 1)])]
    parts = []
    for i, labels in enumerate(pieces):
        parts.append(tmp_path / f"p{i}.parquet")
        events = _events(labels).assign(event=np.arange(2 * i, 2 * i + len(labels)))
        fio.write_part(events, parts[-1], {"labels": {"hypocenter": "json"}, "chunk": i})
    _write_v02(_events(_objects([("Z", 9)])).assign(event=[7]), tmp_path / "old.parquet")
    parts.append(tmp_path / "old.parquet")
    assert "labels" not in fio.read_metadata(parts[0])  # plain strs: no stale tag
    out = tmp_path / "all.parquet"
    fio.merge_parts(parts, out, {"note": "merged", "hypocenter_labels": "repr"})
    cat = fio.read_catalog(out)
    assert cat.metadata["labels"] == {"hypocenter": "json"}
    assert "hypocenter_labels" not in cat.metadata
    want = _objects(["a", "b", 1, 2, "c", 3, ("T", 1), ("Z", 9)])
    _same(cat.events["hypocenter"], want)
    assert pq.read_schema(out).field("hypocenter").type == pa.string()
    # parts stored alike are copied as they are
    fio.write_part(_events(_objects(["x"])).assign(event=[2]), tmp_path / "q.parquet")
    fio.merge_parts([parts[0], tmp_path / "q.parquet"], tmp_path / "same.parquet", {})
    assert "labels" not in fio.read_metadata(tmp_path / "same.parquet")
    typ = pq.read_schema(tmp_path / "same.parquet").field("hypocenter").type
    assert typ == pq.read_schema(parts[0]).field("hypocenter").type


def test_codec_helpers():
    values, tag = encode_column(_objects([("B", 497), "B", 497]), "hypocenter")
    assert tag == "json" and list(values) == ['["B",497]', '"B"', "497"]
    assert decode_column(values, "json").tolist() == [("B", 497), "B", 497]
    ints = np.arange(3)
    assert encode_column(ints, "node") == (ints, None)


@pytest.fixture(scope="module")
def tuple_model():
    graph = nx.relabel_nodes(faultnet.graphs.ring(30), lambda i: ("A", i))
    return faultnet.CarlsonLanger(graph)


def test_tuple_labelled_run_round_trips(tmp_path, tuple_model):
    res = faultnet.simulate(tuple_model, 200, rng=1, progress=False)
    assert isinstance(res.events["hypocenter"].iloc[0], tuple)
    path = tmp_path / "ring.parquet"
    faultnet.write_catalog(res, path)
    cat = faultnet.read_catalog(path)
    pd.testing.assert_frame_equal(cat.events, res.events, check_exact=True)
    assert cat.metadata["labels"] == {"hypocenter": "json"}


def test_tuple_labelled_long_run_round_trips(tmp_path, tuple_model):
    out = tmp_path / "long.parquet"
    faultnet.simulate_to_parquet(tuple_model, 500, out, rng=1, chunk_events=100, progress=False)
    assert pq.ParquetFile(out).metadata.num_row_groups >= 5
    ref = faultnet.simulate(tuple_model, 500, rng=1, progress=False)
    cat = faultnet.read_catalog(out)
    pd.testing.assert_frame_equal(cat.events, ref.events, check_exact=True)
    assert cat.metadata["labels"] == {"hypocenter": "json"}
    streamed = pd.concat(fio.iter_catalog(out, batch_size=128), ignore_index=True)
    pd.testing.assert_frame_equal(streamed, ref.events, check_exact=True)


def test_a_v02_tuple_catalog_is_extended(tmp_path, tuple_model):
    """Extending a finished 0.2 catalog merges its repr part with JSON parts: all JSON."""
    out = tmp_path / "ext.parquet"
    faultnet.simulate_to_parquet(tuple_model, 300, out, rng=1, chunk_events=100, progress=False)
    table = pq.read_table(out)
    md = json.loads(table.schema.metadata[METADATA_KEY])
    md["hypocenter_labels"] = "repr"
    del md["labels"]
    hyp = [repr(h) for h in fio.read_catalog(out).events["hypocenter"]]
    table = table.set_column(table.column_names.index("hypocenter"), "hypocenter", pa.array(hyp))
    schema_md = dict(table.schema.metadata) | {METADATA_KEY: json.dumps(md).encode()}
    pq.write_table(table.replace_schema_metadata(schema_md), out)
    old = fio.read_catalog(out)
    assert isinstance(old.events["hypocenter"].iloc[0], tuple)
    faultnet.simulate_to_parquet(
        tuple_model, 500, out, rng=1, chunk_events=100, progress=False, extend=True
    )
    ref = faultnet.simulate(tuple_model, 500, rng=1, progress=False)
    cat = faultnet.read_catalog(out)
    pd.testing.assert_frame_equal(cat.events, ref.events, check_exact=True)
    assert cat.metadata["labels"] == {"hypocenter": "json"}
    assert "hypocenter_labels" not in cat.metadata


def test_an_unknown_label_encoding_is_a_catalog_error(tmp_path):
    path = tmp_path / "odd.parquet"
    fio.write_part(_events(LABELS["tuple"]), path, {"note": 1})
    table = pq.read_table(path)
    md = json.loads(table.schema.metadata[METADATA_KEY]) | {"labels": {"hypocenter": "pickle"}}
    schema_md = dict(table.schema.metadata) | {METADATA_KEY: json.dumps(md).encode()}
    pq.write_table(table.replace_schema_metadata(schema_md), path)
    with pytest.raises(CatalogError, match="labels must map label columns to one of json"):
        fio.read_catalog(path)


def test_a_long_run_refuses_unsupported_labels_before_it_starts(tmp_path):
    graph = nx.relabel_nodes(faultnet.graphs.ring(10), lambda i: ("A", i + 0.5))
    model = faultnet.CarlsonLanger(graph)
    out = tmp_path / "c.parquet"
    with pytest.raises(InvalidParameterError, match=r"node labels: label \('A', 0.5\)"):
        faultnet.simulate_to_parquet(model, 100, out, rng=1, progress=False)
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # nothing run, nothing written
