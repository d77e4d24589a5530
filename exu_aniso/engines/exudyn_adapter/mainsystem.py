"""``mbs.CreateAnisotropicContact(...)``: the contact set as a MainSystem method, like Exudyn's own
``mbs.CreateRigidBody``, ``mbs.CreateDistanceConstraint``, ...

The method is bound to ``exudyn.MainSystem`` through Exudyn's extension registry
(``exudyn.misc.extensionRegistry``: ``@extends(MainSystem)`` marks it, ``install()`` binds it) when
``exu_aniso`` is imported. It builds the contact with the free function
``exu_aniso.engines.exudyn_adapter.create_contact.CreateAnisotropicContact`` (which stays, and gives the same result), then
adds what an Exudyn item has besides its physics: a name and renderer graphics.
"""
from __future__ import annotations

from typing import Sequence

import exudyn as exu
import numpy as np
from exudyn.misc.extensionRegistry import extends, install

from exu_aniso.engines.exudyn_adapter import create_contact
from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP

_WHERE = "CreateAnisotropicContact"


def _named(error):
    """The same error with the method's name in front (Exudyn names the function that raised)."""
    text = str(error)
    return type(error)(text if text.startswith(_WHERE + ":") else f"{_WHERE}: {text}")


@extends(exu.MainSystem)
def MainSystemCreateAnisotropicContact(mbs, name: str = "", bodyNumber=None, localPoints: Sequence = None,
                                       surface=None, adhesion=None, friction=None,
                                       normalStiffness: float = None, normalDamping: float = 0.,
                                       tangentialDamping: float = 0., returnMap: str = DEFAULT_RETURN_MAP,
                                       masterBodyNumber=None, jacobian: str = "analytic",
                                       initializeHistory: bool = True, storeSensors: bool = True,
                                       storeHistory: bool = False, implementation: str = "auto", contactLaw=None,
                                       show: bool = True, color: Sequence[float] = None,
                                       showTraction: bool = False, tractionScale: float = None,
                                       graphicsSize: float = None, nativeCallbacks: bool = None) -> dict:
    """Create anisotropic frictional contact (Konyukhov & Schweizerhof) between points fixed on a body and
    an analytical surface; the sticking stiffness (adhesion tensor B) and the sliding limit (friction
    tensor F) follow a net on the surface (polar orthotropy on a plane, a thread-like spiral on a cylinder)

    Args:
        mbs: the MainSystem where the contact shall be created
        name: name string of the contact object; its history node gets name+'History', its sensors
            name+'HistorySensor' and name+'DissipationSensor'
        bodyNumber: slave body (ObjectIndex): ObjectRigidBody (EP or rotation-vector node), ObjectRigidBody2D,
            ObjectMassPoint or ObjectMassPoint2D (localPoints=[[0, 0, 0]]), an ObjectGenericODE2 with a
            2-coordinate node (psi, z) for a reduced screw joint, or ANCF cable elements: one
            ObjectANCFCable2D / ObjectANCFCable or a list of them (one contact set for a whole rope),
            or a list of rigid bodies with nodes of one type (a group: one contact set, one Exudyn
            object and one compiled call for all of them, the same localPoints on each; many parts
            on one fixed surface), or a full linear finite-element body (an ObjectGenericODE2 of
            NodePoint nodes: exu_aniso.engines.exudyn_adapter.fem.AddLinearFEBody or Exudyn's
            FEMinterface.CreateLinearFEMObjectGenericODE2; the contact points are its mesh nodes)
        localPoints: list of K body-local contact points, each a 3D list or numpy array [m]; for cable
            elements [x, 0, 0] with 0 <= x <= element length, applied to every element in bodyNumber;
            for a group applied to every body (history rows body by body); for a finite-element body
            the mesh node indices (positions in its nodeNumbers) or the nodes' reference positions
        surface: a surface of exu_aniso (Plane, Cylinder, Cone, Sphere, Torus, Helicoid, SurfaceOfRevolution,
            ParametricSurface), in the frame of the master (ground or masterBodyNumber)
        adhesion: exu_aniso Adhesion field (B), stiffness per point [N/m]
        friction: exu_aniso Friction field (F), Coulomb coefficients
        normalStiffness: normal penalty stiffness per point [N/m], > 0
        normalDamping: normal dashpot per point [N s/m], >= 0
        tangentialDamping: tangential dashpot per point, parallel to friction while loaded [N s/m], >= 0
        returnMap: 'seed' (the papers' closed form), 'exact' (associated closest-point projection; the
            default, DEFAULT_RETURN_MAP) or 'radial' (adhesion-steered sliding); see docs/guide/conventions.md
        masterBodyNumber: None (the surface is fixed to ground) or a 3D rigid body carrying the surface
        jacobian: 'analytic' (consistent tangent) or 'numerical' (Exudyn's finite differences)
        initializeHistory: if True, points in contact at the initial configuration start sticking there
        storeSensors: if True, a sensor of the set's total dissipated energy is added (storeInternal)
        storeHistory: if True, a sensor of the whole history is added too (storeInternal: 9 numbers per
            point and step, so memory grows with points x steps; off unless asked for)
        implementation: 'auto', 'compiled' (numba kernel) or 'numpy'
        nativeCallbacks: None (native where available), True or False: Exudyn calls the compiled kernel
            through a C++ force function, without Python (the same numbers bit for bit)
        contactLaw: a ready exu_aniso.ContactLaw instead of surface, adhesion, friction, normalStiffness,
            normalDamping, tangentialDamping and returnMap
        show: if True, the surface with its net and the contact points (coloured open, stick, slip) are drawn
            in the renderer and in the SolutionViewer
        color: RGBA colour of the surface, e.g. exudyn.graphics.color.lightgrey; None: a default
        showTraction: if True, traction arrows are drawn at the contact points
        tractionScale: arrow length per Newton [m/N]; None: chosen from the scene size
        graphicsSize: the drawn surface's extent L [m] (polar disk radius, square half-width, tube
            half-length); None: from the contact points (AddContactGraphics)

    Returns:
        :dict: 'oContact' (ObjectIndex of the ObjectGenericODE2), 'nData' (NodeIndex of the history:
        9 numbers per point, see exu_aniso.HISTORY_FIELDS), 'nDissipation' (NodeIndex of the set's
        total dissipated energy [J]), 'sHistory' (SensorIndex, with storeHistory) and 'sDissipation'
        (SensorIndex of that total, with storeSensors), 'law' (the ContactLaw), 'points' (K x 3),
        'implementation', 'jacobian', 'nativeCallbacks', and the functions of the free function
        CreateAnisotropicContact (exu_aniso.engines.exudyn_adapter.create_contact): 'pointsAndMasterPose',
        'historyAt', 'bodyPosition', 'generalizedForce'

    Example:
        import exudyn as exu
        from exudyn.utilities import InertiaCuboid
        import exu_aniso
        from exu_aniso import Plane, Adhesion, Friction
        SC = exu.SystemContainer()
        mbs = SC.AddSystem()
        oBlock = mbs.CreateRigidBody(inertia=InertiaCuboid(1000., [0.1]*3), referencePosition=[0.5, 0, 0.05],
                                     nodeType=exu.NodeType.RotationEulerParameters, gravity=[0, 0, -9.81])
        contact = mbs.CreateAnisotropicContact(name='blockOnPlane', bodyNumber=oBlock,
                                               localPoints=[[sx*0.05, sy*0.05, -0.05] for sx in (-1, 1) for sy in (-1, 1)],
                                               surface=Plane(coordinates='polar'),
                                               adhesion=Adhesion.polar(eps_r=2.5e4, eps_phi=2.5e2, core_radius=1e-3),
                                               friction=Friction.polar(mu_r=0.3, mu_phi=0.3, core_radius=1e-3),
                                               normalStiffness=2.5e5, returnMap='radial')
        mbs.Assemble()
        simulationSettings = exu.SimulationSettings()
        simulationSettings.timeIntegration.numberOfSteps = 1000
        simulationSettings.timeIntegration.endTime = 1
        mbs.SolveDynamic(simulationSettings)
    """
    if not isinstance(name, str):
        raise TypeError(f"{_WHERE}: name must be a string; got {type(name).__name__} {name!r}")
    for flag, value in (("show", show), ("showTraction", showTraction)):
        if not isinstance(value, (bool, np.bool_)):
            raise TypeError(f"{_WHERE}: {flag} must be True or False; got {value!r}")
    if bodyNumber is None:
        raise ValueError(f"{_WHERE}: bodyNumber must be given (the slave body, an ObjectIndex)")
    if localPoints is None:
        raise ValueError(f"{_WHERE}: localPoints must be given (a list of body-local points [m])")
    if contactLaw is None:
        lawArgs = dict(surface=surface, adhesion=adhesion, friction=friction, normalStiffness=normalStiffness,
                       normalDamping=normalDamping, tangentialDamping=tangentialDamping, returnMap=returnMap)
    else:
        given = [k for k, v in (("surface", surface), ("adhesion", adhesion), ("friction", friction),
                                ("normalStiffness", normalStiffness)) if v is not None]
        given += [k for k, v in (("normalDamping", normalDamping), ("tangentialDamping", tangentialDamping))
                  if v != 0.]
        if returnMap != "exact":
            given.append("returnMap")
        if given:
            raise ValueError(f"{_WHERE}: contactLaw replaces {', '.join(given)}; give one or the other")
        lawArgs = dict(contactLaw=contactLaw)
    try:
        contact = create_contact.CreateAnisotropicContact(
            mbs, bodyNumber, localPoints, masterBodyNumber=masterBodyNumber, jacobian=jacobian,
            initializeHistory=initializeHistory, storeSensors=storeSensors, storeHistory=storeHistory,
            implementation=implementation, nativeCallbacks=nativeCallbacks, **lawArgs)
    except (TypeError, ValueError) as e:
        raise _named(e) from None
    if name:
        mbs.SetObjectParameter(contact["oContact"], "name", name)
        mbs.SetNodeParameter(contact["nData"], "name", name + "History")
        if "sHistory" in contact:
            mbs.SetSensorParameter(contact["sHistory"], "name", name + "HistorySensor")
        if "sDissipation" in contact:
            mbs.SetSensorParameter(contact["sDissipation"], "name", name + "DissipationSensor")
    from exu_aniso.engines.exudyn_adapter.graphics import AddContactGraphics
    try:
        AddContactGraphics(mbs, contact, show=show, color=color, showTraction=showTraction,
                           tractionScale=tractionScale, size=graphicsSize)
    except (TypeError, ValueError) as e:
        raise _named(e) from None
    return contact


install()
