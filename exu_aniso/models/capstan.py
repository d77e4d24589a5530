"""Capstan: a rope over a drum, pulled until it slips (Euler-Eytelwein), as an Exudyn model.

The scene, its parameters, the slip-onset criterion and the energy ledger are described in
``exu_aniso.scenes.capstan`` (read its module docstring). Here:

* the rope: ``ObjectANCFCable2D`` elements on ``NodePoint2DSlope1`` nodes (x, y, x', y') in the plane
  z = 0, stress-free straight (a rope on the drum carries the bending moment EI / R), placed on the
  drum's circle (arc nodes with unit tangent slopes) and its two tangent tails;
* the drum: one ``mbs.CreateAnisotropicContact`` over the whole rope (``bodyNumber`` = the list of all
  elements, ``localPoints`` = ``points`` points per element) with ``Cylinder(radius,
  side="outside")`` fixed to ground;
* the ends: ``LoadForceVector`` on the end nodes along the tails' initial directions (away from the
  drum; magnitudes ``scenes.capstan.tension_in`` / ``tension_out`` of t), and a dashpot to ground at
  each end (``ObjectConnectorCartesianSpringDamper`` with zero stiffness);
* the run stops (pre-step function) once the in-end has moved ``stop_displacement`` towards the drum
  after t_load: the rope slips as a whole.

There is no reference-engine (numpy integrator) model of the rope: a documented decision; the
capstan's oracle is analytic (exp(mu_1 phi), tests/test_capstan.py).

Run ``python -m exu_aniso.models.capstan`` (or this file) for a plot of the default scene.
"""
from __future__ import annotations

import math

import exudyn as exu
import numpy as np
from exudyn.itemInterface import (LoadForceVector, MarkerBodyPosition, MarkerNodePosition, NodePoint2DSlope1,
                                  ObjectANCFCable2D, ObjectConnectorCartesianSpringDamper, ObjectGround,
                                  SensorBody, SensorNode, VObjectConnectorCartesianSpringDamper)

import exu_aniso  # noqa: F401  (binds mbs.CreateAnisotropicContact)
from exu_aniso.law.history import HISTORY_FIELDS
from exu_aniso.engines.energy import work_trapezoid
from exu_aniso.engines.exudyn_adapter.slaves import hermite_shape_functions
from exu_aniso.engines.exudyn_adapter.runner import HistoryOutputs, ModelScript, SimulationSettingsFor, SceneView
from exu_aniso.scenes.capstan import (SCENE, CapstanParams, capstan_contact_law, element_length, element_points,
                                     tension_in, tension_out)
from exu_aniso.util.validation import check_instance

_STATUS = HISTORY_FIELDS.index("status")
_NORMAL = HISTORY_FIELDS.index("normal")


def ArcLift(p):
    """Factor f >= 1 by which the rope's arc radius exceeds the drum's, so that no contact point of the
    cubic Hermite interpolant of the arc (which lies inside the circle between the nodes) starts
    inside the drum: the rope starts touching, unloaded (a start from a penetration would release
    penalty energy in a jolt: a 1.7 % ledger residual with 30 deg elements). 1 + 1.2e-5 for the default
    15 deg elements, 1 + 1.9e-4 for 30 deg."""
    dth = math.radians(p.wrap_angle) / p.elements
    L = dth                                                    # unit circle, unit-speed slopes
    r0, s0 = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    r1, s1 = np.array([math.cos(dth), math.sin(dth)]), np.array([-math.sin(dth), math.cos(dth)])
    r_min = min(np.linalg.norm(h[0] * r0 + h[1] * s0 + h[2] * r1 + h[3] * s1)
                for h in (hermite_shape_functions((i + 0.5) * L / p.points, L) for i in range(p.points)))
    return max(1.0, 1.0 / r_min)


def RopeGeometry(p):
    """Node positions (N, 2) and unit slopes (N, 2) of the rope, and the element lengths (N - 1,):
    in-tail, arc clockwise over the top of the drum (radius: the drum's times ``ArcLift``), out-tail.
    Also the in- and out-tail directions (unit, along the rope)."""
    R, phi = p.radius * ArcLift(p), math.radians(p.wrap_angle)
    th_a = 0.5 * math.pi + 0.5 * phi                       # start of the arc (left), clockwise to th_a - phi

    def on_arc(th):
        return np.array([R * math.cos(th), R * math.sin(th)]), np.array([math.sin(th), -math.cos(th)])

    pa, ta = on_arc(th_a)
    pb, tb = on_arc(th_a - phi)
    L_arc, L_tail = R * phi / p.elements, element_length(p)[1]
    pos, slope, lengths = [], [], []
    for i in range(p.tail_elements):                       # in-tail, towards the drum
        pos.append(pa - (p.tail_length - i * L_tail) * ta)
        slope.append(ta)
        lengths.append(L_tail)
    for i in range(p.elements + 1):
        x, t = on_arc(th_a - i * L_arc / R)
        pos.append(x)
        slope.append(t)
        if i < p.elements:
            lengths.append(L_arc)
    for i in range(1, p.tail_elements + 1):
        pos.append(pb + i * L_tail * tb)
        slope.append(tb)
        lengths.append(L_tail)
    return np.array(pos), np.array(slope), np.array(lengths), ta, tb


def BuildCapstan(p: CapstanParams, jacobian="analytic", implementation="auto", newtonTolerance=1e-8,
                 rhoInf=0.8, stop=True, show=True, newton="modified"):
    """Build the capstan scene; returns dict with SC, mbs, simulationSettings, solverType, params,
    nodes, elements, contact (dict of CreateAnisotropicContact), sensors (dict), directions (in, out:
    unit vectors of the end forces) and the loads.

    jacobian: contact Jacobian "analytic" | "numerical"; implementation: contact kernel "auto" |
    "compiled" | "numpy"; newtonTolerance: Newton relative and absolute tolerance (1e-8: the rope's
    residual has a round-off floor near 1e-9 with fine elements, where a tighter tolerance makes
    Newton fail and Exudyn cut the step again and again); rhoInf: spectral
    radius of generalized-alpha (solver="generalized_alpha"); newton: "modified" | "full"
    (exu_aniso.engines.exudyn_adapter.runner.SimulationSettingsFor); stop: stop the run at
    stop_displacement (pre-step function); show: renderer graphics of the drum and the contact points
    (mbs.CreateAnisotropicContact(show=...); drawn only when a scene is rendered)."""
    check_instance("p", p, CapstanParams)
    SC = SceneView(exu.SystemContainer())
    mbs = SC.AddSystem()
    pos, slope, lengths, ta, tb = RopeGeometry(p)
    nodes = [mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=[x[0], x[1], s[0], s[1]]))
             for x, s in zip(pos, slope)]
    elements = [mbs.AddObject(ObjectANCFCable2D(nodeNumbers=[nodes[i], nodes[i + 1]], length=float(L),
                                                massPerLength=p.mass_per_length, axialStiffness=p.axial_stiffness,
                                                bendingStiffness=p.bending_stiffness))
                for i, L in enumerate(lengths)]
    # the ends: force along the tail, away from the drum, and a dashpot to ground
    d_in, d_out = -ta, tb
    oGround = mbs.AddObject(ObjectGround())
    loads = []
    for node, d, magnitude in ((nodes[0], d_in, tension_in), (nodes[-1], d_out, tension_out)):
        mNode = mbs.AddMarker(MarkerNodePosition(nodeNumber=node))
        dd = np.array([d[0], d[1], 0.0])

        def UFload(mbs, t, loadVector, dd=dd, magnitude=magnitude):
            return (float(magnitude(p, t)) * dd).tolist()

        loads.append(mbs.AddLoad(LoadForceVector(markerNumber=mNode, loadVector=[0.0, 0.0, 0.0],
                                                 loadVectorUserFunction=UFload)))
        if p.end_damping > 0.0:
            x0 = mbs.GetNodeOutput(node, exu.OutputVariableType.Position, configuration=exu.ConfigurationType.Reference)
            mG = mbs.AddMarker(MarkerBodyPosition(bodyNumber=oGround, localPosition=list(x0)))
            mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[mG, mNode], stiffness=[0.0, 0.0, 0.0],
                                                               damping=[p.end_damping, p.end_damping, 0.0],
                                                               visualization=VObjectConnectorCartesianSpringDamper(
                                                                   show=False)))
    Lmin = float(lengths.min())
    L_arc = float(lengths[p.tail_elements])
    # contact points at (i + 1/2) / points of every element; arc and tail elements differ in length:
    # the points are given for the shortest, so the set takes one list of local x for all elements
    if not math.isclose(Lmin, L_arc) or not math.isclose(float(lengths.max()), L_arc):
        contacts = []
        for L in sorted(set(np.round(lengths, 15))):
            els = [e for e, Le in zip(elements, lengths) if abs(Le - L) < 1e-14]
            contacts.append(mbs.CreateAnisotropicContact(
                name=f"drum{len(contacts)}", bodyNumber=els,
                localPoints=element_points(p, L).tolist(),
                contactLaw=capstan_contact_law(p), jacobian=jacobian, implementation=implementation, show=show,
                storeHistory=True))
    else:
        contacts = [mbs.CreateAnisotropicContact(
            name="drum", bodyNumber=elements, localPoints=element_points(p, L_arc).tolist(),
            contactLaw=capstan_contact_law(p), jacobian=jacobian, implementation=implementation, show=show,
            storeHistory=True)]
    # no KineticEnergy sensor on the elements (RopeKineticEnergy): Exudyn's KineticEnergy output of an ANCF
    # cable allocates 4 arrays, a vector and a matrix per evaluation, i.e. per element and step, which made
    # the default run print Exudyn's 'large amount of memory allocations' warning; the PotentialEnergy
    # output allocates nothing in the solver
    sensors = dict(
        sCoordinates=[mbs.AddSensor(SensorNode(nodeNumber=n, storeInternal=True,
                                               outputVariableType=exu.OutputVariableType.Coordinates))
                      for n in nodes],
        sVelocities=[mbs.AddSensor(SensorNode(nodeNumber=n, storeInternal=True,
                                              outputVariableType=exu.OutputVariableType.Coordinates_t))
                     for n in nodes],
        sPotential=[mbs.AddSensor(SensorBody(bodyNumber=o, localPosition=[0.0, 0.0, 0.0], storeInternal=True,
                                             outputVariableType=exu.OutputVariableType.PotentialEnergy))
                    for o in elements])
    if stop:
        state = dict(u_load=None)

        def PreStep(mbs, t):
            """False (stop after this step) once the in-end has moved stop_displacement towards the drum
            since t_load."""
            # the in-end's coordinates read from a view of Exudyn's Current ODE2 vector (GetNodeOutput would
            # allocate an Exudyn vector per step)
            i = mbs.GetNodeODE2Index(nodes[0])
            q = mbs.systemData.GetODE2Coordinates(configuration=exu.ConfigurationType.Current, copy=False)
            u = float(np.dot(q[i:i + 2], -d_in))
            if t <= p.t_load:
                state["u_load"] = u
                return True
            return not (state["u_load"] is not None and u - state["u_load"] >= p.stop_displacement)

        mbs.SetPreStepUserFunction(PreStep)
    mbs.Assemble()
    ss, st = SimulationSettingsFor(p, rhoInf=rhoInf, newtonTolerance=newtonTolerance, newton=newton)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=st, params=p, nodes=nodes, elements=elements,
                contact=contacts[0], contacts=contacts, sensors=sensors, directions=(d_in, d_out), loads=loads)


def CapstanTrajectory(model):
    """Trajectory dict (scenes.capstan.COLUMNS without the ledger) and the per-sample arrays the ledger
    needs: node coordinates q (n, nodes*4), velocities (n, nodes*4), histories per contact set."""
    mbs, p, S = model["mbs"], model["params"], model["sensors"]
    Q = np.stack([mbs.GetSensorStoredData(s) for s in S["sCoordinates"]])       # (nodes, n, 5)
    V = np.stack([mbs.GetSensorStoredData(s) for s in S["sVelocities"]])
    t = Q[0, :, 0]
    n = len(t)
    q = Q[:, :, 1:].transpose(1, 0, 2).reshape(n, -1)
    qt = V[:, :, 1:].transpose(1, 0, 2).reshape(n, -1)
    d_in, d_out = model["directions"]
    u_in = -(Q[0, :, 1:3] @ d_in)                     # towards the drum (the in-force pulls along d_in)
    u_out = Q[-1, :, 1:3] @ d_out                     # away from the drum
    F_in, F_out = tension_in(p, t), tension_out(p, t)            # applied by the loading devices
    # tensions at the rope's ends: the applied force less the device's dashpot (c v along the force)
    T_in = F_in - p.end_damping * (V[0, :, 1:3] @ d_in)
    T_out = F_out - p.end_damping * (V[-1, :, 1:3] @ d_out)
    H = [HistoryOutputs(mbs, c)[2] for c in model["contacts"]]
    Hall = np.concatenate(H, axis=1)
    # points loaded now and in the sample before: a point that has just come into contact (the rope
    # moving onto the drum) starts sticking by definition and does not count
    loaded = Hall[:, :, _NORMAL] < 0.0
    loaded[1:] &= loaded[:-1]
    sliding = loaded & (Hall[:, :, _STATUS] == 2.0)
    n_loaded = loaded.sum(axis=1)
    traj = dict(t=t, force_in=F_in, force_out=F_out, tension_in=T_in, tension_out=T_out,
                tension_ratio=np.divide(T_out, T_in, out=np.ones(n), where=T_in > 0.0),
                u_in=u_in - u_in[0], u_out=u_out - u_out[0],
                slip_fraction=np.divide(sliding.sum(axis=1), n_loaded, out=np.zeros(n), where=n_loaded > 0),
                contact_fraction=n_loaded / Hall.shape[1],
                dissipated_energy=sum(HistoryOutputs(mbs, c)[0] for c in model["contacts"]))
    # the end nodes' positions and velocities in the plane (the ledger's work in and end dashpots)
    for end, i in (("in", 0), ("out", -1)):
        x0 = mbs.GetNodeOutput(model["nodes"][i], exu.OutputVariableType.Position,
                               configuration=exu.ConfigurationType.Reference)
        traj.update({f"x_{end}": x0[0] + Q[i, :, 1], f"y_{end}": x0[1] + Q[i, :, 2],
                     f"vx_{end}": V[i, :, 1], f"vy_{end}": V[i, :, 2]})
    # u_in from t_load on: the criterion's travel (the in-tail's stretch during loading excluded)
    k_load = int(np.searchsorted(t, p.t_load, side="right")) - 1
    traj["u_in"] = traj["u_in"] - np.where(t > p.t_load, traj["u_in"][k_load], traj["u_in"])
    return traj, q, qt, H


def RopeKineticEnergy(model, qt):
    """Kinetic energy of the rope [J] per sample: sum over the elements of 1/2 v^T M v, v the velocities
    of the element's two nodes (x, y, x', y' each; ``qt`` (n, nodes * 4) in the order of model["nodes"]),
    M = rhoA int_0^L S^T S dx its constant consistent mass matrix (S: the cubic Hermite shape functions,
    ``hermite_shape_functions``; 4-point Gauss-Legendre integrates the degree-6 integrand exactly).
    Exudyn's KineticEnergy output of ObjectANCFCable2D to round-off (tests/test_exudyn_warnings.py),
    without a sensor per element (see BuildCapstan)."""
    mbs = model["mbs"]
    order = [int(nd) for nd in model["nodes"]]
    xg, wg = np.polynomial.legendre.leggauss(4)
    kinetic = np.zeros(qt.shape[0])
    for e in model["elements"]:
        L = float(mbs.GetObjectParameter(e, "length"))
        M4 = np.zeros((4, 4))
        for x, w in zip(xg, wg):
            h = hermite_shape_functions(0.5 * L * (x + 1.0), L)
            M4 += 0.5 * L * w * np.outer(h, h)
        M = float(mbs.GetObjectParameter(e, "massPerLength")) * np.kron(M4, np.eye(2))
        cols = np.concatenate([order.index(int(nd)) * 4 + np.arange(4)
                               for nd in mbs.GetObject(e)["nodeNumbers"]])
        v = qt[:, cols]
        kinetic += 0.5 * np.einsum("ni,ij,nj->n", v, M, v)
    return kinetic


def CapstanLedgerInputs(model, traj, q, qt, H):
    """The inputs of the capstan's energy ledger (``scenes.capstan.capstan_energy``) from the solved
    model: the contact law, the contact points' positions and velocities X, V and their histories H
    (every set's, side by side), the rope's kinetic and strain energy, the end forces' work and the
    end dashpots' dissipation, per sample."""
    mbs, p, S = model["mbs"], model["params"], model["sensors"]
    d_in, d_out = model["directions"]
    kinetic = RopeKineticEnergy(model, qt)
    potential = sum(mbs.GetSensorStoredData(s)[:, 1] for s in S["sPotential"])
    nc = 4
    X_in, X_out = q[:, 0:2], q[:, -nc:-nc + 2]
    V_in, V_out = qt[:, 0:2], qt[:, -nc:-nc + 2]
    work = (work_trapezoid(traj["force_in"][:, None] * d_in[None, :], X_in)
            + work_trapezoid(traj["force_out"][:, None] * d_out[None, :], X_out))
    end_diss = p.end_damping * (work_trapezoid(V_in, X_in) + work_trapezoid(V_out, X_out))
    # contact points of every set per sample (the sets' constant point Jacobians: x = c + Jp q_total)
    Xs, Vs = [], []
    for c in model["contacts"]:
        cs = _contact_set(mbs, c)
        Jp, c0 = cs.slave.jacobian_matrix(cs.points)
        # the set's coordinates are the distinct nodes of its elements, in its own order
        order = [int(nd) for nd in model["nodes"]]
        cols = np.concatenate([order.index(nd) * nc + np.arange(nc) for nd in cs.slave.nodes])
        Xs.append(c0[None] + np.einsum("kij,nj->nki", Jp, cs.slave.ref[None] + q[:, cols]))
        Vs.append(np.einsum("kij,nj->nki", Jp, qt[:, cols]))
    return dict(law=model["contact"]["law"], X=np.concatenate(Xs, axis=1), V=np.concatenate(Vs, axis=1),
                H=np.concatenate(H, axis=1), kinetic=kinetic, potential=potential, work_in=work,
                end_dissipation=end_diss)


def _contact_set(mbs, contact):
    for cs in mbs.variables["exu_aniso_contact_sets"]:
        if cs.nData == contact["nData"]:
            return cs
    raise KeyError("contact set not found")


def ReadCapstan(model, complete):
    """What ``ModelScript.run`` reads from a solved BuildCapstan model: the trajectory, the summary's
    inputs (none) and, for a completed run, the ledger's (``CapstanLedgerInputs``)."""
    traj, q, qt, H = CapstanTrajectory(model)
    return traj, {}, CapstanLedgerInputs(model, traj, q, qt, H) if complete else None


MODEL = ModelScript(SCENE, BuildCapstan, ReadCapstan, contacts=lambda model: model["contacts"],
                    info=lambda model: dict(elements=len(model["elements"])))

RunCapstan = MODEL.run
"""Build (``BuildCapstan(p, **options)``) and solve the capstan scene: ``ModelScript.run``, which returns
an ``exu_aniso.engines.result.Result`` with ``scenes.capstan.COLUMNS``, the summary
(``scenes.capstan.capstan_summary``) and the energy ledger."""


if __name__ == "__main__":
    MODEL.show()
