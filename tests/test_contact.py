"""Contact set (exu_aniso.contact): consistent tangent, covariance, conventions, history."""
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from exu_aniso import OPEN, RETURN_MAPS, SLIP, STICK, Adhesion, ContactLaw, Friction
from exu_aniso.surfaces import Cylinder, Plane  # the transport kernel's surfaces

CASES = {
    "plane-polar-fields": (Plane("polar"), Adhesion.polar(1e4, 3e3, 0.01), Friction.polar(0.2, 0.6, 0.02)),
    "plane-cartesian": (Plane(), Adhesion.orthotropic(1e4, 1e3, 0.4), Friction.orthotropic(0.2, 0.6, -0.3)),
    "hole-spiral": (Cylinder(0.01, (0.001, 0.002, 0.0), (0.1, 0.2, 1.0)), Adhesion.spiral(1e4, 2e3, 0.2),
                    Friction.spiral(0.2, 0.5, 0.2)),
    "shaft-spiral": (Cylinder(0.01, side="outside"), Adhesion.spiral(1e4, 2e3, 0.2), Friction.spiral(0.2, 0.5, 0.2)),
}


def contact_sample(surface, rng, K=6):
    """Penetrating slave points with an active history (mixed stick and slip)."""
    if surface.kind == "plane":
        x = np.c_[rng.uniform(-1, 1, (K, 2)), -rng.uniform(1e-4, 1e-3, K)]
        u = x[:, :2]
    else:
        phi = rng.uniform(-3.1, 3.1, K)
        rad = 0.0101 if surface.side == "inside" else 0.0099
        loc = np.c_[rad * np.cos(phi), rad * np.sin(phi), rng.uniform(-1, 1, K) * 0.01]
        x = loc @ surface.axes + surface.axis_point
        u = surface.frame(x).u
    H = ContactLaw.initial_history(K)
    H[:, 0:2] = rng.normal(size=(K, 2)) * 10
    H[:, 2:4] = u + rng.normal(size=(K, 2)) * 1e-3
    H[:, 4] = 1.0
    return x, rng.normal(size=(K, 3)) * 0.1, H


@pytest.mark.parametrize("method", RETURN_MAPS)
@pytest.mark.parametrize("case", CASES)
def test_consistent_tangent_against_finite_differences(case, method):
    surface, adh, fri = CASES[case]
    law = ContactLaw(surface, adh, fri, 1e5, normal_damping=10.0, return_map=method)
    rng = np.random.default_rng(hash(case) % 1000)
    x, v, H = contact_sample(surface, rng)
    st = law.evaluate(x, v, H)
    assert set(st.status) <= {STICK, SLIP}
    h = 1e-8
    Kfd = np.zeros_like(st.stiffness)
    Dfd = np.zeros_like(st.damping)
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        Kfd[:, :, j] = (law.evaluate(x + e, v, H, False).force - law.evaluate(x - e, v, H, False).force) / (2 * h)
        e[j] = 1e-4
        Dfd[:, :, j] = (law.evaluate(x, v + e, H, False).force - law.evaluate(x, v - e, H, False).force) / 2e-4
    err = np.abs(st.stiffness - Kfd).max() / np.abs(Kfd).max()
    assert err < 1e-6, f"stiffness rel. error {err:.2e} ({case}, {method})"
    assert np.abs(st.damping - Dfd).max() <= 1e-6 * max(np.abs(Dfd).max(), 1.0)


def walk(law, xs):
    H = law.initial_history(xs.shape[1])
    out = []
    for x in xs:
        st = law.evaluate(x, None, H, tangent=False)
        H = st.history
        out.append(st.force)
    return np.array(out), H


@pytest.mark.parametrize("method", RETURN_MAPS)
@pytest.mark.parametrize("fields", ["isotropic", "polar"])
def test_covariance_cartesian_polar_and_transport_agree(method, fields):
    """The papers' chart route in polar and in Cartesian coordinates and the transport-frame
    route give the same forces along a sliding path (stick and slip), isotropic and polar law."""
    rng = np.random.default_rng(3)
    K = 3
    x0 = np.c_[rng.uniform(0.2, 1, (K, 2)), -1e-4 * np.ones(K)]
    xs = np.cumsum(rng.normal(size=(60, K, 3)) * [2e-3, 2e-3, 0], axis=0) + x0
    if fields == "isotropic":
        adh, fri = Adhesion.isotropic(1e4), Friction.isotropic(0.3)
    else:
        adh, fri = Adhesion.polar(1e4, 1e3), Friction.polar(0.2, 0.6)
    ref, _ = walk(ContactLaw(Plane("cartesian"), adh, fri, 1e5, return_map=method), xs)
    for chart in ("cartesian", "polar"):
        out, _ = walk(ContactLaw(Plane(chart), adh, fri, 1e5, return_map=method, formulation="chart"), xs)
        np.testing.assert_allclose(out, ref, rtol=0, atol=1e-11 * np.abs(ref).max(), err_msg=f"chart {chart}")


@pytest.mark.parametrize("method", RETURN_MAPS)
def test_chart_and_transport_agree_on_the_cylinder_across_phi_pi(method):
    rng = np.random.default_rng(4)
    cyl = Cylinder(0.01)
    phis = np.cumsum(rng.normal(size=(80, 3)) * 0.05, axis=0) + np.linspace(3.0, 3.2, 3)
    xs = np.stack([0.0101 * np.cos(phis), 0.0101 * np.sin(phis), np.cumsum(rng.normal(size=(80, 3)) * 1e-4, 0)], -1)
    adh, fri = Adhesion.spiral(1e4, 1e5, 0.3), Friction.spiral(0.2, 0.6, 0.3)
    ref, _ = walk(ContactLaw(cyl, adh, fri, 1e5, return_map=method), xs)
    out, _ = walk(ContactLaw(cyl, adh, fri, 1e5, return_map=method, formulation="chart"), xs)
    np.testing.assert_allclose(out, ref, rtol=0, atol=1e-11 * np.abs(ref).max())


def test_many_points_at_once_equal_one_at_a_time():
    surface, adh, fri = CASES["plane-polar-fields"]
    law = ContactLaw(surface, adh, fri, 1e5, 5.0, "exact")
    x, v, H = contact_sample(surface, np.random.default_rng(5), K=16)
    st = law.evaluate(x, v, H)
    for k in range(16):
        one = law.evaluate(x[k:k + 1], v[k:k + 1], H[k:k + 1])
        np.testing.assert_allclose(one.force[0], st.force[k], rtol=1e-14, atol=1e-14)
        np.testing.assert_allclose(one.stiffness[0], st.stiffness[k], rtol=1e-13, atol=1e-10)


def test_conventions_normal_pushes_out_and_traction_opposes_slip():
    law = ContactLaw(Plane(), Adhesion.isotropic(1e3), Friction.isotropic(0.5), 1e4)
    st = law.evaluate([[0.0, 0.0, -1e-3]])
    assert st.normal[0] == pytest.approx(-10.0) and np.allclose(st.force[0], [0, 0, 10.0])
    st2 = law.evaluate([[1e-3, 0.0, -1e-3]], history=st.history)       # slave moved +x: stick
    assert st2.status[0] == STICK
    np.testing.assert_allclose(st2.force[0], [-1.0, 0.0, 10.0])
    st3 = law.evaluate([[0.1, 0.0, -1e-3]], history=st2.history)       # far: slip at mu |N|
    assert st3.status[0] == SLIP
    np.testing.assert_allclose(st3.force[0], [-5.0, 0.0, 10.0])
    # energy books of the step (trapezoidal quadrature, as the integrator): the traction did the work
    # (1 + 5)/2 * 0.099 over the displacement, the spring's T^2 / (2 eps) grew by (25 - 1) / 2e3; the
    # rest is what the return map removed: (1 + 5)/2 * slip with slip = 0.099 - (5 - 1)/1e3
    assert st3.history[0, 5] == pytest.approx(3.0 * 0.099 - 24.0 / 2e3, rel=1e-12)
    assert st3.history[0, 5] == pytest.approx(3.0 * (0.099 - 4.0 / 1e3), rel=1e-12)
    hole = ContactLaw(Cylinder(1.0), Adhesion.isotropic(1.0), Friction.isotropic(0.5), 10.0)
    assert np.allclose(hole.evaluate([[1.1, 0, 0]]).force[0], [-1.0, 0, 0])                  # towards the axis


def test_contact_lost_and_regained_resets_the_history():
    law = ContactLaw(Plane(), Adhesion.isotropic(1e3), Friction.isotropic(0.5), 1e4)
    H = law.evaluate([[0.0, 0.0, -1e-3]]).history
    H = law.evaluate([[2e-3, 0.0, -1e-3]], history=H).history
    assert H[0, 0] != 0.0 and H[0, 4] == 1.0
    off = law.evaluate([[3e-3, 0.0, 1e-3]], history=H)
    assert off.status[0] == OPEN and np.all(off.force == 0) and np.all(off.history[0, :5] == 0.0)
    # dissipation kept, plus the spring energy T^2 / (2 eps_T) that the reset lets go
    assert off.history[0, 5] == pytest.approx(H[0, 5] + (H[0, 0] ** 2 + H[0, 1] ** 2) / (2 * 1e3), rel=1e-14)
    back = law.evaluate([[5e-3, 0.0, -1e-3]], history=off.history)      # no spike: starts unloaded
    assert np.allclose(back.force[0, :2], 0.0)


@pytest.mark.parametrize("method", ["exact", "radial"])
def test_accumulated_dissipation_nonnegative_on_a_random_walk(method):
    surface, adh, fri = CASES["plane-polar-fields"]
    rng = np.random.default_rng(6)
    xs = np.cumsum(rng.normal(size=(200, 4, 3)) * [3e-3, 3e-3, 0], axis=0) + [0.5, 0.5, -1e-3]
    law = ContactLaw(surface, adh, fri, 1e5, return_map=method)
    H = law.initial_history(4)
    for x in xs:
        st = law.evaluate(x, None, H, tangent=False)
        # the step's dissipation is the trapezoidal -(T_n + T)/2 . dxi_sl = D_BE + (T - T_n)/2 . dxi_sl with
        # the backward-Euler D_BE = -T . dxi_sl >= 0 of every map. The exact map's T maximises T* . C^-1 (T_tr - T)
        # over the (symmetric) friction ellipse, which holds T_n and -T_n, so its trapezoidal value is >= 0 too;
        # the radial map's can dip below zero by at most (T_n - T)/2 . dxi_sl in a reversal.
        T_n = np.where(H[:, 4:5] > 0.5, H[:, 0:2], 0.0)
        bound = 0.5 * np.einsum("ka,ka->k", st.traction - T_n, st.slip) if method == "radial" else 0.0
        assert np.all(st.dissipation >= np.minimum(bound, 0.0) - 1e-15)
        H = st.history
    assert np.all(H[:, 5] > 0)


KERNEL_MODULES = ("surfaces", "fields", "law", "contact", "validation", "reference", "scenes", "energy",
                  "calibration", "oracles", "fastpath", "output", "failure")


def test_kernels_do_not_import_exudyn():
    """No kernel module imports exudyn (only exudyn_glue, mainsystem and graphics do), and with
    Exudyn unavailable the package and every kernel still import."""
    import ast
    import exu_aniso
    root = os.path.dirname(exu_aniso.__file__)
    for name in KERNEL_MODULES:
        tree = ast.parse(open(os.path.join(root, name + ".py")).read())
        for node in ast.walk(tree):
            mods = ([a.name for a in node.names] if isinstance(node, ast.Import)
                    else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            assert not any(m.split(".")[0] == "exudyn" or m.endswith(("exudyn_glue", "mainsystem", "graphics"))
                           for m in mods), (name, mods)
    code = ("import sys\nsys.modules['exudyn'] = None   # import exudyn now raises ImportError\n"
            + "".join(f"import exu_aniso.{m}\n" for m in KERNEL_MODULES)
            + "import exu_aniso\nassert not hasattr(exu_aniso, '_mainsystem')\n")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_bad_arguments():
    with pytest.raises(TypeError, match="adhesion must be an Adhesion field"):
        ContactLaw(Plane(), Friction.isotropic(0.3), Friction.isotropic(0.3), 1.0)
    with pytest.raises(ValueError, match="normal_stiffness must be > 0"):
        ContactLaw(Plane(), Adhesion.isotropic(1.0), Friction.isotropic(0.3), -1.0)
    with pytest.raises(ValueError, match="normal_damping must be finite"):
        ContactLaw(Plane(), Adhesion.isotropic(1.0), Friction.isotropic(0.3), 1.0, normal_damping=math.inf)
    law = ContactLaw(Plane(), Adhesion.isotropic(1.0), Friction.isotropic(0.3), 1.0)
    with pytest.raises(ValueError, match="x must be finite"):
        law.evaluate([[0.0, float("nan"), 0.0]])
    with pytest.raises(ValueError, match=r"x must have shape \(K, 3\)"):
        law.evaluate([[0.0, 0.0]])


def test_isotropic_block_path_is_the_same_in_cartesian_and_polar_coordinates():
    """Covariance through the reference integrator: the papers' chart route in polar and in
    Cartesian plane coordinates and the transport route give the same block path."""
    from exu_aniso.reference import simulate_block
    from exu_aniso.scenes import BlockParams
    p = BlockParams(adhesion="isotropic", friction="isotropic", eps_1=2e4, mu_1=0.3, drive_angle=60.0,
                    drive_speed=0.2, t_end=0.3, dt=2e-3, x0=0.3, y0=0.1)
    K = 4
    paths = {}
    for name, plane, form in (("transport", Plane(), "transport"), ("cartesian", Plane("cartesian"), "chart"),
                              ("polar", Plane("polar"), "chart")):
        law = ContactLaw(plane, Adhesion.isotropic(p.eps_1 / K), Friction.isotropic(p.mu_1), p.eps_n / K,
                         return_map="exact", formulation=form)
        tr = simulate_block(p, law=law).trajectory
        paths[name] = np.c_[tr["x"], tr["y"], tr["theta"]]
    travel = np.ptp(paths["transport"][:, :2], axis=0).max()
    assert travel > 0.01                                    # it slid
    for name in ("cartesian", "polar"):
        np.testing.assert_allclose(paths[name], paths["transport"], rtol=0, atol=1e-8 * travel, err_msg=name)
