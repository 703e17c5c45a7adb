"""Slow, plainly written reference ("oracle") for the Carlson-Langer block-spring model.

This module deliberately does NOT import ``faultnet``.  It is an independent implementation
of the model of Sakaguchi & Morita (2013) on a graph, written for clarity rather than speed,
against which the fast Numba engine is compared.  It also covers Carlson & Langer's (PRA 40,
6470, 1989) plate velocity ``nu`` during events and Kelvin viscous coupling ``eta`` between
blocks; ``nu = 0`` and ``eta = 0`` (the defaults) are the model of Sakaguchi & Morita and run
the same arithmetic as before these were added.  The one change for them is the repair of
joins that the root finder misses (see "Missed joins" below; ``repair_missed_joins=False``
gives the earlier results bit for bit).

Model
-----
N blocks of unit mass, symmetric coupling matrix ``K`` (zero diagonal), symmetric viscous
coupling matrix ``E`` (zero diagonal, the per-edge ``eta``; zero by default), and a unit spring
from every block to a loading plate at position ``u``.  The *force* on block ``i`` is every
force except friction:

    F_i = sum_j K[i, j] (x_j - x_i) + sum_j E[i, j] (v_j - v_i) + (u - x_i).

The same formula serves slipping and stuck blocks.  A stuck block has ``v_i = 0``, so its
force is springs + ``sum_j E[i, j] v_j`` (the viscous pull of its slipping neighbours, >= 0
because blocks never move backwards) + plate.  With ``E = 0`` this is the classic
``F_i = sum_j K[i, j] (x_j - x_i) + (u - x_i)``.

Kinetic friction for ``v > 0`` is ``phi_i(v) = (1 - sigma_i) / (1 + 2 alpha_i v / (1 - sigma_i))``,
maximum static friction is 1 and blocks never move backwards.

* Loading: all blocks are stuck (all ``v = 0``, so no viscous force) and the plate moves with
  ``du/dt = 1``, so every ``F_i`` grows at rate 1.  The plate jumps to
  ``u* = u + max(0, 1 - max_i F_i)``.  The block with the largest force (lowest index on ties)
  is the hypocenter; every block with ``F_i >= 1`` at ``u*`` starts to slip together with it.
* Slip event, in dynamic time ``t`` from 0 at the start of the event: the plate moves as
  ``u(t) = u* + nu t`` (frozen at ``u*`` when ``nu = 0``).  Slipping blocks obey
  ``x_i'' = F_i - phi_i(v_i)`` starting from ``v_i = 0``; stuck blocks do not move.

  - Stick: a slipping block sticks when its velocity returns to 0 (with non-positive
    acceleration ``F_i - phi_i(0)``).
  - Join: a stuck block starts to slip (with ``v = 0``) when its force ``F_i`` -- springs,
    viscous pull of slipping neighbours and plate -- reaches 1.  Every stuck block is watched,
    not only neighbours of slipping blocks: with ``nu > 0`` the moving plate alone can bring
    a block that is coupled to nothing that moves up to the threshold.
  - Continuity: a block joins and sticks with ``v = 0``, so no force jumps when the slipping set
    changes; in particular the viscous term cannot push a stuck block over the threshold at
    the instant a neighbour starts to slip (only the rate ``dF_i/dt`` jumps, by
    ``E[i, j] sigma_j``, the neighbour's initial acceleration).

  The event ends when every block is stuck; the plate is then at ``u* + nu * duration`` and
  the next loading phase starts from there.

Catalogue: ``t`` is the plate position ``u*`` at the start of the event (as for ``nu = 0``),
``duration`` is in dynamic time, ``S`` the total slip, ``n_blocks`` the number of distinct
blocks that slipped (a block that sticks and slips again within an event counts once).

Numerical method
----------------
The event is integrated piecewise with ``scipy.integrate.solve_ivp`` (DOP853).  Within one
*segment* (phase) the set of slipping blocks is fixed.  Each block has one terminal event
function:

* slipping block: ``g = v_i`` with ``direction = -1`` (velocity falls to zero -> stick);
* stuck block:    ``g = F_i - 1`` with ``direction = +1`` (force reaches 1 -> start slipping),
  with ``F_i`` as above: springs, viscous terms and the plate at ``u* + nu t``.

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

Missed joins and the self-check.  SciPy detects a root from the sign of ``g`` at the ends of
each step, so a stuck block whose force crosses 1 and is back below 1 at the end of the step is
missed.  This happens in practice, not only for grazing crossings: when a slipping neighbour
sticks in the same step, the integrator carries on past the stick with the neighbour moving
backwards, which can take the stuck block's force back below 1 by the step's end; solve_ivp
then reports only the stick, and the block ends the segment above the threshold (event 27 of
the self-check's heterogeneous chain: force 1.00045, joined 0.017 time units late).  Therefore,
after every segment, the forces of the blocks that were stuck during it are evaluated from the
dense output at every step end and at ``check_points`` points inside every step:

* repair (``repair_missed_joins=True``, the default): if any exceeds ``1 + 1e-12``, its
  crossing is bracketed between samples and located with brentq on the dense output (as
  solve_ivp locates its own roots); the segment is cut at the earliest such crossing and the
  block joins there.  When nothing is missed the results are bit for bit those of the plain
  root finding;
* assertion: if a stuck block's force still exceeds ``1 + phase_tol`` at a sample point or at
  the end of the segment, :class:`MissedJoinError` is raised (with the repair off, this is how
  a missed join shows; with it on, it guards the repair).

Missed stops, the same way round: a slipping block's velocity can dip below 0 and be back above
it by the end of a step (grazing stops, and stops followed by a quick re-start as a neighbour
pushes), and solve_ivp then reports nothing.  With the repair on, the velocities of the blocks
slipping in the segment are sampled at the same points; the earliest sample below
``-1e-12`` is bracketed and located with brentq, the segment is cut there (unless a missed
join comes first) and the block stops there (the consistency sweep sticks it, or lets it slip
on if its force still exceeds its friction at rest).

With ``record_phases=True`` each event also carries its segments, and :func:`max_stuck_force`
reports the largest stuck-block force over them.

Safety: the number of segments per event and the duration of an event are capped; exceeding
either raises ``RuntimeError`` (rather than silently looping on a Zeno-like sequence).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

__all__ = [
    "MissedJoinError",
    "forces",
    "friction",
    "linear_one_block_slip",
    "linear_single_block_slip",
    "max_stuck_force",
    "reference_events",
    "viscous_matrix",
]


_EPS = np.finfo(float).eps
_JOIN_SLACK = 1e-12  # a stuck block's force above 1 + this at a sample point: a missed join
_STOP_SLACK = 1e-12  # a slipping block's velocity below -this at a sample point: a missed stop


class MissedJoinError(AssertionError):
    """A stuck block's force exceeded the static threshold within a phase: a missed join."""


# ---------------------------------------------------------------------------------------------
# Basic physics
# ---------------------------------------------------------------------------------------------


def forces(K, x, u, v=None, E=None):
    """Forces on all blocks: sum_j K[i, j] (x_j - x_i) + sum_j E[i, j] (v_j - v_i) + (u - x_i).

    The viscous sum is left out when ``E`` (or ``v``) is None, i.e. ``forces(K, x, u)`` is the
    classic spring + plate force.  Stuck blocks must have ``v_i = 0``.
    """
    x = np.asarray(x, dtype=float)
    displacement = x[np.newaxis, :] - x[:, np.newaxis]  # displacement[i, j] = x_j - x_i
    if E is None or v is None:
        return (K * displacement).sum(axis=1) + (u - x)
    v = np.asarray(v, dtype=float)
    relative_velocity = v[np.newaxis, :] - v[:, np.newaxis]  # [i, j] = v_j - v_i
    return (K * displacement).sum(axis=1) + (E * relative_velocity).sum(axis=1) + (u - x)


def force_on_block(K, x, u, i, v=None, E=None):
    """Force on the single block ``i`` (same formula as :func:`forces`)."""
    if E is None or v is None:
        return float(np.sum(K[i] * (x - x[i])) + (u - x[i]))
    return float(np.sum(K[i] * (x - x[i])) + np.sum(E[i] * (v - v[i])) + (u - x[i]))


def friction(v, sigma, alpha):
    """Kinetic friction phi(v) = (1 - sigma) / (1 + 2 alpha v / (1 - sigma)), for v >= 0."""
    return (1.0 - sigma) / (1.0 + 2.0 * alpha * v / (1.0 - sigma))


def _plate(u_star, nu, t):
    """Plate position at dynamic time ``t`` of an event that started with the plate at u*."""
    if nu == 0.0:
        return u_star
    return u_star + nu * t


def _rhs(t, y, K, u_star, sigma, alpha, slipping, nu=0.0, E=None):
    """Right-hand side of the first-order system y = (x, v) for a fixed slipping set."""
    n = K.shape[0]
    x = y[:n]
    v = y[n:]
    F = forces(K, x, _plate(u_star, nu, t), v, E)
    dxdt = np.where(slipping, v, 0.0)
    dvdt = np.where(slipping, F - friction(v, sigma, alpha), 0.0)
    return np.concatenate([dxdt, dvdt])


def _event_functions(K, u_star, slipping, nu=0.0, E=None):
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
                return force_on_block(K, y[:n], _plate(u_star, nu, t), i, y[n:], E) - 1.0

            start.terminal = True
            start.direction = 1.0
            functions.append(start)
    return functions


def _stuck_force_samples(K, E, u_star, nu, stuck, sol, check_points):
    """Forces of the ``stuck`` blocks at sample times of one segment, from its dense output.

    The samples are the step ends of the segment and ``check_points`` evenly spaced points
    inside every step.  Returns (times, F) with ``F[k, m]`` the force on the k-th stuck block
    at ``times[m]`` (same formula as :func:`forces`, vectorised over time).
    """
    n = K.shape[0]
    steps = np.asarray(sol.t, dtype=float)
    fractions = np.arange(1, check_points + 1) / (check_points + 1)
    inside = steps[:-1, np.newaxis] + np.diff(steps)[:, np.newaxis] * fractions
    times = np.sort(np.concatenate([steps, inside.ravel()]))
    Y = sol.sol(times)
    X, V = Y[:n], Y[n:]
    displacement = X[np.newaxis, :, :] - X[:, np.newaxis, :]  # [i, j, m] = x_j - x_i
    F = (K[:, :, np.newaxis] * displacement).sum(axis=1)
    if E is not None:
        relative_velocity = V[np.newaxis, :, :] - V[:, np.newaxis, :]
        F = F + (E[:, :, np.newaxis] * relative_velocity).sum(axis=1)
    F = F + ((u_star + nu * times)[np.newaxis, :] - X)
    return times, F[stuck]


def _first_missed_stop(slipping, sol, times, n):
    """Earliest stop of a slipping block that solve_ivp did not report.

    A velocity that dips below 0 and is back above it at the end of a step is not reported
    (the event function is checked at step ends only).  A sample of a slipping block's
    velocity below ``-_STOP_SLACK`` is a missed stop; its crossing is bracketed between the
    last earlier sample above 0 and located with brentq on the dense output.  Returns
    (time, block) or None.
    """
    V = sol.sol(times)[n:]
    best = None
    for i in np.flatnonzero(slipping):
        below = V[i] < -_STOP_SLACK
        if not below.any():
            continue
        b = int(np.argmax(below))
        a = max(b - 1, 0)
        while a > 0 and V[i, a] <= 0.0:
            a -= 1
        if V[i, a] <= 0.0:
            root = float(times[a])
        else:
            root = brentq(
                lambda t, i=i: sol.sol(t)[n + i], times[a], times[b], xtol=4 * _EPS, rtol=4 * _EPS
            )
        if best is None or root < best[0]:
            best = (root, int(i))
    return best


def _first_missed_join(K, E, u_star, nu, stuck, sol, times, F_stuck):
    """Earliest crossing of 1 by a stuck block's force that solve_ivp did not report.

    ``times`` and ``F_stuck`` are the samples of :func:`_stuck_force_samples`.  A sample above
    ``1 + _JOIN_SLACK`` is a missed join; its crossing is bracketed between the last earlier
    sample below 1 and located with brentq on the dense output, as solve_ivp locates its
    roots.  Returns (time, block) or None.
    """
    n = K.shape[0]
    over = F_stuck > 1.0 + _JOIN_SLACK
    best = None
    for row, i in enumerate(np.flatnonzero(stuck)):
        if not over[row].any():
            continue

        def g(t, i=i):
            y = sol.sol(t)
            return force_on_block(K, y[:n], _plate(u_star, nu, t), i, y[n:], E) - 1.0

        b = int(np.argmax(over[row]))  # first sample above the threshold
        a = max(b - 1, 0)
        while a > 0 and g(times[a]) >= 0.0:
            a -= 1
        if g(times[a]) >= 0.0:  # only round-off: the segment starts below the threshold
            root = float(times[a])
        else:
            root = brentq(g, times[a], times[b], xtol=4 * _EPS, rtol=4 * _EPS)
        if best is None or root < best[0]:
            best = (root, int(i))
    return best


# ---------------------------------------------------------------------------------------------
# One slip event
# ---------------------------------------------------------------------------------------------


def _one_event(
    K,
    sigma,
    alpha,
    x_start,
    u_star,
    slipping,
    rtol,
    atol,
    max_segments,
    max_duration,
    nu=0.0,
    E=None,
    phase_tol=1e-9,
    check_points=8,
    repair_missed_joins=True,
    max_step=math.inf,
    record_phases=False,
):
    """Integrate one slip event that starts with the plate at ``u_star``.

    ``slipping`` is the boolean mask of blocks that slip at t = 0 (all with v = 0).
    Returns (duration, x_end, moved, phases) where ``moved`` marks every block that slipped
    and ``phases`` is the list of segments (empty unless ``record_phases``).
    """
    n = K.shape[0]
    x = np.array(x_start, dtype=float)
    v = np.zeros(n)
    slipping = np.array(slipping, dtype=bool)
    moved = slipping.copy()
    t = 0.0
    phases = []

    for _segment in range(max_segments):
        # Consistency sweep (see module docstring).
        F = forces(K, x, _plate(u_star, nu, t), v, E)
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
            return t, x, moved, phases

        segment_slipping = slipping.copy()
        stuck = ~segment_slipping

        def rhs(t, y, segment_slipping=segment_slipping):
            return _rhs(t, y, K, u_star, sigma, alpha, segment_slipping, nu, E)

        t_begin = t
        sol = solve_ivp(
            rhs,
            (t, max_duration),
            np.concatenate([x, v]),
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=_event_functions(K, u_star, segment_slipping, nu, E),
            dense_output=True,
            max_step=max_step,
        )
        if sol.status == -1:
            raise RuntimeError(f"solve_ivp failed: {sol.message}")
        if sol.status == 0:
            raise RuntimeError(f"slip event lasted longer than max_duration={max_duration}")

        t = float(sol.t[-1])
        x = np.array(sol.y[:n, -1])
        v = np.maximum(np.array(sol.y[n:, -1]), 0.0)  # never move backwards

        # Missed joins (see module docstring): a stuck block whose force went above 1 at a
        # sample point.  Cut the segment at the earliest such crossing and join the block there.
        times, F_stuck = _stuck_force_samples(K, E, u_star, nu, stuck, sol, check_points)
        missed = stopped = None
        if repair_missed_joins:
            missed = _first_missed_join(K, E, u_star, nu, stuck, sol, times, F_stuck)
            stopped = _first_missed_stop(segment_slipping, sol, times[times <= t], n)
            if stopped is not None and (missed is None or stopped[0] < missed[0]):
                missed = None
            else:
                stopped = None
        cut = missed or stopped
        if cut is not None:
            t = cut[0]
            y = sol.sol(t)
            x = np.array(y[:n])
            v = np.maximum(np.array(y[n:]), 0.0)

        # Self-check: no block that was stuck during the segment is above the threshold at a
        # sample point or at the end of the segment.
        F = forces(K, x, _plate(u_star, nu, t), v, E)
        samples = F_stuck[:, times <= t]
        worst = max(samples.max(initial=-math.inf), np.max(F[stuck], initial=-math.inf))
        if phase_tol is not None and repair_missed_joins:
            V = sol.sol(times[times <= t])[n:][segment_slipping]
            if V.size and V.min() < -phase_tol:
                raise MissedJoinError(
                    f"a slipping block's velocity reached {V.min()!r} < -{phase_tol} in the "
                    f"segment [{t_begin!r}, {t!r}] of an event: a missed stop"
                )
        if phase_tol is not None and worst > 1.0 + phase_tol:
            where = np.argwhere(samples > 1.0 + phase_tol)
            block = int(np.flatnonzero(stuck)[where[0, 0]]) if len(where) else "?"
            raise MissedJoinError(
                f"a stuck block ({block}) reached force {worst!r} > 1 + {phase_tol} in the "
                f"segment [{t_begin!r}, {t!r}] of an event: a missed join (try a smaller "
                "max_step, more check_points or repair_missed_joins=True)"
            )
        if record_phases:
            phases.append(
                {
                    "t0": t_begin,
                    "t1": t,
                    "slipping": segment_slipping,
                    "x": x.copy(),
                    "v": v.copy(),
                    "u": _plate(u_star, nu, t),
                    "F": F.copy(),
                    "max_stuck_force": float(worst),
                    "missed_join": None if missed is None else missed[1],
                    "missed_stop": None if stopped is None else stopped[1],
                    "sol": sol.sol,
                }
            )

        if missed is not None:
            slipping[missed[1]] = True
            moved[missed[1]] = True
            v[missed[1]] = 0.0
            continue  # the events solve_ivp reported after the cut are not reached
        if stopped is not None:
            v[stopped[1]] = 0.0  # the consistency sweep sticks it (its acceleration is <= 0)
            continue

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


def viscous_matrix(K, eta):
    """The viscous coupling matrix ``E`` for ``eta``, or None when there is no viscosity.

    ``eta`` is None, a scalar (the same ``eta`` on every edge of ``K``, i.e. on every pair with
    ``K[i, j] > 0``, as faultnet's ``eta=`` parameter) or an (N, N) matrix (symmetric, zero
    diagonal, finite, non-negative; it may couple pairs without a spring).  An all-zero ``E``
    gives None, so ``eta = 0`` runs the plain model's arithmetic.
    """
    K = np.asarray(K, dtype=float)
    n = K.shape[0]
    if eta is None:
        return None
    E = np.array(eta, dtype=float)
    if E.ndim == 0:
        if not (math.isfinite(float(E)) and float(E) >= 0.0):
            raise ValueError(f"eta must be finite and >= 0, got {float(E)!r}")
        E = np.where(K > 0.0, float(E), 0.0)
    if E.shape != (n, n):
        raise ValueError(f"eta must be a scalar or have shape ({n}, {n}), got {E.shape}")
    if not np.all(np.isfinite(E)) or np.any(E < 0.0):
        raise ValueError("eta must be finite and >= 0")
    if np.any(np.diag(E) != 0.0) or not np.allclose(E, E.T, rtol=1e-12, atol=0.0):
        raise ValueError("eta must be symmetric with a zero diagonal")
    if not E.any():
        return None
    return E


def max_stuck_force(phases):
    """Largest force of a stuck block over recorded phases (``record_phases=True``).

    Each phase's value covers the end of the phase and the interior sample points; it must
    not exceed 1 (up to round-off): a larger value means a missed join.  ``-inf`` if no block
    was ever stuck.
    """
    return max((phase["max_stuck_force"] for phase in phases), default=-math.inf)


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
    *,
    nu=0.0,
    eta=None,
    phase_tol=1e-9,
    check_points=8,
    repair_missed_joins=True,
    max_step=math.inf,
    record_phases=False,
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
    nu : plate velocity during events (finite, >= 0; 0 freezes the plate as in the plain model).
    eta : viscous coupling: None/0 (none), a scalar on every edge of ``K``, or an (N, N)
        symmetric matrix with zero diagonal (see :func:`viscous_matrix`).
    phase_tol : self-check; raise :class:`MissedJoinError` if a stuck block's force exceeds
        ``1 + phase_tol`` at the end of a segment or at a sample point inside it.  None turns
        the check off.
    check_points : sample points inside every integration step for the repair and the check.
    repair_missed_joins : join a stuck block where its force crossed 1 unreported by solve_ivp,
        and stop a slipping block where its velocity crossed 0 unreported (see the module
        docstring); False reproduces the plain root finding, bit for bit.
    max_step : largest step of solve_ivp (smaller steps make a missed join less likely).
    record_phases : attach the segments of each event under ``"phases"``.

    Returns
    -------
    (events, u) where ``events`` is a list of dicts with keys
        "t"          plate position u* at the start of the event,
        "u_end"      plate position at the end of the event, ``t + nu * duration``,
        "hypocenter" index of the block that triggered the event,
        "duration"   time from the start of the event to the last stick,
        "slips"      (N,) array x(end) - x(start),
        "S"          sum of the slips,
        "n_blocks"   number of distinct blocks that slipped,
        "x"          (N,) block positions after the event,
        "phases"     (only with ``record_phases``) list of dicts, one per segment: "t0", "t1"
                     (dynamic time), "slipping" (mask during the segment), "x", "v", "u", "F"
                     (state, plate and forces at "t1", before the transitions there),
                     "max_stuck_force" (see :func:`max_stuck_force`), "missed_join" (the
                     block joined by the repair at "t1", or None) and "sol" (dense output),
    and ``u`` is the final plate position (the last event's "u_end"; its "t" when ``nu = 0``).
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
    nu = float(nu)
    if not (math.isfinite(nu) and nu >= 0.0):
        raise ValueError(f"nu must be finite and >= 0, got {nu!r}")
    E = viscous_matrix(K, eta)
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

        duration, x_end, moved, phases = _one_event(
            K,
            sigma,
            alpha,
            x,
            u_star,
            slipping,
            rtol,
            atol,
            max_segments,
            max_duration,
            nu=nu,
            E=E,
            phase_tol=phase_tol,
            check_points=check_points,
            repair_missed_joins=repair_missed_joins,
            max_step=max_step,
            record_phases=record_phases,
        )
        slips = x_end - x
        event = {
            "t": u_star,
            "u_end": _plate(u_star, nu, duration),
            "hypocenter": hypocenter,
            "duration": duration,
            "slips": slips,
            "S": float(np.sum(slips)),
            "n_blocks": int(np.count_nonzero(moved)),
            "x": x_end.copy(),
        }
        if record_phases:
            event["phases"] = phases
        events.append(event)
        x = x_end
        u = event["u_end"]
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
