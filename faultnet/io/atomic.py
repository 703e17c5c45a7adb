"""Atomic file writes: a reader sees either no file or a complete one.

A file is written to a temporary name in the same folder, flushed to disk
(``fsync``), then renamed over the target (``os.replace``), and the folder is
synced.  Whenever the writer is killed, the target is either absent, as it
was, or complete.  Temporary names start with a dot and hold ``.tmp-``, so
:func:`is_tmp_name` recognises the leftovers of a killed writer.

>>> import tempfile, os
>>> p = os.path.join(tempfile.mkdtemp(), "x.json")
>>> atomic_write_json(p, {"a": 1})
>>> open(p).read()
'{\\n  "a": 1\\n}\\n'
"""

from __future__ import annotations

import contextlib
import json
import os
import secrets

import numpy as np

from faultnet.exceptions import OutputExistsError

__all__ = [
    "atomic_path",
    "atomic_write_bytes",
    "atomic_write_json",
    "fsync_dir",
    "fsync_file",
    "is_tmp_name",
    "json_default",
    "tmp_name",
]

_TMP_MARK = ".tmp-"


def fsync_dir(path):
    """Flush a folder's entries (new names, renames) to disk; a no-op where unsupported."""
    try:
        fd = os.open(path or ".", os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def fsync_file(path):
    """Flush a file's contents to disk."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def tmp_name(path):
    """A unique temporary name next to ``path`` (hidden, recognisable by ``.tmp-``)."""
    folder, name = os.path.split(os.fspath(path))
    return os.path.join(folder, f".{name}{_TMP_MARK}{os.getpid()}-{secrets.token_hex(4)}")


def is_tmp_name(name):
    """True for names made by :func:`tmp_name` (leftovers of a killed writer)."""
    return name.startswith(".") and _TMP_MARK in name


@contextlib.contextmanager
def atomic_path(path, overwrite=True):
    """Yield a temporary path; on success move it onto ``path`` atomically.

    The temporary file is fsynced, renamed with ``os.replace`` and the folder
    fsynced.  Where ``path`` is a symbolic link, its target is replaced and the link
    kept.  On an exception the temporary file is removed and ``path`` is untouched.

    >>> import tempfile, os
    >>> p = os.path.join(tempfile.mkdtemp(), "x.txt")
    >>> with atomic_path(p) as tmp:
    ...     _ = open(tmp, "w").write("hello")
    >>> open(p).read()
    'hello'
    """
    path = os.fspath(path)
    if os.path.islink(path):  # replace the link's target, not the link
        path = os.path.realpath(path)
    if not overwrite and os.path.exists(path):
        raise OutputExistsError(f"{path} exists; refusing to overwrite it")
    tmp = tmp_name(path)
    try:
        yield tmp
        fsync_file(tmp)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        raise
    fsync_dir(os.path.dirname(path))


def atomic_write_bytes(path, data):
    """Write ``data`` to ``path`` atomically."""
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(data)


def atomic_write_json(path, obj):
    """Write ``obj`` as indented JSON to ``path`` atomically."""
    atomic_write_bytes(path, (json.dumps(obj, indent=2, default=json_default) + "\n").encode())


def json_default(obj):
    """JSON form of the numpy scalars, arrays and sets that metadata may hold."""
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.floating):
        return float(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (set, frozenset)):
        return sorted(obj)
    raise TypeError(f"metadata value {obj!r} ({type(obj).__name__}) is not JSON-serialisable")
