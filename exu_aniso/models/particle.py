"""A mass point on a surface of the protocol as an Exudyn model (the particle scene).

The scene (surface, gravity, initial state, oracle cases) is ``exu_aniso.scenes.particle`` (read its
module docstring); the point is ``mbs.CreateMassPoint`` (``NodePoint``, 3 coordinates) with gravity
as its body load, and the contact one ``mbs.CreateAnisotropicContact`` call with the scene's
ContactLaw at the local point [0, 0, 0]. ``RunParticle`` returns the same ``Result`` as
``exu_aniso.scenes.particle.simulate_particle`` (trajectory keys, summary, energy ledger), so the two
engines compare field by field.

Run ``python -m exu_aniso.models.particle`` (or this file) for a plot of the default scene
(a point sliding off a rough sphere).
"""
from __future__ import annotations

import exudyn as exu

from exudyn import graphics
from exudyn.itemInterface import SensorNode

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.engines.exudyn_adapter.runner import HistoryOutputs, ModelScript, SimulationSettingsFor, SceneView
from exu_aniso.scenes.particle import (SCENE, ParticleParams, finish_trajectory, gravity_vector, initial_state,
                                      particle_contact_law)
from exu_aniso.util.validation import check_instance


def BuildParticle(p: ParticleParams, jacobian="analytic", solverType=None, rhoInf=0.8, newtonTolerance=1e-10,
                  implementation="auto", contactLaw=None, show=True, newton="modified"):
    """Build the particle scene; returns dict with SC, mbs, simulationSettings, solverType, params,
    oPoint, nPoint, contact (dict of CreateAnisotropicContact) and sensors (dict: sPosition, sVelocity).

    jacobian: "analytic" | "numerical" (contact Jacobian); implementation: contact kernel "auto" |
    "compiled" | "numpy"; solverType: an exu.DynamicSolverType overriding p.solver; rhoInf:
    spectral radius of generalized-alpha; newtonTolerance: Newton relative and absolute tolerance;
    newton: "modified" | "full" (exu_aniso.engines.exudyn_adapter.runner.SimulationSettingsFor);
    contactLaw: a ContactLaw replacing the scene's (e.g. on a surface of one's own); show: draw the
    surface and the contact point in the renderer."""
    check_instance("p", p, ParticleParams)
    law = particle_contact_law(p) if contactLaw is None else contactLaw
    SC = SceneView(exu.SystemContainer())
    mbs = SC.AddSystem()
    x0, v0 = initial_state(p)
    r = 0.02 * p.radius
    oPoint = mbs.CreateMassPoint(referencePosition=x0.tolist(), initialVelocity=v0.tolist(), mass=p.mass,
                                 gravity=gravity_vector(p).tolist(),
                                 graphicsDataList=[graphics.Sphere(radius=r, color=graphics.color.red, nTiles=12)])
    nPoint = mbs.GetObject(oPoint)["nodeNumber"]
    contact = mbs.CreateAnisotropicContact(name="particleContact", bodyNumber=oPoint, localPoints=[[0.0, 0.0, 0.0]],
                                           contactLaw=law, jacobian=jacobian, initializeHistory=True,
                                           implementation=implementation, show=show, storeHistory=True)
    sensors = {name: mbs.AddSensor(SensorNode(nodeNumber=nPoint, storeInternal=True,
                                              outputVariableType=getattr(exu.OutputVariableType, ovt)))
               for name, ovt in (("sPosition", "Position"), ("sVelocity", "Velocity"))}
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, rhoInf=rhoInf, newtonTolerance=newtonTolerance, solverType=solverType,
                                   newton=newton)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, oPoint=oPoint, nPoint=nPoint,
                contact=contact, sensors=sensors)


def ParticleTrajectory(model):
    """Trajectory dict (reference keys) from the stored sensors of a solved BuildParticle model, and
    the contact's history H."""
    mbs, S = model["mbs"], model["sensors"]
    P = mbs.GetSensorStoredData(S["sPosition"])
    V = mbs.GetSensorStoredData(S["sVelocity"])
    diss, slip, H = HistoryOutputs(mbs, model["contact"])
    traj = dict(t=P[:, 0], x=P[:, 1], y=P[:, 2], z=P[:, 3], vx=V[:, 1], vy=V[:, 2], vz=V[:, 3],
                dissipated_energy=diss, slip_distance=slip)
    return finish_trajectory(traj, model["contact"]["law"], H), H


def ReadParticle(model, complete):
    """What ``ModelScript.run`` reads from a solved BuildParticle model: the trajectory, the summary's
    inputs (none) and the ledger's (the contact law and its history)."""
    traj, H = ParticleTrajectory(model)
    return traj, {}, dict(law=model["contact"]["law"], H=H)


MODEL = ModelScript(SCENE, BuildParticle, ReadParticle)

RunParticle = MODEL.run
"""Build (``BuildParticle(p, **options)``) and solve the particle scene: ``ModelScript.run``, which
returns an ``exu_aniso.engines.result.Result`` with the reference's trajectory keys, the summary
(``scenes.particle.particle_summary``) and the energy ledger."""


if __name__ == "__main__":
    MODEL.show()
