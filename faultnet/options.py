"""Run options: every choice that changes a run's numbers, in one frozen record.

A :class:`RunOptions` is validated once, when it is made, with errors that name
the option and its allowed values.  :func:`faultnet.simulate`, the
:class:`~faultnet.Simulator`, long runs to Parquet, sweep files and the
command line all take one; it is recorded whole in
``SimulationResult.metadata["options"]`` and in a checkpoint's identity, so a
resume with other options is refused.

>>> from faultnet import RunOptions
>>> opts = RunOptions(crossings="exact", dt=0.01)
>>> opts.crossings, opts.dt
('exact', 0.01)
>>> RunOptions.from_dict(opts.to_dict()) == opts
True
>>> RunOptions(method="euler")
Traceback (most recent call last):
...
faultnet.exceptions.InvalidParameterError: method must be one of ['dopri5']; got 'euler'
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from faultnet._validate import check_positive
from faultnet.exceptions import InvalidParameterError

__all__ = [
    "CROSSINGS",
    "DEFAULT_RTOL",
    "DT_COEFFICIENT",
    "METHODS",
    "REMOVED",
    "RunOptions",
    "check_crossings",
    "default_dt",
    "omega2_max",
]

#: integration schemes inside events
METHODS = ("dopri5",)
#: default step = DT_COEFFICIENT[method] / sqrt(omega2_max); see :func:`default_dt`
DT_COEFFICIENT = {"dopri5": 0.3}
#: explicit Runge-Kutta steps lose stability on an oscillator near omega*dt = 3; steps from
#: omega*dt = 2.5 on are refused
DT_STABILITY = 2.5
#: the default target accuracy of an event's slip (see :class:`RunOptions`)
DEFAULT_RTOL = 1e-6
#: options and values that faultnet no longer has, with what to use instead
REMOVED = {
    "method='rk4'": (
        "method='rk4' was removed in faultnet 0.3.0: events are integrated with 'dopri5' "
        "(Dormand-Prince 5(4)) only; leave method out, and pass dt=<step> (--dt) for a fixed "
        "step of your own or rtol=<accuracy> (--rtol) for a calibrated one"
    ),
    "local_regions_from": (
        "local_regions_from was removed in faultnet 0.3.0: large events on 2-D graphs take "
        "crossings='interpolated' (the default there, and faster than the local regions "
        "were); pass crossings='exact' (--crossings exact) for the fifth-order treatment of "
        "every crossing"
    ),
}
#: crossing treatments (each has its entry kernel, see :meth:`RunOptions.entry`)
CROSSINGS = ("exact", "interpolated")
#: an event may take at most this many steps of ``dt`` (``max_event_duration / dt``)
MAX_STEPS_PER_EVENT = 1e9


def omega2_max(model) -> float:
    """The squared top frequency, plus the alpha growth rate: the step's scale.

    ``model.top_stiffness + max_i alpha_i^2``: the first term is the largest
    eigenvalue of the stiffness matrix ``I + L`` (estimated from above, at most
    Gershgorin's bound ``max_i (1 + 2 sum_j k_ij)``; :mod:`faultnet._spectrum`);
    the second accounts for the growth rate of the negative damping ``2 alpha``.

    >>> import faultnet
    >>> ring = faultnet.CarlsonLanger(faultnet.graphs.ring(100), k=16, alpha=1.0)
    >>> omega2_max(ring)
    66.0
    """
    return float(model.top_stiffness + np.max(model.alpha_values) ** 2)


def _check_method(method):
    if method == "rk4":
        raise InvalidParameterError(REMOVED["method='rk4'"])
    if not isinstance(method, str) or method not in METHODS:
        raise InvalidParameterError(f"method must be one of {list(METHODS)}; got {method!r}")
    return method


def check_crossings(crossings):
    """``crossings`` if it is a crossing treatment or None, else a clear error."""
    if crossings is not None and crossings not in CROSSINGS:
        raise InvalidParameterError(
            f"crossings must be one of {list(CROSSINGS)} or None; got {crossings!r}"
        )
    return crossings


def default_dt(model, method: str = "dopri5") -> float:
    """The fixed step ``DT_COEFFICIENT[method] / sqrt(omega2_max(model))``.

    Runs use it with ``RunOptions(rtol=None)``; by default the step follows
    ``rtol`` (:func:`faultnet.accuracy.step_for_rtol`).  With the coefficient 0.3,
    slip sizes of single events are within 3e-7 relative of the dt -> 0 limit on
    the one-block, two-block and ring test cases (``tests/test_convergence.py``).

    >>> import faultnet
    >>> one = faultnet.CarlsonLanger(faultnet.graphs.chain(1), alpha=2.0)
    >>> round(default_dt(one), 6)
    0.134164
    """
    return DT_COEFFICIENT[_check_method(method)] / math.sqrt(omega2_max(model))


def _stiffest_spring(model):
    """``(node, node, k)`` of the stiffest spring of ``model`` (the plate's where it has none)."""
    adj = model.adjacency.tocoo()
    if adj.nnz == 0:
        return "plate", model.nodes[0], 1.0
    i = int(np.argmax(adj.data))
    return model.nodes[int(adj.row[i])], model.nodes[int(adj.col[i])], float(adj.data[i])


@dataclass(frozen=True)
class RunOptions:
    """The numerical choices of a run (all of them change results).

    Parameters
    ----------
    method : {"dopri5"}
        Scheme inside events: fixed-step Dormand-Prince 5(4), the only one.
    dt : float or None
        Integration step inside events; it overrides ``rtol``.  None: from
        ``rtol``, or :func:`default_dt` of the model and method when ``rtol``
        is None.
    rtol : float or None
        Target relative accuracy of an event's slip (1e-8 to 1e-4, default
        1e-6): the step and the crossing treatment come from the calibration
        of :func:`faultnet.accuracy.step_for_rtol` (the 90th percentile of the
        relative S error of typical multi-block events is within rtol).  None:
        the fixed step :func:`default_dt`.
    crossings : {"exact", "interpolated"} or None
        Treatment of stops (v -> 0) and joins (F -> 1) inside a step:
        ``"exact"`` redoes the step to each crossing and keeps the scheme's
        order; ``"interpolated"`` places them on the step's dense output and
        never redoes a step (fourth order, cheaper on lattices).
        None: the calibration's choice with ``rtol``, else ``"exact"``.
    solo_cache : bool
        An event whose hypocentre slips alone depends only on that block's
        stiffness, sigma and alpha: integrate it once per such parameter class
        and reuse it (True, default), or integrate every event (False, the
        reference in tests).
    max_event_duration : float
        An event lasting longer (time units) stops the run with an error.
    max_velocity : float
        A block faster than this stops the run with an error (runaway).
    """

    method: str = "dopri5"
    dt: float | None = None
    rtol: float | None = DEFAULT_RTOL
    crossings: str | None = None
    solo_cache: bool = True
    max_event_duration: float = 1e4
    max_velocity: float = 1e3

    def __new__(cls, *args, **kwargs):
        if "local_regions_from" in kwargs:  # before the dataclass's own "unexpected keyword"
            raise InvalidParameterError(REMOVED["local_regions_from"])
        return super().__new__(cls)

    def __post_init__(self):
        _check_method(self.method)
        if self.dt is not None:
            object.__setattr__(self, "dt", check_positive("dt", self.dt))
        if self.rtol is not None:
            from faultnet.accuracy import RTOL_RANGE

            rtol = check_positive("rtol", self.rtol)
            if not RTOL_RANGE[0] <= rtol <= RTOL_RANGE[1]:
                raise InvalidParameterError(
                    f"rtol must be between {RTOL_RANGE[0]:g} and {RTOL_RANGE[1]:g}; got {rtol!r}"
                )
            object.__setattr__(self, "rtol", rtol)
        check_crossings(self.crossings)
        if not isinstance(self.solo_cache, bool | np.bool_):
            raise InvalidParameterError(
                f"solo_cache must be True or False; got {self.solo_cache!r}"
            )
        object.__setattr__(self, "solo_cache", bool(self.solo_cache))
        for name in ("max_event_duration", "max_velocity"):
            object.__setattr__(self, name, check_positive(name, getattr(self, name)))

    def step(self, model) -> float:
        """The step of a run of ``model``: ``dt``, or the default, checked for stability.

        A step beyond the stability limit, or one that would need more
        than 10^9 steps for an event of ``max_event_duration``, is refused.
        """
        limit = DT_STABILITY / math.sqrt(omega2_max(model))
        if self.dt is not None:
            dt = self.dt
        elif self.rtol is not None:
            dt = self._calibrated(model).dt
        else:
            dt = default_dt(model, self.method)
        if dt > limit:
            raise InvalidParameterError(
                f"dt={dt:g} is beyond the stability limit {limit:.4g} of this model "
                f"(stiffest block); use dt <= {limit:.4g} or leave dt=None for "
                f"{default_dt(model, self.method):.4g}"
            )
        stiff = self.max_event_duration / default_dt(model, self.method) > MAX_STEPS_PER_EVENT
        if self.dt is None and stiff:  # the model, not the accuracy asked, needs tiny steps
            a, b, k = _stiffest_spring(model)
            raise InvalidParameterError(
                f"the spring k={k:g} on edge ({a!r}, {b!r}) is too stiff to integrate: it "
                f"needs steps of dt={dt:.3g}, and an event could take more than "
                f"{MAX_STEPS_PER_EVENT:.0e} of them; check the edge's k (in units of the "
                f"plate spring)"
            )
        if self.max_event_duration / dt > MAX_STEPS_PER_EVENT:
            raise InvalidParameterError(
                f"dt={dt:g} is too small: an event of max_event_duration="
                f"{self.max_event_duration:g} would take more than {MAX_STEPS_PER_EVENT:.0e} "
                f"steps and could run for days; use dt >= "
                f"{self.max_event_duration / MAX_STEPS_PER_EVENT:.3g} (default "
                f"{default_dt(model, self.method):.4g})"
            )
        return dt

    def _calibrated(self, model):
        from faultnet.accuracy import step_for_rtol

        return step_for_rtol(model, self.rtol, self.method, self.crossings)

    def treatment(self, model) -> str:
        """The crossing treatment of a run of ``model``: ``"exact"`` or ``"interpolated"``."""
        if self.crossings is not None:
            return self.crossings
        if self.rtol is not None and self.dt is None:
            return self._calibrated(model).crossings
        return "exact"

    def entry(self, model) -> str:
        """Name of the entry kernel (:mod:`faultnet._kernels.carlson_langer.events`) of a run of
        ``model``: one per crossing treatment, so that a run compiles only its own code."""
        if self.treatment(model) == "interpolated":
            return "run_events_dopri5_interpolated"
        return "run_events_dopri5"

    def replace(self, **changes) -> RunOptions:
        """A copy with ``changes`` applied (and validated)."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict:
        """Plain JSON-friendly values."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, d) -> RunOptions:
        """Inverse of :meth:`to_dict`; unknown keys are refused by name.

        A record written by faultnet 0.2 holds ``local_regions_from``: left out where it had no
        effect (None, or ``inf``: the whole-event treatment), refused otherwise.
        """
        if not isinstance(d, dict):
            raise InvalidParameterError(f"run options must be a table/dict; got {d!r}")
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(d) - names - {"local_regions_from"})
        if unknown:
            raise InvalidParameterError(
                f"unknown run option(s) {unknown}; allowed: {sorted(names)}"
            )
        d = dict(d)
        if d.get("local_regions_from", 0) in (None, "inf", "Infinity", math.inf):
            del d["local_regions_from"]
        return cls(**d)

    @classmethod
    def coerce(cls, options) -> RunOptions:
        """``options`` as a RunOptions: None (defaults), a RunOptions or a dict."""
        if options is None:
            return cls()
        if isinstance(options, cls):
            return options
        if isinstance(options, dict):
            return cls.from_dict(options)
        raise InvalidParameterError(
            f"options must be a RunOptions, a dict or None; got {type(options).__name__}"
        )
