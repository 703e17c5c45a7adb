"""Which of the engine's code paths each calibrated setting runs, from steady states.

For each workload and accuracy level the table gives the entry kernel and crossing treatment
that ``RunOptions(rtol=...)`` chooses, and the share of the work each path carried:
``solo`` (events that were one free block's cached slip), ``interp`` (crossings located by
interpolation, per event), ``partial`` (block-steps of exact crossings' partial steps, as a
share of all block-steps).  A path
whose column is zero everywhere is run by no calibrated setting.

    python benchmarks/code_paths.py                 # 20,000 events per row
    python benchmarks/code_paths.py --events 5000   # quicker
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import faultnet  # noqa: E402
from faultnet import graphs  # noqa: E402

RTOLS = {"precise": 1e-6, "statistics": 2e-5}


def workloads(rng):
    cluster = graphs.site_percolation(
        graphs.square_lattice(150, 150), graphs.percolation_threshold("square"), rng=rng
    )
    return {
        "ring 2000, alpha 1": (graphs.ring(2000), 1.0),
        "ring 2000, alpha 0.2": (graphs.ring(2000), 0.2),
        "ring 2000, alpha 2.5": (graphs.ring(2000), 2.5),
        "square 150^2 periodic, alpha 1": (graphs.square_lattice(150, 150, periodic=True), 1.0),
        "square 150^2 periodic, alpha 0.2": (graphs.square_lattice(150, 150, periodic=True), 0.2),
        "square 150^2 periodic, alpha 2.5": (graphs.square_lattice(150, 150, periodic=True), 2.5),
        "percolation cluster 150^2, alpha 0.9": (cluster, 0.9),
    }


def row(name, graph, alpha, level, n_events):
    model = faultnet.CarlsonLanger(graph, alpha=alpha)
    options = faultnet.RunOptions(rtol=RTOLS[level])
    sim = faultnet.Simulator(model, rng=1, options=options)
    while sim.state.u < 2.0:  # to a steady state
        sim.advance(2000, progress=False)
    md = sim.advance(n_events, progress=False).metadata
    steps = max(md["block_steps"], 1)
    return (
        f"| {name} | {level} | {options.entry(model).replace('run_events_', '')} "
        f"| {md['crossings']} | {md['solo_events'] / n_events:.2f} "
        f"| {md['interpolated_crossings'] / n_events:.1f} "
        f"| {md['partial_block_steps'] / steps:.3f} "
    )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--events", type=int, default=20_000)
    args = parser.parse_args(argv)
    print("| workload | level | entry | crossings | solo | interp | partial |")
    print("|---|---|---|---|---|---|---|")
    for name, (graph, alpha) in workloads(rng=7).items():
        for level in RTOLS:
            print(row(name, graph, alpha, level, args.events), flush=True)


if __name__ == "__main__":
    main()
