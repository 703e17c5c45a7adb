"""faultnet uses Numba's public API only, except in the cache locator.

Public: ``njit`` and its documented options, ``numba.extending.overload``, ``numba.types``.
Private: ``numba.core``, ``numba.np``, ``numba._*`` and underscored attributes of Numba's
objects (a dispatcher's ``_cache``).  The one exception is
``faultnet/solver/_kernels/cache.py``, the
locator that stamps every kernel with one hash of all their sources, which needs Numba's
caching module (its fallback is tested in ``test_kernel_cache.py``).  Every module is parsed,
not imported.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2] / "faultnet"
EXCEPTION = ROOT / "solver" / "_kernels" / "cache.py"
#: submodules of numba that are not its public API
PRIVATE = ("numba.core", "numba.np", "numba._")
#: underscored attributes of Numba's objects that faultnet once read
NUMBA_PRIVATE_ATTRS = {
    "_cache",
    "_cache_file",
    "_locator_classes",
    "_compiler",
    "_library",
    "_get_compiled_object",
    "_load_index",
    "_dynfunc",
}


def _violations(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    numba_names = {"numba"}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == "numba":
                    numba_names.add(alias.asname or "numba")
                if alias.name.startswith(PRIVATE):
                    yield node.lineno, f"import {alias.name}"
        elif isinstance(node, ast.ImportFrom) and node.module:
            if node.module.startswith(PRIVATE):
                yield node.lineno, f"from {node.module} import ..."
            if node.module == "numba":
                for alias in node.names:
                    if alias.name in ("core", "np") or alias.name.startswith("_"):
                        yield node.lineno, f"from numba import {alias.name}"
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute):
            if node.attr in NUMBA_PRIVATE_ATTRS:
                yield node.lineno, f".{node.attr}"
            base = node.value
            if isinstance(base, ast.Name) and base.id in numba_names:
                private = node.attr.startswith("_") and not node.attr.endswith("__")
                if node.attr in ("core", "np") or private:
                    yield node.lineno, f"{base.id}.{node.attr}"


MODULES = sorted(p for p in ROOT.rglob("*.py") if p != EXCEPTION)


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(ROOT)))
def test_public_numba_api_only(path):
    assert list(_violations(path)) == []


def test_the_check_finds_private_use(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text(
        "import numba as nb\nfrom numba.core import types\nfrom numba import _helperlib\n"
        "x = nb.core.registry\ny = dispatcher._cache._cache_file\n"
    )
    found = sorted(what for _, what in _violations(bad))
    assert found == sorted(
        ["from numba.core import ...", "from numba import _helperlib", "nb.core", "._cache"]
        + ["._cache_file"]
    )


def test_the_exception_is_the_cache_locator():
    # the one module allowed Numba's private names is the cache locator, and it needs them
    assert "cache" in EXCEPTION.name
    assert list(_violations(EXCEPTION))
