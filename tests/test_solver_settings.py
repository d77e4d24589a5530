"""RecommendedSimulationSettings: one definition of the package's solver settings.

The scenes' SimulationSettingsFor delegates to it and must build the very settings it built
before (every field of Exudyn's settings dictionary compared with the former body, kept here)."""
import exudyn as exu
import pytest

import exu_aniso
from exu_aniso.engines.exudyn_adapter.runner import SimulationSettingsFor
from exu_aniso.scenes.block import BlockParams
from exu_aniso.scenes.screw import ScrewParams
from exu_aniso.engines.timing import step_count
from exu_aniso.engines.exudyn_adapter.solver_settings import RecommendedSimulationSettings


def _former(p, rhoInf=0.8, newtonTolerance=1e-10, solverType=None, newton="modified"):
    """SimulationSettingsFor's body before it delegated (the reference of this test)."""
    ss = exu.SimulationSettings()
    ti = ss.timeIntegration
    ti.numberOfSteps = step_count(p)
    ti.endTime = p.t_end
    ti.minimumStepSize = 2.0 ** -10 * p.t_end / ti.numberOfSteps
    ti.verboseMode = 0
    ti.newton.useModifiedNewton = newton == "modified"
    ti.newton.modifiedNewtonContractivity = 0.01
    ti.newton.relativeTolerance = newtonTolerance
    ti.newton.absoluteTolerance = newtonTolerance
    ti.generalizedAlpha.spectralRadius = rhoInf
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = 0
    if solverType is None:
        solverType = {"trapezoidal": exu.DynamicSolverType.TrapezoidalIndex2,
                      "generalized_alpha": exu.DynamicSolverType.GeneralizedAlpha}[p.solver]
    return ss, solverType


def _params():
    from exu_aniso.scenes.capstan import CapstanParams
    from exu_aniso.scenes.fastening import FasteningParams
    from exu_aniso.scenes.feeder import FeederParams
    from exu_aniso.scenes.particle import ParticleParams
    return [BlockParams(), BlockParams(solver="generalized_alpha", t_end=0.3, dt=7e-4),
            BlockParams(t_end=1.3e-3, dt=1e-3), ScrewParams(),
            ScrewParams(solver="generalized_alpha", dt=2e-4),
            ParticleParams(), CapstanParams(), FeederParams(), FasteningParams()]


OPTIONS = [{}, dict(rhoInf=0.3), dict(rhoInf=0.0, newtonTolerance=1e-8), dict(newton="full"),
           dict(solverType=exu.DynamicSolverType.RK44),
           dict(newton="full", rhoInf=1.0, newtonTolerance=3e-9,
                solverType=exu.DynamicSolverType.GeneralizedAlpha)]


@pytest.mark.parametrize("options", OPTIONS, ids=[str(o) for o in OPTIONS])
def test_scenes_settings_unchanged(options):
    """Every field of Exudyn's settings dictionary and the solver type as before, on every scene."""
    for p in _params():
        ss, st = SimulationSettingsFor(p, **options)
        ref, ref_st = _former(p, **options)
        assert st == ref_st, (type(p).__name__, options)
        assert ss.GetDictionary() == ref.GetDictionary(), (type(p).__name__, options)


def test_recommended_defaults():
    ss, st = RecommendedSimulationSettings(0.5, 1e-3)
    ti = ss.timeIntegration
    assert st == exu.DynamicSolverType.GeneralizedAlpha
    assert (ti.numberOfSteps, ti.endTime) == (500, 0.5)
    assert ti.minimumStepSize == pytest.approx(1e-3 / 1024, rel=1e-15)
    assert ti.newton.useModifiedNewton and ti.newton.modifiedNewtonContractivity == 0.01
    assert ti.newton.relativeTolerance == ti.newton.absoluteTolerance == 1e-10
    assert ti.generalizedAlpha.spectralRadius == 0.8
    assert ti.verboseMode == 0 and not ss.solution.file.write and ss.solution.sensors.writePeriod == 0
    # a fresh SimulationSettings otherwise
    d, fresh = ss.GetDictionary(), exu.SimulationSettings().GetDictionary()
    d["timeIntegration"].pop("newton"), fresh["timeIntegration"].pop("newton")
    for key in ("numberOfSteps", "endTime", "minimumStepSize", "verboseMode"):
        d["timeIntegration"].pop(key), fresh["timeIntegration"].pop(key)
    d["timeIntegration"]["generalizedAlpha"].pop("spectralRadius")
    fresh["timeIntegration"]["generalizedAlpha"].pop("spectralRadius")
    d["solution"]["sensors"].pop("writePeriod"), fresh["solution"]["sensors"].pop("writePeriod")
    d["solution"]["file"].pop("write"), fresh["solution"]["file"].pop("write")
    assert d == fresh


def test_recommended_options():
    ss, st = RecommendedSimulationSettings(1.0, 3e-3, solver="trapezoidal", newton="full", spectralRadius=0.5)
    assert st == exu.DynamicSolverType.TrapezoidalIndex2
    assert ss.timeIntegration.numberOfSteps == 333 and not ss.timeIntegration.newton.useModifiedNewton
    assert ss.timeIntegration.generalizedAlpha.spectralRadius == 0.5
    _, st = RecommendedSimulationSettings(1.0, 1e-3, solver=exu.DynamicSolverType.RK44)
    assert st == exu.DynamicSolverType.RK44
    ss, _ = RecommendedSimulationSettings(1.4e-3, 1e-3)        # the nearest whole number of steps
    assert ss.timeIntegration.numberOfSteps == 1


def test_one_definition():
    assert exu_aniso.RecommendedSimulationSettings is RecommendedSimulationSettings
    assert "RecommendedSimulationSettings" in exu_aniso.__all__


@pytest.mark.parametrize("kwargs, error, words", [
    (dict(endTime=0.0, stepSize=1e-3), ValueError, "endTime must be > 0"),
    (dict(endTime="1", stepSize=1e-3), TypeError, "endTime must be a real number"),
    (dict(endTime=1.0, stepSize=-1e-3), ValueError, "stepSize must be > 0"),
    (dict(endTime=1.0, stepSize=float("nan")), ValueError, "stepSize must be finite"),
    (dict(endTime=1e-4, stepSize=1e-3), ValueError, "stepSize must be <= endTime"),
    (dict(endTime=1.0, stepSize=1e-3, newton="quasi"), ValueError, "newton must be one of"),
    (dict(endTime=1.0, stepSize=1e-3, newtonTolerance=0.0), ValueError, "newtonTolerance must be > 0"),
    (dict(endTime=1.0, stepSize=1e-3, spectralRadius=1.5), ValueError,
     "spectralRadius must lie in [0.0, 1.0]"),
    (dict(endTime=1.0, stepSize=1e-3, solver="euler"), ValueError, "solver must be one of"),
    (dict(endTime=1.0, stepSize=1e-3, solver=3), TypeError, "solver must be a solver name"),
])
def test_recommended_refuses(kwargs, error, words):
    with pytest.raises(error) as info:
        RecommendedSimulationSettings(**kwargs)
    assert words in str(info.value) and "RecommendedSimulationSettings" in str(info.value)


def test_scene_settings_errors_unchanged():
    """SimulationSettingsFor's own argument names stay in its messages."""
    with pytest.raises(ValueError, match="rhoInf must lie in"):
        SimulationSettingsFor(BlockParams(), rhoInf=2.0)
    with pytest.raises(ValueError, match="newtonTolerance must be > 0"):
        SimulationSettingsFor(BlockParams(), newtonTolerance=-1.0)
    with pytest.raises(ValueError, match="newton must be one of"):
        SimulationSettingsFor(BlockParams(), newton="x")
    with pytest.raises(TypeError, match="solverType must be an exudyn.DynamicSolverType"):
        SimulationSettingsFor(BlockParams(), solverType="RK44")
