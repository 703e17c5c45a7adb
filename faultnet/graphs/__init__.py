"""Graph builders: chains, rings, square and triangular lattices, percolation clusters.

Each builder returns a networkx graph (or, for the largest lattices, a
:class:`~faultnet.SparseGraph`) that any faultnet model takes as its network of blocks.
"""

from faultnet.graphs.builders import (
    chain,
    percolation_threshold,
    ring,
    site_percolation,
    square_lattice,
    triangular_lattice,
)

__all__ = [
    "chain",
    "ring",
    "square_lattice",
    "triangular_lattice",
    "site_percolation",
    "percolation_threshold",
]
