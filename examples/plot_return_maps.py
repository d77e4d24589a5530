"""
The three return maps on one anisotropic point
==============================================

A point slides when its trial traction ``T_tr`` leaves the friction ellipse ``T.F T <= |N|^2``.
The three maps bring it back to the ellipse in different places: ``exact`` along the closest
point in the metric of the compliance ``C^-1 = -B^-1`` (associated flow), ``radial`` along the
ray through the origin scaled by ``F`` (sliding steered by the adhesion), ``seed`` the papers'
closed form ``T = -T_hat |N| / sqrt(T_hat.F T_hat)`` with ``T_hat = B F T_tr``. With an isotropic
B, exact and radial coincide; here B is orthotropic at 30 degrees to an orthotropic F.

The law alone, no Exudyn: ``exu_aniso.return_map_point`` in a loop over trial tractions on a
circle outside the ellipse.
"""
import math

import matplotlib.pyplot as plt
import numpy as np

from exu_aniso import return_map_point


def tensor(a, b, angle):
    """Components (t11, t12, t22) of a e1 e1 + b e2 e2, e1 at ``angle`` [rad] to the x axis."""
    c, s = math.cos(angle), math.sin(angle)
    return (a * c * c + b * s * s, (a - b) * c * s, a * s * s + b * c * c)


N_abs = 1.0                                            # |N| [N]
F = tensor(1 / 0.3 ** 2, 1 / 0.6 ** 2, 0.0)            # mu 0.3 along x, 0.6 along y
B = tensor(-1e4, -1e2, math.radians(30.0))             # stiff at 30 deg, soft across [N/m]

phi = np.linspace(0.0, 2.0 * math.pi, 25, endpoint=False)
trial = 0.9 * np.column_stack([np.cos(phi), np.sin(phi)])   # [N], all outside the ellipse

fig, axes = plt.subplots(1, 3, figsize=(11, 3.9), sharex=True, sharey=True)
e = np.linspace(0.0, 2.0 * math.pi, 200)
for ax, method in zip(axes, ("exact", "radial", "seed")):
    ax.plot(0.3 * np.cos(e), 0.6 * np.sin(e), "k", lw=1.2, label="friction limit")
    for T_tr in trial:
        T = return_map_point(T_tr, N_abs, B, F, method=method, tangent=False).T
        ax.annotate("", xy=T, xytext=T_tr, arrowprops=dict(arrowstyle="->", color="C0", lw=0.8))
        ax.plot(*T, "o", color="C3", ms=3)
    ax.set_title(method)
    ax.set_xlim(-1.0, 1.0)
    ax.set_ylim(-1.0, 1.0)
    ax.set_aspect("equal")
    ax.set_xlabel("T_1 [N]")
axes[0].set_ylabel("T_2 [N]")
axes[0].legend(loc="lower left", fontsize=8)
fig.suptitle("trial traction (arrow tail) -> returned traction (dot), |N| = 1 N")
fig.tight_layout()
plt.show()
