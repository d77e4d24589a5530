"""mbs.CreateAnisotropicContact: bound to exudyn.MainSystem by importing exu_aniso (Exudyn's
extension registry), the same result as the free function, Exudyn-style names and errors."""
from __future__ import annotations

import inspect

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")

import exu_aniso  # noqa: E402,F401  (binds the method)
from exu_aniso import Adhesion, ContactLaw, Friction, Plane  # noqa: E402
from exu_aniso.engines.exudyn_adapter.create_contact import CreateAnisotropicContact  # noqa: E402

POINTS = [[sx * 0.05, sy * 0.05, -0.05] for sx in (-1, 1) for sy in (-1, 1)]
LAW = dict(surface=Plane(coordinates="polar"),
           adhesion=Adhesion.polar(eps_r=2.5e4, eps_phi=2.5e2, core_radius=1e-3),
           friction=Friction.polar(mu_r=0.3, mu_phi=0.6, core_radius=1e-3),
           normalStiffness=2.5e5, returnMap="radial")


def _block(method, **kw):
    """A 1 kg cube pressed on the polar plane and pulled sideways by a constant load; returns the
    sensor values of its position and of the dissipated energy after 0.3 s."""
    from exudyn.utilities import InertiaCuboid, LoadForceVector, MarkerBodyPosition, SensorBody
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    oBlock = mbs.CreateRigidBody(inertia=InertiaCuboid(1000., [0.1] * 3), referencePosition=[0.5, 0.1, 0.05 - 3.9e-5],
                                 nodeType=exu.NodeType.RotationEulerParameters, gravity=[0, 0, -9.81])
    m = mbs.AddMarker(MarkerBodyPosition(bodyNumber=oBlock, localPosition=[0, 0, 0]))
    mbs.AddLoad(LoadForceVector(markerNumber=m, loadVector=[3.5, 1.0, 0.0]))
    if method:
        contact = mbs.CreateAnisotropicContact(bodyNumber=oBlock, localPoints=POINTS, **LAW, **kw)
    else:
        contact = CreateAnisotropicContact(mbs, oBlock, POINTS, **LAW)
    sPos = mbs.AddSensor(SensorBody(bodyNumber=oBlock, outputVariableType=exu.OutputVariableType.Position,
                                    storeInternal=True))
    mbs.Assemble()
    s = exu.SimulationSettings()
    s.timeIntegration.numberOfSteps = 300
    s.timeIntegration.endTime = 0.3
    s.timeIntegration.newton.relativeTolerance = 1e-10
    s.timeIntegration.verboseMode = 0
    s.solution.file.write = False
    mbs.SolveDynamic(s)
    return mbs, contact, mbs.GetSensorStoredData(sPos), mbs.GetSensorStoredData(contact["sDissipation"])


def test_method_is_bound_by_importing_the_package():
    assert hasattr(exu.MainSystem, "CreateAnisotropicContact")
    sig = inspect.signature(exu.MainSystem.CreateAnisotropicContact)
    for arg in ("name", "bodyNumber", "localPoints", "surface", "adhesion", "friction", "normalStiffness",
                "show", "color", "showTraction"):
        assert arg in sig.parameters, arg
    assert sig.parameters["show"].default is True
    assert sig.parameters["normalStiffness"].annotation not in (inspect.Parameter.empty, None)
    doc = exu.MainSystem.CreateAnisotropicContact.__doc__
    for part in ("Args:", "Returns:", "Example:", "mbs.CreateAnisotropicContact("):
        assert part in doc, part


def test_method_equals_free_function():
    """Same physics: positions and dissipation of the block bit for bit (graphics off and on)."""
    _, _, pos0, d0 = _block(False)
    for show in (False, True):
        _, _, pos1, d1 = _block(True, show=show)
        np.testing.assert_array_equal(pos0, pos1)
        np.testing.assert_array_equal(d0, d1)
    assert np.linalg.norm(pos0[-1, 1:3] - pos0[0, 1:3]) > 1e-3      # it did slide
    assert d0[-1, 1] > 0.0


def test_names_follow_exudyn():
    mbs, contact, _, _ = _block(True, name="blockOnPlane", show=False)
    assert mbs.GetObject(contact["oContact"])["name"] == "blockOnPlane"
    assert mbs.GetNode(contact["nData"])["name"] == "blockOnPlaneHistory"
    assert mbs.GetSensor(contact["sDissipation"])["name"] == "blockOnPlaneDissipationSensor"
    assert int(mbs.GetObjectNumber("blockOnPlane")) == int(contact["oContact"])


def _fresh():
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    from exudyn.utilities import InertiaCuboid
    oBody = mbs.CreateRigidBody(inertia=InertiaCuboid(1000., [0.1] * 3), referencePosition=[0.5, 0, 0.05],
                                nodeType=exu.NodeType.RotationEulerParameters)
    return mbs, oBody


@pytest.mark.parametrize("change,match,err", [
    (dict(normalStiffness=-1.0), r"^CreateAnisotropicContact: normalStiffness must be > 0", ValueError),
    (dict(normalDamping=float("nan")), r"^CreateAnisotropicContact: normalDamping must be", ValueError),
    (dict(returnMap="closest"), r"^CreateAnisotropicContact: returnMap must be one of", ValueError),
    (dict(name=3), r"^CreateAnisotropicContact: name must be a string", TypeError),
    (dict(show="yes"), r"^CreateAnisotropicContact: show must be True or False", TypeError),
    (dict(initializeHistory=1), r"^CreateAnisotropicContact: initializeHistory must be True or False", TypeError),
    (dict(localPoints=[[0, 0]]), r"^CreateAnisotropicContact: localPoints", ValueError),
    (dict(adhesion=Friction.isotropic(0.3)), r"^CreateAnisotropicContact: adhesion must be an Adhesion", TypeError),
    (dict(contactLaw=ContactLaw(Plane(), Adhesion.isotropic(1e3), Friction.isotropic(0.3), 1e5)),
     r"^CreateAnisotropicContact: contactLaw replaces surface", ValueError),
])
def test_errors_name_the_method_and_the_argument(change, match, err):
    mbs, oBody = _fresh()
    kw = dict(bodyNumber=oBody, localPoints=POINTS, **LAW)
    kw.update(change)
    with pytest.raises(err, match=match):
        mbs.CreateAnisotropicContact(**kw)


def test_missing_body_is_named():
    mbs, _ = _fresh()
    with pytest.raises(ValueError, match="^CreateAnisotropicContact: bodyNumber must be given"):
        mbs.CreateAnisotropicContact(localPoints=POINTS, **LAW)
