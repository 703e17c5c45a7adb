"""Docstring examples of the public modules run as tests."""

import doctest
import importlib
import pkgutil

import pytest

import faultnet

#: every module of the package (``__main__`` would run the command line)
MODULES = sorted(
    ["faultnet"]
    + [
        m.name
        for m in pkgutil.walk_packages(faultnet.__path__, "faultnet.")
        if not m.name.endswith("__main__")
    ]
)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0
