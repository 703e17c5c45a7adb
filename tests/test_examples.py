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
import pandas as pd
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


def run_magnitudes(graph, alpha, n_events, transient_t, seed):
    """A small builder like the pages' own: magnitudes of a ring after a transient."""
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(graph["n"]), alpha=alpha)
    state, n_trans, t_now = None, 0, 0.0
    while t_now < transient_t:
        res = faultnet.simulate(model, 100, x0=state, rng=seed, progress=False)
        state, n_trans = res.state, n_trans + len(res.events)
        t_now = float(res.events["t"].iloc[-1])
    res = faultnet.simulate(model, n_events, x0=state, rng=seed, progress=False)
    t = res.events["t"].to_numpy()
    return {
        "M": res.events["M"].to_numpy(),
        "n_events": len(t),
        "n_transient_events": n_trans,
        "transient_t": transient_t,
        "t_start": float(t[0]),
        "t_end": float(t[-1]),
        "seed": seed,
        "alpha": alpha,
    }


def test_paper_data_store_and_load_round_trip(tmp_path, monkeypatch, capsys):
    paper = _load_helper()
    monkeypatch.setenv("FAULTNET_DATA", str(tmp_path))
    codec = {"encode": paper.encode_magnitudes, "decode": paper.decode_magnitudes}
    first, prov1 = paper.load_or_run("tiny", run_magnitudes, TINY, **codec)
    path = tmp_path / "tiny.npz"
    assert path.is_file() and prov1["source"] == "computed"
    assert first["n_events"] == 300 == first["M"].size
    assert first["counts"].sum() + first["underflow"] + first["overflow"] == 300
    assert first["n_transient_events"] > 0 and first["t_start"] >= 0.5

    again, prov2 = paper.load_or_run("tiny", run_magnitudes, TINY, **codec)
    assert prov2["source"] == "loaded tiny.npz"
    for key in ("counts", "M_edges", "M"):
        np.testing.assert_array_equal(again[key], first[key])
    for key in ("n_events", "n_transient_events", "seed", "alpha", "t_end"):
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
    _, prov3 = paper.load_or_run("tiny", run_magnitudes, other, **codec)
    assert prov3["source"] == "computed"
    _, stored = paper.load_result(path)
    assert stored["params"]["seed"] == 4
    out = capsys.readouterr().out
    assert "holds other parameters" in out
    assert str(tmp_path) not in out  # messages name the file, not its folder


TINY_PAGE = """
import _paper_data as paper
import faultnet


def run_magnitudes(graph, alpha, n_events, transient_t, seed):
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(graph["n"]), alpha=alpha)
    res = faultnet.simulate(model, n_events, rng=seed, progress=False)
    return {{"M": res.events["M"].to_numpy(), "n_events": n_events}}


paper.ENTRIES["tiny"] = {entry!r}
paper.magnitudes("tiny", run_magnitudes, paper.fast_mode())
"""


def test_regenerate_command_reruns_the_page(tmp_path, monkeypatch):
    """``--regenerate NAME`` removes the stored file and runs the page that computes it."""
    paper = _load_helper()
    entry = {"paper": TINY, "fast": TINY}
    page = tmp_path / "plot_tiny.py"
    page.write_text(TINY_PAGE.format(entry=entry))
    monkeypatch.syspath_prepend(str(EXAMPLES))  # the page imports _paper_data
    monkeypatch.setenv("FAULTNET_DATA", str(tmp_path / "unused"))  # restored afterwards
    monkeypatch.delenv("FAULTNET_FAST", raising=False)
    monkeypatch.setattr(paper, "page_of", lambda name: page)
    (tmp_path / "tiny.npz").write_bytes(b"stale")
    entries = {"tiny": entry}
    assert paper.main(["--regenerate", "tiny", "--data-dir", str(tmp_path)], entries=entries) == 0
    result, prov = paper.load_result(tmp_path / "tiny.npz")
    assert prov["name"] == "tiny" and result["n_events"] == 300
    assert prov["command"].endswith("plot_tiny.py")
    with pytest.raises(SystemExit):
        paper.main(["--regenerate", "no_such_entry"])


def test_every_stored_entry_has_a_page():
    paper = _load_helper()
    names = [*paper.ENTRIES, "seis_ring_alpha1", "seis_ring_alpha2", "seis_percolation_alpha1"]
    for name in names:
        assert paper.page_of(name).is_file(), name


def test_stored_magnitudes_give_the_fits_of_the_raw_ones():
    paper = _load_helper()
    rng = np.random.default_rng(0)
    M = -6.0 + rng.exponential(1 / 0.67, 20_000)
    stored = paper.encode_magnitudes({"M": M})
    assert stored["counts"].sum() == M.size and stored["underflow"] == stored["overflow"] == 0
    binned = paper.decode_magnitudes(stored)["M"]
    assert binned.size == M.size and np.all(np.abs(np.sort(binned) - np.sort(M)) <= 0.025 + 1e-12)
    lsq = faultnet.fit_b_lsq(binned, -6.0, 3.0)
    mle = faultnet.fit_b_mle(binned, m_min=-6.0)
    raw_lsq = faultnet.fit_b_lsq(M, -6.0, 3.0)
    raw_mle = faultnet.fit_b_mle(M, m_min=-6.0)
    assert lsq.b == pytest.approx(raw_lsq.b, rel=1e-12)  # window = union of stored bins
    assert mle.b == pytest.approx(raw_mle.b, rel=1e-3)
    table = faultnet.magnitude_distribution(binned, bins=np.arange(-16.0, 16.0 + 1e-9, 0.25))
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


# --------------------------------------------------------------------------- networks of faults


def test_fault_network_page_runs_in_fast_mode(tmp_path):
    out = run_fast("plot_fault_networks.py", tmp_path)
    lines = out.splitlines()
    start = next(
        i for i, line in enumerate(lines) if line.split()[:2] == ["k_coupling", "jump_fraction"]
    )
    fractions = {}
    for line in lines[start + 1 :]:  # the first table: k_coupling, jump fraction, error
        row = line.split()
        if len(row) != 3:
            break
        fractions[float(row[0])] = float(row[1])
    assert set(fractions) == {0.0, 0.1, 0.3, 1.0, 3.0, 10.0, 32.0}, out
    assert fractions[0.0] == 0.0  # no coupling springs: no rupture spans two faults
    assert all(0.0 < f < 1.0 for k, f in fractions.items() if k > 0), out
    assert "slip on the other fault" in out
    assert "b_err" in out and not re.search(r"(^|\s)/\w", out, re.M)  # no absolute path printed


# --------------------------------------------------------------------------- SOC or geometry


def test_soc_or_geometry_page_runs_in_fast_mode(tmp_path):
    out = run_fast("plot_soc_or_geometry.py", tmp_path)
    rows = {}
    for line in out.splitlines():
        parts = line.rsplit(maxsplit=5)
        if len(parts) == 6 and parts[1] in ("lattice", "cluster"):
            rows[(parts[0].strip(), parts[1])] = float(parts[4])  # b
    assert set(rows) == {
        (model, graph) for model in ("OFC", "Carlson-Langer") for graph in ("lattice", "cluster")
    }, out
    assert all(0.2 < b < 4.0 for b in rows.values()), rows
    # the critical cluster cuts the automaton's avalanches off: a steeper fall than the lattice
    assert rows[("OFC", "cluster")] > rows[("OFC", "lattice")], rows


# --------------------------------------------------------------------------- plate during events


def _table(out, first_columns):
    """The printed table whose header starts with ``first_columns``, as a DataFrame."""
    lines = out.splitlines()
    start = next(i for i, line in enumerate(lines) if line.split()[:2] == first_columns)
    header = lines[start].split()
    rows = []
    for line in lines[start + 1 :]:
        row = line.split()
        if len(row) != len(header):
            break
        rows.append([float(v) for v in row])
    return pd.DataFrame(rows, columns=header)


def test_plate_page_runs_in_fast_mode(tmp_path):
    out = run_fast("plot_plate_does_not_stop.py", tmp_path)
    assert "FAST mode" in out
    ring = _table(out, ["nu", "eta"])
    assert len(ring) == 7 and (ring["events"] >= 200).all(), out
    frozen = ring[ring["nu"] == 0]
    # with the plate frozen the plate spends no displacement inside events, and every
    # event is one unbroken patch of the ring (blocks fail only through their neighbours)
    assert (frozen["busy"] == 0).all() and (frozen["split"] == 0).all(), out
    busy = ring[ring["eta"] == 0].set_index("nu")["busy"]
    assert busy[1e-5] < busy[1e-4] < busy[1e-3] < 1.0, out  # a factor 10 in nu each
    split = ring[ring["eta"] == 0].set_index("nu")["split"]
    assert split[1e-3] > 0, out  # a moving plate fails blocks far from the rupture
    assert ring["b_mle"].between(0.05, 3.0).all(), out
    xia = _table(out, ["N", "R"])
    assert list(xia["R"]) == [1, 2, 5, 10] and xia["b_mle"].between(0.2, 3.0).all(), out
    assert not re.search(r"(^|\s)/\w", out, re.M)  # no absolute path printed
