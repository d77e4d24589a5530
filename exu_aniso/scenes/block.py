"""The block scene: a rigid cube on the plane z = 0 with (polar) orthotropic adhesion and friction
about the origin, pressed down by ``normal_load`` and driven in the xy-plane (conventions: the
module docstring of ``exu_aniso.scenes.base``).

Its parameters (``BLOCK_PARAMS``, ``BlockParams``), contact law, points, inertia, summary and energy
ledger, and its body models for the reference engine (``exu_aniso.engines.reference``) with its run
there (``simulate_block``): a planar rigid body (x, y, theta) held at the penetration that carries the
normal load, or a 6-DOF rigid cube on the plane (the reference engine's docstring has the models'
equations). The Exudyn model script is ``exu_aniso.models.block``.

Body models of the reference engine (state = configuration + velocity; generalized coordinates in
brackets):

* "planar" (x, y, theta): the slave points are held at the penetration that carries the normal
  load equally, gap = -normal_load / eps_n (eps_n total); only the in-plane contact force and the
  z-torque act. Inertia m, m, m size^2 / 6.
* "full": the 6-DOF rigid cube (``RigidBody6``). normal_load acts downward at the COM (no separate
  gravity); the contact points carry it through the normal penalty. The block starts at the static
  penetration (no initial bounce).

Drives: "force" P (cos a, sin a, 0) at the COM; "displacement": a spring and a dashpot along the
drive direction d only from a driver point at travel s(t) (drive_speed t, or speeding up over
drive_ramp first), F = (k (s - d.(r - r0)) + c (s' - d.v)) d.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from exu_aniso.engines import energy
from exu_aniso.engines.reference import RUN_OPTIONS, PlanarBody, RigidBody6, run
from exu_aniso.engines.result import Result
from exu_aniso.engines.timing import driver_travel
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.scenes.plotting import (NET_STYLES, add_net, axes_of, drawn, finite_rows, line_net, note,
                                       polar_net)
from exu_aniso.util.validation import check_instance, check_keywords
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Plane
from exu_aniso.law.return_maps import RETURN_MAPS
from exu_aniso.scenes.base import (HEADING_V_ABS, LEDGER_COLUMNS, _POINTS_RULE, SOLVERS, energy_ledger, SceneParams,
                                   scene_parameters, solver_advice)
from exu_aniso.scenes.scene import Scene


POSITION_LIMIT = 1e6     # block: |x0|, |y0| <= POSITION_LIMIT * size


BLOCK_PARAMS = {
    "mass": (1.0, "kg", "mass of the block", "> 0"),
    "size": (0.1, "m", "edge length of the cube", "> 0"),
    "x0": (0.5, "m", "initial x of the centre (polar origin at x = y = 0); |x0| <= 1e6 size", "real"),
    "y0": (0.0, "m", "initial y of the centre; |y0| <= 1e6 size", "real"),
    "points": ("corners", "-", "contact points on the bottom face: one centre point, 4 corners or an "
               "N x N grid including the edges", _POINTS_RULE),
    "normal_load": (9.81, "N", "total downward load (planar: carried by the held penetration; full: "
                    "vertical force at the COM, no separate gravity)", ">= 0"),
    "eps_n": (1e6, "N/m", "total normal penalty stiffness, split equally over the K points", "> 0"),
    "adhesion": ("polar", "-", "adhesion (sticking stiffness) field B", ("isotropic", "orthotropic", "polar")),
    "eps_1": (1e5, "N/m", "total tangential stiffness along e1 (polar: radial; isotropic: both)", "> 0"),
    "eps_2": (1e3, "N/m", "total tangential stiffness along e2 (polar: circumferential)", "> 0"),
    "adhesion_angle": (0.0, "deg", "angle of e1 from e_x for orthotropic adhesion (a constant direction)", "real"),
    "friction": ("polar", "-", "friction field F", ("isotropic", "orthotropic", "polar")),
    "mu_1": (0.3, "-", "friction coefficient along e1 (polar: radial; isotropic: both)", "> 0"),
    "mu_2": (0.3, "-", "friction coefficient along e2 (polar: circumferential)", "> 0"),
    "friction_angle": (0.0, "deg", "angle of e1 from e_x for orthotropic friction (a constant direction)", "real"),
    "return_map": ("radial", "-", "sliding return map; radial here, the package's default is exact: the papers' block "
                   "slides where the polar adhesion steers it (exact: straight along the push)", RETURN_MAPS),
    "drive": ("displacement", "-", "constant force at the COM, or a spring along the drive direction "
              "from a driver moving at drive_speed", ("force", "displacement")),
    "drive_angle": (90.0, "deg", "drive direction in the xy-plane, from e_x", "real"),
    "force": (5.0, "N", "magnitude of the constant drive force (drive = 'force')", ">= 0"),
    "drive_speed": (0.1, "m/s", "speed of the driver point (drive = 'displacement')", "real"),
    "drive_stiffness": (1e3, "N/m", "stiffness of the drive spring, acting along the drive direction only",
                        "> 0"),
    "drive_damping": (0.0, "N s/m", "dashpot beside the drive spring, along the drive direction only: "
                      "c (driver's speed - d.v)", ">= 0"),
    "drive_ramp": (0.0, "s", "the driver speeds up from rest to drive_speed at a constant rate over this time "
                   "(0: it starts at drive_speed)", ">= 0"),
    "t_end": (2.0, "s", "simulated time", "> 0"),
    "dt": (1e-3, "s", "time step", "> 0"),
    "model": ("planar", "-", "planar (x, y, theta; held normal load) or full 6-DOF rigid body",
              ("planar", "full")),
    "solver": ("trapezoidal", "-", "time integrator", SOLVERS),
    "core_radius": (1e-3, "m", "regularisation radius of polar fields at the origin", ">= 0"),
    "normal_damping": (0.0, "N s/m", "total normal contact damping (dashpot on the gap rate), split equally over "
                       "the K points", ">= 0"),
    "tangential_damping": (0.0, "N s/m", "total tangential dashpot parallel to friction while loaded, split equally "
                           "over the K points", ">= 0"),
}


@scene_parameters(BLOCK_PARAMS)
class BlockParams(SceneParams):
    """Block on a (polar-)orthotropic plane; see BLOCK_PARAMS for units and meaning."""

    RENAMED_VALUES = {("adhesion", "cartesian"): "orthotropic", ("friction", "cartesian"): "orthotropic"}

    def contact_points(self):
        return _n_block_points(self)

    def _layout_text(self):
        return f"points={self.points}"

    def _check_scene(self):
        # positions far beyond the block: a double at |x0| resolves only |x0| * 2.2e-16, and at
        # 1e6 size that is 2.2e-10 size -- the limit where contact slips (~1e-5 m) still resolve;
        # beyond ~1e154 m the polar field's x^2 + y^2 overflows. One clear rule instead.
        for name in ("x0", "y0"):
            v = getattr(self, name)
            if not abs(v) <= POSITION_LIMIT * self.size:
                raise ValueError(f"{name} must satisfy |{name}| <= {POSITION_LIMIT:g} * size = "
                                 f"{POSITION_LIMIT * self.size:g} m (double precision must resolve the contact "
                                 f"slip at that distance from the origin); got {name}={v!r}")


def block_points(p):
    """Body-local contact points (K, 3) on the bottom face z = -size/2 of the cube [m].

    "center": the face centre; "corners": the four corners; "grid:N": N x N points including the
    edges (row-major in x, then y)."""
    a = 0.5 * p.size
    if p.points == "center":
        xy = np.zeros((1, 2))
    elif p.points == "corners":
        xy = np.array([[-a, -a], [a, -a], [a, a], [-a, a]])
    else:
        n = int(p.points.split(":")[1])
        s = np.linspace(-a, a, n)
        X, Y = np.meshgrid(s, s, indexing="xy")
        xy = np.stack([X.ravel(), Y.ravel()], axis=-1)
    return np.column_stack([xy, np.full(len(xy), -a)])


def drive_force(p, d, u, v, t):
    """The displacement drive's force (n,) [N] on the block at displacement u (n,) [m] from its start
    and velocity v (n,) [m/s] (n = 2 or 3, d likewise), time t [s]: (k (s - d.u) + c (s' - d.v)) d with
    the driver's travel s and rate s' (``driver_travel``: drive_speed after drive_ramp), and its
    derivatives (n, n) by u and by v (k = drive_stiffness, c = drive_damping)."""
    s, s_t = driver_travel(t, p.drive_speed, 0.0, p.drive_ramp)
    k, c = p.drive_stiffness, p.drive_damping
    dd = np.outer(d, d)
    return (k * (float(s) - d @ u) + c * (float(s_t) - d @ v)) * d, -k * dd, -c * dd


def _n_block_points(p):
    return {"center": 1, "corners": 4}.get(p.points) or int(p.points.split(":")[1]) ** 2


def block_contact_law(p):
    """ContactLaw of the block scene: plane z = 0 (polar chart when a field is polar), per-point
    stiffnesses = total / K, friction coefficients as given."""
    K = _n_block_points(p)
    rad = math.radians
    if p.adhesion == "isotropic":
        B = Adhesion.isotropic(p.eps_1 / K)
    elif p.adhesion == "orthotropic":
        B = Adhesion.orthotropic(p.eps_1 / K, p.eps_2 / K, angle=rad(p.adhesion_angle))
    else:
        B = Adhesion.polar(p.eps_1 / K, p.eps_2 / K, core_radius=p.core_radius)
    if p.friction == "isotropic":
        Fr = Friction.isotropic(p.mu_1)
    elif p.friction == "orthotropic":
        Fr = Friction.orthotropic(p.mu_1, p.mu_2, angle=rad(p.friction_angle))
    else:
        Fr = Friction.polar(p.mu_1, p.mu_2, core_radius=p.core_radius)
    # the Cartesian chart for every field: its coordinate basis is parallel, so the transport of the
    # sticking traction is exact; a polar net is defined on it (nets.PolarNet)
    return ContactLaw(Plane(), B, Fr, normal_stiffness=p.eps_n / K, return_map=p.return_map,
                      normal_damping=p.normal_damping / K, tangential_damping=p.tangential_damping / K)


def block_inertia(p):
    """Mass [kg] and body-frame inertia tensor (3, 3) [kg m^2] of the cube (about its COM)."""
    return p.mass, np.eye(3) * (p.mass * p.size ** 2 / 6.0)


BLOCK_SUMMARY_KEYS = ("x_end", "y_end", "theta_end", "vx_end", "vy_end", "heading_deg", "r_min", "r_max", "r_mean",
                      "slip_distance", "dissipated_energy", "wall_s", "steps", "newton_iterations", "undefined")


HEADING_V_REL = 1e-6     # a final velocity below this fraction of the largest speed of the run (a block come to rest)


def _undefined_heading(vx, vy):
    """Reason why the heading of the final velocity is undefined, or None. Undefined when
    |v_end| <= max(HEADING_V_ABS, HEADING_V_REL * max_t |v|): the direction of a velocity at round-off
    level is noise (atan2 of 1e-14 values)."""
    speed = np.hypot(vx, vy)
    limit = max(HEADING_V_ABS, HEADING_V_REL * float(speed.max()))
    if speed[-1] <= limit:
        return (f"block at rest at the end: |v_end| = {speed[-1]:.3g} m/s <= {limit:.3g} m/s "
                f"(max({HEADING_V_ABS:g} m/s, {HEADING_V_REL:g} x the largest speed of the run, "
                f"{speed.max():.3g} m/s)); its direction is round-off")
    return None


def planar_motion(traj):
    """energy.RigidMotion of the planar block from its trajectory's coordinates (x, y, z, theta and
    their rates; z held)."""
    return energy.motion_about_z(traj["x"], traj["y"], traj["z"], traj["theta"], traj["vx"], traj["vy"], 0.0,
                                 traj["omega"])


def block_energy(p, traj, motion, law, H, extra_work=None):
    """Energy ledger of a block run (any engine): adds the ENERGY_COLUMNS to traj and returns the
    summary entries (energy, energy_ok, energy_tolerance; see exu_aniso.engines.energy.ledger).

    motion: energy.RigidMotion of the cube's COM (world = master frame); law: the contact law as
    evaluated at block_points(p); H (n, K, 9): converged history per sample. Work in: the drive
    force along the drive direction; potential: normal_load (z - z0) (the load stands in for the
    weight; constant in the planar model); extra_work: cumulative work [J] of loads the scene does
    not know (e.g. a lift pulse of a study), added to the work in. The full model's trajectory gains
    omega_x, omega_y (world), so its kinetic energy can be recomputed from trajectory.csv."""
    if p.model == "full":        # what the kinetic energy needs, in the file too (J of the cube is isotropic)
        traj.update(omega_x=motion.omega[:, 0], omega_y=motion.omega[:, 1])
    d = np.array([math.cos(math.radians(p.drive_angle)), math.sin(math.radians(p.drive_angle))])
    s = d[0] * traj["x"] + d[1] * traj["y"]
    mass, J = block_inertia(p)
    stored, diss = energy.rigid_contact_energy(law, motion, block_points(p), H)
    work = energy.work_trapezoid(traj["drive_force"], s)
    return energy_ledger(dict(work_in=work if extra_work is None else work + extra_work,
                        kinetic=energy.rigid_kinetic(motion, mass, J),
                        potential=p.normal_load * (traj["z"] - traj["z"][0]), stored=stored, dissipated=diss),
                   traj, "block run", solver_advice(p))


def block_summary(traj, p, wall_s, steps, newton_iterations):
    """Summary of a block trajectory (dict of arrays with t, x, y, theta, vx, vy, slip_distance,
    dissipated_energy): end state, heading of the final velocity [deg], distance of the centre
    from the origin along the path (min, max, mean) [m], cost figures. ``heading_deg`` is None
    when the block is at rest at the end (see ``_undefined_heading``); ``undefined`` maps every
    None value to its reason. p: the parameters (the scenes' summaries take them; the block's reads
    none)."""
    x, y = traj["x"], traj["y"]
    r = np.hypot(x, y)
    vx, vy = np.asarray(traj["vx"], float), np.asarray(traj["vy"], float)
    undefined = {}
    why = _undefined_heading(vx, vy)
    if why is None:
        heading = float(math.degrees(math.atan2(vy[-1], vx[-1])))
    else:
        heading, undefined["heading_deg"] = None, why
    return dict(x_end=float(x[-1]), y_end=float(y[-1]), theta_end=float(traj["theta"][-1]),
                vx_end=float(vx[-1]), vy_end=float(vy[-1]), heading_deg=heading,
                r_min=float(r.min()), r_max=float(r.max()), r_mean=float(r.mean()),
                slip_distance=float(traj["slip_distance"][-1]),
                dissipated_energy=float(traj["dissipated_energy"][-1]),
                wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations),
                undefined=undefined)


class _BlockPlanar(PlanarBody):
    def __init__(self, p, law):
        self.p = p
        gap = -p.normal_load / p.eps_n
        m, J = block_inertia(p)
        super().__init__(law, block_points(p)[:, :2], m, J[2, 2], p.size, [p.x0, p.y0, 0.0], gap, p.size / 2 + gap)
        self.d = np.array([math.cos(math.radians(p.drive_angle)), math.sin(math.radians(p.drive_angle))])

    def drive(self, q, v, t):
        """The drive's force (2,) on the block and its derivatives by q[:2] and v[:2]."""
        p = self.p
        if p.drive == "force":
            return p.force * self.d, np.zeros((2, 2)), np.zeros((2, 2))
        return drive_force(p, self.d, q[:2] - self.q0[:2], v[:2], t)

    def record(self, q, v, t, st):
        Fd = self.drive(q, v, t)[0]
        return dict(x=q[0], y=q[1], theta=q[2], vx=v[0], vy=v[1], omega=v[2], z=self.com_height,
                    drive_force=float(Fd @ self.d))


class _BlockFull(RigidBody6):
    def __init__(self, p, law):
        self.p = p
        gap = -p.normal_load / p.eps_n
        super().__init__(law, block_points(p), p.mass, np.diag(block_inertia(p)[1]),
                         [p.x0, p.y0, 0.5 * p.size + gap], p.size)
        a = math.radians(p.drive_angle)
        self.d = np.array([math.cos(a), math.sin(a), 0.0])

    def external(self, q, t):
        """The normal load and the force drive (the displacement drive, which depends on the
        velocity too, in ``evaluate``)."""
        p = self.p
        F = np.array([0.0, 0.0, -p.normal_load])
        if p.drive == "force":
            F += p.force * self.d
        return F, np.zeros(3), np.zeros((3, 3)), np.zeros(3)

    def _drive(self, q, v, t):
        """The displacement drive's force (3,) at the COM and its derivatives by r and by v[:3]."""
        if self.p.drive == "force":
            return np.zeros(3), np.zeros((3, 3)), np.zeros((3, 3))
        return drive_force(self.p, self.d, q[0] - self.q0[0], v[:3], t)

    def evaluate(self, q, v, t, H, tangent=True, dt=None):
        g, Gq, Gv, st = super().evaluate(q, v, t, H, tangent, dt)
        F, dF, dF_v = self._drive(q, v, t)
        g[:3] += F
        if tangent:
            Gq[:3, :3] += dF
            Gv[:3, :3] += dF_v
        return g, Gq, Gv, st

    def record(self, q, v, t, st):
        r, R, yaw = q
        w = self.world_omega(q, v)
        F = self.external(q, t)[0] + self._drive(q, v, t)[0]
        return dict(x=r[0], y=r[1], theta=yaw, vx=v[0], vy=v[1], omega=w[2], z=r[2], vz=v[2],
                    tilt=math.acos(max(-1.0, min(1.0, R[2, 2]))), drive_force=float(F @ self.d))


def reference_model(p, law=None):
    """The block's body model for the reference engine and its force floor; ``law`` replaces the
    scene's ContactLaw (e.g. another chart of its surface)."""
    if law is not None:
        check_instance("law", law, ContactLaw)
    law = block_contact_law(p) if law is None else law
    return (_BlockPlanar(p, law) if p.model == "planar" else _BlockFull(p, law)), 1e-6 * p.eps_n * p.size


def simulate_block(params=None, **options):
    """Block scene with the reference integrator; params: BlockParams (defaults if None).

    options: jacobian ("analytic" | "numerical"), rho_inf (generalized_alpha, default 0.8),
    newton_tol (1e-10, scaled residual), max_newton (25), max_halvings (6), nonsmooth_accept
    (True: at the last halving level accept the smallest-residual iterate instead of failing;
    needed by the seed map, whose discontinuity at stick/slip can leave the step without a root;
    counted in ``info["forced_accepts"]``), reject_steps / split_steps (nominal step indices to
    reject after convergence / to halve directly), law (a ContactLaw replacing the scene's, e.g.
    the plane in polar coordinates). Returns Result."""
    p = BlockParams() if params is None else params
    if not isinstance(p, BlockParams):
        raise TypeError(f"params must be BlockParams; got {type(p).__name__}")
    check_keywords("simulate_block", options, RUN_OPTIONS + ("law",))
    model, floor = reference_model(p, options.pop("law", None))
    traj, wall, iters, steps, info, motion, H = run(model, p, floor=floor, **options)
    summary = block_summary(traj, p, wall, steps, iters)
    summary.update(block_energy(p, traj, motion, model.law, H))
    return Result(traj, summary, p, info)


# ----------------------------------------------------------------------------------------------
# closed forms

def orthotropic_heading(pull_angle, pull, normal_force, mu_1, mu_2):
    """Heading [rad] of the steady sliding of a body pulled from rest by a constant force
    ``pull`` [N] at ``pull_angle`` [rad] from e_1 on a plane with orthotropic Coulomb friction
    (coefficient mu_1 along e_1, mu_2 along e_2) and the associated (maximum-dissipation) law,
    under the normal force ``normal_force`` [N].

    The friction force for the sliding direction v is -|N| F^-1 v / sqrt(v.F^-1 v),
    F^-1 = diag(mu_1^2, mu_2^2); the heading is the v where pull + friction is parallel to v
    (then the body accelerates along v and the direction stays constant). Solved with brentq in
    the quadrant of the pull (the problem is symmetric under reflections of either axis). Raises
    ValueError when the pull lies inside the friction ellipse (the body sticks) or an input is
    not finite / not positive."""
    for name, v in (("pull", pull), ("normal_force", normal_force), ("mu_1", mu_1), ("mu_2", mu_2)):
        if not (isinstance(v, (int, float, np.floating)) and math.isfinite(v) and v > 0):
            raise ValueError(f"orthotropic_heading: {name} must be a finite number > 0; got {v!r}")
    if not math.isfinite(pull_angle):
        raise ValueError(f"orthotropic_heading: pull_angle must be finite; got {pull_angle!r}")
    px, py = pull * math.cos(pull_angle), pull * math.sin(pull_angle)
    if (px / (mu_1 * normal_force)) ** 2 + (py / (mu_2 * normal_force)) ** 2 <= 1.0:
        raise ValueError(f"orthotropic_heading: the pull ({px:.6g}, {py:.6g}) N lies inside the friction ellipse "
                         f"(mu_1 |N|, mu_2 |N|) = ({mu_1 * normal_force:.6g}, {mu_2 * normal_force:.6g}) N: "
                         "the body sticks, there is no sliding heading")
    ax, ay = abs(px), abs(py)
    if ay <= 1e-15 * pull:
        phi = 0.0
    elif ax <= 1e-15 * pull:
        phi = 0.5 * math.pi
    else:
        m1, m2 = mu_1 ** 2, mu_2 ** 2

        def cross(phi):              # (pull + friction(phi)) x v
            c, s = math.cos(phi), math.sin(phi)
            k = normal_force / math.sqrt(m1 * c * c + m2 * s * s)
            return (ax - k * m1 * c) * s - (ay - k * m2 * s) * c

        phi = brentq(cross, 0.0, 0.5 * math.pi, xtol=1e-15, maxiter=200)
    return math.atan2(math.copysign(math.sin(phi), py), math.copysign(math.cos(phi), px))


def block_closed_forms(p):
    """The block's closed forms for p: ``heading_deg_theory``, the heading [deg] of the steady
    sliding under the constant force drive on a field of constant direction (isotropic or
    orthotropic friction at ``friction_angle``; ``orthotropic_heading`` with the whole normal load),
    for a block that does not turn (the corners' or the grid's symmetric layout on a constant field).
    None, with its reason under ``undefined``, for a displacement drive (its spring acts along the
    drive direction only), a polar friction net (no closed form) and a pull inside the friction
    ellipse (the block sticks)."""
    undefined = {}
    heading = None
    if p.drive != "force":
        undefined["heading_deg_theory"] = ("drive 'displacement': the spring pulls along the drive direction only; "
                                           "the closed form is for a constant force")
    elif p.friction == "polar":
        undefined["heading_deg_theory"] = "friction 'polar': no closed form of the heading on a polar net"
    else:
        mu_2 = p.mu_1 if p.friction == "isotropic" else p.mu_2
        angle = 0.0 if p.friction == "isotropic" else p.friction_angle
        try:
            heading = angle + math.degrees(orthotropic_heading(math.radians(p.drive_angle - angle), p.force,
                                                               p.normal_load, p.mu_1, mu_2))
        except ValueError as e:
            undefined["heading_deg_theory"] = f"force, normal_load, mu_1, mu_2: {e}"
    return dict(heading_deg_theory=heading, undefined=undefined)


# ----------------------------------------------------------------------------------------------
# the plot of trajectory.png

def _block_nets(params):
    """[(kind, angle [rad], label)] of the distinct non-isotropic nets of adhesion B and friction F."""
    nets = []
    for name, kind, angle in (("B", params.adhesion, params.adhesion_angle),
                              ("F", params.friction, params.friction_angle)):
        if kind == "isotropic":
            continue
        a = math.radians(angle) if kind == "orthotropic" else 0.0
        for i, (k0, a0, names) in enumerate(nets):
            same_lines = math.isclose(math.remainder(a - a0, math.pi), 0.0, abs_tol=1e-12)
            if k0 == kind and (kind == "polar" or same_lines):
                nets[i] = (k0, a0, names + [name])
                break
        else:
            nets.append((kind, a, [name]))
    out = []
    for kind, a, names in nets:
        who = " and ".join(names)
        if kind == "polar":
            out.append((kind, a, f"{who} net: polar (rays e1, circles e2)"))
        else:
            out.append((kind, a, f"{who} net: lines along e1 ({math.degrees(a):.4g} deg)"))
    return out


def PlotBlockPath(traj, params, ax=None):
    """The block's centre path (x, y) over the field net, start and end marked, and the polar
    origin when a field is polar; equal axes. Returns the Axes."""
    ax = axes_of(ax)
    x, y = finite_rows(traj["x"], traj["y"])
    nets = _block_nets(params)
    polar = any(kind == "polar" for kind, _, _ in nets)
    origin_in_view = polar
    if x.size:
        xs, ys = list(x), list(y)
        origin_in_view = polar and math.hypot(x[0], y[0]) < 20.0 * max(np.ptp(x), np.ptp(y), params.size)
        if origin_in_view:            # keep the origin in view unless it is far away
            xs.append(0.0)
            ys.append(0.0)
        lo, hi = np.array([min(xs), min(ys)]), np.array([max(xs), max(ys)])
        centre = 0.5 * (lo + hi)
        half = 0.5 * max(hi[0] - lo[0], hi[1] - lo[1], params.size) * 1.12
        for (kind, angle, label), style in zip(nets, NET_STYLES):
            segments = polar_net(centre, half) if kind == "polar" else line_net(centre, half, angle)
            add_net(ax, segments, style, label)
        ax.plot(*drawn(x, y), "-", color="C0", lw=1.6, label="centre path", zorder=3)
        ax.plot(x[0], y[0], "o", color="C2", label="start", zorder=4)
        ax.plot(x[-1], y[-1], "s", color="C3", ms=5, label="end", zorder=4)
        # the view: the padded square box around the path (and the origin); the net reaches beyond it
        ax.set_xlim(centre[0] - half, centre[0] + half)
        ax.set_ylim(centre[1] - half, centre[1] + half)
    if origin_in_view:
        ax.plot(0.0, 0.0, "k+", ms=12, mew=2, label="polar origin", zorder=4, scalex=False, scaley=False)
    elif polar:
        note(ax, "polar origin (0, 0) out of view")
    if not nets:
        ax.plot([], [], ls="none", label="isotropic B and F: no net")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal", adjustable="box")
    ax.legend(loc="best", fontsize=7)
    return ax


def PlotBlock(traj, params, fig):
    """trajectory.png of the block on the matplotlib Figure fig: PlotBlockPath."""
    PlotBlockPath(traj, params, ax=fig.add_subplot(1, 1, 1))


# ----------------------------------------------------------------------------------------------
# the scene, as every engine and the command line see it

class BlockScene(Scene):
    """The block scene (the module docstring); the summary takes no inputs, the ledger
    ``block_energy``'s (motion, law, H)."""

    name = "block"
    Params = BlockParams
    columns = {"t": "s", "x": "m", "y": "m", "theta": "rad", "vx": "m/s", "vy": "m/s", "omega": "rad/s",
               "slip_distance": "m", "dissipated_energy": "J", "drive_force": "N",
               # the full model's other motions (the planar model holds z and has no vz, tilt, omega_x, omega_y)
               "z": "m", "vz": "m/s", "tilt": "rad", "omega_x": "rad/s", "omega_y": "rad/s", **LEDGER_COLUMNS}
    title_keys = ("heading_deg", "r_mean")
    figsize = (5.5, 5.0)
    law = staticmethod(block_contact_law)
    points = staticmethod(block_points)
    closed_forms = staticmethod(block_closed_forms)
    summary = staticmethod(block_summary)
    ledger = staticmethod(block_energy)
    plot = staticmethod(PlotBlock)
    reference = staticmethod(simulate_block)


SCENE = BlockScene()
