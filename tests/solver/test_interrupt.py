"""Ctrl-C and SIGTERM stop a run inside a slip event; the simulator keeps a true state.

A watcher thread hears the signal through the wake-up descriptor and the kernel stops at the
end of a step (``faultnet.solver.interrupts``); the event under way is undone, so a simulator
interrupted at any moment goes on with the events of an uninterrupted run, bit for bit.
"""

import os
import signal
import socket
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import faultnet
from faultnet.solver._kernels.layout import CTRL_SIZE, CTRL_STOP
from faultnet.solver.interrupts import stoppable

posix = pytest.mark.skipif(os.name != "posix", reason="signals sent with os.kill")

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


@posix
@pytest.mark.parametrize("name", sorted(MODELS))
def test_ctrl_c_at_any_moment_leaves_the_events_of_an_uninterrupted_run(name):
    model = MODELS[name]()
    sim = faultnet.Simulator(model, rng=3)
    sim.advance(1, progress=False)  # compiled or loaded before the clock starts
    for delay in (0.01, 0.03, 0.05):
        threading.Timer(delay, os.kill, (os.getpid(), signal.SIGINT)).start()
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
        stop = threading.Timer(rng.uniform(0.002, 0.01), arrays.ctrl.__setitem__, (CTRL_STOP, 1))
        stop.start()
        k = sim.state.n_events
        status = arrays.call(n - k, k, np.zeros((n, 3)), np.zeros((n, 4), dtype=np.int64), 0)
        stop.join()
        stopped += status == faultnet.solver._kernels.STATUS_INTERRUPTED
        done = sim.state.n_events
        fresh = faultnet.Simulator(model, rng=3)
        fresh.advance(done, progress=False)
        np.testing.assert_array_equal(sim.state.x, fresh.state.x)
        rest = _columns(sim.advance(n - done, progress=False))
        np.testing.assert_array_equal(rest, ref[done:])
    assert stopped > 0


@posix
def test_the_watcher_stops_a_call_on_sigterm_and_passes_every_signal_on():
    """SIGTERM sets the stop flag of the call under way, SIGUSR1 does not; both reach the
    wake-up descriptor found at the call's start, which is set again at its end."""
    heard = []
    handlers = {sig: signal.signal(sig, lambda s, f: heard.append(s))
                for sig in (signal.SIGTERM, signal.SIGUSR1)}  # fmt: skip
    read, write = socket.socketpair()
    write.setblocking(False)
    read.settimeout(5.0)
    before = signal.set_wakeup_fd(write.fileno())
    try:
        ctrl = np.ones(CTRL_SIZE)
        with stoppable(ctrl):
            assert ctrl[CTRL_STOP] == 0.0  # cleared as the call starts
            os.kill(os.getpid(), signal.SIGUSR1)
            assert read.recv(1) == bytes([signal.SIGUSR1])  # passed on
            assert ctrl[CTRL_STOP] == 0.0
            os.kill(os.getpid(), signal.SIGTERM)
            assert read.recv(1) == bytes([signal.SIGTERM])  # after the flag was set
            assert ctrl[CTRL_STOP] == 1.0
        assert signal.set_wakeup_fd(write.fileno()) == write.fileno()  # set again
        assert sorted(heard) == sorted([signal.SIGUSR1, signal.SIGTERM])
    finally:
        signal.set_wakeup_fd(before)
        for sig, handler in handlers.items():
            signal.signal(sig, handler)
        read.close()
        write.close()


def test_outside_the_main_thread_a_call_runs_as_before():
    ctrl, seen = np.ones(CTRL_SIZE), []

    def run():
        with stoppable(ctrl):
            seen.append(float(ctrl[CTRL_STOP]))

    thread = threading.Thread(target=run)
    thread.start()
    thread.join()
    assert seen == [0.0]


@posix
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


_SOCKETS = """
import os
import numpy as np
from faultnet.solver import interrupts
from faultnet.solver._kernels.layout import CTRL_SIZE

with interrupts.stoppable(np.ones(CTRL_SIZE)):
    pass
w = dict(interrupts._watcher)
if os.fork() == 0:  # a child's first call closes its copies of the parent's pair
    with interrupts.stoppable(np.ones(CTRL_SIZE)):
        pass
    os._exit(0 if w["read"].fileno() == w["write"].fileno() == -1 else 1)
assert os.wait()[1] == 0, "the child kept its parent's sockets"
interrupts._close()  # what runs at exit
w["thread"].join(2.0)
assert w["read"].fileno() == w["write"].fileno() == -1 and not w["thread"].is_alive()
print("closed")
"""


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")
def test_the_watchers_sockets_are_closed_at_exit_and_in_a_forked_child():
    out = subprocess.run(
        [sys.executable, "-W", "error::ResourceWarning", "-c", _SOCKETS],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "closed"
    assert "ResourceWarning" not in out.stderr
