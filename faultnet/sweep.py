"""Parameter sweeps: a grid of runs, one Parquet catalog part per point.

A sweep is the product of its parameter lists, times ``replicas``.  Each
point is a pure task -- its configuration plus the child
``SeedSequence(seed, spawn_key=(index,))`` of the sweep's seed -- that writes
its own catalog ``part-00007.parquet`` (checkpointed like a long
``faultnet simulate``, see :mod:`faultnet.runner`).  Rerunning a sweep skips
the finished parts, resumes interrupted ones and recomputes missing or
corrupt ones (a truncated file, say).  Points run on local processes (every
core by default), on any :class:`concurrent.futures.Executor`, or on a Dask
cluster (``scheduler="tcp://HOST:PORT"``; the output folder must then be on
a file system every worker sees).

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
    m_max = 3.0                  # .. to the 99th percentile of M above it)
    out = "runs/alpha"           # output folder, relative to this file (default: its stem)

    [sweep.vars]                 # optional: lists substituted into "{name}" in graph specs
    L = [32, 64]
    p = [0.55, 0.5927, 0.65]     # e.g. graph = "percolation:square:{L}x{L}:p={p}"

Points are numbered in the order ``graph`` (vars varying fastest in the order
listed), ``k``, ``sigma``, ``alpha``, ``dt``, replica.  Random percolation
graphs get their own disorder per point (from the point's seed).  Changing a
parameter that defines the points (anything but transient, chunk,
checkpoint_interval, m_min, m_max and out) in a folder that holds a sweep
is refused unless forced.

Python
------
>>> import faultnet, tempfile
>>> from faultnet.sweep import sweep
>>> table = sweep(graph="ring:30", alpha=[1.0, 2.0], events=200, seed=1,
...               out=tempfile.mkdtemp(), workers=1, progress=False)
>>> table[["point", "alpha", "events", "status"]].to_string(index=False)
' point  alpha  events status\\n     0    1.0     200   done\\n     1    2.0     200   done'
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import difflib
import itertools
import json
import math
import os
import re
import shutil
import string
import sys
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from tqdm.auto import tqdm

from faultnet._system import usable_cores
from faultnet.exceptions import FaultnetError, InvalidParameterError
from faultnet.io import (
    CatalogError,
    OutputExistsError,
    atomic_write_json,
    catalog_stats,
    is_tmp_name,
    read_metadata,
    utc_now,
)
from faultnet.runner import CHECKPOINT_SUFFIX, checkpoint_dir, checkpoint_status

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "ConfigError",
    "SweepConfig",
    "SweepError",
    "load_config",
    "run_point",
    "summarize",
    "sweep",
]

MANIFEST = "sweep.json"
SWEEP_FORMAT = "faultnet-sweep"
_PART_RE = re.compile(r"part-(\d+)\.parquet$")
_LIST_KEYS = ("k", "sigma", "alpha", "dt")
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
}
#: keys that do not change what a point computes
_NON_DEFINING = ("transient", "chunk", "checkpoint_interval", "m_min", "m_max", "out")
_SUMMARY_COLUMNS = [
    "point",
    "replica",
    "graph",
    "n_blocks",
    "k",
    "sigma",
    "alpha",
    "dt",
    "events",
    "transient",
    "M_min",
    "M_max",
    "b_mle",
    "b_mle_err",
    "m_min",
    "m_max",
    "n_fit",
    "b_lsq",
    "b_lsq_err",
    "wall_time_s",
    "events_per_s",
    "seed_entropy",
    "spawn_key",
    "status",
    "part",
]


class ConfigError(InvalidParameterError):
    """A sweep configuration is malformed; the message names the field and the allowed values."""


class SweepError(FaultnetError, RuntimeError):
    """Some points of a sweep failed; ``summary`` holds the table of all points."""

    def __init__(self, message, summary=None):
        super().__init__(message)
        self.summary = summary


# --------------------------------------------------------------------------- configuration


def _is_number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _allowed_list():
    return "; ".join(f"{k} ({v})" for k, v in ALLOWED_KEYS.items())


def _unknown_key(key, where, allowed):
    near = difflib.get_close_matches(key, list(allowed), n=1)
    hint = f" (did you mean {near[0]!r}?)" if near else ""
    return ConfigError(f"unknown key {key!r} in {where}{hint}; allowed keys: {', '.join(allowed)}")


def _numbers(name, value, check, rule):
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
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise ConfigError(f"sweep.{name}: expected an integer >= {minimum}; got {value!r}")
    return int(value)


def _template_fields(template):
    try:
        return [f for _, f, _, _ in string.Formatter().parse(template) if f is not None]
    except ValueError as exc:
        raise ConfigError(f"sweep.graph: bad template {template!r}: {exc}") from None


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

    @classmethod
    def from_dict(cls, table, base_dir=None, where="[sweep]") -> SweepConfig:
        """Validate a ``[sweep]`` table (a dict); paths are relative to ``base_dir``."""
        from faultnet.specs import parse_graph_spec

        if not isinstance(table, dict):
            raise ConfigError(f"{where} must be a table of keys; got {type(table).__name__}")
        for key in table:
            if key not in ALLOWED_KEYS:
                raise _unknown_key(key, where, ALLOWED_KEYS)
        graph = table.get("graph")
        if graph is None:
            raise ConfigError(f"sweep.graph is required: {ALLOWED_KEYS['graph']}")
        templates = graph if isinstance(graph, list) else [graph]
        if not templates or not all(isinstance(g, str) and g.strip() for g in templates):
            raise ConfigError(
                f"sweep.graph: expected a graph spec string or a non-empty list of "
                f'them, e.g. "ring:200"; got {graph!r}'
            )
        variables = table.get("vars", {})
        if isinstance(variables, dict):
            variables = dict(variables)
        else:
            raise ConfigError(
                f"sweep.vars must be a table of lists, e.g. L = [32, 64]; got {variables!r}"
            )
        for name, values in variables.items():
            if not isinstance(values, list) or not values:
                values = [values] if isinstance(values, (str, int, float)) else values
            if (
                not isinstance(values, list)
                or not values
                or not all(
                    isinstance(v, (str, int, float)) and not isinstance(v, bool) for v in values
                )
            ):
                raise ConfigError(
                    f"sweep.vars.{name}: expected a non-empty list of numbers or "
                    f"strings; got {variables[name]!r}"
                )
            variables[name] = values
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
        checks = {
            "k": (lambda v: v > 0, "> 0"),
            "sigma": (lambda v: 0 < v < 1, "in the open interval (0, 1)"),
            "alpha": (lambda v: v >= 0, ">= 0"),
            "dt": (lambda v: v > 0, "> 0"),
        }
        lists = {}
        for name in _LIST_KEYS:
            lists[name] = (
                [None] if table.get(name) is None else _numbers(name, table[name], *checks[name])
            )
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
        fit = {}
        for name in ("m_min", "m_max"):
            v = table.get(name)
            if v is not None and not _is_number(v):
                raise ConfigError(f"sweep.{name}: expected a number; got {v!r}")
            fit[name] = None if v is None else float(v)
        out = table.get("out")
        if out is not None:
            if not isinstance(out, str) or not out:
                raise ConfigError(f"sweep.out: expected a folder name; got {out!r}")
            if base_dir is not None and not os.path.isabs(out):
                out = os.path.join(base_dir, out)
        return cls(
            graphs=graphs,
            events=events,
            replicas=_integer("replicas", table.get("replicas"), 1, default=1),
            seed=_integer("seed", table.get("seed"), 0),
            transient=transient,
            chunk=_integer("chunk", table.get("chunk"), 1, default=100_000),
            checkpoint_interval=float(interval),
            out=out,
            templates=templates,
            vars=variables,
            **lists,
            **fit,
        )

    def with_seed(self) -> SweepConfig:
        """This config with fresh entropy as its seed if it had none."""
        if self.seed is not None:
            return self
        import dataclasses

        return dataclasses.replace(self, seed=int(np.random.SeedSequence().entropy))

    def points(self) -> list:
        """The grid: one dict per point, in point order."""
        if self.seed is None:
            raise ConfigError("sweep.seed is not set; call with_seed() first")
        out = []
        combos = itertools.product(
            self.graphs, self.k, self.sigma, self.alpha, self.dt, range(self.replicas)
        )
        for index, (graph, k, sigma, alpha, dt, rep) in enumerate(combos):
            out.append(
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
                }
            )
        return out

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
        }

    def to_dict(self) -> dict:
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


def _as_config(config, params):
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


# --------------------------------------------------------------------------- output folder


def _part_name(index, n_points):
    width = max(5, len(str(max(n_points - 1, 0))))
    return f"part-{index:0{width}d}.parquet"


def _is_own(name):
    if name == MANIFEST or is_tmp_name(name):
        return True
    base = name[: -len(CHECKPOINT_SUFFIX)] if name.endswith(CHECKPOINT_SUFFIX) else name
    return bool(_PART_RE.fullmatch(base))


def _prepare_out(cfg, out, force):
    """Create or check the output folder and its manifest; return the manifest config."""
    out = os.fspath(out)
    if os.path.exists(out) and not os.path.isdir(out):
        raise OutputExistsError(f"sweep output {out} exists and is not a folder")
    os.makedirs(out, exist_ok=True)
    names = os.listdir(out)
    foreign = sorted(n for n in names if not _is_own(n))
    manifest = os.path.join(out, MANIFEST)
    has_manifest = os.path.isfile(manifest)
    if names and not has_manifest and not force:
        raise OutputExistsError(
            f"output folder {out} is not empty and holds no sweep ({', '.join(sorted(names)[:5])}"
            f"{' ...' if len(names) > 5 else ''}); use another folder, or force=True / --force "
            "to write into it anyway"
        )
    if foreign and not force:
        raise OutputExistsError(
            f"output folder {out} holds files that are not part of a sweep: "
            f"{', '.join(foreign[:5])}{' ...' if len(foreign) > 5 else ''}; move them away, or "
            "pass force=True / --force"
        )
    stored = None
    if has_manifest:
        try:
            with open(manifest, encoding="utf-8") as fh:
                stored = json.load(fh)
        except (OSError, ValueError) as exc:
            if not force:
                raise OutputExistsError(
                    f"{manifest} is unreadable ({exc}); pass --force to replace it"
                ) from None
    if stored is not None and cfg.seed is None:
        cfg.seed = stored.get("config", {}).get("seed")
    cfg = cfg.with_seed()
    if stored is not None:
        old = stored.get("config", {})
        new = json.loads(json.dumps(cfg.defining()))
        diffs = [f"{k}: {old.get(k)!r} -> {new[k]!r}" for k in new if old.get(k) != new[k]]
        if diffs and not force:
            raise OutputExistsError(
                f"{out} holds a sweep with other settings ({'; '.join(diffs)}); use a new "
                "output folder, or force=True / --force to recompute the points that changed"
            )
    record = {
        "format": SWEEP_FORMAT,
        "format_version": 1,
        "config": cfg.to_dict(),
        "n_points": len(cfg.points()),
        "created": (stored or {}).get("created", utc_now()),
        "updated": utc_now(),
    }
    from faultnet import __version__

    record["faultnet_version"] = __version__
    atomic_write_json(manifest, record)
    return cfg


def _same_point(stored, point):
    return json.loads(json.dumps(stored)) == json.loads(json.dumps(point))


def _part_state(point, path, force):
    """``("done", None)`` or ``("todo", why)``; removes corrupt or (forced) stale files.

    ``why`` is ``missing``, ``resume`` (an interrupted run), ``corrupt`` or ``stale``.
    """
    if os.path.exists(path):
        try:
            md = read_metadata(path)
            if not _same_point(md.get("sweep_point"), point):
                if not force:
                    raise OutputExistsError(
                        f"{path} holds another run than point {point['index']} ({point}); "
                        "pass force=True / --force to recompute it"
                    )
                os.remove(path)
                if os.path.isdir(checkpoint_dir(path)):
                    shutil.rmtree(checkpoint_dir(path))
                return "todo", "stale"
            if os.path.isdir(checkpoint_dir(path)):  # killed while cleaning up after merging
                shutil.rmtree(checkpoint_dir(path))
            return "done", None
        except CatalogError:
            os.remove(path)  # truncated or corrupt: recompute
            return "todo", "corrupt"
    wd = checkpoint_dir(path)
    if os.path.isdir(wd):
        try:
            run = (checkpoint_status(path) or {}).get("run", {})
        except (OSError, ValueError):
            run = {}
        stored = (run.get("extra") or {}).get("sweep_point")
        if stored is not None and not _same_point(stored, point):
            if not force:
                raise OutputExistsError(
                    f"{wd} holds an interrupted run of another point; pass force=True / --force"
                )
            shutil.rmtree(wd)
            return "todo", "stale"
        return "todo", "resume"
    return "todo", "missing"


def _row(point, path, md, st, status):
    row = {
        "point": point["index"],
        "replica": point["replica"],
        "graph": point["graph"],
        "n_blocks": md.get("n_blocks"),
        "k": md.get("k", point["k"]),
        "sigma": md.get("sigma", point["sigma"]),
        "alpha": md.get("alpha", point["alpha"]),
        "dt": md.get("dt", point["dt"]),
        "events": st.get("events", 0),
        "transient": st.get("transient"),
        "wall_time_s": md.get("wall_time_s", float("nan")),
        "seed_entropy": str(point["seed_entropy"]),
        "spawn_key": tuple(point["spawn_key"]),
        "status": status,
        "part": os.path.basename(path),
    }
    for key in (
        "M_min",
        "M_max",
        "b_mle",
        "b_mle_err",
        "m_min",
        "m_max",
        "n_fit",
        "b_lsq",
        "b_lsq_err",
    ):
        row[key] = st.get(key, float("nan"))
    wall = row["wall_time_s"]
    row["events_per_s"] = row["events"] / wall if wall and wall == wall else float("nan")
    return row


def _point_row(point, path, transient, m_min, m_max, status="done"):
    md = read_metadata(path)
    st = catalog_stats(path, transient=transient, m_min=m_min, m_max=m_max)
    return _row(point, path, md, st, status)


def run_point(
    point, path, transient=0, chunk=100_000, checkpoint_interval=60.0, m_min=None, m_max=None
):
    """Run one sweep point into ``path`` (resuming its checkpoint) and return its summary row.

    A pure task: the result depends only on ``point`` (its parameters and
    seed), never on where or when it runs.
    """
    from faultnet.runner import run_from_spec

    seq = np.random.SeedSequence(point["seed_entropy"], spawn_key=tuple(point["spawn_key"]))
    run_from_spec(
        point["graph"],
        point["events"],
        path,
        k=point["k"],
        sigma=point["sigma"],
        alpha=point["alpha"],
        dt=point["dt"],
        seed=seq,
        chunk_events=chunk,
        checkpoint_interval=checkpoint_interval,
        transient=transient,
        resume=True,
        progress=False,
        extra={"sweep_point": point},
    )
    return _point_row(point, path, transient, m_min, m_max)


# --------------------------------------------------------------------------- execution


class SerialExecutor(cf.Executor):
    """Runs each task at submission, in this process (``workers=1``)."""

    def submit(self, fn, /, *args, **kwargs):
        fut = cf.Future()
        try:
            fut.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # noqa: B036 - handed to the future like a real executor
            if isinstance(exc, (KeyboardInterrupt, SystemExit)):
                raise
            fut.set_exception(exc)
        return fut


def _local_pool(workers):
    import multiprocessing as mp

    method = "forkserver" if "forkserver" in mp.get_all_start_methods() else "spawn"
    ctx = mp.get_context(method)
    if method == "forkserver":
        ctx.set_forkserver_preload(["faultnet.sweep"])
    return cf.ProcessPoolExecutor(
        max_workers=workers, mp_context=ctx, initializer=_no_compile_helper
    )


def _no_compile_helper():
    """Pool workers are one process per core already: no second process compiling for them."""
    from faultnet import _compile_helper

    os.environ[_compile_helper.ENV] = "0"


@contextlib.contextmanager
def _executor(executor, scheduler, workers, n_tasks):
    if executor is not None:
        yield executor, "the given executor"
        return
    if scheduler is not None:
        try:
            from distributed import Client
        except ImportError:  # pragma: no cover
            raise InvalidParameterError(
                "scheduler= needs Dask: pip install 'dask[distributed]'"
            ) from None
        client = Client(scheduler)
        try:
            yield client.get_executor(pure=False), f"Dask scheduler {scheduler}"
        finally:
            client.close()
        return
    n = workers if workers is not None else usable_cores()
    n = max(1, min(int(n), n_tasks))
    if n == 1:
        yield SerialExecutor(), "this process"
        return
    pool = _local_pool(n)
    try:
        yield pool, f"{n} local processes"
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def sweep(
    config=None,
    out=None,
    *,
    executor=None,
    scheduler=None,
    workers=None,
    force=False,
    progress=None,
    log=None,
    **params,
) -> pd.DataFrame:
    """Run a parameter sweep; return the summary table (one row per point).

    Parameters
    ----------
    config : path, dict, SweepConfig or None
        A sweep TOML file, a ``[sweep]`` table as a dict, or None to give the
        keys as keyword arguments (``graph=..., alpha=[...], events=...``).
    out : path, optional
        Output folder (default: the config's ``out``; for a TOML file, a
        folder named after it next to it).
    executor : concurrent.futures.Executor, optional
        Where to run the points, e.g. ``distributed.Client(...).get_executor()``.
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://HOST:PORT``), instead of ``executor``.
    workers : int, optional
        Local processes (default: every core; 1 runs in this process).
    force : bool
        Write into a folder that holds foreign files or another sweep,
        recomputing the points whose settings changed.
    progress : bool or None
        Progress bar over points (None: on a terminal).
    log : callable, optional
        Called with one line per notable step (skipped / recomputed points).
    **params
        Keys of the ``[sweep]`` table, overriding ``config``.

    Returns
    -------
    pandas.DataFrame
        :func:`summarize`'s table.  ``attrs["out"]`` is the folder.

    Raises
    ------
    ConfigError
        For a malformed configuration (naming the field and allowed values).
    SweepError
        If points failed; finished parts are kept and a rerun retries the rest.
    """
    if executor is not None and scheduler is not None:
        raise InvalidParameterError("give either executor= or scheduler=, not both")
    cfg = _as_config(config, params)
    out = os.fspath(out) if out is not None else cfg.out
    if out is None:
        raise ConfigError("sweep needs an output folder: out=... (or sweep.out in the config)")
    log = log or (lambda msg: None)
    cfg = _prepare_out(cfg, out, force)
    points = cfg.points()
    n_points = len(points)
    rows, todo = {}, []
    for point in points:
        path = os.path.join(out, _part_name(point["index"], n_points))
        state, why = _part_state(point, path, force)
        if state == "done":
            try:
                rows[point["index"]] = _point_row(point, path, cfg.transient, cfg.m_min, cfg.m_max)
                continue
            except CatalogError:
                os.remove(path)
                why = "corrupt"
        if why in ("corrupt", "stale", "resume"):
            log(
                f"point {point['index']}: {'resuming' if why == 'resume' else 'recomputing'} "
                f"{os.path.basename(path)} ({why})"
            )
        todo.append((point, path))
    if rows:
        log(f"{len(rows)} of {n_points} points already done; skipping them")
    failures = []
    if todo:
        with _executor(executor, scheduler, workers, len(todo)) as (ex, where):
            log(f"running {len(todo)} points on {where}")
            futures = {
                ex.submit(
                    run_point,
                    point,
                    os.path.abspath(path),
                    cfg.transient,
                    cfg.chunk,
                    cfg.checkpoint_interval,
                    cfg.m_min,
                    cfg.m_max,
                ): (point, path)
                for point, path in todo
            }
            with tqdm(
                total=n_points,
                initial=len(rows),
                unit="pt",
                desc="sweep",
                disable=(None if progress is None else not progress),
            ) as bar:
                for fut in cf.as_completed(futures):
                    point, path = futures[fut]
                    try:
                        rows[point["index"]] = fut.result()
                    except Exception as exc:  # a failed point must not stop the others
                        failures.append((point, exc))
                        rows[point["index"]] = _failed_row(point, path, exc)
                        log(f"point {point['index']} failed: {type(exc).__name__}: {exc}")
                    bar.update(1)
    table = _table([rows[i] for i in sorted(rows)])
    table.attrs["out"] = out
    if failures:
        first = "; ".join(
            f"point {p['index']} ({p['graph']}, alpha={p['alpha']}): {type(e).__name__}: {e}"
            for p, e in failures[:3]
        )
        raise SweepError(
            f"{len(failures)} of {n_points} points failed: {first}. Finished "
            f"parts are kept in {out}; rerun to retry the rest",
            summary=table,
        )
    return table


def _failed_row(point, path, exc):
    row = _row(point, path, {}, {}, f"failed: {type(exc).__name__}: {exc}")
    return row


def _table(rows):
    table = pd.DataFrame(rows, columns=_SUMMARY_COLUMNS)
    for col in ("point", "replica", "events"):
        table[col] = table[col].astype("int64")
    return table


def summarize(out, *, transient=None, m_min=None, m_max=None) -> pd.DataFrame:
    """Summary table of a sweep folder (or a folder of catalogs): one row per point.

    Columns: point, replica, graph, n_blocks, k, sigma, alpha, dt, events,
    transient, M_min, M_max, b_mle, b_mle_err, m_min, m_max, n_fit, b_lsq,
    b_lsq_err, wall_time_s, events_per_s, seed_entropy, spawn_key, status
    (``done``, ``missing``, ``partial a/b``, ``corrupt: ...``) and part.
    ``transient``, ``m_min``, ``m_max`` default to the sweep's settings.
    """
    out = os.fspath(out)
    if not os.path.isdir(out):
        raise InvalidParameterError(f"{out} is not a folder")
    manifest = os.path.join(out, MANIFEST)
    if not os.path.isfile(manifest):
        return _summarize_catalogs(out, transient, m_min, m_max)
    with open(manifest, encoding="utf-8") as fh:
        record = json.load(fh)
    conf = record["config"]
    cfg = SweepConfig(
        graphs=conf["graphs"],
        events=conf["events"],
        k=conf["k"],
        sigma=conf["sigma"],
        alpha=conf["alpha"],
        dt=conf["dt"],
        replicas=conf["replicas"],
        seed=conf["seed"],
    )
    transient = conf.get("transient", 0) if transient is None else transient
    m_min = conf.get("m_min") if m_min is None else m_min
    m_max = conf.get("m_max") if m_max is None else m_max
    points = cfg.points()
    rows = []
    for point in points:
        path = os.path.join(out, _part_name(point["index"], len(points)))
        if os.path.exists(path):
            try:
                rows.append(_point_row(point, path, transient, m_min, m_max))
            except CatalogError as exc:
                rows.append(_row(point, path, {}, {}, f"corrupt: {exc}"))
            continue
        st = checkpoint_status(path)
        status = f"partial {st['events_done']}/{point['events']}" if st else "missing"
        rows.append(_row(point, path, {}, {}, status))
    table = _table(rows)
    table.attrs["out"] = out
    return table


def _summarize_catalogs(out, transient, m_min, m_max):
    rows = []
    names = sorted(n for n in os.listdir(out) if n.endswith(".parquet") and not is_tmp_name(n))
    for i, name in enumerate(names):
        path = os.path.join(out, name)
        try:
            md = read_metadata(path)
        except CatalogError:
            continue  # not a faultnet catalog
        point = md.get("sweep_point") or {
            "index": i,
            "replica": 0,
            "graph": md.get("graph_spec") or md.get("graph"),
            "k": md.get("k"),
            "sigma": md.get("sigma"),
            "alpha": md.get("alpha"),
            "dt": md.get("dt"),
            "seed_entropy": md.get("seed_entropy"),
            "spawn_key": list(md.get("seed_spawn_key") or ()),
        }
        try:
            rows.append(_point_row(point, path, transient, m_min, m_max))
        except CatalogError as exc:
            rows.append(_row(point, path, md, {}, f"corrupt: {exc}"))
    if not rows:
        raise InvalidParameterError(f"{out} holds no sweep ({MANIFEST}) and no faultnet catalogs")
    table = _table(rows)
    table.attrs["out"] = out
    return table
