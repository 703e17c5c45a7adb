"""Statistics of networks of faults, against catalogues whose answers are known."""

import numpy as np
import pandas as pd
import pytest

import faultnet
from faultnet.exceptions import InvalidParameterError
from faultnet.seismicity import (
    b_per_fault,
    fault_magnitudes,
    fault_triggering,
    multi_fault_fraction,
)


def _catalogue(faults, M, t=None, n_faults=None):
    n = len(M)
    label = np.empty(n, dtype=object)
    label[:] = list(faults)
    return pd.DataFrame(
        {
            "t": np.arange(n, dtype=float) if t is None else t,
            "M": M,
            "fault": label,
            "n_faults": np.ones(n, dtype=np.int64) if n_faults is None else n_faults,
        }
    )


def test_multi_fault_fraction_counts_per_bin():
    M = np.array([0.1, 0.2, 0.3, 0.4, 1.6, 1.7, 1.8, 1.9])
    n_faults = np.array([1, 1, 1, 2, 2, 2, 1, 2])
    table = multi_fault_fraction(_catalogue("A" * 8, M, n_faults=n_faults), bins=[0, 1, 2])
    assert table["events"].tolist() == [4, 4] and table["multi"].tolist() == [1, 3]
    np.testing.assert_allclose(table["fraction"], [0.25, 0.75])
    np.testing.assert_allclose(table["error"], np.sqrt([0.25 * 0.75 / 4] * 2))
    np.testing.assert_allclose(table["M"], [0.5, 1.5])


def test_b_per_fault_recovers_known_b_values():
    rng = np.random.default_rng(5)
    b_true = {("A", 1): 0.5, ("B", 2): 1.0}
    M = np.concatenate([rng.exponential(1 / b, 20_000) for b in b_true.values()])
    faults = [f for f in b_true for _ in range(20_000)]
    table = b_per_fault(_catalogue(faults, M), m_min=0.0)
    assert list(table.index) == list(b_true)
    for fault, b in b_true.items():
        row = table.loc[[fault]].iloc[0]
        assert abs(row["b"] - b) < 3 * row["b_err"] and row["n"] == 20_000


def test_fault_magnitudes_normalises_each_fault_on_shared_bins():
    rng = np.random.default_rng(1)
    M = np.concatenate([rng.normal(0, 1, 3000), rng.normal(2, 1, 1000)])
    table = fault_magnitudes(_catalogue([("A", 0)] * 3000 + [("B", 0)] * 1000, M), bins=20)
    assert table["fault"].map(type).eq(tuple).all()
    for _, part in table.groupby("fault"):
        assert float((part["density"] * part["width"]).sum()) == pytest.approx(1.0)
        assert part["M"].tolist() == table["M"].iloc[:20].tolist()


def test_fault_triggering_sees_followers_and_chance():
    rng = np.random.default_rng(2)
    t_a = np.sort(rng.uniform(0, 1000, 500))
    t_b = t_a + 0.01  # every A event is followed by a B event after 0.01
    t_c = np.sort(rng.uniform(0, 1000, 500))  # C: independent of A
    t = np.concatenate([t_a, t_b, t_c])
    faults = ["A"] * 500 + ["B"] * 500 + ["C"] * 500
    order = np.argsort(t, kind="stable")
    events = _catalogue(np.array(faults)[order], np.zeros(1500), t=t[order])
    table = fault_triggering(events, window=0.02)
    assert table.loc[("A", "B"), "fraction"] == 1.0 and table.loc[("A", "B"), "ratio"] > 50
    chance = 1 - np.exp(-500 / (t.max() - t.min()) * 0.02)
    assert table.loc[("A", "C"), "chance"] == pytest.approx(chance)
    n = table.loc[("A", "C"), "n_source"]
    assert abs(table.loc[("A", "C"), "fraction"] - chance) < 4 * np.sqrt(chance / n)


def test_on_a_simulated_step_over_and_the_errors():
    G = faultnet.graphs.step_over(30, overlap=5, gap=1.0, k_coupling=4.0)
    res = faultnet.simulate(faultnet.CarlsonLanger(G), 3000, rng=1, progress=False)
    table = multi_fault_fraction(res, bins=6)
    assert table["events"].sum() == 3000 and (table["fraction"] <= 1).all()
    assert set(b_per_fault(res).index) == {"A", "B"}
    plain = faultnet.simulate(faultnet.CarlsonLanger(faultnet.graphs.ring(10)), 50, rng=1,
                              progress=False)  # fmt: skip
    with pytest.raises(InvalidParameterError, match="network of faults"):
        multi_fault_fraction(plain)
    with pytest.raises(InvalidParameterError, match="window must be"):
        fault_triggering(res, window=0)
