"""The time grid of a run, the same for every engine: N = round(t_end / dt) steps of t_end / N.

``p`` is any parameter set with ``t_end`` and ``dt`` [s] (every scene's)."""
from __future__ import annotations

import math

import numpy as np


def step_count(p):
    """Number of time steps of a run: N = round(t_end / dt) (at least 1), the same for every engine."""
    return max(1, int(round(p.t_end / p.dt)))


def time_step(p):
    """The step both engines take [s]: t_end / step_count(p), which is dt when t_end is a whole number
    of dt and otherwise the nearest step that divides t_end (relative change below 1 / (2 N))."""
    return p.t_end / step_count(p)


def time_grid(p):
    """The N + 1 sample times [s] of a run, 0 to t_end in steps of time_step(p) (every engine's grid)."""
    return np.linspace(0.0, p.t_end, step_count(p) + 1)


def driver_travel(t, speed, start=0.0, ramp=0.0):
    """A drive's driver point: its travel [m or rad] and rate at time(s) t [s] when it rests until
    ``start``, then speeds up at a constant rate to ``speed`` over ``ramp`` [s] and holds it:
    speed tau^2 / (2 ramp) for tau = t - start < ramp, speed (tau - ramp / 2) after. Its rate is
    continuous, so the drive's force has no jump an integrator would have to resolve; ramp = 0 is
    the jump to speed at start. Returns arrays of t's shape (scalars for a scalar t)."""
    tau = np.asarray(t, dtype=float) - start
    if ramp > 0.0:
        s = np.clip(tau / ramp, 0.0, 1.0)
        travel = speed * np.where(tau < ramp, 0.5 * ramp * s * s, tau - 0.5 * ramp)
        return travel, speed * s
    return speed * np.maximum(tau, 0.0), np.where(tau > 0.0, speed, 0.0 if start > 0.0 else speed)


def smooth_rise(t, duration):
    """A load's share at time(s) t [s] while it rises over ``duration`` [s]: (1 - cos(pi t / duration))
    / 2, then 1 (1 at once for duration 0). Its rate starts and ends at 0, so a load set down this way
    excites no vibration a quasi-static start would not have. A number for a number (the Exudyn load
    user functions call it every Newton iteration), an array for an array."""
    if np.ndim(t) == 0:
        return 1.0 if t >= duration else 0.5 * (1.0 - math.cos(math.pi * t / duration))
    t = np.asarray(t, dtype=float)
    rising = 0.5 * (1.0 - np.cos(math.pi * np.minimum(t, duration) / max(duration, 1e-300)))
    return np.where(t >= duration, 1.0, rising)
