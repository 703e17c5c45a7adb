"""faultnet against the independent yardstick simulator, at equal accuracy.

The yardstick is ``clsim.py`` in ``../shared/yardstick`` (or ``--yardstick DIR``): a plainly
written Carlson-Langer code that integrates the slipping blocks with classical RK4 at a fixed
step and treats every stop and join on the step's cubic Hermite interpolant without redoing the
step.  Both codes run the same graph (faultnet's CSR, as built by ``run.py``'s workloads) from
the same steady state (``run.py``'s transient to plate time 2, expressed relative to the plate),
in alternating rounds; each code keeps its fastest round and the range is printed too.

Two accuracy levels, as in the issue that defines the comparison:

=========== ======= ================ =========================================
level        rtol    yardstick dt     faultnet
=========== ======= ================ =========================================
precise      1e-6    0.0035           ``faultnet.solver.accuracy.step_for_rtol(model, 1e-6)``
statistics   2e-5    0.01             ``faultnet.solver.accuracy.step_for_rtol(model, 2e-5)``
=========== ======= ================ =========================================

Accuracy: the 90th percentile of ``|S / S_true - 1|`` over ``--accuracy-events`` consecutive
multi-block events of the steady state, each run alone from its own pre-event state by both
codes; ``S_true`` is faultnet's exact-crossing treatment at 1/8 of its
default step (the check column gives the yardstick at dt 0.0035 / 4 against the same reference,
an independent confirmation of it).

Run by hand (never a timed test)::

    PYTHONPATH=. python benchmarks/yardstick.py W1 W4            # about a minute per workload
    PYTHONPATH=. python benchmarks/yardstick.py --events 100000 --rounds 3  # the full table
    PYTHONPATH=. python benchmarks/yardstick.py W4 --transient-t 2 3 4  # pooled over 3 states

The event mix of a steady state's window moves the yardstick's events/s by up to 40% on the
lattices (its work grows with the events' size; faultnet's per-event work less so): several
``--transient-t`` values pool the codes' times over as many steady states.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import time

import numpy as np
from run import SIGMA, WORKLOADS, K, _warm_state, build_graph

#: (level, rtol, yardstick dt)
LEVELS = (("precise", 1e-6, 0.0035), ("statistics", 2e-5, 0.01))
#: the reference is faultnet's exact treatment at this fraction of its default step
FINE = 1.0 / 8.0


def _clsim(path):
    if path not in sys.path:
        sys.path.insert(0, path)
    return importlib.import_module("clsim")


def _options(model, rtol):
    """simulate() keyword arguments and kernel options for ``rtol``."""
    from faultnet.solver.accuracy import step_for_rtol

    return step_for_rtol(model, rtol)


def _run_options(opts):
    """The RunOptions of a StepChoice (its step and crossing treatment)."""
    import faultnet

    return faultnet.RunOptions(dt=opts.dt, crossings=opts.crossings)


def _run_faultnet(model, x0, events, opts):
    import faultnet

    tic = time.perf_counter()
    res = faultnet.simulate(model, events, x0=x0, progress=False, options=_run_options(opts))
    return time.perf_counter() - tic, res


def _pre_event_states(model, start, count, max_events):
    """Pre-event states of the first ``count`` multi-block events from ``start`` (default dt)."""
    import faultnet

    states, state = [], start
    for _ in range(max_events):
        res = faultnet.simulate(model, 1, x0=state, progress=False, record_slips=False)
        if int(res.events.n_blocks.iloc[0]) > 1:
            states.append(state)
            if len(states) == count:
                return states
        state = res.state
    raise SystemExit(f"only {len(states)} multi-block events in {max_events}; lower the count")


def _fine_S(model, states):
    import faultnet

    fine = faultnet.RunOptions(dt=faultnet.default_dt(model) * FINE, crossings="exact")
    return np.array(
        [
            float(faultnet.simulate(model, 1, x0=st, progress=False, options=fine).events.S.iloc[0])
            for st in states
        ]
    )


def _yard_S(clsim, graph, model, states, dt):
    alpha = float(np.max(model.alpha_values))
    out = []
    for st in states:
        y = clsim.Sim(graph, k=K, sigma=SIGMA, alpha=alpha, dt=dt, x0=st.x - st.u)
        out.append(float(y.run(1)["S"][0]))
    return np.array(out)


def _fn_S(model, states, opts):
    return np.array([float(_run_faultnet(model, st, 1, opts)[1].events.S.iloc[0]) for st in states])


def _p90(S, ref):
    return float(np.quantile(np.abs(S / ref - 1.0), 0.9))


def workload(wid, args, clsim, transient_t):
    """Time and accuracy of both codes on one workload at both levels, from the steady state at
    plate time ``transient_t``; rows printed."""
    import faultnet

    alpha = WORKLOADS[wid][1]
    model = faultnet.CarlsonLanger(build_graph(wid), k=K, sigma=SIGMA, alpha=alpha)
    adj = model.adjacency
    if not np.all(adj.data == K):
        raise SystemExit(f"{wid}: the yardstick needs uniform springs k = {K}")
    graph = (adj.indptr.astype(np.int64), adj.indices.astype(np.int64))
    st, n_trans, t_end, wall = _warm_state(model, transient_t)
    x_rel = st.x - st.u  # relative to the plate, which both codes then put at 0
    start = faultnet.State.from_x(x_rel, 0.0)
    print(f"{wid}: {model.n} blocks, transient {n_trans} events to t = {t_end:.2f} ({wall:.0f} s)")

    states = _pre_event_states(model, start, args.accuracy_events, 100 * args.accuracy_events)
    ref = _fine_S(model, states)
    check = _p90(_yard_S(clsim, graph, model, states, LEVELS[0][2] / 4), ref)
    rows = []
    for level, rtol, ydt in LEVELS:
        if args.levels and level not in args.levels:
            continue
        opts = _options(model, rtol)
        err_f = _p90(_fn_S(model, states, opts), ref)
        err_y = _p90(_yard_S(clsim, graph, model, states, ydt), ref)
        # compile / warm both, then alternate
        _run_faultnet(model, start, 10, opts)
        clsim.Sim(graph, K, SIGMA, alpha, ydt, x_rel).run(10)
        tf, ty, work = [], [], {}
        for _ in range(args.rounds):
            wall_f, res = _run_faultnet(model, start, args.events, opts)
            tf.append(args.events / wall_f)
            md = res.metadata
            work = {k: md.get(k, 0) / args.events for k in ("block_steps", "partial_block_steps")}
            y = clsim.Sim(graph, K, SIGMA, alpha, ydt, x_rel)
            tic = time.perf_counter()
            out = y.run(args.events)
            ty.append(args.events / (time.perf_counter() - tic))
            ybs = float(out["bsteps"].sum()) / args.events
        row = dict(
            wid=wid,
            t=transient_t,
            level=level,
            rtol=rtol,
            fn=max(tf),
            fn_all=tf,
            yard=max(ty),
            yard_all=ty,
            err_f=err_f,
            err_y=err_y,
            check=check,
            opts=opts,
            ydt=ydt,
            fn_bs=work["block_steps"],
            fn_part=work["partial_block_steps"],
            yard_bs=ybs,
        )
        rows.append(row)
        _print_row(row)
    return rows


HEADER = (
    f"{'wl':3} {'level':10} {'faultnet ev/s':>24} {'90% err':>8} {'yardstick ev/s':>24} "
    f"{'90% err':>8} {'ratio':>5} {'fn bs/ev':>8} {'part':>5} {'yd bs/ev':>8} "
    f"{'check':>7}  faultnet options"
)


def _print_row(r):
    def rate(best, all_):
        return f"{best:,.0f} ({min(all_) / 1e3:.1f}-{max(all_) / 1e3:.1f}k)"

    print(
        f"{r['wid']:3} {r['level']:10} {rate(r['fn'], r['fn_all']):>24} {r['err_f']:8.1e} "
        f"{rate(r['yard'], r['yard_all']):>24} {r['err_y']:8.1e} {r['fn'] / r['yard']:5.2f} "
        f"{r['fn_bs']:8.0f} {r['fn_part'] / max(r['fn_bs'], 1e-300):5.2f} "
        f"{r['yard_bs']:8.0f} {r['check']:7.1e}  "
        f"dt {r['opts'].dt:.4g} (coef {r['opts'].coefficient:.3g}), {r['opts'].crossings}; "
        f"state at t = {r['t']:g}",
        flush=True,
    )


def _print_pooled(rows, events):
    """Each code's events/s over all the steady states together (its best round's time at each
    state summed), their ratio, and the largest 90% error over the states."""
    print(f"\npooled over the steady states at plate times {sorted({r['t'] for r in rows})}")
    print(f"{'wl':3} {'level':10} {'faultnet ev/s':>14} {'90% err':>8} {'yardstick ev/s':>15} "
          f"{'90% err':>8} {'ratio':>5}")  # fmt: skip
    for key in dict.fromkeys((r["wid"], r["level"]) for r in rows):
        group = [r for r in rows if (r["wid"], r["level"]) == key]
        fn = len(group) * events / sum(events / r["fn"] for r in group)
        yd = len(group) * events / sum(events / r["yard"] for r in group)
        err_f = max(r["err_f"] for r in group)
        err_y = max(r["err_y"] for r in group)
        print(f"{key[0]:3} {key[1]:10} {fn:14,.0f} {err_f:8.1e} {yd:15,.0f} {err_y:8.1e} "
              f"{fn / yd:5.2f}")  # fmt: skip


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("ids", nargs="*", help="workloads (default: W1..W6)")
    ap.add_argument("--events", type=int, default=30_000, help="timed events per round")
    ap.add_argument("--rounds", type=int, default=2, help="alternating rounds (best counts)")
    ap.add_argument("--accuracy-events", type=int, default=60, help="multi-block events")
    ap.add_argument("--levels", nargs="*", choices=[lv[0] for lv in LEVELS])
    ap.add_argument(
        "--transient-t",
        type=float,
        nargs="+",
        default=[2.0],
        help="plate time(s) of the steady state(s); with several, a pooled table follows",
    )
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument(
        "--yardstick",
        default=os.path.join(here, "..", "..", "shared", "yardstick"),
        help="directory of clsim.py (default ../shared/yardstick of the checkout's parent)",
    )
    args = ap.parse_args(argv)
    ids = args.ids or sorted(WORKLOADS)
    bad = [w for w in ids if w not in WORKLOADS]
    if bad:
        ap.error(f"unknown workloads {bad}; choose from {sorted(WORKLOADS)}")
    if args.events < 1 or args.rounds < 1 or args.accuracy_events < 1:
        ap.error("--events, --rounds and --accuracy-events must be >= 1")
    path = os.path.abspath(args.yardstick)
    if not os.path.exists(os.path.join(path, "clsim.py")):
        ap.error(f"no clsim.py in {path}; pass --yardstick DIR")
    clsim = _clsim(path)
    import faultnet

    print(f"faultnet from {os.path.dirname(faultnet.__file__)}")
    print(
        "ev/s: best of the alternating rounds (range); 90% err: 90th percentile of |S/S_true - 1| "
        f"over {args.accuracy_events} multi-block events; check: yardstick at dt 0.000875 "
        "against the reference\n"
    )
    print(HEADER)
    rows = []
    for wid in ids:
        for t in args.transient_t:
            rows += workload(wid, args, clsim, t)
    print("\n" + HEADER)
    for r in rows:
        _print_row(r)
    if len(args.transient_t) > 1:
        _print_pooled(rows, args.events)


if __name__ == "__main__":
    main()
