"""Fields given by the user as a function of the surface coordinates (Adhesion.field,
Friction.field): equal to the built-in nets they restate (orthotropic on a sphere, spiral on a
cylinder, polar orthotropy as the coordinate net of the polar plane), consistent tangent of a
varying field, the plain-Python path equal to the compiled one, and clear errors."""
from __future__ import annotations

import math

import numpy as np
import pytest

from exu_aniso import Adhesion, ContactLaw, Friction
from exu_aniso import geometry as geo
from _suite import HANG_S

RNG = np.random.default_rng(5)


def _state(law, surface, box, depth=1e-4):
    """A point below the surface at a random chart point of box, a velocity and an active history."""
    xi = np.array([RNG.uniform(*box[0]), RNG.uniform(*box[1])])
    g = surface.at(xi)
    x = g.point - g.n * RNG.uniform(0.2, 1.0) * depth
    v = RNG.normal(size=3) * 0.1
    H = law.evaluate(x[None, :] + RNG.normal(size=3) * 2e-5, v[None, :], None, tangent=False, dt=1e-3).history
    H[0, 0:2] = RNG.normal(size=2) * 3.0
    return x, v, H


def _same(a, b, surface, box, n=6, rtol=1e-12):
    for _ in range(n):
        x, v, H = _state(a, surface, box)
        sa = a.evaluate(x[None, :], v[None, :], H, dt=1e-3)
        sb = b.evaluate(x[None, :], v[None, :], H, dt=1e-3)
        assert sa.status[0] == sb.status[0]
        fs = 1.0 + np.abs(sa.force).max()
        np.testing.assert_allclose(sb.force, sa.force, rtol=0, atol=rtol * fs)
        ks = 1.0 + np.abs(sa.stiffness).max()
        np.testing.assert_allclose(sb.stiffness, sa.stiffness, rtol=0, atol=1e3 * rtol * ks)
        np.testing.assert_allclose(sb.history, sa.history, rtol=rtol, atol=rtol)


def constant_adhesion(xi1, xi2):
    return 2e4, 3e2, 0.4


def constant_friction(xi1, xi2):
    return 0.2, 0.5, -0.3


class _Python:                      # a Python object inside: numba cannot compile the function
    eps = (2e4, 3e2, 0.4)


PY = _Python()


def python_adhesion(xi1, xi2):
    return PY.eps


@pytest.mark.parametrize("side", ("outside", "inside"))
def test_constant_user_field_is_the_orthotropic_net(side):
    s = geo.Sphere(0.6, center=(0.1, 0, 0), axis_direction=(0, 1, 1), side=side)
    ref = ContactLaw(s, Adhesion.orthotropic(2e4, 3e2, 0.4), Friction.orthotropic(0.2, 0.5, -0.3), 1e5)
    user = ContactLaw(s, Adhesion.field(constant_adhesion), Friction.field(constant_friction), 1e5)
    assert user.compiled
    _same(ref, user, s, [(-3, 3), (0.4, 2.7)])


def test_plain_python_user_field_gives_the_compiled_numbers():
    s = geo.Torus(1.0, 0.3)
    A = Adhesion.field(python_adhesion)
    assert A.cfunc is None and "Typing" in A.compile_error
    compiled = ContactLaw(s, Adhesion.field(constant_adhesion), Friction.field(constant_friction), 1e5)
    python = ContactLaw(s, A, Friction.field(constant_friction), 1e5)
    assert compiled.compiled and not python.compiled
    _same(compiled, python, s, [(-3, 3), (-3, 3)], n=3)


def test_user_spiral_on_the_cylinder_is_the_spiral_net():
    """A helix of lead L on a cylinder of radius R is at atan(L / (2 pi R)) from the circumference."""
    R, lead = 0.05, 0.01
    alpha = math.atan(lead / (2 * math.pi * R))

    def helix(xi1, xi2):
        return 1e3, 1e5, alpha

    s = geo.Cylinder(R, side="inside")
    _same(ContactLaw(s, Adhesion.spiral(1e3, 1e5, lead=lead), Friction.isotropic(0.3), 1e6),
          ContactLaw(s, Adhesion.field(helix), Friction.isotropic(0.3), 1e6), s, [(-3, 3), (-0.1, 0.1)])


def test_polar_orthotropy_is_the_coordinate_net_of_the_polar_plane():
    """Polar orthotropy (papers' eq. 8: e1 = e_r from the point's position) restated by the user as
    e1 along the xi1 = r coordinate line of the polar chart: the same forces. (The history is
    stored per chart, so both laws use the polar chart.)"""
    def radial(r, phi):
        return 2e4, 3e2, 0.0

    def radial_mu(r, phi):
        return 0.2, 0.6, 0.0

    s = geo.Plane("polar")
    _same(ContactLaw(s, Adhesion.polar(2e4, 3e2), Friction.polar(0.2, 0.6), 1e5),
          ContactLaw(s, Adhesion.field(radial), Friction.field(radial_mu), 1e5), s, [(0.2, 1.0), (-3, 3)],
          rtol=1e-10)


def varying(xi1, xi2):
    return 1e4 * (1.5 + math.sin(xi2)), 3e2 * (2.0 + math.cos(xi1)), 0.5 * xi2


def test_tangent_of_a_varying_user_field_equals_finite_differences():
    s = geo.Sphere(0.6)
    law = ContactLaw(s, Adhesion.field(varying), Friction.orthotropic(0.3, 0.5, 0.1), 1e5, return_map="exact")
    for _ in range(6):
        x, v, H = _state(law, s, [(-3, 3), (0.4, 2.7)])
        st = law.evaluate(x[None, :], v[None, :], H, dt=1e-3)
        J = np.zeros((3, 3))
        h = 1e-8
        for j in range(3):
            e = np.zeros(3)
            e[j] = h
            fp = law.evaluate((x + e)[None, :], v[None, :], H, tangent=False, dt=1e-3).force[0]
            fm = law.evaluate((x - e)[None, :], v[None, :], H, tangent=False, dt=1e-3).force[0]
            J[:, j] = (fp - fm) / (2 * h)
        np.testing.assert_allclose(st.stiffness[0], J, rtol=0, atol=2e-5 * np.abs(J).max())


def negative(xi1, xi2):
    return -1.0, 1.0, 0.0


def raising(xi1, xi2):
    raise RuntimeError("no field here")


def test_bad_user_field_is_a_clear_error():
    with pytest.raises(TypeError, match="Adhesion.field: function must be a function"):
        Adhesion.field(3.0)
    s = geo.Sphere(0.6)
    x = np.array([[0.0, 0.3, 0.5]]) / np.linalg.norm([0.0, 0.3, 0.5]) * 0.5999
    for fn in (negative, raising):
        law = ContactLaw(s, Adhesion.field(fn), Friction.isotropic(0.3), 1e5)
        with pytest.raises(ValueError, match=r"field: function\(xi1, xi2\) must return"):
            law.evaluate(x)        # compiled (the net's check) or plain Python (the wrapper's) alike

    class Bad:
        v = (1.0, 2.0)

    bad = Bad()
    law = ContactLaw(s, Adhesion.isotropic(1e3), Friction.field(lambda a, b: bad.v), 1e5)
    with pytest.raises(ValueError, match=r"Friction.field: function\(xi1, xi2\) must return 3 numbers"):
        law.evaluate(x)


_EXIT_SCRIPT = """
import exudyn as exu, exu_aniso
from exu_aniso import Plane, Adhesion, Friction
def B(x1, x2):
    return 1e4, 2e3, 0.3
def F(x1, x2):
    return 0.3, 0.5, 0.3
SC = exu.SystemContainer()
mbs = SC.AddSystem()
o = mbs.CreateMassPoint(referencePosition=[0.1, 0.2, 0.0], initialVelocity=[0.2, 0, 0], mass=1.0,
                        gravity=[0, 0, -9.81])
c = mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=[[0, 0, 0]], surface=Plane(), adhesion=Adhesion.field(B),
                                 friction=Friction.field(F), normalStiffness=1e5)
mbs.Assemble()
s, solver = exu_aniso.RecommendedSimulationSettings(endTime=0.01, stepSize=1e-3)
mbs.SolveDynamic(s, solverType=solver)
print("done", c["nativeCallbacks"])
"""


def test_a_user_field_leaves_quietly_at_exit(tmp_path):
    """A model with user fields left alive at interpreter exit: the stored arguments of its native
    callbacks are dropped without a word (their __del__ printed 'Exception ignored ... NoneType has
    no attribute is_finalizing' twice: the module's globals are gone by then)."""
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", _EXIT_SCRIPT], capture_output=True, text=True, cwd=tmp_path,
                         timeout=HANG_S)
    assert out.returncode == 0 and out.stdout.strip().startswith("done"), out.stderr[-2000:]
    assert "Exception ignored" not in out.stderr and "Traceback" not in out.stderr, out.stderr[-2000:]
