"""``kelvin_kernel``: a term of the plate or the dashpots is compiled for a ``KelvinGraph`` only.

For a plain ``Graph`` a call is its first argument, and the kernel is not typed at all, so that
a plain model's kernels hold none of that code (the cold compile's IR statements).
"""

import numba as nb
import numpy as np

from faultnet.solver._kernels.bundles import Graph, KelvinGraph, graph_bundle
from faultnet.solver._kernels.jit import kelvin_kernel


@kelvin_kernel
def _plate_pull(f, graph):
    """``f`` plus the plate's velocity: a stand-in for a term of the plate."""
    return f + graph.nu


@kelvin_kernel(plain=lambda h, graph, n: (h, -1))
def _plate_step(h, graph, n):
    """A stand-in for a term whose plain result is not its first argument (the graph not last)."""
    return h * graph.nu, n


@nb.njit
def _force(f, graph):
    return _plate_pull(f, graph)


@nb.njit
def _step(h, graph, n):
    return _plate_step(h, graph, n)


def _triangle(nu=0.0, eta=None):
    indptr = np.array([0, 2, 4, 6])
    indices = np.array([1, 2, 0, 2, 0, 1])
    ones = np.ones(3)
    return graph_bundle(indptr, indices, np.ones(6), 3 * ones, 0.99 * ones, ones, nu=nu, eta=eta)


def test_a_plain_graph_gets_the_first_argument_untyped():
    plain, moving, viscous = _triangle(), _triangle(nu=0.25), _triangle(eta=np.full(6, 0.1))
    assert type(plain) is Graph
    assert type(moving) is KelvinGraph and type(viscous) is KelvinGraph
    assert _force(1.0, plain) == 1.0
    assert _force(1.0, moving) == 1.25
    assert _force(1.0, viscous) == 1.0  # nu = 0 there: the term runs and adds nothing
    # the kernel was compiled for the KelvinGraph only (not for the plain Graph)
    signatures = _plate_pull.kernel.signatures
    assert signatures
    assert all(sig[-1].instance_class is KelvinGraph for sig in signatures)


def test_a_plain_result_of_its_own_and_the_graph_anywhere():
    plain, moving = _triangle(), _triangle(nu=0.5)
    assert _step(2.0, plain, 7) == (2.0, -1)
    assert _step(2.0, moving, 7) == (1.0, 7)
    assert _plate_step(2.0, plain, 7) == (2.0, -1)  # in Python too
    assert _plate_step(2.0, moving, 7) == (1.0, 7)
    signatures = _plate_step.kernel.signatures
    assert signatures
    assert all(sig[1].instance_class is KelvinGraph for sig in signatures)


def test_python_calls_take_the_same_branches():
    assert _plate_pull(1.0, _triangle()) == 1.0
    assert _plate_pull(1.0, _triangle(nu=0.5)) == 1.5
    assert _plate_pull.__wrapped__(1.0, _triangle(nu=0.5)) == 1.5
