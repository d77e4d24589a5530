"""Oracle tests of the numpy reference (exu_aniso.engines.reference) and the scene parameters (exu_aniso.scenes.base).

Analytic oracles first (harmonic solutions, Coulomb sliding, anisotropic steady sliding, thread
pitch), then model-vs-model checks (planar vs full block, reduced vs full screw), then the
integrator mechanics (convergence order, step rejection, Jacobian). Fast: the file runs in ~20 s.
"""
import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.optimize import brentq

from exu_aniso.scenes.block import orthotropic_heading
from exu_aniso.engines.reference import jacobian_check
from exu_aniso.scenes import block as block_scene
from exu_aniso.scenes import screw as screw_scene
from exu_aniso.scenes.block import simulate_block
from exu_aniso.scenes.screw import simulate_screw
from exu_aniso.scenes.block import BlockParams, block_points
from exu_aniso.scenes.screw import ScrewParams, pitch, screw_points

# ----------------------------------------------------------------------------------------------
# convergence order on smooth (stick-only, constant B) cases against the analytic solution


def _forced_oscillator(t, k_drive, k_contact, inertia, speed):
    """x'' m = k_d (s t - x) - k_c x, x(0) = x'(0) = 0  ->  x = A t - A/w sin(w t)."""
    A = k_drive * speed / (k_drive + k_contact)
    w = math.sqrt((k_drive + k_contact) / inertia)
    return A * t - A / w * np.sin(w * t)


def _rate(dts, errs):
    return np.polyfit(np.log(dts), np.log(errs), 1)[0]


@pytest.mark.parametrize("solver", ["trapezoidal", "generalized_alpha"])
def test_convergence_order_block_planar(solver):
    """Block pulled through a drive spring, isotropic stick (mu huge): a forced harmonic
    oscillator along the drive direction; the integrator must be second order."""
    dts = [4e-3, 2e-3, 1e-3, 5e-4]
    errs = []
    for dt in dts:
        p = BlockParams(adhesion="isotropic", eps_1=1e3, friction="isotropic", mu_1=10.0, drive="displacement",
                        drive_stiffness=1e3, drive_speed=0.1, drive_angle=90.0, t_end=0.2, dt=dt, solver=solver)
        tr = simulate_block(p).trajectory
        exact = _forced_oscillator(tr["t"], p.drive_stiffness, p.eps_1, p.mass, p.drive_speed)
        errs.append(np.max(np.abs(tr["y"] - p.y0 - exact)))
        assert np.max(np.abs(tr["x"] - p.x0)) < 1e-12      # no transverse motion
    rate = _rate(dts, errs)
    print(f"block planar {solver}: errors {errs}, observed order {rate:.3f}")
    assert rate > 1.8, f"observed order {rate:.3f}"


@pytest.mark.parametrize("model", ["reduced", "full"])
def test_convergence_order_screw_rotation(model):
    """Screw turned through a torsional spring, isotropic stick: J psi'' = k (w t - psi) - k_c psi
    with k_c = eps_1 R^2 (traction eps_1 R dpsi from the slip of the contact point on the hole, acting
    there: lever arm R, the work-conjugate convention of surfaces.Frame).
    The full model exercises the Lie-group (rotation-vector increment) integrator."""
    dts = [2e-4, 1e-4, 5e-5, 2.5e-5]
    errs = []
    for dt in dts:
        p = ScrewParams(adhesion="isotropic", eps_1=1e4, friction="isotropic", mu_1=10.0, drive="rotation",
                        t_end=0.01, dt=dt, model=model)
        tr = simulate_screw(p).trajectory
        kc = p.eps_1 * p.radius ** 2
        exact = _forced_oscillator(tr["t"], p.drive_stiffness, kc, 0.5 * p.mass * p.radius ** 2, p.rotation_speed)
        errs.append(np.max(np.abs(tr["angle"] - exact)))
        assert np.max(np.abs(tr["z"])) < 1e-12
    rate = _rate(dts, errs)
    print(f"screw {model}: errors {errs}, observed order {rate:.3f}")
    assert rate > 1.8, f"observed order {rate:.3f}"


def test_convergence_order_block_full_self():
    """Full 6-DOF block (drive force at the COM tilts it slightly, so the planar analytic solution
    does not hold exactly): self-convergence against a fine solution, second order."""
    def run(dt):
        p = BlockParams(adhesion="isotropic", eps_1=1e3, friction="isotropic", mu_1=10.0, drive="displacement",
                        drive_stiffness=1e3, drive_speed=0.1, t_end=0.05, dt=dt, model="full")
        return simulate_block(p)
    ref = run(2.5e-5)
    dts = [8e-4, 4e-4, 2e-4, 1e-4]
    errs = []
    for dt in dts:
        r = run(dt)
        errs.append(max(abs(r.summary[k] - ref.summary[k]) for k in ("x_end", "y_end", "theta_end"))
                    + abs(r.trajectory["z"][-1] - ref.trajectory["z"][-1]))
    rate = _rate(dts, errs)
    print(f"block full: errors {errs}, observed order {rate:.3f}")
    assert rate > 1.8, f"observed order {rate:.3f}"


# ----------------------------------------------------------------------------------------------
# isotropic Coulomb


def test_coulomb_stick_below_limit():
    """P < mu m g / 2 (so that the undamped elastic overshoot 2P stays below the limit): the
    block only oscillates elastically, x = P / eps_T (1 - cos(w t)), w = sqrt(eps_T / m), with
    eps_T the TOTAL tangential stiffness; no slip."""
    P, eps = 1.0, 1e5
    p = BlockParams(adhesion="isotropic", eps_1=eps, friction="isotropic", mu_1=0.3, drive="force", force=P,
                    drive_angle=0.0, t_end=0.05, dt=1e-4)
    r = simulate_block(p)
    tr = r.trajectory
    u = tr["x"] - p.x0
    exact = P / eps * (1.0 - np.cos(math.sqrt(eps / p.mass) * tr["t"]))
    assert np.max(np.abs(u - exact)) < 1e-2 * P / eps
    mid = 0.5 * (u.max() + u.min())
    assert abs(mid - P / eps) < 1e-3 * P / eps, (mid, P / eps)
    assert r.summary["slip_distance"] == 0.0 and r.summary["dissipated_energy"] == 0.0


@pytest.mark.parametrize("return_map", ["exact", "radial", "seed"])
def test_coulomb_slide_above_limit(return_map):
    """P > mu m g: after the elastic onset the block accelerates at (P - mu m g)/m along the pull."""
    P, mu = 5.0, 0.3
    p = BlockParams(adhesion="isotropic", eps_1=1e5, friction="isotropic", mu_1=mu, drive="force", force=P,
                    drive_angle=30.0, return_map=return_map, t_end=0.5, dt=1e-3)
    r = simulate_block(p)
    tr = r.trajectory
    late = tr["t"] > 0.1
    ax = np.polyfit(tr["t"][late], tr["vx"][late], 1)[0]
    ay = np.polyfit(tr["t"][late], tr["vy"][late], 1)[0]
    a_exact = (P - mu * p.normal_load) / p.mass
    assert abs(math.hypot(ax, ay) / a_exact - 1.0) < 1e-3, (math.hypot(ax, ay), a_exact)
    assert abs(r.summary["heading_deg"] - 30.0) < 1e-6


# ----------------------------------------------------------------------------------------------
# orthotropic friction, exact map: steady anisotropic Coulomb sliding


def test_orthotropic_exact_steady_direction():
    """Constant F (mu_1 = 0.2 along x, mu_2 = 0.6 along y), isotropic adhesion, exact map, pull at
    45 deg from rest. The velocity direction v is where pull + friction is parallel to v, with
    friction -|N| F^-1 v / sqrt(v.F^-1 v); the acceleration is (pull + friction).v / m."""
    P, N, mu1, mu2, m = 10.0, 9.81, 0.2, 0.6, 1.0
    Finv = np.diag([mu1 ** 2, mu2 ** 2])
    pull = P * np.array([math.cos(math.pi / 4), math.sin(math.pi / 4)])

    def friction(phi):
        v = np.array([math.cos(phi), math.sin(phi)])
        return -N * Finv @ v / math.sqrt(v @ Finv @ v)

    def cross(phi):
        net = pull + friction(phi)
        return net[0] * math.sin(phi) - net[1] * math.cos(phi)

    phi = brentq(cross, 1e-6, math.pi / 2 - 1e-6)
    assert phi == pytest.approx(orthotropic_heading(math.pi / 4, P, N, mu1, mu2), abs=1e-9)   # shared oracle
    v = np.array([math.cos(phi), math.sin(phi)])
    a_exact = (pull + friction(phi)) @ v / m

    p = BlockParams(adhesion="isotropic", eps_1=1e5, friction="orthotropic", mu_1=mu1, mu_2=mu2, friction_angle=0.0,
                    return_map="exact", drive="force", force=P, drive_angle=45.0, normal_load=N, mass=m,
                    t_end=1.0, dt=1e-3)
    r = simulate_block(p)
    tr = r.trajectory
    late = tr["t"] > 0.5
    heading = np.degrees(np.arctan2(tr["vy"][late], tr["vx"][late]))
    ax = np.polyfit(tr["t"][late], tr["vx"][late], 1)[0]
    ay = np.polyfit(tr["t"][late], tr["vy"][late], 1)[0]
    print(f"steady direction {math.degrees(phi):.4f} deg, simulated {r.summary['heading_deg']:.4f} deg; "
          f"acceleration {a_exact:.6f}, simulated {math.hypot(ax, ay):.6f}")
    assert np.max(np.abs(heading - math.degrees(phi))) < 0.05
    assert abs(math.hypot(ax, ay) / a_exact - 1.0) < 1e-3
    assert abs(r.summary["theta_end"]) < 1e-9        # symmetric corners: no spin


# ----------------------------------------------------------------------------------------------
# polar orthotropy


def test_polar_equal_stiffness_is_isotropic():
    """eps_r = eps_phi and mu_r = mu_phi: the polar law is isotropic; the dragged block moves on a
    straight line and matches the Cartesian isotropic run (covariance)."""
    common = dict(eps_1=1e4, eps_2=1e4, mu_1=0.3, mu_2=0.3, return_map="radial", t_end=1.0, dt=1e-3)
    polar = simulate_block(BlockParams(adhesion="polar", friction="polar", **common))
    iso = simulate_block(BlockParams(adhesion="isotropic", friction="isotropic", **common))
    a, b = polar.trajectory, iso.trajectory
    assert np.max(np.abs(a["x"] - a["x"][0])) < 1e-12          # straight path along y
    for k in ("x", "y", "theta", "vx", "vy"):
        np.testing.assert_allclose(a[k], b[k], rtol=0, atol=1e-11, err_msg=f"mismatch: {k}")
    assert polar.summary["y_end"] > 0.05                          # it did slide


def test_polar_orthotropy_bends_path_to_circle():
    """Default block: stiff radial, soft circumferential adhesion with the radial map: the path
    bends onto the circle about the origin instead of going straight along the drive (y)."""
    r = simulate_block(BlockParams())
    s = r.summary
    print(s)
    assert s["r_max"] - s["r_min"] < 1e-3 * s["r_mean"]
    assert math.atan2(s["y_end"], s["x_end"]) > 0.3               # > 17 deg of arc
    assert s["x_end"] < 0.5 - 0.02                                # visibly bent
    assert abs(s["theta_end"] - math.atan2(s["y_end"], s["x_end"])) < 0.02   # turns with the frame


# ----------------------------------------------------------------------------------------------
# step rejection, Jacobian


def test_step_rejection_leaves_no_trace():
    """A rejected step (solved to convergence, then thrown away) must not touch the history:
    rejecting steps == directly halving them, to round-off; and both agree with the plain run
    to integration tolerance (well inside the change under global step halving)."""
    rs = [10, 50, 120, 200, 250]
    p = BlockParams(t_end=0.3)
    plain = simulate_block(p)
    rejected = simulate_block(p, reject_steps=rs)
    split = simulate_block(p, split_steps=rs)
    fine = simulate_block(p.with_overrides(dt=0.5 * p.dt))
    assert rejected.info["rejected_steps"] == len(rs)
    assert rejected.summary["steps"] == plain.summary["steps"] + len(rs)
    for k in ("x_end", "y_end", "theta_end", "vx_end", "vy_end", "dissipated_energy", "slip_distance"):
        assert abs(rejected.summary[k] - split.summary[k]) <= 1e-13 * (1 + abs(split.summary[k])), k
        diff, tol = abs(rejected.summary[k] - plain.summary[k]), abs(fine.summary[k] - plain.summary[k])
        assert diff <= 0.2 * tol + 1e-14, (k, diff, tol)
    sr = simulate_screw(ScrewParams(t_end=0.1), reject_steps=[5, 40])
    ss = simulate_screw(ScrewParams(t_end=0.1), split_steps=[5, 40])
    assert abs(sr.summary["z_end"] - ss.summary["z_end"]) <= 1e-15
    assert abs(sr.summary["angle_end"] - ss.summary["angle_end"]) <= 1e-13


@pytest.mark.parametrize("params", [
    BlockParams(), BlockParams(model="full"),
    BlockParams(model="full", return_map="exact", adhesion="orthotropic", adhesion_angle=30.0, friction="orthotropic",
                mu_2=0.6),
    BlockParams(return_map="seed"), ScrewParams(), ScrewParams(model="full"),
    ScrewParams(model="full", return_map="exact", drive="axial", drive_stiffness=1e3, solver="generalized_alpha"),
    BlockParams(normal_damping=3.0, tangential_damping=5.0),
    BlockParams(model="full", normal_damping=30.0, tangential_damping=5.0),
    ScrewParams(model="full", tangential_damping=1.0),
], ids=["block-planar", "block-full", "block-full-exact", "block-planar-seed", "screw-reduced", "screw-full",
       "screw-full-axial", "block-planar-damped", "block-full-damped", "screw-full-damped"])
def test_analytic_jacobian_matches_differences(params):
    """The analytic Newton Jacobian (contact tangent through the point Jacobians, moment geometry,
    drive springs, SO(3) right Jacobian) equals central differences of the residual mid-run."""
    for steps in (3, 150):
        scene = block_scene if isinstance(params, BlockParams) else screw_scene
        _, _, err = jacobian_check(*scene.reference_model(params), params, steps)
        assert err < 1e-5, (steps, err)


def test_numerical_jacobian_same_solution():
    """jacobian='numerical' converges to the same trajectory (it only changes the iterations)."""
    p = BlockParams(t_end=0.2, model="full")
    a, b = simulate_block(p), simulate_block(p, jacobian="numerical")
    print(f"Newton iterations analytic {a.summary['newton_iterations']}, numerical {b.summary['newton_iterations']}")
    assert abs(a.summary["y_end"] - b.summary["y_end"]) < 1e-10
    assert a.summary["newton_iterations"] <= b.summary["newton_iterations"]


# ----------------------------------------------------------------------------------------------
# models agree where their assumptions hold


def test_block_planar_vs_full():
    """Planar (held normal load) and full 6-DOF block agree: the full block only tilts by ~1e-4 rad."""
    p = BlockParams(t_end=1.0)
    a, b = simulate_block(p), simulate_block(p.with_overrides(model="full"))
    travel = math.hypot(a.summary["x_end"] - p.x0, a.summary["y_end"] - p.y0)
    for k in ("x_end", "y_end"):
        assert abs(a.summary[k] - b.summary[k]) < 2e-3 * travel, (k, a.summary[k], b.summary[k])
    assert abs(a.summary["theta_end"] - b.summary["theta_end"]) < 2e-3 * abs(a.summary["theta_end"])
    assert abs(a.summary["dissipated_energy"] / b.summary["dissipated_energy"] - 1) < 5e-3
    assert np.max(b.trajectory["tilt"]) < 1e-3


def test_screw_reduced_vs_full():
    p = ScrewParams(t_end=0.4, axial_load=-0.5)
    a, b = simulate_screw(p), simulate_screw(p.with_overrides(model="full"))
    for k in ("angle_end", "z_end", "dissipated_energy"):
        assert abs(a.summary[k] - b.summary[k]) <= 1e-9 * (1 + abs(a.summary[k])), k
    assert np.max(np.hypot(b.trajectory["x"], b.trajectory["y"])) < 1e-9


# ----------------------------------------------------------------------------------------------
# screw oracles


def test_screw_isotropic_torque_does_not_advance():
    """Isotropic B and F, pure torque above the sliding torque: the screw spins but does not advance."""
    p = ScrewParams(adhesion="isotropic", friction="isotropic", eps_1=1e5, mu_1=0.3, drive="torque", torque=0.2,
                    mass=1.0, t_end=0.1, dt=1e-4)
    r = simulate_screw(p)
    assert r.summary["angle_end"] > 2 * math.pi
    assert np.max(np.abs(r.trajectory["z"])) < 1e-12


def test_screw_thread_limit_advances_one_pitch_per_turn():
    """eps_2 >> eps_1 (thread stiff across the helix), high cross friction, radial map, turned by
    the rotation drive: advance per revolution -> pitch 2 pi R tan(alpha)."""
    p = ScrewParams(eps_1=1e4, eps_2=1e7, mu_2=1.0, return_map="radial", drive="rotation", t_end=1.0)
    r = simulate_screw(p)
    ratio = r.summary["advance_per_rev"] / pitch(p)
    print(f"advance per rev {r.summary['advance_per_rev']:.6e} m, pitch {pitch(p):.6e} m, ratio {ratio:.5f}")
    assert abs(ratio - 1.0) < 0.05
    assert r.summary["angle_end"] > 0.9 * 2 * math.pi


def test_screw_default_advances():
    r = simulate_screw(ScrewParams(t_end=0.5))
    assert r.summary["z_end"] > 0.3 * pitch(ScrewParams()) * r.summary["angle_end"] / (2 * math.pi)
    assert r.summary["dissipated_energy"] > 0


# ----------------------------------------------------------------------------------------------
# parameters


def test_params_validation_messages():
    for bad, words in [(dict(mass="-1"), "mass"), (dict(dt="nan"), "dt"), (dict(eps_n="inf"), "eps_n"),
                       (dict(t_end=0), "t_end"), (dict(dt=5.0), "dt"), (dict(adhesion="spiral"), "adhesion"),
                       (dict(points="grid:1"), "points"), (dict(bogus=1), "bogus"), (dict(mu_1=-0.1), "mu_1")]:
        with pytest.raises(ValueError, match=words):
            BlockParams.from_strings(bad)
    with pytest.raises(ValueError, match="helix_angle"):
        ScrewParams().with_overrides(helix_angle=90)
    with pytest.raises(ValueError, match="rings"):
        ScrewParams().with_overrides(rings="2.5")
    assert ScrewParams.from_strings({"rotation_speed": "4*pi"}).rotation_speed == pytest.approx(4 * math.pi)


def test_point_layouts_and_total_stiffness():
    assert block_points(BlockParams(points="center")).shape == (1, 3)
    g = block_points(BlockParams(points="grid:3"))
    assert g.shape == (9, 3) and np.all(g[:, 2] == -0.05) and np.max(np.abs(g[:, :2])) == 0.05
    s = screw_points(ScrewParams(rings=2, points_per_ring=5))
    assert s.shape == (10, 3)
    np.testing.assert_allclose(np.hypot(s[:, 0], s[:, 1]), 0.005 + 1e-5)
    # total stiffness is independent of the layout: same sticking response for 4 and 9 points
    runs = [simulate_block(BlockParams(points=pts, adhesion="isotropic", friction="isotropic", mu_1=10.0,
                                       t_end=0.05)) for pts in ("corners", "grid:3")]
    assert abs(runs[0].summary["y_end"] - runs[1].summary["y_end"]) < 1e-12


def test_reference_runs_without_exudyn():
    """The standalone reference needs numpy and scipy only: with Exudyn unavailable (import exudyn
    raises ImportError) it still simulates a scene."""
    code = ("import sys\nsys.modules['exudyn'] = None\n"
            "from exu_aniso.scenes.block import simulate_block\nfrom exu_aniso.scenes.block import BlockParams\n"
            "r = simulate_block(BlockParams(t_end=0.01))\nprint(r.summary['steps'], 'exudyn' in sys.modules "
            "and sys.modules['exudyn'] is not None)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["10", "False"]
