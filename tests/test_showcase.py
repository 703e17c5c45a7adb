"""The showcase example (b against alpha) runs in fast mode and its stored data is sane."""

import os
import subprocess
import sys
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parent.parent


def test_showcase_example_fast_mode(tmp_path):
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    env = dict(
        os.environ,
        FAULTNET_FAST="1",
        FAULTNET_FIGURES=str(tmp_path),
        MPLBACKEND="Agg",
        TMPDIR=str(scratch),
    )
    out = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "plot_showcase_b_vs_alpha.py")],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "showcase_b_vs_alpha.png").stat().st_size > 10_000
    # the tiny sweep's parts do not outlive the script
    assert not any(scratch.iterdir()), sorted(scratch.iterdir())


def test_stored_showcase_sweep():
    table = pd.read_csv(ROOT / "data" / "showcase" / "summary.csv")
    assert len(table) == 72 and (table.status == "done").all()
    assert sorted(table.alpha.unique()) == [0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0]
    assert (table.groupby(["graph", "alpha"]).size() == 3).all()
    assert table.seed_entropy.nunique() == 1  # one root seed, children per point
    ring = table[table.graph == "ring:2000"].groupby("alpha").b_mle.mean()
    # ring at alpha = 1: the paper's b = 0.45 +- 0.02 (fit window [-6, 3]); the
    # stored MLE above the maximum-curvature magnitude gives 0.43
    assert abs(ring.loc[1.0] - 0.45) < 0.05
