"""The accuracy knob: from a target relative error of an event's slip to the integration step.

PROVISIONAL: replaced by the calibration table.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from faultnet.exceptions import InvalidParameterError

__all__ = ["CROSSINGS", "RTOL_RANGE", "StepChoice", "step_for_rtol"]

#: kernel codes of the crossing treatments
CROSSINGS = {"exact": 0, "interpolated": 1}
RTOL_RANGE = (1e-8, 1e-4)


@dataclass(frozen=True)
class StepChoice:
    """Integration settings for one accuracy: the step, its coefficient, the crossing treatment."""

    dt: float
    coefficient: float
    crossings: str
    method: str = "dopri5"


def step_for_rtol(model, rtol, method="dopri5"):
    from faultnet.simulate import omega2_max

    rtol = float(rtol)
    if not (RTOL_RANGE[0] <= rtol <= RTOL_RANGE[1]):
        raise InvalidParameterError(
            f"rtol must be between {RTOL_RANGE[0]:g} and {RTOL_RANGE[1]:g}; got {rtol!r}"
        )
    coef = 0.3 if rtol <= 1e-6 else 0.5
    return StepChoice(coef / math.sqrt(omega2_max(model)), coef, "exact", method)
