"""What a floating-frame body costs Exudyn in a time step that refreshes its Jacobian, estimated from its
mesh's node count N and its number of modes m before anything is assembled, and the bounds the
finite-element scenes check.

Exudyn's floating-frame body (``ObjectFFRFreducedOrder``) evaluates its mass matrix and its quadratic
velocity terms as sums over every node of the mesh and differentiates them numerically in its
coordinates, column by column, whenever Newton refreshes the Jacobian (the first steps of a run, and
every step where Newton struggles): such a step costs about ``NODE_MODE2_S N m^2 + MODE3_S m^3``
seconds (the node sums per Jacobian column, and the dense terms between the modes). The two
coefficients are a fit to the first steps of short elastic-block runs, reduced and full, from 30 to
540 modes (``python studies/fe_cost.py``; docs/guide/speed.md, "The cost of a finite-element body"). The other steps reuse the
Jacobian and cost far less, so a whole run usually costs much less per step than this estimate; a body
whose refresh alone takes minutes never gets through its first steps. The estimate is for a 2-core
machine of 2026, used to refuse a body that cannot run, not a promise of speed."""
from __future__ import annotations

MAX_MODES = 1500
"""The most modes (coordinates of the deformation) a floating-frame body may have in a scene."""

NODE_MODE2_S = 1.33e-7
"""Seconds per refresh and unit of N m^2 (the fit above)."""

MODE3_S = 1.53e-7
"""Seconds per refresh and unit of m^3 (the fit above)."""

REFRESH_SECONDS_MAX = 20.0
"""The largest estimated cost of a step that refreshes the body's Jacobian [s] a scene accepts."""


def refresh_seconds(nodes, modes):
    """Estimated wall time [s] of a time step that refreshes the Jacobian of a floating-frame body with
    ``nodes`` mesh nodes and ``modes`` modes (the module's cost model)."""
    return NODE_MODE2_S * nodes * modes ** 2 + MODE3_S * modes ** 3


def check_cost(nodes, modes, layout):
    """Refuse a floating-frame body whose modes or estimated refresh cost are out of bounds (MAX_MODES,
    REFRESH_SECONDS_MAX); ``layout`` names the parameters that set nodes and modes, for the message
    (e.g. "cells=12, basis=craig_bampton")."""
    if modes > MAX_MODES:
        raise ValueError(f"the elastic body would have {modes} modes ({layout}), at most {MAX_MODES} allowed (a bound "
                         f"on a run's cost): use fewer cells or a reduced basis")
    cost = refresh_seconds(nodes, modes)
    if cost > REFRESH_SECONDS_MAX:
        raise ValueError(f"the elastic body's {nodes} nodes x {modes} modes ({layout}) would cost about {cost:.3g} s "
                         f"per step that refreshes its Jacobian (the first steps, and every step where Newton "
                         f"struggles), more than the {REFRESH_SECONDS_MAX:g} s allowed (a bound on a run's cost, "
                         f"estimated by exu_aniso.fe.cost): use fewer cells or modes")


def cost_rules():
    """The bounds above as lines of text, for ``exu-aniso params``."""
    return [f"the elastic body: at most {MAX_MODES} modes, and an estimated {NODE_MODE2_S:.3g} s x nodes x modes^2 + "
            f"{MODE3_S:.3g} s x modes^3 of at most {REFRESH_SECONDS_MAX:g} s per step that refreshes its Jacobian "
            "(exu_aniso.fe.cost)"]
