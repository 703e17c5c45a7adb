"""Docstring examples of the public modules run as tests."""

import doctest
import importlib

import pytest

MODULES = [
    "faultnet",
    "faultnet.model",
    "faultnet.engine",
    "faultnet.options",
    "faultnet._validate",
    "faultnet.runner",
    "faultnet.spec_run",
    "faultnet.specs",
    "faultnet._spec_parser",
    "faultnet.sweep_config",
    "faultnet.atomic",
    "faultnet.summary",
    "faultnet.stats",
    "faultnet.dynamics",
]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0
