"""
A mass point in a spherical bowl with orthotropic friction
==========================================================

A user's own Exudyn model with one call of ``mbs.CreateAnisotropicContact``: a 1 kg mass point
released on the wall of a spherical bowl (radius 0.5 m) with a sideways velocity. Friction and
adhesion follow the sphere's coordinate lines: along the parallels (``xi1``, the chart's longitude)
the friction coefficient is 0.05, along the meridians (``xi2``) 0.3. At the bottom the parallels
run along y and the meridians along x: the swing along x dies within the first loop, the swing
along y lasts. The chart's pole points along x, so the bowl's bottom lies on the
chart's equator, away from the poles where the chart is singular.

The settings are the package's recommendation for a contact model
(``exu_aniso.RecommendedSimulationSettings``). The energy the contact dissipated (its sensor
``sDissipation``) closes the ledger with the loss of kinetic and potential energy, but for what the
contact's springs store and its normal dashpot takes.
"""
import os

import exudyn as exu
import matplotlib.pyplot as plt
import numpy as np
from exudyn.itemInterface import MassPoint, NodePoint, SensorNode

import exu_aniso
from exu_aniso import Adhesion, Friction, Sphere

QUICK = os.environ.get("EXU_ANISO_QUICK") == "1"      # the test suite's short form
R, m, g = 0.5, 1.0, 9.81                              # bowl radius [m], mass [kg], gravity [m/s^2]
t_end, dt = (0.2, 1e-3) if QUICK else (4.0, 1e-3)

SC = exu.SystemContainer()
mbs = SC.AddSystem()
start = np.array([R * np.sin(0.6), 0.0, R - R * np.cos(0.6)])       # on the wall, 0.6 rad up
nPoint = mbs.AddNode(NodePoint(referenceCoordinates=list(start), initialVelocities=[0.0, 1.5, 0.0]))
oPoint = mbs.AddObject(MassPoint(nodeNumber=nPoint, mass=m))
mbs.CreateForce(itemNumber=oPoint, loadVector=[0.0, 0.0, -m * g])
bowl = Sphere(R, center=(0.0, 0.0, R), axis_direction=(1.0, 0.0, 0.0), side="inside")
contact = mbs.CreateAnisotropicContact(bodyNumber=oPoint, localPoints=[[0.0, 0.0, 0.0]], surface=bowl,
                                       adhesion=Adhesion.orthotropic(2e4, 2e4),
                                       friction=Friction.orthotropic(0.05, 0.3), normalStiffness=1e6,
                                       normalDamping=200.0)
sPos = mbs.AddSensor(SensorNode(nodeNumber=nPoint, storeInternal=True, outputVariableType=exu.OutputVariableType.Position))
sVel = mbs.AddSensor(SensorNode(nodeNumber=nPoint, storeInternal=True, outputVariableType=exu.OutputVariableType.Velocity))
mbs.Assemble()

settings, solver = exu_aniso.RecommendedSimulationSettings(t_end, dt)
mbs.SolveDynamic(settings, solverType=solver)

P, V = mbs.GetSensorStoredData(sPos), mbs.GetSensorStoredData(sVel)
D = mbs.GetSensorStoredData(contact["sDissipation"])
t = P[:, 0]
loss = (0.5 * m * np.sum(V[0, 1:] ** 2) + m * g * P[0, 3]) - (0.5 * m * np.sum(V[:, 1:] ** 2, axis=1) + m * g * P[:, 3])
print(f"kinetic + potential energy lost {loss[-1]:.4f} J, dissipated by the contact {D[-1, 1]:.4f} J: "
      f"lost - dissipated = {loss[-1] - D[-1, 1]:.2e} J")

fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4.2))
a.plot(P[:, 1], P[:, 2], lw=0.8)
a.plot(*start[:2], "o", color="C3", label="start")
a.set_aspect("equal")
a.set_xlabel("x [m]")
a.set_ylabel("y [m]")
a.set_title("path seen from above")
a.legend(fontsize=8)
b.plot(t, loss, label="kinetic + potential energy lost")
b.plot(t, D[:, 1], "--", label="dissipated by the contact (sDissipation)")
b.set_xlabel("t [s]")
b.set_ylabel("energy [J]")
b.set_title(f"ledger: lost - dissipated = {loss[-1] - D[-1, 1]:.2e} J at the end")
b.legend(fontsize=8)
fig.tight_layout()
plt.show()
