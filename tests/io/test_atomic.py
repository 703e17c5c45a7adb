"""Atomic writes (faultnet.io.atomic): all or nothing, no leftovers, no silent overwrite."""

import json
import os

import numpy as np
import pytest

from faultnet.exceptions import OutputExistsError
from faultnet.io.atomic import atomic_path, atomic_write_json, is_tmp_name, tmp_name


def test_a_killed_writer_leaves_the_old_file_and_no_temporary(tmp_path):
    path = tmp_path / "x.bin"
    path.write_bytes(b"old")
    with pytest.raises(RuntimeError), atomic_path(path) as tmp:
        assert is_tmp_name(os.path.basename(tmp)) and os.path.dirname(tmp) == str(tmp_path)
        with open(tmp, "wb") as fh:
            fh.write(b"half a file")
        raise RuntimeError("killed")
    assert path.read_bytes() == b"old"
    assert os.listdir(tmp_path) == ["x.bin"]
    with (
        pytest.raises(OutputExistsError, match="refusing to overwrite"),
        atomic_path(path, overwrite=False),
    ):
        pass
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(b"new")
    assert path.read_bytes() == b"new"


def test_json_holds_numpy_values(tmp_path):
    path = tmp_path / "m.json"
    atomic_write_json(path, {"n": np.int64(3), "x": np.float32(0.5), "s": {2, 1}, "b": np.True_})
    assert json.loads(path.read_text()) == {"n": 3, "x": 0.5, "s": [1, 2], "b": True}
    with pytest.raises(TypeError, match="not JSON-serialisable"):
        atomic_write_json(path, {"f": object()})
    assert json.loads(path.read_text())["n"] == 3


def test_tmp_names_are_recognised():
    name = os.path.basename(tmp_name("/a/b/catalog.parquet"))
    assert name.startswith(".catalog.parquet.tmp-") and is_tmp_name(name)
    assert not is_tmp_name("catalog.parquet") and not is_tmp_name(".hidden")
