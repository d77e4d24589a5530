"""The runner's pieces that talk to Exudyn's solver: the progress of a running solve
(``exudyn_pre_step``, reporting to an ``exu_aniso.util.progress.Progress``)."""
from __future__ import annotations

import exudyn as exu


def exudyn_pre_step(progress, previous=None):
    """An Exudyn pre-step user function ``(mbs, t) -> bool`` that updates ``progress`` (started) when due
    and otherwise only reads the clock; ``previous``: an existing Python pre-step function, called
    after it and whose return value (False stops the run) is passed on. The step count and the
    Newton iterations are read from ``mbs.sys["dynamicSolver"].it`` (SolveDynamic with storeSolver)."""
    start_of_step = exu.ConfigurationType.StartOfStep
    clock = progress.clock
    due = progress.next_due

    def pre_step(mbs, t):
        nonlocal due
        if clock() >= due:                      # the common case ends here: one clock read per step
            it = getattr(mbs.sys.get("dynamicSolver"), "it", None)
            steps = max(int(it.currentStepIndex) - 1, 0) if it is not None else 0
            newton = int(it.newtonStepsCount) if it is not None else 0
            # t is the END of the step about to be computed; report the time already reached
            progress.update(float(mbs.systemData.GetTime(start_of_step)), steps, newton)
            due = progress.next_due
        return True if previous is None else previous(mbs, t)

    return pre_step
