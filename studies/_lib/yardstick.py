"""The yardstick of the speed targets (``targets``), a model with no Python in it.

The yardstick (``BuildCube``): a free rigid cube (``NodeRigidBodyEP``, the block's mass and size) on
K ``ObjectConnectorCartesianSpringDamper``s to ground at K points of its bottom face, as many springs
as the scene has contact points, under gravity and a constant C++ force in the plane, at Exudyn's
default settings (a fresh ``exu.SimulationSettings()``: Exudyn's modified Newton and tolerances,
generalized-alpha) with the scene's step and end time. It is linear: what a C++ connector costs.
For the 64 cubes the yardstick is 64 such cubes, each on its own 4 springs
(``scale.BuildCubes(64, "springs")``, Exudyn's sparse solver)."""
from __future__ import annotations

import math

import exudyn as exu
import numpy as np
from exudyn.itemInterface import SensorNode
from exudyn.utilities import InertiaCuboid

from exu_aniso.scenes.block import BlockParams

from .baseline import _cartesian_springs, exudyn_defaults


def cube_points(K, size):
    """K points of the cube's bottom face: the first K of an n x n grid, n = ceil(sqrt(K))."""
    n = max(2, math.ceil(math.sqrt(K)))
    s = np.linspace(-0.5 * size, 0.5 * size, n)
    X, Y = np.meshgrid(s, s, indexing="xy")
    xy = np.stack([X.ravel(), Y.ravel()], axis=-1)[:K]
    return np.column_stack([xy, np.full(K, -0.5 * size)])


def BuildCube(K, t_end, dt, p=None, extra=None):
    """The yardstick (module doc): returns dict(mbs, simulationSettings, solverType, SC, oCube).
    extra(mbs, oCube): adds items before Assemble (the floors)."""
    p = p or BlockParams(model="full")
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    a = p.size
    gap = -p.normal_load / p.eps_n
    oCube = mbs.CreateRigidBody(inertia=InertiaCuboid(density=p.mass / a ** 3, sideLengths=[a, a, a]),
                                referencePosition=[p.x0, p.y0, 0.5 * a + gap], gravity=[0.0, 0.0, -9.81],
                                nodeType=exu.NodeType.RotationEulerParameters)
    mbs.CreateForce(itemNumber=oCube, loadVector=[p.force, 0.5 * p.force, -p.normal_load])
    local = cube_points(K, a)
    anchors = np.column_stack([local[:, 0] + p.x0, local[:, 1] + p.y0, np.zeros(K)])
    _cartesian_springs(mbs, oCube, local, anchors, [[p.eps_1 / K, p.eps_1 / K, p.eps_n / K]] * K)
    mbs.AddSensor(SensorNode(nodeNumber=mbs.GetObject(oCube)["nodeNumber"], storeInternal=True,
                             outputVariableType=exu.OutputVariableType.Position))
    if extra is not None:
        extra(mbs, oCube)
    mbs.Assemble()
    return dict(SC=SC, mbs=mbs, simulationSettings=exudyn_defaults(t_end, dt), oCube=oCube,
                solverType=exu.DynamicSolverType.GeneralizedAlpha)
