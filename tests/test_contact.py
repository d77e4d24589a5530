"""Contact set (exu_aniso.kernel.contact_law on the covariant kernel): consistent tangent against finite
differences on the plane (both charts) and the cylinder (hole and shaft), invariance under a change
of chart (polar vs Cartesian plane; the cylinder's seam phi = +-pi moved away by a rotation about its
axis), conventions, history, dissipation, imports."""
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from exu_aniso import OPEN, RETURN_MAPS, SLIP, STICK, Adhesion, ContactLaw, Cylinder, Friction, Plane
from _suite import covering

CASES = {
    "plane-polar-chart-polar-fields": (Plane("polar"), Adhesion.polar(1e4, 3e3, 0.01), Friction.polar(0.2, 0.6, 0.02)),
    "plane-cartesian-polar-fields": (Plane(), Adhesion.polar(1e4, 3e3, 0.01), Friction.polar(0.2, 0.6, 0.02)),
    "plane-cartesian": (Plane(), Adhesion.orthotropic(1e4, 1e3, 0.4), Friction.orthotropic(0.2, 0.6, -0.3)),
    "hole-spiral": (Cylinder(0.01, (0.001, 0.002, 0.0), (0.1, 0.2, 1.0)), Adhesion.spiral(1e4, 2e3, 0.2),
                    Friction.spiral(0.2, 0.5, 0.2)),
    "shaft-spiral": (Cylinder(0.01, side="outside"), Adhesion.spiral(1e4, 2e3, 0.2), Friction.spiral(0.2, 0.5, 0.2)),
}


def contact_sample(surface, rng, K=6):
    """Penetrating slave points (depth 1e-4 to 1e-3 m on the plane, 1e-4 R on the cylinder) with an
    active history anchored near their closest points (mixed stick and slip)."""
    if isinstance(surface, Cylinder):
        xi = np.c_[rng.uniform(-3.1, 3.1, K), rng.uniform(-1, 1, K) * surface.radius]
        depth = np.full(K, 1e-2 * surface.radius)
    elif surface.coordinates == "polar":
        xi = np.c_[rng.uniform(0.05, 1.4, K), rng.uniform(-3.1, 3.1, K)]
        depth = rng.uniform(1e-4, 1e-3, K)
    else:
        xi = rng.uniform(-1, 1, (K, 2))
        depth = rng.uniform(1e-4, 1e-3, K)
    x = np.array([surface.at(q).point - d * surface.at(q).n for q, d in zip(xi, depth)])
    H = ContactLaw.initial_history(K)
    H[:, 0:2] = rng.normal(size=(K, 2)) * 10
    H[:, 2:4] = xi + rng.normal(size=(K, 2)) * 1e-3
    H[:, 4] = 1.0
    return x, rng.normal(size=(K, 3)) * 0.1, H


@pytest.mark.parametrize("case,method", covering([(c, m) for c in CASES for m in RETURN_MAPS], [0, 1]))
def test_consistent_tangent_against_finite_differences(case, method):
    """df/dx and df/dv of ContactLaw.evaluate against central differences of its force (history
    fixed) on the plane and the cylinder; tests/test_kernel.py does the same on curved surfaces."""
    surface, adh, fri = CASES[case]
    law = ContactLaw(surface, adh, fri, 1e5, normal_damping=10.0, return_map=method)
    rng = np.random.default_rng(sum(map(ord, case)))
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
    """Evaluate the path xs (n, K, 3) step by step from a fresh history: forces, statuses, histories."""
    H = law.initial_history(xs.shape[1])
    forces, status, hist = [], [], []
    for x in xs:
        st = law.evaluate(x, None, H, tangent=False)
        H = st.history
        forces.append(st.force)
        status.append(st.status)
        hist.append(H)
    return np.array(forces), np.array(status), np.array(hist)


def smooth_path(n):
    """Three points on the plane at r = 0.4 to 0.7, each oscillating 1 mm back and forth along a
    slowly turning direction while drifting 1 mm: stick at the reversals, slip in between; n steps."""
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    c = np.array([[0.5, 0.2], [-0.3, 0.6], [0.1, -0.4]])
    ang = np.array([0.3, 2.0, -1.2])
    amp = 1e-3 * np.sin(2 * np.pi * t)[..., None]
    xy = (c + amp * np.stack([np.cos(ang + 3 * t), np.sin(ang + 3 * t)], -1)
          + 1e-3 * t[..., None] * np.stack([np.cos(ang + 1), np.sin(ang + 1)], -1))
    return np.concatenate([xy, np.full(xy.shape[:2] + (1,), -1e-4)], -1)


# the polar fields' laws on both charts are compiled by other tests of the default run, the isotropic
# fields' on the polar chart by none: one map of those by default, -m slow the others
@pytest.mark.parametrize("method,fields", [
    pytest.param(m, f, marks=(pytest.mark.slow,) if f == "isotropic" and m != "exact" else (), id=f"{f}-{m}")
    for f in ("isotropic", "polar") for m in RETURN_MAPS])
def test_polar_and_cartesian_charts_of_the_plane_give_the_same_forces(method, fields):
    """Invariance under a change of chart: the plane in polar coordinates (Christoffel symbols,
    midpoint transport and slip) and in Cartesian coordinates (exact: the chart is the transport
    frame) give the same states and forces along a path with stick and slip. The polar chart's
    transport and slip are second-order rules, so the forces agree up to O(step^2): the difference
    falls by 4 per halved step (measured orders 1.94 to 2.0) and is < 1e-9 of the force at 200 steps."""
    if fields == "isotropic":
        adh, fri = Adhesion.isotropic(1e4), Friction.isotropic(0.3)
    else:
        adh, fri = Adhesion.polar(1e4, 1e3), Friction.polar(0.2, 0.6)
    errs = []
    for n in (50, 100, 200):
        xs = smooth_path(n)
        ref, s_ref, _ = walk(ContactLaw(Plane("cartesian"), adh, fri, 1e5, return_map=method), xs)
        out, s_out, _ = walk(ContactLaw(Plane("polar"), adh, fri, 1e5, return_map=method), xs)
        np.testing.assert_array_equal(s_out, s_ref)
        assert np.any(s_ref == STICK) and np.any(s_ref == SLIP)
        errs.append(np.abs(out - ref).max() / np.abs(ref).max())
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(orders > 1.8) and errs[-1] < 1e-9, (errs, orders)


@pytest.mark.parametrize("method", RETURN_MAPS)
def test_sliding_across_the_cylinder_seam_equals_sliding_away_from_it(method):
    """The seam of the cylinder's chart (phi = +-pi, on the -x side) is no place of the surface: a
    path of a hole's slave points wandering across it gives the forces of the same path turned by
    pi about the axis (which maps the cylinder and its spiral field onto themselves, and takes the
    path to phi ~ 0), turned back; the anchors, unwrapped across the seam, advance the same."""
    rng = np.random.default_rng(4)
    cyl = Cylinder(0.01)
    phis = np.cumsum(rng.normal(size=(80, 3)) * 0.05, axis=0) + np.linspace(3.0, 3.2, 3)
    xs = np.stack([0.0101 * np.cos(phis), 0.0101 * np.sin(phis), np.cumsum(rng.normal(size=(80, 3)) * 1e-4, 0)], -1)
    assert np.any(np.abs(np.angle(np.exp(1j * phis))) > 3.1) and np.ptp(np.sign(np.sin(phis))) == 2  # crosses it
    turn = np.diag([-1.0, -1.0, 1.0])                   # rotation by pi about the axis
    adh, fri = Adhesion.spiral(1e4, 1e5, 0.3), Friction.spiral(0.2, 0.6, 0.3)
    law = ContactLaw(cyl, adh, fri, 1e5, return_map=method)
    across, s_across, H_across = walk(law, xs)
    away, s_away, H_away = walk(law, xs @ turn.T)
    np.testing.assert_array_equal(s_across, s_away)
    assert np.any(s_across == STICK) and np.any(s_across == SLIP)
    np.testing.assert_allclose(across, away @ turn.T, rtol=0, atol=1e-11 * np.abs(away).max())
    d_across = H_across[:, :, 2:4] - H_across[0, :, 2:4]
    d_away = H_away[:, :, 2:4] - H_away[0, :, 2:4]
    np.testing.assert_allclose(d_across, d_away, rtol=0, atol=1e-12)
    assert np.abs(d_across[:, :, 0]).max() < 1.0                # no jump of 2 pi at the seam


def test_many_points_at_once_equal_one_at_a_time():
    surface, adh, fri = CASES["plane-polar-chart-polar-fields"]
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
    assert st3.history[0, 6] == pytest.approx(0.099 - 4.0 / 1e3, rel=1e-12)   # slip distance
    hole = ContactLaw(Cylinder(1.0), Adhesion.isotropic(1.0), Friction.isotropic(0.5), 10.0)
    assert np.allclose(hole.evaluate([[1.1, 0, 0]]).force[0], [-1.0, 0, 0])                  # towards the axis
    shaft = ContactLaw(Cylinder(1.0, side="outside"), Adhesion.isotropic(1.0), Friction.isotropic(0.5), 10.0)
    assert np.allclose(shaft.evaluate([[0, 0.9, 0]]).force[0], [0, 1.0, 0])                  # away from it
    back = ContactLaw(Plane(side="back"), Adhesion.isotropic(1.0), Friction.isotropic(0.5), 10.0)
    assert np.allclose(back.evaluate([[0.3, 0.2, 0.1]]).force[0], [0, 0, -1.0])              # slave below z = 0


def test_contact_lost_and_regained_resets_the_history():
    law = ContactLaw(Plane(), Adhesion.isotropic(1e3), Friction.isotropic(0.5), 1e4)
    H = law.evaluate([[0.0, 0.0, -1e-3]]).history
    H = law.evaluate([[2e-3, 0.0, -1e-3]], history=H).history
    assert H[0, 0] != 0.0 and H[0, 4] == 1.0
    off = law.evaluate([[3e-3, 0.0, 1e-3]], history=H)
    assert off.status[0] == OPEN and np.all(off.force == 0) and np.all(off.history[0, :5] == 0.0)
    # dissipation kept, plus the spring energy T^2 / (2 eps_T) that the reset lets go
    assert off.history[0, 5] == pytest.approx(H[0, 5] + (H[0, 0] ** 2 + H[0, 1] ** 2) / (2 * 1e3), rel=1e-14)
    assert off.history[0, 5] == pytest.approx(H[0, 5] + law.released_energy(H)[0], rel=1e-14)
    back = law.evaluate([[5e-3, 0.0, -1e-3]], history=off.history)      # no spike: starts unloaded
    assert np.allclose(back.force[0, :2], 0.0)


def test_released_energy_is_the_adhesion_springs_energy_at_each_rows_anchor():
    """The ledger's stored tangential energy of history rows (one compiled pass): T . C^-1 T / 2 with
    C = -B of the net at each row's anchor (law.return_maps.elastic_energy on the net's components),
    0 for a row not in contact; a curved surface and an orthotropic net whose axes turn along it."""
    from exu_aniso.law.return_maps import elastic_energy
    law = ContactLaw(Cylinder(0.5), Adhesion.orthotropic(3e3, 2e2, angle=0.4), Friction.isotropic(0.3), 1e4)
    rng = np.random.default_rng(7)
    H = np.zeros((40, 9))
    H[:, 0:2] = rng.normal(size=(40, 2))                                   # traction
    H[:, 2], H[:, 3] = rng.uniform(-3.0, 3.0, 40), rng.uniform(-1.0, 1.0, 40)   # anchor (angle, axial)
    H[:, 4] = rng.uniform(size=40) > 0.3                                  # active
    B = law.adhesion_components(H[:, 2:4])
    expected = np.where(H[:, 4] > 0.5, elastic_energy((H[:, 0], H[:, 1]), (B[:, 0], B[:, 1], B[:, 2])), 0.0)
    assert np.any(H[:, 4] == 0.0) and np.all(expected >= 0.0)
    np.testing.assert_allclose(law.released_energy(H), expected, rtol=1e-13, atol=0.0)
    np.testing.assert_allclose(law.released_energy(np.asfortranarray(H)), expected, rtol=1e-13, atol=0.0)


@pytest.mark.parametrize("method", ["exact", "radial"])
def test_accumulated_dissipation_nonnegative_on_a_random_walk(method):
    """The step's dissipation is the trapezoidal -(T_n + T)/2 . s (s the slip increment) =
    D_BE + (T - T_n)/2 . s with the backward-Euler D_BE = -T . s >= 0 of every map. The exact map's
    T maximises T* . C^-1 (T_tr - T) over the (symmetric) friction ellipse, which holds T_n and -T_n,
    so its trapezoidal value is >= 0 too; the radial map's can dip below zero by at most
    |T - T_n| |s| / 2 in a reversal (|s| is the step's slip distance; on the Cartesian plane T_n
    needs no transport)."""
    _, adh, fri = CASES["plane-cartesian-polar-fields"]
    rng = np.random.default_rng(6)
    xs = np.cumsum(rng.normal(size=(200, 4, 3)) * [3e-3, 3e-3, 0], axis=0) + [0.5, 0.5, -1e-3]
    law = ContactLaw(Plane(), adh, fri, 1e5, return_map=method)
    H = law.initial_history(4)
    for x in xs:
        st = law.evaluate(x, None, H, tangent=False)
        T_n = np.where(H[:, 4:5] > 0.5, H[:, 0:2], 0.0)
        ds = st.history[:, 6] - H[:, 6]
        bound = -0.5 * np.linalg.norm(st.traction - T_n, axis=1) * ds if method == "radial" else 0.0
        assert np.all(st.dissipation >= bound - 1e-15)
        H = st.history
    assert np.all(H[:, 5] > 0)


# the modules that talk to Exudyn: its adapter, the model scripts and what runs them (the command line,
# its catalog, the calibration that fits a scene on either engine)
EXUDYN_PARTS = ("engines.exudyn_adapter", "models", "cli", "catalog", "calibration")


def _package_modules():
    """Dotted names (relative to exu_aniso) of every module of the package."""
    import exu_aniso
    root = os.path.dirname(exu_aniso.__file__)
    out = []
    for folder, _, files in os.walk(root):
        for f in sorted(files):
            if f.endswith(".py"):
                rel = os.path.relpath(os.path.join(folder, f), root)[:-3].replace(os.sep, ".")
                out.append(rel[:-len(".__init__")] if rel.endswith(".__init__") else rel)
    return root, sorted(m for m in out if m != "__init__")


def test_kernels_do_not_import_exudyn():
    """No module outside Exudyn's adapter, the model scripts and the command line imports exudyn or
    the adapter, and with Exudyn unavailable the package and every such module still import."""
    import ast
    root, modules = _package_modules()
    kernel_modules = [m for m in modules if not m.startswith(EXUDYN_PARTS)]
    assert {"geometry.core", "kernel.point", "kernel.sets", "engines.reference", "scenes.base"} <= set(kernel_modules)
    for name in kernel_modules:
        path = os.path.join(root, *name.split("."))
        tree = ast.parse(open(os.path.join(path, "__init__.py") if os.path.isdir(path) else path + ".py").read())
        for node in ast.walk(tree):
            mods = ([a.name for a in node.names] if isinstance(node, ast.Import)
                    else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            assert not any(m.split(".")[0] == "exudyn" or m.startswith(("exu_aniso.engines.exudyn_adapter",
                                                                         "exu_aniso.models"))
                           for m in mods), (name, mods)
    code = ("import sys\nsys.modules['exudyn'] = None   # import exudyn now raises ImportError\n"
            + "".join(f"import exu_aniso.{m}\n" for m in kernel_modules)
            + "import exu_aniso\nassert not hasattr(exu_aniso, '_mainsystem')\n")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_bad_arguments():
    with pytest.raises(TypeError, match="adhesion must be an Adhesion field"):
        ContactLaw(Plane(), Friction.isotropic(0.3), Friction.isotropic(0.3), 1.0)
    with pytest.raises(TypeError, match="surface must be a surface of exu_aniso"):
        ContactLaw("plane", Adhesion.isotropic(1.0), Friction.isotropic(0.3), 1.0)
    with pytest.raises(ValueError, match="normal_stiffness must be > 0"):
        ContactLaw(Plane(), Adhesion.isotropic(1.0), Friction.isotropic(0.3), -1.0)
    with pytest.raises(ValueError, match="normal_damping must be finite"):
        ContactLaw(Plane(), Adhesion.isotropic(1.0), Friction.isotropic(0.3), 1.0, normal_damping=math.inf)
    law = ContactLaw(Plane(), Adhesion.isotropic(1.0), Friction.isotropic(0.3), 1.0)
    with pytest.raises(ValueError, match="x must be finite"):
        law.evaluate([[0.0, float("nan"), 0.0]])
    with pytest.raises(ValueError, match=r"x must have shape \(K, 3\)"):
        law.evaluate([[0.0, 0.0]])


def test_block_path_is_the_same_in_cartesian_and_polar_coordinates():
    """Covariance through the reference integrator: the block slides the same path on the plane in
    polar and in Cartesian coordinates. The polar chart's transport and slip rules are second order
    in the step, so the paths differ by O(dt^2): the difference falls by ~4 when dt halves (measured
    3.3e-7 and 8.4e-8 of the travel) and stays far below the integrator's own error (the path at dt
    against dt/2: 1.9e-4 of the travel)."""
    from exu_aniso.scenes.block import simulate_block
    from exu_aniso.scenes.block import BlockParams
    K = 4
    diff, paths = [], {}
    for dt in (2e-3, 1e-3):
        p = BlockParams(adhesion="isotropic", friction="isotropic", eps_1=2e4, mu_1=0.3, drive_angle=60.0,
                        drive_speed=0.2, t_end=0.3, dt=dt, x0=0.3, y0=0.1)
        for chart in ("cartesian", "polar"):
            law = ContactLaw(Plane(chart), Adhesion.isotropic(p.eps_1 / K), Friction.isotropic(p.mu_1), p.eps_n / K,
                             return_map="exact")
            tr = simulate_block(p, law=law).trajectory
            paths[chart, dt] = np.c_[tr["x"], tr["y"], tr["theta"]]
        diff.append(np.abs(paths["polar", dt] - paths["cartesian", dt]).max())
    travel = np.ptp(paths["cartesian", 1e-3][:, :2], axis=0).max()
    assert travel > 0.01                                    # it slid
    time_error = np.abs(paths["cartesian", 1e-3][::2] - paths["cartesian", 2e-3]).max()
    assert math.log2(diff[0] / diff[1]) > 1.8, diff
    assert diff[1] < 1e-6 * travel and diff[1] < 1e-2 * time_error, (diff, time_error, travel)


def test_a_law_changed_or_pickled_after_its_first_evaluation_runs_its_own_parameters():
    """ContactLaw keeps its compiled law's call between evaluations: a parameter changed afterwards
    gets a new one (the normal force doubles with eps_N: N = eps_N |xi3|), and a pickled law, whose
    addresses belong to the process that made them, makes its own."""
    import pickle
    law = ContactLaw(Plane(), Adhesion.isotropic(1e4), Friction.isotropic(0.3), 1e5)
    x = np.array([[0.1, 0.2, -1e-4]])
    assert law.evaluate(x).force[0, 2] == pytest.approx(10.0, rel=1e-12)
    law.eps_N = 2e5
    assert law.evaluate(x).force[0, 2] == pytest.approx(20.0, rel=1e-12)
    copy = pickle.loads(pickle.dumps(law))
    assert copy._call is None
    np.testing.assert_array_equal(copy.evaluate(x).force, law.evaluate(x).force)
