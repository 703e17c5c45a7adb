"""Checks of the fields of a ``[sweep]`` table, one function per field or group.

Each check takes the raw TOML value and returns the validated one, or raises a
:class:`~faultnet.exceptions.ConfigError` that names the key (``sweep.alpha``)
and the allowed values.  :meth:`faultnet.runs.sweep.config.SweepConfig.from_dict`
puts them together; the schema is in :mod:`faultnet.runs.sweep.config`.
"""

from __future__ import annotations

import difflib
import itertools
import os
import string

from faultnet._validate import check_finite, check_int
from faultnet.exceptions import ConfigError, InvalidParameterError

__all__ = [
    "ALLOWED_KEYS",
    "LIST_KEYS",
    "expand_graphs",
    "graph_templates",
    "graph_vars",
    "integer",
    "model",
    "numbers",
    "out_folder",
    "run_options",
    "run_settings",
    "unknown_key",
]

LIST_KEYS = ("k", "sigma", "alpha", "nu", "eta", "ofc_alpha", "dt")
ALLOWED_KEYS = {
    "graph": 'graph spec or list of specs (required), e.g. "ring:200"',
    "events": "events per point, integer > 0 (required)",
    "alpha": "number or list of numbers >= 0",
    "k": "number or list of numbers > 0",
    "sigma": "number or list of numbers in (0, 1)",
    "nu": "number or list of numbers >= 0: the plate's velocity during slip events (default 0)",
    "eta": "number or list of numbers >= 0: the springs' viscous coupling (default 0)",
    "dt": "number or list of numbers > 0",
    "model": '"carlson-langer" (default) or "ofc" (the OFC automaton: k or ofc_alpha, no '
    "sigma, alpha, nu, eta or dt)",
    "ofc_alpha": 'number or list of numbers > 0: the OFC automaton\'s conservation (model = "ofc")',
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
    "nu": (lambda v: v >= 0, ">= 0"),
    "eta": (lambda v: v >= 0, ">= 0"),
    "ofc_alpha": (lambda v: v > 0, "> 0 (and below 1/q on a graph of coordination q)"),
    "dt": (lambda v: v > 0, "> 0"),
}


def _is_number(x):
    try:
        check_finite("x", x)
    except InvalidParameterError:
        return False
    return True


def unknown_key(key, where, allowed):
    """The error for a key not in ``allowed``, with the nearest allowed key as a hint."""
    near = difflib.get_close_matches(key, list(allowed), n=1)
    hint = f" (did you mean {near[0]!r}?)" if near else ""
    return ConfigError(f"unknown key {key!r} in {where}{hint}; allowed keys: {', '.join(allowed)}")


def numbers(name, value):
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


def integer(name, value, minimum, required=False, default=None):
    """An integer >= ``minimum`` (``default`` when not given, an error when ``required``)."""
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


def graph_templates(table):
    """``sweep.graph`` as a non-empty list of spec strings (which may hold ``{name}``)."""
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


def graph_vars(table):
    """``sweep.vars`` as a dict of non-empty lists of numbers or strings."""
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


def expand_graphs(templates, variables):
    """Every graph spec of the templates, vars varying fastest in the order listed."""
    from faultnet.runs.spec_parser import parse_graph_spec

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


def run_settings(table):
    """events, transient, checkpoint_interval, m_min and m_max of a ``[sweep]`` table."""
    events = integer("events", table.get("events"), 1, required=True)
    transient = integer("transient", table.get("transient"), 0, default=0)
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


def out_folder(out, base_dir):
    """``sweep.out``, relative to ``base_dir`` (the sweep file's folder) unless absolute."""
    if out is None:
        return None
    if not isinstance(out, str) or not out:
        raise ConfigError(f"sweep.out: expected a folder name; got {out!r}")
    if base_dir is not None and not os.path.isabs(out):
        out = os.path.join(base_dir, out)
    return out


def run_options(table, where):
    """The RunOptions of ``[sweep.options]`` and ``rtol``, as the dict of the fields given."""
    from faultnet.solver.options import RunOptions

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


def model(table, lists, options):
    """The sweep's model: None (Carlson-Langer, the default) or ``"ofc"``, with the parameter
    lists that belong to it."""
    from faultnet.runs.specs import MODELS

    name = table.get("model")
    if name is not None and name not in MODELS:
        raise ConfigError(
            f"sweep.model: expected one of {', '.join(map(repr, MODELS))}; got {name!r}"
        )
    if name != "ofc":
        if lists["ofc_alpha"] != [None]:
            raise ConfigError('sweep.ofc_alpha is the OFC automaton\'s: add model = "ofc"')
        return None
    wrong = [key for key in ("sigma", "alpha", "nu", "eta", "dt") if lists[key] != [None]]
    wrong += ["options" if "rtol" not in options else "rtol"] if options else []
    if wrong:
        raise ConfigError(
            f"sweep.{', sweep.'.join(wrong)}: not parameters of the OFC automaton (model = "
            '"ofc"), which has no friction, no viscosity and no integration; give k or ofc_alpha'
        )
    if lists["k"] != [None] and lists["ofc_alpha"] != [None]:
        raise ConfigError("sweep: give the OFC automaton k or ofc_alpha, not both")
    return "ofc"
