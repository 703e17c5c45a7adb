"""How a kernel call runs: in a worker thread that Ctrl-C and SIGTERM can stop, with Python's
garbage collector paused.

Python runs signal handlers in the main thread, between bytecodes: while the main thread is
inside a compiled kernel, Ctrl-C and the command line's SIGTERM wait for the kernel to
return, and one slip event can run for minutes (a plate moving fast during events, a large
lattice).  So a simulator's kernel calls run in a worker thread of its own (the kernels
release the GIL) while the calling thread waits.  A ``KeyboardInterrupt`` (or any exception a
signal handler raises) in the waiting thread sets ``ctrl[CTRL_STOP]``: the kernel undoes the
event under way at the end of its current step and returns ``STATUS_INTERRUPTED``, every event
before it complete; the caller raises the exception again once the kernel has returned.

The worker runs one call at a time, in order, and clears the flag before each under a lock
that the waiting thread also takes to set it; a call interrupted before the worker took it is
not run at all.  So whatever instant an interruption hits, the arrays are never used by two
calls at once, and the caller never leaves while a kernel runs.  A call costs the worker's
hand-over, about 60 µs; the engine's calls run for 0.1-0.5 s.
"""

from __future__ import annotations

import contextlib
import gc
import os
import queue
import threading
import weakref

from faultnet.solver._kernels.layout import CTRL_STOP

__all__ = ["KernelWorker", "collector_paused"]

#: how often the waiting thread lets Python run signal handlers (seconds)
_POLL = 0.05


@contextlib.contextmanager
def collector_paused():
    """Python's cyclic garbage collector paused for one kernel call.

    A running kernel creates no Python objects, so the pause costs nothing then.  The first
    call of a kernel in a process compiles it, and Numba's compiler creates and drops
    millions of objects: the collector's 1,800 passes over them took 1.5-1.8 s of a
    17-19 s cold compile (and the garbage left, about 125 MB, is collected afterwards in
    about 0.6 s).  The collector is left as it was found: a caller that disabled it keeps
    it disabled.
    """
    if not gc.isenabled():
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


class _Call:
    """One kernel call handed to the worker."""

    def __init__(self, run):
        self.run = run
        self.taken = self.cancelled = False
        self.result = self.error = None
        self.done = threading.Event()


def _serve(calls, lock, ctrl):
    """The worker's loop: run each call once, in order, until ``None`` arrives."""
    while (call := calls.get()) is not None:
        if call.taken:  # handed over twice (an interruption hit the hand-over)
            continue
        call.taken = True
        with lock:
            run = not call.cancelled
            if run:
                ctrl[CTRL_STOP] = 0.0
        if run:
            try:
                call.result = call.run()
            except BaseException as exc:  # handed to the waiting thread
                call.error = exc
        call.done.set()


class KernelWorker:
    """The worker thread that runs one simulator's kernel calls (module text).

    Parameters
    ----------
    ctrl : numpy.ndarray
        The simulator's control array, the one its kernels read ``CTRL_STOP`` from.
    """

    def __init__(self, ctrl):
        self._ctrl = ctrl
        self._lock = threading.Lock()
        self._pid = None
        self._calls = None

    def _start(self):
        # (again in a forked child: the parent's worker thread does not exist there)
        self._calls, self._pid = queue.SimpleQueue(), os.getpid()
        threading.Thread(
            target=_serve,
            args=(self._calls, self._lock, self._ctrl),
            name="faultnet-kernel",
            daemon=True,
        ).start()
        weakref.finalize(self, self._calls.put, None)  # the thread ends with its simulator

    def call(self, run):
        """``run()`` in the worker; returns (its result, the interruption or None).

        ``run`` calls a kernel that returns at the end of a step once ``ctrl[CTRL_STOP]`` is
        set, and does whatever must not be cut short by a signal (counting what the kernel
        did).  The interruption is the exception raised in the calling thread while it waited
        (``KeyboardInterrupt``, the command line's SIGTERM), for the caller to raise again;
        the result is None where the call was interrupted before it started.
        """
        if self._pid != os.getpid():
            self._start()
        call = _Call(run)
        with collector_paused():
            interruption = self._wait(call)
        if call.error is not None:
            raise call.error
        return call.result, interruption

    def _wait(self, call):
        """Hand ``call`` to the worker and wait until it is done; returns the interruption."""
        interruption = None
        handed = False
        while not call.done.is_set():
            try:
                if not handed:
                    self._calls.put(call)
                    handed = True
                call.done.wait(_POLL)
            except BaseException as exc:  # the first one counts; the kernel is asked to stop
                interruption = interruption or exc
                with self._lock:
                    call.cancelled = True
                    self._ctrl[CTRL_STOP] = 1.0
        return interruption
