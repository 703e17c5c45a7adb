"""Soak: two writers of one output, started at random offsets, many times over.

Never may a catalog be marked complete (the output file exists, or a sweep
point reads as done) and be wrong: its rows must be events 0..n-1 and equal
a clean run's.  ``FAULTNET_SOAK_TRIALS`` sets the number of trials (default 20).
"""

import os
import random
import subprocess
import sys
import time

import pandas as pd
import pytest

from faultnet.io.parquet import read_catalog
from faultnet.runs.sweep.driver import sweep
from faultnet.runs.sweep.summary import summarize

pytestmark = pytest.mark.slow

PY = [sys.executable, "-m", "faultnet"]
TRIALS = int(os.environ.get("FAULTNET_SOAK_TRIALS", "20"))
SIM = ["ring:100", "--events", "6000", "--seed", "7", "--chunk", "500", "--checkpoint-every", "0"]
SWEEP = """[sweep]
graph = "ring:60"
alpha = [1.0, 2.0]
events = 3000
replicas = 2
seed = 5
chunk = 300
checkpoint_interval = 0
"""


def _two(cmd, offset, kill_after=None):
    """Start ``cmd`` twice, ``offset`` seconds apart; optionally SIGKILL one midway."""
    a = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(offset)
    b = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    if kill_after is not None:
        time.sleep(kill_after)
        a.kill()
    return a.wait(timeout=300), b.wait(timeout=300)


def _check_catalog(path, ref):
    ev = read_catalog(path).events  # read_catalog itself does not check: compare everything
    assert len(ev) == len(ref), (path, len(ev))
    assert (ev["event"].to_numpy() == range(len(ref))).all(), path
    pd.testing.assert_frame_equal(ev, ref)


def test_two_simulate_writers(tmp_path):
    ref_path = tmp_path / "ref.parquet"
    subprocess.run([*PY, "simulate", *SIM, "--out", str(ref_path)], check=True)
    ref = read_catalog(ref_path).events
    rnd = random.Random(1)
    complete = 0
    for trial in range(TRIALS):
        out = tmp_path / f"x{trial}.parquet"
        cmd = [*PY, "simulate", *SIM, "--resume", "--out", str(out)]
        kill = rnd.uniform(0.3, 2.0) if trial % 3 == 2 else None
        _two(cmd, rnd.uniform(0.0, 1.5), kill)
        if out.exists():
            complete += 1
            _check_catalog(out, ref)
        subprocess.run(cmd, check=True, capture_output=True)  # finish (or confirm) the run
        _check_catalog(out, ref)
    print(f"simulate: {TRIALS} trials, {complete} complete after the two writers")


def _finish(cmd, tries=10):
    """Rerun until done: a worker of a killed sweep holds its point's lock until it exits."""
    for _ in range(tries):
        res = subprocess.run(cmd, capture_output=True, text=True)
        if res.returncode == 0:
            return
        assert "OutputLockedError" in res.stderr, res.stderr
        time.sleep(0.5)
    raise AssertionError(res.stderr)


def test_two_sweeps_on_one_folder(tmp_path):
    cfg = tmp_path / "s.toml"
    cfg.write_text(SWEEP)
    refs = sweep(cfg, out=tmp_path / "ref", workers=1, progress=False)
    ref = {p: read_catalog(tmp_path / "ref" / p).events for p in refs["part"]}
    rnd = random.Random(2)
    for trial in range(TRIALS):
        out = tmp_path / f"c{trial}"
        cmd = [*PY, "sweep", str(cfg), "--out", str(out), "--workers", "2", "--quiet"]
        kill = rnd.uniform(0.5, 3.0) if trial % 3 == 2 else None
        _two(cmd, rnd.uniform(0.0, 2.0), kill)
        table = summarize(out)
        for part, status in zip(table["part"], table["status"], strict=True):
            if status == "done":
                _check_catalog(out / part, ref[part])
        _finish(cmd)
        for part in ref:
            _check_catalog(out / part, ref[part])
    print(f"sweep: {TRIALS} trials")
