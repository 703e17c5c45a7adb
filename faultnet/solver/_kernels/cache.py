"""One on-disk cache stamp for all kernels: their sources together, not each file alone.

Numba keeps a compiled kernel in its cache under a stamp of the kernel's own source file, and
reuses it while that stamp matches.  But a kernel's compiled code contains every kernel it
calls, from other files: after a change to ``dopri.py`` alone (an upgrade, a ``git pull``
into an editable install, a contributor's edit), Numba would go on loading the entry kernels
of ``events.py`` with the old step inside, and runs would silently use it.  Here the stamp of
every kernel in this package is the SHA-256 of all its ``.py`` sources (this folder and the
folders below it), so that a change to any kernel recompiles them all, and a reinstall of the
same sources recompiles none.

The stamp comes from a cache locator (a subclass of Numba's locator class, the mechanism its
``NUMBA_CACHE_LOCATOR_CLASSES`` setting also uses) put first in Numba's list of locators.  It
answers only for files in the registered directories and otherwise leaves the choice to
Numba's own locators, so other code's caches are untouched; where it answers, the cache
directory and file names are those Numba's locator would have chosen.  Where Numba's caching
module lacks these names, :func:`register` warns and the kernels keep Numba's per-file stamp.

Every cache file is sealed with the SHA-256 of its contents when it is written, and checked
before it is read (:class:`VerifiedCacheFile`, put on each cached kernel by :func:`verified`).
Numba itself reads its files unchecked: an emptied or truncated file raised EOFError on every
run, and one changed byte of machine code ran, silently giving wrong catalogs.  A file whose
seal does not match is discarded with one line (a :class:`KernelCacheWarning`) and the kernel
is compiled again and cached anew.  Where no cache folder is writable (a shared install whose
``HOME`` and ``NUMBA_CACHE_DIR`` are read-only), :func:`disk_cache_available` is False and the
kernels compile in memory, once per process, after one line that says how to keep them.

This is the only faultnet module that uses Numba's private names: ``numba.core.caching`` (its
locator classes and list, ``IndexDataCacheFile``) and a dispatcher's ``_cache``.
"""

import functools
import hashlib
import io
import os
import pickle
import warnings

from numba.core import caching

__all__ = [
    "KernelCacheWarning",
    "SourcesLocator",
    "VerifiedCacheFile",
    "disk_cache_available",
    "is_cold",
    "register",
    "sources_stamp",
    "verified",
]

#: this package's directory: the kernels' sources, in it and in the folders below it
KERNELS_DIR = os.path.dirname(os.path.abspath(__file__))
#: Numba's locator base class and the class holding its list of locators (their names vary
#: between Numba versions)
_LOCATOR_BASE = getattr(caching, "CacheLocator", None) or getattr(caching, "_CacheLocator", object)
_IMPL = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
#: the first bytes of a sealed cache file; the SHA-256 of the rest follows
SEAL = b"faultnet-sealed-cache-1\n"
_DIGEST = hashlib.sha256().digest_size


class KernelCacheWarning(RuntimeWarning):
    """The kernels' disk cache is damaged or cannot be written: the kernels are recompiled."""


def _say(message):
    """One line on stderr (a warning with no source line under it), for a user to act on."""
    warnings.warn_explicit(f"{message}", KernelCacheWarning, "faultnet", 0)


def sources_stamp(directory):
    """SHA-256 (hex) of the paths and contents of the ``.py`` files under ``directory``, sorted."""
    digest = hashlib.sha256()
    names = []
    # os.walk skips a folder it cannot list: raise instead (OSError: the sources are not in a
    # readable folder, a zipped install), or the stamp would be a constant
    for root, dirs, files in os.walk(directory, onerror=_raise):
        dirs[:] = [d for d in dirs if not d.startswith((".", "__"))]
        rel = os.path.relpath(root, directory)
        names += [os.path.normpath(os.path.join(rel, f)) for f in files if f.endswith(".py")]
    for name in sorted(names):
        with open(os.path.join(directory, name), "rb") as fh:
            digest.update(name.encode() + b"\0" + fh.read() + b"\0")
    return digest.hexdigest()


def _raise(exc):
    raise exc


@functools.cache
def _stamp(directory):
    # with the import path: the cache pickles module names, which a moved folder changes
    return hashlib.sha256(f"{__package__}\0{sources_stamp(directory)}".encode()).hexdigest()


class SourcesLocator(_LOCATOR_BASE):
    """Numba's own locator for a function, with the stamp of all sources in its directory."""

    #: directories whose functions get the shared stamp (see :func:`register`)
    directories = set()

    def __init__(self, inner, stamp):
        self._inner = inner
        self._stamp = stamp

    def ensure_cache_path(self):
        self._inner.ensure_cache_path()

    def get_cache_path(self):
        return self._inner.get_cache_path()

    def get_source_stamp(self):
        return self._stamp

    def get_disambiguator(self):
        return self._inner.get_disambiguator()

    @classmethod
    def from_function(cls, py_func, py_file):
        directory = os.path.dirname(os.path.abspath(py_file))
        root = next((d for d in cls.directories if _inside(directory, d)), None)
        if root is None:
            return None
        try:
            stamp = _stamp(root)
        except OSError:  # sources not in a readable directory (a zipped install)
            return None
        for other in _IMPL._locator_classes:
            if other is not cls:
                inner = other.from_function(py_func, py_file)
                if inner is not None:
                    return cls(inner, stamp)
        return None


def _inside(directory, root):
    """True if ``directory`` is ``root`` or a folder below it."""
    return directory == root or directory.startswith(root + os.sep)


def register(directory=KERNELS_DIR):
    """Give every cached Numba function defined under ``directory`` the stamp of its sources.

    Call before the functions are decorated (Numba picks a function's locator then).
    Returns True if registered, False (with a warning) where Numba lacks the mechanism.
    """
    locators = getattr(_IMPL, "_locator_classes", None)
    if _LOCATOR_BASE is object or not isinstance(locators, list):
        warnings.warn(
            "faultnet could not give its kernels one cache stamp (this Numba's caching module "
            "has no list of cache locators): after changing or upgrading faultnet, delete the "
            "kernels' Numba cache (faultnet/solver/_kernels/**/__pycache__/*.nbi, *.nbc)",
            RuntimeWarning,
            stacklevel=2,
        )
        return False
    SourcesLocator.directories.add(os.path.abspath(directory))
    if SourcesLocator not in locators:
        locators.insert(0, SourcesLocator)
    return True


# --------------------------------------------------------------------------- sealed files


def seal(payload):
    """``payload`` preceded by :data:`SEAL` and its SHA-256."""
    return SEAL + hashlib.sha256(payload).digest() + payload


def unseal(blob):
    """The payload of a sealed ``blob``; ValueError if it is not sealed or does not match."""
    head = len(SEAL) + _DIGEST
    if len(blob) < head or not blob.startswith(SEAL):
        raise ValueError("not a sealed cache file (empty, truncated or foreign)")
    payload = blob[head:]
    if hashlib.sha256(payload).digest() != blob[len(SEAL) : head]:
        raise ValueError("its checksum does not match its contents")
    return payload


class DamagedCacheFile(OSError):
    """A cache file failed its check; Numba's loader treats an OSError as a missing entry."""


class VerifiedCacheFile(caching.IndexDataCacheFile):
    """Numba's index and data files of one kernel, sealed when written, checked when read."""

    #: the damaged files already reported in this process (one line each)
    reported = set()

    def _read(self, path):
        with open(path, "rb") as fh:
            blob = fh.read()
        try:
            return unseal(blob)
        except ValueError as exc:
            if path == self._index_path and _is_numba_index(blob):
                raise DamagedCacheFile("written by Numba itself (an older faultnet)") from None
            if path not in self.reported:
                self.reported.add(path)
                _say(f"discarded the damaged kernel cache file {path} ({exc}); recompiling")
            raise DamagedCacheFile(str(exc)) from None

    def _write(self, path, payload):
        with self._open_for_write(path) as fh:
            fh.write(seal(payload))

    def _load_index(self):
        try:
            payload = self._read(self._index_path)
        except (FileNotFoundError, DamagedCacheFile):
            return {}
        version, rest = _split_pickle(payload)
        if version != self._version:
            return {}
        try:
            stamp, overloads = pickle.loads(rest)
        except (ImportError, AttributeError):  # written by kernels under another import path
            return {}
        return overloads if stamp == self._source_stamp else {}

    def _save_index(self, overloads):
        payload = pickle.dumps(self._version, protocol=-1)
        self._write(self._index_path, payload + self._dump((self._source_stamp, overloads)))

    def _load_data(self, name):
        return pickle.loads(self._read(self._data_path(name)))

    def _save_data(self, name, data):
        self._write(self._data_path(name), self._dump(data))


def _is_numba_index(blob):
    """True if ``blob`` is an index as Numba itself writes it (a version string first)."""
    try:
        version, _ = _split_pickle(blob)
    except Exception:  # noqa: BLE001 - anything unreadable is not
        return False
    return isinstance(version, str)


def _split_pickle(payload):
    """The first pickled object of ``payload`` and the bytes after it."""
    stream = io.BytesIO(payload)
    first = pickle.load(stream)
    return first, stream.read()


def verified(dispatcher):
    """Give a cached kernel :class:`VerifiedCacheFile` files; return it (a plain function, as
    under ``NUMBA_DISABLE_JIT``, or an uncached kernel is returned as it is)."""
    impl = getattr(dispatcher, "_cache", None)
    old = getattr(impl, "_cache_file", None)
    if isinstance(old, caching.IndexDataCacheFile) and not isinstance(old, VerifiedCacheFile):
        new = VerifiedCacheFile.__new__(VerifiedCacheFile)
        new.__dict__.update(old.__dict__)
        impl._cache_file = new
    return dispatcher


def is_cold(dispatcher):
    """True if the disk cache holds nothing usable for ``dispatcher`` (any doubt: False)."""
    try:
        return not dispatcher._cache._cache_file._load_index()
    except Exception:  # noqa: BLE001 - no disk cache (or JIT is off): not cold
        return False


# --------------------------------------------------------------------------- no writable cache


def _probe():  # pragma: no cover - never called: its code object stands for a kernel
    pass


@functools.cache
def disk_cache_available(directory=KERNELS_DIR):
    """True if some cache locator can write the kernels' cache; else say how, once, and False.

    Numba raises "cannot cache function ...: no locator available" at the first cached
    decoration where no folder is writable: the kernels are then compiled without
    ``cache=True``.
    """
    py_file = os.path.join(directory, "carlson_langer", "events.py")
    for cls in _IMPL._locator_classes if _IMPL is not None else ():
        try:
            if cls.from_function(_probe, py_file) is not None:
                return True
        except Exception:  # noqa: BLE001, S112 - a locator that fails is not available
            continue
    where = os.environ.get("NUMBA_CACHE_DIR") or "~/.cache/numba"
    _say(
        f"no writable folder for the kernel cache ({where}, {os.path.dirname(py_file)}/"
        f"__pycache__): the "
        f"kernels compile on every run; set NUMBA_CACHE_DIR to a writable folder to keep them"
    )
    return False
