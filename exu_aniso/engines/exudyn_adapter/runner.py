"""The runner library of the package's Exudyn models (and of a user's own): a scene's model script as
one object whose ``run`` builds, solves, reads back and summarises (``ModelScript``), settings
(``SimulationSettingsFor``), drives (``AddNodeDrive``, ``AddYawDrive``, ``AddSpringDrive``), the timed
solve with its allocation check, progress and failure report (``SolveTimed``), the contact history as
sensors (``HistoryOutputs``), snapshots and the SolutionViewer (``WriteSnapshot``, ``StoreSolution``,
``ViewSolution``), a 3D body's motion for the energy ledger (``SensorMotion``) and the progress hook of a
running solve (``exudyn_pre_step``). It knows no scene: a scene's model script passes its scene
(through the interface of ``exu_aniso.scenes.scene``), its parameters (anything with t_end, dt and
solver) and its model dict."""
from __future__ import annotations

import contextlib
import io
import math
import os
import re
import sys
import time
from dataclasses import dataclass, field

import exudyn as exu
import exudyn.solver
import numpy as np
from exudyn import graphics as exu_graphics
from exudyn.itemInterface import (MarkerNodeCoordinate, MarkerNodeCoordinates, NodeGenericODE2, NodePointGround,
                                  ObjectConnectorCoordinate, ObjectConnectorCoordinateSpringDamper, ObjectConnectorCoordinateVector,
                                  ObjectGenericODE2, VNodePointGround, VObjectGenericODE2,
                                  VObjectConnectorCoordinate, VObjectConnectorCoordinateSpringDamper)
from exudyn.rigidBodyUtilities import (EulerParameters2GLocal, EulerParameters2RotationMatrix, RotationMatrixX,
                                       RotationMatrixZ)

from exu_aniso.law.history import HISTORY_FIELDS, N_HISTORY
from exu_aniso.engines.exudyn_adapter.commit import contact_force_calls, disarm_native
from exu_aniso.engines.failure import SimulationFailure, contact_state_from_history, failure_message
from exu_aniso.engines.result import Result
from exu_aniso.util.output import atomic_write
from exu_aniso.util.progress import make_progress
from exu_aniso.engines.energy import RigidMotion
from exu_aniso.engines.timing import driver_travel
from exu_aniso.engines.exudyn_adapter.solver_settings import NEWTON_MODES, SOLVER_TYPES
from exu_aniso.util.rotations import rotation_matrix, skew, wrap_angle
from exu_aniso.util.validation import check_in_range, check_instance, check_nonnegative, check_positive


NODE_TYPES = {"RotVecLG": exu.NodeType.RotationRotationVector, "EP": exu.NodeType.RotationEulerParameters}


def SimulationSettingsFor(p, rhoInf=0.8, newtonTolerance=1e-10, solverType=None, newton="modified"):
    """SimulationSettings and DynamicSolverType of a scene parameter set p (BlockParams or ScrewParams).

    newton: "modified" (Exudyn's modified Newton with a Jacobian update when an iteration contracts
    by less than NEWTON_CONTRACTIVITY) or "full" (useModifiedNewton False); relative/absolute Newton
    tolerance ``newtonTolerance``; numberOfSteps = scenes.step_count(p) (round(t_end / dt)), the step's
    floor MIN_STEP_FRACTION of the nominal step, sensors every step, no solution
    file, silent. p.solver "trapezoidal" -> TrapezoidalIndex2 (Newmark beta 1/4, gamma 1/2, as the
    reference); "generalized_alpha" -> GeneralizedAlpha with spectralRadius = rhoInf (reference
    rho_inf). solverType: an exu.DynamicSolverType overriding p.solver (e.g. RK44 for an explicit check).
    Built by exu_aniso.engines.exudyn_adapter.solver_settings.RecommendedSimulationSettings (the one definition)."""
    rhoInf = check_in_range("rhoInf", rhoInf, 0.0, 1.0)
    newtonTolerance = check_positive("newtonTolerance", newtonTolerance)
    if newton not in NEWTON_MODES:
        raise ValueError(f"newton must be one of {NEWTON_MODES}; got {newton!r}")
    if solverType is not None:
        check_instance("solverType", solverType, exu.DynamicSolverType, "exudyn.DynamicSolverType")
    # one definition: the package's recommended settings for any model (exu_aniso.engines.exudyn_adapter.solver_settings)
    from exu_aniso.engines.exudyn_adapter.solver_settings import RecommendedSimulationSettings
    return RecommendedSimulationSettings(p.t_end, p.dt, newton=newton, newtonTolerance=newtonTolerance,
                                         spectralRadius=rhoInf,
                                         solver=p.solver if solverType is None else solverType)


def AddScrewJointBody(mbs, mass, inertia, graphicsDataList=(), initialCoordinates=(0.0, 0.0)):
    """A body on a screw joint along the z axis: a NodeGenericODE2 with the coordinates (psi [rad] about
    z, z [m] along it) and an ObjectGenericODE2 with the mass matrix diag(inertia, mass)
    (CreateAnisotropicContact takes it as a screw-joint slave). graphicsDataList: the body's graphics in
    its own frame, drawn turned by psi and moved by z (a GenericODE2 object has no body frame).
    Returns (oBody, nBody)."""
    nBody = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0, 0.0], initialCoordinates=list(initialCoordinates),
                                        initialCoordinates_t=[0.0, 0.0], numberOfODE2Coordinates=2))
    local = list(graphicsDataList)

    def UFgraphics(mbs, itemNumber):
        psi, z = mbs.GetNodeOutput(nBody, exu.OutputVariableType.Coordinates,
                                   configuration=exu.ConfigurationType.Visualization)
        A = np.asarray(RotationMatrixZ(float(psi)))
        return [exu_graphics.Move(g, [0.0, 0.0, float(z)], A) for g in local]

    oBody = mbs.AddObject(ObjectGenericODE2(nodeNumbers=[nBody], massMatrix=np.diag([inertia, mass]),
                                            visualization=VObjectGenericODE2(graphicsDataUserFunction=UFgraphics)))
    return oBody, nBody


def AddNodeDrive(mbs, nodeNumber, nCoordinates, force, jacobian, force_t=None, jacobian_t=None):
    """Add an ObjectGenericODE2 on one node applying the generalized force ``force(t, q) -> (n,)``
    (q: node coordinates without reference values) with the exact LHS Jacobian built from
    ``jacobian(t, q) -> (n, n)`` = -dQ/dq; a drive with a dashpot adds ``force_t(t, q_t) -> (n,)``
    and its ``jacobian_t(t) -> (n, n)`` = -dQ/dq_t. Returns the object number."""
    n = int(nCoordinates)

    def UFforce(mbs, t, itemNumber, q, q_t):
        f = force(t, np.asarray(q))
        return f if force_t is None else f + force_t(t, np.asarray(q_t))

    def UFjacobian(mbs, t, itemNumber, q, q_t, fODE2, fODE2_t):
        J = fODE2 * jacobian(t, np.asarray(q))
        return J if jacobian_t is None else J + fODE2_t * jacobian_t(t)

    return mbs.AddObject(ObjectGenericODE2(nodeNumbers=[nodeNumber], massMatrix=np.zeros((n, n)),
                                           forceUserFunction=UFforce, jacobianUserFunction=UFjacobian))


def AddYawDrive(mbs, nodeNumber, nodeType, torque):
    """A torque tau about the world z axis on a 3D rigid body's node (``nodeType`` "RotVecLG" or
    "EP"), ``torque(yaw, t) -> (tau, dtau/dyaw)``, with yaw the unwrapped angle atan2(A_10, A_00) of
    the body's rotation (a torsional spring to a driver: tau = k (omega t - yaw), dtau/dyaw = -k).
    An ``AddNodeDrive`` (Python ObjectGenericODE2) with its exact Jacobian with respect to the local
    rotation increment. Returns the object number."""
    ep = nodeType == "EP"
    nq = 7 if ep else 6
    yaw_last = [0.0]   # last evaluated yaw: only used to unwrap (per-step change << pi)

    def Kinematics(q):     # Exudyn's own functions of the node, as its sensors and markers use them
        if ep:
            e = q[3:7] + np.array([1.0, 0.0, 0.0, 0.0])
            return np.asarray(EulerParameters2RotationMatrix(e)), np.asarray(EulerParameters2GLocal(e))
        return rotation_matrix(q[3:6]), np.eye(3)

    def Yaw(A):
        yaw = yaw_last[0] + wrap_angle(math.atan2(A[1, 0], A[0, 0]) - yaw_last[0])
        yaw_last[0] = yaw
        return yaw

    def DriveForce(t, q):
        A, G = Kinematics(q)
        tau, _ = torque(Yaw(A), t)
        Q = np.zeros(nq)
        Q[3:] = G.T @ (A[2, :] * tau)       # local torque A^T (0, 0, tau)
        return Q

    def DriveJacobian(t, q):                # -dQ/dq, with respect to the local rotation increment
        A, G = Kinematics(q)
        tau, dtau = torque(Yaw(A), t)
        Kq = np.zeros((nq, nq))
        Kq[3:, 3:] = -G.T @ (skew(A[2, :] * tau) + dtau * np.outer(A[2, :], A[2, :])) @ G
        return Kq

    return AddNodeDrive(mbs, nodeNumber, nq, DriveForce, DriveJacobian)


# Exudyn's implicit solvers (the scenes' own); the explicit ones cannot solve constraints
IMPLICIT_SOLVERS = tuple(SOLVER_TYPES.values())


def AddSpringDrive(mbs, nodeNumber, direction, stiffness, speed, python=False, start=0.0, ramp=0.0, damping=0.0,
                   travel=None):
    """A drive spring on a node: the generalized force k (speed t - d.q) d on the node's coordinates
    q (displacements), d = ``direction`` over them (a unit coordinate vector, or e.g. (d_x, d_y, 0)
    for a spring along an in-plane direction), k = ``stiffness``, plus a dashpot c (speed - d.q_t) d
    beside it, c = ``damping`` [N s/m, or N m s/rad]. Returns the spring's object number.
    start, ramp [s] > 0: the driver rests until start and speeds up over ramp
    (``exu_aniso.engines.timing.driver_travel`` in place of speed t); the spring's force is then a
    Python function of time, one call per Newton iteration. travel: a function t -> (travel, rate) of
    the driver (numbers; e.g. a shaker's) in place of both; speed is then unused.

    Built from Exudyn C++ items, so no Python runs in it: a driver coordinate (a one-coordinate
    ``NodeGenericODE2`` starting at 0 with velocity ``speed``) held at that velocity by an
    ``ObjectConnectorCoordinate`` on velocity level (a constant velocity is integrated exactly, so
    the driver sits at speed t), and an ``ObjectConnectorCoordinateSpringDamper`` from the driven
    coordinate to it. The driven coordinate is q_i itself for a unit vector d = e_i, else a massless
    slider w held at d.q by an ``ObjectConnectorCoordinateVector`` on velocity level from consistent
    initial values (the position-level form drifts under generalized-alpha), which passes the
    spring force to the node. A hold (speed 0, no start, ramp or travel) is the spring and dashpot to
    ground alone, with no driver: Exudyn allocates two matrices per Newton iteration for a coordinate
    constraint in a model with Euler-parameter nodes (measured with ``exu.special.InfoStat``), and a
    hold needs none. python=True (explicit solvers, which cannot solve constraints): the same spring as
    a Python ``ObjectGenericODE2`` with its exact Jacobian (``AddNodeDrive``)."""
    d = np.asarray(direction, dtype=float)
    k, speed = float(stiffness), float(speed)
    start, ramp = check_nonnegative("start", start), check_nonnegative("ramp", ramp)
    c = check_nonnegative("damping", damping)

    last = {}

    def driver(t):
        """The driver's travel and rate at t, evaluated once per time (the force runs at every Newton
        iteration)."""
        if last.get("t") != t:
            s, s_t = driver_travel(t, speed, start, ramp) if travel is None else travel(t)
            last.update(t=t, value=(float(s), float(s_t)))
        return last["value"]
    if python:
        K, C = k * np.outer(d, d), c * np.outer(d, d)
        return AddNodeDrive(mbs, nodeNumber, d.size, lambda t, q: k * (driver(t)[0] - d @ q) * d,
                            lambda t, q: K, force_t=lambda t, q_t: c * (driver(t)[1] - d @ q_t) * d,
                            jacobian_t=lambda t: C)

    def generic_node(q0, q0_t):
        return mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0], initialCoordinates=[q0],
                                           initialCoordinates_t=[q0_t], numberOfODE2Coordinates=1))

    if np.count_nonzero(d) == 1 and d.max() == 1.0:          # d = e_i: the spring acts on q_i
        mDriven = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodeNumber, coordinate=int(np.argmax(d))))
    else:
        node = mbs.GetNode(nodeNumber)
        nSlider = generic_node(*(float(d @ np.asarray(node[name], dtype=float))
                                 for name in ("initialCoordinates", "initialVelocities")))
        mbs.AddObject(ObjectGenericODE2(nodeNumbers=[nSlider], massMatrix=np.zeros((1, 1))))
        mbs.AddObject(ObjectConnectorCoordinateVector(
            markerNumbers=[mbs.AddMarker(MarkerNodeCoordinates(nodeNumber=nodeNumber)),
                           mbs.AddMarker(MarkerNodeCoordinates(nodeNumber=nSlider))],
            scalingMarker0=d.reshape(1, -1), scalingMarker1=np.ones((1, 1)), offset=[0.0], velocityLevel=True))
        mDriven = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nSlider, coordinate=0))
    nGround = mbs.AddNode(NodePointGround(visualization=VNodePointGround(show=False)))
    mGround = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nGround, coordinate=0))
    if speed == 0.0 and start == 0.0 and ramp == 0.0 and travel is None:
        # a hold: the spring to ground itself; a driver held by a constraint would cost Exudyn two
        # matrix allocations per Newton iteration on a model with Euler-parameter nodes
        return mbs.AddObject(ObjectConnectorCoordinateSpringDamper(
            markerNumbers=[mDriven, mGround], stiffness=k, damping=c,
            visualization=VObjectConnectorCoordinateSpringDamper(show=False)))
    if start > 0.0 or ramp > 0.0 or travel is not None:
        # the driver's travel in the spring's force itself: a prescribed velocity that jumps would put
        # an index-2 solver's integrated driver half a step off
        def force(mbs, t, itemNumber, displacement, velocity, stiffness, damping, offset):
            s, s_t = driver(t)                  # displacement, velocity: 0 - (driven) and its rate
            return k * (s + displacement) + c * (s_t + velocity)
        return mbs.AddObject(ObjectConnectorCoordinateSpringDamper(
            markerNumbers=[mDriven, mGround], stiffness=k, damping=c, springForceUserFunction=force,
            visualization=VObjectConnectorCoordinateSpringDamper(show=False)))
    nDriver = generic_node(0.0, speed)
    mbs.AddObject(ObjectGenericODE2(nodeNumbers=[nDriver], massMatrix=np.zeros((1, 1))))
    mDriver = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nDriver, coordinate=0))
    mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[mGround, mDriver], offset=speed, velocityLevel=True,
                                            visualization=VObjectConnectorCoordinate(show=False)))
    return mbs.AddObject(ObjectConnectorCoordinateSpringDamper(
        markerNumbers=[mDriven, mDriver], stiffness=k, damping=c,
        visualization=VObjectConnectorCoordinateSpringDamper(show=False)))


def SolveTimed(mbs, simulationSettings, solverType, contacts=(), progress=None):
    """mbs.SolveDynamic with wall time; returns (wall_s, steps, newton_iterations, info dict); info
    has the solver type, the nominal and accepted steps, Newton's Jacobians and solve_cpu_s, the
    process CPU time of the solve [s] (both cores' when Exudyn uses threads).

    progress: None/False (silent), True or an ``exu_aniso.util.progress.Progress``: a run longer than
    about 2 s shows its progress on stderr (simulated time in %, ETA, steps/s, Newton iterations),
    through a pre-step user function chained with any existing Python one and removed afterwards
    (it reads a clock and returns until an update is due: +0.2 to +0.7 % on the default scenes, within
    the timing noise).

    If the solver fails (Exudyn raises SolverError when Newton fails at the minimum step size or
    with step reduction off, ModelError when a user function raises) this raises
    ``exu_aniso.engines.failure.SimulationFailure`` instead: its message gives the simulated time reached,
    the step size, the cause and the contact state of the last accepted step of every contact set
    in ``contacts`` (dicts of CreateAnisotropicContact), read from their history nodes. Exudyn's own
    failure printout (to stdout) is captured into ``SimulationFailure.solver_output`` when the
    solver is silent (verboseMode 0); on success it is passed on unchanged."""
    ti = simulationSettings.timeIntegration
    capture = io.StringIO() if int(ti.verboseMode) == 0 else None
    prog, previous = _AttachProgress(mbs, make_progress(progress), ti)
    allocations = exu.special.InfoStat(False)
    calls = contact_force_calls(mbs)
    threshold = exudyn.solver.solverCheckMemoryAllocationsThreshold
    exudyn.solver.solverCheckMemoryAllocationsThreshold = math.inf   # checked below, without Exudyn's own
    t0, c0 = time.perf_counter(), time.process_time()
    disarm_native(mbs)                          # the first call of the solve checks the views in Python
    try:
        with contextlib.redirect_stdout(capture) if capture is not None else contextlib.nullcontext():
            ok = mbs.SolveDynamic(simulationSettings, solverType=solverType, storeSolver=True)
        error = None if ok else "SolveDynamic returned False"
    except Exception as e:                      # exudyn.SolverError, exudyn.ModelError, ...
        error = e
    finally:
        disarm_native(mbs)
        exudyn.solver.solverCheckMemoryAllocationsThreshold = threshold
        if prog is not None:                    # leave the system as it was given
            mbs.SetPreStepUserFunction(previous if previous is not None else 0)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    it = mbs.sys["dynamicSolver"].it
    steps = int(it.currentStepIndex) - 1 if solverType in SOLVER_TYPES.values() else int(it.currentStepIndex)
    if prog is not None:                        # end the progress line before anything else is printed
        reached = exu.ConfigurationType.Current if error is None else exu.ConfigurationType.StartOfStep
        prog.finish(t=float(mbs.systemData.GetTime(reached)), steps=steps, newton_iterations=int(it.newtonStepsCount),
                    ok=error is None)          # a model may end a run early (a pre-step function returning False)
    if capture is not None and error is None and capture.getvalue():
        sys.stdout.write(capture.getvalue())
    if error is None:
        CheckAllocations(allocations, contact_force_calls(mbs) - calls, int(it.newtonStepsCount), threshold)
    if error is not None:
        raise _Failure(mbs, simulationSettings, it, steps, error, contacts,
                       capture.getvalue() if capture is not None else "") from (error if isinstance(error, Exception)
                                                                                 else None)
    # accepted steps beyond the nominal number mean Newton failed somewhere and Exudyn reduced the step
    # (the solver keeps no count of rejected attempts; count PreStep calls for that)
    info = dict(solverType=str(solverType), nominal_steps=int(simulationSettings.timeIntegration.numberOfSteps),
                accepted_steps=steps, newton_jacobians=int(getattr(it, "newtonJacobiCount", 0)), solve_cpu_s=cpu)
    return wall, steps, int(it.newtonStepsCount), info


@dataclass(frozen=True)
class ModelScript:
    """A scene's Exudyn model script as one object: ``run`` is what every scene's Run function does
    with it, written once.

    scene: the scene (``exu_aniso.scenes.scene.Scene``: its ``name``, ``Params``, ``summary`` and
    ``ledger``); build: ``Build<Model>(p, **options)`` -> the model dict (``mbs``,
    ``simulationSettings``, ``solverType``, ...); read(model, complete) -> (trajectory, summary
    inputs, ledger inputs): the trajectory from the solved model's sensors and the keyword arguments
    of the scene's ``summary`` and ``ledger`` (read after a failure with complete False: the ledger's
    inputs are then not used); contacts(model): the dicts of CreateAnisotropicContact (failure
    reports, ``SettingsInfo``); info(model): the scene's entries of a completed run's info (before
    the settings of ``SettingsInfo``); snapshotOptions: of ``WriteSnapshot``."""

    scene: object
    build: object
    read: object
    contacts: object = None
    info: object = None
    snapshotOptions: dict = field(default_factory=dict)

    def model_contacts(self, model):
        """The model's contacts: ``contacts(model)``, or the one ``model["contact"]``."""
        return [model["contact"]] if self.contacts is None else self.contacts(model)

    def run(self, p=None, progress=False, snapshot=None, solutionFile=None, **options):
        """Build and solve the scene with parameters p (the scene's defaults if None); returns an
        ``exu_aniso.engines.result.Result``: the trajectory with the scene's columns, the summary
        (``scene.summary``) with the energy ledger (``scene.ledger``), p and info. options: of the
        build function.

        progress: show the progress of a run longer than about 2 s on stderr (True, or an
        exu_aniso.util.progress.Progress; see SolveTimed); snapshot: file name of a PNG of the final
        state (``WriteSnapshot``: raytraced, no display needed; written only when the run completes);
        solutionFile: let Exudyn write its solution there, to be played back with
        ``ViewSolution(build(p, **options), solutionFile)``. A run that fails raises its
        ``SimulationFailure`` with the trajectory and summary up to the failure in ``failure.partial``
        (a ``Result``, info["complete"] False). info["post_cpu_s"]: the process CPU time [s] of
        reading the trajectory and the ledger."""
        scene = self.scene
        p = scene.Params() if p is None else p
        model = self.build(p, **options)
        contacts = self.model_contacts(model)
        if solutionFile is not None:
            StoreSolution(model["simulationSettings"], solutionFile)
        try:
            wall, steps, iters, info = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"],
                                                  contacts=contacts, progress=make_progress(progress, scene.name))
        except SimulationFailure as failure:        # keep what was computed: the trajectory up to the failure
            traj, inputs, _ = self.read(model, False)
            summary = scene.summary(traj, p, float("nan"), failure.steps, failure.newton_iterations, **inputs)
            failure.partial = Result(traj, summary, p, dict(engine="exudyn", complete=False,
                                                            time_reached=failure.time_reached))
            raise
        info["engine"] = "exudyn"
        c0 = time.process_time()
        traj, inputs, ledger_inputs = self.read(model, True)
        summary = scene.summary(traj, p, wall, steps, iters, **inputs)
        summary.update(scene.ledger(p, traj, **ledger_inputs))
        info.update(**({} if self.info is None else self.info(model)),
                    **SettingsInfo(model["simulationSettings"], contacts))
        info["post_cpu_s"] = time.process_time() - c0
        if snapshot is not None:
            info["snapshot"] = WriteSnapshot(model, snapshot, **self.snapshotOptions)
        return Result(traj, summary, p, info)

    def show(self, p=None):
        """What a model script does as ``python -m exu_aniso.models.<scene>``: run the scene (its
        defaults if p is None) with progress, print the summary's plain values and show its
        trajectory plot (``scene.plot`` on a Figure of ``scene.figsize``). Returns the Result."""
        import matplotlib.pyplot as plt
        result = self.run(p, progress=True)
        print({k: v for k, v in result.summary.items() if not isinstance(v, (dict, list))})
        fig = plt.figure(figsize=self.scene.figsize)
        self.scene.plot(result.trajectory, result.params, fig)
        fig.tight_layout()
        plt.show()
        return result


def SettingsInfo(simulationSettings, contacts):
    """The settings every scene's run reports in its info, read from what was built (not from the
    defaults of the options): the contacts' Jacobian ("analytic" | "numerical") and implementation
    (the first contact's; a scene's contacts share them), their points K (the evaluated points: one
    under the screw's symmetry) and Newton's variant ("modified" | "full") and relative tolerance."""
    n = simulationSettings.timeIntegration.newton
    return dict(jacobian=contacts[0]["jacobian"], implementation=contacts[0]["implementation"],
                K=sum(len(c["points"]) for c in contacts), newton="modified" if n.useModifiedNewton else "full",
                newton_tol=float(n.relativeTolerance))


def CheckAllocations(before, contact_calls, newton_iterations, threshold):
    """Exudyn's check of a solve's memory allocations (``exudyn.solver.CheckSolverInfoStatistics``:
    a warning when the most new Exudyn arrays, vectors or matrices exceed ``threshold`` and at
    least one per Newton iteration), without the allocations Exudyn makes itself for every call of
    a contact set's force function: 2 vectors, its copies of the returned force (tests/
    test_exudyn_warnings.py), which are no sign of a slow model and about which a user can do
    nothing. Anything else that allocates every iteration (a sensor, a user function of the
    model) still gives the warning. before: ``exu.special.InfoStat(False)`` at the solve's start;
    contact_calls: the force calls in the solve (commit.contact_force_calls). Returns the
    count checked."""
    new = np.array(exu.special.InfoStat(False)) - np.array(before)
    count = max(new[0], new[2] - 2 * contact_calls, new[4])
    if count > threshold and count >= newton_iterations:
        print(f"WARNING: the solve made {count} memory allocations beyond the 2 vectors Exudyn makes for "
              "every call of a contact's force function; something allocates in every time step (a sensor "
              "or a user function of the model): the solver may be slow", flush=True)
    return int(count)


def _AttachProgress(mbs, prog, ti):
    """Start ``prog`` (Progress or None) and install its pre-step function, chained with the system's
    own Python pre-step function; returns (prog or None, previous function or None). A symbolic
    pre-step function cannot be chained from Python: then no progress is shown."""
    if prog is None:
        return None, None
    previous = mbs.GetPreStepUserFunction()
    if isinstance(previous, dict):              # {'function': f, 'type': 'Python' | symbolic}
        if previous.get("type") != "Python":
            return None, None
        previous = previous["function"]
    if not callable(previous):                  # 0: none set
        previous = None
    prog.start(float(ti.endTime), float(ti.startTime))
    mbs.SetPreStepUserFunction(exudyn_pre_step(prog, previous))
    return prog, previous


def _cause(error):
    """Short text of what stopped the solver (the user function's own error line if there is one)."""
    if isinstance(error, str):
        return error
    text = str(error)
    if type(error).__name__ == "SolverError":
        return ("Newton did not converge and the step size could not be reduced further "
                "(exudyn.SolverError: " + text + ")")
    m = re.search(r"^\s*(\w+(?:Error|Exception|Failure)): (.*?)(?:\n\s*\n|\nAt:|$)", text, re.M | re.S)
    if "USER FUNCTION" in text and m:
        return f"a user function raised {m.group(1)}: {m.group(2).strip()}"
    return f"{type(error).__name__}: {text.strip()}"


def _Failure(mbs, simulationSettings, it, steps, error, contacts, output):
    """Build the SimulationFailure of a failed SolveDynamic (see SolveTimed)."""
    ti = simulationSettings.timeIntegration
    t_reached = float(mbs.systemData.GetTime(exu.ConfigurationType.StartOfStep))
    states = []
    for c in contacts:
        h = mbs.GetNodeOutput(c["nData"], exu.OutputVariableType.Coordinates,
                              configuration=exu.ConfigurationType.StartOfStep)
        law = c.get("law")
        states.append(contact_state_from_history(h, getattr(law, "eps_N", None), getattr(law, "d_N", 0.0)))
    hint = ""
    if type(error).__name__ == "SolverError":
        h = float(ti.endTime) / max(1.0, float(ti.numberOfSteps))
        hint = (f"(the step fell to its floor, minimumStepSize {ti.minimumStepSize:.3g} s = "
                f"{ti.minimumStepSize / h:.3g} of the nominal step {h:.3g} s; Newton maxIterations "
                f"{ti.newton.maxIterations}; try a smaller dt, softer penalties or another return map)")
    cause = _cause(error)
    msg = failure_message(t_reached, float(ti.endTime), float(it.currentStepSize), cause, states, steps=steps,
                          newton_iterations=int(it.newtonStepsCount), hint=hint)
    return SimulationFailure(msg, time_reached=t_reached, end_time=float(ti.endTime),
                             step_size=float(it.currentStepSize), cause=cause, contact_states=states, steps=steps,
                             newton_iterations=int(it.newtonStepsCount), solver_output=output)


def HistoryOutputs(mbs, contact):
    """Per-step total dissipated energy [J] and mean accumulated slip distance [m] from the
    contact's history sensor, and the history array (steps + 1, K, N_HISTORY)."""
    D = mbs.GetSensorStoredData(contact["sHistory"])
    H = _WithoutFirstColumn(D).reshape(D.shape[0], -1, N_HISTORY)
    return (H[:, :, HISTORY_FIELDS.index("dissipated_energy")].sum(axis=1),
            H[:, :, HISTORY_FIELDS.index("slip_distance")].mean(axis=1), H)


def _WithoutFirstColumn(D):
    """D[:, 1:] as a C-contiguous array in D's own memory (D, a fresh array of the caller's, is
    overwritten): the rows are moved down one by one, each over its own end and the next row's
    time. A copy would take a new block of the size of D, whose first touch costs the OS's page
    faults: 50-90 ms for the 8 x 8 block's 5.5 s history (5501 x 577 numbers), against 6-8 ms here."""
    n, m = D.shape
    if not D.flags.c_contiguous:
        return np.ascontiguousarray(D[:, 1:])
    flat = D.reshape(-1)
    for i in range(n):                 # numpy copies an overlapping slice as if through a buffer
        flat[i * (m - 1):(i + 1) * (m - 1)] = flat[i * m + 1:(i + 1) * m]
    return flat[:n * (m - 1)].reshape(n, m - 1)


def Unwrap(angle):
    """Continuous angle from a sequence of wrapped ones (per-step change below pi)."""
    return np.unwrap(np.asarray(angle, dtype=float))


SNAPSHOT_SIZE = (800, 600)                      # [width, height] of snapshot.png in pixels


# view of the snapshot (openGL.advanced.initialModelRotation): oblique from above, z up the image, from
# 35 deg above the xy-plane, from the side the default light falls on (applied at the first render of an SC)
SNAPSHOT_ROTATION = (RotationMatrixX(-math.radians(55.0)) @ RotationMatrixZ(math.radians(150.0))).T


def SceneView(SC, modelRotation=None):
    """The view a scene's model starts with, in the live renderer and the SolutionViewer as in the
    snapshot: obliquely from above (SNAPSHOT_ROTATION, or modelRotation 3x3) and zoomed onto small
    bodies too (minSceneSize 1 mm: the screw is 2 cm long, and Exudyn's default 0.1 m shows it as a
    dot seen from above). Every Build function of exu_aniso.models calls it on its SystemContainer."""
    settings = SC.visualizationSettings
    settings.general.minSceneSize = 1e-3
    rotation = SNAPSHOT_ROTATION if modelRotation is None else np.asarray(modelRotation, dtype=float)
    settings.openGL.advanced.initialModelRotation = np.asarray(rotation, dtype=float).tolist()
    return SC


def SnapshotImage(model, size=SNAPSHOT_SIZE, modelRotation=None):
    """The model's Current state (after a solve: the final one) as an RGB image (height, width, 3),
    uint8, rendered by Exudyn's software raytracer without a window (exudyn.interactive.ShowImage;
    no display needed). modelRotation: 3x3 view rotation (None: SNAPSHOT_ROTATION, oblique from
    above). The solver's status line is left out of the picture; the time is kept."""
    from exudyn.interactive import ShowImage
    SC = model["SC"]
    sd = model["mbs"].systemData                # draw the Current state, whatever the renderer last showed
    sd.SetSystemState(sd.GetSystemState(exu.ConfigurationType.Current), exu.ConfigurationType.Visualization)
    sd.SetTime(sd.GetTime(exu.ConfigurationType.Current), exu.ConfigurationType.Visualization)
    general = SC.visualizationSettings.general
    before = general.showSolverInformation, general.minSceneSize
    general.showSolverInformation = False
    general.minSceneSize = 1e-3                  # zoom onto a small body too (the screw is 2 cm long)
    try:
        return ShowImage(SC, size=list(size), show=False,
                         modelRotation=SNAPSHOT_ROTATION if modelRotation is None else modelRotation)
    finally:
        general.showSolverInformation, general.minSceneSize = before


def Snapshot(mbs, fileName=None, size=SNAPSHOT_SIZE, modelRotation=None):
    """A picture of a model's current state, for any Exudyn model (a user's own too), without a
    display: Exudyn's raytracer, the view fitted to everything drawn (the contact's surface with its
    net, the bodies, the contact points), seen obliquely from above (or along ``modelRotation``,
    3x3). Returns the RGB image (height, width, 3) as uint8 and writes it as PNG to ``fileName``
    when given. ``exu_aniso.Snapshot(mbs, "final.png")`` after ``mbs.SolveDynamic(...)``; the
    contact must be created with ``show=True`` (the default) for its surface to be drawn."""
    model = dict(SC=mbs.GetSystemContainer(), mbs=mbs)
    image = SnapshotImage(model, size=size, modelRotation=modelRotation)
    if fileName is not None:
        from matplotlib.image import imsave
        atomic_write(fileName, lambda f: imsave(f, image, format="png"))
    return image


def WriteSnapshot(model, fileName, size=SNAPSHOT_SIZE, modelRotation=None):
    """Write ``SnapshotImage`` as PNG to fileName, atomically (temporary name, then moved into place)."""
    from matplotlib.image import imsave
    image = SnapshotImage(model, size=size, modelRotation=modelRotation)
    atomic_write(fileName, lambda f: imsave(f, image, format="png"))
    return fileName


def StoreSolution(simulationSettings, fileName, frames=500):
    """Let the solver write its solution (coordinates, binary) to fileName, about ``frames`` rows over
    the run, for ``ViewSolution``."""
    ss = simulationSettings
    ss.solution.file.write = True
    ss.solution.file.binary = True
    ss.solution.file.name = str(fileName)
    span = float(ss.timeIntegration.endTime - ss.timeIntegration.startTime)
    ss.solution.file.writePeriod = span / max(int(frames), 1)


def DisplayProblem():
    """Why no render window can open here ("DISPLAY is not set", a display that does not answer),
    or None. Exudyn's renderer.Start() aborts the whole process on Linux without a display, so check
    this before calling it."""
    if bool(exu.special.userInterface.suppressRenderer):   # Start() returns at once: harmless
        return None
    if sys.platform.startswith(("win", "cygwin", "darwin")):
        return None
    display = os.environ.get("DISPLAY")
    if not display:
        return "DISPLAY is not set"
    return _XServerProblem(display)


def _XServerProblem(display):
    """None if an X server answers at ``display`` ("[host]:N[.screen]"), else why not. A local
    display is the socket /tmp/.X11-unix/XN (or Linux's abstract socket of that name), a remote
    one TCP port 6000 + N; a display that does not answer makes Exudyn's renderer abort the
    process ("terminate called without an active exception")."""
    import socket
    host, sep, rest = display.rpartition(":")
    number = rest.split(".")[0]
    if not sep or not number.isdigit():
        return f"DISPLAY={display!r} is not of the form [host]:N[.screen]"
    if host in ("", "unix") or host.startswith("/"):
        path = f"/tmp/.X11-unix/X{number}"
        for address in (path, "\0" + path):          # the file, then Linux's abstract name
            with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
                s.settimeout(1.0)
                try:
                    s.connect(address)
                    return None
                except OSError:
                    continue
        return f"DISPLAY={display} does not answer (no X server at {path})"
    try:
        with socket.create_connection((host, 6000 + int(number)), timeout=1.0):
            return None
    except OSError as e:
        return f"DISPLAY={display} does not answer (no X server at {host}:{6000 + int(number)}: {e})"


def ViewSolution(model, fileName, title=""):
    """Open Exudyn's SolutionViewer (render window and dialog) on the solution file written by a run
    of the same model (RunBlock/RunScrew solutionFile=..., or ``StoreSolution``); returns when the
    window is closed. Raises RuntimeError instead of opening it when there is no display."""
    problem = DisplayProblem()
    if problem:
        raise RuntimeError(f"ViewSolution needs a display ({problem}); "
                           "use WriteSnapshot, or run under xvfb-run -a")
    from exudyn.utilities import LoadSolutionFile
    solution = LoadSolutionFile(str(fileName), verbose=False)
    model["mbs"].SolutionViewer(solution, title=title)


def SensorMotion(model):
    """energy.RigidMotion of a 3D rigid body from the model's stored sensors sPosition, sRotation,
    sVelocity and sOmega (position, rotation matrix, velocity, angular velocity)."""
    mbs, S = model["mbs"], model["sensors"]
    P, A, V, W = (mbs.GetSensorStoredData(S[k])[:, 1:] for k in ("sPosition", "sRotation", "sVelocity", "sOmega"))
    return RigidMotion(P, A.reshape(-1, 3, 3), V, W)


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
