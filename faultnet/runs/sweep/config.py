"""Sweep configuration: the ``[sweep]`` TOML table, validated into a :class:`SweepConfig`.

A sweep is the product of its parameter lists, times ``replicas``; each
element is a *point* (see :mod:`faultnet.runs.sweep.driver`).  The check of each field
(what it accepts, the error that names it) is in ``faultnet.runs.sweep.fields``.

Sweep file (TOML)
-----------------
::

    [sweep]
    graph = ["ring:200", "square:16x16:periodic"]   # graph spec(s), see faultnet.runs.specs
    alpha = [0.5, 1.0, 2.0]      # number or list of numbers
    k = 16                       # number or list (default: 16, or the graph file's k)
    sigma = 0.01                 # number or list (default: 0.01, or the graph file's)
    nu = [0.0, 0.01]             # optional number or list: the plate's velocity during events
    eta = 0.1                    # optional number or list: the springs' viscous coupling
    dt = 0.005                   # optional number or list (default: faultnet.default_dt)
    model = "ofc"                # optional: the OFC automaton instead of the Carlson-Langer
    ofc_alpha = [0.15, 0.2]      # .. model, with its conservation (or k), no sigma/alpha/nu/
                                 # .. eta/dt
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
    crossings = "interpolated"   # e.g. crossings, solo_cache, max_event_duration

    [sweep.vars]                 # optional: lists substituted into "{name}" in graph specs
    L = [32, 64]
    p = [0.55, 0.5927, 0.65]     # e.g. graph = "percolation:square:{L}x{L}:p={p}"

Points are numbered in the order ``graph`` (vars varying fastest in the order
listed), ``k``, ``sigma``, ``alpha``, ``nu``, ``eta``, ``ofc_alpha``, ``dt``, replica.  Random
percolation graphs get their own disorder per point (from the point's seed).  ``nu`` and
``eta`` (default 0, as :class:`faultnet.CarlsonLanger`'s) are in the points, and in the
settings compared on reruns, only where the sweep sets them: the folders of sweeps without them
stay theirs.

>>> cfg = SweepConfig.from_dict({"graph": "ring:{n}", "vars": {"n": [10, 20]},
...                              "alpha": [1.0, 2.0], "events": 100, "seed": 5})
>>> [(p["index"], p["graph"], p["alpha"]) for p in cfg.points()]
[(0, 'ring:10', 1.0), (1, 'ring:10', 2.0), (2, 'ring:20', 1.0), (3, 'ring:20', 2.0)]
"""

from __future__ import annotations

import dataclasses
import itertools
import os
import sys
from dataclasses import dataclass, field

import numpy as np

from faultnet.exceptions import ConfigError
from faultnet.runs.sweep import fields as checks
from faultnet.runs.sweep.fields import ALLOWED_KEYS, LIST_KEYS

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["ALLOWED_KEYS", "ConfigError", "SweepConfig", "as_config", "load_config"]

#: the Carlson-Langer parameters that are in the points only where a sweep sets them
_KELVIN = ("nu", "eta")


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
    nu: list = field(default_factory=lambda: [None])
    eta: list = field(default_factory=lambda: [None])
    ofc_alpha: list = field(default_factory=lambda: [None])
    dt: list = field(default_factory=lambda: [None])
    model: str | None = None
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
                raise checks.unknown_key(key, where, ALLOWED_KEYS)
        templates = checks.graph_templates(table)
        variables = checks.graph_vars(table)
        graphs = checks.expand_graphs(templates, variables)
        lists = {
            name: [None] if table.get(name) is None else checks.numbers(name, table[name])
            for name in LIST_KEYS
        }
        settings = checks.run_settings(table)
        settings["options"] = checks.run_options(table, where)
        settings["model"] = checks.model(table, lists, settings["options"])
        out = checks.out_folder(table.get("out"), base_dir)
        return cls(
            graphs=graphs,
            replicas=checks.integer("replicas", table.get("replicas"), 1, default=1),
            seed=checks.integer("seed", table.get("seed"), 0),
            chunk=checks.integer("chunk", table.get("chunk"), 1, default=100_000),
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
            self.graphs, self.k, self.sigma, self.alpha, self.nu, self.eta, self.ofc_alpha,
            self.dt, range(self.replicas),
        )  # fmt: skip
        return [
            {
                "index": index,
                "graph": graph,
                "k": k,
                "sigma": sigma,
                "alpha": alpha,
                **{
                    name: value
                    for name, value in (("nu", nu), ("eta", eta))
                    if getattr(self, name) != [None]
                },
                "dt": dt,
                "replica": rep,
                "events": self.events,
                "seed_entropy": self.seed,
                "spawn_key": [index],
                **({"options": self.options} if self.options else {}),
                **({"model": self.model, "ofc_alpha": ofc_alpha} if self.model else {}),
            }
            for index, (graph, k, sigma, alpha, nu, eta, ofc_alpha, dt, rep) in enumerate(combos)
        ]

    def defining(self) -> dict:
        """The settings that fix what each point computes (compared on reruns)."""
        return {
            "graphs": self.graphs,
            "k": self.k,
            "sigma": self.sigma,
            "alpha": self.alpha,
            **{name: getattr(self, name) for name in _KELVIN if getattr(self, name) != [None]},
            "dt": self.dt,
            "events": self.events,
            "replicas": self.replicas,
            "seed": self.seed,
            **({"options": self.options} if self.options else {}),
            **({"model": self.model, "ofc_alpha": self.ofc_alpha} if self.model else {}),
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
