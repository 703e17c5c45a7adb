"""Every kernel of the Carlson-Langer engine documents every argument.

A kernel's arguments are named in its own docstring or in its module's (the modules list the
arguments their kernels share: ``graph``, ``work``, ``h`` ...).  The sources are parsed, not
imported.  The folder holds kernel code only, within its line budget.
"""

import ast
import re
from pathlib import Path

import pytest

FOLDER = Path(__file__).resolve().parents[2] / "faultnet" / "solver" / "_kernels" / "carlson_langer"
DECORATORS = {"kernel", "inline_kernel", "forced_kernel", "kelvin_kernel", "entry"}
#: the engine's kernels stay small enough to read
MAX_LINES = 3200
#: the engine's kernel modules and the OFC kernel
KERNEL_FILES = sorted(FOLDER.glob("*.py")) + [FOLDER.parent / "ofc.py"]


def _kernels():
    for path in sorted(FOLDER.glob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        module_doc = ast.get_docstring(tree) or ""
        for node in tree.body:
            if isinstance(node, ast.FunctionDef):
                calls = [d.func for d in node.decorator_list if isinstance(d, ast.Call)]
                names = {d.id for d in node.decorator_list + calls if isinstance(d, ast.Name)}
                yield path.name, node, bool(names & DECORATORS), module_doc


def _mentioned(name, text):
    """``name`` appears in ``text``, alone or inside a range such as ``c0 ... c4``."""
    if re.search(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9_])", text):
        return True
    m = re.fullmatch(r"([A-Za-z]+)(\d)", name)
    if not m:
        return False
    prefix, n = m.group(1), int(m.group(2))
    ranges = re.findall(
        rf"(?<![A-Za-z0-9_]){prefix}(\d)`*,?\s*(?:\.\.\.|\.\.|…),?\s*`*{prefix}?(\d)", text
    )
    return any(int(lo) <= n <= int(hi) for lo, hi in ranges)


KERNELS = [(f, n, m) for f, n, is_kernel, m in _kernels() if is_kernel]


def test_the_folder_holds_kernels_only():
    # every function is a kernel (a Python helper belongs to the Python layer)
    plain = [f"{f}:{n.name}" for f, n, is_kernel, _ in _kernels() if not is_kernel]
    assert plain == []
    assert len(KERNELS) > 40


def test_the_engine_fits_its_line_budget():
    lines = sum(len(p.read_text(encoding="utf-8").splitlines()) for p in FOLDER.glob("*.py"))
    assert lines <= MAX_LINES


@pytest.mark.parametrize("file, node, module_doc", KERNELS, ids=lambda x: getattr(x, "name", ""))
def test_every_kernel_argument_is_documented(file, node, module_doc):
    doc = ast.get_docstring(node) or ""
    args = [a.arg for a in node.args.args]
    missing = [a for a in args if not (_mentioned(a, doc) or _mentioned(a, module_doc))]
    assert missing == [], f"{file}:{node.name} does not document {missing}"


def _numba_compiles_apart(tree):
    """Constructs for which Numba compiles a library of its own in kernels built without its
    rewrite passes (jit.py): a constant index into an array's shape (``len(a)``, or
    ``_, n = a.shape``, instead), and the builtins ``min``, ``max`` and ``int`` (compared, and
    cast with ``np.int64``, instead), whose overloads compile per argument types and flags."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Subscript) and isinstance(node.value, ast.Attribute):
            if node.value.attr == "shape":
                yield node.lineno, "shape[...]"
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            if node.func.id in ("min", "max", "int"):
                yield node.lineno, node.func.id


@pytest.mark.parametrize("path", KERNEL_FILES, ids=lambda p: p.name)
def test_no_construct_that_numba_compiles_apart(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    assert list(_numba_compiles_apart(tree)) == []


def test_the_check_finds_those_constructs():
    tree = ast.parse("def f(a, x, y):\n    return a.shape[0] + min(x, y) + max(x, y) + int(x)\n")
    found = sorted(what for _, what in _numba_compiles_apart(tree))
    assert found == ["int", "max", "min", "shape[...]"]
