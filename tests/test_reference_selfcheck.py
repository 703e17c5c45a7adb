"""Self-checks of the slow reference oracle in ``tests/reference.py``.

These tests validate the oracle against analytical results of Sakaguchi & Morita (2013) and
against basic consistency / symmetry properties, so that it can be trusted as the ground truth
for the fast engine.  They do not use ``faultnet``.
"""

from __future__ import annotations

import numpy as np
import pytest

try:  # tests/ is not a package: pytest puts this directory on sys.path
    from reference import (
        forces,
        linear_one_block_slip,
        linear_single_block_slip,
        reference_events,
    )
except ImportError:  # pragma: no cover - if tests/ becomes a package
    from tests.reference import (
        forces,
        linear_one_block_slip,
        linear_single_block_slip,
        reference_events,
    )


ONE_BLOCK = np.zeros((1, 1))
TWO_BLOCKS = np.array([[0.0, 16.0], [16.0, 0.0]])


def chain4():
    """4-block open chain with heterogeneous springs 5, 12, 8."""
    K = np.zeros((4, 4))
    for i, j, k in [(0, 1, 5.0), (1, 2, 12.0), (2, 3, 8.0)]:
        K[i, j] = K[j, i] = k
    return K


CHAIN_SIGMA = np.array([0.01, 0.02, 0.015, 0.03])
CHAIN_ALPHA = np.array([2.0, 1.5, 0.5, 3.0])
CHAIN_X0 = np.array([0.01, 0.03, 0.0, 0.02])


# ---------------------------------------------------------------------------------------------
# 1. One block, small sigma: linear theory, Eq. (6)
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("alpha", [0.1, 0.3, 0.5])
def test_one_block_matches_linear_theory(alpha):
    events, _ = reference_events(ONE_BLOCK, 1e-4, alpha, [0.0], 2)
    expected = linear_one_block_slip(1e-4, alpha)
    for event in events:
        assert event["n_blocks"] == 1
        assert event["hypocenter"] == 0
        assert abs(event["S"] / expected - 1.0) < 0.01


def test_linear_formulas():
    # kappa = 1 reproduces the one-block formula
    assert linear_single_block_slip(0.01, 0.5, 1.0) == pytest.approx(
        linear_one_block_slip(0.01, 0.5), rel=1e-15
    )
    assert linear_single_block_slip(0.01, 2.0, 17.0) == pytest.approx(3.948e-3, rel=1e-3)
    with pytest.raises(ValueError):
        linear_one_block_slip(0.01, 1.0)
    with pytest.raises(ValueError):
        linear_single_block_slip(0.01, 2.0, 4.0)


# ---------------------------------------------------------------------------------------------
# 2. One block, sigma = 0.01, alpha = 2: periodic slip 1.274 (paper)
# ---------------------------------------------------------------------------------------------


def test_one_block_periodic_slip():
    events, u = reference_events(ONE_BLOCK, 0.01, 2.0, [0.0], 5)
    slips = np.array([event["S"] for event in events])
    for s in slips[2:]:
        assert abs(s - 1.274) < 1e-3
    np.testing.assert_allclose(slips[3:], slips[2:-1], rtol=1e-8)
    # the plate advances by exactly the slip between periodic events
    assert events[0]["t"] == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_allclose(np.diff([e["t"] for e in events]), slips[:-1], rtol=1e-9)
    assert u == events[-1]["t"]


# ---------------------------------------------------------------------------------------------
# 3. Two blocks, K = 16: small single-block slips and large simultaneous slips
# ---------------------------------------------------------------------------------------------


def test_two_blocks_single_and_simultaneous_slips():
    events, _ = reference_events(TWO_BLOCKS, 0.01, 2.0, [0.001, 0.002], 50)
    expected_single = linear_single_block_slip(0.01, 2.0, 17.0)  # ~3.95e-3

    singles = [event for event in events if event["n_blocks"] == 1]
    doubles = [event for event in events if event["n_blocks"] == 2]
    assert len(singles) > 10
    for event in singles:
        assert abs(event["S"] / expected_single - 1.0) < 0.05
        # only the hypocenter moved
        others = np.delete(event["slips"], event["hypocenter"])
        assert np.all(others == 0.0)
    # after the first (simultaneous) event, single-block slips come first
    assert events[1]["n_blocks"] == 1
    assert len(doubles) >= 1
    for event in doubles:
        assert 2.0 < event["S"] < 2.8


def test_identical_uncoupled_and_in_phase_blocks_slip_together():
    # Exact tie: both blocks reach the threshold together.  In-phase motion does not
    # stretch the coupling spring, so each block slips like an isolated block.
    one, _ = reference_events(ONE_BLOCK, 0.01, 2.0, [0.0], 1)
    for K in (np.zeros((2, 2)), TWO_BLOCKS):
        events, _ = reference_events(K, 0.01, 2.0, [0.0, 0.0], 1)
        assert events[0]["hypocenter"] == 0
        assert events[0]["n_blocks"] == 2
        np.testing.assert_allclose(events[0]["slips"], one[0]["S"], rtol=1e-9)


# ---------------------------------------------------------------------------------------------
# 4. Consistency: non-negative slips, forces below threshold after every event, S = sum s_i
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "K, sigma, alpha, x0",
    [
        (TWO_BLOCKS, 0.01, 2.0, [0.001, 0.002]),
        (chain4(), CHAIN_SIGMA, CHAIN_ALPHA, CHAIN_X0),
    ],
)
def test_consistency(K, sigma, alpha, x0):
    events, u = reference_events(K, sigma, alpha, x0, 40)
    x_prev = np.asarray(x0, dtype=float)
    t_prev = -np.inf
    for event in events:
        slips = event["slips"]
        assert np.all(slips >= 0.0)
        assert event["S"] == pytest.approx(np.sum(slips), abs=1e-15)
        np.testing.assert_array_equal(event["x"], x_prev + slips)
        assert event["n_blocks"] >= np.count_nonzero(slips > 0.0)
        assert event["slips"][event["hypocenter"]] > 0.0
        assert event["duration"] > 0.0
        assert event["t"] >= t_prev
        # plate is frozen during the event at u* = t; all blocks stuck below threshold
        F = K @ event["x"] - K.sum(axis=1) * event["x"] + (event["t"] - event["x"])
        assert np.all(F <= 1.0 + 1e-9)
        np.testing.assert_allclose(F, forces(K, event["x"], event["t"]), atol=1e-12)
        x_prev = event["x"]
        t_prev = event["t"]
    assert u == events[-1]["t"]


# ---------------------------------------------------------------------------------------------
# 5. Mirror symmetry of a heterogeneous chain
# ---------------------------------------------------------------------------------------------


def test_mirrored_chain_gives_mirrored_events():
    K = chain4()
    P = np.arange(4)[::-1]
    n_events = 40
    events, _ = reference_events(K, CHAIN_SIGMA, CHAIN_ALPHA, CHAIN_X0, n_events)
    mirrored, _ = reference_events(
        K[np.ix_(P, P)], CHAIN_SIGMA[P], CHAIN_ALPHA[P], CHAIN_X0[P], n_events
    )
    assert len({event["n_blocks"] for event in events}) >= 3  # a non-trivial sequence
    for a, b in zip(events, mirrored, strict=True):
        assert b["hypocenter"] == 3 - a["hypocenter"]
        assert b["n_blocks"] == a["n_blocks"]
        assert b["t"] == pytest.approx(a["t"], abs=1e-8)
        assert b["duration"] == pytest.approx(a["duration"], abs=1e-8)
        np.testing.assert_allclose(b["slips"][P], a["slips"], atol=1e-8)
        np.testing.assert_allclose(b["x"][P], a["x"], atol=1e-8)


# ---------------------------------------------------------------------------------------------
# Safety caps and input validation
# ---------------------------------------------------------------------------------------------


def test_safety_caps_raise():
    # the first two-block event needs several segments (block 1 joins, then two sticks)
    with pytest.raises(RuntimeError):
        reference_events(TWO_BLOCKS, 0.01, 2.0, [0.001, 0.002], 1, max_segments=2)
    with pytest.raises(RuntimeError):
        reference_events(ONE_BLOCK, 0.01, 2.0, [0.0], 1, max_duration=1.0)


def test_input_validation():
    with pytest.raises(ValueError):
        reference_events([[0.0, 1.0], [2.0, 0.0]], 0.01, 2.0, [0.0, 0.0], 1)
    with pytest.raises(ValueError):
        reference_events(ONE_BLOCK, 1.5, 2.0, [0.0], 1)
    with pytest.raises(ValueError):
        reference_events(TWO_BLOCKS, [0.01, 0.02, 0.03], 2.0, [0.0, 0.0], 1)
