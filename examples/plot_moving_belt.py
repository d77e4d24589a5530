"""
Parts on a moving belt: a moving master
=======================================

Three cubes lie on a belt, a free rigid plate of 1e6 kg moving at 0.5 m/s along x, which carries
the contact surface (``masterBodyNumber``: the plate receives the reaction). Each cube is a contact
set of its own: a group (``bodyNumber`` a list of bodies, one compiled call for all) needs a fixed
surface. Friction is orthotropic on
the belt, mu 0.2 along x and 0.6 across: a sideways push of 0.5 N on each cube slides it across
the belt only while it also slides along; once a cube sticks to the belt it is carried at the
belt's speed, and the push (below the sticking limit across) no longer moves it sideways.
"""
import os

import exudyn as exu
import matplotlib.pyplot as plt
import numpy as np
from exudyn.itemInterface import SensorBody
from exudyn.utilities import InertiaCuboid

import exu_aniso
from exu_aniso import Adhesion, Friction, Plane

QUICK = os.environ.get("EXU_ANISO_QUICK") == "1"      # the test suite's short form
t_end, dt = (0.1, 1e-3) if QUICK else (1.5, 1e-3)
a, m, g = 0.1, 1.0, 9.81                              # cube edge [m], mass [kg], gravity [m/s^2]

SC = exu.SystemContainer()
mbs = SC.AddSystem()
belt = mbs.CreateRigidBody(inertia=InertiaCuboid(1e6 / (4.0 * 1.0 * 0.02), [4.0, 1.0, 0.02]),
                           referencePosition=[0.0, 0.0, -0.01], initialVelocity=[0.5, 0.0, 0.0],
                           nodeType=exu.NodeType.RotationRotationVector, gravity=[0.0, 0.0, 0.0])
cubes = []
for k, x in enumerate((-0.6, 0.0, 0.6)):
    o = mbs.CreateRigidBody(inertia=InertiaCuboid(m / a ** 3, [a, a, a]), referencePosition=[x, 0.0, 0.5 * a],
                            initialVelocity=[0.1 * k, 0.0, 0.0], nodeType=exu.NodeType.RotationRotationVector,
                            gravity=[0.0, 0.0, -g])
    mbs.CreateForce(itemNumber=o, loadVector=[0.0, 0.5, 0.0])
    cubes.append(o)
corners = [[sx * 0.5 * a, sy * 0.5 * a, -0.5 * a] for sx in (-1, 1) for sy in (-1, 1)]
for o in cubes:
    mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=corners, surface=Plane(), masterBodyNumber=belt,
                                 adhesion=Adhesion.orthotropic(2e4, 2e4), friction=Friction.orthotropic(0.2, 0.6),
                                 normalStiffness=2.5e5, normalDamping=100.0)
sensors = [mbs.AddSensor(SensorBody(bodyNumber=o, storeInternal=True, outputVariableType=exu.OutputVariableType.Velocity))
           for o in cubes]
mbs.Assemble()
settings, solver = exu_aniso.RecommendedSimulationSettings(t_end, dt)
mbs.SolveDynamic(settings, solverType=solver)

fig, (ax, ay) = plt.subplots(1, 2, figsize=(10, 4))
for k, s in enumerate(sensors):
    V = mbs.GetSensorStoredData(s)
    ax.plot(V[:, 0], V[:, 1], label=f"cube {k}")
    ay.plot(V[:, 0], V[:, 2], label=f"cube {k}")
ax.axhline(0.5, color="k", ls=":", lw=0.8, label="belt")
ax.set(xlabel="t [s]", ylabel="v_x [m/s]", title="carried along the belt")
ay.set(xlabel="t [s]", ylabel="v_y [m/s]", title="pushed across it (0.5 N each)")
for axis in (ax, ay):
    axis.grid(True, alpha=0.3)
    axis.legend(fontsize=8)
fig.tight_layout()
plt.show()
