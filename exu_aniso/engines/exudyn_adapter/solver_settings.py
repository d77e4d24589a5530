"""The solver settings the package recommends for a model with anisotropic contact.

``RecommendedSimulationSettings(endTime, stepSize)`` returns the ``exu.SimulationSettings`` and the
``exu.DynamicSolverType`` for ``mbs.SolveDynamic``. The package's scenes get theirs from it too
(``exu_aniso.engines.exudyn_adapter.runner.SimulationSettingsFor`` delegates here), so a user's own model runs at
exactly the settings every figure of the documentation was measured with::

    import exudyn as exu
    import exu_aniso
    from exu_aniso import RecommendedSimulationSettings

    ...  # build mbs with mbs.CreateAnisotropicContact(...), then mbs.Assemble()
    ss, solverType = RecommendedSimulationSettings(endTime=1.0, stepSize=1e-3)
    mbs.SolveDynamic(ss, solverType=solverType)
"""
from __future__ import annotations

import exudyn as exu

from exu_aniso.util.validation import check_in_range, check_instance, check_positive

# Newton modes: "modified" (Exudyn's modified Newton with a Jacobian refresh by contractivity) and
# "full" (a fresh Jacobian at every iteration)
NEWTON_MODES = ("modified", "full")
# A fresh Jacobian whenever a Newton iteration reduces the residual by less than this factor (Exudyn's
# own threshold is 0.5)
NEWTON_CONTRACTIVITY = 0.01
# Floor of Exudyn's step reduction relative to the nominal step: 10 halvings
MIN_STEP_FRACTION = 2.0 ** -10
# solver names -> Exudyn's dynamic solver
SOLVER_TYPES = {"trapezoidal": exu.DynamicSolverType.TrapezoidalIndex2,
                "generalized_alpha": exu.DynamicSolverType.GeneralizedAlpha}

_WHERE = "RecommendedSimulationSettings"


def RecommendedSimulationSettings(endTime, stepSize, newton="modified", newtonTolerance=1e-10,
                                  spectralRadius=0.8, solver="generalized_alpha"):
    """Simulation settings and solver type for a model with anisotropic contact.

    Returns ``(simulationSettings, solverType)``: pass them to ``mbs.SolveDynamic(simulationSettings,
    solverType=solverType)``.

    endTime [s] > 0; stepSize [s], 0 < stepSize <= endTime: the nominal step. The run takes
    ``numberOfSteps = round(endTime / stepSize)`` steps of ``endTime / numberOfSteps`` (dt
    itself when endTime is a whole number of steps), as the package's scenes do;
    newton: "modified" (default) or "full" (see below);
    newtonTolerance > 0: Newton's relative and absolute tolerance (default 1e-10);
    spectralRadius in [0, 1]: generalized-alpha's spectral radius at infinite frequency (rho_inf;
    default 0.8; used by GeneralizedAlpha);
    solver: "generalized_alpha" (default), "trapezoidal" (TrapezoidalIndex2: Newmark beta 1/4,
    gamma 1/2, the scenes' default, for parity with the reference engine) or an
    ``exu.DynamicSolverType`` (e.g. ``RK44`` for an explicit check: explicit solvers need the 2D or
    the rotation-vector node).

    What the settings are and why:

    * **Modified Newton with a Jacobian refresh by contractivity** (``useModifiedNewton = True``,
      ``modifiedNewtonContractivity = NEWTON_CONTRACTIVITY = 0.01``): Exudyn keeps its Jacobian over
      iterations and steps and computes a fresh one whenever an iteration reduces the residual by
      less than a factor 0.01. The contact's tangent changes when points change between stick and
      slip; with Exudyn's own threshold, 0.5, a stale Jacobian keeps being used through sliding, where
      the residual then falls only by a constant factor per iteration. At 0.01 a sliding step refreshes
      it, and while the contact sticks (a linear spring) the old Jacobian is kept. On the scenes this
      costs a fraction of full Newton's CPU time and changes the results far below the time-step
      error (iterations, times and errors: docs/guide/settings.md, ``python
      studies/newton_settings.py``).
      ``newton="full"`` (a Jacobian at every iteration) solves each step to round-off: use it to
      compare two implementations to round-off or to close an energy ledger to round-off.
    * **Tolerance 1e-10, relative and absolute** (Exudyn's defaults: 1e-8 relative): the contact
      history (sticking anchor, traction) is committed from the converged state of every step and
      carried on, so Newton's error stays in the path; at Exudyn's defaults the reduced screw departs
      from full Newton far more than at these settings (docs/guide/settings.md).
    * **Generalized-alpha with spectral radius 0.8**: the contact stiffness puts vibrations far
      above what the step resolves; numerical damping at high frequency removes them (undamped they
      can grow through the contact nonlinearity), while 0.8 keeps the resolved motion nearly
      undamped. Choose "trapezoidal" only to compare with an undamped reference.
    * **A floor on the step reduction**: ``minimumStepSize = MIN_STEP_FRACTION * step`` (10
      halvings). A run whose step collapses stops (the solver reports it) instead of creeping on at
      a thousandth of the step (Exudyn's own floor is an absolute 1e-8 s).
    * **No solution file, sensors written every step, silent** (``solution.file.write = False``,
      ``solution.sensors.writePeriod = 0``, ``verboseMode = 0``): the solve costs what the model
      costs. For Exudyn's SolutionViewer switch the file back on
      (``simulationSettings.solution.file.write = True``).

    Every argument is checked; an error names it (``ValueError`` / ``TypeError``)."""
    endTime = check_positive(f"{_WHERE}: endTime", endTime)
    stepSize = check_positive(f"{_WHERE}: stepSize", stepSize)
    if not stepSize <= endTime:
        raise ValueError(f"{_WHERE}: stepSize must be <= endTime; got stepSize={stepSize!r} > "
                         f"endTime={endTime!r}")
    if newton not in NEWTON_MODES:
        raise ValueError(f"{_WHERE}: newton must be one of {NEWTON_MODES}; got {newton!r}")
    newtonTolerance = check_positive(f"{_WHERE}: newtonTolerance", newtonTolerance)
    spectralRadius = check_in_range(f"{_WHERE}: spectralRadius", spectralRadius, 0.0, 1.0)
    if isinstance(solver, str):
        if solver not in SOLVER_TYPES:
            raise ValueError(f"{_WHERE}: solver must be one of {tuple(SOLVER_TYPES)} or an "
                             f"exudyn.DynamicSolverType; got {solver!r}")
        solverType = SOLVER_TYPES[solver]
    else:
        solverType = check_instance(f"{_WHERE}: solver", solver, exu.DynamicSolverType,
                                    "solver name (str) or exudyn.DynamicSolverType")
    # >= 1 (stepSize <= endTime); as exu_aniso.engines.timing.step_count
    steps = max(1, int(round(endTime / stepSize)))
    ss = exu.SimulationSettings()
    ti = ss.timeIntegration
    ti.numberOfSteps = steps
    ti.endTime = endTime
    ti.minimumStepSize = MIN_STEP_FRACTION * endTime / steps
    ti.verboseMode = 0
    ti.newton.useModifiedNewton = newton == "modified"
    ti.newton.modifiedNewtonContractivity = NEWTON_CONTRACTIVITY
    ti.newton.relativeTolerance = newtonTolerance
    ti.newton.absoluteTolerance = newtonTolerance
    ti.generalizedAlpha.spectralRadius = spectralRadius
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = 0          # every step
    return ss, solverType
