"""The Numba kernel against the slow DOP853 reference, event by event."""

import networkx as nx
import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from reference import reference_events

import faultnet
from faultnet import default_dt


def random_model(seed, n=6, p_edge=0.5):
    """Small random graph with heterogeneous springs and friction."""
    rng = np.random.default_rng(seed)
    g = nx.gnp_random_graph(n, p_edge, seed=int(rng.integers(2**31)))
    for a, b in g.edges:
        g.edges[a, b]["k"] = float(rng.uniform(2.0, 20.0))
    for v in g.nodes:
        g.nodes[v]["sigma"] = float(rng.uniform(0.005, 0.05))
        g.nodes[v]["alpha"] = float(rng.uniform(0.2, 2.5))
    return faultnet.CarlsonLanger(g), rng.uniform(0.0, 0.05, n)


def compare_event_by_event(model, x0, n_events, rel=1e-5, dt=None):
    ref, _ = reference_events(
        model.adjacency.toarray(),
        model.sigma_values,
        model.alpha_values,
        x0,
        n_events,
        rtol=1e-12,
        atol=1e-15,
    )
    starts = [(np.asarray(x0, float), 0.0)] + [(e["x"], e["t"]) for e in ref[:-1]]
    for k, ((x, u), e) in enumerate(zip(starts, ref, strict=True)):
        res = faultnet.simulate(
            model, 1, x0=faultnet.State.from_x(x, u), dt=dt, progress=False, record_slips=True
        )
        row = res.events.iloc[0]
        assert row["hypocenter"] == model.nodes[e["hypocenter"]], k
        assert row["n_blocks"] == e["n_blocks"], k
        assert row["t"] == pytest.approx(e["t"], abs=1e-12), k
        assert row["S"] == pytest.approx(e["S"], rel=rel), k
        # A block left at the threshold to round-off when the last one stops re-slips by a few
        # 1e-8 in one code and not in the other: the same slips, but an end later by up to 1e-2
        # (seed 2367637, n = 2: durations 2.80146 and 2.81060, S within 2.7e-7).
        same_end = row["duration"] == pytest.approx(e["duration"], rel=1e-5)
        assert same_end or abs(row["S"] / e["S"] - 1.0) < 1e-6, (k, row["duration"], e["duration"])
        slips = np.zeros(model.n)
        slips[res.slips["node"].to_numpy()] = res.slips["slip"].to_numpy()
        np.testing.assert_allclose(slips, e["slips"], rtol=rel, atol=1e-12)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_random_heterogeneous_graphs(seed):
    model, x0 = random_model(seed)
    compare_event_by_event(model, x0, 12)


def test_whole_sequence_on_a_heterogeneous_chain():
    # a whole sequence, while chaos has not yet amplified the 1e-7 differences
    # of single events (they reach 1e-6 at event 8 and 1e-2 at event 19)
    g = faultnet.graphs.chain(4)
    for (a, b), k in zip(g.edges, [5.0, 12.0, 8.0], strict=True):
        g.edges[a, b]["k"] = k
    for v, (s, al) in enumerate([(0.01, 0.5), (0.02, 0.8), (0.015, 0.3), (0.01, 0.6)]):
        g.nodes[v]["sigma"], g.nodes[v]["alpha"] = s, al
    model = faultnet.CarlsonLanger(g)
    x0 = np.array([0.0, 0.01, 0.004, 0.02])
    ref, _ = reference_events(
        model.adjacency.toarray(),
        model.sigma_values,
        model.alpha_values,
        x0,
        8,
        rtol=1e-12,
        atol=1e-15,
    )
    res = faultnet.simulate(model, 8, x0=x0, progress=False)
    assert res.events.n_blocks.tolist() == [e["n_blocks"] for e in ref]
    np.testing.assert_allclose(res.events.S, [e["S"] for e in ref], rtol=1e-5)
    np.testing.assert_allclose(res.x, ref[-1]["x"], rtol=1e-6)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(2, 5))
@example(seed=16405, n=5)
@example(seed=2367637, n=2)
def test_hypothesis_random_graphs(seed, n):
    """The event logic on random graphs, at half the default step.

    Random heterogeneous events can be long, and at the default step their error
    reaches the 1e-5 tolerance.  Seed 16405 (n = 5) has a third event of 5 blocks over
    8 time units: at the default step its S is off by 7.4e-6 and its duration by 1.8e-5;
    at half the step by 3.9e-7 and 9.5e-7 (fourth to fifth order; 1.0e-9 and 2.5e-9 at
    dt / 8).  The default step's accuracy is what ``test_convergence.py`` checks.
    """
    model, x0 = random_model(seed, n=n, p_edge=0.7)
    compare_event_by_event(model, x0, 3, dt=default_dt(model) / 2)
