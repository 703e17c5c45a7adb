"""simulate / slip_event: catalog, recordings, exact continuation, bad input, failures."""

import numba
import numpy as np
import pandas as pd
import pytest

import faultnet
from faultnet import EventTooLongError, InvalidParameterError, NumericalInstabilityError


@pytest.fixture(scope="module")
def ring_model():
    return faultnet.CarlsonLanger(faultnet.graphs.ring(40), k=16, sigma=0.01, alpha=1.0)


def test_catalog_columns_and_consistency(ring_model):
    res = faultnet.simulate(ring_model, 2000, rng=2, progress=False, record_slips=True)
    ev = res.events
    for col in ["event", "t", "duration", "n_blocks", "S", "M", "hypocenter"]:
        assert col in ev.columns
    assert ev.event.tolist() == list(range(2000))
    assert np.all(np.diff(ev.t) >= 0)
    assert np.all(ev.S > 0) and np.all(np.isfinite(ev.M))
    np.testing.assert_allclose(ev.M, np.log(ev.S))
    slips = res.slips
    assert (slips.slip >= 0).all()
    per_event = slips.groupby("event").slip.sum()
    np.testing.assert_allclose(per_event.to_numpy(), ev.S.to_numpy(), rtol=1e-12)
    assert (slips.groupby("event").size().to_numpy() == ev.n_blocks.to_numpy()).all()
    # after every event no block is above the static threshold
    forces = ring_model.forces(res.x, res.u)
    assert forces.max() <= 1.0 + 1e-9
    # the hypocenter slipped
    first = slips.groupby("event").node.apply(set)
    assert all(h in first[e] for e, h in zip(ev.event, ev.hypocenter, strict=True))


def test_seed_recorded_and_reproducible(ring_model):
    a = faultnet.simulate(ring_model, 300, rng=None, progress=False)
    entropy = a.metadata["seed_entropy"]
    assert entropy is not None and a.seed == entropy
    b = faultnet.simulate(ring_model, 300, rng=np.random.SeedSequence(entropy), progress=False)
    pd.testing.assert_frame_equal(a.events, b.events)
    c = faultnet.simulate(ring_model, 300, rng=7, progress=False)
    assert c.metadata["seed_entropy"] == 7
    assert not np.array_equal(a.x, c.x)


def test_exact_continuation_including_alpha_change(ring_model):
    whole = faultnet.simulate(ring_model, 1500, rng=5, progress=False)
    first = faultnet.simulate(ring_model, 700, rng=5, progress=False)
    second = faultnet.simulate(ring_model, 800, x0=first, progress=False)
    joined = pd.concat([first.events, second.events], ignore_index=True)
    pd.testing.assert_frame_equal(whole.events, joined, check_exact=True)
    np.testing.assert_array_equal(whole.x, second.x)
    assert whole.u == second.u
    # continuing with another alpha starts from the same state
    other = ring_model.with_params(alpha=2.0)
    cont = faultnet.simulate(other, 10, x0=first.state, progress=False)
    fresh = faultnet.simulate(other, 10, x0=first.state.copy(), progress=False)
    pd.testing.assert_frame_equal(cont.events, fresh.events)
    assert cont.events.t.iloc[0] >= first.u


def test_long_run_keeps_precision():
    # u in the thousands: the re-centred frame keeps slips as accurate as at u ~ 0
    one = faultnet.CarlsonLanger(faultnet.graphs.chain(1), sigma=0.01, alpha=2.0)
    early = faultnet.simulate(one, 3, x0=[0.0], progress=False)
    late = faultnet.simulate(one, 3, x0=faultnet.State.from_x([5000.0], 5000.0), progress=False)
    np.testing.assert_allclose(late.events.S, early.events.S, rtol=1e-13)
    run = faultnet.simulate(one, 4000, x0=[0.0], progress=False)
    assert run.u > 5000
    np.testing.assert_allclose(run.events.S.iloc[-1], early.events.S.iloc[-1], rtol=1e-13)


def test_profiles_and_traces():
    model = faultnet.CarlsonLanger(faultnet.graphs.chain(2), k=16, sigma=0.01, alpha=2.0)
    res = faultnet.simulate(
        model, 5, x0=[0.0, 0.00142], progress=False, record_profiles=True, trace_nodes=[0, 1]
    )
    assert res.profiles.shape == (5, 2)
    np.testing.assert_array_equal(res.profiles[-1], res.x)
    tr = res.traces
    assert set(tr.columns) == {"event", "time", "node", "x", "v"}
    first = tr[tr.event == 0]
    assert first.time.min() == 0.0
    assert first.time.max() == pytest.approx(res.events.duration.iloc[0])
    assert (first.v >= -1e-9).all()
    x_end = first[first.time == first.time.max()].sort_values("node").x.to_numpy()
    np.testing.assert_allclose(x_end, res.profiles[0], rtol=1e-12)
    assert not tr.attrs["truncated"]
    small = faultnet.simulate(
        model, 5, x0=[0.0, 0.00142], progress=False, trace_nodes=[1], max_trace_rows=10
    )
    assert len(small.traces) == 10 and small.traces.attrs["truncated"]


def test_slip_event_returns_state_and_row():
    model = faultnet.CarlsonLanger(faultnet.graphs.chain(2), k=16, sigma=0.01, alpha=2.0)
    state, row = faultnet.slip_event(model, [0.0, 0.005])
    assert row["n_blocks"] == 1 and row["hypocenter"] == 0
    d_next = state.x[1] - state.x[0]
    # the delayed block catches up by one single-block slip (paper: 0.0038)
    assert d_next == pytest.approx(0.005 - row["S"], rel=1e-12)
    state2, row2 = faultnet.slip_event(model, state)
    assert row2["event"] == 1


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n_events": 0}, "n_events.*0"),
        ({"n_events": -5}, "n_events.*-5"),
        ({"n_events": 2.5}, "n_events.*2.5"),
        ({"dt": 0.0}, "dt.*0"),
        ({"dt": -1e-3}, "dt.*-0.001"),
        ({"dt": float("nan")}, "dt.*nan"),
        ({"dt": 5.0}, "dt=5.*stability"),
        ({"x0": np.zeros(3)}, r"x0.*\(4,\).*\(3,\)"),
        ({"x0": [0.0, np.nan, 0.0, np.inf]}, r"x0.*non-finite.*\[1, 3\]"),
        ({"trace_nodes": [99]}, "trace_nodes.*99"),
        ({"options": {"max_event_duration": 0}}, "max_event_duration"),
        ({"options": {"dt": 1e-12}}, "dt=1e-12 is too small"),
        ({"options": {"smoothing": 1}}, r"unknown run option.*smoothing"),
        ({"options": "fast"}, "options must be a RunOptions"),
        ({"method": "euler"}, r"method must be one of \['dopri5'\]; got 'euler'"),
        ({"method": "rk4"}, r"method='rk4' was removed.*'dopri5'"),
        ({"options": {"local_regions_from": 8}}, r"local_regions_from was removed.*crossings="),
    ],
)
def test_bad_run_input(kwargs, match):
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(4))
    args = {"n_events": 10}
    args.update(kwargs)
    with pytest.raises(InvalidParameterError, match=match):
        faultnet.simulate(model, progress=False, **args)


def test_bad_model_type():
    with pytest.raises(InvalidParameterError, match="CarlsonLanger"):
        faultnet.simulate("ring", 10)


def test_runaway_and_too_long_events_raise_clear_errors():
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10), k=16, sigma=0.01, alpha=2.0)
    with pytest.raises(NumericalInstabilityError, match="reduce dt"):
        faultnet.simulate(model, 100, rng=1, progress=False, options={"max_velocity": 1e-3})
    with pytest.raises(EventTooLongError, match="max_event_duration") as info:
        faultnet.simulate(model, 100, rng=1, progress=False, options={"max_event_duration": 0.05})
    assert "nu" not in str(info.value)


def test_an_event_that_a_moving_plate_keeps_going_names_nu():
    """At nu = 0.05 a ring of 100 slips without end from its fifth event on; the error says
    that the plate's velocity is the likely cause, not only the step."""
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(100), nu=0.05)
    with pytest.raises(EventTooLongError, match=r"with nu = 0.05 the plate drives the blocks"):
        faultnet.simulate(model, 50, rng=1, progress=False, options={"max_event_duration": 50})


def test_slip_recording_is_bounded():
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(30), k=16, sigma=0.01, alpha=1.0)
    full = faultnet.simulate(model, 500, rng=4, progress=False, record_slips=True)
    assert not full.slips.attrs["truncated"]
    with pytest.warns(UserWarning, match="max_slip_rows"):
        cut = faultnet.simulate(
            model, 500, rng=4, progress=False, record_slips=True, max_slip_rows=100
        )
    assert len(cut.slips) == 100 and cut.slips.attrs["truncated"]
    pd.testing.assert_frame_equal(cut.slips, full.slips.iloc[:100])
    pd.testing.assert_frame_equal(cut.events, full.events)


def _ring(alpha=1.0, n=40):
    return faultnet.CarlsonLanger(faultnet.graphs.ring(n), k=16, sigma=0.01, alpha=alpha)


def test_simulator_chunks_equal_one_run():
    model = _ring()
    whole = faultnet.simulate(model, 900, rng=2, progress=False)
    sim = faultnet.Simulator(model, rng=2)
    parts = [sim.advance(n, progress=False) for n in (1, 299, 600)]
    chunked = pd.concat([p.events for p in parts], ignore_index=True)
    pd.testing.assert_frame_equal(chunked, whole.events)
    assert np.array_equal(sim.state.z, whole.state.z) and sim.state.n_events == 900
    assert parts[-1].metadata["first_event"] == 300
    assert parts[-1].metadata["seed_entropy"] == 2  # every chunk records the seed


def test_set_model_equals_a_fresh_run_from_the_state():
    model = _ring(alpha=0.5)
    sim = faultnet.Simulator(model, rng=4)
    sim.advance(400, progress=False)
    state = sim.state
    new = model.with_params(alpha=2.0)
    sim.set_model(new)
    kept = sim.advance(300, progress=False)
    fresh = faultnet.simulate(new, 300, x0=state, progress=False)
    pd.testing.assert_frame_equal(kept.events, fresh.events)
    assert kept.dt == fresh.dt != faultnet.default_dt(model)  # the step follows alpha
    with pytest.raises(InvalidParameterError, match="same blocks"):
        sim.set_model(_ring(n=41))
    # the same blocks, other springs: the kernels would read the old springs' layout
    chain = faultnet.CarlsonLanger(faultnet.graphs.chain(model.n), alpha=2.0)
    assert list(chain.nodes) == list(model.nodes)
    with pytest.raises(InvalidParameterError, match="same springs"):
        sim.set_model(chain)
    sim.set_model(new.with_params(k=9.0))  # other spring constants are fine


def test_chunk_metadata_follows_set_model_and_is_each_chunks_own():
    model = _ring(alpha=0.5)
    sim = faultnet.Simulator(model, rng=4)
    first = sim.advance(50, progress=False)
    first.metadata["options"]["rtol"] = "changed by a user"
    first.metadata["alpha"] = -1.0
    second = sim.advance(50, progress=False)
    assert second.metadata["alpha"] == 0.5 and second.metadata["options"]["rtol"] == 1e-6
    sim.set_model(model.with_params(alpha=2.0))
    third = sim.advance(50, progress=False)
    fresh = faultnet.simulate(model.with_params(alpha=2.0), 50, x0=second.state, progress=False)
    assert third.metadata["alpha"] == 2.0 and third.metadata["dt"] == fresh.metadata["dt"]
    assert third.metadata["dt"] != second.metadata["dt"]


def test_options_are_recorded_and_change_results():
    model = _ring()
    exact = faultnet.RunOptions(crossings="exact")
    sim = faultnet.Simulator(model, rng=1, options=exact, solo_cache=False)
    res = sim.advance(200, progress=False)
    assert res.metadata["options"] == exact.to_dict() and res.metadata["solo_cache"] is False
    assert res.metadata["options"]["crossings"] == "exact"
    assert faultnet.RunOptions.from_dict(res.metadata["options"]) == exact
    assert res.metadata["solo_events"] == 0
    assert faultnet.simulate(model, 200, rng=1, progress=False).metadata["solo_events"] > 0


@numba.njit(cache=True)
def _never_compiled(x):
    return x + 1


def test_cache_is_cold():
    from faultnet.solver._kernels.cache import is_cold as _cache_is_cold

    assert _cache_is_cold(_never_compiled)  # nothing in its on-disk cache
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10))
    faultnet.simulate(model, 2, rng=1, progress=False)
    from faultnet.solver import _kernels

    entry = getattr(_kernels, faultnet.RunOptions().entry(model))
    assert not _cache_is_cold(entry)  # just compiled
    assert not _cache_is_cold(_never_compiled.py_func)  # no JIT: never cold


def test_progress_bar_says_when_the_first_run_compiles(monkeypatch, capsys):
    from faultnet.solver import simulator as engine

    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10))
    faultnet.simulate(model, 2, rng=1, progress=False)  # compiled and cached from here on
    capsys.readouterr()
    faultnet.simulate(model, 5, rng=1, progress=True)
    assert engine.COMPILING_LABEL not in capsys.readouterr().err
    from faultnet.solver import _kernels

    monkeypatch.setattr(_kernels, "is_cold", lambda kernel: True)  # a cold cache
    faultnet.simulate(model, 5, rng=1, progress=True)
    assert engine.COMPILING_LABEL in capsys.readouterr().err


def test_trace_nodes_takes_one_label_alone():
    """One node label, also a lattice's (i, j), traces that block; a scalar that is no label is
    an error naming trace_nodes."""
    import networkx as nx

    grid = faultnet.CarlsonLanger(nx.grid_2d_graph(4, 4))
    one = faultnet.simulate(grid, 5, rng=1, progress=False, trace_nodes=(0, 1))
    listed = faultnet.simulate(grid, 5, rng=1, progress=False, trace_nodes=[(0, 1)])
    assert list(one.traces["node"].unique()) == [(0, 1)]
    pd.testing.assert_frame_equal(one.traces, listed.traces)
    ring = faultnet.CarlsonLanger(faultnet.graphs.ring(10))
    assert list(
        faultnet.simulate(ring, 3, rng=1, progress=False, trace_nodes=4).traces.node.unique()
    ) == [4]
    with pytest.raises(faultnet.InvalidParameterError, match="trace_nodes must be node labels"):
        faultnet.simulate(ring, 3, rng=1, progress=False, trace_nodes=99)


def test_collector_paused_during_kernel_calls_only():
    """collector_paused turns the collector off and back on, also on errors; simulate leaves
    it as the caller had it."""
    import gc

    from faultnet.solver.arrays import collector_paused

    assert gc.isenabled()
    with collector_paused():
        assert not gc.isenabled()
    assert gc.isenabled()
    with pytest.raises(RuntimeError), collector_paused():
        raise RuntimeError("inside a kernel call")
    assert gc.isenabled()
    ring = faultnet.CarlsonLanger(faultnet.graphs.ring(10))
    faultnet.simulate(ring, 5, rng=1, progress=False)
    assert gc.isenabled()
    gc.disable()  # a caller that turned it off keeps it off
    try:
        with collector_paused():
            pass
        faultnet.simulate(ring, 5, rng=1, progress=False)
        assert not gc.isenabled()
    finally:
        gc.enable()
