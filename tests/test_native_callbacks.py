"""The native force callback (exu_aniso.engines.exudyn_adapter._native, exu_aniso.kernel.native):
Exudyn calls the compiled kernel through a C++ function, without Python.

Oracles: the same compiled call on the same arguments, so every scene gives the same numbers bit
for bit with the native callback and with the Python one (trajectories, histories, ledgers); the
native path's own bookkeeping (one call in Python per solve, restarts, a re-assembled system,
errors with their messages, the registry's size)."""
import ctypes
import gc
import sys

import exudyn as exu
import numpy as np
import pytest
from exudyn.utilities import InertiaCuboid

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso import Adhesion, ContactLaw, Cylinder, Friction, Plane
from exu_aniso.engines.exudyn_adapter import commit, create_contact, native_callbacks
from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
from exu_aniso.kernel.native import KERNEL_ERROR
from exu_aniso.models.block import BuildBlock
from exu_aniso.models.particle import BuildParticle
from exu_aniso.models.screw import BuildScrew
from exu_aniso.scenes.block import BlockParams
from exu_aniso.scenes.particle import ParticleParams
from exu_aniso.scenes.screw import ScrewParams


def test_the_native_extension_is_built():
    assert native_callbacks.extension is not None, ("exu_aniso.engines.exudyn_adapter._native is missing: `pip install .` builds it "
                                      "(setup.py, a C++ compiler and pybind11)")


@pytest.fixture
def callbacks(monkeypatch):
    """callbacks(native): every CreateAnisotropicContact of the block after it uses that callback."""
    original = create_contact.CreateAnisotropicContact

    def choose(native):
        def create(*args, **kwargs):
            kwargs["nativeCallbacks"] = native
            return original(*args, **kwargs)
        monkeypatch.setattr(create_contact, "CreateAnisotropicContact", create)
    return choose


def _sets(model):
    return model["mbs"].variables[commit.SETS_KEY]


def _sensors(model):
    mbs = model["mbs"]
    out = {}
    for name, s in list(model.get("sensors", {}).items()) + [(k, v) for k, v in model["contact"].items()
                                                              if k in ("sHistory", "sDissipation")]:
        out[name] = mbs.GetSensorStoredData(s)
    return out


def _run_both(callbacks, build):
    results = {}
    for native in (False, True):
        callbacks(native)
        model = build()
        assert model["contact"]["nativeCallbacks"] is native
        SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
        results[native] = (_sensors(model), model)
    return results


@pytest.mark.parametrize("build", [
    lambda: BuildBlock(BlockParams(model="full", points="corners", t_end=0.15)),            # EP node, plane
    lambda: BuildBlock(BlockParams(model="planar", points="grid:3", t_end=0.15)),           # 2D node
    lambda: BuildScrew(ScrewParams(t_end=0.05)),                                            # screw joint, helicoid
    lambda: BuildParticle(ParticleParams(t_end=0.1)),                                       # mass point (linear)
], ids=["block-full", "block-planar", "screw-reduced", "particle"])
def test_native_and_python_callbacks_give_the_same_numbers(callbacks, build):
    res = _run_both(callbacks, build)
    python, native = res[False][0], res[True][0]
    assert python.keys() == native.keys() and python
    for name in python:
        assert np.array_equal(python[name], native[name]), name
    cs = _sets(res[True][1])[0]
    n_native, n_delegated = cs.native_calls()
    assert n_delegated == 1 and n_native > 0          # the initial accelerations in Python, every Newton call native
    assert cs.native_jacobians()[0] > 0 and cs.native_jacobians()[1] == 0        # every Jacobian native
    committed_natively, in_python = commit.post_newton_calls(res[True][1]["mbs"])
    assert committed_natively > 0 and in_python <= committed_natively // 10   # the commit too (Python: unresolved steps)
    assert res[True][1]["mbs"].GetPostNewtonUserFunction()["function"] is native_callbacks.extension.post_newton


def test_a_law_that_cannot_be_cached_compiles_the_same_call_in_the_process(callbacks, monkeypatch):
    """A set whose argument type cannot be spelled out for numba's disk cache (a user's function in
    the law; here every type is declared so) gets the same cfunc compiled in the process, not from a
    file: the same numbers as the Python callback."""
    from exu_aniso.kernel import native
    monkeypatch.setattr(native, "_type_key", lambda ty: None)
    monkeypatch.setattr(native, "_CFUNCS", {})
    res = _run_both(callbacks, lambda: BuildBlock(BlockParams(model="full", points="corners", t_end=0.05)))
    for name, data in res[False][0].items():
        assert np.array_equal(data, res[True][0][name]), name
    module = _sets(res[True][1])[0]._native.cfunc._pyfunc.__module__         # numba's CFunc keeps its function
    assert module.startswith("exu_aniso_native_") and module not in sys.modules     # made here, not from a file


def test_argument_types_are_spelled_out_only_when_they_are_for_good():
    """The disk-cache key of a native cfunc: named tuples by importable classes, arrays, numbers;
    anything else (a class made at run time, a function) is not cached across processes."""
    from collections import namedtuple

    from numba import typeof

    from exu_aniso.kernel.native import _type_key
    from exu_aniso.kernel.point import LawParams
    from exu_aniso.law.return_maps import Radial
    law = LawParams(1.0, 0.0, 0.0, Radial())
    assert _type_key(typeof((np.zeros((2, 9)), law, 3))) == (
        "(array(float64, 2d, C), exu_aniso.kernel.point.LawParams(float64, float64, float64, "
        "exu_aniso.law.return_maps.Radial()), int64)")
    Local = namedtuple("LawParams", LawParams._fields)           # same name and fields, another class
    assert _type_key(typeof(Local(1.0, 0.0, 0.0, Radial()))) is None
    assert _type_key(typeof((np.zeros(2), Local(1.0, 0.0, 0.0, Radial())))) is None
    Mine = namedtuple("Radial", ())                              # a map type made at run time
    assert _type_key(typeof(LawParams(1.0, 0.0, 0.0, Mine()))) is None


def test_a_system_with_a_python_set_commits_in_python():
    """Two cubes, one native set and one on the Python callback: the system's post-Newton function is
    the Python one (it commits both), and the histories equal those of two Python sets."""
    histories = {}
    for natives in ((False, False), (True, False)):
        SC = exu.SystemContainer()
        mbs = SC.AddSystem()
        contacts = [_cube_on_plane(mbs, x0, native) for x0, native in zip((0.0, 1.0), natives)]
        mbs.Assemble()
        _solve(mbs, 0.05)
        assert mbs.GetPostNewtonUserFunction()["function"] is commit.post_newton
        histories[natives] = [np.array(mbs.GetNodeOutput(c["nData"], exu.OutputVariableType.Coordinates))
                              for c in contacts]
        assert [c["nativeCallbacks"] for c in contacts] == list(natives)
    for h0, h1 in zip(histories[(False, False)], histories[(True, False)]):
        assert np.array_equal(h0, h1) and np.any(h0 != 0.0)


def test_a_restart_and_a_continuation_equal_fresh_runs(callbacks):
    """Solving the same model again from t = 0 (the start before the last commit) and continuing a
    solve: the first call of each solve goes to Python, which sets the start of the step; the
    results equal a fresh model's."""
    callbacks(True)
    p = BlockParams(model="full", points="corners", t_end=0.1)
    fresh = BuildBlock(p)
    SolveTimed(fresh["mbs"], fresh["simulationSettings"], fresh["solverType"])
    again = BuildBlock(p)
    for _ in range(2):                                # the same solve twice: the second restarts at 0
        SolveTimed(again["mbs"], again["simulationSettings"], again["solverType"])
    for name, data in _sensors(fresh).items():
        assert np.array_equal(data, _sensors(again)[name]), name
    assert _sets(again)[0].native_calls()[1] == 2


def test_a_call_more_than_two_steps_after_the_armed_step_goes_to_python():
    """As after a solve interrupted by an exception (no disarm), a new solve that starts later: the
    armed set takes a call within two nominal steps of its start of step natively, and one beyond
    goes to Python (which checks the views and arms again); so does the Jacobian."""
    model = BuildBlock(BlockParams(model="full", points="corners", t_end=0.02))
    mbs = model["mbs"]
    SolveTimed(mbs, model["simulationSettings"], model["solverType"])
    cs = _sets(model)[0]
    dt = 0.02 / model["simulationSettings"].timeIntegration.numberOfSteps
    q, q_t = list(cs._q), list(cs._q_t)
    assert cs._native.clock[native_callbacks.extension.CLOCK_STEP] == pytest.approx(2 * dt)
    for later, native in ((1.5, True), (2.5, False)):
        cs._native.clock[:2] = (0.02, 1.0)                 # armed at the last step's end, as if not disarmed
        calls, jacobians = cs.native_calls(), cs.native_jacobians()
        native_callbacks.extension.call_force(mbs, cs.oContact, 0.02 + later * dt, q, q_t, 1)
        native_callbacks.extension.call_jacobian(mbs, cs.oContact, 0.02 + later * dt, q, q_t, 1.0, 0.0)
        went = 0 if native else 1
        assert cs.native_calls()[went] == calls[went] + 1
        assert cs.native_jacobians()[went] == jacobians[went] + 1


def _cube_on_plane(mbs, x0, native):
    a = 0.1
    o = mbs.CreateRigidBody(inertia=InertiaCuboid(1000.0, [a, a, a]), referencePosition=[x0, 0.0, 0.5 * a - 1e-4],
                            initialVelocity=[0.2, 0.0, 0.0], gravity=[0.0, 0.0, -9.81],
                            nodeType=exu.NodeType.RotationEulerParameters)
    corners = [[sx * a / 2, sy * a / 2, -a / 2] for sx in (-1, 1) for sy in (-1, 1)]
    law = ContactLaw(Plane(), Adhesion.isotropic(1e4), Friction.isotropic(0.3), normal_stiffness=1e5,
                     normal_damping=50.0)
    return mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=corners, contactLaw=law, nativeCallbacks=native,
                                        show=False)


def _solve(mbs, t_end):
    ss, st = exu_aniso.RecommendedSimulationSettings(endTime=t_end, stepSize=1e-3)
    mbs.SolveDynamic(ss, solverType=st)
    return ss


def test_a_grown_and_reassembled_system_is_read_from_its_new_vectors():
    """Between two solves a second cube with its contact is added and the system re-assembled:
    Exudyn may move its vectors, so the native set must not keep reading the old ones. Both cubes'
    histories after the second solve equal those of the Python callbacks."""
    histories = {}
    for native in (False, True):
        SC = exu.SystemContainer()
        mbs = SC.AddSystem()
        c1 = _cube_on_plane(mbs, 0.0, native)
        mbs.Assemble()
        _solve(mbs, 0.05)
        c2 = _cube_on_plane(mbs, 1.0, native)
        mbs.Assemble()
        _solve(mbs, 0.05)
        histories[native] = [np.array(mbs.GetNodeOutput(c["nData"], exu.OutputVariableType.Coordinates))
                             for c in (c1, c2)]
        if native:
            assert [cs.native_calls()[0] > 0 for cs in mbs.variables[commit.SETS_KEY]] == [True, True]
    for h0, h1 in zip(histories[False], histories[True]):
        assert np.array_equal(h0, h1)
        assert np.any(h0 != 0.0)


def _mass_point_in_cylinder(position):
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    o = mbs.CreateMassPoint(referencePosition=position, mass=1.0, gravity=[0.0, 0.0, -9.81])
    law = ContactLaw(Cylinder(radius=0.5, side="outside"), Adhesion.isotropic(1e4), Friction.isotropic(0.3),
                     normal_stiffness=1e5)
    mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=[[0.0, 0.0, 0.0]], contactLaw=law, nativeCallbacks=True,
                                 initializeHistory=False, show=False)
    mbs.Assemble()
    return SC, mbs


def test_an_error_in_the_kernel_reaches_the_user_with_its_message():
    """A slave point on the axis of a solid cylinder (the closest point is not unique there): the
    solve fails with the kernel's message, as with the Python callback; and the native kernel
    itself, called at such a state, returns KERNEL_ERROR (the native caller then repeats the call
    in Python, which raises the message) instead of a force."""
    SC, mbs = _mass_point_in_cylinder([0.0, 0.0, 0.0])
    with pytest.raises(exu.ModelError, match="centre of curvature"):
        _solve(mbs, 0.01)

    SC, mbs = _mass_point_in_cylinder([0.3, 0.0, 0.0])
    _solve(mbs, 0.002)
    cs = mbs.variables[commit.SETS_KEY][0]
    assert cs._native.clock[1] == 0.0                  # the end of the solve disarmed it
    cs._native.H[:] = 0.0                              # a new contact (on an active one the step is unresolved)
    status = []
    for x in ([0.3, 0.0, 0.0], [0.0, 0.0, 0.0]):
        q = (np.array(x) - np.array([0.3, 0.0, 0.0])).ctypes
        qd = np.zeros(3)
        status.append(cs._native.cfunc.ctypes(cs._native.args.address, 0, 1e-3, q.data_as(ctypes.POINTER(ctypes.c_double)),
                                              qd.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), 3, 0.0, 0.0))
    assert status == [1, KERNEL_ERROR]


def test_the_registry_forgets_the_sets_of_deleted_systems():
    before = native_callbacks.extension.registered()
    for _ in range(3):
        SC = exu.SystemContainer()
        mbs = SC.AddSystem()
        _cube_on_plane(mbs, 0.0, True)
        mbs.Assemble()
        assert native_callbacks.extension.registered() == before + 1
        del SC, mbs
        gc.collect()
    assert native_callbacks.extension.registered() == before
