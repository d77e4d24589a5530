"""The elastic screw in a hole with a spiral net (the second paper's finite-element experiment).

An elastic shank (a tube: outer radius ``radius + interference``, inner radius ``bore``, length
``length``; ``cells_r`` x ``cells_theta`` x ``cells_z`` trilinear hexahedra of a polar grid; Young's
modulus ``E``, Poisson's ratio ``nu``, ``density``; ``exu_aniso.fe.shank_mesh``) turns in the rigid
hole of the screw scene (``exu_aniso.scenes.screw``: the cylinder of radius ``radius``, axis z,
adhesion and friction on a spiral net of helix angle ``helix_angle``). Every node of its outer
surface (the thread side) carries the contact, the stiffnesses totals over those nodes, so that the
nodes sit where the rigid screw's ``rings x points_per_ring`` points do (rings = cells_z + 1,
points_per_ring = cells_theta) and the interference fit presses them onto the hole. It is turned at
its head (the face z = +length/2) by a torsional spring ``drive_stiffness`` to a driver rotating at
``rotation_speed``; a constant ``axial_load`` acts along +z.

The body is Exudyn's ObjectFFRFreducedOrder (a floating frame of reference and modes, so the shank
turns through whole revolutions with linear elasticity in its frame), with a basis that vanishes at
the head: the frame is the head's rigid motion, and the drive acts on it. ``model=full``: every
coordinate of the other nodes is a mode (the full FE body in that frame); ``model=reduced`` with
``basis=craig_bampton``: the static modes of every thread node coordinate with the head clamped
(``ElasticMesh.craig_bampton_modes``: they span the shank's static response to any load on the
thread, so its give under the contact is the mesh's) plus ``modes`` eigenmodes of the shank clamped
at its head and thread; with ``basis=eigenmodes``: the ``modes`` lowest eigenmodes of the shank
clamped at its head (``ElasticMesh.clamped_modes``), which bend and twist it but hardly let the
thread give radially. The summary says how much of the thread nodes' static compliance the basis
keeps (``contact_compliance_share``, ``exu_aniso.fe.compliance_share``) and warns below
``scenes.base.COMPLIANCE_SHARE_FLOOR`` (``basis_warning``, a BasisWarning).
Stiffness-proportional damping ``stiffness_damping`` (D = beta K) damps the body's own vibration.
The shank starts at rest pressed into the hole (``press_fit``: the basis's static state under the
interference fit), not undeformed with the whole interference as a jump of force on it.

What it measures: the advance per revolution and the drive's torque (as the rigid screw), and the
twist along the shank: each ring's rotation relative to the head, from the modal displacements of
its nodes. In steady sliding every node slides with the same friction force, so the shank carries
equal torques T / rings at its rings; statics of a shaft gives the twist of ring j (at s_j = j L /
cells_z from the tip) relative to the head

    phi_j = -(T / (G J)) (L / cells_z) sum_{i=j}^{cells_z-1} (i + 1) / (cells_z + 1),

G = E / (2 (1 + nu)), J = pi (R^4 - bore^4) / 2 (R the shank's outer radius); at the tip this is
-T L / (2 G J), the value of the shaft under a uniformly distributed torque T / L, whose twist is
phi(s) = -T (L^2 - s^2) / (2 G J L) (``twist_closed_form``). The FE mesh approaches it as it is
refined (its polygonal section and trilinear elements are stiffer or softer by a few per cent).

Its limit: as E grows the shank becomes the rigid screw of the screw scene with the same points
(``rigid_screw``, model "full"), and the advance and torque approach that run's like 1/E
(tests/test_fe_screw.py).
"""
from __future__ import annotations

import math

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.fe import cost as fe_cost
from exu_aniso.fe import shank_mesh
from exu_aniso.law.return_maps import RETURN_MAPS
from exu_aniso.scenes.base import (LEDGER_COLUMNS, LEDGER_TERM_COLUMNS, SOLVERS, SceneParams, basis_compliance,
                                   energy_ledger, scene_parameters, solver_advice)
from exu_aniso.scenes.scene import Scene
from exu_aniso.scenes.fe_block import contact_columns
from exu_aniso.scenes.screw import (SCREW_NORMAL_DAMPING, SCREW_PARAMS, ScrewParams, screw_closed_forms,
                                    screw_contact_law, screw_summary)

FE_SCREW_PARAMS = {
    "model": ("reduced", "-", "the elastic body in its floating frame: full (every coordinate of the nodes off the "
              "head) or reduced (the mode basis `basis`, clamped at the head)", ("full", "reduced")),
    "basis": ("craig_bampton", "-", "reduced: craig_bampton (the static modes of every thread node coordinate off the "
              "head, which hold the contact's local compliance, plus `modes` eigenmodes of the shank clamped at its "
              "head and thread) or eigenmodes (the `modes` lowest eigenmodes of the shank clamped at its head, which "
              "miss most of its radial give under the thread)", ("craig_bampton", "eigenmodes")),
    "modes": (0, "-", "reduced: the number of eigenmodes (see basis)", "int >= 0"),
    "radius": (0.005, "m", "radius of the hole (the shank's outer radius is radius + interference)", "> 0"),
    "bore": (0.0025, "m", "inner radius of the hollow shank (a cannulated screw), in (0, radius)", "> 0"),
    "length": (0.02, "m", "length of the shank, all of it engaged in the hole", "> 0"),
    "cells_r": (1, "-", "hexahedra across the wall", "int >= 1"),
    "cells_theta": (24, "-", "hexahedra around the circumference (the thread nodes per ring), at least 6; the "
                    "twist's error is the polygonal section's (studies/fe_screw.py)", "int >= 1"),
    "cells_z": (2, "-", "hexahedra along the shank (cells_z + 1 rings of thread nodes)", "int >= 1"),
    "E": (3e9, "Pa", "Young's modulus (3 GPa: a polyamide screw)", "> 0"),
    "nu": (0.3, "-", "Poisson's ratio, in (-1, 0.5)", "real"),
    "density": (1150.0, "kg/m^3", "density", "> 0"),
    "stiffness_damping": (0.0, "s", "stiffness-proportional damping beta (D = beta K) of the shank; none by default: "
                          "generalized-alpha damps the modes dt does not resolve, and the steady sliding does not "
                          "depend on it", ">= 0"),
    "interference": (1e-5, "m", "interference fit: the shank's outer radius minus the hole's", ">= 0"),
    "eps_n": (1e7, "N/m", "total normal penalty stiffness, split equally over the thread nodes", "> 0"),
    # the net and the law's tangential part: the screw scene's own entries
    **{name: SCREW_PARAMS[name] for name in ("helix_angle", "adhesion", "eps_1", "eps_2", "friction", "mu_1", "mu_2")},
    "return_map": ("radial", "-", "sliding return map; radial here, the package's default is exact: the papers' "
                   "screw slides where the spiral adhesion steers it (the screw scene's choice)", RETURN_MAPS),
    "rotation_speed": (2.0 * math.pi, "rad/s", "angular speed of the driver at the head", "real"),
    "drive_stiffness": (1.0, "N m/rad", "stiffness of the torsional spring from the driver to the head", "> 0"),
    "axial_load": (0.0, "N", "constant axial force along +z on the head", "real"),
    "normal_damping": (SCREW_NORMAL_DAMPING, "N s/m", "total normal contact damping, split equally over the thread "
                       "nodes (the screw scene's default)", ">= 0"),
    "tangential_damping": (0.0, "N s/m", "total tangential dashpot parallel to friction while loaded", ">= 0"),
    "t_end": (1.0, "s", "simulated time", "> 0"),
    "dt": (1e-3, "s", "time step", "> 0"),
    "solver": ("generalized_alpha", "-", "time integrator: generalized-alpha (rho_inf 0.8) damps the shank's modes "
               "above what dt resolves; the trapezoidal rule keeps them and cuts its steps at the contact "
               "(docs/guide/scenes.md)", SOLVERS),
}





@scene_parameters(FE_SCREW_PARAMS)
class FeScrewParams(SceneParams):
    """Elastic screw in a hole with a spiral net; see FE_SCREW_PARAMS for units and meaning."""

    def _check_scene(self):
        if self.cells_theta < 6:
            raise ValueError(f"cells_theta must be >= 6 (a polygon close to the circle); got {self.cells_theta}")
        if not -1.0 < self.nu < 0.5:
            raise ValueError(f"nu must lie in (-1, 0.5) (a positive definite elasticity); got {self.nu!r}")
        if not self.bore < self.radius:
            raise ValueError(f"bore must be < radius (a tube); got bore={self.bore!r}, radius={self.radius!r}")
        free, static = self.free_coordinates(), self.static_modes()
        if self.model == "reduced":
            if self.basis == "eigenmodes" and self.modes < 1:
                raise ValueError("modes must be >= 1 with model=reduced and basis=eigenmodes (the shank's only "
                                 "deformation)")
            if self.basis == "eigenmodes" and self.modes > free:
                raise ValueError(f"modes must be <= {free} with basis=eigenmodes (the coordinates off the head); "
                                 f"got {self.modes}")
            if self.basis == "craig_bampton" and self.modes > free - static:
                raise ValueError(f"modes must be <= {free - static} with basis=craig_bampton (the coordinates off "
                                 f"the head and the thread: the fixed-interface eigenmodes); got {self.modes}")
        # the elastic body's cost, once its modes are known to exist
        layout = (f"cells_r={self.cells_r}, cells_theta={self.cells_theta}, cells_z={self.cells_z}, model={self.model}"
                  + (f", basis={self.basis}, modes={self.modes}" if self.model == "reduced" else ""))
        nodes = (self.cells_r + 1) * self.cells_theta * (self.cells_z + 1)
        fe_cost.check_cost(nodes, self.body_modes(), layout)

    def free_coordinates(self):
        """The mesh's coordinates off the head (the frame's)."""
        return 3 * (self.cells_r + 1) * self.cells_theta * self.cells_z

    def static_modes(self):
        """Craig-Bampton's static modes: the thread's coordinates off the head (3 cells_theta cells_z)."""
        return 3 * self.cells_theta * self.cells_z

    def body_modes(self):
        """The shank's modes: every coordinate off the head (full), the thread's static modes plus
        ``modes`` (craig_bampton) or ``modes`` (eigenmodes)."""
        if self.model == "full":
            return self.free_coordinates()
        return self.modes + (self.static_modes() if self.basis == "craig_bampton" else 0)

    @classmethod
    def cost_rules(cls):
        return super().cost_rules() + fe_cost.cost_rules()

    def contact_points(self):
        return (self.cells_z + 1) * self.cells_theta

    def _layout_text(self):
        return f"cells_z + 1 = {self.cells_z + 1} rings x cells_theta = {self.cells_theta} thread nodes"


def fe_screw_mesh(p):
    """The shank's ElasticMesh (body frame: axis z, centre at the origin, head at z = +length/2)."""
    return shank_mesh(p.radius + p.interference, p.bore, p.length, (p.cells_r, p.cells_theta, p.cells_z),
                      E=p.E, nu=p.nu, rho=p.density)


def rigid_screw(p, mass):
    """The screw scene's parameters of the rigid screw with the same contact points and law, drive
    and load: model "full" (6 DOF), rings = cells_z + 1, points_per_ring = cells_theta, mass [kg]
    (the shank's: its inertia is then the screw scene's solid cylinder, which steady sliding does not
    see)."""
    return ScrewParams(model="full", drive="rotation", surface="cylinder", radius=p.radius, length=p.length,
                       mass=mass, interference=p.interference, helix_angle=p.helix_angle, eps_n=p.eps_n,
                       adhesion=p.adhesion, eps_1=p.eps_1, eps_2=p.eps_2, friction=p.friction, mu_1=p.mu_1,
                       mu_2=p.mu_2, return_map=p.return_map, rotation_speed=p.rotation_speed,
                       drive_stiffness=p.drive_stiffness, axial_load=p.axial_load, rings=p.cells_z + 1,
                       points_per_ring=p.cells_theta, normal_damping=p.normal_damping,
                       tangential_damping=p.tangential_damping, t_end=p.t_end, dt=p.dt, solver=p.solver)


def fe_screw_contact_law(p):
    """The screw scene's hole and spiral fields, per thread node (screw_contact_law of rigid_screw)."""
    return screw_contact_law(rigid_screw(p, 1.0))


def fe_screw_basis(p, mesh):
    """The mode basis (3N, m): zero at the head's nodes; every other coordinate (full), the static
    modes of the thread nodes' coordinates with the head clamped plus ``modes`` fixed-interface
    eigenmodes (reduced, craig_bampton: ``ElasticMesh.craig_bampton_modes``) or the clamped shank's
    ``modes`` lowest eigenmodes (reduced, eigenmodes: ``ElasticMesh.clamped_modes``)."""
    head = mesh.node_sets["head"]
    if p.model == "full":
        return mesh.clamped_modes(head, None)
    if p.basis == "craig_bampton":
        return mesh.craig_bampton_modes(head, mesh.node_sets["thread"], p.modes)
    return mesh.clamped_modes(head, p.modes)


def basis_name(p):
    """The basis in words, for the warning: e.g. "12 clamped eigenmodes"."""
    if p.model == "full":
        return "the full body"
    if p.basis == "eigenmodes":
        return f"{p.modes} clamped eigenmodes"
    return f"Craig-Bampton: {p.static_modes()} static modes + {p.modes} fixed-interface eigenmodes"


def contact_compliance(p, mesh, basis, warn=True):
    """The summary's entries on the basis: ``scenes.base.basis_compliance`` of the thread nodes, the head clamped."""
    return basis_compliance(p, mesh, basis, "thread", "head", (basis_name(p), "thread nodes", "shank"), warn)


def thread_directions(mesh):
    """The thread nodes (K,) of the shank's mesh and their radial and circumferential unit vectors
    e_r, e_phi (K, 3) in the body frame (axis z)."""
    thread = mesh.node_sets["thread"]
    r = mesh.nodes[thread]
    e_r = np.column_stack([r[:, 0], r[:, 1], np.zeros(len(r))]) / np.hypot(r[:, 0], r[:, 1])[:, None]
    return thread, e_r, np.column_stack([-e_r[:, 1], e_r[:, 0], np.zeros(len(r))])


def press_fit(p, mesh, basis):
    """The modal coordinates eta (m,) [m] of the shank pressed into the hole at rest: every thread node
    k at its reference radius R + interference penetrates the hole by interference + e_r . u_k and
    the normal penalty eps_n / K pushes it in along -e_r, so the static state of the basis Psi solves

        (Psi^T K Psi + sum_k eps Psi_k^T e_r e_r^T Psi_k) eta = -sum_k eps interference Psi_k^T e_r

    (linear: the normal penalty only, no friction). Starting there, the run does not begin with the
    whole interference as a jump of force on the elastic shank (which cut the first steps)."""
    thread, e_r, _ = thread_directions(mesh)
    eps = p.eps_n / len(thread)
    rows = (3 * thread[:, None] + np.arange(3)).ravel()
    radial = np.einsum("ki,kim->km", e_r, basis[rows].reshape(len(thread), 3, -1))     # e_r . Psi_k (K, m)
    A = basis.T @ (mesh.stiffness @ basis) + eps * radial.T @ radial
    return np.linalg.solve(A, -eps * p.interference * radial.sum(axis=0))


def torsional_rigidity(p):
    """G J [N m^2] of the shank's circular section: G = E / (2 (1 + nu)), J = pi (R^4 - bore^4) / 2."""
    R = p.radius + p.interference
    return p.E / (2.0 * (1.0 + p.nu)) * 0.5 * math.pi * (R ** 4 - p.bore ** 4)


def twist_closed_form(p, torque):
    """Rotation [rad] of each ring of thread nodes (tip first) relative to the head when the shank
    carries equal torques torque / rings at its rings [N m in all], from the statics of a shaft
    (module docstring); the last entry (the head) is 0."""
    n = p.cells_z
    dz = p.length / n
    segment = torque * (np.arange(n) + 1.0) / (n + 1)           # torque carried between ring i and i + 1
    return -np.concatenate([np.cumsum(segment[::-1])[::-1], [0.0]]) * dz / torsional_rigidity(p)


def ring_twist(p, mesh, displacement):
    """Rotation [rad] of each ring of thread nodes (tip first) relative to the head, from the nodes'
    displacements in the body frame (n, N, 3): the mean of e_phi . u / R over the ring's nodes."""
    thread, _, e_phi = thread_directions(mesh)
    R = p.radius + p.interference
    phi = np.einsum("nki,ki->nk", np.asarray(displacement)[:, thread], e_phi) / R
    return phi.reshape(len(phi), p.cells_z + 1, p.cells_theta).mean(axis=2)


def static_twist(p, torque, mesh=None):
    """The FE answer to twist_closed_form: the rotation [rad] of each ring (tip first) relative to the
    head of the shank's mesh clamped at its head, each thread node loaded by the tangential force
    torque / (rings cells_theta R) [N] against e_phi (friction resisting the turn: equal torques at
    the rings, torque [N m] in all, which the head carries), from K u = f (scipy's sparse solve)."""
    import scipy.sparse.linalg
    mesh = fe_screw_mesh(p) if mesh is None else mesh
    thread, _, e_phi = thread_directions(mesh)
    R = p.radius + p.interference
    f = np.zeros((mesh.number_of_nodes, 3))
    f[thread] = -torque / (len(thread) * R) * e_phi
    free = np.ones(mesh.number_of_nodes, dtype=bool)
    free[mesh.node_sets["head"]] = False
    free = np.flatnonzero(np.repeat(free, 3))
    u = np.zeros(mesh.number_of_coordinates)
    u[free] = scipy.sparse.linalg.spsolve(mesh.stiffness[free][:, free].tocsc(), f.ravel()[free])
    return ring_twist(p, mesh, u.reshape(1, -1, 3))[0]


COLUMNS = {"t": "s", "angle": "rad", "z": "m", "omega": "rad/s", "vz": "m/s", "torque": "N m", "axial_force": "N",
           "twist_tip": "rad", "strain_energy": "J", "stick_fraction": "-", "slip_fraction": "-",
           "dissipated_energy": "J", **{k: "J" for k in LEDGER_TERM_COLUMNS}, "rayleigh_dissipated_energy": "J",
           **LEDGER_COLUMNS}
TITLE_KEYS = ("advance_per_rev", "twist_tip")


def fe_screw_summary(traj, p, wall_s, steps, newton_iterations, compliance=None):
    """The screw's summary (advance per revolution, mean torque and axial force over the last half,
    with the rigid screw's closed-form steady sliding beside them: ``exu_aniso.scenes.screw.screw_summary``
    of ``rigid_screw``) and the twist: every ring's rotation relative to the
    head averaged over the last half (twist_profile, tip first) against twist_closed_form of the
    mean torque (twist_profile_theory), their tip values (twist_tip, twist_tip_theory; from
    traj["twist_rings"] (n, rings): the rotations) and the ratio (twist_ratio: 1 for a shaft of the
    closed form's section); compliance: the basis's entries (``contact_compliance``), added last."""
    s = screw_summary(traj, rigid_screw(p, 1.0), wall_s, steps, newton_iterations)
    late = np.asarray(traj["t"]) >= 0.5 * traj["t"][-1]
    profile = np.asarray(traj["twist_rings"])[late].mean(axis=0)
    theory = twist_closed_form(p, s["torque_mean"])
    if theory[0] != 0.0:
        ratio = float(profile[0] / theory[0])
    else:
        ratio = None
        s["undefined"]["twist_ratio"] = "the closed form's tip twist is 0 (no torque over the last half)"
    s.update(twist_profile=profile.tolist(), twist_profile_theory=theory.tolist(), twist_tip=float(profile[0]),
             twist_tip_theory=float(theory[0]), twist_ratio=ratio,
             strain_energy_end=float(traj["strain_energy"][-1]),
             slip_fraction_end=float(traj["slip_fraction"][-1]), **(compliance or {}))
    return s


def fe_screw_energy(p, traj, X, V, H):
    """The energy ledger (the ENERGY_COLUMNS and the contact's energy columns added to traj): the
    drive's torque over the head's angle and the axial load over z = the shank's kinetic energy +
    stored (strain, the contact's penalty and adhesion) + dissipated (the contact's and the Rayleigh
    damping's); every term is a column of traj (COLUMNS). X, V (n, K, 3): the thread nodes; H
    (n, K, 9) their history."""
    traj["contact_stored_energy"], traj["contact_dissipated_energy"] = energy.contact_energy(
        fe_screw_contact_law(p), X, V, H)
    work = energy.work_trapezoid(traj["torque"], traj["angle"]) + energy.work_trapezoid(traj["axial_force"], traj["z"])
    return energy_ledger(dict(work_in=work, kinetic=traj["kinetic_energy"], potential=np.zeros(len(work)),
                              stored=traj["contact_stored_energy"] + traj["strain_energy"],
                              dissipated=traj["contact_dissipated_energy"] + traj["rayleigh_dissipated_energy"]), traj,
                         "fe_screw run", solver_advice(p))


def fe_screw_columns(traj, H):
    """Add stick_fraction and slip_fraction of the thread nodes (history H (n, K, 9)) to traj."""
    traj["stick_fraction"], traj["slip_fraction"] = contact_columns(H)


def PlotFeScrew(traj, params, fig):
    """trajectory.png: the advance z against the angle (left), the drive's torque and the tip's twist
    over time (middle), the twist along the shank (traj["twist_rings"], averaged over the last half)
    against the closed forms (right)."""
    p = params
    a1, a2, a3 = fig.subplots(1, 3)
    a1.plot(traj["angle"], 1e3 * np.asarray(traj["z"]), color="C0")
    a1.set_xlabel("angle of the head [rad]")
    a1.set_ylabel("axial advance z [mm]")
    a1.grid(alpha=0.3)
    a2.plot(traj["t"], traj["torque"], color="C1", label="drive torque [N m]")
    a2.set_xlabel("t [s]")
    a2.set_ylabel("drive torque [N m]")
    a2b = a2.twinx()
    a2b.plot(traj["t"], 1e3 * np.asarray(traj["twist_tip"]), color="C2", lw=0.8, label="tip twist [mrad]")
    a2b.set_ylabel("twist of the tip against the head [mrad]")
    a2.legend(fontsize=7, loc="upper left")
    a2b.legend(fontsize=7, loc="lower right")
    t = np.asarray(traj["t"])
    late = t >= 0.5 * t[-1]
    torque = float(np.mean(np.asarray(traj["torque"])[late]))
    s = np.linspace(0.0, p.length, p.cells_z + 1)
    G_J = torsional_rigidity(p)
    fine = np.linspace(0.0, p.length, 101)
    a3.plot(1e3 * fine, -1e3 * torque * (p.length ** 2 - fine ** 2) / (2.0 * G_J * p.length), "k--", lw=0.9,
            label="shaft, uniform torque")
    a3.plot(1e3 * s, 1e3 * twist_closed_form(p, torque), "o", mfc="none", color="k", ms=5, label="shaft, ring torques")
    if "twist_rings" in traj:
        a3.plot(1e3 * s, 1e3 * np.asarray(traj["twist_rings"])[late].mean(axis=0), "s-", color="C0", ms=4,
                label="FE shank")
    a3.set_xlabel("distance from the tip [mm]")
    a3.set_ylabel("rotation against the head [mrad]")
    a3.set_title(f"mean torque {torque:.3g} N m over the last half", fontsize=9)
    a3.legend(fontsize=7)
    a3.grid(alpha=0.3)


# ----------------------------------------------------------------------------------------------
# the scene, as every engine and the command line see it

class FeScrewScene(Scene):
    """The fe_screw scene (the module docstring); no reference-engine model of the elastic shank (its
    limit is the screw scene's rigid screw, ``rigid_screw``); the summary's input: the basis's
    compliance entries, the ledger ``fe_screw_energy``'s (X, V, H)."""

    name = "fe_screw"
    Params = FeScrewParams
    columns = COLUMNS
    title_keys = TITLE_KEYS
    figsize = (13.0, 4.8)
    law = staticmethod(fe_screw_contact_law)
    summary = staticmethod(fe_screw_summary)
    ledger = staticmethod(fe_screw_energy)
    plot = staticmethod(PlotFeScrew)

    def points(self, p):
        """The thread's mesh nodes in the shank's reference configuration [m]."""
        mesh = fe_screw_mesh(p)
        return mesh.nodes[mesh.node_sets["thread"]]

    def closed_forms(self, p):
        """The rigid screw's steady sliding (``screw_closed_forms`` of ``rigid_screw``: advance per
        revolution [m], torque [N m]) and the tip's twist [rad] under that torque
        (``twist_closed_form``), None with the reason under ``undefined`` where the steady sliding
        does not apply."""
        out = screw_closed_forms(rigid_screw(p, 1.0))
        torque = out["torque_mean_theory"]
        out["twist_tip_theory"] = None if torque is None else float(twist_closed_form(p, torque)[0])
        if torque is None:
            out["undefined"]["twist_tip_theory"] = out["undefined"]["torque_mean_theory"]
        return out


SCENE = FeScrewScene()
