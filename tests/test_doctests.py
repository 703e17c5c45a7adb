"""Docstring examples run as tests, one test per module that has examples."""

import doctest
import importlib
import importlib.util
import pkgutil
from pathlib import Path

import pytest

import faultnet


def _has_examples(name):
    """True if the module's source holds a ``>>>`` example (read, not imported)."""
    return ">>>" in Path(importlib.util.find_spec(name).origin).read_text(encoding="utf-8")


#: the modules with examples (``__main__`` would run the command line)
MODULES = sorted(
    name
    for name in ["faultnet"]
    + [m.name for m in pkgutil.walk_packages(faultnet.__path__, "faultnet.")]
    if not name.endswith("__main__") and _has_examples(name)
)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0
