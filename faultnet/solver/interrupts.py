"""Ctrl-C and SIGTERM inside a kernel call: the signal wake-up descriptor and a watcher thread.

Python runs signal handlers in the main thread, between bytecodes: while the main thread is
inside a compiled kernel, Ctrl-C and the command line's SIGTERM wait for the kernel to return,
and one slip event can run for minutes (a plate moving fast during events, a large lattice).
The operating system's signal still reaches Python's C-level handler at once, and that handler
writes the signal's number to the descriptor set with :func:`signal.set_wakeup_fd`.

So for the length of a kernel call from the main thread, :func:`stoppable` sets that
descriptor to one end of a socket pair whose other end a watcher thread reads.  For SIGINT or
SIGTERM the watcher sets ``ctrl[CTRL_STOP]`` of the call: the kernel undoes the event under way
at the end of its current step and returns ``STATUS_INTERRUPTED``, every event before it
complete.  Python's own handler then runs as soon as the kernel has returned
(``KeyboardInterrupt``, the command line's SIGTERM handler).  Where that handler does not raise,
the caller runs the undone event again.

The kernel keeps running in the calling thread (a worker thread per simulator, which the
waiting thread would ask to stop, cost 6-23% events/s: ``benchmarks/README.md``); a call here
costs two :func:`signal.set_wakeup_fd` calls.  The descriptor found at the start of a call (an
asyncio event loop's, for instance) is set again at its end, and the watcher passes on to it
every byte it reads meanwhile.  Outside the main thread, and where the descriptor cannot be
set, a call runs as before: signals wait for it to return.  The socket pair is closed at exit,
and a forked child closes its copies of its parent's pair at its first call.
"""

from __future__ import annotations

import atexit
import contextlib
import os
import signal
import socket
import threading

from faultnet.solver._kernels.layout import CTRL_STOP

__all__ = ["STOPPING_SIGNALS", "stoppable"]

#: the signals that stop a kernel call (their Python handlers run once it has returned)
STOPPING_SIGNALS = frozenset({signal.SIGINT, signal.SIGTERM})

_lock = threading.Lock()
#: the control arrays of the calls under way, by id
_running = {}
#: this process's watcher: its pid, thread and socket pair, the descriptor to pass bytes on to
_watcher = {"pid": None, "thread": None, "read": None, "write": None, "previous": -1}


def _watch(read):
    """The watcher's loop: on a stopping signal, set the stop flag of every call under way."""
    while True:
        try:
            data = read.recv(256)
        except OSError:
            data = b""
        if not data:  # the write end closed (at exit)
            read.close()
            return
        if any(b in STOPPING_SIGNALS for b in data):
            with _lock:
                for ctrl in _running.values():
                    ctrl[CTRL_STOP] = 1.0
        previous = _watcher["previous"]
        if previous != -1:
            with contextlib.suppress(OSError):
                os.write(previous, data)


def _descriptor():
    """The write end of this process's socket pair, its watcher started on first use (again in
    a forked child, where the parent's thread does not run)."""
    if _watcher["pid"] != os.getpid():
        if _watcher["pid"] is None:
            atexit.register(_close)
        for inherited in (_watcher["read"], _watcher["write"]):  # a forked child's copies
            if inherited is not None:
                inherited.close()
        read, write = socket.socketpair()
        write.setblocking(False)
        thread = threading.Thread(target=_watch, args=(read,), name="faultnet-signals", daemon=True)
        thread.start()
        _watcher.update(pid=os.getpid(), thread=thread, read=read, write=write, previous=-1)
    return _watcher["write"].fileno()


def _close():
    """At exit: the write end closed, so that the watcher reads the end and closes its own."""
    if _watcher["pid"] == os.getpid():
        _watcher["write"].close()
        _watcher["thread"].join(timeout=1.0)


@contextlib.contextmanager
def stoppable(ctrl):
    """A kernel call that SIGINT and SIGTERM stop at the end of a step (``ctrl[CTRL_STOP]``).

    The flag is cleared first.  In a thread other than the main one the call is left as it is.

    Examples
    --------
    >>> import numpy as np
    >>> from faultnet.solver._kernels.layout import CTRL_SIZE, CTRL_STOP
    >>> ctrl = np.ones(CTRL_SIZE)
    >>> with stoppable(ctrl):
    ...     float(ctrl[CTRL_STOP])  # a kernel reads the flag after each step
    0.0
    """
    ctrl[CTRL_STOP] = 0.0
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    ours = _descriptor()
    try:
        previous = signal.set_wakeup_fd(ours, warn_on_full_buffer=False)
    except (ValueError, OSError):  # an embedded interpreter without signals, for instance
        yield
        return
    # (kept after the call: the watcher may pass on a byte of the call's last moments)
    _watcher["previous"] = -1 if previous == ours else previous
    with _lock:
        _running[id(ctrl)] = ctrl
    try:
        yield
    finally:
        with _lock:
            _running.pop(id(ctrl), None)
        signal.set_wakeup_fd(_watcher["previous"])
