"""Disconnected graphs: events stay inside one cluster; isolated blocks slip alone."""

import networkx as nx
import numpy as np
import pytest

import faultnet


@pytest.fixture(scope="module")
def run():
    g = nx.disjoint_union_all(
        [
            faultnet.graphs.ring(12),
            faultnet.graphs.chain(5),
            nx.empty_graph(3),
            faultnet.graphs.square_lattice(3, 3),
        ]
    )
    model = faultnet.CarlsonLanger(g, k=16, sigma=0.01, alpha=2.0)
    res = faultnet.simulate(model, 3000, rng=11, progress=False, record_slips=True)
    return g, model, res


def test_each_event_stays_in_one_cluster(run):
    g, _, res = run
    comp = {}
    for c, nodes in enumerate(nx.connected_components(g)):
        comp.update(dict.fromkeys(nodes, c))
    clusters = res.slips.assign(c=res.slips.node.map(comp)).groupby("event").c.nunique()
    assert clusters.max() == 1
    hyp_cluster = res.events.set_index("event").hypocenter.map(comp)
    slip_cluster = res.slips.assign(c=res.slips.node.map(comp)).groupby("event").c.first()
    assert (hyp_cluster.loc[slip_cluster.index] == slip_cluster).all()


def test_isolated_blocks_give_the_one_block_slip(run):
    _, _, res = run
    one = faultnet.CarlsonLanger(faultnet.graphs.chain(1), sigma=0.01, alpha=2.0)
    s_one = faultnet.simulate(one, 3, x0=[0.0], dt=res.dt, progress=False).events.S.iloc[-1]
    isolated = res.events[res.events.hypocenter.isin([17, 18, 19])]
    assert len(isolated) > 20
    # after its first slip every isolated block repeats the one-block cycle exactly
    later = isolated.groupby("hypocenter").S.apply(lambda s: s.iloc[1:]).to_numpy()
    np.testing.assert_allclose(later, s_one, rtol=1e-9)
    assert (isolated.n_blocks == 1).all()
