"""The result of a run, the same for every engine: trajectory, summary, parameters and solver info."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

# a run whose steps shrank below the nominal step over this factor, or that took this factor more steps
STEP_WARNING_FACTOR = 10.0


@dataclass
class Result:
    """trajectory: dict of arrays (one entry per accepted step and t = 0); summary: dict of
    scalars; params: the scene parameters; info: solver settings and counters."""

    trajectory: dict
    summary: dict
    params: object
    info: dict = field(default_factory=dict)


def step_accounting(t, dt):
    """How a run's steps compare with its nominal step dt [s], from its time samples t (t0 and one
    per accepted step), for any engine: nominal_steps over the time reached, step_reductions (the
    steps shorter than 0.99 dt), smallest_step [s] (NaN without a step) and reduced_between [s]: the
    start of the first and the end of the last shortened step ([] without one), which tells a start
    transient from a run that struggles throughout. The last step of a run of several is left out of
    the reductions and the smallest step: after a cut the solver shortens it to land on the end time,
    which is no failure of Newton's."""
    t = np.asarray(t, dtype=float)
    h = np.diff(t)
    body = h[:-1] if len(h) > 1 else h
    cut = np.flatnonzero(body < 0.99 * dt)
    return dict(nominal_steps=int(round((t[-1] - t[0]) / dt)) if len(t) > 1 else 0,
                step_reductions=int(len(cut)),
                smallest_step=float(body.min()) if len(body) else math.nan,
                reduced_between=[float(t[cut[0]]), float(t[cut[-1] + 1])] if len(cut) else [])


def step_warning(accounting, steps, dt):
    """A warning (str) when the solver had to cut the step by more than STEP_WARNING_FACTOR or took
    that many times the nominal steps, naming the likely cause and the parameters; else None."""
    nominal, smallest = accounting["nominal_steps"], accounting["smallest_step"]
    if not (steps > STEP_WARNING_FACTOR * max(nominal, 1) or smallest < dt / STEP_WARNING_FACTOR):
        return None
    window = accounting.get("reduced_between") or []
    when = f" between t = {window[0]:.4g} and {window[1]:.4g} s" if window else ""
    return (f"the solver cut the step: {steps} steps where {nominal} were planned ({accounting['step_reductions']} "
            f"shorter than dt = {dt:g} s{when}, the smallest {smallest:.3g} s). Newton did not converge at the "
            "nominal step; the likely causes are a contact stiffness too high for dt (a penalty k against a mass m "
            "oscillates with the period 2 pi sqrt(m / k), which dt must resolve: lower dt (--set dt=...) or the "
            "stiffness (eps_n, eps_1, eps_2)) or, where the cuts stay in a short window, a force that jumps there "
            "(a normal dashpot as points close on the surface: lower the normal damping)")
