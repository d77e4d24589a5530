"""The elastic block on the polar-orthotropic plane (the first paper's finite-element experiment).

An elastic cube (edge ``size``, ``cells`` trilinear hexahedra along each edge, Young's modulus
``E``, Poisson's ratio ``nu``, ``density``; ``exu_aniso.fe.block_mesh``) stands on the plane z = 0
with the centre of its bottom face at (x0, y0). Its bottom face's nodes carry the contact: polar
adhesion (eps_r along the radius from the origin, eps_phi along the circles) and polar friction
(mu_r, mu_phi), the stiffnesses totals over the bottom nodes.

The drive, as the paper ran it: the block is pressed down by a prescribed displacement w, then
moved horizontally, and the net alone decides where it goes across that push. Its top face is held
by a press plate, rigid and bonded to it: the body is Exudyn's floating-frame body
(ObjectFFRFreducedOrder) with a basis that vanishes at the top face, so the frame is the top face's
rigid motion, the plate. The plate's height is prescribed: down by ``press`` (w) over ``t_press``
along a smooth step (3 s^2 - 2 s^3), then held; its tilt is held level. Across the plane and about
the vertical axis the plate is free: after the pressing it is pulled along ``drive_angle`` by the
rigid block scene's drive, a spring ``drive_stiffness`` and a dashpot ``drive_damping`` beside it,
both along that direction only, F = (k (s - d.(r - r0)) + c (s' - d.v)) d, from a driver point that
rests until t_press, speeds up over ``drive_ramp`` and has gone ``travel`` (v) at t_end. So the
bottom is steered by the net as the rigid block is, and the rigid ``block`` scene under the same
drive (``rigid_block``: the same points, law, mass and drive, held at the penetration w) is this
scene's stiff limit exactly, not a second model of it. (A spring rather than a carriage that
prescribes the travel: the rigid block scene has that drive, so its limit needs no model of its
own; at 1e5 N/m the spring lags the driver by its force / k, 0.1 mm per 10 N.) The basis
(``fe_block_basis``): ``model=full``, every coordinate of the nodes off the top face (the full
mesh in the frame); ``model=reduced`` with ``basis=craig_bampton``, the static modes of every bottom
node coordinate (which hold the contact's local compliance) plus ``modes`` fixed-interface
eigenmodes; with ``basis=eigenmodes``, ``modes`` eigenmodes of the block clamped at its top (which
miss it, and the run says so: ``contact_compliance``). The floating frame carries the block's yaw
exactly; a linear FE body in global coordinates would resist a finite yaw with the spurious strain
(1 - cos yaw) of its rotation. Stiffness-proportional damping ``stiffness_damping`` (D = beta K)
keeps the run quasi-static.

What it measures: the path of the bottom face's centre and of the plate over the net, the plate's
rotation about the vertical, the drive's force and the press's, the contact state of every bottom
node, the share of the contact nodes' static compliance the basis keeps, and the energy ledger with
the strain energy u.K u / 2, the drive spring's energy and the damping's dissipation beside the
contact's.

Its limit (``rigid_limit``): as E grows the block becomes rigid and the bottom face's centre follows
the rigid block scene's path under the same drive, which the reference engine integrates
(``exu_aniso.scenes.block.simulate_block``, planar model); the error falls like 1/E
(tests/test_fe_block.py). ``return_map=seed`` is refused: the papers' closed-form sliding rule jumps
at the stick/slip switch, and Newton finds no root at the bottom nodes' transitions.
"""
from __future__ import annotations

import math

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.engines.timing import driver_travel
from exu_aniso.fe import cost as fe_cost
from exu_aniso.fe import block_mesh
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Plane
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.law.history import HISTORY_FIELDS, SLIP, STICK
from exu_aniso.law.return_maps import RETURN_MAPS
from exu_aniso.scenes.block import BlockParams, simulate_block
from exu_aniso.scenes.base import (LEDGER_COLUMNS, LEDGER_TERM_COLUMNS, SOLVERS, SceneParams, basis_compliance,
                                   energy_ledger, scene_parameters)
from exu_aniso.scenes.scene import Scene

FE_BLOCK_PARAMS = {
    "model": ("reduced", "-", "the elastic body in its floating frame (the top face's motion): full (every coordinate "
              "of the nodes off the top face) or reduced (a basis of modes, see basis)", ("full", "reduced")),
    "basis": ("craig_bampton", "-", "reduced: craig_bampton (static modes of every bottom node coordinate, plus `modes` "
              "fixed-interface eigenmodes) or eigenmodes (`modes` eigenmodes of the block clamped at its top)",
              ("craig_bampton", "eigenmodes")),
    "modes": (0, "-", "reduced: the number of eigenmodes (see basis)", "int >= 0"),
    "size": (0.1, "m", "edge length of the cube", "> 0"),
    "cells": (4, "-", "trilinear hexahedra along each edge (4: within 1 % of the converged mesh in the drive's and the "
              "press's forces, studies/fe_block.py)", "int >= 1"),
    "E": (1e6, "Pa", "Young's modulus", "> 0"),
    "nu": (0.3, "-", "Poisson's ratio, in (-1, 0.5)", "real"),
    "density": (1000.0, "kg/m^3", "density", "> 0"),
    "stiffness_damping": (1e-3, "s", "stiffness-proportional damping beta (D = beta K): keeps the run "
                          "quasi-static", ">= 0"),
    "x0": (0.5, "m", "initial x of the bottom face's centre (polar origin at x = y = 0)", "real"),
    "y0": (0.0, "m", "initial y of the bottom face's centre", "real"),
    "eps_n": (1e7, "N/m", "normal penalty stiffness, total over the bottom nodes", "> 0"),
    "eps_r": (1e6, "N/m", "adhesion stiffness along the radius from the origin, total", "> 0"),
    "eps_phi": (1e4, "N/m", "adhesion stiffness along the circles about the origin, total", "> 0"),
    "mu_r": (0.3, "-", "friction coefficient along the radius", "> 0"),
    "mu_phi": (0.3, "-", "friction coefficient along the circles", "> 0"),
    "core_radius": (1e-3, "m", "regularisation radius of the polar fields at the origin", ">= 0"),
    "return_map": ("radial", "-", "sliding return map; radial here, the package's default is exact: the papers' "
                   "elastic block is steered by the adhesion net as their rigid one (the block scene's choice); "
                   "seed is refused (no Newton root at the stick/slip switch on this body)",
                   RETURN_MAPS),
    "press": (1e-3, "m", "w: the top face pressed down over t_press", "> 0"),
    "travel": (0.1, "m", "v: the driver's travel along drive_angle after the pressing, at constant speed until "
               "t_end", ">= 0"),
    "drive_angle": (90.0, "deg", "direction of the drive from +x (90: along +y, along the circle at the start)",
                    "real"),
    "drive_stiffness": (1e5, "N/m", "the drive spring from the driver to the press plate, along drive_angle only "
                        "(the rigid block scene's drive)", "> 0"),
    "drive_ramp": (0.1, "s", "after the pressing the driver speeds up from rest at a constant rate over this time "
                   "(its rate continuous: no jump of the dashpot's force)", ">= 0"),
    "drive_damping": (300.0, "N s/m", "the dashpot beside the drive spring (about half the critical 2 sqrt(k m) of "
                      "the block's mass on it: the block follows the driver without ringing)", ">= 0"),
    "t_press": (0.2, "s", "duration of the pressing", "> 0"),
    "t_end": (1.2, "s", "simulated time", "> 0"),
    "dt": (1e-3, "s", "time step", "> 0"),
    "solver": ("trapezoidal", "-", "time integrator", SOLVERS),
}




@scene_parameters(FE_BLOCK_PARAMS)
class FeBlockParams(SceneParams):
    """Elastic block on the polar-orthotropic plane; see FE_BLOCK_PARAMS for units and meaning."""

    def _check_scene(self):
        if not -1.0 < self.nu < 0.5:
            raise ValueError(f"nu must lie in (-1, 0.5) (a positive definite elasticity); got {self.nu!r}")
        if not self.press < 0.5 * self.size:
            raise ValueError(f"press must be < size / 2 (small deformation); got press={self.press!r}, "
                             f"size={self.size!r}")
        if not self.t_press < self.t_end:
            raise ValueError(f"t_press must be < t_end (the travel follows the pressing); got t_press="
                             f"{self.t_press!r}, t_end={self.t_end!r}")
        if not self.drive_ramp < self.t_end - self.t_press:
            raise ValueError(f"drive_ramp must be < t_end - t_press (the driver reaches its speed within the "
                             f"travel); got drive_ramp={self.drive_ramp!r}, t_end - t_press="
                             f"{self.t_end - self.t_press!r}")
        if self.return_map == "seed":
            raise ValueError("return_map=seed is refused here: the papers' closed-form sliding rule jumps at the "
                             "stick/slip switch, and on the elastic block Newton finds no root at the bottom nodes' "
                             "transitions, at any step tried (docs/guide/scenes.md, the elastic block); use "
                             "return_map=radial (the papers' steering) or exact")
        if self.cells > 12:
            raise ValueError(f"cells must be <= 12 (the mesh's coordinates grow like cells^3: "
                             f"{3 * (self.cells + 1) ** 3} here); got {self.cells}")
        if self.model == "reduced":
            room = self.free_coordinates() - (0 if self.basis == "eigenmodes" else self.static_modes())
            if self.basis == "eigenmodes" and self.modes < 1:
                raise ValueError("modes must be >= 1 with model=reduced and basis=eigenmodes (the body's only "
                                 "deformation)")
            if self.modes > room:
                raise ValueError(f"modes must be <= {room} with basis={self.basis} and cells={self.cells} (the "
                                 f"{'free' if self.basis == 'eigenmodes' else 'interior'} coordinates); got "
                                 f"{self.modes}")
        # the elastic body's cost, once its modes are known to exist
        layout = f"cells={self.cells}, model={self.model}" + (f", basis={self.basis}, modes={self.modes}"
                                                               if self.model == "reduced" else "")
        fe_cost.check_cost((self.cells + 1) ** 3, self.body_modes(), layout)

    def free_coordinates(self):
        """The mesh's coordinates off the top face (the frame's)."""
        return 3 * self.cells * (self.cells + 1) ** 2

    def static_modes(self):
        """Craig-Bampton's static modes: every coordinate of the bottom nodes."""
        return 3 * (self.cells + 1) ** 2

    def body_modes(self):
        """The elastic body's modes: every coordinate off the top face (full), the bottom nodes' static
        modes plus ``modes`` (craig_bampton) or ``modes`` (eigenmodes)."""
        if self.model == "full":
            return self.free_coordinates()
        return self.modes + (self.static_modes() if self.basis == "craig_bampton" else 0)

    @classmethod
    def cost_rules(cls):
        return super().cost_rules() + ["cells <= 12 (the mesh's assembly and eigenmodes)"] + fe_cost.cost_rules()

    def contact_points(self):
        return (self.cells + 1) ** 2

    def _layout_text(self):
        return f"cells={self.cells}: (cells + 1)^2 bottom nodes"


def fe_block_mesh(p):
    """The block's ElasticMesh (body frame: the bottom face's centre at the origin)."""
    return block_mesh((p.size,) * 3, (p.cells,) * 3, E=p.E, nu=p.nu, rho=p.density)


def fe_block_contact_law(p):
    """The plane z = 0 with polar adhesion and friction about the origin, per bottom node."""
    K = p.contact_points()
    return ContactLaw(Plane(), Adhesion.polar(p.eps_r / K, p.eps_phi / K, core_radius=p.core_radius),
                      Friction.polar(p.mu_r, p.mu_phi, core_radius=p.core_radius), normal_stiffness=p.eps_n / K,
                      return_map=p.return_map)


def fe_block_basis(p, mesh):
    """The mode basis (3N, m) of the floating-frame body: zero at the top face's nodes (the frame is
    the top face's motion); every other coordinate (model full), the bottom nodes' static modes plus
    p.modes fixed-interface eigenmodes (reduced, craig_bampton) or p.modes eigenmodes of the block
    clamped at its top (reduced, eigenmodes)."""
    top = mesh.node_sets["top"]
    if p.model == "full":
        return mesh.clamped_modes(top)
    if p.basis == "eigenmodes":
        return mesh.clamped_modes(top, p.modes)
    return mesh.craig_bampton_modes(top, mesh.node_sets["bottom"], p.modes)


def basis_name(p):
    """The basis in words (for warnings)."""
    if p.model == "full":
        return "the full mesh"
    if p.basis == "eigenmodes":
        return f"{p.modes} eigenmodes of the block clamped at its top"
    return f"the bottom nodes' static modes and {p.modes} eigenmodes"


def contact_compliance(p, mesh, basis, warn=True):
    """The summary's entries on the basis: ``scenes.base.basis_compliance`` of the bottom nodes, the top clamped."""
    return basis_compliance(p, mesh, basis, "bottom", "top", (basis_name(p), "bottom nodes", "block"), warn)


def drive_direction(p):
    """The drive's unit direction d (2,) in the plane."""
    a = math.radians(p.drive_angle)
    return np.array([math.cos(a), math.sin(a)])


def drive_speed(p):
    """The driver's speed [m/s] once it has sped up: travel / (t_end - t_press - drive_ramp / 2), so
    that it has travelled ``travel`` at t_end."""
    return p.travel / (p.t_end - p.t_press - 0.5 * p.drive_ramp)


def press_depth(p, t):
    """The plate's prescribed descent [m] (positive down) and its rate [m/s] at time(s) t: press
    (3 s^2 - 2 s^3) with s = t / t_press, held after t_press (no jump in velocity)."""
    s = np.clip(np.atleast_1d(np.asarray(t, dtype=float)) / p.t_press, 0.0, 1.0)
    return p.press * s * s * (3.0 - 2.0 * s), p.press * 6.0 * s * (1.0 - s) / p.t_press


def drive_stretch(p, t, x, y, vx, vy):
    """The drive spring's stretch [m] and its rate [m/s] when the plate's centre is at (x, y) [m] and
    moves at (vx, vy) [m/s] (arrays over time t [s]): s(t) - d.(r - r0) and its derivative. The drive's
    force on the plate along d is drive_stiffness stretch + drive_damping rate [N]."""
    d = drive_direction(p)
    s, s_t = driver_travel(t, drive_speed(p), p.t_press, p.drive_ramp)
    return (s - d[0] * (np.asarray(x) - p.x0) - d[1] * (np.asarray(y) - p.y0),
            s_t - d[0] * np.asarray(vx) - d[1] * np.asarray(vy))


# trajectory columns (trajectory.csv) -> SI unit; x_top, y_top, z_top, yaw_top: the plate (the frame);
# force_x, force_y, force_z: the forces applied at the frame (the drive's along d, the press's, negative
# down); drive_stretch: the drive spring's; dissipated_energy: the contact's friction alone; the energy
# terms: every term of the ledger (fe_block_energy), so that the file recomputes it
COLUMNS = {"t": "s", "x_top": "m", "y_top": "m", "z_top": "m", "yaw_top": "rad", "x_bottom": "m", "y_bottom": "m",
           "z_bottom": "m", "drive_force": "N", "force_x": "N", "force_y": "N", "force_z": "N", "drive_stretch": "m",
           "stick_fraction": "-", "slip_fraction": "-", "strain_energy": "J", "dissipated_energy": "J",
           **{k: "J" for k in LEDGER_TERM_COLUMNS}, "drive_spring_energy": "J", "rayleigh_dissipated_energy": "J",
           "drive_dashpot_dissipated_energy": "J", **LEDGER_COLUMNS}
TITLE_KEYS = ("steer_end", "force_ratio_end")

_STATUS = HISTORY_FIELDS.index("status")


def contact_columns(H):
    """stick_fraction and slip_fraction (n,) of the bottom nodes from the history H (n, K, 9)."""
    S = np.asarray(H)[:, :, _STATUS]
    return (S == STICK).mean(axis=1), (S == SLIP).mean(axis=1)


def fe_block_energy(p, traj, Xb, Vb, H, work_in):
    """The energy ledger (energy_ledger's summary entries; the ENERGY_COLUMNS and the contact's
    energy columns added to traj): work of the press and of the driver (work_in (n,) [J]) = kinetic
    (block and plate) + stored (strain, the drive spring's energy, the contact's penalty and adhesion)
    + dissipated (the contact's, the Rayleigh damping's and the drive dashpot's). Every term is a
    column of traj (COLUMNS). Xb, Vb (n, K, 3): the bottom nodes; H (n, K, 9) their history."""
    traj["contact_stored_energy"], traj["contact_dissipated_energy"] = energy.contact_energy(
        fe_block_contact_law(p), Xb, Vb, H)
    stored = traj["contact_stored_energy"] + traj["strain_energy"] + traj["drive_spring_energy"]
    dissipated = traj["contact_dissipated_energy"] + (traj["rayleigh_dissipated_energy"]
                                                      + traj["drive_dashpot_dissipated_energy"])
    return energy_ledger(dict(work_in=work_in, kinetic=traj["kinetic_energy"], potential=np.zeros(len(work_in)),
                              stored=stored, dissipated=dissipated), traj,
                         "fe_block run", "reduce dt, or raise stiffness_damping (a quasi-static run)")


def fe_block_summary(traj, p, wall_s, steps, newton_iterations, compliance=None):
    """Summary of a run: where the bottom face's centre ends, its offset across the drive direction
    from its start (steer_end [m]: the steering by the net; positive to the left of the drive, towards
    the origin on the defaults) and along it (advance_end [m]), its distance from the origin, the
    plate's rotation about the vertical (yaw_end [rad]), the drive spring's force and the plate's
    force on the top face at the end and the ratio of the latter's horizontal part to its vertical
    one, the contact state; compliance: the basis's entries (``contact_compliance``) of a completed
    run, added after them."""
    d = drive_direction(p)
    n = np.array([-d[1], d[0]])
    u = np.array([traj["x_bottom"][-1] - p.x0, traj["y_bottom"][-1] - p.y0])
    F = np.array([traj["force_x"][-1], traj["force_y"][-1], traj["force_z"][-1]])
    undefined = {}
    if F[2] != 0.0:
        ratio = float(math.hypot(F[0], F[1]) / abs(F[2]))
    else:
        ratio, undefined["force_ratio_end"] = None, "the plate presses with no force at the end"
    return dict(complete=True, x_bottom_end=float(traj["x_bottom"][-1]), y_bottom_end=float(traj["y_bottom"][-1]),
                x_top_end=float(traj["x_top"][-1]), y_top_end=float(traj["y_top"][-1]),
                advance_end=float(u @ d), steer_end=float(u @ n), yaw_end=float(traj["yaw_top"][-1]),
                r_bottom_end=float(math.hypot(traj["x_bottom"][-1], traj["y_bottom"][-1])),
                drive_force_end=float(traj["drive_force"][-1]),
                force_x_end=float(F[0]), force_y_end=float(F[1]), force_z_end=float(F[2]), force_ratio_end=ratio,
                stick_fraction_end=float(traj["stick_fraction"][-1]), slip_fraction_end=float(traj["slip_fraction"][-1]),
                strain_energy_end=float(traj["strain_energy"][-1]),
                dissipated_energy=float(traj["dissipated_energy"][-1]),
                wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations), undefined=undefined,
                **(compliance or {}))


def rigid_block(p):
    """The block scene's parameters of this scene's stiff limit: the rigid cube (planar model) with the
    bottom nodes as its points (grid:(cells + 1)), the same law and totals, held at the penetration w
    (normal_load = eps_n press), the block's mass, pulled by the same drive from t_press on (its time
    0) for t_end - t_press."""
    return BlockParams(mass=p.density * p.size ** 3, size=p.size, x0=p.x0, y0=p.y0, points=f"grid:{p.cells + 1}",
                       normal_load=p.eps_n * p.press, eps_n=p.eps_n, adhesion="polar", eps_1=p.eps_r,
                       eps_2=p.eps_phi, friction="polar", mu_1=p.mu_r, mu_2=p.mu_phi, return_map=p.return_map,
                       drive="displacement", drive_angle=p.drive_angle, drive_speed=drive_speed(p),
                       drive_stiffness=p.drive_stiffness, drive_damping=p.drive_damping, drive_ramp=p.drive_ramp,
                       t_end=p.t_end - p.t_press, dt=p.dt, model="planar",
                       solver=p.solver, core_radius=p.core_radius)


def rigid_limit(p):
    """The scene's stiff limit: the rigid block scene under the same drive (``rigid_block``) on the
    reference engine, its times shifted by t_press. Returns the block's Result trajectory with t on
    this scene's clock (x, y: the bottom face's centre [m], theta [rad], drive_force [N], ...)."""
    traj = dict(simulate_block(rigid_block(p)).trajectory)
    traj["t"] = np.asarray(traj["t"]) + p.t_press
    return traj


def path_from_rigid(p, traj, limit=None):
    """The largest distance [m] of the bottom face's centre from the rigid limit's path at the same
    times, over the travel (t >= t_press; the limit interpolated onto the run's samples)."""
    limit = rigid_limit(p) if limit is None else limit
    t = np.asarray(traj["t"])
    late = t >= p.t_press
    x = np.interp(t[late], limit["t"], limit["x"])
    y = np.interp(t[late], limit["t"], limit["y"])
    return float(np.hypot(np.asarray(traj["x_bottom"])[late] - x, np.asarray(traj["y_bottom"])[late] - y).max())


def PlotFeBlock(traj, params, fig):
    """trajectory.png: the bottom centre's path and the press plate's over the polar net (left), the
    drive's and the press's forces and the sliding share of the bottom nodes (right)."""
    p = params
    a1, a2 = fig.subplots(1, 2)
    xb, yb = np.asarray(traj["x_bottom"]), np.asarray(traj["y_bottom"])
    xt, yt = np.asarray(traj["x_top"]), np.asarray(traj["y_top"])
    r = np.hypot(np.concatenate([xb, xt]), np.concatenate([yb, yt]))
    phi = np.linspace(0.0, 2.0 * math.pi, 361)
    for rc in np.linspace(max(r.min() - 0.05, 0.0), r.max() + 0.05, 6):
        a1.plot(rc * np.cos(phi), rc * np.sin(phi), color="0.85", lw=0.6)
    a1.plot(xt, yt, "k--", lw=0.9, label="press plate (pulled along the drive)")
    a1.plot(xb, yb, color="C0", lw=1.4, label="bottom face's centre")
    a1.plot([p.x0], [p.y0], "o", color="C3", ms=4, label="start")
    pad = 0.3 * max(np.ptp(np.concatenate([xb, xt])), np.ptp(np.concatenate([yb, yt])), p.size)
    a1.set_xlim(min(xb.min(), xt.min()) - pad, max(xb.max(), xt.max()) + pad)
    a1.set_ylim(min(yb.min(), yt.min()) - pad, max(yb.max(), yt.max()) + pad)
    a1.set_aspect("equal")
    a1.set_xlabel("x [m]")
    a1.set_ylabel("y [m]")
    a1.set_title(f"paths over the polar net (circles about the origin)\neps_r / eps_phi = {p.eps_r / p.eps_phi:g}",
                 fontsize=9)
    a1.legend(fontsize=7, loc="best")
    t = np.asarray(traj["t"])
    a2.plot(t, traj["drive_force"], label="the drive's force along its direction")
    a2.plot(t, -np.asarray(traj["force_z"]), label="the press's force (down)")
    a2.set_xlabel("t [s]")
    a2.set_ylabel("force on the press plate [N]")
    a2b = a2.twinx()
    a2b.plot(t, traj["slip_fraction"], color="0.5", lw=0.8, ls=":", label="sliding share of the bottom nodes")
    a2b.set_ylim(-0.05, 1.05)
    a2b.set_ylabel("sliding share [-]")
    a2.legend(fontsize=7, loc="upper left")
    a2b.legend(fontsize=7, loc="lower right")
    a2.grid(alpha=0.3)


# ----------------------------------------------------------------------------------------------
# the scene, as every engine and the command line see it

class FeBlockScene(Scene):
    """The fe_block scene (the module docstring); no reference-engine model of the elastic body (its
    limit is the rigid block, ``rigid_limit``); the summary's input: the basis's compliance entries,
    the ledger ``fe_block_energy``'s (Xb, Vb, H, work_in)."""

    name = "fe_block"
    Params = FeBlockParams
    columns = COLUMNS
    title_keys = TITLE_KEYS
    figsize = (11.0, 4.8)
    law = staticmethod(fe_block_contact_law)
    summary = staticmethod(fe_block_summary)
    ledger = staticmethod(fe_block_energy)
    plot = staticmethod(PlotFeBlock)

    def points(self, p):
        """The bottom face's mesh nodes in the body's reference configuration [m]."""
        mesh = fe_block_mesh(p)
        return mesh.nodes[mesh.node_sets["bottom"]]

    def closed_forms(self, p):
        """None: the elastic block's limit is a run, the rigid block's (``rigid_limit``), not a closed
        form."""
        return dict(undefined={})


SCENE = FeBlockScene()
