"""
A nut on a bolt: self-locking, and how fast it runs down
========================================================

A free M10 nut set down on a vertical bolt either holds under its own weight or runs down the thread.
The thread holds it when its friction reaches tan(phi) cos(beta_n), the lead angle's tangent times the
cosine of the flank's half angle in the helix's normal section: 0.0458 for M10, well below the
tan(phi) = 0.0529 of a box on an incline of the lead angle. Below it the nut runs down at a constant
acceleration that its mass, its moment of inertia, the lead, the flank angle and the friction fix.

Every point of the plot is one run of the nut scene (``exu_aniso.models.nut.RunNut``, the reduced
model: the nut on a screw joint against the bolt's helicoid flank), its descent acceleration fitted
over the run's second half; the line is the closed form (``exu_aniso.scenes.threads.nut_descent``).
"""
import math
import os

import matplotlib.pyplot as plt
import numpy as np

from exu_aniso.models.nut import RunNut
from exu_aniso.scenes.nut import NutParams
from exu_aniso.scenes.threads import nut_descent, self_locking_friction

QUICK = os.environ.get("EXU_ANISO_QUICK") == "1"      # the test suite's short form
p0 = NutParams()
beta = math.radians(p0.flank_angle)
mu_c = self_locking_friction(p0.d2, p0.pitch, beta)
mus = np.linspace(0.05, 1.25, 4 if QUICK else 13) * mu_c      # none on the threshold itself

measured, held = [], []
for mu in mus:
    s = RunNut(p0.with_overrides(mu_thread=float(mu))).summary
    held.append(s["held"])
    measured.append(np.nan if s["descent_acceleration"] is None else s["descent_acceleration"])
    print(f"mu {mu:.4f}: {'holds' if s['held'] else 'runs down'}, "
          f"descent acceleration {measured[-1]:.6g} m/s^2")

line = np.linspace(0.02, 0.9999, 200) * mu_c
theory = [nut_descent(p0.d2, p0.pitch, beta, m, p0.nut_mass, p0.nut_inertia, p0.gravity)[0] for m in line]
fig, ax = plt.subplots(figsize=(6.5, 4.2))
ax.plot(line, -1e3 * np.array(theory), "k-", lw=0.9, label="closed form (nut_descent)")
down = ~np.array(held)
ax.plot(mus[down], -1e3 * np.array(measured)[down], "o", color="C0", label="runs down (Exudyn)")
ax.plot(mus[~down], np.zeros((~down).sum()), "s", color="C3", label="holds (Exudyn)")
ax.axvline(mu_c, color="0.5", ls="--", lw=0.8, label=f"tan(phi) cos(beta_n) = {mu_c:.4f}")
ax.axvline(math.tan(math.atan(p0.pitch / (math.pi * p0.d2))), color="0.5", ls=":", lw=0.8,
           label="tan(phi): a box on an incline")
ax.set(xlabel="thread friction mu along the helix [-]", ylabel="descent acceleration [mm/s^2]",
       title="A free M10 nut on a vertical bolt")
ax.legend(fontsize=7)
fig.tight_layout()
plt.show()
