"""Ctrl-C and SIGTERM stop a run inside a slip event; the simulator keeps a true state.

The kernel runs in a worker thread and stops at the end of a step once asked to
(``faultnet.solver.kernel_calls``); the event under way is undone, so a simulator interrupted
at any moment goes on with the events of an uninterrupted run, bit for bit.
"""

import _thread
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import faultnet
from faultnet.solver._kernels.layout import CTRL_STOP
from faultnet.solver.kernel_calls import KernelWorker

g = faultnet.graphs
MODELS = {
    "interpolated": lambda: faultnet.CarlsonLanger(g.ring(300), k=16, sigma=0.01, alpha=1.0),
    "exact": lambda: faultnet.CarlsonLanger(g.ring(300), k=16, sigma=0.01, alpha=2.5),
    "eta": lambda: faultnet.CarlsonLanger(g.square_lattice(12, 12), k=8, alpha=1.0, eta=0.1),
    "nu": lambda: faultnet.CarlsonLanger(g.ring(100), k=16, sigma=0.01, alpha=1.0, nu=1e-3),
}
COLUMNS = ["event", "t", "duration", "S", "n_blocks", "hypocenter", "n_steps"]


def _columns(result):
    return result.events[COLUMNS].to_numpy(dtype=float)


class _InThisThread:
    """A worker that runs the kernel at once, in the calling thread, flag untouched."""

    def call(self, run):
        return run(), None


@pytest.mark.parametrize("name", sorted(MODELS))
def test_ctrl_c_at_any_moment_leaves_the_events_of_an_uninterrupted_run(name):
    model = MODELS[name]()
    sim = faultnet.Simulator(model, rng=3)
    sim.advance(1, progress=False)  # compiled or loaded before the clock starts
    for delay in (0.01, 0.03, 0.05):
        threading.Timer(delay, _thread.interrupt_main).start()
        t0 = time.perf_counter()
        with pytest.raises(KeyboardInterrupt):
            while True:
                sim.advance(10**5, progress=False)
        assert time.perf_counter() - t0 < delay + 1.0
    done = sim.state.n_events
    rest = _columns(sim.advance(300, progress=False))
    ref = _columns(faultnet.Simulator(model, rng=3).advance(done + 300, progress=False))
    np.testing.assert_array_equal(rest, ref[done:])


@pytest.mark.parametrize("name", sorted(MODELS))
def test_a_stop_inside_an_event_undoes_it(name):
    """The flag set from another thread while the kernel runs in this one: the event under way
    is undone at once, and the state is that of the uninterrupted run after the events before
    it; the next call runs the event again."""
    model = MODELS[name]()
    n = 1500
    ref = _columns(faultnet.Simulator(model, rng=3).advance(n, progress=False))
    rng = np.random.default_rng(5)
    stopped = 0
    for _ in range(4):
        sim = faultnet.Simulator(model, rng=3)
        sim.advance(int(rng.integers(1, 300)), progress=False)
        arrays = sim._arrays
        worker, arrays.worker = arrays.worker, _InThisThread()
        timer = threading.Timer(rng.uniform(0.0, 0.01), arrays.ctrl.__setitem__, (CTRL_STOP, 1.0))
        timer.start()
        k = sim.state.n_events
        status, _ = arrays.call(n - k, k, np.zeros((n, 3)), np.zeros((n, 4), dtype=np.int64), 0)
        timer.join()
        arrays.ctrl[CTRL_STOP] = 0.0
        arrays.worker = worker
        stopped += status == faultnet.solver._kernels.STATUS_INTERRUPTED
        done = sim.state.n_events
        fresh = faultnet.Simulator(model, rng=3)
        fresh.advance(done, progress=False)
        np.testing.assert_array_equal(sim.state.x, fresh.state.x)
        rest = _columns(sim.advance(n - done, progress=False))
        np.testing.assert_array_equal(rest, ref[done:])
    assert stopped > 0


def test_the_worker_hands_back_errors_and_runs_calls_in_order():
    ctrl = np.zeros(8)
    worker = KernelWorker(ctrl)
    assert worker.call(lambda: 7) == (7, None)
    with pytest.raises(ZeroDivisionError):
        worker.call(lambda: 1 / 0)
    seen = []
    assert [worker.call(lambda i=i: seen.append(i) or i)[0] for i in range(5)] == list(range(5))
    assert seen == list(range(5))


def test_sigterm_stops_the_command_inside_a_never_ending_event(tmp_path):
    """A plate this fast during events fails blocks faster than they stick: the first event
    never ends.  SIGTERM still stops the command within a step, with its one line."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "faultnet", "simulate", "ring:2000", "--nu", "0.05"]
        + ["--events", "10", "--seed", "1", "--no-progress", "--out", str(tmp_path / "r.parquet")],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=tmp_path,
    )
    time.sleep(3.0)  # loaded (or compiled: the stop then waits for the compiler)
    t0 = time.perf_counter()
    proc.send_signal(signal.SIGTERM)
    try:
        _, err = proc.communicate(timeout=300)
    finally:
        proc.kill()
    assert proc.returncode == 130, err
    assert "interrupted" in err and "Traceback" not in err, err
    assert time.perf_counter() - t0 < 300
    if os.environ.get("CI") is None:  # a warm kernel cache: within a few steps
        assert time.perf_counter() - t0 < 30
