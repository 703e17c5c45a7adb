"""Per-block and per-fault slips on disk: streamed in chunks, resumed and extended exactly."""

import os

import numpy as np
import pandas as pd
import pytest
from crash_hooks import Crash, crash_after

import faultnet
from faultnet.exceptions import CatalogError, InvalidParameterError
from faultnet.runs import chunks
from faultnet.runs.checkpoint import checkpoint_dir
from faultnet.runs.long_run import simulate_to_parquet

N = 1200


@pytest.fixture(scope="module")
def faults():
    graph = faultnet.graphs.parallel_faults(2, 25, k_coupling=2.0, periodic=True)
    model = faultnet.CarlsonLanger(graph, k=16, sigma=0.01, alpha=1.0)
    ref = faultnet.simulate(model, N, rng=5, record_slips=True, progress=False)
    return model, ref


def _run(model, out, n=N, **kw):
    kw = {"rng": 5, "chunk_events": 150, "checkpoint_interval": 0, "progress": False, **kw}
    return simulate_to_parquet(model, n, out, **kw)


def test_slips_on_disk_equal_the_slips_in_memory(tmp_path, faults):
    model, ref = faults
    out = str(tmp_path / "net.parquet")
    _run(model, out, record_slips=True)
    assert sorted(os.listdir(tmp_path)) == [
        "net.fault_slips.parquet",
        "net.parquet",
        "net.slips.parquet",
    ]
    slips = faultnet.read_slips(out)
    pd.testing.assert_frame_equal(slips, ref.slips)
    assert isinstance(slips["node"].iloc[0], tuple)  # labels come back with their type
    pd.testing.assert_frame_equal(faultnet.read_slips(out, per="fault"), ref.fault_slips)
    pd.testing.assert_frame_equal(faultnet.read_catalog(out).events, ref.events)
    batches = list(faultnet.iter_slips(out, batch_size=500))
    assert max(map(len, batches)) <= 500
    pd.testing.assert_frame_equal(pd.concat(batches, ignore_index=True), ref.slips)


def test_a_network_of_faults_writes_its_fault_slips_without_record_slips(tmp_path, faults):
    model, ref = faults
    out = str(tmp_path / "net.parquet")
    _run(model, out)
    assert sorted(os.listdir(tmp_path)) == ["net.fault_slips.parquet", "net.parquet"]
    pd.testing.assert_frame_equal(faultnet.read_slips(out, per="fault"), ref.fault_slips)
    with pytest.raises(CatalogError, match="record_slips=True"):
        faultnet.read_slips(out)


@pytest.mark.parametrize("commits", [1, 4])
def test_resumed_slips_are_bit_identical(tmp_path, faults, commits):
    model, ref = faults
    out = str(tmp_path / "net.parquet")
    with pytest.raises(Crash):
        _run(model, out, record_slips=True, on_commit=crash_after(commits))
    assert os.path.isdir(checkpoint_dir(out)) and not os.path.exists(out)
    rep = _run(model, out, record_slips=True, resume=True)
    assert rep.status == "resumed"
    pd.testing.assert_frame_equal(faultnet.read_slips(out), ref.slips)
    pd.testing.assert_frame_equal(faultnet.read_slips(out, per="fault"), ref.fault_slips)
    clean = str(tmp_path / "clean.parquet")
    _run(model, clean, record_slips=True)
    for name in ("slips", "fault_slips"):
        a = faultnet.read_slips(out, per="block" if name == "slips" else "fault")
        b = faultnet.read_slips(clean, per="block" if name == "slips" else "fault")
        assert np.array_equal(
            a["slip"].to_numpy().view(np.int64), b["slip"].to_numpy().view(np.int64)
        )


def test_an_extension_records_the_slips_of_one_longer_run(tmp_path, faults):
    model, ref = faults
    out = str(tmp_path / "net.parquet")
    _run(model, out, n=500, record_slips=True)
    with pytest.raises(Crash):
        _run(model, out, extend=True, record_slips=True, on_commit=crash_after(2))
    assert len(faultnet.read_slips(out)["event"].unique()) == 500  # still the shorter run
    _run(model, out, extend=True, record_slips=True)
    pd.testing.assert_frame_equal(faultnet.read_slips(out), ref.slips)
    pd.testing.assert_frame_equal(faultnet.read_slips(out, per="fault"), ref.fault_slips)


def test_a_run_without_slips_cannot_be_extended_with_them(tmp_path, faults):
    model, _ = faults
    out = str(tmp_path / "net.parquet")
    _run(model, out, n=300)
    with pytest.raises(InvalidParameterError, match="without record_slips"):
        _run(model, out, extend=True, record_slips=True)
    assert not os.path.exists(checkpoint_dir(out))


def test_resume_with_another_record_slips_is_refused(tmp_path, faults):
    model, _ = faults
    out = str(tmp_path / "net.parquet")
    with pytest.raises(Crash):
        _run(model, out, record_slips=True, on_commit=crash_after(1))
    with pytest.raises(InvalidParameterError, match="record_slips: checkpoint has True"):
        _run(model, out, resume=True)


def test_a_damaged_slips_chunk_is_refused_on_resume(tmp_path, faults):
    model, _ = faults
    out = str(tmp_path / "net.parquet")
    with pytest.raises(Crash):
        _run(model, out, record_slips=True, on_commit=crash_after(2))
    part = os.path.join(checkpoint_dir(out), "slips-000001.parquet")
    with open(part, "r+b") as fh:
        fh.seek(20)
        fh.write(b"\x00\x01\x02")
    with pytest.raises(CatalogError, match="slips-000001.parquet does not match its checksum"):
        _run(model, out, record_slips=True, resume=True)


def test_slips_from_another_run_are_refused_and_a_forced_run_removes_them(tmp_path, faults):
    model, _ = faults
    out = str(tmp_path / "net.parquet")
    _run(model, out, n=300, record_slips=True)
    kept = str(tmp_path / "kept.slips.parquet")
    os.replace(str(tmp_path / "net.slips.parquet"), kept)
    _run(model, out, n=300, rng=6, force=True, record_slips=True)
    os.replace(kept, str(tmp_path / "net.slips.parquet"))  # the first run's slips
    with pytest.raises(CatalogError, match="does not belong to the catalog"):
        faultnet.read_slips(out)
    with pytest.raises(CatalogError, match="does not belong"):  # resume checks them too
        _run(model, out, n=300, rng=6, resume=True, record_slips=True)
    _run(model, out, n=300, force=True)  # without record_slips: the stale file goes
    assert not os.path.exists(str(tmp_path / "net.slips.parquet"))


def test_side_rows_commit_a_chunk_to_bound_memory(tmp_path, faults, monkeypatch):
    model, ref = faults
    monkeypatch.setattr(chunks, "SIDE_ROWS_PER_CHUNK", 200)
    commits = []
    out = str(tmp_path / "net.parquet")
    _run(model, out, record_slips=True, chunk_events=N, checkpoint_interval=3600,
         on_commit=commits.append)  # fmt: skip
    assert len(commits) > 1  # the rows, not the events or the clock, set the chunks
    pd.testing.assert_frame_equal(faultnet.read_slips(out), ref.slips)


def test_bad_requests_get_one_clear_error(tmp_path, faults):
    model, _ = faults
    with pytest.raises(InvalidParameterError, match="give an output file"):
        simulate_to_parquet(model, 10, None, record_slips=True, progress=False)
    with pytest.raises(InvalidParameterError, match="record_slips must be True or False"):
        simulate_to_parquet(model, 10, str(tmp_path / "a.parquet"), record_slips="yes")
    out = str(tmp_path / "net.parquet")
    _run(model, out, n=100)
    with pytest.raises(InvalidParameterError, match="per must be one of 'block', 'fault'"):
        faultnet.read_slips(out, per="node")
    ring = str(tmp_path / "ring.parquet")
    _run(faultnet.CarlsonLanger(faultnet.graphs.ring(20)), ring, n=100)
    with pytest.raises(CatalogError, match="network of faults"):
        faultnet.read_slips(ring, per="fault")


def test_a_kill_between_the_slips_and_the_catalog_merge_resumes(tmp_path, faults, monkeypatch):
    """The side tables are merged first: a kill before the catalog's merge leaves them next to
    no catalog, and the resumed run merges them again."""
    from faultnet.runs import long_run

    model, ref = faults
    out = str(tmp_path / "net.parquet")
    real = long_run.merge_parts

    def merge(parts, target, md, **kw):
        if target == out:
            raise Crash
        return real(parts, target, md, **kw)

    monkeypatch.setattr(long_run, "merge_parts", merge)
    with pytest.raises(Crash):
        _run(model, out, record_slips=True)
    assert not os.path.exists(out) and os.path.exists(str(tmp_path / "net.slips.parquet"))
    monkeypatch.setattr(long_run, "merge_parts", real)
    assert _run(model, out, record_slips=True, resume=True).status == "resumed"
    pd.testing.assert_frame_equal(faultnet.read_slips(out), ref.slips)
    pd.testing.assert_frame_equal(faultnet.read_catalog(out).events, ref.events)


def test_uncommitted_slips_chunks_are_discarded_on_resume(tmp_path, faults):
    """A kill after a chunk's files but before its checkpoint: the resume drops them."""
    model, ref = faults
    out = str(tmp_path / "net.parquet")
    with pytest.raises(Crash):
        _run(model, out, record_slips=True, on_commit=crash_after(2))
    wd = checkpoint_dir(out)
    for name in ("chunk", "slips", "fault_slips"):  # a chunk 2 the checkpoint does not cover
        src = os.path.join(wd, f"{name}-000001.parquet")
        with open(src, "rb") as fh, open(os.path.join(wd, f"{name}-000002.parquet"), "wb") as dst:
            dst.write(fh.read())
    _run(model, out, record_slips=True, resume=True)
    pd.testing.assert_frame_equal(faultnet.read_slips(out), ref.slips)
