"""The integration step: its scale, the default fixed step and the choices that set it.

Every step of faultnet is a multiple of ``1 / sqrt(omega2_max(model))``, the
period scale of the stiffest mode.  :func:`default_dt` is the fixed step that
``RunOptions(rtol=None)`` takes; :mod:`faultnet.solver.accuracy` calibrates the
coefficient to a target accuracy.
"""

from __future__ import annotations

import math

import numpy as np

from faultnet.exceptions import InvalidParameterError

__all__ = [
    "CROSSINGS",
    "DEFAULT_RTOL",
    "DT_COEFFICIENT",
    "METHODS",
    "REMOVED",
    "VISCOUS_SAFETY",
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
    "solo_cache": (
        "solo_cache is no longer a run option: the cache of lone slips is part of the engine "
        "and always on (its events agree with full integration to round-off); a reference "
        "run without it is Simulator(model, ..., solo_cache=False)"
    ),
}
#: crossing treatments (each has its entry kernel, see :meth:`RunOptions.entry`)
CROSSINGS = ("exact", "interpolated")
#: viscous models take the exact step of ``rtol / VISCOUS_SAFETY`` (``accuracy.step_for_rtol``):
#: the calibration has no dashpots, and their 90% error reached 2.4 rtol at the calibrated step
#: on one of 24 random graphs (1.16 rtol at most with it; the plate alone, 0.61 rtol at most;
#: ``benchmarks/README.md``)
VISCOUS_SAFETY = 2.0
#: an event may take at most this many steps of ``dt`` (``max_event_duration / dt``)
MAX_STEPS_PER_EVENT = 1e9


def omega2_max(model) -> float:
    """The squared top frequency, plus the alpha growth rate: the step's scale.

    ``model.top_stiffness + max_i alpha_i^2``: the first term is the largest
    eigenvalue of the stiffness matrix ``I + L`` (estimated from above, at most
    Gershgorin's bound ``max_i (1 + 2 sum_j k_ij)``; :mod:`faultnet.model.spectrum`);
    the second accounts for the growth rate of the negative damping ``2 alpha``; viscous
    coupling adds the square of its fastest decay rate (:func:`_viscous_rate`).

    >>> import faultnet
    >>> ring = faultnet.CarlsonLanger(faultnet.graphs.ring(100), k=16, alpha=1.0)
    >>> omega2_max(ring)
    66.0
    """
    top = model.top_stiffness + np.max(model.alpha_values) ** 2
    if getattr(model, "viscous", False):
        top += _viscous_rate(model) ** 2
    return float(top)


def _viscous_rate(model) -> float:
    """Gershgorin's bound on the viscous coupling's fastest decay rate, ``max_i 2 sum_j eta_ij``.

    A damping rate ``c`` gives an explicit step the time scale ``1 / c``; adding ``c^2`` to
    the squared top frequency keeps the step's coefficient meaning the same where viscosity
    is small and shortens the step where it dominates.
    """
    indptr = model.adjacency.indptr
    rows = np.repeat(np.arange(indptr.size - 1), np.diff(indptr))
    return float(2.0 * np.max(np.bincount(rows, weights=model.eta_values), initial=0.0))


def check_method(method):
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
    ``rtol`` (:func:`faultnet.solver.accuracy.step_for_rtol`).  With the coefficient 0.3,
    slip sizes of single events are within 3e-7 relative of the dt -> 0 limit on
    the one-block, two-block and ring test cases (``tests/solver/test_convergence.py``).

    >>> import faultnet
    >>> one = faultnet.CarlsonLanger(faultnet.graphs.chain(1), alpha=2.0)
    >>> round(default_dt(one), 6)
    0.134164
    """
    return DT_COEFFICIENT[check_method(method)] / math.sqrt(omega2_max(model))


def stiffest_spring(model):
    """``(node, node, k)`` of the stiffest spring of ``model`` (the plate's where it has none)."""
    adj = model.adjacency.tocoo()
    if adj.nnz == 0:
        return "plate", model.nodes[0], 1.0
    i = int(np.argmax(adj.data))
    return model.nodes[int(adj.row[i])], model.nodes[int(adj.col[i])], float(adj.data[i])
