"""
A nut's bearing ring that slides sideways loses its grip on the turning
=======================================================================

Why do shaken bolted joints loosen? While a contact ring slides sideways at a speed v, Coulomb friction
acts against every point's slip velocity v e_x + omega r e_phi, so it resists a turning only in
proportion to the spin ratio s = omega r / v: the ring's friction torque is mu N r G(s), with G(s) about
s / 2 for a slow turn. A small torque then turns a ring that, at rest, would hold many times more.

Left: each point is one run of the loosening scene (``exu_aniso.models.loosening.RunLoosening``, case
``bearing``: an M10 nut's bearing ring pressed by 10 kN, dragged across the plate at 0.02 m/s while a
torque turns it), its spin rate against the ring integral (``exu_aniso.scenes.threads``). Right: the
same ring pushed by a rising force instead slides as a whole where force and torque reach the ring's
friction limit, the curve (mu N D(s), mu N r G(s)) over the spin ratio.
"""
import os

import matplotlib.pyplot as plt
import numpy as np

from exu_aniso.models.loosening import RunLoosening
from exu_aniso.scenes.loosening import LooseningParams, loosening_closed_forms
from exu_aniso.scenes.threads import ring_drag_factor, ring_torque_factor

QUICK = os.environ.get("EXU_ANISO_QUICK") == "1"      # the test suite's short form
p0 = LooseningParams()
muNr = p0.mu_bearing * p0.preload * p0.bearing_radius            # the ring's whole friction torque [N m]
torques = np.linspace(0.5, 6.5, 3 if QUICK else 7)

spin = [RunLoosening(p0.with_overrides(torque=float(T))).summary["spin_rate"] for T in torques]
onset = [RunLoosening(p0.with_overrides(torque=float(T), drag="ramp", force_rate=1e3,
                                        t_end=p0.load_time + 1.01 * loosening_closed_forms(
                                            p0.with_overrides(torque=float(T), drag="ramp"))
                                        ["drag_force_theory"] / 1e3)).summary["onset_force"]
         for T in torques]
for T, w, q in zip(torques, spin, onset):
    print(f"torque {T:.2f} N m: spin {w:.5f} rad/s, slides as a whole at {q:.1f} N")

s = np.linspace(0.0, 6.0, 300)
G = np.array([ring_torque_factor(x) for x in s])
D = np.array([ring_drag_factor(x) for x in s])
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4.2))
a.plot(s * p0.slip_speed / p0.bearing_radius, muNr * G, "k-", lw=0.9, label="ring integral mu N r G(omega r / v)")
a.plot(spin, torques, "o", color="C0", label="runs (Exudyn)")
a.plot(s * p0.slip_speed / p0.bearing_radius, muNr * s / 2, ":", color="0.5", label="mu N r (omega r) / (2 v)")
a.set(xlabel="spin rate omega [rad/s]", ylabel="torque [N m]", ylim=(0, 1.05 * muNr),
      title=f"dragged sideways at {p0.slip_speed:g} m/s")
a.legend(fontsize=7)
b.plot(p0.mu_bearing * p0.preload * D, muNr * G, "k-", lw=0.9, label="friction limit (mu N D(s), mu N r G(s))")
b.plot(onset, torques, "s", color="C3", label="slides as a whole (Exudyn)")
b.set(xlabel="transverse force [N]", ylabel="torque [N m]", title="pushed by a rising force")
b.legend(fontsize=7)
fig.tight_layout()
plt.show()
