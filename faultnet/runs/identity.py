"""What makes two runs the same run: the identity a resume, an extension and a finished
output are checked against, and the tables a run writes besides its events.

``run.json`` and every catalog record the fields :data:`IDENTITY`; :func:`mismatch` names the
ones in which a stored run and a call differ (a resume, an extension or ``--resume`` of a
finished output is then refused, naming them).

The plate's velocity during events ``nu`` and the viscous coupling ``eta`` of a
Carlson-Langer model are identity fields where they are not 0 (a run records them, as its
metadata does, only then); a file without them was written with ``nu = eta = 0``, so the runs
of before resume as they did, and a change of either is refused by name.  Per-edge ``eta``
values are in the ``graph_hash``.

>>> mismatch({"graph_hash": "h"}, {"graph_hash": "h", "nu": 0.01})
['nu: checkpoint has 0.0, this call 0.01']
>>> mismatch({"graph_hash": "h", "eta": 0.0}, {"graph_hash": "h"})
[]
"""

from __future__ import annotations

from faultnet.io.slips import SIDE_TABLES

__all__ = ["IDENTITY", "IDENTITY_DEFAULTS", "mismatch", "run_identity", "side_tables"]

#: run.json fields that must agree for a resume to continue the same run
IDENTITY = (
    "n_events",
    "dt",
    "options",
    "seed_entropy",
    "seed_spawn_key",
    "nu",
    "eta",
    "graph_hash",
    "record_slips",
)
#: the value of an identity field that files written before it existed lack
IDENTITY_DEFAULTS = {"record_slips": False, "nu": 0.0, "eta": 0.0}
#: identity fields a run records only where they are not 0: the model's parameters of that
#: name (in its metadata only then too)
_MODEL_FIELDS = ("nu", "eta")


def side_tables(model, record_slips) -> tuple:
    """The side tables a run of ``model`` writes: the per-block slips where ``record_slips``,
    the per-fault slips on a network of faults (of blocks: an automaton's topplings are not
    summed per fault)."""
    per_fault = model.faults is not None and model.params.get("model") != "ofc"
    return tuple(
        name for name, wanted in zip(SIDE_TABLES, (record_slips, per_fault), strict=True) if wanted
    )


def run_identity(model, n_events, dt, options, seq, record_slips=False) -> dict:
    """What makes two runs the same run (compared by :func:`mismatch` on resume)."""
    from faultnet.model.identity import graph_hash
    from faultnet.runs.models import options_record

    params = model.params
    return {
        "n_events": int(n_events),
        "dt": float(dt),
        "options": options_record(model, options),
        "seed_entropy": seq.entropy,
        "seed_spawn_key": list(seq.spawn_key),
        "graph_hash": graph_hash(model),
        "record_slips": bool(record_slips),
        **{key: float(params[key]) for key in _MODEL_FIELDS if key in params},
    }


def mismatch(stored, wanted, keys=IDENTITY) -> list:
    """The identity fields in which ``stored`` and ``wanted`` differ, as sentences."""
    diffs = []
    for key in keys:
        default = IDENTITY_DEFAULTS.get(key)
        a, b = stored.get(key, default), wanted.get(key, default)
        if isinstance(a, list | tuple) or isinstance(b, list | tuple):
            a, b = list(a or []), list(b or [])
        if a != b:
            diffs.append(
                f"{key}: checkpoint has {stored.get(key, default)!r}, this call "
                f"{wanted.get(key, default)!r}"
            )
    return diffs
