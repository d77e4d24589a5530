"""The models the speed targets (``targets``) build beside the package's scenes and the yardstick
(``yardstick``): the full block's contact on a free plate instead of the fixed plane
(``plate_builder``: the moving master; ``free_plate``), and a user's body on a curved surface built
as a user builds it (``BuildUserBody``: a 1 kg box on its 4 bottom corners in a spherical bowl or
down a conical trough, resting at ``user_body_pose``)."""
from __future__ import annotations

import math

import exudyn as exu
import numpy as np
from exudyn.itemInterface import SensorNode
from exudyn.rigidBodyUtilities import RotationMatrixY
from exudyn.utilities import InertiaCuboid


def node_of(mbs, o):
    return mbs.GetObject(o)["nodeNumber"]


def plate_builder(p, speed=0.0, nodeType=exu.NodeType.RotationEulerParameters, implementation="auto",
                  jacobian="analytic", touching=True):
    """contactBuilder of BuildBlock: the block's contact on a free plate (a rigid body of 1e9 kg
    without load, moving uniformly at (speed, -speed/2, 0)) instead of the fixed plane: a
    moving-master set over the block's and the plate's coordinates. touching False: the block's
    contact stays on the fixed plane and the plate is beside it, in contact with nothing (what the
    plate's own dynamics cost in Exudyn)."""
    def build(mbs, oBlock, localPoints):
        from exu_aniso.scenes.block import block_contact_law
        oPlate = free_plate(mbs, speed, nodeType)
        return mbs.CreateAnisotropicContact(name="blockContact", bodyNumber=oBlock, localPoints=localPoints,
                                            contactLaw=block_contact_law(p),
                                            masterBodyNumber=oPlate if touching else None,
                                            jacobian=jacobian, initializeHistory=True,
                                            implementation=implementation, show=False,
                                            storeHistory=True)   # as the scene's own contact
    return build


def free_plate(mbs, speed=0.0, nodeType=exu.NodeType.RotationEulerParameters):
    return mbs.CreateRigidBody(inertia=InertiaCuboid(1e9 / 0.02, [1.0, 1.0, 0.02]),
                               referencePosition=[0.0, 0.0, 0.0], initialVelocity=[speed, -0.5 * speed, 0.0],
                               nodeType=nodeType, gravity=[0.0, 0.0, 0.0])


# the user's body: a box on its 4 bottom corners, values of the README's example (1 kg, 0.1 m)
USER_MASS, USER_SIZE, USER_NORMAL_STIFFNESS = 1.0, 0.1, 2.5e5          # kg, m, N/m per point
USER_ADHESION = (2.5e4, 2.5e3)                                         # N/m per point, along xi1 and xi2
BOWL_RADIUS, BOWL_START = 1.0, math.radians(30.0)                      # m; start 30 deg up the wall
BOWL_FRICTION = (0.3, 0.2)                                             # tan 30 deg = 0.58 > 0.3: it slides
TROUGH_RADIUS, TROUGH_HALF_ANGLE = 0.3, math.radians(20.0)             # m at the start; rad
TROUGH_FRICTION = (0.3, 0.15)                                          # along the trough 0.15 < tan 20 deg


def user_body_pose(surface):
    """(position, rotation matrix, local points, the surface) of the user's box resting on its 4
    bottom corners at the static penetration m g / (4 eps_N):
    "sphere": inside a spherical bowl (Sphere, side "inside", centre 1 m above the origin, its pole
    axis along y so the chart's poles are off the path) at 30 deg from the bottom in the xz-plane;
    "cone": at the bottom of a conical trough (Cone, side "inside", axis along x at 0.3 m height,
    half angle 20 deg: its bottom line descends along +x), face parallel to the bottom line and
    tilted about y so that the four corners press equally (the trough's sagitta differs front to
    back)."""
    from exu_aniso import Cone, Sphere
    h = c = 0.5 * USER_SIZE
    pen = USER_MASS * 9.81 / (4 * USER_NORMAL_STIFFNESS)
    local = np.array([[sx * h, sy * h, -c] for sx in (-1, 1) for sy in (-1, 1)])
    if surface == "sphere":
        R, al = BOWL_RADIUS, BOWL_START
        C = np.array([0.0, 0.0, R])
        n = np.array([math.sin(al), 0.0, -math.cos(al)])             # outward at the start
        d = math.sqrt((R + pen) ** 2 - 2 * h * h)                     # face centre from the centre
        return (C + (d - c) * n, RotationMatrixY(-al), local,
                Sphere(radius=R, center=C.tolist(), axis_direction=[0.0, 1.0, 0.0], side="inside"))
    if surface != "cone":
        raise ValueError(f"surface must be 'sphere' or 'cone'; got {surface!r}")
    R0, ha = TROUGH_RADIUS, TROUGH_HALF_ANGLE
    A0 = np.array([0.0, 0.0, R0])

    def pose(v):
        off, tilt = v
        A = np.asarray(RotationMatrixY(ha + tilt))
        return A @ np.array([0.0, 0.0, 1.0]) * off, A           # face centre at the origin (bottom line)

    def pens(v):
        x0, A = pose(v)
        X = x0 + local @ A.T
        rho = np.hypot(X[:, 1] - A0[1], X[:, 2] - A0[2])
        return (rho - (R0 + (X[:, 0] - A0[0]) * math.tan(ha))) * math.cos(ha)

    def res(v):
        P = pens(v)
        return np.array([np.mean(P) - pen, P[2] - P[0]])

    v = np.array([c, 0.0])
    for _ in range(10):                                              # Newton with a difference Jacobian
        r = res(v)
        J = np.column_stack([(res(v + e) - r) / 1e-8 for e in np.eye(2) * 1e-8])
        v = v - np.linalg.solve(J, r)
    x0, A = pose(v)
    return (x0, A, local, Cone(half_angle=ha, radius=R0, axis_point=A0.tolist(),
                               axis_direction=[1.0, 0.0, 0.0], side="inside"))


def BuildUserBody(surface, t_end, dt):
    """A user's model (module doc): mbs.CreateRigidBody, mbs.CreateAnisotropicContact on the Sphere
    or Cone with orthotropic adhesion and friction and otherwise the function's defaults, solved at
    RecommendedSimulationSettings. Returns dict(mbs, simulationSettings, solverType, contact, SC,
    oBody, sPosition)."""
    import exu_aniso
    from exu_aniso import Adhesion, Friction
    x0, A, local, surf = user_body_pose(surface)
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    a = USER_SIZE
    oBody = mbs.CreateRigidBody(inertia=InertiaCuboid(USER_MASS / a ** 3, [a] * 3),
                                referencePosition=list(x0), referenceRotationMatrix=np.asarray(A),
                                gravity=[0.0, 0.0, -9.81],
                                nodeType=exu.NodeType.RotationEulerParameters)
    mu = BOWL_FRICTION if surface == "sphere" else TROUGH_FRICTION
    contact = mbs.CreateAnisotropicContact(name=f"userBodyOn{type(surf).__name__}", bodyNumber=oBody,
                                           localPoints=local.tolist(), surface=surf,
                                           adhesion=Adhesion.orthotropic(*USER_ADHESION),
                                           friction=Friction.orthotropic(*mu),
                                           normalStiffness=USER_NORMAL_STIFFNESS)
    sPosition = mbs.AddSensor(SensorNode(nodeNumber=node_of(mbs, oBody), storeInternal=True,
                                         outputVariableType=exu.OutputVariableType.Position))
    mbs.Assemble()
    ss, solverType = exu_aniso.RecommendedSimulationSettings(t_end, dt)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=solverType, contact=contact, oBody=oBody,
                sPosition=sPosition)
