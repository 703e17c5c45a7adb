"""Graph-spec strings -> :class:`GraphSpec`: the parser behind :mod:`faultnet.runs.specs`.

The forms, and how a spec becomes a graph and a model, are described in
:mod:`faultnet.runs.specs`, which re-exports the names here.  Parsing builds
nothing and draws no random numbers.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field

from faultnet import graphs
from faultnet.exceptions import GraphSpecError

__all__ = ["GRAPH_SPEC_FORMS", "GraphSpec", "parse_graph_spec"]

GRAPH_SPEC_FORMS = (
    "chain:N[:reach=R][:kc=K]  e.g. chain:100, chain:500:reach=3",
    "ring:N[:reach=R][:kc=K]   e.g. ring:2000, ring:2000:reach=10:kc=100 (R springs on each "
    "side, each of K/2R)",
    "square:RxC[:periodic|:fixed]  e.g. square:150x150:periodic (square:L means LxL)",
    "triangular:RxC[:periodic|:fixed]  e.g. triangular:150x150",
    "percolation:LATTICE:RxC[:periodic|:fixed]:p=P[:largest|:all][:prune][:seed=S]"
    "  e.g. percolation:square:150x150:p=0.5927:largest (p=pc: the threshold)",
    "file:PATH or PATH.graphml / PATH.json  a GraphML or node-link JSON graph file",
)

_GRAPH_FILE_SUFFIXES = (".graphml", ".json")
#: a lattice's boundary tokens (``open`` is the older name of ``free``)
_BOUNDARY_TOKENS = ("periodic", "fixed", "free", "open")
#: the options of a chain or a ring (``k_c=`` is a synonym of ``kc=``)
_LONG_RANGE_OPTIONS = "reach=R (an integer >= 1) and kc=K (a finite number > 0)"


def _spec_error(spec, why):
    forms = "\n  ".join(GRAPH_SPEC_FORMS)
    return GraphSpecError(f"invalid graph spec {spec!r}: {why}\nvalid forms:\n  {forms}")


@dataclass(frozen=True)
class GraphSpec:
    """A parsed graph spec.

    Attributes
    ----------
    kind : str
        ``chain``, ``ring``, ``square``, ``triangular``, ``percolation`` or ``file``.
    size : tuple of int
        ``(n,)`` for chains and rings, ``(rows, cols)`` for lattices, ``()`` for files.
    periodic : bool
    fixed : bool
        A lattice with ``boundary="fixed"`` (frame springs at its edge; see
        :func:`faultnet.graphs.square_lattice`).  Neither periodic nor fixed: a free boundary
        (the token ``free``, or the older ``open``).
    lattice : str or None
        ``square`` / ``triangular`` for percolation.
    p : float or None
        Occupation probability for percolation.
    keep : str
        ``largest`` or ``all`` (percolation).
    prune : bool
        Drop isolated occupied sites (percolation).
    seed : int or None
        Fixed disorder seed (percolation); None derives it from the run seed.
    path : str or None
        Graph file (``kind == "file"``).
    reach : int
        Chains and rings: each block is linked to its ``reach`` nearest neighbours on each
        side (:func:`faultnet.graphs.ring`); 1 is the nearest-neighbour graph.
    k_c : float or None
        Chains and rings: every spring gets ``k = k_c / (2 reach)``; None leaves the
        model's ``k``.
    """

    kind: str
    size: tuple = ()
    periodic: bool = False
    fixed: bool = False
    lattice: str | None = None
    p: float | None = None
    keep: str = "largest"
    prune: bool = False
    seed: int | None = None
    path: str | None = None
    reach: int = 1
    k_c: float | None = None
    text: str = field(default="", compare=False)

    @property
    def random(self) -> bool:
        """True when building the graph draws random numbers."""
        return self.kind == "percolation" and self.seed is None

    @property
    def boundary(self) -> str:
        """The lattice's boundary: ``"periodic"``, ``"fixed"`` or ``"free"``."""
        return "periodic" if self.periodic else "fixed" if self.fixed else "free"

    @property
    def canonical(self) -> str:
        """The spec in normal form (what is recorded in catalog metadata)."""
        if self.kind in ("chain", "ring"):
            out = f"{self.kind}:{self.size[0]}"
            if self.reach != 1:
                out += f":reach={self.reach}"
            if self.k_c is not None:
                out += f":kc={_format_number(self.k_c)}"
            return out
        if self.kind == "file":
            return f"file:{self.path}"
        tail = {"periodic": ":periodic", "fixed": ":fixed", "free": ""}[self.boundary]
        dims = f"{self.size[0]}x{self.size[1]}" + tail
        if self.kind in ("square", "triangular"):
            return f"{self.kind}:{dims}"
        out = f"percolation:{self.lattice}:{dims}:p={self.p!r}:{self.keep}"
        if self.prune:
            out += ":prune"
        if self.seed is not None:
            out += f":seed={self.seed}"
        return out


def _format_number(value):
    """``value`` as a spec writes it: ``100`` for 100.0, else the float's repr."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def _int_token(spec, token, what):
    if not re.fullmatch(r"\d+", token):
        raise _spec_error(spec, f"{what} must be a positive integer, got {token!r}")
    return int(token)


def _dims(spec, token):
    m = re.fullmatch(r"(\d+)(?:x(\d+))?", token)
    if not m:
        raise _spec_error(
            spec, f"lattice size must look like ROWSxCOLS (e.g. 150x150), got {token!r}"
        )
    rows = int(m.group(1))
    cols = int(m.group(2)) if m.group(2) else rows
    return rows, cols


def _looks_like_file(spec):
    return spec.startswith("file:") or spec.lower().endswith(_GRAPH_FILE_SUFFIXES)


def parse_graph_spec(spec) -> GraphSpec:
    """Parse a graph spec string (see the module docstring for the forms).

    Raises
    ------
    GraphSpecError
        Naming the problem and listing the valid forms.

    >>> parse_graph_spec("percolation:square:64x64:p=pc").p
    0.592746
    >>> parse_graph_spec("ring:2000:reach=10:kc=100.0").canonical
    'ring:2000:reach=10:kc=100'
    >>> parse_graph_spec("hexagonal:10")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    faultnet.exceptions.GraphSpecError: invalid graph spec 'hexagonal:10': unknown graph kind...
    """
    if isinstance(spec, GraphSpec):
        return spec
    if not isinstance(spec, str) or not spec.strip():
        raise _spec_error(spec, "a graph spec must be a non-empty string")
    spec = spec.strip()
    if _looks_like_file(spec):
        path = spec[5:] if spec.startswith("file:") else spec
        if not path:
            raise _spec_error(spec, "file: needs a path")
        return GraphSpec(kind="file", path=path, text=spec)
    parts = spec.split(":")
    kind = parts[0].lower()
    args = parts[1:]
    if kind in ("chain", "ring"):
        return _parse_chain_or_ring(spec, kind, args)
    if kind in ("square", "triangular"):
        if not args or len(args) > 2:
            raise _spec_error(
                spec, f"{kind} takes ROWSxCOLS and optionally a boundary, :periodic or :fixed"
            )
        periodic = fixed = False
        if len(args) == 2:
            if args[1].lower() not in _BOUNDARY_TOKENS:
                raise _spec_error(
                    spec, f"unknown option {args[1]!r}; allowed: {', '.join(_BOUNDARY_TOKENS)}"
                )
            periodic, fixed = args[1].lower() == "periodic", args[1].lower() == "fixed"
        size = _dims(spec, args[0])
        return GraphSpec(kind=kind, size=size, periodic=periodic, fixed=fixed, text=spec)
    if kind == "percolation":
        return _parse_percolation(spec, args)
    if os.path.sep in spec or os.path.exists(spec):
        raise _spec_error(
            spec, "graph files must end in .graphml or .json (or be given as file:PATH)"
        )
    raise _spec_error(spec, f"unknown graph kind {kind!r}")


def _parse_chain_or_ring(spec, kind, args):
    if not args:
        raise _spec_error(spec, f"{kind} takes a size, e.g. {kind}:200")
    n = _int_token(spec, args[0], "the size")
    given = {}
    for token in args[1:]:
        name, sep, value = token.partition("=")
        name = {"k_c": "kc"}.get(name.lower(), name.lower())
        if not sep or name not in ("reach", "kc"):
            raise _spec_error(
                spec, f"unknown {kind} option {token!r}; allowed: {_LONG_RANGE_OPTIONS}"
            )
        if name in given:
            raise _spec_error(spec, f"{name}= is given twice")
        given[name] = value
    reach = 1
    if "reach" in given:
        if not re.fullmatch(r"\d+", given["reach"]) or int(given["reach"]) < 1:
            raise _spec_error(spec, f"reach must be an integer >= 1, got {given['reach']!r}")
        reach = int(given["reach"])
        limit = (n - 1) // 2 if kind == "ring" else max(n - 1, 1)
        if reach > limit:
            bound = "(N - 1) // 2 on a ring" if kind == "ring" else "N - 1 on a chain"
            raise _spec_error(
                spec, f"reach must be at most {bound}, here {limit}; got reach={reach}"
            )
    k_c = None
    if "kc" in given:
        try:
            k_c = float(given["kc"])
        except ValueError:
            k_c = math.nan
        if not (math.isfinite(k_c) and k_c > 0.0):
            raise _spec_error(spec, f"kc must be a finite number > 0, got {given['kc']!r}")
    return GraphSpec(kind=kind, size=(n,), reach=reach, k_c=k_c, text=spec)


def _parse_percolation(spec, args):
    if len(args) < 2:
        raise _spec_error(spec, "percolation needs a lattice, a size and p=P")
    lattice = args[0].lower()
    if lattice not in ("square", "triangular"):
        raise _spec_error(
            spec, f"percolation lattice must be square or triangular, got {args[0]!r}"
        )
    size = _dims(spec, args[1])
    periodic, fixed, keep, prune, p, seed = False, False, "largest", False, None, None
    for token in args[2:]:
        low = token.lower()
        if low in _BOUNDARY_TOKENS:
            periodic, fixed = low == "periodic", low == "fixed"
        elif low in ("largest", "all"):
            keep = low
        elif low == "prune":
            prune = True
        elif low.startswith("p="):
            value = low[2:]
            if value == "pc":
                p = graphs.percolation_threshold(lattice)
            else:
                try:
                    p = float(value)
                except ValueError:
                    raise _spec_error(
                        spec, f"p must be a number or pc, got {token[2:]!r}"
                    ) from None
                if not 0.0 <= p <= 1.0:
                    raise _spec_error(spec, f"p must lie in [0, 1], got {p!r}")
        elif low.startswith("seed="):
            seed = _int_token(spec, token[5:], "seed")
        else:
            raise _spec_error(
                spec,
                f"unknown percolation option {token!r}; allowed: periodic, fixed, p=P, largest, "
                "all, prune, seed=S",
            )
    if p is None:
        raise _spec_error(spec, "percolation needs p=P (a probability, or p=pc)")
    return GraphSpec(
        kind="percolation",
        size=size,
        periodic=periodic,
        fixed=fixed,
        lattice=lattice,
        p=p,
        keep=keep,
        prune=prune,
        seed=seed,
        text=spec,
    )
