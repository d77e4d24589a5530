"""Bad input everywhere a user can pass it: every case must raise ValueError/TypeError whose message
names the parameter, the rule and what came in (the expected words of each row); the command line
must exit with code 2, print that message without a traceback and write nothing in --out.

Table rows: (callable, kwargs, words). A row fails if the call succeeds, raises anything else, or
the message lacks one of the words (case-sensitive substrings)."""
import math
import os
import subprocess
import sys

import exudyn as exu
import numpy as np
import pytest
from exudyn.utilities import InertiaCuboid

from exu_aniso import Adhesion, ContactLaw, Friction, return_map_batch, return_map_point
from exu_aniso.geometry import Cylinder, Plane
from exu_aniso.cli import main
from exu_aniso.engines.exudyn_adapter.create_contact import CreateAnisotropicContact
from exu_aniso.models.block import BuildBlock, RunBlock
from exu_aniso.models.screw import BuildScrew, RunScrew
from exu_aniso.scenes.block import simulate_block
from exu_aniso.scenes.screw import simulate_screw
from exu_aniso.scenes.block import BlockParams
from exu_aniso.scenes.screw import ScrewParams
from _suite import HANG_S

NAN, INF = float("nan"), float("inf")
B_OK, F_OK = (-1e3, 0.0, -2e3), (11.0, 0.0, 4.0)   # valid law inputs (B negative, F positive definite)


def law(**kw):
    a = dict(surface=Plane(), adhesion=Adhesion.isotropic(1e3), friction=Friction.isotropic(0.3),
             normal_stiffness=1e5)
    a.update(kw)
    return ContactLaw(**a)


def evaluate(**kw):
    a = dict(x=[[0.1, 0.2, -1e-4]])
    a.update(kw)
    return law().evaluate(**a)


def point(**kw):
    a = dict(T_tr=(3.0, 1.0), N_abs=1.0, B=B_OK, F=F_OK)
    a.update(kw)
    return return_map_point(**a)


def batch(**kw):
    a = dict(T_tr=np.ones((3, 2)), N_abs=np.ones(3), B=np.tile(B_OK, (3, 1)), F=np.tile(F_OK, (3, 1)))
    a.update(kw)
    return return_map_batch(**a)


def short_block(**kw):
    return BlockParams(t_end=0.01, dt=1e-3, **kw)


def contact(**kw):
    """CreateAnisotropicContact on a fresh mbs with one rigid body; kw override the valid arguments."""
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    body = mbs.CreateRigidBody(inertia=InertiaCuboid(1000.0, [0.1] * 3), referencePosition=[0.5, 0, 0.05])
    a = dict(mbs=mbs, bodyNumber=body, localPoints=[[0.0, 0.0, -0.05]], surface=Plane(),
             adhesion=Adhesion.isotropic(1e3), friction=Friction.isotropic(0.3), normalStiffness=1e5)
    if kw.get("contactLaw") is not None:
        a.update(surface=None, adhesion=None, friction=None, normalStiffness=None)
    a.update(kw)
    return CreateAnisotropicContact(**a)


CASES = [
    # --- surfaces
    (Plane, dict(coordinates="spherical"), ("coordinates", "'cartesian' or 'polar'", "'spherical'")),
    (Plane, dict(coordinates=None), ("coordinates", "'cartesian' or 'polar'", "None")),
    (Cylinder, dict(radius="1"), ("radius", "real number", "'1'")),
    (Cylinder, dict(radius=None), ("radius", "real number", "None")),
    (Cylinder, dict(radius=[1.0]), ("radius", "real number", "[1.0]")),
    (Cylinder, dict(radius=0.0), ("radius", "> 0", "0.0")),
    (Cylinder, dict(radius=-2.0), ("radius", "> 0", "-2.0")),
    (Cylinder, dict(radius=INF), ("radius", "finite", "inf")),
    (Cylinder, dict(radius=1.0, axis_point=(0.0, 0.0)), ("axis_point", "shape (3,)", "(2,)")),
    (Cylinder, dict(radius=1.0, axis_point=(NAN, 0, 0)), ("axis_point", "finite", "nan")),
    (Cylinder, dict(radius=1.0, axis_direction=(0, 0, 0)), ("axis_direction", "non-zero", "[0.0, 0.0, 0.0]")),
    (Cylinder, dict(radius=1.0, side="top"), ("side", "'inside'", "'top'")),
    # --- tensor fields
    (Adhesion.isotropic, dict(stiffness=-1.0), ("stiffness", "> 0", "-1.0")),
    (Adhesion.isotropic, dict(stiffness=0), ("stiffness", "> 0", "0")),
    (Adhesion.isotropic, dict(stiffness="1e3"), ("stiffness", "real number", "'1e3'")),
    (Adhesion.isotropic, dict(stiffness=None), ("stiffness", "real number", "None")),
    (Adhesion.isotropic, dict(stiffness=[1e3]), ("stiffness", "real number", "[1000.0]")),
    (Adhesion.isotropic, dict(stiffness=True), ("stiffness", "real number", "True")),
    (Adhesion.orthotropic, dict(eps_1=1.0, eps_2=INF), ("eps_2", "finite", "inf")),
    (Adhesion.orthotropic, dict(eps_1=1.0, eps_2=2.0, angle=NAN), ("angle", "finite", "nan")),
    (Adhesion.polar, dict(eps_r=1.0, eps_phi=-1.0), ("eps_phi", "> 0", "-1.0")),
    (Adhesion.polar, dict(eps_r=1.0, eps_phi=1.0, core_radius=-1e-3), ("core_radius", ">= 0", "-0.001")),
    (Adhesion.spiral, dict(eps_1=1.0, eps_2=2.0, helix_angle=math.pi / 2), ("helix_angle", "(-pi/2, pi/2)", "1.57")),
    (Adhesion.spiral, dict(eps_1=1.0, eps_2=2.0, helix_angle=None), ("helix_angle", "exactly one of", "None")),
    (Adhesion.spiral, dict(eps_1=1.0, eps_2=2.0, lead=float("nan")), ("lead", "finite", "nan")),
    (Adhesion.from_matrix, dict(B=[[-2.0, 0.5], [0.4, -1.0]]), ("B", "symmetric", "0.4")),
    (Adhesion.from_matrix, dict(B=[[-2.0, 0.0], [0.0, 1.0]]), ("B", "negative definite", "1.0")),
    (Adhesion.from_matrix, dict(B=[[2.0, 0.0], [0.0, 1.0]]), ("B", "negative definite", "2.0")),
    (Adhesion.from_matrix, dict(B=[[-1.0, 0.0], [0.0, 0.0]]), ("B", "negative definite", "0.0")),
    (Adhesion.from_matrix, dict(B=np.eye(3)), ("B", "2x2", "(3, 3)")),
    (Adhesion.from_matrix, dict(B="abc"), ("B", "2x2 matrix of real numbers", "'abc'")),
    (Adhesion.from_matrix, dict(B=[[-INF, 0.0], [0.0, -1.0]]), ("B", "finite", "inf")),
    (Friction.from_matrix, dict(F=[[1.0, 2.0], [2.0, 1.0]]), ("F", "positive definite", "2.0")),
    (Friction.from_matrix, dict(F=[[1.0, NAN], [0.0, 1.0]]), ("F", "finite", "nan")),
    (Friction.isotropic, dict(mu=-0.3), ("mu", "> 0", "-0.3")),
    (Friction.isotropic, dict(mu=NAN), ("mu", "finite", "nan")),
    (Friction.isotropic, dict(mu="0.3"), ("mu", "real number", "'0.3'")),
    (Friction.orthotropic, dict(mu_1=0.2, mu_2=0.0), ("mu_2", "> 0", "0.0")),
    (Friction.polar, dict(mu_r=0.2, mu_phi=0.3, core_radius=INF), ("core_radius", "finite", "inf")),
    (Friction.spiral, dict(mu_1=0.2, mu_2=0.3, helix_angle=2.0), ("helix_angle", "(-pi/2, pi/2)", "2.0")),
    # --- contact law and its evaluation
    (law, dict(surface=None), ("surface", "a surface of exu_aniso", "None")),
    (law, dict(adhesion=Friction.isotropic(0.3)), ("adhesion", "Adhesion field", "Friction.isotropic")),
    (law, dict(friction="iso"), ("friction", "Friction field", "'iso'")),
    (law, dict(friction=Friction.spiral(0.1, 0.2, 0.1)), ("spiral", "needs a Cylinder or a Cone", "Plane")),
    (law, dict(friction=Friction.spiral(0.1, 0.2, lead=0.1)), ("spiral", "needs an angle as the first", "Plane")),
    (law, dict(adhesion=Adhesion.polar(1.0, 2.0), surface=Cylinder(1.0)), ("polar", "Plane only", "Cylinder")),
    (law, dict(normal_stiffness=0.0), ("normal_stiffness", "> 0", "0.0")),
    (law, dict(normal_stiffness=-1e5), ("normal_stiffness", "> 0", "-100000.0")),
    (law, dict(normal_stiffness="1e5"), ("normal_stiffness", "real number", "'1e5'")),
    (law, dict(normal_stiffness=None), ("normal_stiffness", "real number", "None")),
    (law, dict(normal_damping=-1.0), ("normal_damping", ">= 0", "-1.0")),
    (law, dict(return_map="closest"), ("return_map", "'seed', 'exact', 'radial'", "'closest'")),
    (law, dict(return_map=None), ("return_map", "'seed', 'exact', 'radial'", "None")),
    (law, dict(surface="plane"), ("surface", "surface of exu_aniso", "'plane'")),
    (evaluate, dict(x=[[0.0, 0.0]]), ("x", "(K, 3)", "(1, 2)")),
    (evaluate, dict(x=[[NAN, 0.0, -1.0]]), ("x", "finite", "non-finite")),
    (evaluate, dict(v=[1.0, 2.0]), ("v", "shape (1, 3)", "(2,)")),
    (evaluate, dict(v=[[INF, 0.0, 0.0]]), ("v", "finite", "[[0, 0]]")),
    (evaluate, dict(history=np.zeros(5)), ("history", "shape (1, 9)", "(5,)")),
    (evaluate, dict(history=np.full(9, NAN)), ("history", "finite", "non-finite")),
    # --- return maps
    (point, dict(T_tr=(NAN, 0.0)), ("T_tr", "finite", "nan")),
    (point, dict(T_tr=(INF, 0.0)), ("T_tr", "finite", "inf")),
    (point, dict(T_tr=(1.0, 2.0, 3.0)), ("T_tr", "shape (2,)", "(3,)")),
    (point, dict(T_tr="ab"), ("T_tr", "2 real numbers", "'ab'")),
    (point, dict(N_abs=-1.0), ("N_abs", ">= 0", "-1.0")),
    (point, dict(N_abs=NAN), ("N_abs", "finite", "nan")),
    (point, dict(N_abs=INF), ("N_abs", "finite", "inf")),
    (point, dict(N_abs=None), ("N_abs", "real number", "None")),
    (point, dict(B=(1.0, 0.0, 1.0)), ("B", "negative definite", "[1.0, 0.0, 1.0]")),
    (point, dict(B=(-1.0, 2.0, -1.0)), ("B", "negative definite", "[-1.0, 2.0, -1.0]")),
    (point, dict(B=(-1.0, 0.0)), ("B", "shape (3,)", "(2,)")),
    (point, dict(F=(1.0, 2.0, 1.0)), ("F", "positive definite", "[1.0, 2.0, 1.0]")),
    (point, dict(F=(-1.0, 0.0, -1.0)), ("F", "positive definite", "[-1.0, 0.0, -1.0]")),
    (point, dict(F=(1.0, NAN, 1.0)), ("F", "finite", "[[1]]")),
    (point, dict(method="closest"), ("method", "'seed', 'exact', 'radial'", "'closest'")),
    (point, dict(T_tr=(0.0, 0.0), method="closest"), ("method", "'seed', 'exact', 'radial'", "'closest'")),
    (batch, dict(T_tr=np.ones((3, 3))), ("T_tr", "(K, 2)", "(3, 3)")),
    (batch, dict(N_abs=np.ones(2)), ("N_abs", "(3,)", "(2,)")),
    (batch, dict(N_abs=-np.ones(3)), ("N_abs", ">= 0", "-1.0")),
    (batch, dict(B=np.tile(B_OK, (2, 1))), ("B", "(3, 3)", "(2, 3)")),
    (batch, dict(B=np.tile((1.0, 0.0, 1.0), (3, 1))), ("B", "negative definite", "[1.0, 0.0, 1.0]")),
    (batch, dict(F=np.tile((1.0, 5.0, 1.0), (3, 1))), ("F", "positive definite", "[1.0, 5.0, 1.0]")),
    (batch, dict(T_tr=np.full((3, 2), NAN)), ("T_tr", "finite", "non-finite")),
    (batch, dict(method="x"), ("method", "'seed', 'exact', 'radial'", "'x'")),
    # --- scene parameter sets (constructor, with_overrides, from_strings)
    (BlockParams, dict(mass="abc"), ("mass", "number", "'abc'")),
    (BlockParams, dict(mass=None), ("mass", "number", "None")),
    (BlockParams, dict(mass=[1.0]), ("mass", "number", "[1.0]")),
    (BlockParams, dict(mass=NAN), ("mass", "finite", "nan")),
    (BlockParams, dict(mass=-1.0), ("mass", "> 0", "-1.0")),
    (BlockParams, dict(eps_n=0.0), ("eps_n", "> 0", "0.0")),
    (BlockParams, dict(eps_1=-1e5), ("eps_1", "> 0", "-100000.0")),
    (BlockParams, dict(mu_1=-0.3), ("mu_1", "> 0", "-0.3")),
    (BlockParams, dict(mu_2=0), ("mu_2", "> 0", "0")),
    (BlockParams, dict(normal_load=-9.81), ("normal_load", ">= 0", "-9.81")),
    (BlockParams, dict(core_radius=-1.0), ("core_radius", ">= 0", "-1.0")),
    (BlockParams, dict(t_end=0.0), ("t_end", "> 0", "0.0")),
    (BlockParams, dict(t_end=-1.0), ("t_end", "> 0", "-1.0")),
    (BlockParams, dict(dt=0.0), ("dt", "> 0", "0.0")),
    (BlockParams, dict(dt=-1e-3), ("dt", "> 0", "-0.001")),
    (BlockParams, dict(dt=3.0, t_end=2.0), ("dt", "<= t_end", "3.0")),
    (BlockParams, dict(drive="pull"), ("drive", "'force', 'displacement'", "'pull'")),
    (BlockParams, dict(model="3d"), ("model", "'planar', 'full'", "'3d'")),
    (BlockParams, dict(solver="rk4"), ("solver", "'trapezoidal', 'generalized_alpha'", "'rk4'")),
    (BlockParams, dict(return_map="closest"), ("return_map", "'seed', 'exact', 'radial'", "'closest'")),
    (BlockParams, dict(adhesion="spiral"), ("adhesion", "'isotropic', 'orthotropic', 'polar'", "'spiral'")),
    (BlockParams, dict(points="grid:1"), ("points", "grid:N", "'grid:1'")),
    (BlockParams, dict(points=4), ("points", "grid:N", "4")),
    (BlockParams, dict(nonsense=1.0), ("nonsense",)),
    (BlockParams().with_overrides, dict(nonsense=1.0), ("unknown parameter", "nonsense", "valid names")),
    (BlockParams().with_overrides, dict(mass=-1.0), ("mass", "> 0", "-1.0")),
    (BlockParams().with_overrides, dict(dt="1e-3*1e4"), ("dt", "<= t_end", "10.0")),
    (BlockParams.from_strings, dict(values={"nonsense": "1"}), ("unknown parameter", "nonsense", "valid names")),
    (BlockParams.from_strings, dict(values={"mass": "abc"}), ("mass", "number", "'abc'")),
    (BlockParams.from_strings, dict(values={"mass": ""}), ("mass", "number", "''")),
    (BlockParams.from_strings, dict(values={"mass": "1e999"}), ("mass", "finite", "'1e999'")),
    (BlockParams.from_strings, dict(values={"mass": "9**9**9"}), ("mass", "number", "'9**9**9'")),
    (BlockParams.from_strings, dict(values={"drive_angle": "inf"}), ("drive_angle", "finite", "'inf'")),
    (BlockParams.from_strings, dict(values="mass=1"), ("values", "mapping", "'mass=1'")),
    (BlockParams.from_strings, dict(values=None), ("values", "mapping", "None")),
    (ScrewParams, dict(rings=2.5), ("rings", "integer", "2.5")),
    (ScrewParams, dict(rings=0), ("rings", "integer >= 1", "0")),
    (ScrewParams, dict(rings=True), ("rings", "number", "True")),
    (ScrewParams, dict(points_per_ring=-1), ("points_per_ring", "integer >= 1", "-1")),
    (ScrewParams, dict(model="full", points_per_ring=2), ("points_per_ring", ">= 3", "2")),
    (ScrewParams, dict(helix_angle=90.0), ("helix_angle", "(-90, 90)", "90.0")),
    (ScrewParams, dict(interference=-1e-5), ("interference", ">= 0", "-1e-05")),
    (ScrewParams, dict(adhesion="polar"), ("adhesion", "'isotropic', 'spiral'", "'polar'")),
    (ScrewParams, dict(drive="push"), ("drive", "'torque', 'rotation', 'axial'", "'push'")),
    (ScrewParams, dict(model="6dof"), ("model", "'reduced', 'full'", "'6dof'")),
    (ScrewParams, dict(t_end=0.01, dt=0.02), ("dt", "<= t_end", "0.02")),
    (ScrewParams.from_strings, dict(values={"rings": "2.5"}), ("rings", "integer", "'2.5'")),
    (ScrewParams.from_strings, dict(values={"radius": "-0.005"}), ("radius", "> 0", "'-0.005'")),
    (ScrewParams().with_overrides, dict(solver="euler"), ("solver", "'trapezoidal', 'generalized_alpha'", "'euler'")),
    # --- reference engine options
    (simulate_block, dict(params="block"), ("params", "BlockParams", "str")),
    (simulate_block, dict(params=ScrewParams()), ("params", "BlockParams", "ScrewParams")),
    (simulate_screw, dict(params=BlockParams()), ("params", "ScrewParams", "BlockParams")),
    (simulate_block, dict(params=short_block(), nonsense=1), ("unknown option", "nonsense", "valid options")),
    (simulate_screw, dict(params=ScrewParams(t_end=0.01), law=None), ("unknown option", "law", "valid options")),
    (simulate_block, dict(params=short_block(), jacobian="exact"), ("jacobian", "'analytic' or 'numerical'", "'exact'")),
    (simulate_block, dict(params=short_block(solver="generalized_alpha"), rho_inf=2.0), ("rho_inf", "[0.0, 1.0]", "2.0")),
    (simulate_block, dict(params=short_block(solver="generalized_alpha"), rho_inf="a"), ("rho_inf", "real number", "'a'")),
    (simulate_block, dict(params=short_block(), newton_tol=-1.0), ("newton_tol", "> 0", "-1.0")),
    (simulate_block, dict(params=short_block(), newton_tol=NAN), ("newton_tol", "finite", "nan")),
    (simulate_block, dict(params=short_block(), max_newton=0), ("max_newton", "integer >= 1", "0")),
    (simulate_block, dict(params=short_block(), max_newton=2.5), ("max_newton", "integer", "2.5")),
    (simulate_block, dict(params=short_block(), max_halvings=-1), ("max_halvings", "integer >= 0", "-1")),
    (simulate_block, dict(params=short_block(), law="polar"), ("law", "ContactLaw", "'polar'")),
    (simulate_block, dict(params=short_block(), reject_steps=5), ("reject_steps", "sequence", "5")),
    (simulate_block, dict(params=short_block(), split_steps=[1.5]), ("split_steps entry", "integer", "1.5")),
    (simulate_block, dict(params=short_block(), nonsmooth_accept="yes"), ("nonsmooth_accept", "True or False", "'yes'")),
    # --- Exudyn models
    (RunBlock, dict(p="block"), ("p", "BlockParams", "'block'")),
    (BuildBlock, dict(p=None), ("p", "BlockParams", "None")),
    (RunBlock, dict(p=ScrewParams()), ("p", "BlockParams", "ScrewParams")),
    (RunBlock, dict(p=short_block(), nonsense=1), ("nonsense",)),
    (RunBlock, dict(p=short_block(), jacobian="exact"), ("jacobian", "'analytic' or 'numerical'", "'exact'")),
    (RunBlock, dict(p=short_block(model="full"), nodeType="quaternion"), ("nodeType", "'RotVecLG', 'EP'", "'quaternion'")),
    (RunBlock, dict(p=short_block(), solverType="RK44"), ("solverType", "DynamicSolverType", "'RK44'")),
    (RunBlock, dict(p=short_block(solver="generalized_alpha"), rhoInf=2.0), ("rhoInf", "[0.0, 1.0]", "2.0")),
    (RunBlock, dict(p=short_block(), rhoInf="a"), ("rhoInf", "real number", "'a'")),
    (RunBlock, dict(p=short_block(), newtonTolerance=-1.0), ("newtonTolerance", "> 0", "-1.0")),
    (RunBlock, dict(p=short_block(), newtonTolerance=NAN), ("newtonTolerance", "finite", "nan")),
    (RunScrew, dict(p="screw"), ("p", "ScrewParams", "'screw'")),
    (BuildScrew, dict(p=BlockParams()), ("p", "ScrewParams", "BlockParams")),
    (RunScrew, dict(p=ScrewParams(t_end=0.01), contactOutputs="no"), ("contactOutputs", "True or False", "'no'")),
    (BuildScrew, dict(p=ScrewParams(model="full"), nodeType="x"), ("nodeType", "'RotVecLG', 'EP'", "'x'")),
    # --- CreateAnisotropicContact
    (contact, dict(mbs=None), ("mbs", "MainSystem", "None")),
    (contact, dict(bodyNumber="b"), ("bodyNumber", "object number", "'b'")),
    (contact, dict(bodyNumber=None), ("bodyNumber", "object number", "None")),
    (contact, dict(bodyNumber=99), ("bodyNumber", "existing object number", "99")),
    (contact, dict(bodyNumber=-1), ("bodyNumber", "existing object number", "-1")),
    (contact, dict(masterBodyNumber=0), ("masterBodyNumber", "differ from bodyNumber", "0")),
    (contact, dict(masterBodyNumber="m"), ("masterBodyNumber", "object number", "'m'")),
    (contact, dict(localPoints=[[0.0, 0.0]]), ("localPoints", "(K, 3)", "(1, 2)")),
    (contact, dict(localPoints=[]), ("localPoints", "K >= 1", "(0,)")),
    (contact, dict(localPoints=[[NAN, 0.0, 0.0]]), ("localPoints", "finite", "non-finite")),
    (contact, dict(localPoints="abc"), ("localPoints", "real numbers", "'abc'")),
    (contact, dict(surface=None), ("surface", "a surface of exu_aniso", "None")),
    (contact, dict(adhesion=None), ("adhesion", "Adhesion field", "None")),
    (contact, dict(friction=Adhesion.isotropic(1.0)), ("friction", "Friction field", "Adhesion.isotropic")),
    (contact, dict(normalStiffness=-1.0), ("normalStiffness", "> 0", "-1.0")),
    (contact, dict(normalStiffness="1"), ("normalStiffness", "real number", "'1'")),
    (contact, dict(normalDamping=NAN), ("normalDamping", "finite", "nan")),
    (contact, dict(returnMap="closest"), ("returnMap", "'seed', 'exact', 'radial'", "'closest'")),
    (contact, dict(normalStiffness=None), ("normalStiffness", "contactLaw", "give")),
    (contact, dict(contactLaw=law(), normalStiffness=1.0), ("contactLaw", "one or the other", "normalStiffness")),
    (contact, dict(contactLaw="law"), ("contactLaw", "ContactLaw", "'law'")),
    (contact, dict(jacobian="exact"), ("jacobian", "'analytic' or 'numerical'", "'exact'")),
    (contact, dict(jacobian=None), ("jacobian", "'analytic' or 'numerical'", "None")),
    (contact, dict(initializeHistory="no"), ("initializeHistory", "True or False", "'no'")),
    (contact, dict(storeSensors=1), ("storeSensors", "True or False", "1")),
    (contact, dict(storeHistory="yes"), ("storeHistory", "True or False", "'yes'")),
]


def _id(case):
    f, kw, _ = case
    name = getattr(f, "__qualname__", str(f))
    return f"{name}({', '.join(f'{k}={v!r:.20}' for k, v in kw.items())})"


@pytest.mark.parametrize("call, kwargs, words", CASES, ids=[_id(c) for c in CASES])
def test_bad_input_raises_a_named_error(call, kwargs, words):
    with pytest.raises((ValueError, TypeError)) as info:
        call(**kwargs)
    message = str(info.value)
    missing = [w for w in words if w not in message]
    assert not missing, f"message {message!r} lacks {missing}"


CLI_CASES = [
    (["run", "block", "--set", "mass=-1"], ("mass", "> 0", "'-1'")),
    (["run", "block", "--set", "mass=abc"], ("mass", "number", "'abc'")),
    (["run", "block", "--set", "mass=[1]"], ("mass", "number", "'[1]'")),
    (["run", "block", "--set", "t_end=nan"], ("t_end", "finite", "'nan'")),
    (["run", "block", "--set", "t_end=0"], ("t_end", "> 0", "'0'")),
    (["run", "block", "--set", "dt=-1e-3"], ("dt", "> 0", "'-1e-3'")),
    (["run", "block", "--set", "dt=3", "--set", "t_end=2"], ("dt", "<= t_end", "3.0")),
    (["run", "block", "--set", "nonsense=1"], ("unknown parameter", "nonsense", "valid names")),
    (["run", "block", "--set", "=1"], ("unknown parameter", "''", "valid names")),
    (["run", "block", "--set", "mass"], ("--set", "NAME=VALUE", "'mass'")),
    (["run", "block", "--set", "mass=1", "--set", "mass=2"], ("--set", "mass", "twice")),
    (["run", "block", "--set", "return_map=closest"], ("return_map", "'seed', 'exact', 'radial'", "'closest'")),
    (["run", "block", "--set", "drive=pull"], ("drive", "'force', 'displacement'", "'pull'")),
    (["run", "block", "--set", "model=3d"], ("model", "'planar', 'full'", "'3d'")),
    (["run", "block", "--set", "solver=rk4"], ("solver", "'trapezoidal', 'generalized_alpha'", "'rk4'")),
    (["run", "block", "--set", "points=grid:1"], ("points", "grid:N", "'grid:1'")),
    (["run", "block", "--set", "mu_2=0"], ("mu_2", "> 0", "'0'")),
    (["run", "screw", "--set", "rings=2.5"], ("rings", "integer", "'2.5'")),
    (["run", "screw", "--set", "points_per_ring=0"], ("points_per_ring", "integer >= 1", "'0'")),
    (["run", "screw", "--set", "helix_angle=90"], ("helix_angle", "(-90, 90)", "'90'")),
    (["run", "screw", "--set", "model=full", "--set", "points_per_ring=2"], ("points_per_ring", ">= 3", "2")),
    (["run", "screw", "--set", "eps_1=1e999"], ("eps_1", "finite", "'1e999'")),
    # from a robustness campaign: each message names the parameter that breaks the rule
    (["run", "fastening", "--set", "d2=1e-9"], ("d2, pitch", "lead angle", "89.9999 deg")),
    (["run", "fastening", "--set", "mu_thread=20"], ("mu_thread:", "locks", "< 1")),
    (["run", "fe_block", "--set", "E=5e-324"], ("E", "at least", "5e-324")),
    (["run", "block", "--set", "mu_1=5e-324"], ("mu_1", "at least", "5e-324")),
    (["run", "fe_block", "--set", "model=reduced", "--set", "basis=eigenmodes", "--set", "modes=100000"],
     ("modes must be <= 300", "basis=eigenmodes", "100000")),
    (["run", "fe_block", "--set", "basis=craig_bampton", "--set", "modes=100000"],
     ("modes must be <= 225", "basis=craig_bampton", "100000")),
    (["run", "all", "--set", "mass=2"], ("--set", "one scene", "block")),
    (["run", "block", "--engine", "bullet"], ("--engine", "invalid choice", "'bullet'")),
    (["run", "cube"], ("scene", "invalid choice", "'cube'")),
    (["run"], ("scene", "required",)),
    (["params", "cube"], ("scene", "invalid choice", "'cube'")),
    (["fly"], ("command", "invalid choice", "'fly'")),
]


def _cli(args, capsys):
    try:
        code = main(args)
    except SystemExit as e:     # argparse reports its own errors by SystemExit(2)
        code = e.code
    return code, capsys.readouterr().err


@pytest.mark.parametrize("args, words", CLI_CASES, ids=[" ".join(a) for a, _ in CLI_CASES])
def test_cli_bad_input_exit_2_message_nothing_written(tmp_path, capsys, args, words):
    out = tmp_path / "out"
    code, err = _cli(args + ["--out", str(out)] if args[0] == "run" and len(args) > 1 else args, capsys)
    assert code == 2
    missing = [w for w in words if w not in err]
    assert not missing, f"stderr {err!r} lacks {missing}"
    assert "Traceback" not in err
    assert os.listdir(tmp_path) == []           # no --out directory, no temporary files


def test_cli_bad_input_leaves_an_existing_out_dir_untouched(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("x")
    code, err = _cli(["run", "screw", "--set", "rings=2.5", "--out", str(out)], capsys)
    assert code == 2 and "rings" in err
    assert sorted(os.listdir(out)) == ["keep.txt"] and os.listdir(tmp_path) == ["out"]


@pytest.mark.parametrize("target", ["afile", "afile/sub"])
def test_cli_out_on_an_existing_file_is_bad_input(tmp_path, capsys, target):
    (tmp_path / "afile").write_text("x")
    code, err = _cli(["run", "block", "--engine", "reference", "--set", "t_end=0.01", "--out",
                      str(tmp_path / target)], capsys)
    assert code == 2 and "--out must be a directory" in err and "afile" in err
    assert sorted(os.listdir(tmp_path)) == ["afile"] and (tmp_path / "afile").read_text() == "x"


def test_cli_process_prints_no_traceback(tmp_path):
    """The installed entry point: exit code 2, one message line naming the parameter, nothing written."""
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-c", "import sys; from exu_aniso.cli import main; sys.exit(main())",
                        "run", "screw", "--set", "rings=2.5", "--out", str(out)],
                       capture_output=True, text=True, timeout=HANG_S)
    assert r.returncode == 2
    assert "Traceback" not in r.stderr and "rings must be an integer; got '2.5'" in r.stderr
    assert r.stdout == "" and not out.exists()


def test_api_bounds_name_the_argument():
    """The fields' constructors bound their values (a friction coefficient whose 1 / mu^2 leaves the
    doubles, an adhesion stiffness that makes a chart look singular), the mesh helpers their size and
    geometry, node_at a finite point: each error names the argument and the rule."""
    from exu_aniso.fe import block_mesh, shank_mesh
    from exu_aniso.fields.tensor_fields import Adhesion, Friction
    for call, message in ((lambda: Friction.isotropic(1e-200), "mu must lie in"),
                          (lambda: Friction.isotropic(1e200), "mu must lie in"),
                          (lambda: Friction.polar(0.3, 1e-12), "mu_phi must lie in"),
                          (lambda: Adhesion.isotropic(1e300), "stiffness must lie in"),
                          (lambda: block_mesh(cells=(400, 400, 400)), "cells must give at most"),
                          (lambda: block_mesh(size=(0.1, 0.1, 1e-200)), "size must have its smallest entry"),
                          (lambda: shank_mesh(bore=0.005 * (1 - 1e-15)), "bore must leave a wall"),
                          (lambda: block_mesh(cells=(1, 1, 1)).node_at([float("nan")] * 3), "point must be finite")):
        with pytest.raises(ValueError, match=message):
            call()


def test_duplicate_points_on_a_rigid_body_are_refused():
    """A rigid body's localPoints listing a point twice (as the finite-element route refuses a node
    twice): the error names the rows."""
    import exudyn as exu
    from exudyn.utilities import InertiaCuboid
    from exu_aniso.fields.tensor_fields import Adhesion, Friction
    from exu_aniso.geometry import Plane
    from exu_aniso.kernel.contact_law import ContactLaw
    import exu_aniso  # noqa: F401
    mbs = exu.SystemContainer().AddSystem()
    o = mbs.CreateRigidBody(inertia=InertiaCuboid(1000.0, [0.1] * 3), referencePosition=[0.0, 0.0, 0.05])
    law = ContactLaw(Plane(), Adhesion.isotropic(1e3), Friction.isotropic(0.3), normal_stiffness=1e5)
    with pytest.raises(ValueError, match=r"localPoints lists a point more than once \(rows \[0, 2\]"):
        mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=[[0, 0, -0.05], [0.05, 0, -0.05], [0, 0, -0.05]],
                                     contactLaw=law)
    # a group of rigid bodies and a mass point: the same rule
    o2 = mbs.CreateRigidBody(inertia=InertiaCuboid(1000.0, [0.1] * 3), referencePosition=[0.3, 0.0, 0.05])
    with pytest.raises(ValueError, match=r"localPoints lists a point more than once \(rows \[0, 1\]"):
        mbs.CreateAnisotropicContact(bodyNumber=[o, o2], localPoints=[[0, 0, -0.05]] * 2, contactLaw=law)
    m = mbs.CreateMassPoint(mass=1.0, referencePosition=[0.0, 0.5, 0.0])
    with pytest.raises(ValueError, match=r"localPoints lists a point more than once \(rows \[0, 1\]"):
        mbs.CreateAnisotropicContact(bodyNumber=m, localPoints=[[0, 0, 0]] * 2, contactLaw=law)


@pytest.mark.parametrize("text,message", [
    ("-" * 3000 + "1", "of at most 200 characters"),
    ("(-8)**(1/3)", "must be a real number; the expression '\\(-8\\)\\*\\*\\(1/3\\)' gives a complex one"),
    ("--1", "without digit separators, hex/octal/binary or doubled signs"),
    ("0x10", "without digit separators, hex/octal/binary or doubled signs"),
    ("1_000", "without digit separators, hex/octal/binary or doubled signs"),
])
def test_a_number_is_a_plain_decimal_or_a_small_expression(text, message):
    """The parameter parser's rule, named with the parameter: no recursion error on a long chain of
    signs, no complex power, no hex, digit separators or doubled signs passed as numbers; plain
    decimals and expressions with pi still read."""
    from exu_aniso.scenes.block import BlockParams
    with pytest.raises(ValueError, match="mass: .*" + message):
        BlockParams.from_strings({"mass": text})
    assert BlockParams.from_strings({"mass": "2*pi"}).mass == pytest.approx(2 * math.pi)
    assert BlockParams.from_strings({"mass": ".5e1"}).mass == 5.0
