"""Tests of faultnet.stats (magnitudes, b fits, irregularity) and faultnet.dynamics."""

import math

import numpy as np
import pandas as pd
import pytest

import faultnet
from faultnet.stats import (
    BFit,
    fit_b_lsq,
    fit_b_mle,
    irregularity,
    magnitude_distribution,
)

# ---------------------------------------------------------------- magnitudes


def _exponential_magnitudes(b, n, seed, m0=0.0):
    return m0 + np.random.default_rng(seed).exponential(1.0 / b, n)


def test_magnitude_distribution_normalised():
    M = _exponential_magnitudes(0.5, 5000, seed=0, m0=-3.0)
    table = magnitude_distribution(M, bins=30)
    assert list(table.columns) == ["M", "density", "count", "width"]
    assert table["count"].sum() == 5000
    assert math.isclose((table["density"] * table["width"]).sum(), 1.0, rel_tol=1e-12)
    # a narrower range keeps the densities of the whole catalogue
    part = magnitude_distribution(M, bins=10, range=(-3.0, 0.0))
    inside = np.count_nonzero(M <= 0.0)
    assert math.isclose((part["density"] * part["width"]).sum(), inside / 5000, rel_tol=1e-12)


def test_magnitude_distribution_accepts_events_frame():
    S = np.array([1e-3, 1e-2, 0.1, 1.0, 0.0])  # S = 0 -> M = -inf is dropped
    events = pd.DataFrame({"S": S, "M": np.log(np.where(S > 0, S, np.nan))})
    table = magnitude_distribution(events, bins=4)
    assert table.attrs["n"] == 4
    assert np.allclose(table["count"], [1, 1, 1, 1])
    from_s = magnitude_distribution(events[["S"]], bins=4)
    assert np.allclose(from_s["density"], table["density"])
    with pytest.raises(ValueError, match="at least one finite"):
        magnitude_distribution([np.nan, -np.inf])


# ---------------------------------------------------------------- b fits


@pytest.mark.parametrize(("b", "seed"), [(0.45, 1), (0.67, 2), (0.85, 3)])
def test_fit_b_lsq_recovers_b(b, seed):
    M = _exponential_magnitudes(b, 40_000, seed, m0=-6.0)
    fit = fit_b_lsq(M, -6.0, -6.0 + 3.5 / b, bins=20)
    assert isinstance(fit, BFit) and fit.method == "lsq"
    assert abs(fit.b - b) < 3 * fit.b_err, fit
    assert fit.b_err < 0.05 * b
    weighted = fit_b_lsq(M, -6.0, -6.0 + 3.5 / b, bins=20, weighted=True)
    assert abs(weighted.b - b) < 3 * weighted.b_err, weighted


@pytest.mark.parametrize(("b", "seed"), [(0.45, 4), (0.67, 5), (0.85, 6)])
def test_fit_b_mle_recovers_b(b, seed):
    M = _exponential_magnitudes(b, 20_000, seed, m0=-2.0)
    fit = fit_b_mle(M, m_min=-2.0)
    assert fit.n == 20_000 and fit.method == "mle"
    assert abs(fit.b - b) < 3 * fit.b_err, fit
    assert math.isclose(fit.b_err, fit.b / math.sqrt(fit.n))
    # a threshold inside the exponential range gives the same b (memorylessness)
    upper = fit_b_mle(M, m_min=0.0)
    assert upper.n < fit.n and abs(upper.b - b) < 3 * upper.b_err
    # default threshold: centre of the modal bin, near the lower edge here
    auto = fit_b_mle(M)
    assert -2.0 < auto.m_min < -1.5 and abs(auto.b - b) < 3 * auto.b_err
    unbiased = fit_b_mle(M, m_min=-2.0, unbiased=True)
    assert math.isclose(unbiased.b, fit.b * (fit.n - 1) / fit.n)


def test_fit_b_mle_unbiased_correction_small_samples():
    rng = np.random.default_rng(7)
    raw = [fit_b_mle(rng.exponential(1 / 0.67, 10), m_min=0.0).b for _ in range(4000)]
    corrected = np.mean(raw) * 9 / 10
    assert np.mean(raw) > 0.67 * 1.05  # the MLE is biased up by n / (n - 1)
    assert abs(corrected - 0.67) < 0.02


def test_fit_b_bad_input():
    """Each bad input is an InvalidParameterError (so also a ValueError) naming the problem."""
    M = _exponential_magnitudes(0.67, 1000, seed=8)
    with pytest.raises(faultnet.exceptions.InvalidParameterError, match="m_min < m_max"):
        fit_b_lsq(M, 2.0, 1.0)
    with pytest.raises(faultnet.exceptions.InvalidParameterError, match="at least 2"):
        fit_b_mle([])
    with pytest.raises(ValueError, match="m_min < m_max"):
        fit_b_lsq(M, 2.0, 1.0)
    with pytest.raises(ValueError, match="m_min < m_max"):
        fit_b_lsq(M, 1.0, 1.0)
    with pytest.raises(ValueError, match="non-empty bins"):
        fit_b_lsq(M, 50.0, 60.0)  # empty window
    with pytest.raises(ValueError, match="non-empty bins"):
        fit_b_lsq([0.1, 0.2], 0.0, 1.0)  # too few events
    with pytest.raises(ValueError, match="bins >= 3"):
        fit_b_lsq(M, 0.0, 1.0, bins=2)
    with pytest.raises(ValueError, match="finite"):
        fit_b_lsq(M, -np.inf, 1.0)
    with pytest.raises(ValueError, match="need >= 2"):
        fit_b_mle(M, m_min=100.0)
    with pytest.raises(ValueError, match="at least 2"):
        fit_b_mle([1.0])
    with pytest.raises(ValueError, match="undefined"):
        fit_b_mle([1.0, 1.0, 1.0], m_min=1.0)


def test_bfit_conversions():
    fit = BFit(b=2 / 3, b_err=0.02, m_min=-6.0, m_max=3.0, n=100, method="lsq")
    assert math.isclose(fit.b_gr, 1.0) and math.isclose(fit.powerlaw_alpha, 5 / 3)
    assert "b = 0.667" in str(fit)
    with pytest.raises(AttributeError):
        fit.b = 1.0  # frozen


# ---------------------------------------------------------------- irregularity


def test_irregularity_ring_by_hand():
    x = np.array([0.0, 0.3, 0.1, -0.2, 0.4])
    by_hand = (0.3 + 0.2 + 0.3 + 0.6 + 0.4) / 5  # Eq. (13), periodic
    assert math.isclose(irregularity(x), by_hand)
    ring = faultnet.graphs.ring(5)
    assert math.isclose(irregularity(x, ring), by_hand)
    model = faultnet.CarlsonLanger(ring, k=16)
    assert math.isclose(irregularity(x, model), by_hand)
    assert irregularity([1.0, 3.0]) == 2.0  # two blocks: |x2 - x1|
    assert irregularity([5.0]) == 0.0


def test_irregularity_profiles_match_loop():
    rng = np.random.default_rng(9)
    profiles = rng.normal(size=(7, 12))
    ring_loop = [np.mean(np.abs(np.roll(p, -1) - p)) for p in profiles]
    assert np.allclose(irregularity(profiles), ring_loop)
    grid = faultnet.graphs.square_lattice(3, 4)
    edges = list(grid.edges)
    grid_loop = [np.mean([abs(p[i] - p[j]) for i, j in edges]) for p in profiles]
    assert np.allclose(irregularity(profiles, grid), grid_loop)


def test_irregularity_of_result_and_errors():
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10), k=16, sigma=0.01, alpha=1.5)
    res = faultnet.simulate(model, 30, rng=3, progress=False, record_profiles=True)
    delta = irregularity(res)
    assert delta.shape == (30,) and np.allclose(delta, irregularity(res.profiles))
    with pytest.raises(ValueError, match="record_profiles"):
        irregularity(faultnet.simulate(model, 2, rng=3, progress=False))
    with pytest.raises(ValueError, match="blocks"):
        irregularity(np.zeros(4), model)
    with pytest.raises(ValueError, match="no edges"):
        irregularity(np.zeros(1), faultnet.graphs.chain(1))
    with pytest.raises(ValueError, match="shape"):
        irregularity(np.zeros((2, 2, 2)))


# ---------------------------------------------------------------- dynamics
