"""Inner kernels linked into the entries' code, with no machine code of their own."""

import os
import subprocess
import sys
import textwrap

import numba as nb
import pytest
from numba.core.caching import NullCache

from faultnet._kernels import dopri, events, linking

pytestmark = pytest.mark.skipif(linking.PIPELINE is None, reason="this Numba's layout differs")

PACKAGE = {
    "leaf.py": """
        import numba as nb
        from faultnet._kernels.linking import PIPELINE

        @nb.njit(pipeline_class=PIPELINE, no_cpython_wrapper=True)
        def leaf(x):
            return x * 3.0
    """,
    "middle.py": """
        import numba as nb
        from faultnet._kernels.linking import PIPELINE
        from leaf import leaf

        @nb.njit(pipeline_class=PIPELINE, no_cpython_wrapper=True)
        def middle(x, n):
            s = 0.0
            for i in range(n):
                s += leaf(x + i)
            return s
    """,
    "top.py": """
        import numba as nb
        from leaf import leaf
        from middle import middle

        @nb.njit(cache=True)
        def top(x, n):
            return middle(x, n) + leaf(x)  # leaf twice: directly and inside middle
    """,
}

RUNNER = """
import sys
sys.path.insert(0, {pkg!r})
from top import top
import leaf, middle
print(top(1.0, 4), len(leaf.leaf.overloads), len(middle.middle.overloads))
"""


def _run(pkg, cache_dir):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir))
    code = RUNNER.format(pkg=str(pkg))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    value, n_leaf, n_middle = out.stdout.split()
    return float(value), int(n_leaf), int(n_middle)


def test_linked_kernels_run_inside_an_entry_and_from_its_cache(tmp_path):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    for name, text in PACKAGE.items():
        (pkg / name).write_text(textwrap.dedent(text))
    expected = 3.0 * (1 + 2 + 3 + 4) + 3.0
    assert _run(pkg, tmp_path / "cache") == (expected, 1, 1)  # compiled: every kernel typed
    files = [f for _, _, names in os.walk(tmp_path / "cache") for f in names]
    assert any(f.startswith("top.") and f.endswith(".nbi") for f in files)
    assert not any(f.startswith(("leaf.", "middle.")) for f in files)  # nothing of theirs cached
    assert _run(pkg, tmp_path / "cache") == (expected, 0, 0)  # the entry's cache alone


def test_an_inner_kernel_is_optimised_and_emitted_only_inside_its_caller(monkeypatch):
    from numba.core import codegen

    finished = []  # the libraries that went through module passes and machine code
    original = codegen.JITCodeLibrary._finalize_final_module

    def spy(self):
        finished.append(self)
        return original(self)

    monkeypatch.setattr(codegen.JITCodeLibrary, "_finalize_final_module", spy)

    @nb.njit(pipeline_class=linking.PIPELINE, no_cpython_wrapper=True)
    def twice(x):
        return 2.0 * x

    @nb.njit
    def entry(x):
        return twice(x) + 1.0

    assert entry(2.0) == 5.0
    (inner,) = twice.overloads.values()
    (outer,) = entry.overloads.values()
    assert isinstance(inner.library, linking.LinkOnlyLibrary)
    assert inner.library._finalized  # linked into the entry's library
    assert "fmul" in inner.library.get_llvm_str()
    assert outer.library in finished
    assert inner.library not in finished


def test_faultnet_inner_kernels_are_linked_and_not_cached():
    assert isinstance(dopri.dopri_step._cache, NullCache)
    assert dopri.dopri_step.targetoptions.get("no_cpython_wrapper")
    assert not isinstance(events.run_events_dopri5_interpolated._cache, NullCache)
