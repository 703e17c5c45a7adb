"""Exclusive locks on outputs: one writer per catalog and per sweep folder.

A lock is an advisory ``flock`` on a small file next to the output, held for as long as the
writer runs.  The operating system releases it when the writer's process ends in any way (a
return, an exception, SIGKILL, the OOM killer), so a killed run never blocks its own resume:
there is no pid to check and no stale lock to break.  A process that has been killed but not
yet reaped (a zombie) holds no lock either.  The file also holds the writer's pid, host, start
time and command, for the message only: a second writer is refused with
:class:`~faultnet.exceptions.OutputLockedError` naming the holder.  On Linux, ``flock`` on a
network file system (NFS) is carried over as a POSIX lock that other hosts see too.

Nothing a failed start leaves behind blocks the next run: a lock file that no process holds
(empty, garbled, or written by a process that is gone) is simply taken.  The file is removed
when the ``with`` block ends, also on an exception or ``KeyboardInterrupt``.

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
import fcntl
import json
import os
import socket
import sys
import time

from faultnet.exceptions import OutputLockedError

__all__ = ["LOCK_SUFFIX", "alive", "holder_text", "output_lock", "read_holder"]

LOCK_SUFFIX = ".lock"


def alive(pid) -> bool:
    """True if process ``pid`` runs on this host (a zombie, killed but not reaped, is dead)."""
    try:
        os.kill(pid, 0)
    except PermissionError:
        pass  # another user's process: it exists
    except (OSError, OverflowError, TypeError, ValueError):
        return False
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as fh:
            text = fh.read()
    except OSError:
        return True  # no /proc (not Linux): kill(pid, 0) is all we know
    # the command name (field 2) may hold spaces and parentheses: the state follows the last ')'
    return text[text.rfind(")") + 2 :][:1] not in ("Z", "X")


def _me():
    return {
        "pid": os.getpid(),
        "host": socket.gethostname(),
        "started": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "command": " ".join(sys.argv) or sys.executable,
    }


def _parse(raw):
    try:
        data = json.loads(raw.decode("utf-8"))
    except (UnicodeDecodeError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def read_holder(path) -> dict | None:
    """The holder recorded in lock file ``path`` (None if absent; {} if empty or unreadable)."""
    try:
        with open(path, "rb") as fh:
            return _parse(fh.read())
    except FileNotFoundError:
        return None
    except OSError:
        return {}


def holder_text(holder) -> str:
    """One line naming the holder of a lock."""
    if not holder:
        return "a process that is starting (its lock file is not written yet)"
    return (
        f"pid {holder.get('pid')} on {holder.get('host')} since {holder.get('started')} "
        f"({holder.get('command')})"
    )


def _open(path):
    """A descriptor of lock file ``path`` (created if absent); clear error if it cannot be."""
    try:
        return os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
    except OSError as exc:
        raise OutputLockedError(
            f"cannot open the lock file {path} ({exc.strerror or exc}); if it belongs to "
            f"another user or to a run that is gone, delete it or choose another output"
        ) from None


def _is_current(fd, path):
    """True if ``fd`` is still the file at ``path`` (a releasing writer may have removed it)."""
    try:
        here = os.stat(path)
    except FileNotFoundError:
        return False
    mine = os.fstat(fd)
    return (here.st_dev, here.st_ino) == (mine.st_dev, mine.st_ino)


def _write_holder(fd, path, me):
    """Record ``me`` in the locked file; on failure (a full disk) give the lock up, clearly."""
    try:
        os.ftruncate(fd, 0)
        os.pwrite(fd, json.dumps(me).encode("utf-8"), 0)
    except OSError as exc:
        _release(fd, path)
        raise OutputLockedError(
            f"cannot write the lock file {path} ({exc.strerror or exc}); free some space "
            f"or choose another output, then run again"
        ) from None


def acquire(path, what=None):
    """Lock ``path`` (see module doc) or raise :class:`OutputLockedError`; return its descriptor."""
    for _ in range(20):
        fd = _open(path)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            holder = _parse(os.pread(fd, 65536, 0))
            os.close(fd)
            raise OutputLockedError(
                f"{what or path} is being written by {holder_text(holder)}; wait for it to "
                f"finish or stop it"
            ) from None
        if _is_current(fd, path):
            _write_holder(fd, path, _me())
            return fd
        os.close(fd)  # the holder released and removed it meanwhile: take the new file
    raise OutputLockedError(f"could not take the lock {path}: other writers keep taking it")


def _release(fd, path):
    """Remove lock file ``path`` while still holding it, then let the lock go."""
    try:
        if _is_current(fd, path):
            with contextlib.suppress(OSError):
                os.remove(path)
    finally:
        os.close(fd)


@contextlib.contextmanager
def output_lock(path, what=None):
    """Hold the exclusive lock file ``path`` for the ``with`` block (see module doc)."""
    path = os.fspath(path)
    fd = acquire(path, what)
    try:
        yield fd
    finally:
        _release(fd, path)
