"""SimulationFailure: a time integration that stopped before its end time, with the context to act on it.

No Exudyn here. ``exu_aniso.engines.exudyn_adapter.runner.SolveTimed`` raises it when ``mbs.SolveDynamic`` fails
(Exudyn 1.13.6 raises ``exudyn.SolverError("SolveDynamic terminated")`` when Newton fails at the
minimum step size or step reduction is off, and ``exudyn.ModelError`` when a user function raises,
e.g. a ``ValueError`` of the contact law; the sensors with ``storeInternal`` keep every accepted step
up to the failure). ``RunBlock`` / ``RunScrew`` attach the partial trajectory (``partial``, an
``exu_aniso.engines.result.Result``) before re-raising, and the command line writes it with
``"complete": false``.

The message states the simulated time reached, the end time, the step size at the failure, the
cause, and the contact state of the last accepted step (per point: open / stick / slip, gap,
tangential traction, normal traction), read from the contact history (``HISTORY_FIELDS``).
"""
from __future__ import annotations

import numpy as np

from exu_aniso.law.history import HISTORY_FIELDS, N_HISTORY, OPEN, SLIP, STICK

STATUS_NAMES = {OPEN: "open", STICK: "stick", SLIP: "slip"}
MAX_POINTS_SHOWN = 8


class SimulationFailure(RuntimeError):
    """The solver stopped at ``time_reached`` < ``end_time``.

    Attributes: time_reached [s], end_time [s], step_size [s] (at the failure), cause (text of the
    solver's or the user function's error), contact_states (list of dicts, one per contact set:
    status (K,) names, gap (K,) [m] (NaN where open or unknown), traction (K, 2) [N], normal (K,) [N]),
    steps (accepted), newton_iterations, partial (Result with the trajectory up to the failure, set
    by RunBlock / RunScrew; None before), solver_output (what Exudyn printed while failing)."""

    def __init__(self, message, *, time_reached, end_time, step_size, cause="", contact_states=(), steps=0,
                 newton_iterations=0, solver_output=""):
        super().__init__(message)
        self.time_reached = float(time_reached)
        self.end_time = float(end_time)
        self.step_size = float(step_size)
        self.cause = cause
        self.contact_states = list(contact_states)
        self.steps = int(steps)
        self.newton_iterations = int(newton_iterations)
        self.solver_output = solver_output
        self.partial = None

    def as_dict(self):
        """JSON-ready summary of the failure (for summary.json)."""
        return dict(complete=False, failure=str(self), time_reached=self.time_reached, end_time=self.end_time,
                    step_size=self.step_size, cause=self.cause)


def contact_state_from_history(history, normal_stiffness=None, normal_damping=0.0):
    """Per-point contact state of one contact set from its history row block (K * 9 numbers).

    The gap is N / eps_N for points in contact when the normal damping is off (N = eps_N xi3 exactly
    then); otherwise, and for open points, NaN (the history does not store the gap)."""
    H = np.asarray(history, dtype=float).reshape(-1, N_HISTORY)
    status = H[:, HISTORY_FIELDS.index("status")].round().astype(int)
    active = H[:, HISTORY_FIELDS.index("active")] > 0.5
    status = np.where(active, status, OPEN)
    normal = H[:, HISTORY_FIELDS.index("normal")]
    gap = np.full(len(H), np.nan)
    if normal_stiffness and not normal_damping:
        gap = np.where(active & (normal < 0.0), normal / float(normal_stiffness), np.nan)
    traction = H[:, [HISTORY_FIELDS.index("traction_1"), HISTORY_FIELDS.index("traction_2")]]
    return dict(status=[STATUS_NAMES.get(int(s), str(s)) for s in status], gap=gap, traction=traction,
                normal=normal)


def describe_contact_state(state, name="contact set"):
    """One text paragraph: counts per status, then the first MAX_POINTS_SHOWN points."""
    st = state["status"]
    K = len(st)
    counts = ", ".join(f"{sum(1 for s in st if s == k)} {k}" for k in ("open", "stick", "slip"))
    lines = [f"{name} ({K} points: {counts})"]
    for k in range(min(K, MAX_POINTS_SHOWN)):
        g = state["gap"][k]
        gap = "n/a" if not np.isfinite(g) else f"{g:.3e} m"
        T = state["traction"][k]
        lines.append(f"  point {k}: {st[k]}, gap {gap}, traction ({T[0]:.4g}, {T[1]:.4g}) N, "
                     f"normal {state['normal'][k]:.4g} N")
    if K > MAX_POINTS_SHOWN:
        lines.append(f"  ... {K - MAX_POINTS_SHOWN} more points")
    return "\n".join(lines)


def failure_message(time_reached, end_time, step_size, cause, contact_states=(), names=None, steps=None,
                    newton_iterations=None, hint=""):
    """The text of a SimulationFailure (see the module docstring)."""
    head = (f"simulation failed at t = {time_reached:.6g} s of t_end = {end_time:.6g} s "
            f"(step size {step_size:.3g} s")
    if steps is not None:
        head += f", {steps} steps accepted"
    if newton_iterations is not None:
        head += f", {newton_iterations} Newton iterations"
    head += f"): {cause}"
    parts = [head]
    if hint:
        parts.append(hint)
    if contact_states:
        parts.append("contact state at the last accepted step:")
        for i, s in enumerate(contact_states):
            parts.append(describe_contact_state(s, (names[i] if names else f"contact set {i}")))
    return "\n".join(parts)
