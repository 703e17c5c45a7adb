"""The import graph: no submodule imports the package face, no cycles between modules.

Every faultnet module is parsed (not imported) and its imports read with
``ast``.  ``faultnet/__init__.py`` is the package face: it imports the
modules, so a module that imports a name from it (``from faultnet import
__version__``) runs back up the graph; names come from their own module
(``faultnet._version``, ``faultnet.exceptions`` ...).  Cycles count every
import: at module level, inside functions and under ``TYPE_CHECKING``, so that
a circle cannot hide behind an import deferred to call time.  The layers
between subpackages are the import-linter contract in ``pyproject.toml``
(checked by ``tests/test_lint.py``), which sees the same imports.
"""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent / "faultnet"


def _module_name(path):
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(p): p for p in sorted(ROOT.rglob("*.py"))}


def _walk(node, module_level):
    """Every node below ``node``; with ``module_level``, not those inside functions."""
    for child in ast.iter_child_nodes(node):
        if module_level and isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        yield child
        yield from _walk(child, module_level)


def _imports(path, module_level):
    """``(target module, imported name or None, line)`` of every faultnet import in ``path``."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in _walk(tree, module_level):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "faultnet":
                    yield alias.name, None, node.lineno
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if node.module.split(".")[0] == "faultnet":
                for alias in node.names:
                    yield node.module, alias.name, node.lineno


def _edges(name, path):
    """The faultnet modules that ``name`` imports, anywhere in its source."""
    out = set()
    for module, item, _ in _imports(path, module_level=False):
        sub = f"{module}.{item}" if item else None
        out.add(sub if sub in MODULES else module)
    out.discard(name)
    return {m for m in out if m in MODULES}


def test_the_module_list_is_found():
    assert {
        "faultnet",
        "faultnet.io.parquet",
        "faultnet.runs.sweep.driver",
        "faultnet._version",
    } <= set(MODULES)


def test_no_submodule_imports_a_name_from_the_package_face():
    bad = []
    for name, path in MODULES.items():
        if name == "faultnet":
            continue
        for module, item, line in _imports(path, module_level=False):
            if module == "faultnet" and (item is None or f"faultnet.{item}" not in MODULES):
                bad.append(f"{path.relative_to(ROOT.parent)}:{line}: from faultnet import {item}")
    assert not bad, "import these names from their own module:\n" + "\n".join(bad)


def _find_cycle(graph):
    state = {}

    def visit(node, stack):
        state[node] = "open"
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == "open":
                return stack[stack.index(nxt) :] + [nxt]
            if nxt not in state:
                found = visit(nxt, stack)
                if found:
                    return found
        state[node] = "done"
        stack.pop()
        return None

    for node in sorted(graph):
        if node not in state:
            found = visit(node, [])
            if found:
                return found
    return None


def test_no_import_cycles_between_modules():
    graph = {name: _edges(name, path) for name, path in MODULES.items()}
    # every submodule import runs the package face first: that edge is not a cycle
    graph = {name: edges - {"faultnet"} for name, edges in graph.items()}
    cycle = _find_cycle(graph)
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


def test_imports_inside_functions_and_type_checking_count(tmp_path):
    source = tmp_path / "probe.py"
    source.write_text(
        "from typing import TYPE_CHECKING\n"
        "if TYPE_CHECKING:\n"
        "    from faultnet.io.lock import output_lock\n"
        "def later():\n"
        "    from faultnet.cli import commands\n"
    )
    assert _edges("probe", source) == {"faultnet.io.lock", "faultnet.cli.commands"}


def test_the_cycle_finder_finds_cycles():
    assert _find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _find_cycle({"a": {"b"}, "b": set()}) is None
