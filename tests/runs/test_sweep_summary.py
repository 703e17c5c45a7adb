"""Summary tables (faultnet.runs.sweep.summary): a folder of plain catalogs, bad folders."""

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import faultnet
from faultnet.exceptions import InvalidParameterError
from faultnet.io.parquet import write_catalog
from faultnet.io.summary import catalog_stats
from faultnet.runs.sweep.summary import SUMMARY_COLUMNS, summarize


def test_a_folder_of_catalogs(tmp_path):
    for i, alpha in enumerate((1.0, 2.0)):
        model = faultnet.CarlsonLanger(faultnet.graphs.ring(20), alpha=alpha)
        res = faultnet.simulate(model, 150, rng=i, progress=False)
        write_catalog(res, tmp_path / f"run{i}.parquet")
    pq.write_table(pa.table({"x": [1]}), tmp_path / "other.parquet")  # not a catalog: skipped
    table = summarize(tmp_path, transient=20)
    assert list(table.columns) == SUMMARY_COLUMNS
    assert table["part"].tolist() == ["run0.parquet", "run1.parquet"]
    assert table["alpha"].tolist() == [1.0, 2.0]
    assert table["point"].tolist() == [1, 2]  # place among the folder's .parquet names
    assert table["seed_entropy"].tolist() == ["0", "1"] and (table["status"] == "done").all()
    st = catalog_stats(tmp_path / "run1.parquet", transient=20)
    assert table["b_mle"].iloc[1] == st["b_mle"] and table["events"].iloc[1] == 150
    assert table.attrs["out"] == str(tmp_path)


def test_bad_folders(tmp_path):
    with pytest.raises(InvalidParameterError, match="holds no sweep"):
        summarize(tmp_path)
    with pytest.raises(InvalidParameterError, match="is not a folder"):
        summarize(tmp_path / "missing")
