"""One on-disk cache stamp for all kernels: their sources together, not each file alone.

Numba keeps a compiled kernel in its cache under a stamp of the kernel's own source file, and
reuses it while that stamp matches.  But a kernel's compiled code contains every kernel it
calls, from other files: after a change to ``dopri.py`` alone (an upgrade, a ``git pull``
into an editable install, a contributor's edit), Numba would go on loading the entry kernels
of ``events.py`` with the old step inside, and runs would silently use it.  Here the stamp of
every kernel in this package is the SHA-256 of all its ``.py`` sources, so that a change to
any kernel recompiles them all, and a reinstall of the same sources recompiles none.

The stamp comes from a cache locator (a subclass of Numba's locator class, the mechanism its
``NUMBA_CACHE_LOCATOR_CLASSES`` setting also uses) put first in Numba's list of locators.  It
answers only for files in the registered directories and otherwise leaves the choice to
Numba's own locators, so other code's caches are untouched; where it answers, the cache
directory and file names are those Numba's locator would have chosen.  Where Numba's caching
module lacks these names, :func:`register` warns and the kernels keep Numba's per-file stamp.
"""

import functools
import hashlib
import os
import warnings

from numba.core import caching

__all__ = ["SourcesLocator", "register", "sources_stamp"]

#: this package's directory: the kernels' sources
KERNELS_DIR = os.path.dirname(os.path.abspath(__file__))
#: Numba's locator base class and the class holding its list of locators (their names vary
#: between Numba versions)
_LOCATOR_BASE = getattr(caching, "CacheLocator", None) or getattr(caching, "_CacheLocator", object)
_IMPL = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)


def sources_stamp(directory):
    """SHA-256 (hex) of the names and contents of the ``.py`` files in ``directory``, sorted."""
    digest = hashlib.sha256()
    for name in sorted(os.listdir(directory)):
        if name.endswith(".py"):
            with open(os.path.join(directory, name), "rb") as fh:
                digest.update(name.encode() + b"\0" + fh.read() + b"\0")
    return digest.hexdigest()


@functools.cache
def _stamp(directory):
    return sources_stamp(directory)


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
        if directory not in cls.directories:
            return None
        try:
            stamp = _stamp(directory)
        except OSError:  # sources not in a readable directory (a zipped install)
            return None
        for other in _IMPL._locator_classes:
            if other is not cls:
                inner = other.from_function(py_func, py_file)
                if inner is not None:
                    return cls(inner, stamp)
        return None


def register(directory=KERNELS_DIR):
    """Give every cached Numba function defined in ``directory`` the stamp of all its sources.

    Call before the functions are decorated (Numba picks a function's locator then).
    Returns True if registered, False (with a warning) where Numba lacks the mechanism.
    """
    locators = getattr(_IMPL, "_locator_classes", None)
    if _LOCATOR_BASE is object or not isinstance(locators, list):
        warnings.warn(
            "faultnet could not give its kernels one cache stamp (this Numba's caching module "
            "has no list of cache locators): after changing or upgrading faultnet, delete the "
            "kernels' Numba cache (faultnet/_kernels/__pycache__/*.nbi, *.nbc)",
            RuntimeWarning,
            stacklevel=2,
        )
        return False
    SourcesLocator.directories.add(os.path.abspath(directory))
    if SourcesLocator not in locators:
        locators.insert(0, SourcesLocator)
    return True
