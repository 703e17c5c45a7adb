"""Ring (paper Sect. 4, Fig. 5): the single-block slip of the traveling-wave regime."""

import numpy as np
import pytest
from reference import linear_single_block_slip

import faultnet

K, SIGMA, ALPHA = 16.0, 0.01, 1.5


def test_single_block_slip_in_ring():
    # one block ahead of flat neighbours: only it slips, neighbours stay stuck
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10), k=K, sigma=SIGMA, alpha=ALPHA)
    x = np.zeros(10)
    x[3] = -0.01  # block 3 lags behind: it fails first
    _, row = faultnet.slip_event(model, x)
    assert row["n_blocks"] == 1 and row["hypocenter"] == 3
    lin = linear_single_block_slip(SIGMA, ALPHA, 2 * K + 1)
    # evaluating the paper's formula gives 1.012e-3 (the paper quotes "~1.03e-3")
    assert lin == pytest.approx(1.0118e-3, rel=1e-3)
    assert row["S"] == pytest.approx(1.007e-3, rel=2e-3)  # paper: 1.007e-3
    assert row["S"] == pytest.approx(lin, rel=0.01)
