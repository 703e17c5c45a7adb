"""The example gallery (examples/): every script in fast mode, and the stored-data helper.

Each ``examples/plot_figNN_*.py`` runs as a subprocess with FAULTNET_FAST=1 and
its outputs redirected to ``tmp_path``; the test checks the exit code, the PNG
and that the printed table carries the paper's values (and, where fast mode
measures them exactly, faultnet's).  All ten take about a minute on one core.
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import faultnet

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

# script -> strings its printed output must contain: the paper's values (first)
# and faultnet values that fast mode already measures at full accuracy (single
# events and regular states only: chaotic sequences change with any rounding)
EXPECTED = {
    "plot_fig01_one_block.py": ["1.274", "Eq.(6)", "1.27450"],
    "plot_fig02_two_block_intermittency.py": [
        "~ 3.8e-3",
        "~ 2.4",
        "3-20",
        "+-0.0019",
        "0.0038",
        "0.065",
        "3.7834e-03",
        "0.00378",
    ],
    # one event each: the sign and size of x2' - x1' (the magnification is ~400-fold)
    "plot_fig03_two_block_trajectories.py": ["0.00142", "0.00169", "0.065", "-0.05", "+0.065"],
    "plot_fig04_two_block_alpha028.py": ["+-0.00066", "0.25 < alpha < 0.32", "-0.00065"],
    "plot_fig05_traveling_wave.py": ["1.007e-3", "~ 1.03e-3", "1.0073e-03", "1.0000"],
    "plot_fig06_ring10_irregularity.py": [
        "1.007e-3",
        "< 0 (decreases)",
        "> 0 (jumps up)",
        "1.0073e-03",
    ],
    "plot_fig07_ring500_irregularity.py": ["(S > 30)", "< 0 (decreases)", "> 0 (jumps up)"],
    "plot_fig08_magnitude_1d_2d.py": ["0.45 +/- 0.02", "0.85 +/- 0.02", "~ 4", "~ 8.5", "~ 1"],
    "plot_fig09_percolation.py": ["~ 0.67", "~ 3", "~ -1", "singular peak", "~ 0"],
    "plot_fig10_triangular_percolation.py": ["0.67", "(b) alpha=1: b (lsq)"],
}


def test_every_figure_script_is_listed():
    scripts = sorted(p.name for p in EXAMPLES.glob("plot_fig*.py"))
    assert scripts == sorted(EXPECTED)
    assert len(scripts) == 10
    assert (EXAMPLES / "README.txt").is_file()


def run_fast(script, tmp_path):
    """Run an example in fast mode with its figures and data under ``tmp_path``; its stdout."""
    env = dict(os.environ)
    env.update(
        FAULTNET_FAST="1",
        FAULTNET_FIGURES=str(tmp_path / "figures"),
        FAULTNET_DATA=str(tmp_path / "data"),
        MPLBACKEND="Agg",
        PYTHONIOENCODING="utf-8",
    )
    proc = subprocess.run(
        [sys.executable, str(EXAMPLES / script)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    out = proc.stdout
    assert proc.returncode == 0, f"{script} failed:\n{out[-3000:]}\n{proc.stderr[-3000:]}"
    return out


@pytest.mark.parametrize("script", sorted(EXPECTED))
def test_example_runs_in_fast_mode(script, tmp_path):
    out = run_fast(script, tmp_path)
    png = tmp_path / "figures" / f"{script[5:10]}.png"  # plot_fig01_... -> fig01.png
    assert png.is_file(), f"{script} wrote no {png.name}; output:\n{out[-2000:]}"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
    assert "FAST mode" in out
    assert "quantity" in out and "paper" in out and "faultnet" in out
    missing = [s for s in EXPECTED[script] if s not in out]
    assert not missing, f"{script}: {missing} not in the printed table:\n{out[-3000:]}"
    # fast mode must not store anything: the data directory stays untouched
    assert not (tmp_path / "data").exists()


def _load_helper():
    spec = importlib.util.spec_from_file_location("_paper_data", EXAMPLES / "_paper_data.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


TINY = {
    "graph": {"kind": "ring", "n": 20},
    "alpha": 1.0,
    "n_events": 300,
    "transient_t": 0.5,
    "seed": 3,
}


def test_paper_data_store_and_load_round_trip(tmp_path, monkeypatch, capsys):
    paper = _load_helper()
    monkeypatch.setenv("FAULTNET_DATA", str(tmp_path))
    first, prov1 = paper.load_or_run("tiny", paper.run_magnitudes, TINY)
    path = tmp_path / "tiny.npz"
    assert path.is_file() and prov1["source"] == "computed"
    assert (
        first["n_events"] == 300
        and first["counts"].sum() + first["underflow"] + first["overflow"] == 300
    )
    assert first["n_transient_events"] > 0 and first["t_start"] >= 0.5

    again, prov2 = paper.load_or_run("tiny", paper.run_magnitudes, TINY)
    assert prov2["source"].startswith("loaded")
    for key in ("counts", "M_edges"):
        np.testing.assert_array_equal(again[key], first[key])
    for key in ("n_events", "n_transient_events", "seed", "alpha", "t_end", "M_max"):
        assert again[key] == first[key]
    for key in (
        "faultnet_version",
        "params",
        "command",
        "wall_time_s",
        "date",
        "seed",
        "n_events",
        "n_transient_events",
        "transient_t",
    ):
        assert key in prov2, key
    assert prov2["faultnet_version"] == faultnet.__version__
    assert prov2["params"] == TINY and prov2["builder"] == "run_magnitudes"

    # other parameters: the stored file is not used but recomputed and replaced
    other = dict(TINY, seed=4)
    _, prov3 = paper.load_or_run("tiny", paper.run_magnitudes, other)
    assert prov3["source"] == "computed"
    _, stored = paper.load_result(path)
    assert stored["params"]["seed"] == 4
    assert "holds other parameters" in capsys.readouterr().out


def test_regenerate_command_writes_the_entry(tmp_path, monkeypatch):
    paper = _load_helper()
    monkeypatch.setattr(paper, "ENTRIES", {"tiny": {"paper": TINY, "fast": TINY}})
    assert paper.main(["--regenerate", "tiny", "--data-dir", str(tmp_path)]) == 0
    result, prov = paper.load_result(tmp_path / "tiny.npz")
    assert prov["name"] == "tiny" and result["n_events"] == 300
    with pytest.raises(SystemExit):
        paper.main(["--regenerate", "no_such_entry"])


def test_histogram_fits_match_fits_on_raw_magnitudes():
    paper = _load_helper()
    rng = np.random.default_rng(0)
    M = -6.0 + rng.exponential(1 / 0.67, 20_000)
    counts, _ = np.histogram(M, bins=paper.M_EDGES)
    assert counts.sum() == M.size
    result = {"M_edges": paper.M_EDGES, "counts": counts, "underflow": 0, "overflow": 0}
    lsq, mle = paper.fits(result, (-6.0, 3.0))
    raw_lsq = faultnet.fit_b_lsq(M, -6.0, 3.0)
    raw_mle = faultnet.fit_b_mle(M, m_min=-6.0)
    assert lsq.b == pytest.approx(raw_lsq.b, rel=1e-12)  # window = union of fine bins
    assert mle.b == pytest.approx(raw_mle.b, rel=1e-3)
    table = paper.magnitude_table(result, width=0.25)
    assert float((table["density"] * table["width"]).sum()) == pytest.approx(1.0)


# --------------------------------------------------------------------------- seismicity pages

SEISMICITY_PAGES = {
    # the literature's qualitative statements and the three-way b comparison must be printed
    "plot_seismicity_ring.py": (
        "seismicity_ring.png",
        ["< 1 (quasi-periodic)", "< 1 (doughnut)", "no Omori law", "three-way b", "alpha=2"],
    ),
    "plot_seismicity_percolation.py": (
        "seismicity_percolation.png",
        ["< 1 (quasi-periodic)", "(graph)", "(euclidean)", "three-way b", "paper (lsq): ~0.67"],
    ),
}


@pytest.mark.parametrize("script", sorted(SEISMICITY_PAGES))
def test_seismicity_page_runs_in_fast_mode(script, tmp_path):
    png, expected = SEISMICITY_PAGES[script]
    out = run_fast(script, tmp_path)
    path = tmp_path / "figures" / png
    assert path.is_file() and path.stat().st_size > 10_000
    assert "FAST mode" in out and "computed (fast" in out
    missing = [s for s in expected if s not in out]
    assert not missing, f"{script}: {missing} not printed:\n{out[-3000:]}"
    # the three estimates of b are one number once the conventions are converted
    lines = [line for line in out.splitlines() if "three-way b" in line]
    values = {re.search(r"agree\s+([-\d.]+) \+/-", line).group(1) for line in lines}
    assert len(lines) == 3 and len(values) == 1, lines
    assert not (tmp_path / "data").exists()  # fast mode stores nothing


def test_stored_seismicity_runs_have_provenance():
    """The stored paper-scale reductions reload and say how they were made."""
    helper = _load_helper()
    for name in ("seis_ring_alpha1", "seis_ring_alpha2", "seis_percolation_alpha1"):
        path = EXAMPLES.parent / "data" / f"{name}.npz"  # the repository's, not $FAULTNET_DATA
        result, prov = helper.load_result(path)
        for key in ("params", "seed", "n_events", "wall_time_s", "faultnet_version", "command"):
            assert key in prov, (name, key)
        assert prov["builder"] == "run_seismicity" and result["n_events"] >= 2_000_000
        assert result["n_mainshocks"] > 300
