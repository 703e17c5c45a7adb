"""Shared fixtures: the slow reference oracle lives in tests/reference.py."""

import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(__file__))


@pytest.fixture
def one_line(capsys):
    """A reader of the one line a command printed on stderr (never a traceback)."""

    def read():
        err = capsys.readouterr().err.strip()
        assert "Traceback" not in err
        assert len(err.splitlines()) == 1, err
        return err

    return read


def pytest_collection_modifyitems(config, items):
    """Tests marked slow run only when asked for (``-m slow``)."""
    if "slow" in (config.getoption("-m") or ""):
        return
    skip = pytest.mark.skip(reason="slow: run with -m slow")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)
