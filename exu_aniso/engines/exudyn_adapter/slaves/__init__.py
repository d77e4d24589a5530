"""The slaves: what carries a contact set's points, one module per family (``base``: the interface;
``rigid``: rigid nodes and groups; ``linear``: mass points, cables, the nodes of a full
finite-element body; ``floating_frame``: a reduced finite-element body), and the registry that picks
one from the bodies given to ``CreateAnisotropicContact``.

A new slave kind is a module with its class (a ``base.Slave``) and a row in SLAVES (one body) or
GROUPS (a list of bodies), keyed by Exudyn's object type (docs/adding_a_slave.md)."""
from __future__ import annotations

import numpy as np

from exu_aniso.engines.exudyn_adapter.slaves.base import Slave
from exu_aniso.engines.exudyn_adapter.slaves.floating_frame import FloatingFrame
from exu_aniso.engines.exudyn_adapter.slaves.linear import LinearSlave, MeshNodes, hermite_shape_functions, is_mesh_body
from exu_aniso.engines.exudyn_adapter.slaves.rigid import RigidGroup, node_kinematics, rigid_body
from exu_aniso.util.validation import check_index

__all__ = ["GROUPS", "SLAVES", "FloatingFrame", "LinearSlave", "MeshNodes", "RigidGroup", "Slave",
           "hermite_shape_functions", "node_kinematics", "slave_kinematics"]


def generic_ode2(mbs, body, localPoints):
    """An ObjectGenericODE2: a full linear finite-element body (NodePoint nodes only: its mesh nodes
    are the points) or the screw joint (one 2-coordinate NodeGenericODE2)."""
    if is_mesh_body(mbs, mbs.GetObject(body)):
        return MeshNodes(mbs, body, localPoints)
    return rigid_body(mbs, body)


def _linear_body(mbs, body, localPoints):
    return LinearSlave(mbs, [body])


SLAVES = {
    # Exudyn object type: the slave of one such body, f(mbs, body, localPoints)
    "RigidBody": rigid_body,
    "RigidBody2D": rigid_body,
    "GenericODE2": generic_ode2,
    "MassPoint": _linear_body,
    "MassPoint2D": _linear_body,
    "ANCFCable2D": _linear_body,
    "ANCFCable": _linear_body,
    "FFRFreducedOrder": FloatingFrame,
}
"""The slave of one body by its object type; another object type is taken as a body with one rigid
node (``rigid_body``, whose error names the node types the kernel knows)."""

GROUPS = {
    # Exudyn object type: (the slave of a list of such bodies, f(mbs, objects), what one of them is called)
    "RigidBody": (RigidGroup, "body"),
    "RigidBody2D": (RigidGroup, "body"),
    "ANCFCable2D": (LinearSlave, "cable element"),
    "ANCFCable": (LinearSlave, "cable element"),
}
# (a list holds one slave's bodies; a group's may mix RigidBody and RigidBody2D objects, RigidGroup then
# refuses nodes of two types; cables are of one object type)
"""The slave of a list of bodies (one contact set over all of them): rigid bodies of one node type (a
group) or ANCF cable elements of one type (a rope)."""


def slave_kinematics(mbs, bodyNumber, nObjects, localPoints=None):
    """The slave of bodyNumber: one body (SLAVES) or a list of bodies (GROUPS), each an object index
    below nObjects."""
    many = isinstance(bodyNumber, (list, tuple, np.ndarray))
    objects = list(bodyNumber) if many else [bodyNumber]
    if many and not objects:
        raise ValueError("CreateAnisotropicContact: bodyNumber is an empty list; give a body or a list of ANCF cable "
                         "elements")
    for i, o in enumerate(objects):
        check_index(f"bodyNumber[{i}]" if many else "bodyNumber", o, nObjects, "object")
    types = [mbs.GetObject(o)["objectType"] for o in objects]
    if not many:
        return SLAVES.get(types[0], rigid_body)(mbs, bodyNumber, localPoints)
    builds = {GROUPS.get(t, (None, None))[0] for t in types}
    if len(builds) > 1 or None in builds:            # the entries that are not cables, as a rope is the usual list
        bad = [f"bodyNumber[{i}] = {o} is Object{t}" for i, (o, t) in enumerate(zip(objects, types))
               if GROUPS.get(t, (None, None))[1] != "cable element"]
        raise ValueError("CreateAnisotropicContact: a list in bodyNumber must hold either ANCF cable elements "
                         "(ObjectANCFCable2D or ObjectANCFCable, all of one type) or rigid bodies (ObjectRigidBody, "
                         "ObjectRigidBody2D, all of one node type); " + "; ".join(bad))
    build, member = GROUPS[types[0]]
    if member == "cable element" and len(set(types)) > 1:
        raise ValueError(f"CreateAnisotropicContact: the cable elements in bodyNumber must be all ObjectANCFCable2D or "
                         f"all ObjectANCFCable; got {sorted(set(types))}")
    if len(set(int(o) for o in objects)) < len(objects):
        raise ValueError(f"CreateAnisotropicContact: bodyNumber lists a {member} more than once; got {objects}")
    return build(mbs, objects)
