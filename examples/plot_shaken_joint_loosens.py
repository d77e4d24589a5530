"""
A preloaded nut shaken across the bolt turns loose
==================================================

A bolted joint whose nut is shaken across the bolt's axis loses its preload: while the thread's and the
bearing's contact rings slide sideways, their friction resists the nut's turning only in proportion to
its spin rate, so the pitch's torque F P / (2 pi) turns the nut back by a fixed angle per metre of slip
path, and every radian backs the nut off by P / (2 pi), which costs the preload the joint's stiffness
times that.

Left: the preload against the cycles of the shaking (0.2 mm at 12.5 Hz; an M10 nut, 10 kN, mu 0.12) for
the loosening scene's full joint (``exu_aniso.models.loosening.RunLoosening``, case ``joint``, model
``full``: a 6-DOF nut on the bolt's helicoid, the plate on the joint's spring) on a 60 degree and a
square thread, each run until the joint is loose; dashed, the same joint if its two rings stayed
uniform and slid as the closed form assumes (model ``rings``: its rotation per cycle times the preload
lost per radian). The full nut wedges its flank as it shifts, opens part of its thread ring, and loosens
more slowly. Right: the transverse force against the nut's shift on the 60 degree thread, the
hysteresis loop, beside the uniform rings' sliding force.
"""
import os

import matplotlib.pyplot as plt
import numpy as np

from exu_aniso.models.loosening import RunLoosening
from exu_aniso.scenes.loosening import LooseningParams

QUICK = os.environ.get("EXU_ANISO_QUICK") == "1"      # the test suite's short form
cycles = 6 if QUICK else 80
full = dict(case="joint", model="full", t_end=0.005 + cycles / 12.5)

fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4.2))
for flank, color in ((60.0, "C0"), (0.0, "C3")):
    r = RunLoosening(LooseningParams(flank_angle=flank, **full))
    s, traj = r.summary, r.trajectory
    p = r.params
    n = (np.asarray(traj["t"]) - p.load_time) * p.shake_frequency
    rings = RunLoosening(LooseningParams(case="joint", flank_angle=flank, t_end=0.005 + 4 / 12.5)).summary
    drop = rings["rotation_per_cycle"] * s["preload_loss_per_radian_theory"]       # N per cycle, uniform rings
    print(f"flank {flank:g} deg: {s['rotation_per_cycle']:.4f} rad per cycle (uniform rings "
          f"{rings['rotation_per_cycle']:.4f}), loose after {s['cycles_to_loose']} cycles")
    shaking = n >= 0.0
    a.plot(n[shaking], 1e-3 * np.asarray(traj["preload"])[shaking], color=color, lw=0.8,
           label=f"{flank:g} deg thread, full nut")
    a.plot(n[shaking], 1e-3 * np.maximum(s["preload_start"] - drop * n[shaking], 0.0), "--", color=color, lw=0.8,
           label=f"{flank:g} deg, uniform rings")
    if flank == 60.0:
        b.plot(1e3 * np.asarray(traj["x"])[shaking], 1e-3 * np.asarray(traj["drag_force"])[shaking], color=color,
               lw=0.6, label="full nut")
        plateau = rings["slide_force_per_preload_theory"] * p.preload
        for sign in (1.0, -1.0):
            b.axhline(1e-3 * sign * plateau, color="k", ls="--", lw=0.8,
                      label="uniform rings sliding (at 10 kN)" if sign > 0 else None)
a.set(xlabel="cycles", ylabel="preload [kN]", ylim=(0.0, None), title="preload against the cycles")
a.legend(fontsize=7)
b.set(xlabel="nut's shift x [mm]", ylabel="transverse force [kN]", title="hysteresis loop, 60 degree thread")
b.legend(fontsize=7)
fig.tight_layout()
plt.show()
