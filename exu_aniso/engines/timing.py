"""The time grid of a run, the same for every engine: N = round(t_end / dt) steps of t_end / N.

``p`` is any parameter set with ``t_end`` and ``dt`` [s] (every scene's)."""
from __future__ import annotations

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
