"""Graph specifications: short strings (``ring:2000``) and graph files -> models.

A *graph spec* names a graph in one token, as on the command line and in
sweep files::

    chain:N[:reach=R][:kc=K]     open chain of N blocks
    ring:N[:reach=R][:kc=K]      periodic ring of N blocks (N >= 3); with reach=R each
                                 block has springs to its R nearest neighbours on each
                                 side (R <= (N - 1) // 2 on a ring, N - 1 on a chain),
                                 with kc=K each spring has k = K / 2R
    square:RxC[:periodic|:fixed] square lattice, R rows x C columns (square:L = LxL);
                                 a free boundary, or periodic, or fixed (frame springs)
    triangular:RxC[:periodic|:fixed]  triangular lattice
    percolation:LATTICE:RxC[:periodic|:fixed]:p=P[:largest|:all][:prune][:seed=S]
                                 site-diluted square or triangular lattice; P is a
                                 probability or ``pc`` (the lattice's threshold)
    file:PATH, PATH.graphml, PATH.json
                                 a custom asperity graph: GraphML or node-link JSON

Graph files may carry the model parameters: a graph attribute ``k``,
``sigma`` or ``alpha`` sets the default for the whole graph, an edge
attribute ``k`` sets one spring and node attributes ``sigma`` / ``alpha`` set
one block (see :class:`faultnet.CarlsonLanger`).  Parameters given
explicitly (``--k`` / ``k=``) override the graph-level defaults, never the
per-edge or per-node values.

The percolation disorder is random.  Unless the spec fixes it with
``seed=S``, it is drawn from the run's seed: from the SeedSequence
``SeedSequence(entropy, spawn_key=(*spawn_key, 0))`` (:func:`graph_seed`),
so one ``--seed`` reproduces both the graph and the run.

Parsing a spec string (:class:`GraphSpec`, :func:`parse_graph_spec`) is the
job of ``faultnet.runs.spec_parser``; this module builds graphs and models from
specs and hashes them, and re-exports the parser's names.

>>> from faultnet.runs.specs import build_graph, parse_graph_spec
>>> parse_graph_spec("square:16x16:periodic").canonical
'square:16x16:periodic'
>>> G = build_graph("percolation:square:20x20:p=0.7", rng=1)
>>> G.graph["p"]
0.7
"""

from __future__ import annotations

import json
import os

import networkx as nx
import numpy as np

from faultnet import graphs
from faultnet._validate import seed_sequence
from faultnet.exceptions import GraphSpecError, InvalidParameterError
from faultnet.runs.spec_parser import GRAPH_SPEC_FORMS, GraphSpec, parse_graph_spec

__all__ = [
    "DEFAULT_PARAMS",
    "MODELS",
    "OFC_DEFAULT_K",
    "GRAPH_SPEC_FORMS",
    "GraphSpec",
    "GraphSpecError",
    "build_graph",
    "build_model",
    "graph_seed",
    "parse_graph_spec",
    "read_graph_file",
]

#: model defaults used when neither the caller nor the graph file sets a value
DEFAULT_PARAMS = {"k": 16.0, "sigma": 0.01, "alpha": 1.0}
#: the models a spec run builds: ``--model`` of ``faultnet simulate``, ``model`` of a sweep
MODELS = ("carlson-langer", "ofc")
#: the OFC automaton's spring constant where none is given (alpha = 0.2 on a fixed square
#: lattice)
OFC_DEFAULT_K = 1.0


def graph_seed(seq):
    """SeedSequence for a random graph, derived from a run's SeedSequence ``seq``.

    It is the child ``SeedSequence(seq.entropy, spawn_key=(*seq.spawn_key, 0))``:
    independent of the stream that draws the run's initial state.
    """
    return np.random.SeedSequence(seq.entropy, spawn_key=(*seq.spawn_key, 0))


#: square lattices with at least this many blocks are built as a
#: :class:`faultnet.SparseGraph` (a networkx graph costs ~1 kB per node)
SPARSE_LATTICE_BLOCKS = 250_000


def _lattice(kind, rows, cols, boundary, sparse_ok=False):
    if kind == "square":
        sparse = sparse_ok and rows * cols >= SPARSE_LATTICE_BLOCKS
        return graphs.square_lattice(rows, cols, sparse=sparse, boundary=boundary)
    return graphs.triangular_lattice(rows, cols, boundary=boundary)


def build_graph(spec, rng=None):
    """Build the graph a spec names.

    Parameters
    ----------
    spec : str or GraphSpec
    rng : None, int or SeedSequence
        Seed of the run; only percolation graphs without ``seed=`` use it
        (through :func:`graph_seed`).  None draws fresh entropy.

    Returns
    -------
    networkx.Graph or SparseGraph
        ``G.graph["spec"]`` holds the canonical spec.  Square lattices of
        :data:`SPARSE_LATTICE_BLOCKS` blocks or more come as a
        :class:`faultnet.SparseGraph`.
    """
    gs = parse_graph_spec(spec)
    try:
        if gs.kind == "chain":
            G = graphs.chain(gs.size[0], reach=gs.reach, k_c=gs.k_c)
        elif gs.kind == "ring":
            G = graphs.ring(gs.size[0], reach=gs.reach, k_c=gs.k_c)
        elif gs.kind in ("square", "triangular"):
            G = _lattice(gs.kind, *gs.size, gs.boundary, sparse_ok=True)
        elif gs.kind == "percolation":
            parent = _lattice(gs.lattice, *gs.size, gs.boundary)
            if gs.seed is not None:
                seq = np.random.SeedSequence(gs.seed)
            else:
                seq = graph_seed(seed_sequence(rng))
            G = graphs.site_percolation(
                parent, gs.p, rng=seq, keep=gs.keep, prune_isolated=gs.prune
            )
            G.graph["seed_entropy"] = seq.entropy
            G.graph["seed_spawn_key"] = list(seq.spawn_key)
        else:
            G = read_graph_file(gs.path)
    except (ValueError, TypeError) as exc:
        if isinstance(exc, GraphSpecError):
            raise
        raise GraphSpecError(f"graph spec {gs.text or gs.canonical!r}: {exc}") from exc
    G.graph["spec"] = gs.canonical
    return G


def read_graph_file(path) -> nx.Graph:
    """Read a GraphML or node-link JSON graph (``.graphml`` / ``.json``).

    GraphML node ids that are all integers become ``int`` labels.  Node-link
    JSON may use ``"edges"`` or the older ``"links"`` key; a missing
    ``"multigraph"`` key means a simple graph.  Graph attributes ``k``,
    ``sigma``, ``alpha`` are kept in ``G.graph`` (see :func:`build_model`).
    """
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise GraphSpecError(f"graph file {path!r} does not exist")
    low = path.lower()
    try:
        if low.endswith(".json"):
            with open(path, encoding="utf-8") as fh:
                data = json.load(fh)
            if not isinstance(data, dict) or "nodes" not in data:
                raise GraphSpecError(
                    f"graph file {path!r}: expected node-link JSON (an object with 'nodes' "
                    "and 'edges' lists, as written by networkx.node_link_data)"
                )
            edges = "links" if "links" in data and "edges" not in data else "edges"
            data.setdefault(edges, [])
            try:
                G = nx.node_link_graph(data, directed=False, multigraph=False, edges=edges)
            except TypeError:  # networkx < 3.4 names the keyword "link"
                G = nx.node_link_graph(data, directed=False, multigraph=False, link=edges)
        elif low.endswith(".graphml"):
            try:
                G = nx.read_graphml(path, node_type=int)
            except (ValueError, TypeError):
                G = nx.read_graphml(path)
        else:
            raise GraphSpecError(f"graph file {path!r}: the name must end in .graphml or .json")
    except GraphSpecError:
        raise
    except Exception as exc:  # parser errors of json / lxml / networkx
        raise GraphSpecError(f"cannot read graph file {path!r}: {exc}") from exc
    if G.is_directed() or G.is_multigraph():
        raise GraphSpecError(
            f"graph file {path!r} holds a {'directed' if G.is_directed() else 'multi'}graph; "
            "springs are symmetric, so write an undirected simple graph"
        )
    G = nx.Graph(G)
    G.graph.setdefault("name", f"file:{os.path.basename(path)}")
    return G


def _graph_param(G, name):
    if name not in G.graph:
        return None
    value = G.graph[name]
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InvalidParameterError(
            f"graph attribute {name!r} must be a number; got {value!r}"
        ) from None
    return value


def build_model(spec, *, k=None, sigma=None, alpha=None, rng=None, model=None, ofc_alpha=None):
    """Build a :class:`faultnet.CarlsonLanger` model, or an :class:`faultnet.OFC` automaton,
    from a graph spec.

    ``k``, ``sigma``, ``alpha``: explicit values win, then graph-level
    attributes of a graph file, then :data:`DEFAULT_PARAMS`.  ``model="ofc"`` builds the
    automaton: with ``ofc_alpha`` (:meth:`faultnet.OFC.from_alpha`) or ``k`` (default: the
    graph file's, else :data:`OFC_DEFAULT_K`); ``sigma`` and ``alpha`` do not apply to it.

    >>> build_model("ring:10", alpha=2.0).alpha
    2.0
    >>> build_model("square:8x8:fixed", model="ofc", ofc_alpha=0.2).k
    1.0
    """
    from faultnet.model.carlson_langer import CarlsonLanger, SparseGraph

    model = MODELS[0] if model is None else model
    if model not in MODELS:
        raise InvalidParameterError(
            f"model must be one of {', '.join(map(repr, MODELS))}; got {model!r}"
        )
    if model == "ofc":
        return _build_ofc(spec, k, sigma, alpha, rng, ofc_alpha)
    if ofc_alpha is not None:
        raise InvalidParameterError(
            "ofc_alpha (--ofc-alpha) is the OFC automaton's; give model='ofc' (--model ofc), "
            "or alpha (--alpha) for the Carlson-Langer friction"
        )
    G = spec if isinstance(spec, (nx.Graph, SparseGraph)) else build_graph(spec, rng=rng)
    params = {}
    for name, given in (("k", k), ("sigma", sigma), ("alpha", alpha)):
        if given is None:
            given = _graph_param(G, name)
        params[name] = DEFAULT_PARAMS[name] if given is None else given
    return CarlsonLanger(G, **params)


def _build_ofc(spec, k, sigma, alpha, rng, ofc_alpha):
    from faultnet.model.carlson_langer import SparseGraph
    from faultnet.model.ofc import OFC

    given = [name for name, value in (("sigma", sigma), ("alpha", alpha)) if value is not None]
    if given:
        raise InvalidParameterError(
            f"{' and '.join(given)} (--{' and --'.join(given)}) are the Carlson-Langer model's "
            "friction: the OFC automaton has none; its conservation is ofc_alpha "
            "(--ofc-alpha) or k (--k)"
        )
    if k is not None and ofc_alpha is not None:
        raise InvalidParameterError(
            "give the OFC automaton k (--k) or ofc_alpha (--ofc-alpha), not both: "
            "ofc_alpha = k / (q k + 1) on a graph of coordination q"
        )
    G = spec if isinstance(spec, (nx.Graph, SparseGraph)) else build_graph(spec, rng=rng)
    if ofc_alpha is not None:
        return OFC.from_alpha(G, ofc_alpha)
    if k is None:
        k = _graph_param(G, "k")
    return OFC(G, k=OFC_DEFAULT_K if k is None else k)
