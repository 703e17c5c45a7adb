"""The accuracy knob: from a target relative error of an event's slip to the integration settings.

``rtol`` is the target relative accuracy of an event's slip S: at the settings
:func:`step_for_rtol` returns, the 90th percentile of ``|S / S_true - 1|`` over typical
multi-block events is at most ``rtol`` on every benchmark workload (W1-W6 of
``benchmarks/run.py``: rings of 2,000 blocks at alpha 1, 2, 0.25; the periodic 150^2
lattice; the square and triangular critical percolation clusters).

Two crossing treatments (``faultnet.solver._kernels.carlson_langer.slip``):

- ``"exact"``: every stop and join is reached by the scheme itself (partial steps),
  so events keep the fifth order of the DP5 steps;
- ``"interpolated"``: every full step is kept, and the crossings inside it are placed from
  what the step computed (``carlson_langer.interp``, ``response``): far cheaper per
  crossing, and with the neighbours' answer to each crossing as accurate as the exact
  treatment on small events at the same step.

``CALIBRATION`` holds, per graph class (rings: W1-W3; 2-D graphs: W4-W6) and treatment, the
90th-percentile error of the class's worst workload per step coefficient (step =
coefficient / sqrt(omega2_max), :func:`faultnet.solver.step_size.omega2_max`: the top eigenvalue of
the stiffness matrix plus alpha^2), measured by::

    PYTHONPATH=. python benchmarks/calibrate.py      # 60 events per workload
    PYTHONPATH=. python benchmarks/calibrate.py W4 W5 W6 --events 150 --treatments interpolated
    PYTHONPATH=. python benchmarks/calibrate.py W1 W2 W3 --events 100 --treatments interpolated
    PYTHONPATH=. python benchmarks/calibrate.py W4 --treatments interpolated --alpha 0.5
    PYTHONPATH=. python benchmarks/calibrate.py W4 --treatments exact --alpha 3
    PYTHONPATH=. python benchmarks/calibrate.py W1 --events 100 --treatments exact --alpha 3

(each column's text below :data:`CALIBRATION` names the workloads and alphas it is the
worst of).  The interpolated columns were measured with the stopping and joining blocks' own
paths integrated by four RK4 sub-steps; their Taylor series (``carlson_langer.physics.lone_path``)
gives the same 90th percentiles within 1% on W1-W6 at coefficients 0.05 to 0.6, from the
same pre-event states.

====== ============ ============ ============ ============ ============
coef    ring exact   ring interp  2-D exact    2-D interp   2-D interp
                                               alpha 0.25-  alpha 0.5-3
                                               0.5
====== ============ ============ ============ ============ ============
0.03                 5.9e-11                   1.0e-11      1.1e-11
0.05                 5.6e-10                   8.6e-11      7.5e-11
0.07                 3.4e-09                   4.7e-10      5.0e-10
0.10    1.1e-08      1.9e-08      3.0e-09      3.1e-09      2.9e-09
0.15    8.2e-08      1.3e-07      2.1e-08      2.3e-08      2.2e-08
0.20    3.3e-07      4.9e-07      8.1e-08      9.5e-08      8.5e-08
0.30    2.3e-06      3.2e-06      4.8e-07      6.6e-07      6.0e-07
0.40    7.7e-06      1.2e-05      1.5e-06      2.6e-06      2.0e-06
0.50    1.9e-05      3.0e-05      5.1e-06      7.8e-06      5.3e-06
0.60    3.7e-05      6.2e-05      1.4e-05      1.8e-05      1.2e-05
0.80    1.4e-04      1.7e-04      5.9e-05      5.7e-05      5.8e-05
====== ============ ============ ============ ============ ============

The interpolated columns are from 150 events per 2-D workload and 100 per ring.  Events of
10 or more blocks are less accurate than the 90th percentile over all multi-block events says
(``benchmarks/calibrate.py`` prints their error next to the table's; see the accuracy guide);
where the largest events matter most, use ``RunOptions(crossings="exact")`` or a smaller rtol.

The error depends on alpha too, and each column holds over a measured alpha band
(``calibrate.py W1 --alpha A``; :data:`CALIBRATION`).  At coefficient 0.479 the ring's
error is 2.0e-5 at alpha 0.05, 1.6e-5 at 0.1, 1.5e-5 at 0.25, 8.5e-6 at 0.5, 6.2e-6 at
0.75, 3.5e-6 at 1, 3.2e-6 at 1.5, 8.4e-6 at 2, 1.7e-5 at 2.5, 3.5e-5 at 3, 3.3e-5 at 4 and
1.7e-5 at 5, so rings have three bands: 0-0.1 (up to 1.5 times the W1-W3 column's error
from coefficient 0.4 on), 0.1-2.5 (the W1-W3 column) and 2.5-5 (2-5 times its error); the
interpolated ring column is W1-W3 (alpha 0.25 to 2).  2-D graphs have one band, 0.25-3, for
the exact treatment (the periodic lattice at alpha 0.25, 0.5, 2 and 3 is part of its
column), and two for the interpolated one: 0.25-0.5 (the lattice at alpha 0.25 and 0.5,
up to 1.5 times the error of the other from coefficient 0.4 on) and 0.5-3 (W4-W6 and the
lattice at alpha 0.5, 2 and 3).  A model whose blocks' alphas meet several bands takes the
worst of them; outside every band it gets the nearest one and an
:class:`~faultnet.exceptions.AccuracyWarning`.

For each treatment the coefficient is read off its column (log-log between the rows, the
scheme's order below the first) at ``rtol / SAFETY``.  The interpolated treatment is chosen
wherever its column covers the model's alpha and rtol is at least
:data:`INTERPOLATED_FROM` (1e-7 on rings; everywhere on 2-D graphs): events/s of the ring
workloads W1, W2, W3 against the exact treatment, each at its calibrated step, from saved
steady states, are 6% to 8% lower at rtol 1e-8, 1% lower to 7% higher at 1e-7 (W3, W1, W2);
on the lattices the interpolated treatment is by far the faster.  An explicit
``crossings=`` takes that treatment's own coefficient.  Resulting settings:

====== ============== ================== ================ ============== ==================
rtol   rings, alpha   rings, alpha       rings, alpha     rings, alpha   2-D graphs, alpha
       0-0.1          0.1-0.25, 2-2.5    0.25-2           2.5-5          0.25-0.5 / 0.5-3
====== ============== ================== ================ ============== ==================
1e-8   exact 0.094    exact 0.094        exact 0.094      exact 0.094    interpolated 0.110
                                                                         / 0.112
1e-7   exact 0.149    exact 0.149        interpolated     exact 0.148    interpolated 0.176
                                         0.123                           / 0.179
1e-6   exact 0.241    exact 0.241        interpolated     exact 0.231    interpolated 0.283
                                         0.201                           / 0.289
2e-5   exact 0.454    exact 0.479        interpolated     exact 0.400    interpolated 0.528
                                         0.384                           / 0.576
1e-4   exact 0.666    exact 0.709        interpolated     exact 0.536    interpolated 0.774
                                         0.568                           / 0.779
====== ============== ================== ================ ============== ==================
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from faultnet.exceptions import AccuracyWarning, InvalidParameterError
from faultnet.solver.step_size import CROSSINGS, VISCOUS_SAFETY, check_crossings

__all__ = [
    "CALIBRATION",
    "CROSSINGS",
    "INTERPOLATED_FROM",
    "RTOL_RANGE",
    "StepChoice",
    "graph_class",
    "step_for_rtol",
]

#: the calibrated range of rtol
RTOL_RANGE = (1e-8, 1e-4)
#: the target error is rtol / SAFETY[graph class][treatment]: the table's 90th percentiles come
#: from 60-150 events each, and other systems scatter about them (interpolated crossings, 60
#: events 3,000 events after a random start, ``tests/solver/test_accuracy.py``'s systems: a ring of
#: 200 blocks 1.4e-7, 8.3e-7, 3.1e-6 at coefficients 0.2, 0.3, 0.4, below the ring column; a
#: periodic 12^2 lattice 9.7e-8, 6.6e-7, 2.4e-6, 5.7e-6 at 0.2 to 0.5, up to 1.2 times the
#: 2-D alpha 0.5-3 one)
SAFETY = {
    "ring": {"exact": 1.25, "interpolated": 2.0},
    "2-D": {"exact": 1.25, "interpolated": 2.0},
}
#: the smallest rtol at which the interpolated treatment is the faster (module text)
INTERPOLATED_FROM = {"ring": 1e-7, "2-D": RTOL_RANGE[0]}
#: order of the S error in the step, used below the first row of the table
ORDER = {"exact": 5.0, "interpolated": 4.0}
#: (coefficient, 90th-percentile S error) columns from ``benchmarks/calibrate.py``.
#: Rings, exact: the worst of W1-W3 (alpha 0.25, 1, 2; alpha 0.1 and 2.5 lie on it)
_RING_EXACT = (
    (0.1, 1.1e-08),
    (0.15, 8.2e-08),
    (0.2, 3.3e-07),
    (0.3, 2.3e-06),
    (0.4, 7.7e-06),
    (0.5, 1.9e-05),
    (0.6, 3.7e-05),
    (0.8, 1.4e-04),
)
#: rings, exact, alpha 0 to 0.1: the W1-W3 column and alpha 0.05 (100 events), up to 1.5 times
#: the column's error from coefficient 0.4 on (alpha 0 gave no multi-block event in 10^4 events
#: of W1's steady state)
_RING_EXACT_LOW = (
    (0.1, 1.1e-08),
    (0.15, 8.2e-08),
    (0.2, 3.3e-07),
    (0.3, 2.3e-06),
    (0.4, 8.9e-06),
    (0.5, 2.5e-05),
    (0.6, 5.4e-05),
    (0.8, 1.6e-04),
)
#: rings, exact, alpha 2.5 to 5: the worst of alpha 3 and 4 (alpha 2.5 and 5 lie below it),
#: 2-5 times the error of alpha 2
_RING_EXACT_HIGH = (
    (0.1, 1.1e-08),
    (0.15, 8.6e-08),
    (0.2, 3.7e-07),
    (0.3, 3.2e-06),
    (0.4, 1.6e-05),
    (0.5, 5.4e-05),
    (0.6, 1.5e-04),
    (0.8, 6.3e-04),
)
#: rings, interpolated: the worst of W1-W3 (100 events each)
_RING_INTERPOLATED = (
    (0.03, 5.9e-11),
    (0.05, 5.6e-10),
    (0.07, 3.4e-09),
    (0.1, 1.9e-08),
    (0.15, 1.3e-07),
    (0.2, 4.9e-07),
    (0.3, 3.2e-06),
    (0.4, 1.2e-05),
    (0.5, 3.0e-05),
    (0.6, 6.2e-05),
    (0.8, 1.7e-04),
)
#: 2-D graphs, exact: the worst of W4-W6 and the periodic 150^2 lattice at alpha 0.25, 2 and
#: 3 (which from coefficient 0.5 on have up to 10 times the error of alpha 1)
_2D_EXACT = (
    (0.1, 3.0e-09),
    (0.15, 2.1e-08),
    (0.2, 8.1e-08),
    (0.3, 4.8e-07),
    (0.4, 1.5e-06),
    (0.5, 5.1e-06),
    (0.6, 1.4e-05),
    (0.8, 5.9e-05),
)
#: 2-D graphs, interpolated, alpha 0.5 to 3: the worst of W4-W6 (150 events each) and the
#: periodic 150^2 lattice at alpha 0.5 (100 events), 2 and 3 (60)
_2D_INTERPOLATED = (
    (0.03, 1.1e-11),
    (0.05, 7.5e-11),
    (0.07, 5.0e-10),
    (0.1, 2.9e-09),
    (0.15, 2.2e-08),
    (0.2, 8.5e-08),
    (0.3, 6.0e-07),
    (0.4, 2.0e-06),
    (0.5, 5.3e-06),
    (0.6, 1.2e-05),
    (0.8, 5.8e-05),
)
#: 2-D graphs, interpolated, alpha 0.25 to 0.5: the periodic 150^2 lattice at alpha 0.25 and
#: 0.5 (100 events each), up to 1.5 times the error of the alpha 0.5-3 column from coefficient
#: 0.4 on
_2D_INTERPOLATED_LOW = (
    (0.03, 1.0e-11),
    (0.05, 8.6e-11),
    (0.07, 4.7e-10),
    (0.1, 3.1e-09),
    (0.15, 2.3e-08),
    (0.2, 9.5e-08),
    (0.3, 6.6e-07),
    (0.4, 2.6e-06),
    (0.5, 7.8e-06),
    (0.6, 1.8e-05),
    (0.8, 5.7e-05),
)
#: per graph class and treatment, the alpha bands ``((lowest, highest alpha), column)``; a
#: model takes the worst column of every band its blocks' alpha range meets (bands share
#: their ends, so alpha 0.1 and 2.5 take the stricter neighbour)
CALIBRATION = {
    "ring": {
        "exact": (
            ((0.0, 0.1), _RING_EXACT_LOW),
            ((0.1, 2.5), _RING_EXACT),
            ((2.5, 5.0), _RING_EXACT_HIGH),
        ),
        "interpolated": (((0.25, 2.0), _RING_INTERPOLATED),),
    },
    "2-D": {
        "exact": (((0.25, 3.0), _2D_EXACT),),
        "interpolated": (((0.25, 0.5), _2D_INTERPOLATED_LOW), ((0.5, 3.0), _2D_INTERPOLATED)),
    },
}


def graph_class(model):
    """ "ring" for graphs of mean degree <= 2.5 (rings, chains), else "2-D"."""
    return "ring" if model.adjacency.nnz <= 2.5 * model.n else "2-D"


@dataclass(frozen=True)
class StepChoice:
    """Integration settings for one accuracy.

    Attributes
    ----------
    dt : float
        The step inside events (``simulate(..., dt=)``).
    coefficient : float
        ``dt * sqrt(omega2_max(model))``.
    crossings : {"exact", "interpolated"}
        The treatment of stops and joins (:data:`CROSSINGS`).
    method : str
        The scheme ("dopri5": the calibration is for it).
    """

    dt: float
    coefficient: float
    crossings: str
    method: str = "dopri5"


def _covered(cls, crossings):
    """The alpha range ``(lowest, highest)`` that a treatment's bands span."""
    bands = CALIBRATION[cls][crossings]
    return min(b[0][0] for b in bands), max(b[0][1] for b in bands)


def _gap(covered, alpha):
    """How far the alpha range ``alpha`` reaches outside the calibrated range ``covered``."""
    return max(covered[0] - alpha[0], alpha[1] - covered[1], 0.0)


def _columns(cls, crossings, alpha):
    """The worst calibrated row over every alpha band that the range ``alpha`` =
    (lowest, highest) of a model meets (a range outside the bands is clamped to them)."""
    bands = CALIBRATION[cls][crossings]
    covered = _covered(cls, crossings)
    lo, hi = (min(max(a, covered[0]), covered[1]) for a in alpha)
    columns = [rows for (a, b), rows in bands if a <= hi and b >= lo]
    return tuple(
        (c, max(column[i][1] for column in columns)) for i, (c, _) in enumerate(columns[0])
    )


def _coefficient(rows, crossings, target):
    """Largest coefficient whose calibrated error is <= target (log-log between the rows)."""
    c0, e0 = rows[0]
    if target <= e0:
        return c0 * (target / e0) ** (1.0 / ORDER[crossings])
    best = c0
    for (c1, e1), (c2, e2) in zip(rows[:-1], rows[1:], strict=True):
        if target >= e2:
            best = c2
            continue
        f = math.log(target / e1) / math.log(e2 / e1)
        return c1 * (c2 / c1) ** f
    return best


def step_for_rtol(model, rtol, method="dopri5", crossings=None):
    """Integration settings whose typical event slip is within ``rtol`` (relative).

    Parameters
    ----------
    model : CarlsonLanger
        Sets the step's scale, ``1 / sqrt(omega2_max(model))``.
    rtol : float
        Target relative error of an event's slip S (90th percentile over multi-block
        events), between 1e-8 and 1e-4.
    method : {"dopri5"}
        The calibrated scheme.
    crossings : {None, "exact", "interpolated"}
        The crossing treatment; None picks the faster one at ``rtol`` (see the module's
        text).  Each has its own step: the interpolated treatment needs a shorter one.

    Returns
    -------
    StepChoice

    Examples
    --------
    >>> import faultnet
    >>> from faultnet.solver.accuracy import step_for_rtol
    >>> grid = faultnet.graphs.square_lattice(12, 12, periodic=True)
    >>> lattice = faultnet.CarlsonLanger(grid, k=16, sigma=0.01, alpha=1.0)
    >>> s = step_for_rtol(lattice, 2e-5)
    >>> s.crossings, round(s.coefficient, 3)
    ('interpolated', 0.576)
    >>> ring = faultnet.CarlsonLanger(faultnet.graphs.ring(100), k=16, sigma=0.01, alpha=1.0)
    >>> step_for_rtol(ring, 1e-6).crossings
    'interpolated'
    >>> round(step_for_rtol(ring, 1e-6, crossings="exact").coefficient, 3)
    0.241
    >>> step_for_rtol(ring, 5e-8).crossings  # below INTERPOLATED_FROM["ring"]
    'exact'
    >>> slow = faultnet.CarlsonLanger(faultnet.graphs.ring(100), alpha=0.1)
    >>> step_for_rtol(slow, 1e-6).crossings  # interpolated is calibrated from alpha 0.25
    'exact'
    >>> step_for_rtol(lattice, 1e-3)
    Traceback (most recent call last):
    ...
    faultnet.exceptions.InvalidParameterError: rtol must be between 1e-08 and 0.0001; got 0.001
    """
    from faultnet.solver.step_size import omega2_max

    if method != "dopri5":
        raise InvalidParameterError(
            f"step_for_rtol is calibrated for method 'dopri5'; got {method!r}"
        )
    try:
        rtol = float(rtol)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"rtol must be a number; got {rtol!r}") from None
    if not (RTOL_RANGE[0] <= rtol <= RTOL_RANGE[1]):
        raise InvalidParameterError(
            f"rtol must be between {RTOL_RANGE[0]:g} and {RTOL_RANGE[1]:g}; got {rtol!r}"
        )
    check_crossings(crossings)
    cls = graph_class(model)
    alpha = (float(np.min(model.alpha_values)), float(np.max(model.alpha_values)))
    if crossings is None:
        # the interpolated treatment is the faster from INTERPOLATED_FROM on (module text),
        # unless the exact one is calibrated nearer to this alpha
        gap = {t: _gap(_covered(cls, t), alpha) for t in CROSSINGS}
        nearer = gap["exact"] < gap["interpolated"]
        crossings = "exact" if nearer or rtol < INTERPOLATED_FROM[cls] else "interpolated"
    covered = _covered(cls, crossings)
    if _gap(covered, alpha) > 0.0 and model.adjacency.nnz:  # without springs: solo slips only
        _warn_outside(cls, crossings, alpha, covered)
    rows = _columns(cls, crossings, alpha)
    viscous = VISCOUS_SAFETY if getattr(model, "viscous", False) else 1.0
    coef = _coefficient(rows, crossings, rtol / SAFETY[cls][crossings] / viscous)
    return StepChoice(coef / math.sqrt(omega2_max(model)), coef, crossings, method)


def _warn_outside(cls, crossings, alpha, covered):
    lo, hi = covered
    side = f"below {lo:g}" if alpha[0] < lo else f"above {hi:g}"
    warnings.warn(
        f"rtol is calibrated on {cls} graphs with {crossings} crossings for alpha in "
        f"[{lo:g}, {hi:g}]; with alpha {side} slip errors may exceed rtol (the step is that "
        "of the nearest calibrated alpha; pass dt= to choose one)",
        AccuracyWarning,
        stacklevel=3,
    )
