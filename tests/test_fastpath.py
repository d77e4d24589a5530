"""The compiled route is held equal to the Python route.

Three levels: the compiled point kernel (exu_aniso.kernel.point.contact_point) against its plain-Python
twin (the same source run by the interpreter: force, tangent, history) over surfaces, fields,
maps and random states; a whole compiled contact set (exu_aniso.kernel.sets.evaluate_set) on every
node kind against the numpy route (generalized force, Jacobian, history candidate); and whole
Exudyn runs of both scenes with implementation="compiled" against implementation="numpy".
"""
import math
import zlib
import os
import subprocess
import sys

import numpy as np
import pytest

from exu_aniso import Adhesion, Friction
from exu_aniso.geometry import Cylinder, Plane
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.kernel import point as kernel
from exu_aniso.law.return_maps import MAPS


def _laws():
    out = []
    for m in ("seed", "exact", "radial"):
        out.append((f"polar-{m}", ContactLaw(Plane("polar"), Adhesion.polar(2e4, 3e2, core_radius=1e-3),
                                             Friction.polar(0.2, 0.5, core_radius=1e-3), 2e5, 0.0, m)))
        out.append((f"cart-{m}", ContactLaw(Plane(), Adhesion.orthotropic(5e3, 4e4, angle=0.4),
                                            Friction.orthotropic(0.3, 0.7, angle=-0.3), 1e5, 30.0, m,
                                            tangential_damping=7.0)))
        out.append((f"hole-{m}", ContactLaw(Cylinder(0.05, side="inside"), Adhesion.spiral(1e3, 1e5, 0.2),
                                            Friction.spiral(0.2, 0.6, 0.2), 1e6, 0.0, m)))
        out.append((f"shaft-{m}", ContactLaw(Cylinder(0.05, axis_point=(0.1, -0.2, 0.3), axis_direction=(1, 2, 2),
                                                      side="outside"), Adhesion.isotropic(4e3),
                                             Friction.orthotropic(0.25, 0.4, angle=0.7), 1e6, 5.0, m,
                                             tangential_damping=3.0)))
    return out


LAWS = _laws()


def _states(law, rng, n=12):
    """(Tolerances: the gap is microns against coordinates of decimetres, so the two routes' different
    order of operations in the projection differs by ~1e-12 relative.) Slave points near the surface (some open), velocities and histories (active or not,
    sticking or far enough to slide)."""
    s = law.surface
    out = []
    for _ in range(n):
        if isinstance(s, Plane):
            x = np.array([rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6), rng.uniform(-3e-5, 1e-5)])
            u_old = x[:2] + rng.normal(scale=2e-4, size=2)
        else:
            phi, z = rng.uniform(-math.pi, math.pi), rng.uniform(-0.1, 0.1)
            gap = rng.uniform(-3e-6, 1e-6)
            e1, e2, a = s.axes
            dist = s.radius + s.sign * gap
            x = s.axis_point + dist * (math.cos(phi) * e1 + math.sin(phi) * e2) + z * a
            # anchor on the other side of phi = +-pi sometimes, and a few revolutions away
            u_old = np.array([phi + rng.normal(scale=1e-3) + 2 * math.pi * rng.integers(-2, 3), z + rng.normal(scale=1e-4)])
        v = rng.normal(scale=0.1, size=3)
        h = np.zeros(9)
        if rng.random() < 0.8:
            h[4] = 1.0
            h[0:2] = rng.normal(scale=0.5, size=2)
            h[2:4] = u_old
            h[5:7] = rng.uniform(0, 1, size=2)
        out.append((x, v, h))
    return out


@pytest.mark.parametrize("name,law", LAWS, ids=[n for n, _ in LAWS])
def test_compiled_point_kernel_equals_its_plain_python_source(name, law):
    """numba's machine code and the interpreter run the same source to the same numbers (to
    round-off: fused multiply-adds and libm may differ in the last bits)."""
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    py = kernel.plain_python()
    lp = kernel.LawParams(law.eps_N, law.d_N, law.d_T, MAPS[law.return_map])
    args = (law.surface.params, law._nets[0], law._nets[1], lp)
    statuses = set()
    for x, v, h in _states(law, rng):
        dt = float(rng.choice([0.0, 1e-3, 0.5]))     # no prediction, a resolved and an unresolved step
        out = []
        for fn in (kernel.contact_point, py.contact_point):
            f, Kx, Dv, hn = np.zeros(3), np.zeros((3, 3)), np.zeros((3, 3)), np.zeros(9)
            st, gap = fn(*args, x, v, h, dt, True, f, Kx, Dv, hn, np.zeros((3, 9, 9)))
            out.append((st, gap, f, Kx, Dv, hn))
        (st, gap, f, Kx, Dv, hn), ref = out
        statuses.add(st)
        assert st == ref[0]
        assert gap == pytest.approx(ref[1], rel=1e-12, abs=1e-15)
        scale = max(1.0, np.abs(ref[2]).max())
        np.testing.assert_allclose(f, ref[2], rtol=0, atol=1e-9 * scale)
        np.testing.assert_allclose(Kx, ref[3], rtol=0, atol=1e-8 * max(1.0, np.abs(ref[3]).max()))
        np.testing.assert_allclose(Dv, ref[4], rtol=0, atol=1e-8 * max(1.0, np.abs(ref[4]).max()))
        np.testing.assert_allclose(hn, ref[5], rtol=1e-9, atol=1e-12)
    assert statuses >= {1, 2} or statuses >= {0, 2}, f"{name}: states did not cover stick/slip: {statuses}"


# --- whole contact sets on every node kind, against the numpy route ------------------------------

exu = pytest.importorskip("exudyn")


def _mbs_with(node_kind, law, points, q0, v0):
    from exudyn.itemInterface import (NodeGenericODE2, NodeRigidBody2D, ObjectGenericODE2, ObjectRigidBody2D)
    from exudyn.utilities import InertiaCuboid
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    if node_kind == "RigidBody2D":
        n = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0.3, 0.1, 0.2], initialCoordinates=q0,
                                        initialVelocities=v0))
        o = mbs.AddObject(ObjectRigidBody2D(nodeNumber=n, mass=1.0, inertia=0.01))
    elif node_kind == "GenericODE2":
        n = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0, 0.0], initialCoordinates=q0,
                                        initialCoordinates_t=v0, numberOfODE2Coordinates=2))
        o = mbs.AddObject(ObjectGenericODE2(nodeNumbers=[n], massMatrix=np.eye(2)))
    else:
        nt = exu.NodeType.RotationRotationVector if node_kind == "RigidBodyRotVecLG" else \
            exu.NodeType.RotationEulerParameters
        o = mbs.CreateRigidBody(inertia=InertiaCuboid(1000.0, [0.1] * 3), referencePosition=[0.3, 0.1, 0.05],
                                referenceRotationMatrix=np.eye(3), initialVelocity=v0[:3],
                                initialAngularVelocity=v0[3:6], nodeType=nt)
    return mbs, o


KIND_CASES = [
    ("RigidBody2D", "polar-radial", [0.01, -0.02, 0.3], [0.1, 0.2, 1.0]),
    ("RigidBody2D", "cart-exact", [0.01, -0.02, -2.0], [0.1, 0.2, -1.0]),
    ("GenericODE2", "hole-seed", [2.5, 1e-3], [3.0, 0.01]),
    ("GenericODE2", "hole-exact", [-3.5, -1e-3], [-3.0, 0.01]),
    ("RigidBodyRotVecLG", "cart-radial", None, [0.1, 0.2, 0.0, 0.3, -0.2, 1.0]),
    ("RigidBodyEP", "polar-exact", None, [0.1, 0.2, 0.0, 0.3, -0.2, 1.0]),
]


@pytest.mark.parametrize("node_kind,lawname,q0,v0", KIND_CASES, ids=[f"{c[0]}-{c[1]}" for c in KIND_CASES])
def test_set_kernel_equals_numpy_route(node_kind, lawname, q0, v0):
    """Generalized force, Jacobian (with its geometric term) and history candidate of the
    compiled set equal the numpy set, at perturbed states with an active history."""
    from exu_aniso.engines.exudyn_adapter import create_contact
    law = dict(LAWS)[lawname]
    rng = np.random.default_rng(7)
    if node_kind == "GenericODE2":
        R = law.surface.radius
        points = np.array([[(R + 2e-6) * math.cos(a), (R + 2e-6) * math.sin(a), z]
                           for a in np.linspace(0, 2 * math.pi, 6, endpoint=False) for z in (-0.01, 0.01)])
    elif node_kind == "RigidBody2D":
        points = np.array([[sx * 0.05, sy * 0.05, -1e-5] for sx in (-1, 1) for sy in (-1, 1)])
    else:
        points = np.array([[sx * 0.05, sy * 0.05, -0.05 - 1e-5] for sx in (-1, 1) for sy in (-1, 1)])
    mbs, o = _mbs_with(node_kind, law, points, q0, v0)
    sets = {}
    for impl in ("numpy", "compiled"):
        c = create_contact.CreateAnisotropicContact(mbs, o, points, contactLaw=law, implementation=impl, storeSensors=False)
        assert c["implementation"] == impl
        sets[impl] = mbs.variables["exu_aniso_contact_sets"][-1]
    plain, comp = sets["numpy"], sets["compiled"]
    n = plain.slave.n
    H0 = plain.state(mbs, plain.slave.q0, plain.slave.v0, None, tangent=False)[0].history
    for trial in range(4):
        q = plain.slave.q0 + rng.normal(scale=2e-4, size=n)
        if node_kind == "RigidBodyEP":       # stay near the unit quaternion
            q[3:] = 0.0
        qt = plain.slave.v0 + rng.normal(scale=0.05, size=n)
        H = H0.copy()
        H[:, 0:2] = rng.normal(scale=0.3, size=(len(points), 2))
        st_p = plain.state(mbs, q, qt, H, tangent=True)
        comp.pk.H[:] = H
        comp.pk.evaluate(0, q, qt, 0.0, 0.0, 0.0)
        Q_plain = np.einsum("kij,ki->j", st_p[1], st_p[2])
        np.testing.assert_allclose(comp.pk.Q, Q_plain, rtol=0, atol=1e-9 * max(1.0, np.abs(Q_plain).max()))
        comp.pk.evaluate(2, q, qt, 0.0, 0.0, 0.0)
        np.testing.assert_allclose(comp.pk.Hn, st_p[0].history, rtol=1e-9, atol=1e-12)
        # Jacobian through the numpy route's own method (it reads the history from the mbs, so
        # compare through a state with that history): use plain.jacobian's formula directly
        Kq = np.einsum("kia,kij,kjb->ab", st_p[1], st_p[0].stiffness, st_p[4].dx)
        Dq = np.einsum("kia,kij,kjb->ab", st_p[1], st_p[0].damping, st_p[1])
        plain._add_geometric(Kq, st_p[1], st_p[4])
        J_plain = -(0.7 * Kq + 0.3 * Dq)
        comp.pk.evaluate(1, q, qt, 0.7, 0.3, 0.0)
        np.testing.assert_allclose(comp.pk.J, J_plain, rtol=0, atol=1e-8 * max(1.0, np.abs(J_plain).max()))
    assert np.any(np.abs(Q_plain) > 0)


def _python_only_plane(u, v):         # a user surface numba cannot compile (a Python object inside)
    h = PLANE_HEIGHT.z
    return [u, v, h], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [[[0.0] * 3] * 2] * 2


class _Height:
    z = 0.0


PLANE_HEIGHT = _Height()


def test_compiled_requires_a_compiled_surface():
    """(A moving master is compiled too: tests/test_moving_master_compiled.py.)"""
    from exu_aniso.engines.exudyn_adapter import create_contact
    from exu_aniso.geometry import ParametricSurface
    surface = ParametricSurface(_python_only_plane, bounds=((-1.0, 1.0), (-1.0, 1.0)))
    assert not surface.compiled
    law = ContactLaw(surface, Adhesion.isotropic(1e3), Friction.isotropic(0.3), 1e5)
    mbs, o = _mbs_with("RigidBody2D", law, None, [0, 0, 0], [0, 0, 0])
    with pytest.raises(ValueError, match="implementation='compiled' needs"):
        create_contact.CreateAnisotropicContact(mbs, o, [[0, 0, -1e-5]], contactLaw=law, implementation="compiled")
    c = create_contact.CreateAnisotropicContact(mbs, o, [[0, 0, -1e-5]], contactLaw=law, implementation="auto",
                                      storeSensors=False)
    assert c["implementation"] == "numpy"
    with pytest.raises(ValueError, match="implementation must be"):
        create_contact.CreateAnisotropicContact(mbs, o, [[0, 0, -1e-5]], contactLaw=law, implementation="fast")


# --- whole runs ---------------------------------------------------------------------------------

RUNS = [
    ("block", dict(t_end=0.5), {}),
    ("block", dict(t_end=0.3, return_map="exact", drive="force", drive_angle=30.0, force=4.0), {}),
    ("block", dict(t_end=0.3, return_map="seed", dt=5e-4), {}),
    ("block", dict(t_end=0.2, model="full"), {}),
    ("block", dict(t_end=0.2, model="full", adhesion="isotropic", eps_1=1e5), dict(nodeType="RotVecLG")),
    ("screw", dict(t_end=0.3), {}),
    ("screw", dict(t_end=0.2, return_map="exact", drive="torque", torque=0.2), {}),
    ("screw", dict(t_end=0.1, model="full"), {}),
]


@pytest.mark.parametrize("scene,over,opts", RUNS, ids=[f"{r[0]}-{i}" for i, r in enumerate(RUNS)])
def test_exudyn_run_compiled_equals_numpy(scene, over, opts):
    """Whole Exudyn runs: the compiled route reproduces the numpy route to round-off (same steps,
    same Newton iterations)."""
    from exu_aniso.scenes.block import BlockParams
    from exu_aniso.scenes.screw import ScrewParams
    if scene == "block":
        from exu_aniso.models.block import RunBlock as run
        p = BlockParams(**over)
    else:
        from exu_aniso.models.screw import RunScrew as run
        p = ScrewParams(**over)
    a = run(p, implementation="numpy", **opts)
    b = run(p, implementation="compiled", **opts)
    assert a.info["implementation"] == "numpy" and b.info["implementation"] == "compiled"
    assert a.summary["steps"] == b.summary["steps"]
    assert abs(a.summary["newton_iterations"] - b.summary["newton_iterations"]) <= 0.02 * a.summary["newton_iterations"]
    for k, va in a.trajectory.items():
        vb = b.trajectory[k]
        scale = max(1e-3, float(np.max(np.abs(va))))   # floor: vz, tilt of the full block are ~0
        if k.startswith("energy_"):                    # ledger columns: on the scale of the work in
            scale = max(scale, float(np.max(np.abs(a.trajectory["energy_work_in"]))))
        err = float(np.max(np.abs(vb - va))) / scale
        assert err < 1e-8, f"{scene} {over}: trajectory '{k}' differs by {err:.2e} (relative)"


@pytest.mark.parametrize("over", [dict(t_end=0.3), dict(t_end=0.2, return_map="exact", drive="torque", torque=0.2),
                                  dict(t_end=0.2, return_map="seed", dt=5e-4, rings=2, points_per_ring=5)],
                         ids=["radial-rotation", "exact-torque", "seed-2x5"])
def test_reduced_screw_symmetry_equals_all_points(over):
    """The reduced screw with one representative point (symmetry=True, default) reproduces the
    run that evaluates every point of the layout."""
    from exu_aniso.models.screw import RunScrew
    from exu_aniso.scenes.screw import ScrewParams
    p = ScrewParams(**over)
    a = RunScrew(p, symmetry=False)
    b = RunScrew(p)
    assert a.info["K"] == p.rings * p.points_per_ring and b.info["K"] == 1
    assert a.summary["steps"] == b.summary["steps"]
    for k, va in a.trajectory.items():
        scale = max(1e-3, float(np.max(np.abs(va))))
        if k.startswith("energy_"):                    # ledger columns: on the scale of the work in
            scale = max(scale, float(np.max(np.abs(a.trajectory["energy_work_in"]))))
        err = float(np.max(np.abs(b.trajectory[k] - va))) / scale
        assert err < 1e-8, f"{over}: trajectory '{k}' differs by {err:.2e} (relative)"


@pytest.mark.slow
def test_first_compile_is_announced_once_and_cached(tmp_path):
    """A fresh numba cache: the first run says it compiles its law and its set kernel (before each
    pass), the second run loads the cache from disk and says nothing."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba"))
    code = ("import numpy as np\nfrom exu_aniso import Adhesion, ContactLaw, Friction, Plane\n"
            "law = ContactLaw(Plane(), Adhesion.isotropic(1e3), Friction.isotropic(0.3), 1e5)\n"
            "from exu_aniso.kernel.packed_sets import CovariantSet\n"
            "pk = CovariantSet(law, 'RigidBody2D', np.zeros(3), [[0.0, 0.0, -1e-3]])\n"
            "pk.evaluate(0, np.zeros(3), np.zeros(3), 0.0, 0.0, 1e-3)\n"
            "assert pk.Q[1] == 0.0 and pk.Q.shape == (3,)\n")
    first = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    second = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert first.stderr.count("compiling the contact law for") == 1, first.stderr
    assert first.stderr.count("compiling the contact set kernel for") == 1, first.stderr
    assert "compiling" not in second.stderr, second.stderr
    assert any((tmp_path / "numba").rglob("*.nbi"))


def test_compile_announcement_only_when_not_cached(monkeypatch, capsys):
    """A kernel not in the cache is announced once per process, with what it is for and how long it
    takes (COMPILE_SECONDS): the law for its surface, nets and return map, a set's kernel for its
    node kind; one in the cache is not announced."""
    from exu_aniso.kernel import compiling, law_call, packed_sets
    from exu_aniso.kernel.nodes import NODE_KINDS
    bundle = law_call.law_bundle(ContactLaw(Plane(coordinates="polar"), Adhesion.isotropic(1e3),
                                            Friction.isotropic(0.3), 1e5))
    kind, master = NODE_KINDS["RigidBody2D"], NODE_KINDS["RigidBodyEP"]
    call = law_call.LawCall(0, 0)
    cases = [(law_call.law_entry, (bundle,), "law",
              "compiling the contact law for PolarPlane, IsotropicNet adhesion, IsotropicNet friction, exact map"),
             (packed_sets.evaluate_covariant, (np.zeros(3), call, kind), "fixed",
              "compiling the contact set kernel for a RigidBody2D node"),
             (packed_sets.evaluate_covariant_pair, (np.zeros(10), call, kind, master), "moving",
              "compiling the contact set kernel for a RigidBody2D slave on an EulerParameters master")]
    for entry, args, which, text in cases:
        for cached, expected in ((True, ""), (False, text)):
            monkeypatch.setattr(compiling, "compiled_here", {})
            monkeypatch.setattr(compiling, "kernels_cached", lambda entry=None, sig=None: cached)
            compiling.announce_compile(entry=entry, sig=("a",), args=args)
            compiling.announce_compile(entry=entry, sig=("a",), args=args)     # once per process and kernel
            err = capsys.readouterr().err
            assert (expected in err) and err.count("compiling") == (0 if cached else 1), err
            if not cached:
                low, high = compiling.COMPILE_SECONDS[which]
                assert f"about {low}-{high} s" in err
