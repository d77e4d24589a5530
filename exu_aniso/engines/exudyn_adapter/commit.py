"""The post-Newton commit of a system's contact sets (every set stages its history candidate at the
converged state; an unresolved step is rejected and repeated shorter), in Python or native, and the
system's counters of calls."""
from __future__ import annotations

import weakref

import exudyn as exu

from exu_aniso.engines.exudyn_adapter.native_callbacks import alive, extension

SETS_KEY = "exu_aniso_contact_sets"
"""mbs.variables key of the system's contact sets (contact_set.ContactSet), in the order made."""

_SOS = exu.ConfigurationType.StartOfStep


def commit(mbs, t, sets):
    """Write the history candidates of the contact sets at the converged state of time t into the
    Current data coordinates (in place, through views of Exudyn's vector). Returns False when a
    set's step is unresolved; sets staged before it have written into Current, which Exudyn
    restores from StartOfStep when it rejects the step."""
    for cs in sets:
        if not cs.stage(mbs, t):
            return False
    return True


# Step reduction asked for when a contact point's motion in a step is unresolved (see
# ContactLaw.evaluate): the step is repeated with this fraction of its size.
UNRESOLVED_STEP_FACTOR = 0.25


def contact_force_calls(mbs):
    """How many times Exudyn called the force user functions of this system's contact sets so far.
    Exudyn allocates 2 vectors per call of an ObjectGenericODE2 force function (its own copies of the
    returned force), which its solver's allocation check counts (exu_aniso.engines.exudyn_adapter.runner.SolveTimed)."""
    sets = mbs.variables.get(SETS_KEY, ())
    return sum(cs.force_calls + cs.native_calls()[0] for cs in sets)


def post_newton(mbs, t):
    """Commit every contact set's history candidate; if any set saw an unresolved step, reject the
    step and ask Exudyn to repeat it with a quarter of the step size (Exudyn restores Current
    from StartOfStep, so sets already written leave no trace)."""
    sets = mbs.variables[SETS_KEY]
    if not commit(mbs, t, sets):
        h = t - mbs.systemData.GetTime(_SOS)
        return [1.0, UNRESOLVED_STEP_FACTOR * h]
    for cs in sets:
        if cs._native is not None:
            cs.step_done(t)
    return [0.0, -1.0]


def disarm_native(mbs):
    """Every native set of mbs calls Python first at its next call (``CompiledSet.disarm``): before
    and after a solve whose start the sets cannot see."""
    for cs in mbs.variables.get(SETS_KEY, ()):
        cs.disarm()


def post_newton_calls(mbs):
    """(native, Python) calls of the native post-Newton function of mbs so far."""
    return extension.post_newton_calls(extension.system_address(mbs)) if extension is not None else (0, 0)


class PostNewtonFallback:
    """What the native post-Newton function calls in Python: post_newton of the system, held weakly."""

    def __init__(self, mbs):
        self.mbs = weakref.ref(mbs)

    def __call__(self, t):
        return post_newton(alive(self.mbs, "the exudyn.MainSystem of a contact set"), t)

