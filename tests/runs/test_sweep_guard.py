"""A sweep folder has one writer; its workers die with it; SIGTERM stops it as Ctrl-C does."""

import glob
import os
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest

from faultnet.__main__ import main
from faultnet.exceptions import OutputLockedError, SweepError
from faultnet.io.lock import alive, read_holder
from faultnet.io.parquet import read_catalog
from faultnet.runs.sweep.driver import summarize, sweep

PY = [sys.executable, "-m", "faultnet"]
LONG = """[sweep]
graph = "ring:400"
alpha = [1.0, 1.5, 2.0, 2.5]
events = 2000000
seed = 1
chunk = 2000
checkpoint_interval = 0.2
"""


def _start(tmp_path, workers):
    cfg = tmp_path / "s.toml"
    cfg.write_text(LONG)
    out = tmp_path / "c"
    proc = subprocess.Popen(
        [*PY, "sweep", str(cfg), "--out", str(out), "--workers", str(workers), "--quiet"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # signals reach only the process the test names
    )
    return proc, cfg, out


def _wait_for(pattern, proc, n=1, timeout=60):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        found = glob.glob(pattern)
        if len(found) >= n:
            return found
        if proc.poll() is not None:
            raise AssertionError(proc.communicate())
        time.sleep(0.05)
    raise AssertionError(f"no {pattern} after {timeout} s")


def _worker_pids(out, proc):
    locks = _wait_for(os.path.join(out, "part-*.parquet.lock"), proc, n=2)
    pids = set()
    for path in locks:
        holder = read_holder(path) or {}
        if isinstance(holder.get("pid"), int) and holder["pid"] != proc.pid:
            pids.add(holder["pid"])
    assert pids, locks
    return pids


def _all_gone(pids, timeout=10):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        if not any(alive(p) for p in pids):
            return True
        time.sleep(0.05)
    return False


def _zombie(pid):
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] == "Z"
    except OSError:
        return True


def _stop(proc):
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGKILL)
    proc.communicate()


def test_second_sweep_on_a_folder_is_refused_naming_the_first(tmp_path):
    proc, cfg, out = _start(tmp_path, workers=1)
    try:
        _wait_for(os.path.join(out, "sweep.lock"), proc)
        with pytest.raises(OutputLockedError, match=rf"sweep folder .* pid {proc.pid} .*sweep"):
            sweep(cfg, out=out, workers=1, progress=False)
    finally:
        _stop(proc)


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_workers_exit_when_the_sweep_process_dies_or_is_terminated(tmp_path, sig):
    proc, cfg, out = _start(tmp_path, workers=2)
    try:
        pids = _worker_pids(out, proc)
        os.kill(proc.pid, sig)
        rc = proc.wait(timeout=30)
        assert _all_gone(pids), f"workers {pids} still alive"
        if sig == signal.SIGTERM:  # shut down as Ctrl-C does: one line, 130, lock released
            err = proc.stderr.read()
            assert rc == 130 and "interrupted" in err and "Traceback" not in err, err
            assert not os.path.exists(os.path.join(out, "sweep.lock"))
    finally:
        _stop(proc)


@pytest.mark.parametrize("text", ["{not json", "[1, 2]", '{"config": 3}'])
def test_garbled_manifest_gives_one_line(tmp_path, capsys, text):
    out = tmp_path / "c"
    sweep(out=out, graph="ring:30", alpha=[1.0], events=200, seed=1, workers=1, progress=False)
    (out / "sweep.json").write_text(text)
    assert main(["summarize", str(out)]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert "sweep.json" in err and "--force" in err


KILLABLE = """[sweep]
graph = "ring:100"
alpha = [1.0, 1.5, 2.0]
events = 60000
replicas = 2
seed = 3
chunk = 1000
checkpoint_interval = 0
"""


def test_a_killed_worker_fails_no_point(tmp_path):
    """SIGKILL one pool worker (as the OOM killer would): every point still runs to the end."""
    cfg = tmp_path / "s.toml"
    cfg.write_text(KILLABLE)
    out = tmp_path / "c"
    proc = subprocess.Popen(
        [*PY, "sweep", str(cfg), "--out", str(out), "--workers", "2", "--quiet"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        victim = min(_worker_pids(out, proc))
        os.kill(victim, signal.SIGKILL)
        stdout, stderr = proc.communicate(timeout=600)
        assert proc.returncode == 0, stderr
    finally:
        _stop(proc)
    table = summarize(out)
    assert list(table["status"]) == ["done"] * 6, table
    # the lost points resumed their checkpoints: each catalog equals a clean one
    clean = tmp_path / "clean"
    sweep(cfg, out=clean, workers=1, progress=False)
    for name in sorted(os.listdir(clean)):
        if name.startswith("part-"):
            pd.testing.assert_frame_equal(
                read_catalog(out / name).events, read_catalog(clean / name).events
            )


def test_a_point_that_keeps_killing_its_worker_fails_alone(tmp_path, monkeypatch):
    """Lost points run again on a fresh pool; one lost MAX_LOSSES times fails, the rest run."""
    import concurrent.futures as cf
    from concurrent.futures.process import BrokenProcessPool

    from faultnet.runs.sweep import driver as sweep_module

    class Doomed(cf.Executor):  # point 1 always dies with its worker
        def submit(self, fn, point, *args):
            fut = cf.Future()
            if point["index"] == 1:
                fut.set_exception(BrokenProcessPool("terminated abruptly"))
            else:
                fut.set_result(fn(point, *args))
            return fut

    pools = []

    def renew():
        pools.append(Doomed())
        return pools[-1]

    monkeypatch.setattr(sweep_module, "_executor", lambda *a: _fixed((Doomed(), "test", renew)))
    with pytest.raises(SweepError, match=r"1 of 3 points failed: point 1 .*worker process died"):
        sweep(graph="ring:30", alpha=[1.0, 1.5, 2.0], events=200, seed=1, out=tmp_path / "c")
    assert len(pools) == sweep_module.MAX_LOSSES - 1
    assert list(summarize(tmp_path / "c")["status"]) == ["done", "missing", "done"]


def _fixed(value):
    import contextlib

    @contextlib.contextmanager
    def cm():
        yield value

    return cm()
