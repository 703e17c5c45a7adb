"""The dynamical state between events, stored so runs continue bit for bit."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from faultnet.exceptions import InvalidParameterError

__all__ = ["State"]


@dataclass(frozen=True, eq=False)
class State:
    """Block displacements and plate position between two events.

    Internally the displacements are kept relative to an integer ``offset``
    (``x = offset + z``, ``u = offset + w``) so that round-off does not grow
    with the plate position.  Continuing a run from a ``State`` reproduces an
    uninterrupted run exactly.

    Attributes
    ----------
    z : numpy.ndarray
        Displacements minus ``offset`` (node order of the model).
    offset : float
        Integer-valued shift of the frame.
    w : float
        Plate position minus ``offset``.
    n_events : int
        Events run so far (the next event gets this number).
    """

    z: np.ndarray
    offset: float = 0.0
    w: float = 0.0
    n_events: int = 0

    @classmethod
    def from_x(cls, x, u=0.0, n_events=0) -> State:
        """Build a state from absolute displacements ``x`` and plate position ``u``."""
        x = np.array(x, dtype=np.float64, copy=True)
        if x.ndim != 1 or x.size == 0:
            raise InvalidParameterError(
                f"x must be 1-D, one displacement per block; got shape {x.shape}"
            )
        bad = np.flatnonzero(~np.isfinite(x))
        if bad.size:
            raise InvalidParameterError(f"x has non-finite entries at positions {bad[:5].tolist()}")
        u = float(u)
        if not math.isfinite(u):
            raise InvalidParameterError(f"plate position u must be finite; got {u!r}")
        offset = float(math.floor(u))
        return cls(z=x - offset, offset=offset, w=u - offset, n_events=int(n_events))

    @property
    def x(self) -> np.ndarray:
        """Absolute block displacements."""
        return self.offset + self.z

    @property
    def u(self) -> float:
        """Absolute plate position (time in units of 1/v0)."""
        return self.offset + self.w

    def copy(self) -> State:
        return State(self.z.copy(), self.offset, self.w, self.n_events)
