"""Energy balance of a contact simulation from its trajectory and contact history (no Exudyn).

    work in (drive and other external loads) = kinetic + dissipated (friction) + stored (elastic)

* work of a force sampled at the step ends: ``work_trapezoid`` = sum over steps of
  (f_n + f_{n+1})/2 . (x_{n+1} - x_n). With the trapezoidal rule (Newmark beta 1/4, gamma 1/2)
  this is exactly the discrete work that changes the kinetic energy, so the balance checks the
  contact law and the bookkeeping, not the quadrature;
* dissipated: the history column ``dissipated_energy`` (sum over points of D = -T . dxi_sl);
* stored tangential: T . C^-1 T / 2 per point in contact (``law.elastic_energy``), with C = -B at
  the stored contact point (history anchor);
* stored normal: N^2 / (2 eps_N) per point in contact (penalty N = eps_N xi3; normal damping off).

What the residual measures: with constant B in stick the discrete balance is exact (the trapezoidal
work of T over du equals the change of T.C^-1 T / 2). In slip the backward-Euler dissipation T_{n+1}
. dxi_sl differs from the trapezoidal work by (T_{n+1} - T_n) . dxi_sl / 2 per step: first order in
the step at stick/slip transitions, zero in steady sliding. A position-dependent B (polar
orthotropy, rate form) has no stored-energy potential at all (hypo-elastic), and the seed map's
dissipation is not the discrete work of its traction jump; both show up in the residual.
"""
from __future__ import annotations

import numpy as np

from .contact import HISTORY_FIELDS, N_HISTORY
from .law import elastic_energy

_T = [HISTORY_FIELDS.index("traction_1"), HISTORY_FIELDS.index("traction_2")]
_A = [HISTORY_FIELDS.index("anchor_1"), HISTORY_FIELDS.index("anchor_2")]
_ACTIVE = HISTORY_FIELDS.index("active")
_NORMAL = HISTORY_FIELDS.index("normal")
_DISS = HISTORY_FIELDS.index("dissipated_energy")


def work_trapezoid(force, displacement):
    """Cumulative work [J] (length n) of a force (n,) or (n, d) along a displacement of the same shape."""
    f = np.asarray(force, dtype=float)
    x = np.asarray(displacement, dtype=float)
    if f.shape != x.shape:
        raise ValueError(f"force and displacement must have the same shape; got {f.shape} and {x.shape}")
    if f.ndim == 1:
        f, x = f[:, None], x[:, None]
    dw = np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x, axis=0), axis=1)
    return np.concatenate([[0.0], np.cumsum(dw)])


def _history(H):
    H = np.asarray(H, dtype=float)
    return H.reshape(H.shape[0], -1, N_HISTORY)


def stored_tangential(H, law):
    """Tangential elastic energy [J] per history row (n, K*9) or (n, K, 9): sum of T.C^-1 T / 2 over
    the points in contact, C = -B at the stored contact point."""
    H = _history(H)
    n, K, _ = H.shape
    rows = H.reshape(n * K, N_HISTORY)
    active = rows[:, _ACTIVE] > 0.5
    E = np.zeros(n * K)
    if np.any(active):
        B, _ = law.adhesion.physical(rows[active][:, _A], derivatives=False)
        T = rows[active][:, _T]
        E[active] = [elastic_energy(t, b) for t, b in zip(T, B)]
    return E.reshape(n, K).sum(axis=1)


def stored_normal(H, law):
    """Normal penalty energy [J] per history row: sum of N^2 / (2 eps_N) over the points in contact
    (exact for normal damping 0)."""
    if law.d_N:
        raise ValueError(f"stored_normal needs normal damping 0 (N = eps_N xi3); got normal_damping={law.d_N}")
    H = _history(H)
    N = np.where(H[:, :, _ACTIVE] > 0.5, H[:, :, _NORMAL], 0.0)
    return np.sum(N * N, axis=1) / (2.0 * law.eps_N)


def dissipated(H):
    """Accumulated friction dissipation [J] per history row (sum over points)."""
    return _history(H)[:, :, _DISS].sum(axis=1)


def balance(work_in, kinetic, dissipation, stored):
    """Energy balance at the last sample: dict of the four terms (changes from the first sample) and
    the residual relative to max(|work in|, kinetic + dissipated + stored changes)."""
    w = float(work_in[-1] - work_in[0])
    k = float(kinetic[-1] - kinetic[0])
    d = float(dissipation[-1] - dissipation[0])
    s = float(stored[-1] - stored[0])
    residual = w - (k + d + s)
    scale = max(abs(w), abs(k) + abs(d) + abs(s), 1e-300)
    return dict(work_in=w, kinetic=k, dissipated=d, stored=s, residual=residual, relative_residual=residual / scale)
