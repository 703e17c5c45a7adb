"""One block (paper Sect. 2, Fig. 1): periodic stick-slip against Eq. (6)."""

import numpy as np
import pytest
from reference import linear_one_block_slip, reference_events

import faultnet


def one_block(sigma, alpha):
    return faultnet.CarlsonLanger(faultnet.graphs.chain(1), sigma=sigma, alpha=alpha)


def periodic_slip(sigma, alpha, n=3):
    res = faultnet.simulate(one_block(sigma, alpha), n, x0=[0.0], progress=False)
    return res.events["S"].to_numpy()


def test_fig1a_slip_is_1274():
    s = periodic_slip(0.01, 2.0)
    assert s[-1] == pytest.approx(1.274, abs=1e-3)  # paper: 1.274
    np.testing.assert_allclose(s, s[-1], rtol=1e-12)  # strictly periodic


def test_fig1a_matches_dop853_oracle():
    ref, _ = reference_events(np.zeros((1, 1)), 0.01, 2.0, np.zeros(1), 2, rtol=1e-12, atol=1e-15)
    s = periodic_slip(0.01, 2.0, n=2)
    assert s[-1] == pytest.approx(ref[-1]["S"], rel=1e-6)


@pytest.mark.parametrize("alpha", [0.05, 0.2, 0.4, 0.6])
def test_small_sigma_matches_eq6(alpha):
    s = periodic_slip(1e-4, alpha)[-1]
    assert s == pytest.approx(linear_one_block_slip(1e-4, alpha), rel=0.01)


def test_slip_rises_steeply_near_alpha_one():
    alphas = np.array([0.45, 0.55, 0.8, 0.95, 1.05, 1.5])
    s = np.array([periodic_slip(1e-4, a)[-1] for a in alphas])
    assert np.all(np.diff(s) > 0)
    # Fig. 1c: almost 0 below alpha = 1, O(1) above it
    assert s[alphas <= 0.8].max() < 0.01
    assert s[-1] > 0.5
    slope_half = (s[1] - s[0]) / 0.1
    slope_one = (s[4] - s[3]) / 0.1
    assert slope_one > 100 * slope_half
