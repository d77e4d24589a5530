"""
The papers' block: steered by polar orthotropy
==============================================

The first paper's example: a block pressed onto a plane whose adhesion is polar-orthotropic about
the origin, pushed along +y from (0.5, 0) m by a spring to a driver moving at 0.1 m/s. The ratio of
the radial to the circumferential sticking stiffness steers it: with a stiff radial direction the
block keeps its distance from the origin and turns onto a circle; with the directions swapped it
is pushed outward. Friction is isotropic (mu = 0.3), so only B is anisotropic; the return map is
``radial``, the block scene's choice (adhesion-steered sliding).

The scene's own model script (``exu_aniso.models.block.RunBlock``) with its parameters
(``exu_aniso.scenes.block.BlockParams``), as ``exu-aniso run block --set eps_1=... --set
eps_2=...`` runs it.
"""
import os

import matplotlib.pyplot as plt
import numpy as np

from exu_aniso.models.block import RunBlock
from exu_aniso.scenes.block import BlockParams

QUICK = os.environ.get("EXU_ANISO_QUICK") == "1"      # the test suite's short form
t_end = 0.3 if QUICK else 4.5

fig, ax = plt.subplots(figsize=(6, 6))
phi = np.linspace(0.0, 0.5 * np.pi, 100)
ax.plot(0.5 * np.cos(phi), 0.5 * np.sin(phi), "k:", lw=0.8, label="circle r = 0.5 m")
for eps_r, eps_phi in ((1e5, 1e3), (1e4, 1e4), (1e3, 1e5)):
    p = BlockParams(eps_1=eps_r, eps_2=eps_phi, t_end=t_end)
    res = RunBlock(p)
    tr, s = res.trajectory, res.summary
    ax.plot(tr["x"], tr["y"], label=f"eps_r / eps_phi = {eps_r / eps_phi:g}: heading {s['heading_deg']:.0f} deg, "
                                    f"ledger residual {s['energy']['residual']:.1e}")
ax.plot(0.5, 0.0, "o", color="k")
ax.set_aspect("equal")
ax.set_xlabel("x [m]")
ax.set_ylabel("y [m]")
ax.set_title(f"block centre over {t_end:g} s, pushed along +y")
ax.legend(fontsize=7, loc="upper right")
fig.tight_layout()
plt.show()
