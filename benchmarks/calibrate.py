"""Calibrate the accuracy knob: the S error of each crossing treatment against the step.

For each workload (W1-W6, ``run.py``'s graphs and steady states) this takes
``--events`` consecutive multi-block events, runs each alone from its pre-event state
with faultnet at each step coefficient (step = coefficient / sqrt(omega2_max)) and each
crossing treatment ("exact", "interpolated"), and prints the 90th percentile of
``|S / S_true - 1|``; ``S_true`` is the exact treatment at 1/8 of
the default step (``yardstick.py``'s reference).  The last table is the worst workload
per coefficient: ``faultnet.solver.accuracy.CALIBRATION`` holds it::

    PYTHONPATH=. python benchmarks/calibrate.py             # W1-W6, 60 events, ~5 minutes
    PYTHONPATH=. python benchmarks/calibrate.py W1 --events 30
    PYTHONPATH=. python benchmarks/calibrate.py W4 W5 W6 --events 150 --treatments interpolated
    PYTHONPATH=. python benchmarks/calibrate.py W4 --treatments interpolated --coefficients 0.3 0.4
    PYTHONPATH=. python benchmarks/calibrate.py W4 --treatments interpolated --alpha 0.25
"""

from __future__ import annotations

import argparse
import json

import numpy as np
from run import SIGMA, WORKLOADS, K, _warm_state, build_graph
from yardstick import _fine_S, _fn_S, _pre_event_states

#: events of at least this many blocks get their own error line (they are few, and the
#: 90th percentile over all multi-block events is set by the small ones)
BIG = 10
COEFFICIENTS = {
    "exact": (0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8),
    "interpolated": (0.03, 0.05, 0.07, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8),
}


def errors(
    wid, count, transient_t=2.0, treatments=tuple(COEFFICIENTS), coefficients=None, alpha=None
):
    """{treatment: {coefficient: p90}} on ``count`` multi-block events of workload ``wid``.

    ``coefficients`` replaces :data:`COEFFICIENTS` for every treatment; ``alpha`` replaces
    the workload's alpha (its graph at another alpha).
    """
    import faultnet
    from faultnet.solver.accuracy import StepChoice
    from faultnet.solver.step_size import omega2_max

    alpha = WORKLOADS[wid][1] if alpha is None else alpha
    model = faultnet.CarlsonLanger(build_graph(wid), k=K, sigma=SIGMA, alpha=alpha)
    st, *_ = _warm_state(model, transient_t)
    start = faultnet.State.from_x(st.x - st.u, 0.0)
    states = _pre_event_states(model, start, count, 100 * count)
    ref = _fine_S(model, states)
    root = omega2_max(model) ** 0.5
    big = _n_blocks(model, states) >= BIG
    out = {}
    for crossings in treatments:
        out[crossings] = {}
        for c in coefficients or COEFFICIENTS[crossings]:
            err = np.abs(_fn_S(model, states, StepChoice(c / root, c, crossings)) / ref - 1.0)
            out[crossings][c] = float(np.quantile(err, 0.9))
            tail = (
                f"; {big.sum()} events of >= {BIG} blocks: 90% {np.quantile(err[big], 0.9):.2e}, "
                f"max {err[big].max():.2e}"
                if big.any()
                else ""
            )
            print(f"{wid} {crossings:12} {c:5.3f} {out[crossings][c]:.2e}{tail}", flush=True)
    return out


def _n_blocks(model, states):
    import faultnet

    return np.array(
        [
            int(faultnet.simulate(model, 1, x0=st, progress=False).events.n_blocks.iloc[0])
            for st in states
        ]
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("ids", nargs="*", help="workloads (default: W1..W6)")
    ap.add_argument("--events", type=int, default=60, help="multi-block events per workload")
    ap.add_argument("--json", help="write {workload: {treatment: {coef: p90}}} to this file")
    ap.add_argument(
        "--treatments", nargs="*", choices=list(COEFFICIENTS), default=list(COEFFICIENTS)
    )
    ap.add_argument("--coefficients", nargs="*", type=float, help="instead of the table's")
    ap.add_argument("--alpha", type=float, help="instead of each workload's alpha")
    args = ap.parse_args(argv)
    ids = args.ids or sorted(WORKLOADS)
    table = {
        wid: errors(
            wid,
            args.events,
            treatments=args.treatments,
            coefficients=args.coefficients,
            alpha=args.alpha,
        )
        for wid in ids
    }
    for crossings in args.treatments:
        coefs = args.coefficients or COEFFICIENTS[crossings]
        print(f"\n{crossings}: 90th percentile of |S/S_true - 1|")
        print(f"{'coef':>6} " + " ".join(f"{w:>8}" for w in ids) + f" {'worst':>8}")
        for c in coefs:
            vals = [table[w][crossings][c] for w in ids]
            print(f"{c:6.3f} " + " ".join(f"{v:8.1e}" for v in vals) + f" {max(vals):8.1e}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(table, fh)


if __name__ == "__main__":
    main()
