"""The elastic block on the polar-orthotropic plane (the first paper's finite-element experiment).

An elastic cube (edge ``size``, ``cells`` trilinear hexahedra along each edge, Young's modulus
``E``, Poisson's ratio ``nu``, ``density``; ``exu_aniso.fe.block_mesh``) stands on the plane z = 0
with the centre of its bottom face at (x0, y0). Its bottom face's nodes carry the contact: polar
adhesion (eps_r along the radius from the origin, eps_phi along the circles) and polar friction
(mu_r, mu_phi), the stiffnesses totals over the bottom nodes. Its top face is driven: every top node
is tied by a stiff spring (per node and direction ``TOP_STIFFNESS_FACTOR`` E size / top nodes: the
drive is far stiffer than the block) to its place on a driver moved by the prescribed displacement
of the top face: first pressed down by ``press`` (w) over ``t_press``, then moved horizontally by
``travel`` (v) along ``direction`` until t_end, both along a smooth step (3 s^2 - 2 s^3: no jump in
velocity). The elastic body is the full linear FE body (``model=full``: every node's coordinates)
or a reduced one (``model=reduced``: Exudyn's ObjectFFRFreducedOrder, a floating frame and
``modes``; ``basis=craig_bampton``: the static modes of every top and bottom node coordinate,
which hold the contact's local compliance, plus ``modes`` fixed-interface eigenmodes;
``basis=eigenmodes``: ``modes`` free-free eigenmodes only, which miss it). Stiffness-proportional
damping ``stiffness_damping`` (D = beta K) keeps the run quasi-static.

What it measures: the path of the bottom face's centre over the net against the top's prescribed
path (the elastic block lets its bottom be steered by the anisotropy), the force the drive exerts on
the top face (the contact's reaction, through the block), the contact state of every bottom node,
and the energy ledger with the strain energy u.K u / 2, the drive springs' energy and the damping's
dissipation beside the contact's.

Its limit (``rigid_limit``): as E grows the block becomes rigid and its bottom nodes follow the top's
prescribed motion; the contact force is then the contact law driven along that rigid motion, which
this module computes without any multibody engine (the law stepped along the path, its history
committed each step). The scene approaches it like 1/E (tests/test_fe_block.py).
"""
from __future__ import annotations

import math

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.engines.timing import time_grid, time_step
from exu_aniso.fe import block_mesh
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Plane
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.law.history import HISTORY_FIELDS, SLIP, STICK, N_HISTORY
from exu_aniso.law.return_maps import RETURN_MAPS
from exu_aniso.scenes.base import ENERGY_COLUMNS, SOLVERS, SceneParams, energy_ledger, scene_parameters

FE_BLOCK_PARAMS = {
    "model": ("full", "-", "the elastic body: full (every mesh node's coordinates) or reduced (a floating frame "
              "and modes: Exudyn's ObjectFFRFreducedOrder)", ("full", "reduced")),
    "basis": ("craig_bampton", "-", "reduced: craig_bampton (static modes of every top and bottom node coordinate, "
              "plus `modes` fixed-interface eigenmodes) or eigenmodes (`modes` free-free eigenmodes)",
              ("craig_bampton", "eigenmodes")),
    "modes": (0, "-", "reduced: the number of eigenmodes (see basis)", "int >= 0"),
    "size": (0.1, "m", "edge length of the cube", "> 0"),
    "cells": (3, "-", "trilinear hexahedra along each edge", "int >= 1"),
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
                   "elastic block is steered by the adhesion net as their rigid one (the block scene's choice)",
                   RETURN_MAPS),
    "press": (1e-3, "m", "w: the top face pressed down over t_press", "> 0"),
    "travel": (0.1, "m", "v: the top face's horizontal travel after the pressing, until t_end", ">= 0"),
    "direction": (90.0, "deg", "direction of the travel from +x (90: along +y, along the circle at the start)",
                  "real"),
    "t_press": (0.2, "s", "duration of the pressing", "> 0"),
    "t_end": (1.2, "s", "simulated time", "> 0"),
    "dt": (1e-3, "s", "time step", "> 0"),
    "solver": ("trapezoidal", "-", "time integrator", SOLVERS),
}

TOP_STIFFNESS_FACTOR = 100.0
"""The drive's spring per top node and direction is TOP_STIFFNESS_FACTOR E size / (top nodes) [N/m]:
a hundred times the block's own axial stiffness E size in all, so the top face follows its prescribed
motion to about 1 %, and in the stiff limit the springs' compliance falls like 1/E as the block's."""

DRIVER_MASS_FACTOR = 1e-3
"""The driver (a mass point moved by prescribed coordinates) has this share of the block's mass."""


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
        if self.model == "reduced" and self.basis == "eigenmodes" and self.modes < 1:
            raise ValueError("modes must be >= 1 with model=reduced and basis=eigenmodes (the body's only "
                             "deformation)")
        if self.cells > 12:
            raise ValueError(f"cells must be <= 12 (the full body's coordinates grow like cells^3: "
                             f"{3 * (self.cells + 1) ** 3} here); got {self.cells}")

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


def top_stiffness(p):
    """The drive's spring per top node and direction [N/m] (TOP_STIFFNESS_FACTOR)."""
    return TOP_STIFFNESS_FACTOR * p.E * p.size / (p.cells + 1) ** 2


def _smooth(s):
    """3 s^2 - 2 s^3 on [0, 1] and its derivative (0 and 1 outside)."""
    s = np.clip(s, 0.0, 1.0)
    return s * s * (3.0 - 2.0 * s), 6.0 * s * (1.0 - s)


def drive(p, t):
    """The top face's prescribed displacement [m] and velocity [m/s] at time(s) t: (n, 3), (n, 3)."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    s1, ds1 = _smooth(t / p.t_press)
    s2, ds2 = _smooth((t - p.t_press) / (p.t_end - p.t_press))
    a = math.radians(p.direction)
    e = np.array([math.cos(a), math.sin(a), 0.0])
    u = p.travel * s2[:, None] * e - p.press * s1[:, None] * np.array([0.0, 0.0, 1.0])
    v = p.travel * ds2[:, None] / (p.t_end - p.t_press) * e - p.press * (ds1 / p.t_press)[:, None] * np.array(
        [0.0, 0.0, 1.0])
    return u, v


# trajectory columns (trajectory.csv) -> SI unit
COLUMNS = {"t": "s", "x_top": "m", "y_top": "m", "x_bottom": "m", "y_bottom": "m", "z_bottom": "m",
           "force_x": "N", "force_y": "N", "force_z": "N", "stick_fraction": "-", "slip_fraction": "-",
           "strain_energy": "J", "dissipated_energy": "J", **{k: "J" for k in ENERGY_COLUMNS}}
TITLE_KEYS = ("steer_end", "force_ratio_end")

_STATUS = HISTORY_FIELDS.index("status")


def contact_columns(H):
    """stick_fraction and slip_fraction (n,) of the bottom nodes from the history H (n, K, 9)."""
    S = np.asarray(H)[:, :, _STATUS]
    return (S == STICK).mean(axis=1), (S == SLIP).mean(axis=1)


def fe_block_energy(p, traj, Xb, Vb, H, kinetic, strain, springs, damping, work_in):
    """The energy ledger (energy_ledger's summary entries; the ENERGY_COLUMNS added to traj): work of
    the drive = kinetic (block and driver) + stored (strain, the drive's springs, the contact's
    penalty and adhesion) + dissipated (the contact's and the Rayleigh damping's). Xb, Vb (n, K, 3):
    the bottom nodes; H (n, K, 9) their history; the other terms (n,) [J] from the model."""
    stored, dissipated = energy.contact_energy(fe_block_contact_law(p), Xb, Vb, H)
    return energy_ledger(dict(work_in=work_in, kinetic=kinetic, potential=np.zeros(len(work_in)),
                              stored=stored + strain + springs, dissipated=dissipated + damping), traj,
                         "fe_block run", "reduce dt, or raise stiffness_damping (a quasi-static run)")


def fe_block_summary(traj, p, wall_s, steps, newton_iterations):
    """Summary of a run: the end of the bottom centre's path against the top's, its offset along and
    across the travel (lag_end, steer_end [m]: the steering by the net), the drive's force on the top
    face at the end and the ratio of its horizontal part to its vertical one, the contact state."""
    a = math.radians(p.direction)
    e, n = np.array([math.cos(a), math.sin(a)]), np.array([-math.sin(a), math.cos(a)])
    d = np.array([traj["x_bottom"][-1] - traj["x_top"][-1], traj["y_bottom"][-1] - traj["y_top"][-1]])
    F = np.array([traj["force_x"][-1], traj["force_y"][-1], traj["force_z"][-1]])
    return dict(complete=True, x_bottom_end=float(traj["x_bottom"][-1]), y_bottom_end=float(traj["y_bottom"][-1]),
                x_top_end=float(traj["x_top"][-1]), y_top_end=float(traj["y_top"][-1]),
                lag_end=float(-d @ e), steer_end=float(d @ n),
                r_bottom_end=float(math.hypot(traj["x_bottom"][-1], traj["y_bottom"][-1])),
                force_x_end=float(F[0]), force_y_end=float(F[1]), force_z_end=float(F[2]),
                force_ratio_end=float(math.hypot(F[0], F[1]) / abs(F[2])) if F[2] != 0.0 else None,
                stick_fraction_end=float(traj["stick_fraction"][-1]), slip_fraction_end=float(traj["slip_fraction"][-1]),
                strain_energy_end=float(traj["strain_energy"][-1]),
                dissipated_energy=float(traj["dissipated_energy"][-1]),
                wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations))


def rigid_limit(p):
    """The scene's limit of a rigid block: the bottom nodes translated by the top's prescribed
    displacement, the contact law stepped along that motion on the scene's time grid (its history
    committed each step, as an engine does). Returns dict t (n,), force (n, 3): the force the contact
    exerts on the block [N] (the drive's force on the top face is its negative), H (n, K, 9)."""
    law = fe_block_contact_law(p)
    mesh = fe_block_mesh(p)
    X0 = mesh.nodes[mesh.node_sets["bottom"]] + np.array([p.x0, p.y0, 0.0])
    t = time_grid(p)
    U, V = drive(p, t)
    dt = time_step(p)
    H = np.zeros((len(t), len(X0), N_HISTORY))
    F = np.zeros((len(t), 3))
    h = np.zeros((len(X0), N_HISTORY))
    for i in range(len(t)):
        st = law.evaluate(X0 + U[i], np.broadcast_to(V[i], X0.shape), h, False, dt if i else 0.0)
        h = st.history
        H[i], F[i] = h, st.force.sum(axis=0)
    return dict(t=t, force=F, H=H)


def PlotFeBlock(traj, params, fig):
    """trajectory.png: the bottom centre's path and the top's over the polar net (left), the drive's
    force on the top face and the sliding share of the bottom nodes (right)."""
    p = params
    a1, a2 = fig.subplots(1, 2)
    xb, yb = np.asarray(traj["x_bottom"]), np.asarray(traj["y_bottom"])
    xt, yt = np.asarray(traj["x_top"]), np.asarray(traj["y_top"])
    r = np.hypot(np.concatenate([xb, xt]), np.concatenate([yb, yt]))
    phi = np.linspace(0.0, 2.0 * math.pi, 361)
    for rc in np.linspace(max(r.min() - 0.05, 0.0), r.max() + 0.05, 6):
        a1.plot(rc * np.cos(phi), rc * np.sin(phi), color="0.85", lw=0.6)
    a1.plot(xt, yt, "k--", lw=0.9, label="top face (prescribed)")
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
    for key, label in (("force_x", "$F_x$"), ("force_y", "$F_y$"), ("force_z", "$F_z$")):
        a2.plot(t, traj[key], label=label)
    a2.set_xlabel("t [s]")
    a2.set_ylabel("drive's force on the top face [N]")
    a2b = a2.twinx()
    a2b.plot(t, traj["slip_fraction"], color="0.5", lw=0.8, ls=":", label="sliding share of the bottom nodes")
    a2b.set_ylim(-0.05, 1.05)
    a2b.set_ylabel("sliding share [-]")
    a2.legend(fontsize=7, loc="upper left")
    a2b.legend(fontsize=7, loc="lower right")
    a2.grid(alpha=0.3)
