"""The yardstick: a careful but unoptimised event-driven RK4, timed on this machine.

The event-rate targets of the benchmark suite are stated against "a careful
but unoptimised event-driven RK4 implementation on this machine at the same
accuracy".  This script is that implementation, written plainly and
independently of ``faultnet._kernels`` (it uses faultnet only to build the
workload graphs and their steady states), so the premise of the targets can be
checked instead of assumed:

- *event-driven*: between events every block is stuck and the plate jumps to
  the next failure (an argmax over the blocks' static forces, which only change
  for the blocks an event touched);
- *careful*: inside an event only the slipping blocks are integrated, with
  classical RK4 at a fixed step ``DT_COEFFICIENT / sqrt(omega2_max)``; a stop
  (v -> 0) or a join (force -> 1) inside a step is located on the step's
  cubic Hermite interpolant and the step is redone up to it (again if an
  earlier crossing shows up in the shortened step), so the scheme keeps its
  order;
- *unoptimised*: no cached solo slips, no dense output, no local regions, no
  tournament tree.

The small helpers (force, acceleration) are inlined by Numba (``inline=
"always"``): as plain calls each one passed its arrays with a reference-count
update, and the baseline ran 2.5x slower (4,315 against 10,713 events/s on W1).
That is a Numba pitfall, not a design choice, so the yardstick avoids it.

``check`` compares the three named single events (one block, two blocks,
a 10-block ring; see ``docs/guide/accuracy.rst``) with a dt -> 0 reference
(``tests/reference.py``, SciPy DOP853 at rtol 1e-13) and with faultnet; ``time``
runs a workload from the same steady state as ``run.py`` and prints events/s
next to faultnet's default DP5 (with ``--rk4`` also faultnet's RK4, at its own
step ``DT_COEFFICIENT["rk4"]`` = 0.08), the codes alternating ``--repeat``
times::

    python benchmarks/baseline_rk4.py check
    python benchmarks/baseline_rk4.py time W1 W2 W3 W4 W5 W6 --events 100000 --repeat 3

``typical W1 --coefficients 0.12 0.08`` compares the errors of S on typical
multi-block events (the named three are not typical: the baseline at 0.12 is
about five times less accurate than faultnet on a W1 event); ``time
--coefficient 0.08`` then times the baseline at the step that matches
faultnet's typical accuracy.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numba as nb
import numpy as np

#: RK4 step = DT_COEFFICIENT / sqrt(omega2_max): the largest of 0.02, 0.04, ... that keeps
#: the three named events within 1e-6 (``check``: 0.12 gives 1.0e-7, 4.8e-8, 8.5e-7; 0.14
#: puts the 10-block ring at 1.6e-6), the most favourable step for the baseline
DT_COEFFICIENT = 0.12
MAX_STEPS = 10_000_000


@nb.njit(cache=True, inline="always")
def _force(i, x, u, indptr, indices, kval):
    """Static force on block i: springs to its neighbours and to the plate at u."""
    s = u - x[i]
    for p in range(indptr[i], indptr[i + 1]):
        s += kval[p] * (x[indices[p]] - x[i])
    return s


@nb.njit(cache=True, inline="always")
def _accel(i, x, v, u, indptr, indices, kval, oms, cfr):
    """Acceleration of slipping block i with velocity v (friction floored for v < 0 probes)."""
    den = max(1.0 + cfr[i] * v, 0.5)
    return _force(i, x, u, indptr, indices, kval) - oms[i] / den


@nb.njit(cache=True)
def _rk4(h, act, nact, x, v, a, xs, xn, vn, an, kv, ka, u, indptr, indices, kval, oms, cfr):
    """One RK4 step of the active blocks from (x, v, a) to (xn, vn, an).

    Stage positions are written to ``xs`` (which equals x on every stuck block)
    after each whole stage, so every block sees its neighbours at the same stage;
    on return ``xs`` holds the end positions (xn on the active blocks).
    """
    for q in range(nact):  # stage 2
        i = act[q]
        kv[q, 0], ka[q, 0] = v[i], a[i]
        kv[q, 1] = v[i] + 0.5 * h * a[i]
    for q in range(nact):
        i = act[q]
        xs[i] = x[i] + 0.5 * h * kv[q, 0]
    for q in range(nact):
        ka[q, 1] = _accel(act[q], xs, kv[q, 1], u, indptr, indices, kval, oms, cfr)
    for s in range(2, 4):  # stages 3 and 4
        c = 0.5 * h if s == 2 else h
        for q in range(nact):
            i = act[q]
            xs[i] = x[i] + c * kv[q, s - 1]
            kv[q, s] = v[i] + c * ka[q, s - 1]
        for q in range(nact):
            ka[q, s] = _accel(act[q], xs, kv[q, s], u, indptr, indices, kval, oms, cfr)
    for q in range(nact):
        i = act[q]
        xn[i] = x[i] + h / 6.0 * (kv[q, 0] + 2.0 * kv[q, 1] + 2.0 * kv[q, 2] + kv[q, 3])
        vn[i] = v[i] + h / 6.0 * (ka[q, 0] + 2.0 * ka[q, 1] + 2.0 * ka[q, 2] + ka[q, 3])
        xs[i] = xn[i]
    for q in range(nact):
        i = act[q]
        an[i] = _accel(i, xs, vn[i], u, indptr, indices, kval, oms, cfr)


@nb.njit(cache=True)
def _hermite_root(g0, d0, g1, d1):
    """A root in [0, 1] of the cubic Hermite interpolant (values g, slopes d per step).

    Bisection on the sign change between g0 and g1: when the cubic has three roots
    there, the one found need not be the first (rare; the redone step re-checks).
    """
    lo, hi = 0.0, 1.0
    for _ in range(60):  # bisection: the sign change is between g0 and g1
        th = 0.5 * (lo + hi)
        t2, t3 = th * th, th * th * th
        g = (
            (2 * t3 - 3 * t2 + 1) * g0
            + (t3 - 2 * t2 + th) * d0
            + (-2 * t3 + 3 * t2) * g1
            + (t3 - t2) * d1
        )
        if (g > 0.0) == (g0 > 0.0):
            lo = th
        else:
            hi = th
    return hi


@nb.njit(cache=True)
def _earliest(h, act, nact, flag, x, v, a, xs, vn, an, u, indptr, indices, kval):
    """Earliest stop or join inside the step just taken: (theta, block, is_join); -1 if none.

    ``xs``: every block's position at the end of the step.
    """
    best, who, join = 2.0, -1, False
    for q in range(nact):
        i = act[q]
        if vn[i] <= 0.0 < v[i]:
            th = _hermite_root(v[i], h * a[i], vn[i], h * an[i])
            if th < best:
                best, who, join = th, i, False
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if flag[j] == 1:
                continue
            f1 = _force(j, xs, u, indptr, indices, kval)
            if f1 < 1.0:
                continue
            f0 = _force(j, x, u, indptr, indices, kval)
            d0 = d1 = 0.0
            for r in range(indptr[j], indptr[j + 1]):
                d0 += kval[r] * v[indices[r]]
                d1 += kval[r] * vn[indices[r]]
            th = _hermite_root(f0 - 1.0, h * d0, f1 - 1.0, h * d1) if f0 < 1.0 else 0.0
            if th < best:
                best, who, join = th, j, True
    return best, who, join


@nb.njit(cache=True)
def _event(hyp, u, h, x, v, a, xs, xn, vn, an, x0, flag, act, slipped, kv, ka, arr):
    """One event from hypocentre ``hyp``: (S, blocks that slipped, steps, block-steps)."""
    indptr, indices, kval, oms, cfr = arr
    nact, nslip, steps, bsteps = 1, 1, 0, 0
    act[0], slipped[0], flag[hyp], x0[hyp] = hyp, hyp, 1, x[hyp]
    v[hyp], vn[hyp] = 0.0, 0.0
    a[hyp] = _accel(hyp, x, 0.0, u, indptr, indices, kval, oms, cfr)
    while nact > 0:
        hs = h
        who, join = -1, False
        for _ in range(8):  # a step, or redone up to its earliest crossing
            _rk4(hs, act, nact, x, v, a, xs, xn, vn, an, kv, ka, u, indptr, indices, kval, oms, cfr)
            steps += 1
            bsteps += nact
            th, w2, j2 = _earliest(
                hs, act, nact, flag, x, v, a, xs, vn, an, u, indptr, indices, kval
            )
            if w2 < 0 or (w2 == who and th > 1.0 - 1e-6):
                break
            who, join, hs = w2, j2, th * hs
        if steps > MAX_STEPS:
            return -1.0, nslip, steps, bsteps
        for q in range(nact):  # commit
            i = act[q]
            x[i], v[i], a[i] = xn[i], vn[i], an[i]
            xs[i] = x[i]
        if who >= 0 and join:
            j = who
            if flag[j] == 0:  # first slip in this event (a block may stop and slip again)
                slipped[nslip], x0[j] = j, x[j]
                nslip += 1
            flag[j], act[nact], v[j], vn[j] = 1, j, 0.0, 0.0
            a[j] = _accel(j, x, 0.0, u, indptr, indices, kval, oms, cfr)
            nact += 1
        q = 0
        while q < nact:  # stops: v <= 0 and decelerating (a block that just joined accelerates)
            i = act[q]
            if (i == who and not join) or (v[i] <= 0.0 and a[i] <= 0.0):
                v[i], vn[i], flag[i] = 0.0, 0.0, 2
                nact -= 1
                act[q] = act[nact]
            else:
                q += 1
    S = 0.0
    for r in range(nslip):
        S += x[slipped[r]] - x0[slipped[r]]
    return S, nslip, steps, bsteps


@nb.njit(cache=True)
def run_events(n_events, x, u, h, indptr, indices, kval, oms, cfr, out):
    """``n_events`` events from x and plate u; rows of ``out``: u, S, blocks, steps, block-steps.

    Returns the plate position after the last event (x is updated in place), or
    -1.0 when an event ran past ``MAX_STEPS``.
    """
    n = x.shape[0]
    arr = (indptr, indices, kval, oms, cfr)
    c = np.empty(n)  # static force minus the plate position
    for i in range(n):
        c[i] = _force(i, x, 0.0, indptr, indices, kval)
    v, a, xn, vn, an, x0 = np.zeros((6, n))  # rows of one block of memory
    xs = x.copy()
    flag = np.zeros(n, np.int64)  # 0 untouched, 1 slipping, 2 slipped and stuck again
    act, slipped = np.empty(n, np.int64), np.empty(n, np.int64)
    kv, ka = np.empty((n, 4)), np.empty((n, 4))
    for e in range(n_events):
        hyp = np.argmax(c)
        u = max(u, 1.0 - c[hyp])
        S, nslip, steps, bsteps = _event(
            hyp, u, h, x, v, a, xs, xn, vn, an, x0, flag, act, slipped, kv, ka, arr
        )
        if S < 0.0:
            return -1.0
        out[e, 0], out[e, 1], out[e, 2], out[e, 3], out[e, 4] = u, S, nslip, steps, bsteps
        for r in range(nslip):  # the static forces of the blocks that moved and their neighbours
            i = slipped[r]
            flag[i] = 0
            c[i] = _force(i, x, 0.0, indptr, indices, kval)
            for p in range(indptr[i], indptr[i + 1]):
                c[indices[p]] = _force(indices[p], x, 0.0, indptr, indices, kval)
    return u


# ---------------------------------------------------------------------------------------------
# Python side: the model's arrays, the accuracy check, the timing
# ---------------------------------------------------------------------------------------------


def model_arrays(model):
    """CSR arrays and friction constants of a faultnet model, in the kernel's form."""
    adj = model.adjacency.tocsr()
    oms = 1.0 - model.sigma_values  # per-block arrays of the model
    return (
        adj.indptr.astype(np.int64),
        adj.indices.astype(np.int64),
        adj.data.astype(np.float64),
        oms,
        2.0 * model.alpha_values / oms,
    )


def step_size(model, coefficient=DT_COEFFICIENT):
    """RK4 step: ``coefficient / sqrt(omega2_max)`` (faultnet's bound on the top frequency)."""
    from faultnet.simulate import omega2_max

    return coefficient / math.sqrt(omega2_max(model))


def one_event(model, x0, coefficient=DT_COEFFICIENT):
    """S of the first event from displacements ``x0`` (plate at 0)."""
    out = np.zeros((1, 5))
    x = np.array(x0, dtype=np.float64)
    run_events(1, x, 0.0, step_size(model, coefficient), *model_arrays(model), out)
    return out[0, 1]


def named_events():
    """The three named single events of the accuracy checks: (label, model, x0)."""
    import faultnet

    g = faultnet.graphs
    cases = [
        ("one block, alpha 2", g.chain(1), 2.0, [0.0]),
        ("two blocks, alpha 2, x2 - x1 = 0.001", g.chain(2), 2.0, [0.0, 0.001]),
        ("10-block ring, alpha 1.5", g.ring(10), 1.5, np.linspace(0, 0.009, 10) ** 2 * 50),
    ]
    return [
        (label, faultnet.CarlsonLanger(gr, k=16, sigma=0.01, alpha=a), np.asarray(x, float))
        for label, gr, a, x in cases
    ]


def check(coefficients):
    """Relative error of S against the dt -> 0 reference for each named event and coefficient."""
    import faultnet

    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
    from reference import reference_events

    print(
        "| event | reference S | faultnet (default dt) | "
        + " | ".join(f"baseline {c}" for c in coefficients)
        + " |"
    )
    print("|---" * (3 + len(coefficients)) + "|")
    for label, model, x0 in named_events():
        ref, _ = reference_events(
            model.adjacency.toarray(), model.sigma_values, model.alpha_values, x0, 1,
            rtol=1e-13, atol=1e-16,
        )  # fmt: skip
        s_ref = ref[0]["S"]
        _, row = faultnet.slip_event(model, x0)
        errs = [abs(one_event(model, x0, c) / s_ref - 1.0) for c in coefficients]
        print(
            f"| {label} | {s_ref:.10f} | {abs(row['S'] / s_ref - 1):.1e} | "
            + " | ".join(f"{e:.1e}" for e in errs) + " |"
        )  # fmt: skip


def typical(model, state, count, coefficients, reference=0.015):
    """S errors on typical events: the first ``count`` multi-block events from ``state``.

    Each event starts from faultnet's own pre-event state; faultnet (default
    dt) and the baseline at each coefficient are compared with the baseline
    at ``reference`` (an RK4 error (0.12 / 0.015)^4 = 4,096 times smaller than
    at 0.12).  Returns {"faultnet" or coefficient: array of relative errors}
    and the events' sizes.
    """
    import faultnet

    arrays = model_arrays(model)
    steps = {c: step_size(model, c) for c in (*coefficients, reference)}
    errs = {"faultnet": [], **{c: [] for c in coefficients}}
    sizes = []
    for _ in range(1000 * count):
        if len(sizes) == count:
            break
        res = faultnet.simulate(model, 1, x0=state, progress=False, record_slips=False)
        row = res.events.iloc[0]
        if row.n_blocks >= 2:
            off = math.floor(state.u)
            s = {}
            for c, h in steps.items():
                out = np.zeros((1, 5))
                run_events(1, state.x - off, state.u - off, h, *arrays, out)
                s[c] = out[0, 1]
            errs["faultnet"].append(abs(row.S / s[reference] - 1.0))
            for c in coefficients:
                errs[c].append(abs(s[c] / s[reference] - 1.0))
            sizes.append(int(row.n_blocks))
        state = res.state
    if len(sizes) < count:
        raise RuntimeError(f"only {len(sizes)} multi-block events in {1000 * count} events")
    return {k: np.array(v) for k, v in errs.items()}, np.array(sizes)


def _print_typical(wid, count, coefficients, transient_t=2.0):
    errs, sizes = typical(*_steady_state(wid, transient_t), count, coefficients)
    print(f"{wid}: {count} consecutive multi-block events ({sizes.min()}-{sizes.max()} blocks)")
    print("| code | median error | 90% | largest | median, events of >= 20 blocks |")
    print("|---|---|---|---|---|")
    big = sizes >= 20
    for name, e in errs.items():
        label = name if isinstance(name, str) else f"baseline at {name}"
        med_big = f"{np.median(e[big]):.1e}" if big.any() else "-"
        print(
            f"| {label} | {np.median(e):.1e} | {np.quantile(e, 0.9):.1e} | {e.max():.1e} "
            f"| {med_big} |"
        )


def _steady_state(wid, transient_t):
    """The workload's model and its state after the transient (as run.py starts its runs)."""
    from events_ab import _model
    from run import _warm_state

    model = _model(wid)
    return model, _warm_state(model, transient_t)[0]


def time_workload(wid, events, transient_t, repeat, rk4=False, coefficient=DT_COEFFICIENT):
    """events/s of the baseline and of faultnet from the same steady state.

    The codes alternate ``repeat`` times (this VM drifts by 15-25% within an hour);
    each keeps its best round.  ``rk4``: time faultnet's RK4 as well.
    ``coefficient``: the baseline's step coefficient.
    """
    import faultnet

    model, state = _steady_state(wid, transient_t)
    arrays = model_arrays(model)
    h = step_size(model, coefficient)
    off = math.floor(state.u)
    best_b = best_f = best_r = math.inf
    run_events(1, state.x - off, state.u - off, h, *arrays, np.zeros((1, 5)))  # compile first
    for _ in range(repeat):
        x = state.x - off
        out = np.zeros((events, 5))
        tic = time.perf_counter()
        u = run_events(events, x, state.u - off, h, *arrays, out)
        best_b = min(best_b, time.perf_counter() - tic)
        if u < 0:
            raise SystemExit(f"{wid}: an event ran past {MAX_STEPS} steps")
        res = faultnet.simulate(model, events, x0=state, progress=False, record_slips=False)
        best_f = min(best_f, res.metadata["wall_time_s"])
        if rk4:
            r4 = faultnet.simulate(
                model, events, x0=state, progress=False, record_slips=False, method="rk4"
            )
            best_r = min(best_r, r4.metadata["wall_time_s"])
    ev = res.events
    return {
        "workload": wid,
        "events": events,
        "baseline_ev_s": events / best_b,
        "faultnet_ev_s": events / best_f,
        "faultnet_rk4_ev_s": events / best_r if rk4 else None,
        "baseline_ns_per_block_step": 1e9 * best_b / out[:, 4].sum(),
        "faultnet_ns_per_block_step": 1e9 * best_f / res.metadata["block_steps"],
        "baseline_mean_blocks": float(out[:, 2].mean()),
        "faultnet_mean_blocks": float(ev.n_blocks.mean()),
        "baseline_steps_per_event": float(out[:, 3].mean()),
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("check", help="accuracy of the three named events")
    c.add_argument("--coefficients", type=float, nargs="+", default=[0.08, 0.06, 0.04])
    t = sub.add_parser("time", help="events/s of the baseline and faultnet")
    t.add_argument("workloads", nargs="+")
    t.add_argument("--events", type=int, default=100_000)
    t.add_argument("--transient-t", type=float, default=2.0)
    t.add_argument("--repeat", type=int, default=3, help="alternating rounds (best kept)")
    t.add_argument("--rk4", action="store_true", help="time faultnet's RK4 too")
    t.add_argument(
        "--coefficient", type=float, default=DT_COEFFICIENT, help="the baseline's step coefficient"
    )
    ty = sub.add_parser("typical", help="S errors on typical events of a workload")
    ty.add_argument("workload")
    ty.add_argument("--count", type=int, default=150)
    ty.add_argument("--coefficients", type=float, nargs="+", default=[0.12, 0.08])
    args = ap.parse_args(argv)
    if args.cmd == "check":
        check(args.coefficients)
        return
    if args.cmd == "typical":
        _print_typical(args.workload, args.count, args.coefficients)
        return
    print(
        "| workload | baseline RK4 ev/s | faultnet ev/s (DP5) | ratio | faultnet RK4 ev/s "
        "| ns per block-step (baseline, faultnet) | blocks/event (baseline, faultnet) "
        "| baseline steps/event |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for wid in args.workloads:
        r = time_workload(
            wid, args.events, args.transient_t, args.repeat, args.rk4, args.coefficient
        )
        rk4 = "-" if r["faultnet_rk4_ev_s"] is None else f"{r['faultnet_rk4_ev_s']:,.0f}"
        print(
            f"| {wid} | {r['baseline_ev_s']:,.0f} | {r['faultnet_ev_s']:,.0f} | "
            f"{r['faultnet_ev_s'] / r['baseline_ev_s']:.1f} | "
            f"{rk4} | "
            f"{r['baseline_ns_per_block_step']:.0f}, {r['faultnet_ns_per_block_step']:.0f} | "
            f"{r['baseline_mean_blocks']:.2f}, {r['faultnet_mean_blocks']:.2f} | "
            f"{r['baseline_steps_per_event']:.1f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
