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

from faultnet._validate import check_positive
from faultnet.exceptions import InvalidParameterError
from faultnet.solver.accuracy import RTOL_RANGE, step_for_rtol
from faultnet.solver.step_size import (
    DEFAULT_RTOL,
    DT_STABILITY,
    MAX_STEPS_PER_EVENT,
    REMOVED,
    check_crossings,
    check_method,
    default_dt,
    omega2_max,
    stiffest_spring,
)

__all__ = ["RunOptions"]


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
        of :func:`faultnet.solver.accuracy.step_for_rtol` (the 90th percentile of the
        relative S error of typical multi-block events is within rtol).  None:
        the fixed step :func:`default_dt`.
    crossings : {"exact", "interpolated"} or None
        Treatment of stops (v -> 0) and joins (F -> 1) inside a step:
        ``"exact"`` redoes the step to each crossing and keeps the scheme's
        order; ``"interpolated"`` places them on the step's dense output and
        never redoes a step (fourth order, cheaper on lattices).
        None: the calibration's choice with ``rtol``, else ``"exact"``.
    max_event_duration : float
        An event lasting longer (time units) stops the run with an error.
    max_velocity : float
        A block faster than this stops the run with an error (runaway).
    """

    method: str = "dopri5"
    dt: float | None = None
    rtol: float | None = DEFAULT_RTOL
    crossings: str | None = None
    max_event_duration: float = 1e4
    max_velocity: float = 1e3

    def __new__(cls, *args, **kwargs):
        for name in ("local_regions_from", "solo_cache"):  # before "unexpected keyword"
            if name in kwargs:
                raise InvalidParameterError(REMOVED[name])
        return super().__new__(cls)

    def __post_init__(self):
        check_method(self.method)
        if self.dt is not None:
            object.__setattr__(self, "dt", check_positive("dt", self.dt))
        if self.rtol is not None:
            rtol = check_positive("rtol", self.rtol)
            if not RTOL_RANGE[0] <= rtol <= RTOL_RANGE[1]:
                raise InvalidParameterError(
                    f"rtol must be between {RTOL_RANGE[0]:g} and {RTOL_RANGE[1]:g}; got {rtol!r}"
                )
            object.__setattr__(self, "rtol", rtol)
        check_crossings(self.crossings)
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
            a, b, k = stiffest_spring(model)
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
        crossings = "exact" if _moving_or_viscous(model) else self.crossings
        return step_for_rtol(model, self.rtol, self.method, crossings)

    def treatment(self, model) -> str:
        """The crossing treatment of a run of ``model``: ``"exact"`` or ``"interpolated"``.

        A model whose plate moves during events (``nu > 0``) or with viscous coupling
        (``eta > 0``) takes ``"exact"``: the interpolated crossings place joins on a path
        that has neither term.
        """
        if _moving_or_viscous(model):
            if self.crossings == "interpolated":
                raise InvalidParameterError(
                    "crossings='interpolated' is not available with nu > 0 or eta > 0 (the "
                    "plate moving during events, viscous coupling); leave crossings=None or "
                    "pass crossings='exact'"
                )
            return "exact"
        if self.crossings is not None:
            return self.crossings
        if self.rtol is not None and self.dt is None:
            return self._calibrated(model).crossings
        return "exact"

    def entry(self, model) -> str:
        """Name of the entry kernel (:mod:`~faultnet.solver._kernels.carlson_langer.events`) of a
        run of
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

        A record written by faultnet 0.2 holds ``local_regions_from`` and ``solo_cache``: left
        out where they had no effect (None or ``inf``; True), refused otherwise.
        """
        if not isinstance(d, dict):
            raise InvalidParameterError(f"run options must be a table/dict; got {d!r}")
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(d) - names - {"local_regions_from", "solo_cache"})
        if unknown:
            raise InvalidParameterError(
                f"unknown run option(s) {unknown}; allowed: {sorted(names)}"
            )
        d = dict(d)
        if d.get("local_regions_from", 0) in (None, "inf", "Infinity", math.inf):
            del d["local_regions_from"]
        if d.get("solo_cache") is True:
            del d["solo_cache"]
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


def _moving_or_viscous(model) -> bool:
    """Whether ``model``'s plate moves during events or its springs are viscous."""
    return getattr(model, "nu", 0.0) > 0.0 or bool(getattr(model, "viscous", False))
