"""``CreateAnisotropicContact``: adds a contact set between a slave's points and a ContactLaw's surface
to an mbs, the public constructor (``exu_aniso`` puts it on Exudyn's MainSystem).

Mechanism (verified against Exudyn 1.13; see docs/guide/contact_api.md, "How it works inside Exudyn"):

* one ``ObjectGenericODE2`` per contact set acting on the slave's nodes (and the master body node
  when the surface moves), with a ``forceUserFunction`` returning the generalized contact forces
  ``Q = sum_k Jp_k^T f_k`` and a ``jacobianUserFunction`` with the consistent tangent of
  ``exu_aniso.kernel.contact_law`` mapped through the point Jacobians ``Jp_k``, completed by the terms
  of ``Jp_k`` depending on the node coordinates (lever arms and point velocities turning with the
  body; ``ContactSet._add_geometric``) for every node type; with a moving master the compiled route
  (``kernel.sets.evaluate_pair``) gives it over the slave's and the master's coordinates, the numpy
  route leaves the Jacobian to Exudyn (numerical);
* the slave (``slaves``: a rigid body, a group of them, mass points, cables, the nodes of a
  finite-element body) is picked by the registry ``slaves.SLAVES`` / ``slaves.GROUPS`` from
  Exudyn's object type; the contact set (``contact_set``) by the slave's compiled route and the
  master;
* the history lives in a ``NodeGenericData`` (9 numbers per point, ``HISTORY_FIELDS``). During
  Newton the law is evaluated from the last *converged* history (``ConfigurationType.StartOfStep``);
  one post-Newton function per mbs (``commit``: native when every set is, else Python) evaluates
  every set at the converged state and writes the candidate to ``ConfigurationType.Current``.
  Exudyn copies Current to StartOfStep only when a step is accepted and restores Current from
  StartOfStep when it rejects a step, so rejected or reduced steps leave no trace.

The law itself is never changed here: every force comes from the ContactLaw.
"""
from __future__ import annotations

import exudyn as exu
import numpy as np
from exudyn.itemInterface import NodeGenericData, ObjectGenericODE2, SensorNode

from exu_aniso.engines.exudyn_adapter.commit import SETS_KEY, PostNewtonFallback, post_newton
from exu_aniso.engines.exudyn_adapter.contact_set import (CompiledGroupSet, CompiledPairSet, CompiledPointLaw,
                                                          CompiledSet, ContactSet)
from exu_aniso.engines.exudyn_adapter.native_callbacks import extension
from exu_aniso.engines.exudyn_adapter.slaves import slave_kinematics
from exu_aniso.engines.exudyn_adapter.slaves.rigid import body_node, node_kinematics
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.law.history import HISTORY_FIELDS, N_HISTORY
from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP
from exu_aniso.util.validation import check_bool, check_index, check_instance, check_points

_DISSIPATED = HISTORY_FIELDS.index("dissipated_energy")

COMPILED_SETS = {
    # (the slave's compiled route, a moving master): the contact set on the compiled kernel
    ("set", False): CompiledSet,
    ("set", True): CompiledPairSet,
    ("group", False): CompiledGroupSet,
}
"""The compiled contact set of a slave (``Slave.compiled_route``) on a fixed or a moving master. A
group has no moving master (``Slave.moving_master``), a slave without a route no compiled set."""


def CreateAnisotropicContact(mbs, bodyNumber, localPoints, surface=None, adhesion=None, friction=None,
                             normalStiffness=None, normalDamping=None, returnMap=DEFAULT_RETURN_MAP, contactLaw=None,
                             masterBodyNumber=None, jacobian="analytic", initializeHistory=True, storeSensors=True,
                             implementation="auto", tangentialDamping=None, storeHistory=False,
                             nativeCallbacks=None):
    """Add anisotropic frictional contact between body-fixed points and an analytical surface.

    bodyNumber: slave body (ObjectRigidBody, ObjectRigidBody2D for a planar model, ObjectMassPoint or
    ObjectMassPoint2D), or an ANCF cable: one ObjectANCFCable2D / ObjectANCFCable element or a list of
    them (one contact set over all their distinct nodes, e.g. a whole rope), or a list of rigid
    bodies with nodes of one type (a group: one contact set over all of them with localPoints on
    each, one ObjectGenericODE2, one compiled call per user function, the Jacobian as the bodies'
    diagonal blocks in a sparse matrix; a fixed surface only; history rows body by body), or a full
    linear finite-element body (an ObjectGenericODE2 of NodePoint nodes, MeshNodes: its mesh nodes
    are the points, given in localPoints as mesh node indices or reference positions; the result's
    'meshNodes' lists them); localPoints: (K, 3)
    body-local contact points [m]; for cables element-local points [x, 0, 0] with 0 <= x <= element
    length, applied to every element of the list (points ordered element by element: K = elements x
    points; x = Exudyn's Hermite shape functions, linear in the node coordinates, so the analytic
    Jacobian has no geometric terms); surface: a surface of
    exu_aniso (Plane, Cylinder, Cone, Sphere, Torus, Helicoid, SurfaceOfRevolution, ParametricSurface) in the
    master frame; adhesion / friction: exu_aniso Adhesion / Friction fields; normalStiffness
    eps_N [N/m per point]; normalDamping d_N [N s/m per point, default 0]; tangentialDamping d_T
    [N s/m per point, default 0: a dashpot -d_T v_t parallel to friction while loaded];
    returnMap "seed" | "exact" | "radial"; or contactLaw: a ready ContactLaw instead of these
    seven arguments (giving both is an error).
    masterBodyNumber: None (surface fixed to ground) or a 3D rigid body (RotVecLG or EP node)
    carrying the surface (equal and opposite force on it at the material point coinciding with each
    slave point).
    jacobian: "analytic" (consistent tangent; with a moving master over the slave's and the master's
    coordinates, on the compiled route only: the numpy route then uses Exudyn's) or "numerical"
    (Exudyn's).
    storeSensors: True -> a sensor of the set's total dissipated energy (one number per step);
    storeHistory: True -> also a sensor of the whole history (9 numbers per point and step: memory
    grows with points x steps, so it is off unless asked for; the history itself is always in the
    data node 'nData', for the renderer, the solution file and 'historyAt').
    initializeHistory: True -> points already in contact at the initial configuration start
    sticking there (anchor = initial contact point, T = 0), as in the reference engine; False ->
    they start as a new contact in the first step.
    Slave node types: NodeRigidBody2D, NodeRigidBodyRotVecLG, NodeRigidBodyEP, NodePoint, NodePoint2D,
    NodePoint2DSlope1 / NodePointSlope1 (cables), or a NodeGenericODE2 with 2 coordinates (psi about
    z [rad], z [m]) for a reduced screw-joint model.
    implementation: "compiled" (the numba kernel of exu_aniso.kernel.sets: one compiled call per user
    function; a surface and fields numba compiles; ground or moving master), "numpy"
    (ContactLaw.evaluate with numpy; any configuration) or "auto" (compiled where it applies, numpy
    otherwise). Both give the same results to round-off (tests/test_fastpath.py,
    tests/test_moving_master_compiled.py).
    nativeCallbacks: None (default: where the compiled kernel is used and the native extension is
    built), True (required: an error otherwise) or False: Exudyn calls the compiled kernel through a
    C++ force function (``_native.cpp``) without entering Python, instead of through a Python user
    function; the same compiled call on the same arguments, so the same numbers bit for bit
    (tests/test_native_callbacks.py). When every set of the system is native, the post-Newton commit
    is native too (``_native.post_newton``: the compiled stage kernel; Python for an unresolved step).
    The Jacobian stays in Python.

    Returns a dict with 'oContact' (ObjectGenericODE2), 'nDissipation' (NodeGenericData with the set's
    total dissipated energy [J], written with the history), 'nData' (NodeGenericData, the history:
    9 numbers per point, see HISTORY_FIELDS), 'sHistory' (sensor of the history, with storeHistory),
    'sDissipation' (sensor of the total dissipated energy [J], with storeSensors), 'law', 'points', 'implementation' (the one used),
    'jacobian' (as given) and 'nativeCallbacks' (True when Exudyn calls the native force),
    and for graphics and post-processing: 'bodyNumber', 'masterBodyNumber' (as given), and three
    read-only functions of (mbs, configuration=None) (an exu.ConfigurationType; None: the initial
    coordinates, usable before Assemble): 'pointsAndMasterPose' -> (slave points in the master frame
    (K, 3), master position (3,), master rotation (3, 3)), 'historyAt' -> history (K, 9) and
    'bodyPosition' -> global position (3,) of the slave body's local origin (a cable: the start of
    its first element); and 'generalizedForce', a function (q, q_t, history) -> the contact object's
    generalized force over its coordinates (reference values excluded; the slave's, then the
    master's) from a converged history (K, 9), as the solver evaluates it (post-processing of
    stored states: contact torques, reaction forces); samples at once: q, q_t (n, nq) and history
    (n, K, 9) give (n, nq).
    """
    if contactLaw is None:
        if normalStiffness is None:
            raise ValueError("CreateAnisotropicContact: give normalStiffness (with surface, adhesion, friction) "
                             "or a ready contactLaw")
        try:
            contactLaw = ContactLaw(surface, adhesion, friction, normalStiffness,
                                    0.0 if normalDamping is None else normalDamping, returnMap,
                                    tangential_damping=0.0 if tangentialDamping is None else tangentialDamping)
        except (TypeError, ValueError) as e:   # name the arguments as this function spells them
            raise type(e)("CreateAnisotropicContact: " + str(e).replace("normal_stiffness", "normalStiffness").replace(
                "normal_damping", "normalDamping").replace("tangential_damping", "tangentialDamping").replace(
                "return_map", "returnMap")) from None
    elif any(a is not None for a in (surface, adhesion, friction, normalStiffness, normalDamping, tangentialDamping)):
        raise ValueError("CreateAnisotropicContact: contactLaw replaces surface/adhesion/friction/normalStiffness/"
                         "normalDamping/tangentialDamping; give one or the other")
    check_instance("mbs", mbs, exu.MainSystem, "MainSystem of Exudyn (SC.AddSystem())")
    check_instance("contactLaw", contactLaw, ContactLaw)
    nObjects = mbs.systemData.NumberOfObjects()
    slave = slave_kinematics(mbs, bodyNumber, nObjects, localPoints)
    if masterBodyNumber is not None and check_index("masterBodyNumber", masterBodyNumber, nObjects, "object") in (
            [int(o) for o in (bodyNumber if isinstance(bodyNumber, (list, tuple, np.ndarray)) else [bodyNumber])]):
        raise ValueError(f"CreateAnisotropicContact: masterBodyNumber must differ from bodyNumber; got both "
                         f"{masterBodyNumber}")
    check_bool("initializeHistory", initializeHistory)
    check_bool("storeSensors", storeSensors)
    check_bool("storeHistory", storeHistory)
    if jacobian not in ("analytic", "numerical"):
        raise ValueError(f"CreateAnisotropicContact: jacobian must be 'analytic' or 'numerical'; got {jacobian!r}")
    if slave.points_are_nodes:      # every point is a mesh node (resolved from localPoints): no offset from it
        points = np.zeros((len(slave.mesh_indices), 3))
    else:
        points = check_points("localPoints", localPoints)
        slave.check_points(points)
    master = None
    if masterBodyNumber is not None:
        master = node_kinematics(mbs, body_node(mbs, masterBodyNumber))
        if master.kind not in ("RigidBodyRotVecLG", "RigidBodyEP"):
            raise ValueError("CreateAnisotropicContact: masterBodyNumber must be a 3D rigid body (RotVecLG or EP node)")
    if implementation not in ("auto", "compiled", "numpy"):
        raise ValueError("CreateAnisotropicContact: implementation must be 'auto', 'compiled' or 'numpy'; "
                         f"got {implementation!r}")
    point_law = slave.compiled_route is None       # its kinematics in numpy, the law compiled (CompiledPointLaw)
    compiled_ok = contactLaw.compiled and not (point_law and master is not None)
    if implementation == "compiled" and not compiled_ok:
        raise ValueError("CreateAnisotropicContact: implementation='compiled' needs a surface and fields numba can "
                         "compile, and has no route for an ObjectFFRFreducedOrder slave on a moving master; use "
                         "'numpy' or 'auto'")
    use_compiled = compiled_ok and implementation != "numpy" and not point_law
    if nativeCallbacks not in (None, True, False):
        raise ValueError(f"CreateAnisotropicContact: nativeCallbacks must be None, True or False; got {nativeCallbacks!r}")
    if nativeCallbacks and not use_compiled:
        raise ValueError("CreateAnisotropicContact: nativeCallbacks=True needs the compiled kernel (implementation "
                         "'auto' or 'compiled' with a surface and fields numba compiles; an ObjectFFRFreducedOrder "
                         "slave has no native callback)")
    if nativeCallbacks and extension is None:
        raise ValueError("CreateAnisotropicContact: nativeCallbacks=True, but the native extension "
                         "exu_aniso.engines.exudyn_adapter._native is not built (pip install builds it with a C++ "
                         "compiler)")
    use_native = use_compiled and extension is not None and nativeCallbacks is not False
    if not slave.moving_master and master is not None:
        raise ValueError("CreateAnisotropicContact: a list of rigid bodies in bodyNumber (a group) needs a fixed "
                         "surface (masterBodyNumber None); give each body its own contact set on a moving master")
    cls = COMPILED_SETS[slave.compiled_route, master is not None] if use_compiled else ContactSet
    cs = cls(mbs, contactLaw, slave, points, master)
    K = cs.K
    if point_law and compiled_ok and implementation != "numpy":
        cs.point_law = CompiledPointLaw(contactLaw, K)
    h0 = np.zeros(K * N_HISTORY)
    if initializeHistory:   # points in contact at t = 0 start sticking at their initial contact point
        nodes = [slave] + ([master] if master is not None else [])
        h0 = cs.initial_history(np.concatenate([nd.q0 for nd in nodes]), np.concatenate([nd.v0 for nd in nodes]))
    cs.nData = mbs.AddNode(NodeGenericData(initialCoordinates=h0.tolist(), numberOfDataCoordinates=K * N_HISTORY))
    # the set's total dissipated energy, written with the history: a C++ sensor reads it (no Python per step)
    cs.nTotal = mbs.AddNode(NodeGenericData(initialCoordinates=[float(h0[_DISSIPATED::N_HISTORY].sum())],
                                            numberOfDataCoordinates=1))
    nodes = slave.nodes + (master.nodes if master is not None else [])
    kw = {}
    if jacobian == "analytic" and (master is None or use_compiled):   # numpy route, moving master: Exudyn's
        kw["jacobianUserFunction"] = cs.jacobian_in_place if use_compiled else cs.jacobian
    # no mass matrix (the bodies have theirs): a dense zero n x n one would put (n)^2 zeros into a group's
    # sparse system matrix
    oContact = mbs.AddObject(ObjectGenericODE2(nodeNumbers=nodes, forceUserFunction=cs.force_in_place
                                               if use_compiled else cs.force, **kw))
    cs.locate(mbs, oContact)
    if use_native:
        mbs.SetObjectParameter(oContact, "forceUserFunction", cs.use_native(mbs))
        if "jacobianUserFunction" in kw:
            mbs.SetObjectParameter(oContact, "jacobianUserFunction", extension.jacobian)
    first = SETS_KEY not in mbs.variables
    sets = mbs.variables.setdefault(SETS_KEY, [])
    sets.append(cs)
    current = None if first else mbs.GetPostNewtonUserFunction()
    current = current.get("function") if isinstance(current, dict) else current    # Exudyn's record of it
    if first or current is post_newton or (extension is not None and current is extension.post_newton):
        if all(s._native is not None for s in sets):       # the commit without Python too (_native.cpp)
            extension.register_system(mbs, PostNewtonFallback(mbs))
            mbs.SetPostNewtonUserFunction(extension.post_newton)
        else:
            mbs.SetPostNewtonUserFunction(post_newton)
    out = {"oContact": oContact, "nData": cs.nData, "nDissipation": cs.nTotal, "law": contactLaw, "points": points,
           "implementation": "compiled" if use_compiled or cs.point_law is not None else "numpy",
           "nativeCallbacks": use_native, "jacobian": jacobian,
           # read-only views (exu_aniso.engines.exudyn_adapter.graphics); functions of (mbs,
           # configuration=None), see ContactSet
           "bodyNumber": bodyNumber, "masterBodyNumber": masterBodyNumber,
           "pointsAndMasterPose": cs.points_and_master_pose, "historyAt": cs.history_at,
           "bodyPosition": cs.body_position, "generalizedForce": cs.generalized_force}
    if slave.points_are_nodes:
        out["meshNodes"] = list(slave.mesh_indices)
    if storeHistory:     # 9 numbers per point and step: only when asked for
        out["sHistory"] = mbs.AddSensor(SensorNode(nodeNumber=cs.nData,
                                                   outputVariableType=exu.OutputVariableType.Coordinates,
                                                   storeInternal=True))
    if storeSensors:
        out["sDissipation"] = mbs.AddSensor(SensorNode(nodeNumber=cs.nTotal,
                                                       outputVariableType=exu.OutputVariableType.Coordinates,
                                                       storeInternal=True))
    return out


def HistoryComponent(point, field):
    """Sensor component index of `field` (a HISTORY_FIELDS name) of contact point `point` in the
    'sHistory' sensor, e.g. mbs.PlotSensor(sHistory, components=HistoryComponent(0, 'traction_1'))."""
    if field not in HISTORY_FIELDS:
        raise ValueError(f"field must be one of {HISTORY_FIELDS}; got {field!r}")
    return int(point) * N_HISTORY + HISTORY_FIELDS.index(field)
