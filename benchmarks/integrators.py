"""Would another integrator need fewer derivative evaluations per event at the same accuracy?

    python benchmarks/integrators.py                # 60 events of W1 from its steady state
    python benchmarks/integrators.py --events 200

Takes W1 (ring N = 2000, k = 16, sigma = 0.01, alpha = 1) after a transient to plate time 2,
runs events one at a time with faultnet, and integrates every event with more than one slipping
block again with SciPy on a window of 61 blocks around its hypocentre (the blocks next to the
window held still; events reaching the window's edge are skipped): DOP853 at rtol 1e-12 as the
dt -> 0 reference, then error-controlled Dormand-Prince 5(4) (``RK45``) and DOP853 at several
tolerances, with SciPy's own event location.  Prints, per scheme, the derivative evaluations
over all events (faultnet: 6 per step, partial steps to crossings included) and the median and
largest relative error of the slip sum S against the reference.  Needs ``tests/reference.py``
(the friction law of the independent reference implementation).
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np
from scipy.integrate import solve_ivp

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(HERE, "..", "tests")]

import reference  # noqa: E402
import run as suite  # noqa: E402

import faultnet  # noqa: E402

N, K, SIGMA, ALPHA, HALF = 2000, 16.0, 0.01, 1.0, 30


class Window:
    """One event on the 2 HALF + 1 blocks around its hypocentre, the rest of the ring held."""

    def __init__(self, x, hyp):
        idx = np.arange(hyp - HALF, hyp + HALF + 1) % N
        self.x0 = x[idx]
        self.left, self.right = x[(hyp - HALF - 1) % N], x[(hyp + HALF + 1) % N]
        self.n = idx.size
        self.u = 0.0
        self.u = 1.0 - self.forces(self.x0)[HALF]  # the hypocentre is at threshold

    def forces(self, x):
        f = self.u - x - 2.0 * K * x
        f[1:] += K * x[:-1]
        f[:-1] += K * x[1:]
        f[0] += K * self.left
        f[-1] += K * self.right
        return f

    def slip(self, method, rtol):
        """Integrate the event segment by segment; (S, derivative evaluations)."""
        n, x, v = self.n, self.x0.copy(), np.zeros(self.n)
        slipping = self.forces(x) >= 1.0
        slipping[HALF] = True
        nfev = 0
        t = 0.0
        while slipping.any():
            fixed = slipping.copy()

            def rhs(_, y, fixed=fixed):
                acc = self.forces(y[:n]) - reference.friction(y[n:], SIGMA, ALPHA)
                return np.concatenate([np.where(fixed, y[n:], 0.0), np.where(fixed, acc, 0.0)])

            def crossing(i, fixed=fixed):
                if fixed[i]:
                    f = lambda _, y: y[n + i]  # noqa: E731 - stick: v falls to 0
                    f.direction = -1
                else:
                    f = lambda _, y: self.forces(y[:n])[i] - 1.0  # noqa: E731 - join
                    f.direction = 1
                f.terminal = True
                return f

            y0 = np.concatenate([x, v])
            events = [crossing(i) for i in range(n)]
            sol = solve_ivp(rhs, (t, 1e3), y0, method=method, rtol=rtol, atol=rtol * 1e-3,
                            events=events)  # fmt: skip
            nfev += sol.nfev
            t, x, v = sol.t[-1], sol.y[:n, -1].copy(), np.maximum(sol.y[n:, -1], 0.0)
            f = self.forces(x)
            static = f - reference.friction(0.0, SIGMA, ALPHA)
            for i in range(n):
                fired = len(sol.t_events[i]) > 0 and sol.t_events[i][-1] == t
                if not slipping[i] and (fired or f[i] >= 1.0):
                    slipping[i], v[i] = True, 0.0  # a join (located to the root's tolerance)
                elif slipping[i] and (fired or v[i] <= 0.0) and static[i] <= 0.0:
                    slipping[i], v[i] = False, 0.0
        if x[0] != self.x0[0] or x[-1] != self.x0[-1]:
            return None, nfev  # reached the window's edge
        return float((x - self.x0).sum()), nfev


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--events", type=int, default=60, help="W1 events to look at (default 60)")
    args = ap.parse_args(argv)
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(N), k=K, sigma=SIGMA, alpha=ALPHA)
    state = suite._warm_state(model, 2.0)[0]
    tols = {"RK45": (1e-5, 1e-6, 1e-7, 1e-8), "DOP853": (1e-6, 1e-7, 1e-8, 1e-9)}
    ours, theirs, skipped = [], {}, 0
    for _ in range(args.events):
        res = faultnet.simulate(model, 1, x0=state, progress=False)
        ev = res.events.iloc[0]
        if ev.n_blocks >= 2:
            win = Window(np.asarray(state.x, dtype=float), int(ev.hypocenter))
            s_ref, _ = win.slip("DOP853", 1e-12)
            if s_ref is None:
                skipped += 1
            else:
                ours.append((6 * int(ev.n_steps), abs(ev.S / s_ref - 1)))
                for method, rtols in tols.items():
                    for rtol in rtols:
                        s, nfev = win.slip(method, rtol)
                        theirs.setdefault((method, rtol), []).append((nfev, abs(s / s_ref - 1)))
        state = res.state
    print(f"{len(ours)} W1 events with >= 2 slipping blocks ({skipped} wider than the window)")
    print(f"{'scheme':34} {'evaluations':>11} {'median err':>10} {'max err':>9}")
    rows = [("faultnet DP5, fixed dt (default)", ours)]
    rows += [(f"SciPy {m}, rtol {r:.0e}", v) for (m, r), v in theirs.items()]
    for name, vals in rows:
        evals, err = np.array(vals).T
        print(f"{name:34} {evals.sum():>11,.0f} {np.median(err):>10.1e} {err.max():>9.1e}")


if __name__ == "__main__":
    main()
