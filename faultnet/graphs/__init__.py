"""Graph builders: chains, rings, square and triangular lattices, percolation clusters, and
networks of faults (parallel faults, step-overs, branches, any faults composed).

Each builder returns a networkx graph (or, for the largest lattices, a
:class:`~faultnet.SparseGraph`) that any faultnet model takes as its network of blocks.
The fault builders set the node attribute ``fault`` (the segment of each block) and give
the coupling springs between faults their own ``k``.
"""

from faultnet.graphs.builders import (
    chain,
    percolation_threshold,
    ring,
    site_percolation,
    square_lattice,
    triangular_lattice,
)
from faultnet.graphs.faults import branch, compose, parallel_faults, step_over

__all__ = [
    "chain",
    "ring",
    "square_lattice",
    "triangular_lattice",
    "site_percolation",
    "percolation_threshold",
    "parallel_faults",
    "step_over",
    "branch",
    "compose",
]
