"""Joins revealed by the crossings of an interpolated step (``carlson_langer.late_joins``).

A stuck block that a step's crossings push over the threshold crossed it inside the step,
where the step's scan did not list it: it is appended to the crossings (``_reveal``) and
placed where its force on its neighbours' paths reaches 1.  A block that stops and is over
the threshold again at the end of the step has the step taken again at half its length
(``take_again`` undoes the crossings first).  The events in which this happens are the
large ones, and they stay as accurate as the others.
"""

import numba as nb
import numpy as np

import faultnet
from faultnet.solver._kernels.bundles import Work, work_array
from faultnet.solver._kernels.carlson_langer.late_joins import _reveal, take_again
from faultnet.solver._kernels.carlson_langer.work import (
    ACTIVE,
    CAND,
    FLAG,
    FRONTIER,
    JOINING,
    LOC_NCAND,
    LOC_SIZE,
    N_IWORK,
    N_WORK,
    P2,
    SA,
    STOPPING,
    STUCK,
    SV,
    VS,
    D,
)
from faultnet.solver._kernels.layout import CNT_REVEALED_JOINS, CNT_SIZE
from faultnet.solver.step_size import omega2_max


@nb.njit(cache=False)
def _undo(ncand, W, IW):
    take_again(ncand, Work(W, IW, np.zeros(LOC_SIZE), np.zeros(CNT_SIZE, dtype=np.int64)))


@nb.njit(cache=False)
def _reveal_all(blocks, W, IW, loc, cnt):
    work = Work(W, IW, loc, cnt)
    ncand = np.int64(loc[LOC_NCAND])
    for j in blocks:
        ncand = _reveal(j, ncand, work)
    return ncand


def _arrays(n):
    W = work_array(n, N_WORK)
    IW = np.zeros((N_IWORK, n), dtype=np.int64)
    IW[FLAG, :] = STUCK
    return W, IW


def test_take_again_undoes_the_crossings():
    """Stops slip again; joins are stuck where they were, STUCK if they slipped before in the
    event (a displacement), FRONTIER if not; a dropped entry (-1) is left alone."""
    W, IW = _arrays(5)
    IW[FLAG, 0] = STOPPING
    IW[FLAG, 1:3] = JOINING
    W[1, D] = 0.25  # slipped earlier in the event
    W[1:3, P2] = (0.5, 0.125)  # their path ends, before the commit
    IW[FLAG, 3] = ACTIVE
    IW[CAND, :4] = (-2 - 0, 1, 2, -1)
    _undo(4, W, IW)
    assert list(IW[FLAG, :4]) == [ACTIVE, STUCK, FRONTIER, ACTIVE]
    assert W[1, P2] == 0.25 and W[2, P2] == 0.0


def test_reveal_appends_a_join_at_rest_at_the_end_of_the_step():
    """Each revealed block is appended to the crossings as a join at the step's end, at rest,
    until it is placed; the work counter counts it."""
    W, IW = _arrays(6)
    loc = np.zeros(LOC_SIZE)
    cnt = np.zeros(CNT_SIZE, dtype=np.int64)
    loc[LOC_NCAND] = 2.0  # the scan listed two crossings
    IW[CAND, :2] = (-2 - 5, 4)
    W[:3, SV] = W[:3, SA] = 0.5
    blocks = np.arange(3, dtype=np.int64)
    assert _reveal_all(blocks, W, IW, loc, cnt) == 5
    assert list(IW[CAND, :5]) == [-2 - 5, 4, 0, 1, 2]
    assert (IW[FLAG, blocks] == JOINING).all()
    assert (W[blocks, VS] == 1.0).all() and (W[blocks, SV] == 0.0).all()
    assert (W[blocks, SA] == 0.0).all()
    assert cnt[CNT_REVEALED_JOINS] == 3


def _events_with(counter, model, count, options=None, within=40_000):
    """Pre-event states of the first ``count`` events whose work ``counter`` is not 0, after a
    transient; the test fails if ``within`` events do not hold that many (the two tests below
    need about 7,400 and 1,500)."""
    state = faultnet.simulate(model, 3000, rng=7, progress=False, options=options).state
    states = []
    for _ in range(within):
        res = faultnet.simulate(model, 1, x0=state, progress=False, options=options)
        if res.metadata[counter] > 0:
            states.append(state)
            if len(states) == count:
                return states
        state = res.state
    raise AssertionError(f"{len(states)} of {within} events counted {counter}, not {count}")


def _errors(model, states, options=None):
    """|S / S_exact - 1| of each event, against the exact crossings at 1/16 of the default
    step, each event from its own pre-event state."""
    fine = faultnet.RunOptions(dt=faultnet.default_dt(model) / 16, crossings="exact")
    S = [
        [faultnet.simulate(model, 1, x0=s, progress=False, options=o).events.S.iloc[0]
         for s in states]
        for o in (fine, options)
    ]  # fmt: skip
    return np.abs(np.array(S[1]) / np.array(S[0]) - 1)


def test_events_with_revealed_joins_are_accurate():
    """On the periodic 12^2 lattice at the default rtol (1e-6), 20 events with joins that the
    crossings revealed (26-121 blocks).  Measured: 90th percentile 2.0e-6, worst 2.3e-5
    (with the revealed joins placed by bisection on the neighbours' paths, 1.4e-6 and 1.2e-5
    over 40 such events).  A revealed join placed at the first push of
    its neighbours rather than where its force reached 1 on the dense output made one of
    these events 2.7e-3 off."""
    g = faultnet.graphs.square_lattice(12, 12, periodic=True)
    model = faultnet.CarlsonLanger(g, k=16, sigma=0.01, alpha=1.0)
    err = _errors(model, _events_with("revealed_joins", model, 20))
    assert np.quantile(err, 0.9) <= 5e-6, err
    assert err.max() <= 1e-4, err


def test_a_stop_and_a_new_start_in_one_step_are_accurate():
    """On a ring of 200 at the long step of coefficient 0.5 (the statistics level's), 24
    events with a step taken again at half its length: a block stopped and started again
    within it.  Measured: 90th percentile 3.2e-5, worst 1.0e-4; with such a block started
    from rest at the end of the full step instead, 1.3e-3 and 4.4e-3."""
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(200), k=16, sigma=0.01, alpha=1.0)
    opts = faultnet.RunOptions(dt=0.5 / omega2_max(model) ** 0.5, crossings="interpolated")
    err = _errors(model, _events_with("retaken_steps", model, 24, opts), opts)
    assert np.quantile(err, 0.9) <= 1e-4, err
    assert err.max() <= 1e-3, err
