"""Local regions (faultnet._kernels.local) against the whole-event treatment.

Inside large events the crossings of a step are handled in small regions
whose boundary follows the outer step's dense output.  The oracle is the
exact whole-event treatment (``LOCAL_REGIONS_FROM = inf``) at the same dt,
and the size of that treatment's own dt error (the same event at dt / 4):
the local regions must change the result by much less than the integrator's
own error, and must save work.
"""

import importlib

import numpy as np
import pytest

import faultnet

SIM = importlib.import_module("faultnet.simulate")


def _run(monkeypatch, model, state, n, local, dt=None, **kw):
    monkeypatch.setattr(SIM, "LOCAL_REGIONS_FROM", 8 if local else float("inf"))
    return faultnet.simulate(model, n, x0=state, dt=dt, progress=False, **kw)


def _compare_event(monkeypatch, model, state):
    loc = _run(monkeypatch, model, state, 1, True)
    glob = _run(monkeypatch, model, state, 1, False)
    fine = _run(monkeypatch, model, state, 1, False, dt=glob.dt / 4)
    diff = np.abs(loc.state.x - glob.state.x).max()
    own = np.abs(glob.state.x - fine.state.x).max()
    return loc, glob, diff, own


@pytest.fixture(scope="module")
def square40():
    """A 40 x 40 periodic lattice in its correlated regime (plate time >= 3)."""
    model = faultnet.CarlsonLanger(
        faultnet.graphs.square_lattice(40, 40, periodic=True), k=16, sigma=0.01, alpha=1.0
    )
    res = faultnet.simulate(model, 1000, rng=3, progress=False, record_slips=False)
    while res.events.t.iloc[-1] < 3.0:
        res = faultnet.simulate(model, 20000, x0=res.state, progress=False, record_slips=False)
    return model, res.state


def test_whole_lattice_event(monkeypatch):
    """Nearly uniform start: every block of a 24 x 24 lattice slips in one event."""
    model = faultnet.CarlsonLanger(
        faultnet.graphs.square_lattice(24, 24, periodic=True), k=16, sigma=0.01, alpha=1.0
    )
    x = np.random.default_rng(5).uniform(0.0, 3e-5, model.n)
    state = faultnet.State.from_x(x)
    loc, glob, diff, own = _compare_event(monkeypatch, model, state)
    assert int(glob.events.n_blocks.iloc[0]) == model.n
    assert loc.metadata["local_steps"] > 20
    assert glob.metadata["local_steps"] == 0
    assert int(loc.events.n_blocks.iloc[0]) == model.n
    assert diff < 0.5 * own, (diff, own)
    assert abs(loc.events.S.iloc[0] / glob.events.S.iloc[0] - 1.0) < 1e-9


def test_large_correlated_events(monkeypatch, square40):
    """The first three events of >= 100 blocks after the transient, one by one."""
    model, state = square40
    monkeypatch.setattr(SIM, "LOCAL_REGIONS_FROM", float("inf"))
    run = faultnet.simulate(model, 3000, x0=state, progress=False, record_slips=False)
    big = np.flatnonzero(run.events.n_blocks.to_numpy() >= 100)[:3]
    assert big.size == 3
    saved = 0
    for e in big:
        before = _run(monkeypatch, model, state, int(e), False, record_slips=False).state
        loc, glob, diff, own = _compare_event(monkeypatch, model, before)
        assert loc.events.n_blocks.iloc[0] == glob.events.n_blocks.iloc[0]
        assert loc.events.hypocenter.iloc[0] == glob.events.hypocenter.iloc[0]
        assert diff < 0.5 * own, (e, diff, own)
        assert loc.metadata["local_steps"] > 0
        saved += glob.metadata["block_steps"] - loc.metadata["block_steps"]
    assert saved > 0


def test_catalog_follows_whole_event_treatment(monkeypatch, square40):
    """A run of 1500 events: same hypocentres, slips within the chaotic drift."""
    model, state = square40
    loc = _run(monkeypatch, model, state, 1500, True, record_slips=False)
    glob = _run(monkeypatch, model, state, 1500, False, record_slips=False)
    assert loc.metadata["local_steps"] > 0
    a, b = loc.events, glob.events
    # chaotic: tiny differences after a large event grow; compare the first 300
    np.testing.assert_array_equal(a.hypocenter[:300], b.hypocenter[:300])
    np.testing.assert_array_equal(a.n_blocks[:300], b.n_blocks[:300])
    np.testing.assert_allclose(a.S[:300], b.S[:300], rtol=1e-4)


def test_rk4_never_uses_local_regions(monkeypatch):
    model = faultnet.CarlsonLanger(
        faultnet.graphs.square_lattice(16, 16, periodic=True), k=16, sigma=0.01, alpha=1.0
    )
    x = np.random.default_rng(5).uniform(0.0, 3e-5, model.n)
    res = _run(monkeypatch, model, faultnet.State.from_x(x), 1, True, method="rk4")
    assert res.metadata["local_steps"] == 0
    assert int(res.events.n_blocks.iloc[0]) == model.n
