"""Slow, plainly written reference ("oracle") for the Carlson-Langer block-spring model.

This module deliberately does NOT import ``faultnet``.  It is an independent implementation
of the model of Sakaguchi & Morita (2013) on a graph, written for clarity rather than speed,
against which the fast Numba engine is compared.

Model
-----
N blocks of unit mass, symmetric coupling matrix ``K`` (zero diagonal), and a unit spring from
every block to a loading plate at position ``u``.  The force on block ``i`` is

    F_i = sum_j K[i, j] (x_j - x_i) + (u - x_i).

Kinetic friction for ``v > 0`` is ``phi_i(v) = (1 - sigma_i) / (1 + 2 alpha_i v / (1 - sigma_i))``,
maximum static friction is 1 and blocks never move backwards.

* Loading: all blocks are stuck and the plate moves with ``du/dt = 1``, so every ``F_i`` grows at
  rate 1.  The plate jumps to ``u* = u + max(0, 1 - max_i F_i)``.  The block with the largest
  force (lowest index on ties) is the hypocenter; every block with ``F_i >= 1`` at ``u*`` starts
  to slip together with it.
* Slip event: the plate is frozen at ``u*``.  Slipping blocks obey ``x_i'' = F_i - phi_i(v_i)``
  starting from ``v_i = 0``; stuck blocks do not move.  A slipping block sticks when its velocity
  returns to 0; a stuck block starts to slip (with ``v = 0``) when its force reaches 1.  The event
  ends when every block is stuck.

Numerical method
----------------
The event is integrated piecewise with ``scipy.integrate.solve_ivp`` (DOP853).  Within one
*segment* the set of slipping blocks is fixed.  Each block has one terminal event function:

* slipping block: ``g = v_i`` with ``direction = -1`` (velocity falls to zero -> stick);
* stuck block:    ``g = F_i - 1`` with ``direction = +1`` (force reaches 1 -> start slipping).

When an event function fires, the integration is restarted from that instant with the updated
slipping set (``v_i = 0`` exactly for a block that sticks or joins).

Roots at the start of a segment (documented choice: *ignore them*, no Taylor head start).
A block that has just joined has ``v = 0`` and acceleration ``F_i - (1 - sigma_i) ~ sigma_i > 0``.
SciPy only reports a root of a ``direction = -1`` function when ``g`` goes from ``>= 0`` to
``<= 0`` over a step, so this upward start is not reported.  As an explicit second guard, a
stick event is only accepted if the block's acceleration at the root is ``<= 0``; a root with a
positive acceleration (i.e. one sitting at the start of the segment of a just-joined block) is
ignored and the integration simply continues.  In addition, before every segment a consistency
sweep joins any stuck block whose force is already ``>= 1`` and sticks any slipping block with
``v <= 0`` and non-positive acceleration; this catches two transitions that are so close in time
that the root finder merged them into one restart.

Safety: the number of segments per event and the duration of an event are capped; exceeding
either raises ``RuntimeError`` (rather than silently looping on a Zeno-like sequence).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

__all__ = [
    "forces",
    "friction",
    "linear_one_block_slip",
    "linear_single_block_slip",
    "reference_events",
]


# ---------------------------------------------------------------------------------------------
# Basic physics
# ---------------------------------------------------------------------------------------------


def forces(K, x, u):
    """Forces on all blocks: F_i = sum_j K[i, j] (x_j - x_i) + (u - x_i)."""
    x = np.asarray(x, dtype=float)
    displacement = x[np.newaxis, :] - x[:, np.newaxis]  # displacement[i, j] = x_j - x_i
    return (K * displacement).sum(axis=1) + (u - x)


def force_on_block(K, x, u, i):
    """Force on the single block ``i`` (same formula as :func:`forces`)."""
    return float(np.sum(K[i] * (x - x[i])) + (u - x[i]))


def friction(v, sigma, alpha):
    """Kinetic friction phi(v) = (1 - sigma) / (1 + 2 alpha v / (1 - sigma)), for v >= 0."""
    return (1.0 - sigma) / (1.0 + 2.0 * alpha * v / (1.0 - sigma))


def _rhs(t, y, K, u, sigma, alpha, slipping):
    """Right-hand side of the first-order system y = (x, v) for a fixed slipping set."""
    n = K.shape[0]
    x = y[:n]
    v = y[n:]
    F = forces(K, x, u)
    dxdt = np.where(slipping, v, 0.0)
    dvdt = np.where(slipping, F - friction(v, sigma, alpha), 0.0)
    return np.concatenate([dxdt, dvdt])


def _event_functions(K, u, slipping):
    """One terminal event function per block for a fixed slipping set."""
    n = K.shape[0]
    functions = []
    for i in range(n):
        if slipping[i]:

            def stick(t, y, i=i):
                return y[n + i]

            stick.terminal = True
            stick.direction = -1.0
            functions.append(stick)
        else:

            def start(t, y, i=i):
                return force_on_block(K, y[:n], u, i) - 1.0

            start.terminal = True
            start.direction = 1.0
            functions.append(start)
    return functions


# ---------------------------------------------------------------------------------------------
# One slip event
# ---------------------------------------------------------------------------------------------


def _one_event(K, sigma, alpha, x_start, u, slipping, rtol, atol, max_segments, max_duration):
    """Integrate one slip event with the plate frozen at ``u``.

    ``slipping`` is the boolean mask of blocks that slip at t = 0 (all with v = 0).
    Returns (duration, x_end, moved) where ``moved`` marks every block that slipped.
    """
    n = K.shape[0]
    x = np.array(x_start, dtype=float)
    v = np.zeros(n)
    slipping = np.array(slipping, dtype=bool)
    moved = slipping.copy()
    t = 0.0

    for _segment in range(max_segments):
        # Consistency sweep (see module docstring).
        F = forces(K, x, u)
        for i in range(n):
            if not slipping[i] and F[i] >= 1.0:
                slipping[i] = True
                moved[i] = True
                v[i] = 0.0
            elif slipping[i] and v[i] <= 0.0:
                v[i] = 0.0
                if F[i] - friction(0.0, sigma[i], alpha[i]) <= 0.0:
                    slipping[i] = False

        if not slipping.any():
            return t, x, moved

        segment_slipping = slipping.copy()

        def rhs(t, y, segment_slipping=segment_slipping):
            return _rhs(t, y, K, u, sigma, alpha, segment_slipping)

        sol = solve_ivp(
            rhs,
            (t, max_duration),
            np.concatenate([x, v]),
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=_event_functions(K, u, segment_slipping),
        )
        if sol.status == -1:
            raise RuntimeError(f"solve_ivp failed: {sol.message}")
        if sol.status == 0:
            raise RuntimeError(f"slip event lasted longer than max_duration={max_duration}")

        t = float(sol.t[-1])
        x = np.array(sol.y[:n, -1])
        v = np.maximum(np.array(sol.y[n:, -1]), 0.0)  # never move backwards

        F = forces(K, x, u)
        for i in range(n):
            fired = len(sol.t_events[i]) > 0 and sol.t_events[i][-1] == t
            if not fired:
                continue
            if slipping[i]:
                acceleration = F[i] - friction(0.0, sigma[i], alpha[i])
                if acceleration <= 0.0:
                    slipping[i] = False  # genuine stick
                    v[i] = 0.0
                # else: root at the start of a just-joined block's motion -> ignored
            else:
                slipping[i] = True  # force reached the static threshold
                moved[i] = True
                v[i] = 0.0

    raise RuntimeError(f"slip event needed more than max_segments={max_segments} segments")


# ---------------------------------------------------------------------------------------------
# Event loop
# ---------------------------------------------------------------------------------------------


def _per_block(value, n, name):
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    if arr.shape != (n,):
        raise ValueError(f"{name} must be a scalar or have shape ({n},), got {arr.shape}")
    return arr.copy()


def reference_events(
    K,
    sigma,
    alpha,
    x0,
    n_events,
    u0=0.0,
    rtol=1e-11,
    atol=1e-14,
    max_segments=10_000,
    max_duration=1e4,
):
    """Simulate ``n_events`` slip events of the Carlson-Langer model.

    Parameters
    ----------
    K : (N, N) array, symmetric, zero diagonal, non-negative spring constants.
    sigma, alpha : scalar or (N,) arrays, ``0 < sigma < 1``, ``alpha >= 0``.
    x0 : (N,) initial block positions (all blocks stuck).
    n_events : number of events to simulate.
    u0 : initial plate position.
    rtol, atol : solve_ivp tolerances.
    max_segments, max_duration : safety caps per event (``RuntimeError`` if exceeded).

    Returns
    -------
    (events, u) where ``events`` is a list of dicts with keys
        "t"          plate position u* at the start of the event,
        "hypocenter" index of the block that triggered the event,
        "duration"   time from the start of the event to the last stick,
        "slips"      (N,) array x(end) - x(start),
        "S"          sum of the slips,
        "n_blocks"   number of distinct blocks that slipped,
        "x"          (N,) block positions after the event,
    and ``u`` is the final plate position (equal to the last event's "t").
    """
    K = np.array(K, dtype=float)
    if K.ndim != 2 or K.shape[0] != K.shape[1]:
        raise ValueError("K must be a square matrix")
    if not np.allclose(K, K.T, rtol=1e-12, atol=0.0):
        raise ValueError("K must be symmetric")
    if np.any(np.diag(K) != 0.0) or np.any(K < 0.0):
        raise ValueError("K must have a zero diagonal and non-negative entries")
    n = K.shape[0]
    sigma = _per_block(sigma, n, "sigma")
    alpha = _per_block(alpha, n, "alpha")
    if np.any(sigma <= 0.0) or np.any(sigma >= 1.0):
        raise ValueError("sigma must lie in (0, 1)")
    if np.any(alpha < 0.0):
        raise ValueError("alpha must be >= 0")
    x = _per_block(x0, n, "x0")
    u = float(u0)

    events = []
    for _ in range(n_events):
        # Loading phase: all forces grow at rate 1 until the largest one reaches 1.
        F = forces(K, x, u)
        hypocenter = int(np.argmax(F))  # lowest index on exact ties
        u_star = u + max(0.0, 1.0 - F[hypocenter])
        F_star = F + (u_star - u)
        # The hypocenter, exact ties with it, and every block already at/over threshold.
        slipping = F_star >= min(1.0, F_star[hypocenter])

        duration, x_end, moved = _one_event(
            K, sigma, alpha, x, u_star, slipping, rtol, atol, max_segments, max_duration
        )
        slips = x_end - x
        events.append(
            {
                "t": u_star,
                "hypocenter": hypocenter,
                "duration": duration,
                "slips": slips,
                "S": float(np.sum(slips)),
                "n_blocks": int(np.count_nonzero(moved)),
                "x": x_end.copy(),
            }
        )
        x = x_end
        u = u_star
    return events, u


# ---------------------------------------------------------------------------------------------
# Analytical results of the linearised model
# ---------------------------------------------------------------------------------------------


def linear_one_block_slip(sigma, alpha):
    """Eq. (6) of Sakaguchi & Morita (2013): s = sigma (1 + exp(alpha pi / sqrt(1 - alpha^2))).

    Valid for the linearised friction law of one isolated block; requires ``alpha < 1``.
    """
    if not alpha < 1.0:
        raise ValueError("linear_one_block_slip requires alpha < 1")
    return sigma * (1.0 + math.exp(alpha * math.pi / math.sqrt(1.0 - alpha * alpha)))


def linear_single_block_slip(sigma, alpha, kappa):
    """Slip of one block of total stiffness ``kappa`` (= 1 + sum_j K[i, j]) with stuck neighbours.

    s = sigma / kappa (1 + exp(alpha pi / sqrt(kappa - alpha^2))); requires ``alpha^2 < kappa``.
    """
    if not alpha * alpha < kappa:
        raise ValueError("linear_single_block_slip requires alpha**2 < kappa")
    return sigma / kappa * (1.0 + math.exp(alpha * math.pi / math.sqrt(kappa - alpha * alpha)))
