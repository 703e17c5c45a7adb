"""Code style and the import-linter contracts (pyproject.toml), checked in the default run."""

import importlib.util
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.skipif(importlib.util.find_spec("ruff") is None, reason="ruff not installed")
def test_ruff_clean():
    out = subprocess.run(
        [sys.executable, "-m", "ruff", "check", "faultnet", "tests", "benchmarks"],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stdout + out.stderr


def test_kernel_layer_imports_only_numpy_numba_math():
    lint = shutil.which("lint-imports", path=str(Path(sys.executable).parent))
    if lint is None:
        pytest.skip("import-linter not installed")
    out = subprocess.run([lint], cwd=ROOT, capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
    assert " kept, 0 broken" in out.stdout


def test_import_leaves_the_heavy_dependencies_for_later():
    """``import faultnet`` does not import numba or scipy.sparse (0.25 s and 0.2 s of start-up).

    The kernels are imported by the first run, scipy.sparse by the first model.
    """
    code = (
        "import sys, faultnet; "
        "print(sorted(m for m in ('numba', 'scipy.sparse', 'matplotlib') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
    code = (
        "import sys, faultnet; m = faultnet.CarlsonLanger(faultnet.graphs.ring(5)); "
        "faultnet.simulate(m, 3, rng=1, progress=False); "
        "print('numba' in sys.modules, 'scipy.sparse' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split()[-2:] == ["True", "True"]
