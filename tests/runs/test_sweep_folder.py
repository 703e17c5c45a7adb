"""A sweep's output folder (faultnet.runs.sweep.folder): names, manifest, point states."""

import json

import pytest

from faultnet._version import __version__
from faultnet.exceptions import OutputExistsError
from faultnet.runs.checkpoint import CHECKPOINT_SUFFIX
from faultnet.runs.sweep.config import SweepConfig
from faultnet.runs.sweep.folder import (
    MANIFEST,
    is_own_file,
    point_file_name,
    point_state,
    prepare_out,
)


def test_point_file_names_and_own_files():
    assert point_file_name(7, 12) == "part-00007.parquet"
    assert point_file_name(3, 123_457) == "part-000003.parquet"
    for name in ("part-00007.parquet", MANIFEST, "part-00007.parquet" + CHECKPOINT_SUFFIX):
        assert is_own_file(name), name
    assert is_own_file(".part-00007.parquet.tmp-12-ab12cd34")
    for name in ("notes.txt", "part-7.csv", "catalog.parquet"):
        assert not is_own_file(name), name


def test_prepare_out_keeps_the_manifest_seed(tmp_path):
    table = {"graph": "ring:10", "events": 20}
    out = tmp_path / "o"
    cfg = prepare_out(SweepConfig.from_dict(table), out, force=False)
    record = json.loads((out / MANIFEST).read_text())
    assert record["config"]["seed"] == cfg.seed is not None
    assert record["n_points"] == 1 and record["faultnet_version"] == __version__
    again = prepare_out(SweepConfig.from_dict(table), out, force=False)
    assert again.seed == cfg.seed
    with pytest.raises(OutputExistsError, match="events: 20 -> 30"):
        prepare_out(SweepConfig.from_dict(dict(table, events=30)), out, force=False)
    forced = prepare_out(SweepConfig.from_dict(dict(table, events=30)), out, force=True)
    assert json.loads((out / MANIFEST).read_text())["config"]["events"] == forced.events == 30


def test_prepare_out_refuses_a_file_and_a_foreign_folder(tmp_path):
    cfg = SweepConfig.from_dict({"graph": "ring:10", "events": 20})
    (tmp_path / "f").write_text("x")
    with pytest.raises(OutputExistsError, match="is not a folder"):
        prepare_out(cfg, tmp_path / "f", force=False)
    with pytest.raises(OutputExistsError, match=r"holds no sweep \(f\)"):
        prepare_out(cfg, tmp_path, force=False)


def test_point_state_missing_and_corrupt(tmp_path):
    cfg = SweepConfig.from_dict({"graph": "ring:10", "events": 20, "seed": 1})
    point = cfg.points()[0]
    path = tmp_path / point_file_name(0, 1)
    assert point_state(point, str(path), force=False) == ("todo", "missing")
    path.write_bytes(b"not parquet")
    assert point_state(point, str(path), force=False) == ("todo", "corrupt")
    assert not path.exists()
