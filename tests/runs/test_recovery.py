"""Ordinary accidents end in one line naming the cause, never a traceback or a wrong answer."""

import json
import os
import subprocess
import sys
import time

import pyarrow.parquet as pq
import pytest

import faultnet
from faultnet.__main__ import main
from faultnet.exceptions import CatalogError, InvalidParameterError
from faultnet.io.parquet import read_catalog
from faultnet.io.summary import catalog_stats

SIM = ["simulate", "ring:50", "-n", "2000", "--seed", "1", "--no-progress"]


@pytest.fixture(scope="module")
def catalog(tmp_path_factory):
    path = tmp_path_factory.mktemp("cat") / "c.parquet"
    assert main([*SIM, "--out", str(path)]) == 0
    return path


def _rewrite(src, dst, rename=None, metadata=None):
    table = pq.read_table(src)
    md = dict(table.schema.metadata)
    if rename:
        table = table.rename_columns([rename.get(n, n) for n in table.column_names])
    if metadata is not None:
        md[b"faultnet"] = json.dumps(metadata).encode()
    pq.write_table(table.replace_schema_metadata(md), dst)
    return dst


def _metadata(path):
    return json.loads(pq.read_schema(path).metadata[b"faultnet"])


DAMAGES = {
    "M renamed": (dict(rename={"M": "mag"}), r"has no column 'M'"),
    "t renamed": (dict(rename={"t": "time"}), r"has no column 't'"),
    "n_blocks renamed": (dict(rename={"n_blocks": "nb"}), r"has no column 'n_blocks'"),
    "event renamed": (dict(rename={"event": "id"}), r"has no column 'event'"),
    "metadata a list": (dict(metadata=[1, 2]), r"metadata is garbled: it is a JSON list"),
    "n_events a string": ("n_events", r"n_events must be an integer; got '2000'"),
}


def _damaged(catalog, tmp_path, damage):
    how, _ = DAMAGES[damage]
    if how == "n_events":
        how = dict(metadata=dict(_metadata(catalog), n_events="2000"))
    return _rewrite(catalog, tmp_path / "bad.parquet", **how)


@pytest.mark.parametrize("damage", sorted(DAMAGES))
def test_a_damaged_catalog_gets_one_line_in_info_and_resume(
    catalog, tmp_path, capsys, damage, one_line
):
    bad = _damaged(catalog, tmp_path, damage)
    pattern = DAMAGES[damage][1]
    assert main(["info", str(bad)]) == 1
    err = one_line()
    assert str(bad) in err and __import__("re").search(pattern, err), err
    with pytest.raises(CatalogError, match=pattern):
        catalog_stats(bad)
    rc = main(["simulate", "--resume", "--out", str(bad), "--no-progress"])
    assert rc == 1
    one_line()


def test_summarize_reports_the_good_files_and_names_the_bad_ones(catalog, tmp_path, capsys):
    folder = tmp_path / "runs"
    folder.mkdir()
    good = folder / "a-good.parquet"
    good.write_bytes(catalog.read_bytes())
    for i, damage in enumerate(["M renamed", "metadata a list", "n_events a string"]):
        os.replace(_damaged(catalog, tmp_path, damage), folder / f"b-bad{i}.parquet")
    assert main(["summarize", str(folder)]) == 0
    out = capsys.readouterr().out
    table = faultnet.summarize(folder)
    assert list(table["status"].str[:7]) == ["done", "corrupt", "corrupt", "corrupt"]
    assert table["b_mle"].iloc[0] == pytest.approx(catalog_stats(catalog)["b_mle"])
    for i in range(3):
        assert f"b-bad{i}.parquet" in table["status"].iloc[i + 1]
    assert "corrupt" in out


def test_simulate_and_info_print_the_same_fits(tmp_path, capsys):
    """The transient that simulate left out by default is recorded, and info uses it."""
    path = tmp_path / "b.parquet"
    assert main([*SIM, "--out", str(path)]) == 0
    printed = capsys.readouterr().out
    md = read_catalog(path).metadata
    assert md["transient"] > 0 and "plate time 2" in md["transient_rule"]
    assert main(["info", str(path)]) == 0
    info = capsys.readouterr().out

    def fits(text):
        return [line for line in text.splitlines() if line.startswith("b (")]

    assert fits(printed) == fits(info) and len(fits(info)) == 2
    assert f"after a transient of {md['transient']:,}" in fits(info)[0]
    # the same count as the rule applied to the catalog's own plate times
    t = read_catalog(path).events["t"].to_numpy()
    assert md["transient"] == min(int((t < 2.0).sum()), len(t) // 2)
    # without --out the same fits are printed
    assert main(SIM) == 0
    assert fits(capsys.readouterr().out) == fits(printed)


@pytest.mark.parametrize("n_events", [10**20, 10**9])
def test_more_events_than_memory_is_refused_up_front(n_events, capsys, monkeypatch, one_line):
    from faultnet import _validate

    monkeypatch.setattr(_validate, "available_memory", lambda: 4 * 2**30)  # a small machine
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(20))
    with pytest.raises(
        InvalidParameterError, match=r"n_events=.* GiB of memory.*simulate_to_parquet"
    ):
        faultnet.simulate(model, n_events, progress=False)
    assert main(["simulate", "ring:20", "-n", str(n_events), "--no-progress"]) == 2
    assert "give an output file" in one_line()


def test_a_too_stiff_spring_is_named():
    g = faultnet.graphs.ring(20)
    g.edges[3, 4]["k"] = 1e300
    with pytest.raises(
        InvalidParameterError, match=r"spring k=1e\+300 on edge \(3, 4\) is too stiff"
    ):
        faultnet.simulate(faultnet.CarlsonLanger(g), 10, progress=False)


def test_a_symlinked_out_is_written_through(tmp_path, capsys):
    (tmp_path / "store").mkdir()
    target = tmp_path / "store" / "real.parquet"
    link = tmp_path / "link.parquet"
    link.symlink_to(target)
    assert main(["simulate", "ring:20", "-n", "300", "--seed", "2", "--out", str(link)]) == 0
    assert link.is_symlink() and target.is_file()
    assert len(read_catalog(link).events) == 300
    # resume and a second write go through the link too
    assert main(["simulate", "--resume", "--out", str(link)]) == 0
    assert "already complete" in capsys.readouterr().out
    assert link.is_symlink()


def test_an_out_folder_deleted_mid_run_is_said_so(tmp_path):
    folder = tmp_path / "runs"
    folder.mkdir()
    out = folder / "c.parquet"
    cmd = [sys.executable, "-m", "faultnet", *SIM[:2], "-n", "4000000", "--chunk", "500",
           "--checkpoint-every", "0", "--out", str(out)]  # fmt: skip
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not (folder / "c.parquet.checkpoint" / "checkpoint.npz").exists():
        assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
        time.sleep(0.02)
    os.rename(folder, tmp_path / "gone")  # atomic, unlike rm -rf beside a running writer
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 1, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert "is gone too" in err and "intact" not in err
