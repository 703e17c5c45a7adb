"""Event columns of a network of faults: the hypocentre's fault and the faults that slipped.

``n_faults`` is counted in the kernel; the reference here counts it from the per-block slips
of the same run (``record_slips=True``), event by event.
"""

import networkx as nx
import numpy as np
import pandas as pd
import pytest

import faultnet
from faultnet.exceptions import InvalidParameterError


def _faults_from_slips(result, graph):
    fault = {node: data["fault"] for node, data in graph.nodes(data=True)}
    slips = result.slips
    return slips.assign(fault=slips["node"].map(fault)).groupby("event")["fault"].nunique()


@pytest.mark.parametrize("crossings", ["exact", "interpolated"])
@pytest.mark.parametrize("k_coupling", [0.5, 16.0])
def test_n_faults_counts_the_faults_among_the_slipped_blocks(crossings, k_coupling):
    graph = faultnet.graphs.parallel_faults(3, 20, k_coupling=k_coupling)
    model = faultnet.CarlsonLanger(graph, k=16, sigma=0.01, alpha=1.0)
    options = faultnet.RunOptions(crossings=crossings)
    res = faultnet.simulate(model, 2000, rng=3, options=options, record_slips=True, progress=False)
    ev = res.events.set_index("event")
    expected = _faults_from_slips(res, graph).reindex(ev.index)
    np.testing.assert_array_equal(ev["n_faults"].to_numpy(), expected.to_numpy())
    assert ev["n_faults"].min() == 1 and ev["n_faults"].max() <= 3
    if k_coupling == 16.0:
        assert (ev["n_faults"] > 1).sum() > 20  # strongly coupled: many ruptures jump
    hypo_fault = ev["hypocenter"].map(lambda node: graph.nodes[node]["fault"])
    assert ev["fault"].tolist() == hypo_fault.tolist()


def test_solo_slips_count_one_fault_and_the_columns_match_a_run_without_the_cache():
    graph = faultnet.graphs.step_over(30, overlap=5, gap=1.0, k_coupling=2.0)
    model = faultnet.CarlsonLanger(graph, k=16, sigma=0.01, alpha=1.0)
    fast = faultnet.Simulator(model, rng=1).advance(1500, progress=False)
    assert fast.metadata["solo_events"] > 0
    solo = fast.events[fast.events["n_blocks"] == 1]
    assert len(solo) and (solo["n_faults"] == 1).all()
    slow = faultnet.Simulator(model, rng=1, solo_cache=False).advance(1500, progress=False)
    assert slow.metadata["solo_events"] == 0
    assert (slow.events[slow.events["n_blocks"] == 1]["n_faults"] == 1).all()


def test_graphs_without_faults_have_no_fault_columns():
    res = faultnet.simulate(faultnet.CarlsonLanger(faultnet.graphs.ring(20)), 50, rng=1,
                            progress=False)  # fmt: skip
    assert "fault" not in res.events and "n_faults" not in res.events
    assert list(res.events.columns) == [
        "event", "t", "duration", "n_blocks", "S", "M", "hypocenter", "n_steps"
    ]  # fmt: skip


def test_fault_labels_must_be_on_every_block_and_of_a_kept_type():
    g = nx.path_graph(4)
    nx.set_node_attributes(g, {0: "A", 1: "A"}, "fault")
    with pytest.raises(InvalidParameterError, match="set on 2 of 4 blocks .*not on 2"):
        faultnet.CarlsonLanger(g)
    nx.set_node_attributes(g, {2: "B", 3: 1.5}, "fault")
    with pytest.raises(InvalidParameterError, match=r"fault of node 3 must be .*got 1.5"):
        faultnet.CarlsonLanger(g)


def test_fault_columns_survive_a_catalog_file_and_a_long_run(tmp_path):
    graph = faultnet.graphs.parallel_faults(2, 15, k_coupling=4.0, names=[("A", 1), ("B", 2)])
    model = faultnet.CarlsonLanger(graph)
    res = faultnet.simulate(model, 400, rng=2, progress=False)
    assert res.events["fault"].iloc[0] in {("A", 1), ("B", 2)}
    out = tmp_path / "faults.parquet"
    faultnet.simulate_to_parquet(model, 400, out, rng=2, chunk_events=150, progress=False)
    pd.testing.assert_frame_equal(faultnet.read_catalog(out).events, res.events)


def test_the_faults_change_the_graph_hash():
    from faultnet.model.identity import graph_hash

    plain = faultnet.graphs.chain(6)
    labelled = plain.copy()
    nx.set_node_attributes(labelled, {i: "A" if i < 3 else "B" for i in range(6)}, "fault")
    assert graph_hash(faultnet.CarlsonLanger(plain)) != graph_hash(faultnet.CarlsonLanger(labelled))


def _sum_in_row_order(result, graph):
    """Each event's slip per fault, added in the order of the per-block rows."""
    fault = {node: data["fault"] for node, data in graph.nodes(data=True)}
    sums = {}
    for event, node, slip in result.slips.itertuples(index=False):
        key = (int(event), fault[node])
        sums[key] = sums.get(key, 0.0) + slip
    return sums


@pytest.mark.parametrize("k_coupling", [0.0, 4.0])
def test_fault_slips_agree_exactly_with_the_per_block_slips(k_coupling):
    graph = faultnet.graphs.parallel_faults(3, 15, k_coupling=k_coupling)
    model = faultnet.CarlsonLanger(graph, k=16, sigma=0.01, alpha=1.0)
    res = faultnet.simulate(model, 1500, rng=8, record_slips=True, progress=False)
    fs = res.fault_slips
    assert list(fs.columns) == ["event", "fault", "slip"]
    expected = _sum_in_row_order(res, graph)
    got = {(int(e), f): s for e, f, s in fs.itertuples(index=False)}
    assert got == expected  # the same pairs, the same sums to the last bit
    per_event = fs.groupby("event").size().reindex(res.events["event"]).to_numpy()
    assert np.array_equal(per_event, res.events["n_faults"].to_numpy())
    assert (fs["event"].diff().dropna() >= 0).all()
    if k_coupling == 0.0:
        assert per_event.max() == 1
    else:
        assert per_event.max() > 1


def test_fault_slips_need_no_per_block_slips_and_survive_their_truncation():
    graph = faultnet.graphs.parallel_faults(2, 20, k_coupling=2.0)
    model = faultnet.CarlsonLanger(graph, k=16, sigma=0.01, alpha=1.0)
    full = faultnet.simulate(model, 800, rng=4, record_slips=True, progress=False)
    plain = faultnet.simulate(model, 800, rng=4, progress=False)
    assert plain.slips is None
    pd.testing.assert_frame_equal(plain.fault_slips, full.fault_slips)
    pd.testing.assert_frame_equal(plain.events, full.events)
    with pytest.warns(UserWarning, match="max_slip_rows"):
        cut = faultnet.simulate(model, 800, rng=4, record_slips=True, max_slip_rows=100,
                                progress=False)  # fmt: skip
    assert len(cut.slips) == 100 and cut.slips.attrs["truncated"]
    pd.testing.assert_frame_equal(cut.fault_slips, full.fault_slips)


def test_a_graph_without_faults_has_no_fault_slips():
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(20), k=16, sigma=0.01, alpha=1.0)
    assert faultnet.simulate(model, 50, rng=1, progress=False).fault_slips is None


def test_fault_slips_continue_across_advances():
    graph = faultnet.graphs.parallel_faults(2, 20, k_coupling=2.0)
    model = faultnet.CarlsonLanger(graph, k=16, sigma=0.01, alpha=1.0)
    whole = faultnet.simulate(model, 600, rng=2, progress=False).fault_slips
    sim = faultnet.Simulator(model, rng=2)
    parts = [sim.advance(n, progress=False).fault_slips for n in (1, 299, 300)]
    pd.testing.assert_frame_equal(pd.concat(parts, ignore_index=True), whole)


def test_the_jump_fraction_of_large_events_grows_with_the_coupling():
    """Two parallel rings coupled block by block: the share of the largest tenth of the
    events that rupture both faults is 0 without coupling springs and grows with them.

    Averaged over three seeds: one run's share at a given coupling moves by up to 0.1 from
    one seed to the next (at 1.0: 0.29 to 0.54 over seeds 1 to 5), more than the steps
    between the couplings above 0.3."""
    fractions = []
    for k_coupling in (0.0, 0.03, 0.3, 1.0):
        graph = faultnet.graphs.parallel_faults(2, 100, k_coupling=k_coupling, periodic=True)
        model = faultnet.CarlsonLanger(graph, k=16, sigma=0.01, alpha=1.0)
        shares = []
        for seed in (1, 2, 3):
            ev = faultnet.simulate(model, 15_000, rng=seed, progress=False).events
            ev = ev[ev["t"] > 2.0]
            large = ev[ev["M"] >= ev["M"].quantile(0.9)]
            shares.append(float(np.mean(large["n_faults"] > 1)))
        fractions.append(float(np.mean(shares)))
    assert fractions[0] == 0.0
    assert all(a + 0.02 < b for a, b in zip(fractions, fractions[1:], strict=False)), fractions
