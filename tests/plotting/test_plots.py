"""Tests of faultnet.plotting.figures (Agg backend, saved to tmp_path)."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.collections import LineCollection, PathCollection  # noqa: E402

import faultnet  # noqa: E402
from faultnet import plotting as plots  # noqa: E402
from faultnet.solver.dynamics import return_map  # noqa: E402
from faultnet.stats import fit_b_lsq, fit_b_mle, magnitude_distribution  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _save(ax, tmp_path, name):
    path = tmp_path / f"{name}.png"
    ax.figure.savefig(path, dpi=50)
    assert path.stat().st_size > 0


def test_import_faultnet_does_not_import_plots():
    import subprocess
    import sys

    code = (
        "import sys, faultnet; "
        "print('faultnet.plotting.figures' in sys.modules, 'matplotlib.pyplot' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


def test_plot_magnitude_distribution(tmp_path):
    M = np.random.default_rng(0).exponential(1 / 0.67, 20_000) - 6.0
    fit = fit_b_lsq(M, -6.0, 0.0)
    ax = plots.plot_magnitude_distribution(M, fit=fit, label="synthetic")
    assert isinstance(ax, Axes)
    assert ax.get_yscale() == "log" and ax.get_xlabel() == "M = ln S"
    data, line = ax.get_lines()
    assert data.get_label() == "synthetic" and line.get_label().startswith("b = 0.6")
    # the fitted line follows the histogram in the window
    table = magnitude_distribution(M, bins=50)
    at = table[(table["M"] > -5) & (table["M"] < -1)]
    predicted = np.interp(at["M"], line.get_xdata(), line.get_ydata())
    assert np.allclose(predicted, at["density"], rtol=0.15)
    _save(ax, tmp_path, "pm")
    # a precomputed table and an events frame on a shared axis, MLE fit
    fig, ax2 = plt.subplots()
    assert plots.plot_magnitude_distribution(table, ax=ax2) is ax2
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(20), k=16, sigma=0.01, alpha=1.0)
    events = faultnet.simulate(model, 200, rng=1, progress=False).events
    plots.plot_magnitude_distribution(events, fit=fit_b_mle(events), ax=ax2, label="ring")
    assert len(ax2.get_lines()) == 3
    _save(ax2, tmp_path, "pm2")


def test_plot_profiles(tmp_path):
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10), k=16, sigma=0.01, alpha=1.5)
    res = faultnet.simulate(model, 60, rng=2, progress=False, record_profiles=True)
    ax = plots.plot_profiles(res.profiles)
    assert isinstance(ax, Axes) and len(ax.get_images()) == 1
    assert ax.get_xlabel() == "block i" and ax.get_ylabel() == "event"
    assert len(ax.figure.axes) == 2  # image + colour bar
    _save(ax, tmp_path, "profiles")
    ax = plots.plot_profiles(res.profiles, t=res.events["t"], subtract_mean=True)
    assert ax.get_ylabel() == "t" and len(ax.collections) == 1
    assert ax.figure.axes[1].get_ylabel() == "x_i - <x>"
    _save(ax, tmp_path, "profiles_t")
    with pytest.raises(ValueError, match="shape"):
        plots.plot_profiles(np.zeros(5))


def test_plot_time_series(tmp_path):
    t = np.arange(5.0)
    ax = plots.plot_time_series(t, [0.1, 2.0, 0.1, 0.1, 3.0], kind="S")
    assert ax.get_ylabel() == "S" and len(ax.collections) == 1
    fig, ax2 = plt.subplots()
    plots.plot_time_series(t, [0.5, 0.4, 0.3, 0.9, 0.8], ax=ax2, kind="delta")
    assert ax2.get_ylabel() == "Δ" and len(ax2.get_lines()) == 1
    _save(ax2, tmp_path, "delta")
    with pytest.raises(faultnet.exceptions.InvalidParameterError, match="kind"):
        plots.plot_time_series(t, t, kind="M")


def test_plot_return_map(tmp_path):
    two = faultnet.CarlsonLanger(faultnet.graphs.chain(2), k=16, sigma=0.01, alpha=2.0)
    table = return_map(two, np.linspace(-0.005, 0.005, 21))
    ax = plots.plot_return_map(table)
    labels = [line.get_label() for line in ax.get_lines()]
    assert labels == ["d' = d", "d' = -d"]
    assert isinstance(ax.collections[0], PathCollection)
    assert len(ax.collections[0].get_offsets()) == 21
    _save(ax, tmp_path, "map")


def test_plot_graph(tmp_path):
    lattice = faultnet.graphs.square_lattice(30, 30)
    clusters = faultnet.graphs.site_percolation(lattice, 0.56, rng=3, keep="all")
    ax = plots.plot_graph(clusters, color_by="component")
    lines = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert len(lines) == 1 and len(lines[0].get_segments()) == clusters.number_of_edges()
    assert len(np.unique(lines[0].get_colors(), axis=0)) > 1
    _save(ax, tmp_path, "clusters")
    torus = faultnet.graphs.square_lattice(5, 5, periodic=True)
    ax = plots.plot_graph(faultnet.CarlsonLanger(torus))
    assert len(ax.collections[0].get_segments()) == 40  # 10 wrap-around bonds hidden
    ax = plots.plot_graph(faultnet.graphs.ring(8), color_by=np.arange(8.0))
    assert len(ax.figure.axes) == 2
    _save(ax, tmp_path, "ring")
    with pytest.raises(ValueError, match="one value per node"):
        plots.plot_graph(faultnet.graphs.ring(8), color_by=np.arange(3.0))


def test_plot_graph_large_lattice_is_fast(tmp_path):
    import time

    lattice = faultnet.graphs.square_lattice(150, 150)
    tic = time.perf_counter()
    ax = plots.plot_graph(lattice)
    assert time.perf_counter() - tic < 3.0
    assert len(ax.collections[0].get_segments()) == lattice.number_of_edges()


def test_plot_faults_colours_faults_and_dashes_couplings(tmp_path):
    G = faultnet.graphs.parallel_faults(3, 12, k_coupling=2.0, spacing=2.0, periodic=True)
    ax = plots.plot_faults(faultnet.CarlsonLanger(G))
    inside, coupling = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert len(inside.get_segments()) == 3 * 11  # the wrap-around springs hidden
    assert len(np.unique(inside.get_colors(), axis=0)) == 3
    assert len(coupling.get_segments()) == 2 * 12
    assert coupling.get_linestyle()[0][1] is not None  # dashed
    dots = [c for c in ax.collections if isinstance(c, PathCollection)]
    assert len(dots) == 1 and len(dots[0].get_offsets()) == 36
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["0", "1", "2", "coupling"]
    _save(ax, tmp_path, "faults")
    fig, ax2 = plt.subplots()
    branched = faultnet.graphs.branch(10, 5, at=4, k_coupling=0, names=("main", ("b", 1)))
    assert plots.plot_faults(branched, ax=ax2, legend=False, node_size=0) is ax2
    assert ax2.get_legend() is None
    assert len([c for c in ax2.collections if isinstance(c, LineCollection)]) == 1
    # plot_graph hides the same wrap-around springs, by the graph's period
    assert len(plots.plot_graph(G).collections[0].get_segments()) == 3 * 11 + 2 * 12
    with pytest.raises(ValueError, match="'fault' attribute"):
        plots.plot_faults(faultnet.graphs.ring(5))


def test_magnitude_distribution_leaves_gaps_at_empty_bins():
    import numpy as np

    from faultnet.plotting import plot_magnitude_distribution

    M = np.concatenate([np.full(50, -3.0), np.full(5, 3.0)])  # nothing in between
    ax = plot_magnitude_distribution(M, bins=12)
    y = ax.get_lines()[0].get_ydata()
    assert np.isnan(y).sum() >= 5  # the empty bins are gaps, not bridged
    assert np.nanmin(y) > 0


def test_plots_take_results_and_name_wrong_tables():
    """A SimulationResult is accepted where its events or profiles are meant; a table of the
    wrong function, or a SparseGraph to draw, is an error that says what is needed."""
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(30))
    res = faultnet.simulate(model, 300, rng=2, progress=False)
    assert fit_b_mle(res, -6.0).b == fit_b_mle(res.events, -6.0).b
    a = plots.plot_magnitude_distribution(res)
    b = plots.plot_magnitude_distribution(res.events)
    np.testing.assert_array_equal(a.get_lines()[0].get_ydata(), b.get_lines()[0].get_ydata())
    with pytest.raises(faultnet.InvalidParameterError, match="record_profiles=True"):
        plots.plot_profiles(res)
    with_profiles = faultnet.simulate(model, 20, rng=2, progress=False, record_profiles=True)
    assert isinstance(plots.plot_profiles(with_profiles), Axes)
    with pytest.raises(faultnet.InvalidParameterError, match="DataFrame of .*return_map"):
        plots.plot_return_map(res.events)
    sparse = faultnet.graphs.square_lattice(5, 5, sparse=True)
    with pytest.raises(TypeError, match="SparseGraph, which has no node positions"):
        plots.plot_graph(faultnet.CarlsonLanger(sparse))


def test_interevent_times_axis_stays_near_the_data():
    """The Poisson line exp(-theta) is not drawn down to exp(-100) ~ 1e-44."""
    from faultnet.plotting import plot_interevent_times

    theta = np.random.default_rng(3).exponential(1.0, 5000)
    ax = plot_interevent_times(theta)
    ax.figure.canvas.draw()
    lowest = min(np.nanmin(line.get_ydata()[line.get_ydata() > 0]) for line in ax.get_lines())
    assert ax.get_ylim()[0] > 1e-8 and lowest >= 1e-8
    plt.close(ax.figure)
