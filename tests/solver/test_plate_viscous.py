"""The plate moving during events (nu) and viscous coupling (eta) in the engine.

Against the DOP853 oracle event by event, each event from the oracle's own pre-event state
(chaos amplifies any difference along a sequence), and against closed forms: one block with
the plate moving, a block that the plate alone brings to the threshold, two viscous blocks in
the linear regime.
"""

import networkx as nx
import numpy as np
import pytest
import scipy.sparse as sp
from reference import max_stuck_force, reference_events
from test_reference_plate import (
    TWO_BLOCKS,
    linear_event,
    near_threshold,
    one_block_constant_friction,
)

import faultnet
from faultnet.exceptions import InvalidParameterError

#: (nu, eta): the plate alone, viscosity alone, both, a slow plate with strong viscosity
CASES = [(0.01, 0.0), (0.0, 0.1), (0.01, 0.1), (0.001, 0.5)]
TIGHT = {"rtol": 1e-12, "atol": 1e-15}


def viscous_dense(model):
    """The model's viscous coupling as a dense matrix (the oracle's ``eta``)."""
    adj = model.adjacency
    return sp.csr_matrix((model.eta_values, adj.indices, adj.indptr), shape=adj.shape).toarray()


def oracle(model, x0, n_events, u0=0.0):
    """The oracle's events; it proves itself: no stuck block ends a phase above 1."""
    events, _ = reference_events(
        model.adjacency.toarray(),
        model.sigma_values,
        model.alpha_values,
        x0,
        n_events,
        u0=u0,
        nu=model.nu,
        eta=viscous_dense(model),
        record_phases=True,
        **TIGHT,
    )
    for e in events:
        assert max_stuck_force(e["phases"]) <= 1.0 + 1e-9
    return events


def one_event(model, x, u, rtol=None):
    state = faultnet.State.from_x(x, u)
    res = faultnet.simulate(model, 1, x0=state, progress=False, record_slips=True, rtol=rtol)
    return res.events.iloc[0], res


def event_by_event(model, x0, n_events, u0=0.0):
    """Relative S errors of the engine at the default rtol, every event from the oracle's
    pre-event state; the events' hypocentres, sizes and starts agree."""
    ref = oracle(model, x0, n_events, u0=u0)
    starts = [(np.asarray(x0, float), u0)] + [(e["x"], e["u_end"]) for e in ref[:-1]]
    errors = []
    for k, ((x, u), e) in enumerate(zip(starts, ref, strict=True)):
        row, _ = one_event(model, x, u)
        assert row["hypocenter"] == model.nodes[e["hypocenter"]], k
        assert row["n_blocks"] == e["n_blocks"], k
        assert row["t"] == pytest.approx(e["t"], abs=1e-12), k
        errors.append(abs(row["S"] / e["S"] - 1.0))
    return np.array(errors), ref


def random_model(seed, nu, eta, n=8):
    rng = np.random.default_rng(seed)
    g = nx.gnp_random_graph(n, 0.5, seed=seed)
    for a, b in g.edges:
        g.edges[a, b]["k"] = float(rng.uniform(2.0, 20.0))
        if eta > 0.0:
            g.edges[a, b]["eta"] = float(eta * rng.uniform(0.5, 1.5))
    model = faultnet.CarlsonLanger(g, sigma=0.02, alpha=1.0, nu=nu, eta=eta)
    # every force within 0.05 of the threshold: events of several blocks
    return model, near_threshold(model.adjacency.toarray(), rng, 0.05)


@pytest.mark.parametrize("nu, eta", CASES)
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_random_graphs_event_by_event(seed, nu, eta):
    model, x0 = random_model(seed, nu, eta)
    errors, ref = event_by_event(model, x0, 16)
    rtol = faultnet.RunOptions().rtol
    assert np.quantile(errors, 0.9) <= 2.0 * rtol, errors
    assert errors[0] <= 1e-5  # the first event of a run from x0
    assert max(e["n_blocks"] for e in ref) > 1  # multi-block events are tested


@pytest.mark.parametrize("nu, eta", [(0.01, 0.1), (0.001, 0.0)])
def test_ring_event_by_event(nu, eta):
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(30), k=16, alpha=1.0, nu=nu, eta=eta)
    state = faultnet.simulate(model, 1500, rng=5, progress=False).state  # after a transient
    errors, ref = event_by_event(model, state.x, 30, u0=state.u)
    assert np.quantile(errors, 0.9) <= 2.0 * faultnet.RunOptions().rtol, errors
    assert sum(e["n_blocks"] > 1 for e in ref) >= 5


@pytest.mark.parametrize("nu", [0.001, 0.01, 0.1])
def test_one_block_with_the_plate_moving(nu):
    """alpha = 0: the driven oscillator's slip 2 sigma + nu t_s and duration t_s."""
    sigma = 0.01
    model = faultnet.CarlsonLanger(faultnet.graphs.chain(1), sigma=sigma, alpha=0.0, nu=nu)
    _, _, t_stop, slip = one_block_constant_friction(sigma, nu)
    row, _ = one_event(model, [0.0], 1.0, rtol=1e-8)
    assert row["S"] == pytest.approx(slip, rel=1e-7)
    assert row["duration"] == pytest.approx(t_stop, rel=1e-7)
    # the plate moved on during the event: the next event starts from there
    res = faultnet.simulate(model, 3, x0=faultnet.State.from_x([0.0], 1.0), progress=False)
    t, d = res.events.t.to_numpy(), res.events.duration.to_numpy()
    assert np.all(t[1:] >= t[:-1] + nu * d[:-1] - 1e-12)


def test_a_block_that_only_the_plate_pushes_joins():
    """Two blocks without a spring: block 1 starts delta below the threshold and joins at
    delta / nu; with the plate frozen it stays put."""
    sigma, nu, delta = 0.01, 0.01, 0.005
    g = nx.empty_graph(2)
    _, _, t_stop, slip = one_block_constant_friction(sigma, nu)
    model = faultnet.CarlsonLanger(g, sigma=sigma, alpha=0.0, nu=nu)
    row, res = one_event(model, [0.0, delta], 1.0, rtol=1e-8)
    assert row["n_blocks"] == 2
    assert row["S"] == pytest.approx(2 * slip, rel=1e-7)
    assert row["duration"] == pytest.approx(delta / nu + t_stop, rel=1e-7)
    frozen, _ = one_event(model.with_params(nu=0.0), [0.0, delta], 1.0)
    assert frozen["n_blocks"] == 1


def test_a_block_stuck_earlier_rejoins_through_the_plate():
    """A block that stuck in the event, and whose neighbours are still, slips again when the
    plate alone brings it back to 1 (the oracle agrees on every event)."""
    g = nx.path_graph(3)
    model = faultnet.CarlsonLanger(g, k=2.0, sigma=0.3, alpha=0.0, nu=0.2)
    ref = oracle(model, [0.0, 0.0, 0.0], 4, u0=0.0)
    starts = [(np.zeros(3), 0.0)] + [(e["x"], e["u_end"]) for e in ref[:-1]]
    for (x, u), e in zip(starts, ref, strict=True):
        row, res = one_event(model, x, u, rtol=1e-8)
        assert row["n_blocks"] == e["n_blocks"]
        assert row["S"] == pytest.approx(e["S"], rel=1e-6)
        assert row["duration"] == pytest.approx(e["duration"], rel=1e-6)
    resliding = [
        (p["t0"], i)
        for e in ref
        for p in e["phases"]
        for i in np.flatnonzero(p["slipping"])
        if p["t0"] > 0.0
    ]
    assert resliding  # blocks joined after the start


@pytest.mark.parametrize("eta, nu", [(0.5, 0.0), (0.5, 0.01), (2.0, 0.01)])
def test_two_viscous_blocks_match_the_matrix_exponential(eta, nu):
    """alpha = 0: both blocks start at force 1, the linear event is solved exactly."""
    sigma = np.array([0.01, 0.03])
    g = nx.Graph()
    g.add_nodes_from([(0, {"sigma": sigma[0]}), (1, {"sigma": sigma[1]})])
    g.add_edge(0, 1, k=float(TWO_BLOCKS[0, 1]))
    model = faultnet.CarlsonLanger(g, alpha=0.0, nu=nu, eta=eta)
    _, x_end, duration = linear_event(
        TWO_BLOCKS, eta * (TWO_BLOCKS > 0), sigma, np.zeros(2), 1.0, nu, [True, True]
    )
    row, res = one_event(model, [0.0, 0.0], 1.0, rtol=1e-8)
    assert row["n_blocks"] == 2
    slips = res.slips.sort_values("node").slip.to_numpy()
    np.testing.assert_allclose(slips, x_end, rtol=1e-6)
    assert row["duration"] == pytest.approx(duration, rel=1e-6)


def test_zero_nu_and_eta_are_the_plain_model():
    g = faultnet.graphs.ring(50)
    nx.set_edge_attributes(g, 0.0, "eta")
    plain = faultnet.simulate(faultnet.CarlsonLanger(g), 500, rng=3, progress=False)
    zero = faultnet.simulate(faultnet.CarlsonLanger(g, nu=0.0, eta=0.0), 500, rng=3, progress=False)
    assert plain.events.equals(zero.events)
    assert plain.metadata["crossings"] == "interpolated"


def test_continuation_is_bit_identical():
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(60), alpha=1.0, nu=0.01, eta=0.1)
    whole = faultnet.simulate(model, 600, rng=4, progress=False)
    first = faultnet.simulate(model, 250, rng=4, progress=False)
    rest = faultnet.simulate(model, 350, x0=first.state, progress=False)
    joined = np.concatenate([first.events.S.to_numpy(), rest.events.S.to_numpy()])
    assert np.array_equal(joined, whole.events.S.to_numpy())
    assert np.array_equal(rest.state.z, whole.state.z)
    assert whole.metadata["crossings"] == "exact"
    assert whole.metadata["solo_events"] == 0


def test_no_block_is_left_above_the_threshold():
    """After every event each block's force (springs and plate) is below 1."""
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(40), alpha=1.0, nu=0.01, eta=0.1)
    state = faultnet.simulate(model, 300, rng=2, progress=False).state
    for _ in range(150):
        res = faultnet.simulate(model, 1, x0=state, progress=False)
        state = res.state
        assert np.max(model.forces(state.x, state.u)) < 1.0 + 1e-9


def test_interpolated_crossings_are_refused():
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(20), nu=0.01)
    with pytest.raises(InvalidParameterError, match="crossings='exact'"):
        opts = faultnet.RunOptions(crossings="interpolated")
        faultnet.simulate(model, 5, progress=False, options=opts)


def test_the_step_of_an_rtol():
    """The plate keeps the exact treatment's calibrated step; viscosity takes the step of
    rtol / VISCOUS_SAFETY (seed 3 above needs it: its 90% error was 2.4e-6 without)."""
    from faultnet.solver.accuracy import step_for_rtol
    from faultnet.solver.step_size import VISCOUS_SAFETY

    plain = faultnet.CarlsonLanger(faultnet.graphs.ring(20))
    exact = step_for_rtol(plain, 1e-6, crossings="exact")
    moving = step_for_rtol(plain.with_params(nu=0.01), 1e-6, crossings="exact")
    viscous = step_for_rtol(plain.with_params(eta=0.1), 1e-6, crossings="exact")
    assert moving.coefficient == exact.coefficient
    half = step_for_rtol(plain, 1e-6 / VISCOUS_SAFETY, crossings="exact")
    assert viscous.coefficient == half.coefficient
    opts = faultnet.RunOptions()
    assert opts.treatment(plain.with_params(nu=0.01)) == "exact"
    assert opts.step(plain.with_params(eta=0.1)) == pytest.approx(viscous.dt)


def test_viscosity_shortens_the_step_only_where_it_dominates():
    from faultnet.solver.step_size import omega2_max

    ring = faultnet.graphs.ring(20)
    plain = faultnet.CarlsonLanger(ring, k=16)
    assert omega2_max(plain.with_params(eta=0.1)) == pytest.approx(omega2_max(plain) + 0.16)
    assert omega2_max(plain.with_params(eta=10.0)) > 6 * omega2_max(plain)


def test_a_simulator_restarted_from_a_state_gives_the_same_events():
    """Nothing a run leaves in the work arrays changes the next events: with viscous coupling a
    join's rate reads its slipping neighbours' accelerations at the step's end, all of which
    the step writes before its scan for joins (a run resumed from a checkpoint starts from
    fresh arrays)."""
    g = faultnet.graphs
    model = faultnet.CarlsonLanger(g.square_lattice(12, 12), k=8, alpha=1.0, eta=0.1)
    cols = ["t", "duration", "S", "n_blocks", "hypocenter", "n_steps"]
    for k in (283, 674, 889, 1744):
        sim = faultnet.Simulator(model, rng=3)
        sim.advance(k, progress=False)
        restarted = faultnet.Simulator(model, rng=3, x0=sim.state)
        np.testing.assert_array_equal(
            sim.advance(20, progress=False).events[cols].to_numpy(dtype=float),
            restarted.advance(20, progress=False).events[cols].to_numpy(dtype=float),
        )
