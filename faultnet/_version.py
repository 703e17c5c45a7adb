"""The installed faultnet version: the ground floor that every module may import.

Submodules import ``__version__`` from here, never from the package face
``faultnet/__init__.py``, so the import graph has no edge running back up.
"""

from importlib.metadata import PackageNotFoundError, version

__all__ = ["__version__"]

try:
    __version__ = version("faultnet")
except PackageNotFoundError:  # running from a source tree
    __version__ = "0+unknown"
