"""The Carlson-Langer model with frame springs (node attribute ``wall``, ``boundary="fixed"``)."""

import numpy as np

import faultnet
from faultnet.model.identity import graph_hash


def test_walls_of_zero_change_nothing_bit_for_bit():
    plain = faultnet.graphs.square_lattice(8, 8)
    zeros = faultnet.graphs.square_lattice(8, 8)
    for v in zeros:
        zeros.nodes[v]["wall"] = 0
    a, b = (faultnet.CarlsonLanger(g, k=4, sigma=0.01, alpha=1.0) for g in (plain, zeros))
    assert graph_hash(a) == graph_hash(b) and a.params == b.params
    ra = faultnet.simulate(a, 4000, rng=2, progress=False)
    rb = faultnet.simulate(b, 4000, rng=2, progress=False)
    assert ra.state.offset > 0  # the frame offset moved during the run
    assert ra.events.equals(rb.events) and np.array_equal(ra.state.z, rb.state.z)
    assert ra.dt == rb.dt


def test_a_fixed_boundary_stiffens_the_edge_blocks_and_changes_the_run():
    fixed = faultnet.CarlsonLanger(faultnet.graphs.square_lattice(8, 8, boundary="fixed"), k=4)
    free = faultnet.CarlsonLanger(faultnet.graphs.square_lattice(8, 8), k=4)
    np.testing.assert_array_equal(fixed.stiffness, np.full(64, 17.0))
    assert free.stiffness[0] == 9.0 and fixed.frame[0] == 8.0 and fixed.frame[9] == 0.0
    assert fixed.params["frame_springs"] == 32.0 and "frame_springs" not in free.params
    assert graph_hash(fixed) != graph_hash(free)
    assert fixed.top_stiffness >= free.top_stiffness
    x = np.random.default_rng(0).random(64)
    np.testing.assert_allclose(fixed.forces(x, 2.0), free.forces(x, 2.0) - fixed.frame * x)
    rf = faultnet.simulate(fixed, 500, rng=3, progress=False)
    rr = faultnet.simulate(free, 500, rng=3, progress=False)
    assert not np.allclose(rf.events.S, rr.events.S)


def test_the_frame_stays_at_zero_while_the_plate_frame_moves():
    """One block with two frame springs: F = u - (1 + 2k) x, so every event starts at
    u = 1 + (1 + 2k) x, also after the re-centred frame moved by whole units."""
    g = faultnet.graphs.chain(1)
    g.nodes[0]["wall"] = 2
    k = 3.0
    model = faultnet.CarlsonLanger(g, k=k, sigma=0.05, alpha=0.5)
    assert model.stiffness[0] == 1 + 2 * k
    res = faultnet.simulate(model, 300, x0=[0.01], progress=False)
    ev = res.events
    x_before = 0.01 + np.concatenate([[0.0], np.cumsum(ev.S.to_numpy())[:-1]])
    np.testing.assert_allclose(ev.t, 1.0 + (1 + 2 * k) * x_before, rtol=1e-11)
    assert res.state.offset >= 8  # the frame offset moved at least twice
    assert model.forces(res.state.x, res.state.u)[0] < 1.0
