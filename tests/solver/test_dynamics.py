"""Small-system dynamics: the linear slip, two-block return maps, one-block curves, alpha ramps."""

import math

import numpy as np
import pandas as pd
import pytest

import faultnet
from faultnet.solver.dynamics import continuation, linear_slip, one_block_slip_curve, return_map


def test_linear_slip():
    assert math.isclose(linear_slip(0.01, 0.0), 0.02)
    expected = 0.01 / 17 * (1 + math.exp(2 * math.pi / math.sqrt(13)))
    assert math.isclose(linear_slip(0.01, 2.0, kappa=17.0), expected)
    assert math.isclose(expected, 0.0039, abs_tol=1e-4)  # the paper's estimate
    out = linear_slip(0.01, np.array([0.5, 1.0, 1.5]))
    assert np.isfinite(out[0]) and np.isnan(out[1:]).all()


def test_return_map_two_blocks():
    two = faultnet.CarlsonLanger(faultnet.graphs.chain(2), k=16, sigma=0.01, alpha=2.0)
    table = return_map(two, [0.005, -0.005, 0.003, 0.0])
    assert list(table.columns) == ["d", "d_next", "S", "n_blocks"]
    jump = table["d_next"] - table["d"]
    # paper: x2' - x1' = x2 - x1 -/+ 0.0038 outside |d| < 0.0019 (one-block slips)
    assert abs(jump[0] - (-0.0038)) < 2e-4
    assert abs(jump[1] - 0.0038) < 2e-4
    assert abs(jump[2] - (-0.0038)) < 2e-4
    assert table["n_blocks"].tolist()[:3] == [1, 1, 1]
    assert np.allclose(table["S"][:3], np.abs(jump[:3]))
    assert table["n_blocks"].iloc[3] == 2 and table["S"].iloc[3] > 1.0  # simultaneous slip
    shifted = return_map(two, [0.005], base=0.37)
    assert math.isclose(shifted["d_next"].iloc[0], table["d_next"].iloc[0], abs_tol=1e-9)
    with pytest.raises(ValueError, match="2 blocks"):
        return_map(faultnet.CarlsonLanger(faultnet.graphs.chain(3)), [0.0])


def test_one_block_slip_curve():
    alphas = [0.1, 0.2, 0.3, 0.4, 0.5]
    curve = one_block_slip_curve(alphas, sigma=1e-4)
    assert list(curve.columns) == ["alpha", "s", "s_linear", "duration"]
    assert np.allclose(curve["s"], curve["s_linear"], rtol=0.01)
    steep = one_block_slip_curve([0.9, 1.1], sigma=1e-4)
    assert steep["s"].iloc[1] / steep["s"].iloc[0] > 10
    assert np.isnan(steep["s_linear"].iloc[1])
    paper = one_block_slip_curve([2.0], sigma=0.01)  # Fig. 1(a): s = 1.274
    assert abs(paper["s"].iloc[0] - 1.274) < 2e-3


def test_continuation_carries_state_exactly():
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10), k=16, sigma=0.01, alpha=0.0)
    alphas = [0.2, 0.6, 1.0, 1.4]
    result, steps = continuation(model, alphas, 40, rng=11)
    assert steps["alpha"].tolist() == alphas
    assert steps.attrs["seed_entropy"] == 11
    state = None
    for a in alphas:
        manual = faultnet.simulate(model.with_params(alpha=a), 40, x0=state, rng=11, progress=False)
        state = manual.state
    assert np.array_equal(result.state.z, manual.state.z)
    assert result.state.u == manual.state.u
    assert result.state.n_events == 160
    pd.testing.assert_frame_equal(result.events, manual.events)
    assert math.isclose(steps["S_last"].iloc[-1], manual.events["S"].iloc[-1])
    again, _ = continuation(model, [0.5], 5, x0=result, progress=False)
    assert again.events["event"].iloc[0] == 160
