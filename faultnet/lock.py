"""Exclusive locks on outputs: one writer per catalog and per sweep folder.

A lock is a small JSON file created with ``O_CREAT | O_EXCL`` (atomic on
local and network file systems) holding the holder's pid, host, process
start time and command.  A second writer finds the file and is refused with
:class:`~faultnet.exceptions.OutputLockedError` naming the holder.  A lock
left by a killed process is *stale* and is taken over: on the same host when
its pid is no longer alive, or when the pid now belongs to another process
(its start time in ``/proc/<pid>/stat`` differs).  A lock held on another
host cannot be checked from here; the message says which host and process
hold it, so a user who knows it is gone can delete the file.

The lock is released when the ``with`` block ends, also on an exception or
``KeyboardInterrupt``.

>>> import tempfile, os
>>> path = os.path.join(tempfile.mkdtemp(), "out.parquet.lock")
>>> with output_lock(path):
...     holder = read_holder(path)
...     holder["pid"] == os.getpid()
True
>>> os.path.exists(path)
False
"""

from __future__ import annotations

import contextlib
import json
import os
import socket
import sys
import time

from faultnet.exceptions import OutputLockedError

__all__ = ["LOCK_SUFFIX", "holder_text", "is_stale", "output_lock", "read_holder"]

LOCK_SUFFIX = ".lock"
#: a break file (taking over a stale lock) older than this is itself left over
_BREAK_STALE_S = 30.0


def _start_ticks(pid):
    """Start time of process ``pid`` in clock ticks after boot (None where unknown)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as fh:
            text = fh.read()
    except OSError:
        return None
    # the command name (field 2) may hold spaces and parentheses: split after the last ')'
    fields = text[text.rfind(")") + 2 :].split()
    try:
        return int(fields[19])  # field 22 of the whole line
    except (IndexError, ValueError):
        return None


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    except OSError:
        return False
    return True


def _me():
    return {
        "pid": os.getpid(),
        "host": socket.gethostname(),
        "start_ticks": _start_ticks(os.getpid()),
        "started": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "command": " ".join(sys.argv) or sys.executable,
    }


def read_holder(path) -> dict | None:
    """The holder recorded in lock file ``path`` (None if absent; {} if unreadable)."""
    try:
        with open(path, encoding="utf-8") as fh:
            data = json.load(fh)
    except FileNotFoundError:
        return None
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def is_stale(holder) -> bool:
    """True if the process that wrote ``holder`` is gone (checkable on this host only)."""
    if not holder:
        return False  # being written right now, or garbled: not provably stale
    if holder.get("host") != socket.gethostname():
        return False
    pid = holder.get("pid")
    if not isinstance(pid, int) or pid <= 0:
        return False
    if not _alive(pid):
        return True
    start = holder.get("start_ticks")
    now = _start_ticks(pid)
    return start is not None and now is not None and now != start


def holder_text(holder) -> str:
    """One line naming the holder of a lock."""
    if not holder:
        return "a process that is writing it (the lock file is being written or is garbled)"
    return (
        f"pid {holder.get('pid')} on {holder.get('host')} since {holder.get('started')} "
        f"({holder.get('command')})"
    )


def _try_create(path, me):
    try:
        fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
    except FileExistsError:
        return False
    with os.fdopen(fd, "w", encoding="utf-8") as fh:
        json.dump(me, fh)
        fh.flush()
        os.fsync(fh.fileno())
    return True


def _break_stale(path, holder):
    """Remove the stale lock ``path`` if no other process is breaking it; True if removed."""
    brk = path + ".break"
    try:
        fd = os.open(brk, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
    except FileExistsError:
        with contextlib.suppress(OSError):
            if time.time() - os.path.getmtime(brk) > _BREAK_STALE_S:
                os.remove(brk)
        return False
    os.close(fd)
    try:
        if read_holder(path) == holder:  # still the same stale lock, not a fresh one
            os.remove(path)
            return True
        return False
    finally:
        with contextlib.suppress(OSError):
            os.remove(brk)


def acquire(path, what=None):
    """Create lock file ``path`` or raise :class:`OutputLockedError`; return the holder dict."""
    me = _me()
    for _ in range(20):
        if _try_create(path, me):
            return me
        holder = read_holder(path)
        if holder is None:
            continue  # released meanwhile: try again
        if holder == {}:
            time.sleep(0.05)  # its writer is between create and write
            holder = read_holder(path)
            if holder is None:
                continue
        if is_stale(holder):
            _break_stale(path, holder)
            continue
        raise OutputLockedError(
            f"{what or path} is being written by {holder_text(holder)}; wait for it to "
            f"finish or stop it (if that process is gone, delete {path})"
        )
    raise OutputLockedError(f"could not take the lock {path}: other writers keep taking it")


def release(path, me):
    """Remove lock file ``path`` if it still is ``me``'s."""
    holder = read_holder(path)
    if (
        holder is not None
        and holder.get("pid") == me["pid"]
        and holder.get("start_ticks") == me.get("start_ticks")
    ):
        with contextlib.suppress(OSError):
            os.remove(path)


@contextlib.contextmanager
def output_lock(path, what=None):
    """Hold the exclusive lock file ``path`` for the ``with`` block (see module doc)."""
    path = os.fspath(path)
    me = acquire(path, what)
    try:
        yield me
    finally:
        release(path, me)
