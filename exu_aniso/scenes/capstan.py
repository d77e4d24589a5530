"""The capstan scene (a rope over a drum at slip onset, Euler-Eytelwein): parameters,
CSV columns, summary, energy ledger and plot. No Exudyn here: the model is ``exu_aniso/models/capstan.py``
(``exu_aniso.models.capstan``: ``BuildCapstan``, ``RunCapstan``).

Scene
-----
A rope (2D ANCF cables, ``ObjectANCFCable2D``, in the plane z = 0) lies over a drum
``Cylinder(radius, side="outside")`` about the z axis, fixed to ground. It wraps ``wrap_angle``
symmetrically about the top of the drum (+y), with straight tails of ``tail_length`` along the
tangents at both ends of the arc. Going along the rope: the in-end (left tail, start of the rope),
the arc clockwise over the top, the out-end (right tail). Both end forces act along the tails'
initial directions, away from the drum:

* ``0 <= t <= t_load``: both ends are loaded from 0 to ``tension_in`` (smooth ramp, equal tensions:
  the rope settles on the drum);
* ``t > t_load``: the in-end force stays ``tension_in``; the out-end force rises at
  ``ramp_rate * tension_in`` per second (quasi-static) until the rope slips as a whole.

Each end also carries a dashpot to ground (``end_damping``, both directions of the plane: the
loading device's damping; at sqrt(EA m') it absorbs the axial waves of the tail). The drum's
contact has normal damping. Gravity is off. The tails may cross below the drum for wrap angles
above 180 deg: this is a planar model without rope-rope contact.

Friction ``isotropic`` (mu_1) or ``orthotropic``: ``Friction.orthotropic(mu_1, mu_2, angle=0)`` on
the Cylinder, whose xi1 is the angle about the axis, so e1 is circumferential (along the rope) and
e2 axial (across it). Adhesion likewise with eps_1_per_length (circumferential) and eps_2_per_length (axial).
The rope slides along e1 only, so the theory is exp(mu_1 phi) whatever mu_2 (tests/test_capstan.py).

Slip onset (``tension_ratio``): the rope slips as a whole when no contact point on the arc sticks
any more (quasi-static Euler theory: the slip zone grows from the out-end and reaches the in-end at
T_out = T_in exp(mu phi)). The criterion, on the converged history: the first sample of the last
uninterrupted run of samples, ending at the end of the run, in which every contact point loaded
(N < 0) in this sample and the one before has status slip (a point that has just come onto the
drum starts sticking by definition: it does not count); the run itself stops once the in-end
has moved ``stop_displacement`` towards the drum (counted from t_load), so that run of gross slip
is established. Flickers of "all slip"
before (e.g. while the rope settles) do not count. ``tension_ratio`` = T_out / T_in there, with
the tensions at the rope's ends: the applied force less the end dashpot's force (columns
``tension_in``, ``tension_out``; the applied forces are ``force_in``, ``force_out``: measured
by them the ratio is late by the dashpot's share). The error against exp(mu_1 phi) is the time
resolution of the ramp (the ratio rises by ramp_rate dt per step) and the quasi-static lag of the
ramp, which shows at fast ramps (tests/test_capstan.py::test_ratio_as_the_ramp_slows; the figures:
docs/guide/scenes.md).
``tension_ratio_displacement`` is a cross-check with a different criterion: T_out / T_in when the
in-end has moved ``slip_displacement`` towards the drum (late by the time the rope needs to
accelerate; it is an upper bound).

Stiffnesses are per unit length of rope (a point carries eps * ds, ds = element length / points),
so refining the rope keeps the distributed stiffness: ``eps_n_per_length`` [N/m^2],
``eps_1_per_length``, ``eps_2_per_length`` [N/m^2], ``normal_damping_per_length`` [N s/m^2] (the
names say per length: the other scenes' ``eps_n``, ``eps_1``, ``eps_2`` and ``normal_damping`` are
totals of a contact set).

Energy ledger (``capstan_energy``): work in = work of the two end forces; kinetic =
1/2 q_t^T M q_t of the cable (Exudyn's KineticEnergy of each ObjectANCFCable2D, which is that
quadratic form with the consistent Hermite mass matrix); potential = the cable's strain energy
(Exudyn's PotentialEnergy of each element: axial and bending; tests/test_cable.py checks that it
closes a free vibration); stored and dissipated = the contact's (``energy.contact_energy``: normal
penalty, adhesion, friction, normal dashpot) plus the end dashpots' dissipation (trapezoid of
c |v|^2 over the steps). With the trapezoidal rule the residual is the contact law's bookkeeping
(energy.py) and the rope's bending stiffness on the drum (small).
"""
from __future__ import annotations

import math
import sys

import numpy as np

from exu_aniso.engines import energy
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.fields.tensor_fields import Adhesion, Friction
from exu_aniso.geometry import Cylinder
from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP, RETURN_MAPS
from exu_aniso.scenes.base import (LEDGER_COLUMNS, LEDGER_TERM_COLUMNS, SOLVERS, energy_ledger, SceneParams,
                                   scene_parameters)
from exu_aniso.scenes.scene import Scene

CAPSTAN_PARAMS = {
    "radius": (0.1, "m", "drum radius", "> 0"),
    "wrap_angle": (180.0, "deg", "angle the rope wraps the drum (0, 360]; the tails cross below the drum above 180",
                   "> 0"),
    "tail_length": (0.1, "m", "length of each straight tail (tangent to the drum at the ends of the arc)", "> 0"),
    "elements": (12, "-", "ANCF cable elements on the wrapped arc", "int >= 1"),
    "tail_elements": (2, "-", "ANCF cable elements on each tail", "int >= 1"),
    "points": (3, "-", "contact points per element (at x = (i + 1/2) L / points)", "int >= 1"),
    "mass_per_length": (0.1, "kg/m", "mass per length of the rope", "> 0"),
    "axial_stiffness": (1e4, "N", "axial stiffness EA of the rope", "> 0"),
    "bending_stiffness": (1e-4, "N m^2", "bending stiffness EI of the rope (small: a rope)", ">= 0"),
    "tension_in": (10.0, "N", "tension T_in held at the in-end", "> 0"),
    "ramp_rate": (1.0, "1/s", "rise of the out-end force per second, relative to tension_in", "> 0"),
    "t_load": (0.05, "s", "time over which both ends are loaded to tension_in", "> 0"),
    "eps_n_per_length": (1e7, "N/m^2", "normal penalty stiffness per length of rope", "> 0"),
    "adhesion": ("isotropic", "-", "adhesion (sticking stiffness) field B on the drum", ("isotropic", "orthotropic")),
    "eps_1_per_length": (1e6, "N/m^2", "tangential stiffness per length along the circumference (isotropic: "
                         "both)", "> 0"),
    "eps_2_per_length": (1e6, "N/m^2", "tangential stiffness per length along the drum axis",
                         "> 0"),
    "friction": ("isotropic", "-", "friction field F on the drum", ("isotropic", "orthotropic")),
    "mu_1": (0.3, "-", "friction coefficient along the circumference (isotropic: both)", "> 0"),
    "mu_2": (0.3, "-", "friction coefficient along the drum axis (across the rope)", "> 0"),
    "return_map": (DEFAULT_RETURN_MAP, "-", "sliding return map", RETURN_MAPS),
    "normal_damping_per_length": (1e3, "N s/m^2", "normal contact damping per length of rope", ">= 0"),
    "end_damping": (30.0, "N s/m", "dashpot to ground at each rope end (the loading device)", ">= 0"),
    "slip_displacement": (1e-3, "m", "in-end travel towards the drum that marks gross slip (cross-check)", "> 0"),
    "stop_displacement": (5e-3, "m", "in-end travel towards the drum at which the run stops", "> 0"),
    "t_end": (2.0, "s", "longest simulated time (the run stops earlier at stop_displacement)", "> 0"),
    "dt": (1e-3, "s", "time step", "> 0"),
    "solver": ("trapezoidal", "-", "time integrator", SOLVERS),
}


@scene_parameters(CAPSTAN_PARAMS)
class CapstanParams(SceneParams):
    """Rope over a drum (capstan); see CAPSTAN_PARAMS for units and meaning."""

    def contact_points(self):
        return (self.elements + 2 * self.tail_elements) * self.points

    def _layout_text(self):
        return f"(elements={self.elements} + 2 x tail_elements={self.tail_elements}) x points={self.points}"

    def _check_scene(self):
        if not self.wrap_angle <= 360.0:
            raise ValueError(f"wrap_angle must lie in (0, 360] deg; got {self.wrap_angle!r}")
        if not self.t_load < self.t_end:
            raise ValueError(f"t_load must be < t_end; got t_load={self.t_load!r}, t_end={self.t_end!r}")
        if not self.slip_displacement <= self.stop_displacement:
            raise ValueError(f"slip_displacement must be <= stop_displacement; got {self.slip_displacement!r} > "
                             f"{self.stop_displacement!r}")


# trajectory columns -> SI unit (CSV order)
COLUMNS = {"t": "s", "force_in": "N", "force_out": "N", "tension_in": "N", "tension_out": "N", "tension_ratio": "-",
           "u_in": "m", "u_out": "m",
           "x_in": "m", "y_in": "m", "vx_in": "m/s", "vy_in": "m/s",
           "x_out": "m", "y_out": "m", "vx_out": "m/s", "vy_out": "m/s",
           "slip_fraction": "-", "contact_fraction": "-", "dissipated_energy": "J",
           **{k: "J" for k in LEDGER_TERM_COLUMNS}, "strain_energy": "J", "end_dissipated_energy": "J",
           **LEDGER_COLUMNS}
"""trajectory.csv: the applied end forces (force_in, force_out: along ``end_directions(p)``) and the
tensions at the rope's ends (less the end dashpots), their ratio, the ends' travel along the forces
(u_in towards the drum from t_load on, u_out away from it), the end nodes' positions (x, y) and
velocities (vx, vy) in the plane, the sliding and loaded fractions of the contact points, the
contact's history dissipation (friction; dissipated_energy), every term of the energy ledger
(capstan_energy: the rope's kinetic and strain energy, the contact's stored and dissipated energy,
the end dashpots' dissipation) and the ledger. From these and the parameters one recomputes the
ledger's work in (the end forces over the end positions) and the end dashpots' dissipation
(end_damping |v|^2 over the steps); the rope's and the contact's terms need every node and every
contact point, so they are written as they were summed."""

# summary keys for the plot title
TITLE_KEYS = ("tension_ratio", "tension_ratio_theory")


def end_directions(p):
    """Unit vectors (2,) of the in- and out-end forces, along the tails away from the drum: d_in =
    (-cos(phi/2), -sin(phi/2)), d_out = (cos(phi/2), -sin(phi/2)), phi = wrap_angle."""
    h = 0.5 * math.radians(p.wrap_angle)
    return np.array([-math.cos(h), -math.sin(h)]), np.array([math.cos(h), -math.sin(h)])


# the domain of Euler-Eytelwein (capstan_theory): where the slip-onset ratio stays within 1e-3 of
# exp(mu_1 phi) (tests/test_capstan.py holds both edges; the figures: docs/guide/scenes.md)
BENDING_NUMBER_MAX = 2e-3
"""Largest EI / (T_in R^2) (bending_stiffness over tension_in radius^2) for which the rope counts as
perfectly flexible: the ratio falls with it by about 0.3 times the number."""
QUASI_STATIC_MAX = 6.6e-3
"""Largest ramp_rate * L sqrt(mass_per_length / axial_stiffness) (the ramp's relative rise while an
axial wave crosses the rope of length L = radius phi + 2 tail_length) for which the loading counts
as quasi-static (a massless rope). Above it the rope rings at the slip onset and the ratio's error
swings with the ringing's phase, beyond RATIO_RTOL of tests/test_capstan.py (1e-3) at some rates
(tests/test_capstan.py::test_theory_domain_edge_quasi_static holds the edge)."""


def bending_number(p):
    """EI / (T_in R^2): the rope's bending stiffness against the tension at the held end."""
    return p.bending_stiffness / (p.tension_in * p.radius ** 2)


def quasi_static_number(p):
    """ramp_rate * L sqrt(m' / EA), L the rope's length (arc and tails)."""
    L = p.radius * math.radians(p.wrap_angle) + 2.0 * p.tail_length
    return p.ramp_rate * L * math.sqrt(p.mass_per_length / p.axial_stiffness)


EXPONENT_MAX = math.log(sys.float_info.max)
"""The largest mu_1 phi whose exp(mu_1 phi) is a finite double (709.78)."""


def capstan_theory(p):
    """(exp(mu_1 phi), None) where Euler-Eytelwein applies to the scene, else (None, reason naming the
    parameter that breaks it). Its assumptions and how the scene meets them:

    * a perfectly flexible rope: ``bending_number(p)`` <= BENDING_NUMBER_MAX (else the reason names
      bending_stiffness);
    * a massless rope loaded quasi-statically (slip of the whole wrap at rest, no inertia):
      ``quasi_static_number(p)`` <= QUASI_STATIC_MAX (else ramp_rate and mass_per_length);
    * Coulomb friction mu_1 along the rope: the rope slides along e1 (circumference) only, a
      principal axis of the net (the scene's nets are never turned), so mu_2 and the return map change
      nothing (tests/test_capstan.py::test_cross_friction_mu2_does_not_change_the_ratio);
    * the rope conforms to the drum (pressure T / R per length): the penalty's penetration
      T / (eps_n_per_length R) is 1e-5 m on the defaults, and the contact points' polygon is refined away
      (tests/test_capstan.py: 6 to 48 elements within 1e-3);
    * an extensible rope changes nothing at the onset of gross slip (the classic result); no
      tangential dashpot (the scene's law has none); the end dashpots are taken out of the tensions;
      the normal dashpot acts on normal velocities, zero at slip onset; no gravity (the scene has none)."""
    b = bending_number(p)
    if b > BENDING_NUMBER_MAX:
        return None, (f"bending_stiffness: EI / (tension_in radius^2) = {b:.3g} > {BENDING_NUMBER_MAX:g}: the rope "
                      "is not perfectly flexible (its bending stiffness lowers the ratio by ~0.3 times that number)")
    q = quasi_static_number(p)
    if q > QUASI_STATIC_MAX:
        return None, (f"ramp_rate, mass_per_length: ramp_rate L sqrt(mass_per_length / axial_stiffness) = {q:.3g} > "
                      f"{QUASI_STATIC_MAX:g}: the loading is not quasi-static (the rope's inertia delays the slip)")
    exponent = p.mu_1 * math.radians(p.wrap_angle)
    if exponent > EXPONENT_MAX:
        return None, (f"mu_1, wrap_angle: exp(mu_1 phi) = exp({exponent:.6g}) overflows a double (mu_1 phi must be "
                      f"<= {EXPONENT_MAX:.6g} for a finite theory)")
    return math.exp(exponent), None


def element_length(p):
    """(arc element length, tail element length) [m]."""
    return p.radius * math.radians(p.wrap_angle) / p.elements, p.tail_length / p.tail_elements


def element_points(p, length):
    """The contact points of an element of ``length`` [m] in its local frame: ``points`` points at
    (i + 1/2) length / points along its axis [m], (points, 3)."""
    return np.array([[(i + 0.5) * length / p.points, 0.0, 0.0] for i in range(p.points)])


def point_spacing(p):
    """Rope length per contact point on the arc [m] (the share of the distributed stiffnesses)."""
    return element_length(p)[0] / p.points


def capstan_contact_law(p):
    """ContactLaw of the drum: Cylinder(radius, side='outside') about z; per-point values = per-length
    values times the point spacing on the arc (tail points get the same: they are off the drum)."""
    ds = point_spacing(p)
    if p.adhesion == "isotropic":
        B = Adhesion.isotropic(p.eps_1_per_length * ds)
    else:
        B = Adhesion.orthotropic(p.eps_1_per_length * ds, p.eps_2_per_length * ds, angle=0.0)
    if p.friction == "isotropic":
        F = Friction.isotropic(p.mu_1)
    else:
        F = Friction.orthotropic(p.mu_1, p.mu_2, angle=0.0)
    return ContactLaw(Cylinder(p.radius, side="outside"), B, F, normal_stiffness=p.eps_n_per_length * ds,
                      normal_damping=p.normal_damping_per_length * ds, return_map=p.return_map)


def tension_out(p, t):
    """Out-end force [N] at time(s) t: smooth rise to tension_in over t_load, then the ramp."""
    t = np.asarray(t, dtype=float)
    s = np.clip(t / p.t_load, 0.0, 1.0)
    smooth = s * s * (3.0 - 2.0 * s)
    return p.tension_in * np.where(t <= p.t_load, smooth, 1.0 + p.ramp_rate * (t - p.t_load))


def tension_in(p, t):
    """In-end force [N] at time(s) t: smooth rise to tension_in over t_load, then constant."""
    t = np.asarray(t, dtype=float)
    s = np.clip(t / p.t_load, 0.0, 1.0)
    return p.tension_in * s * s * (3.0 - 2.0 * s)


def slip_onset(traj, p):
    """Index of the slip onset (module docstring) or None, and the reason when None."""
    t = np.asarray(traj["t"], float)
    after = t > p.t_load
    gross = (np.asarray(traj["slip_fraction"]) >= 1.0) & after & (np.asarray(traj["contact_fraction"]) > 0.0)
    if not gross[-1]:
        return None, "the rope did not slip as a whole by the end of the run (some contact point still sticks)"
    if np.max(traj["u_in"]) < p.stop_displacement:
        return None, (f"the in-end moved only {np.max(traj['u_in']):.3g} m < stop_displacement = "
                      f"{p.stop_displacement:g} m: gross slip is not established")
    k = len(t) - 1
    while k > 0 and gross[k - 1]:
        k -= 1
    return k, None


def capstan_summary(traj, p, wall_s, steps, newton_iterations):
    """summary.json of a capstan run: tension_ratio (slip onset, ``slip_onset``), the theory
    exp(mu_1 phi) where it applies (``capstan_theory``: None outside its domain), their relative
    difference, the cross-check at slip_displacement, cost figures; ``undefined`` maps every None
    value to its reason."""
    phi = math.radians(p.wrap_angle)
    theory, why_theory = capstan_theory(p)
    undefined = {}
    if theory is None:
        undefined["tension_ratio_theory"] = undefined["tension_ratio_error"] = why_theory
    k, why = slip_onset(traj, p)
    ratio = t_slip = None
    if k is None:
        undefined["tension_ratio"] = undefined["t_slip"] = why
        undefined.setdefault("tension_ratio_error", why)
    else:
        ratio, t_slip = float(traj["tension_ratio"][k]), float(traj["t"][k])
    moved = np.nonzero((np.asarray(traj["u_in"]) >= p.slip_displacement) & (np.asarray(traj["t"]) > p.t_load))[0]
    ratio_disp = None
    if moved.size:
        ratio_disp = float(traj["tension_ratio"][moved[0]])
    else:
        undefined["tension_ratio_displacement"] = (f"the in-end never moved slip_displacement = "
                                                   f"{p.slip_displacement:g} m towards the drum")
    return dict(tension_ratio=ratio, tension_ratio_theory=theory,
                tension_ratio_error=None if ratio is None or theory is None else (ratio - theory) / theory,
                tension_ratio_displacement=ratio_disp, t_slip=t_slip, wrap_angle_rad=phi,
                t_end_reached=float(traj["t"][-1]), dissipated_energy=float(traj["dissipated_energy"][-1]),
                wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations),
                undefined=undefined)


def capstan_energy(p, traj, law, X, V, H, kinetic, potential, work_in, end_dissipation):
    """Energy ledger of a capstan run: adds the ENERGY_COLUMNS and its terms' columns to traj and
    returns the summary entries (energy, energy_ok, energy_tolerance). p: the parameters (the scenes'
    ledgers take them; the capstan's reads none); X, V (n, K, 3): contact points; H (n, K, 9)
    history; kinetic, potential: the cable's (Exudyn's KineticEnergy, PotentialEnergy summed over
    the elements) per sample; work_in: cumulative work of the end forces; end_dissipation:
    cumulative dissipation of the end dashpots."""
    traj["contact_stored_energy"], traj["contact_dissipated_energy"] = energy.contact_energy(law, X, V, H)
    traj.update(kinetic_energy=kinetic, strain_energy=potential, end_dissipated_energy=end_dissipation)
    return energy_ledger(dict(work_in=work_in, kinetic=kinetic, potential=potential,
                              stored=traj["contact_stored_energy"], dissipated=traj["contact_dissipated_energy"] + end_dissipation), traj, "capstan run")


def PlotCapstan(traj, params, fig):
    """The capstan's trajectory figure on the matplotlib Figure fig: tensions T_in, T_out and the
    theoretical slip limit T_in exp(mu_1 phi) over time (top; where ``capstan_theory`` applies), in-end
    travel and the fraction of sliding contact points (bottom); the slip onset marked when there is one."""
    p = params
    a1, a2 = fig.subplots(2, 1, sharex=True)
    t = np.asarray(traj["t"])
    a1.plot(t, traj["tension_out"], label="$T_{out}$ (pulled end of the rope)")
    a1.plot(t, traj["tension_in"], label="$T_{in}$ (held end of the rope)")
    ratio, _ = capstan_theory(p)
    if ratio is not None:
        a1.axhline(p.tension_in * ratio, color="k", ls="--", lw=0.8,
                   label=r"$T_{in}\,e^{\mu_1\varphi}$ (Euler-Eytelwein)")
    k, _ = slip_onset(traj, p)
    if k is not None:
        for ax in (a1, a2):
            ax.axvline(t[k], color="r", lw=0.8, ls=":")
        a1.plot([t[k]], [traj["tension_out"][k]], "ro", label=f"slip onset: ratio {traj['tension_ratio'][k]:.4g}")
    a1.set_ylabel("force [N]")
    a1.legend(fontsize=7, loc="upper left")
    a1.grid(alpha=0.3)
    a2.plot(t, 1e3 * np.asarray(traj["u_in"]), label="in-end travel towards the drum [mm]")
    a2b = a2.twinx()
    a2b.plot(t, traj["slip_fraction"], color="tab:red", lw=0.8, label="sliding fraction of loaded points")
    a2b.set_ylim(-0.05, 1.05)
    a2b.set_ylabel("sliding fraction [-]")
    a2.set_xlabel("t [s]")
    a2.set_ylabel("travel [mm]")
    a2.grid(alpha=0.3)
    h1, l1 = a2.get_legend_handles_labels()
    h2, l2 = a2b.get_legend_handles_labels()
    a2.legend(h1 + h2, l1 + l2, fontsize=7, loc="upper left")
    return a1, a2



# ----------------------------------------------------------------------------------------------
# the scene, as every engine and the command line see it

class CapstanScene(Scene):
    """The capstan scene (the module docstring); no reference-engine model of the rope (the oracle
    is Euler-Eytelwein's); the summary takes no inputs, the ledger ``capstan_energy``'s (law, X, V,
    H, kinetic, potential, work_in, end_dissipation)."""

    name = "capstan"
    Params = CapstanParams
    columns = COLUMNS
    title_keys = TITLE_KEYS
    figsize = (6.0, 6.5)
    law = staticmethod(capstan_contact_law)
    summary = staticmethod(capstan_summary)
    ledger = staticmethod(capstan_energy)
    plot = staticmethod(PlotCapstan)

    def points(self, p):
        """The contact points of an arc element in its local frame [m] (``element_points``)."""
        return element_points(p, element_length(p)[0])

    def closed_forms(self, p):
        """Euler-Eytelwein's ``tension_ratio_theory`` = exp(mu_1 phi) [-] (``capstan_theory``), None with
        the reason under ``undefined`` outside its assumptions."""
        value, why = capstan_theory(p)
        return dict(tension_ratio_theory=value, undefined={"tension_ratio_theory": why} if why else {})


SCENE = CapstanScene()
