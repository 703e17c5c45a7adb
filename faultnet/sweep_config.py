"""Sweep configuration: the ``[sweep]`` TOML table, validated into a :class:`SweepConfig`.

A sweep is the product of its parameter lists, times ``replicas``; each
element is a *point* (see :mod:`faultnet.sweep`).

Sweep file (TOML)
-----------------
::

    [sweep]
    graph = ["ring:200", "square:16x16:periodic"]   # graph spec(s), see faultnet.specs
    alpha = [0.5, 1.0, 2.0]      # number or list of numbers
    k = 16                       # number or list (default: 16, or the graph file's k)
    sigma = 0.01                 # number or list (default: 0.01, or the graph file's)
    dt = 0.005                   # optional number or list (default: faultnet.default_dt)
    events = 20000               # events per point (required)
    replicas = 2                 # independent runs per parameter set (default 1)
    seed = 12345                 # root seed (default: fresh entropy, kept in sweep.json)
    transient = 2000             # events left out of the b fits (default 0)
    chunk = 100000               # events per catalog chunk (memory bound; default 100000)
    checkpoint_interval = 60     # seconds between checkpoints (default 60)
    m_min = -6.0                 # optional b-fit window (default: maximum curvature ..
    m_max = 3.0                  # .. to the largest event)
    out = "runs/alpha"           # output folder, relative to this file (default: its stem)
    rtol = 2e-5                  # optional: target accuracy of slips (faultnet.RunOptions.rtol)

    [sweep.options]              # optional: any other faultnet.RunOptions field
    crossings = "interpolated"   # e.g. method, crossings, solo_cache, local_regions_from

    [sweep.vars]                 # optional: lists substituted into "{name}" in graph specs
    L = [32, 64]
    p = [0.55, 0.5927, 0.65]     # e.g. graph = "percolation:square:{L}x{L}:p={p}"

Points are numbered in the order ``graph`` (vars varying fastest in the order
listed), ``k``, ``sigma``, ``alpha``, ``dt``, replica.  Random percolation
graphs get their own disorder per point (from the point's seed).

>>> cfg = SweepConfig.from_dict({"graph": "ring:{n}", "vars": {"n": [10, 20]},
...                              "alpha": [1.0, 2.0], "events": 100, "seed": 5})
>>> [(p["index"], p["graph"], p["alpha"]) for p in cfg.points()]
[(0, 'ring:10', 1.0), (1, 'ring:10', 2.0), (2, 'ring:20', 1.0), (3, 'ring:20', 2.0)]
"""

from __future__ import annotations

import dataclasses
import difflib
import itertools
import os
import string
import sys
from dataclasses import dataclass, field

import numpy as np

from faultnet._validate import check_finite, check_int
from faultnet.exceptions import ConfigError, InvalidParameterError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["ALLOWED_KEYS", "ConfigError", "SweepConfig", "as_config", "load_config"]

LIST_KEYS = ("k", "sigma", "alpha", "dt")
ALLOWED_KEYS = {
    "graph": 'graph spec or list of specs (required), e.g. "ring:200"',
    "events": "events per point, integer > 0 (required)",
    "alpha": "number or list of numbers >= 0",
    "k": "number or list of numbers > 0",
    "sigma": "number or list of numbers in (0, 1)",
    "dt": "number or list of numbers > 0",
    "replicas": "integer >= 1",
    "seed": "integer >= 0",
    "transient": "integer >= 0, less than events",
    "chunk": "integer >= 1",
    "checkpoint_interval": "number of seconds >= 0",
    "m_min": "number",
    "m_max": "number",
    "out": "output folder (string)",
    "vars": "table of lists substituted into graph specs",
    "rtol": "number in [1e-8, 1e-4]: target relative accuracy of slips",
    "options": "table of faultnet.RunOptions fields (method, crossings, solo_cache, ...)",
}
_LIST_CHECKS = {
    "k": (lambda v: v > 0, "> 0"),
    "sigma": (lambda v: 0 < v < 1, "in the open interval (0, 1)"),
    "alpha": (lambda v: v >= 0, ">= 0"),
    "dt": (lambda v: v > 0, "> 0"),
}


# --------------------------------------------------------------------------- field checks


def _is_number(x):
    try:
        check_finite("x", x)
    except InvalidParameterError:
        return False
    return True


def _unknown_key(key, where, allowed):
    near = difflib.get_close_matches(key, list(allowed), n=1)
    hint = f" (did you mean {near[0]!r}?)" if near else ""
    return ConfigError(f"unknown key {key!r} in {where}{hint}; allowed keys: {', '.join(allowed)}")


def _numbers(name, value):
    """A non-empty list of floats from a number or list of numbers, each passing its check."""
    check, rule = _LIST_CHECKS[name]
    values = value if isinstance(value, list) else [value]
    if not values:
        raise ConfigError(
            f"sweep.{name}: expected a number or a non-empty list of numbers "
            f"({rule}); got an empty list"
        )
    for v in values:
        if not _is_number(v):
            raise ConfigError(
                f"sweep.{name}: expected a number or a list of numbers ({rule}); got {v!r}"
            )
        if not check(v):
            raise ConfigError(f"sweep.{name}: {v!r} is not allowed; {name} must be {rule}")
    return [float(v) for v in values]


def _integer(name, value, minimum, required=False, default=None):
    if value is None:
        if required:
            raise ConfigError(f"sweep.{name} is required: {ALLOWED_KEYS[name]}")
        return default
    try:
        return check_int(f"sweep.{name}", value, minimum)
    except InvalidParameterError:
        rule = f"expected an integer >= {minimum}; got {value!r}"
        raise ConfigError(f"sweep.{name}: {rule}") from None


def _template_fields(template):
    try:
        return [f for _, f, _, _ in string.Formatter().parse(template) if f is not None]
    except ValueError as exc:
        raise ConfigError(f"sweep.graph: bad template {template!r}: {exc}") from None


def _templates(table):
    graph = table.get("graph")
    if graph is None:
        raise ConfigError(f"sweep.graph is required: {ALLOWED_KEYS['graph']}")
    templates = graph if isinstance(graph, list) else [graph]
    if not templates or not all(isinstance(g, str) and g.strip() for g in templates):
        raise ConfigError(
            f"sweep.graph: expected a graph spec string or a non-empty list of "
            f'them, e.g. "ring:200"; got {graph!r}'
        )
    return templates


def _is_scalar(v):
    return isinstance(v, (str, int, float)) and not isinstance(v, bool)


def _variables(table):
    variables = table.get("vars", {})
    if not isinstance(variables, dict):
        raise ConfigError(
            f"sweep.vars must be a table of lists, e.g. L = [32, 64]; got {variables!r}"
        )
    variables = dict(variables)
    for name, values in variables.items():
        if not isinstance(values, list) or not values:
            values = [values] if isinstance(values, (str, int, float)) else values
        if not isinstance(values, list) or not values or not all(map(_is_scalar, values)):
            raise ConfigError(
                f"sweep.vars.{name}: expected a non-empty list of numbers or "
                f"strings; got {variables[name]!r}"
            )
        variables[name] = values
    return variables


def _expand_graphs(templates, variables):
    """Every graph spec of the templates, vars varying fastest in the order listed."""
    from faultnet.specs import parse_graph_spec

    used = set()
    graphs = []
    for i, tpl in enumerate(templates):
        fields = list(dict.fromkeys(_template_fields(tpl)))
        for f in fields:
            if f not in variables:
                raise ConfigError(
                    f"sweep.graph[{i}] = {tpl!r} uses {{{f}}} but sweep.vars has no {f!r}; "
                    f"defined vars: {', '.join(variables) or 'none'}"
                )
        used.update(fields)
        for combo in itertools.product(*(variables[f] for f in fields)):
            spec = tpl.format(**dict(zip(fields, combo, strict=True)))
            try:
                parse_graph_spec(spec)
            except InvalidParameterError as exc:
                raise ConfigError(f"sweep.graph[{i}]: {exc}") from None
            graphs.append(spec)
    unused = [v for v in variables if v not in used]
    if unused:
        raise ConfigError(
            f"sweep.vars: {', '.join(map(repr, unused))} not used by any graph "
            "spec (write {name} in sweep.graph)"
        )
    return graphs


def _run_settings(table):
    """events, transient, checkpoint_interval, m_min and m_max of a ``[sweep]`` table."""
    events = _integer("events", table.get("events"), 1, required=True)
    transient = _integer("transient", table.get("transient"), 0, default=0)
    if transient >= events:
        raise ConfigError(
            f"sweep.transient: {transient} leaves no events to fit out of "
            f"events = {events}; it must be less than events"
        )
    interval = table.get("checkpoint_interval", 60.0)
    if not _is_number(interval) or interval < 0:
        raise ConfigError(f"sweep.checkpoint_interval: expected seconds >= 0; got {interval!r}")
    settings = {"events": events, "transient": transient, "checkpoint_interval": float(interval)}
    for name in ("m_min", "m_max"):
        v = table.get(name)
        if v is not None and not _is_number(v):
            raise ConfigError(f"sweep.{name}: expected a number; got {v!r}")
        settings[name] = None if v is None else float(v)
    return settings


def _out_folder(out, base_dir):
    if out is None:
        return None
    if not isinstance(out, str) or not out:
        raise ConfigError(f"sweep.out: expected a folder name; got {out!r}")
    if base_dir is not None and not os.path.isabs(out):
        out = os.path.join(base_dir, out)
    return out


# --------------------------------------------------------------------------- the config


@dataclass
class SweepConfig:
    """A validated sweep (see the module docstring for the TOML schema).

    Attributes mirror the TOML keys; ``graphs`` is the expanded list of graph
    specs and ``seed`` the root entropy (fresh when not given).
    """

    graphs: list
    events: int
    k: list = field(default_factory=lambda: [None])
    sigma: list = field(default_factory=lambda: [None])
    alpha: list = field(default_factory=lambda: [None])
    dt: list = field(default_factory=lambda: [None])
    replicas: int = 1
    seed: int | None = None
    transient: int = 0
    chunk: int = 100_000
    checkpoint_interval: float = 60.0
    m_min: float | None = None
    m_max: float | None = None
    out: str | None = None
    templates: list = field(default_factory=list)
    vars: dict = field(default_factory=dict)
    options: dict = field(default_factory=dict)

    @classmethod
    def from_dict(cls, table, base_dir=None, where="[sweep]") -> SweepConfig:
        """Validate a ``[sweep]`` table (a dict); paths are relative to ``base_dir``."""
        if not isinstance(table, dict):
            raise ConfigError(f"{where} must be a table of keys; got {type(table).__name__}")
        for key in table:
            if key not in ALLOWED_KEYS:
                raise _unknown_key(key, where, ALLOWED_KEYS)
        templates = _templates(table)
        variables = _variables(table)
        graphs = _expand_graphs(templates, variables)
        lists = {
            name: [None] if table.get(name) is None else _numbers(name, table[name])
            for name in LIST_KEYS
        }
        settings = _run_settings(table)
        settings["options"] = _run_options(table, where)
        out = _out_folder(table.get("out"), base_dir)
        return cls(
            graphs=graphs,
            replicas=_integer("replicas", table.get("replicas"), 1, default=1),
            seed=_integer("seed", table.get("seed"), 0),
            chunk=_integer("chunk", table.get("chunk"), 1, default=100_000),
            out=out,
            templates=templates,
            vars=variables,
            **lists,
            **settings,
        )

    def with_seed(self) -> SweepConfig:
        """This config with fresh entropy as its seed if it had none."""
        if self.seed is not None:
            return self
        return dataclasses.replace(self, seed=int(np.random.SeedSequence().entropy))

    def points(self) -> list:
        """The grid: one dict per point, in point order."""
        if self.seed is None:
            raise ConfigError("sweep.seed is not set; call with_seed() first")
        combos = itertools.product(
            self.graphs, self.k, self.sigma, self.alpha, self.dt, range(self.replicas)
        )
        return [
            {
                "index": index,
                "graph": graph,
                "k": k,
                "sigma": sigma,
                "alpha": alpha,
                "dt": dt,
                "replica": rep,
                "events": self.events,
                "seed_entropy": self.seed,
                "spawn_key": [index],
                **({"options": self.options} if self.options else {}),
            }
            for index, (graph, k, sigma, alpha, dt, rep) in enumerate(combos)
        ]

    def defining(self) -> dict:
        """The settings that fix what each point computes (compared on reruns)."""
        return {
            "graphs": self.graphs,
            "k": self.k,
            "sigma": self.sigma,
            "alpha": self.alpha,
            "dt": self.dt,
            "events": self.events,
            "replicas": self.replicas,
            "seed": self.seed,
            **({"options": self.options} if self.options else {}),
        }

    def to_dict(self) -> dict:
        """Every setting, as stored in the sweep folder's manifest."""
        d = self.defining()
        d.update(
            templates=self.templates,
            vars=self.vars,
            transient=self.transient,
            chunk=self.chunk,
            checkpoint_interval=self.checkpoint_interval,
            m_min=self.m_min,
            m_max=self.m_max,
        )
        return d


def _run_options(table, where):
    """The RunOptions of ``[sweep.options]`` and ``rtol``, as the dict of the fields given."""
    from faultnet.options import RunOptions

    given = table.get("options", {})
    if not isinstance(given, dict):
        raise ConfigError(f"{where}.options must be a table of RunOptions fields; got {given!r}")
    given = dict(given)
    if "rtol" in table:
        given["rtol"] = table["rtol"]
    try:
        opts = RunOptions.from_dict(given)
    except InvalidParameterError as exc:
        raise ConfigError(f"{where}: {exc}") from None
    full = opts.to_dict()
    return {key: full[key] for key in given}


def load_config(path) -> SweepConfig:
    """Read and validate a sweep TOML file (schema in the module docstring)."""
    path = os.fspath(path)
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except FileNotFoundError:
        raise ConfigError(f"sweep file {path} does not exist") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"sweep file {path} is not valid TOML: {exc}") from None
    for key in data:
        if key != "sweep":
            raise ConfigError(
                f"{path}: unknown top-level key or table {key!r}; a sweep file has one table "
                f"[sweep] with keys: {', '.join(ALLOWED_KEYS)}"
            )
    if "sweep" not in data:
        raise ConfigError(
            f"{path}: no [sweep] table; expected e.g.\n[sweep]\ngraph = "
            '"ring:200"\nalpha = [0.5, 1.0]\nevents = 20000'
        )
    cfg = SweepConfig.from_dict(data["sweep"], base_dir=os.path.dirname(os.path.abspath(path)))
    if cfg.out is None:
        stem = os.path.splitext(os.path.basename(path))[0]
        cfg.out = os.path.join(os.path.dirname(os.path.abspath(path)), stem)
    return cfg


def as_config(config, params) -> SweepConfig:
    """The SweepConfig of ``sweep()``'s arguments: a path, dict or SweepConfig, and overrides."""
    if isinstance(config, SweepConfig):
        if params:
            table = {k: v for k, v in config.to_dict().items() if k in ALLOWED_KEYS}
            table["graph"] = config.templates
            table.update(out=config.out, **params)
            return SweepConfig.from_dict(
                {k: v for k, v in table.items() if v is not None and v != [None]},
                where="sweep()",
            )
        return config
    if config is None:
        return SweepConfig.from_dict(dict(params), where="sweep()")
    if isinstance(config, dict):
        table = config.get("sweep", config) if set(config) <= {"sweep"} else config
        table = dict(table)
        table.update(params)
        return SweepConfig.from_dict(table, where="sweep()")
    if isinstance(config, (str, os.PathLike)):
        cfg = load_config(config)
        if params:
            with open(os.fspath(config), "rb") as fh:
                raw = tomllib.load(fh)["sweep"]
            raw.update(params)
            raw.setdefault("out", cfg.out)
            cfg = SweepConfig.from_dict(raw, base_dir=os.path.dirname(os.path.abspath(config)))
        return cfg
    raise ConfigError(
        f"config must be a path to a TOML file, a dict or a SweepConfig; got "
        f"{type(config).__name__}"
    )
