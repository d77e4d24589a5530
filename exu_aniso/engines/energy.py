"""Energy ledger of a contact simulation, computed from the solver's own states (no Exudyn).

    work in (drives, loads) = kinetic + potential + stored + dissipated        (changes from t = 0)

Every engine records, per accepted step, the rigid motion of the slave body (``RigidMotion``: COM
position, rotation matrix, velocity, angular velocity, all in the master frame) and the converged
contact history H (n, K, 9). From these and the contact law this module computes each term with
the integrator's own quadrature, so the books close to round-off for a conservative case and the
residual measures the contact law and its bookkeeping, not the quadrature:

* work in: ``work_trapezoid`` = sum over steps of (f_n + f_{n+1})/2 . (x_{n+1} - x_n). With the
  trapezoidal rule (Newmark beta 1/4, gamma 1/2) this is exactly the discrete work that changes
  the kinetic energy of a body with constant mass matrix;
* kinetic: m |v|^2 / 2 + omega . (A J A^T) omega / 2 (``rigid_kinetic``);
* potential: given by the scene (the block's ``normal_load`` stands in for its weight);
* stored (``contact_energy``): normal penalty eps_N min(gap, 0)^2 / 2 at the current points plus
  adhesion T . C^-1 T / 2 at the stored contact point (C = -B);
* dissipated (``contact_energy``): the history column ``dissipated_energy`` (the kernel's
  trapezoid D = -(T_n + T)/2 . dxi_sl of friction, plus the adhesion energy released when a point
  loses contact) and the trapezoid of the normal and tangential dashpot forces over the points'
  displacements.

What the residual may contain besides round-off (the tolerance ``ENERGY_TOLERANCE`` is set above
these for the scenes' defaults; docs/guide/energy_ledger.md quotes the measured values):

* a position-dependent B (polar orthotropy) has no stored-energy potential (hypo-elastic rate
  form): T . C^-1 T / 2 at the anchor differs from the work done on the adhesion spring at second
  order in the anchor's motion;
* rotations: the trapezoidal rule is not exactly energy-consistent for rigid rotation (Euler
  parameters, rotation vectors), and on a curved surface the normal turns within a step;
* generalized-alpha dissipates high frequencies numerically (rho_inf < 1): that energy is real
  numerical loss and shows up as a positive residual that falls with dt and vanishes at rho_inf 1.
  The reduced screw under a constant torque (stick vibration) loses a large share of the drive
  work this way at rho_inf 0.8 (docs/guide/energy_ledger.md), and the warning is meant for exactly
  that case: the run's motion differs from the undamped one.
"""
from __future__ import annotations

import math
import warnings
from typing import NamedTuple

import numpy as np

from exu_aniso.law.history import HISTORY_FIELDS, N_HISTORY

ENERGY_TOLERANCE = 1e-2
"""Relative residual above which a run's ledger does not close (``energy_ok`` false, warning)."""

LEDGER_KEYS = ("work_in", "kinetic", "potential", "stored", "dissipated", "residual")

_ACTIVE = HISTORY_FIELDS.index("active")
_NORMAL = HISTORY_FIELDS.index("normal")
_DISS = HISTORY_FIELDS.index("dissipated_energy")


class EnergyWarning(UserWarning):
    """The energy ledger of a run does not close within ENERGY_TOLERANCE."""


class RigidMotion(NamedTuple):
    """Motion of a rigid body per sample, in the master frame: position (n, 3) of the reference
    point (COM), rotation (n, 3, 3) body -> master, velocity (n, 3), omega (n, 3) angular velocity."""
    position: np.ndarray
    rotation: np.ndarray
    velocity: np.ndarray
    omega: np.ndarray


def _rotations_z(angle):
    c, s = np.cos(angle), np.sin(angle)
    A = np.zeros((len(c), 3, 3))
    A[:, 0, 0], A[:, 0, 1], A[:, 1, 0], A[:, 1, 1], A[:, 2, 2] = c, -s, s, c, 1.0
    return A


def motion_about_z(x, y, z, angle, vx, vy, vz, omega):
    """RigidMotion of a body that turns about the z axis only (planar block, reduced screw)."""
    cols = [np.broadcast_to(np.asarray(a, dtype=float), np.shape(angle)) for a in (x, y, z, vx, vy, vz, omega)]
    zero = np.zeros(np.shape(angle))
    return RigidMotion(np.column_stack(cols[0:3]), _rotations_z(np.asarray(angle, dtype=float)),
                       np.column_stack(cols[3:6]), np.column_stack([zero, zero, cols[6]]))


def point_motion(motion, b):
    """Positions and velocities (n, K, 3) of the body-local points b (K, 3)."""
    arm = np.matmul(motion.rotation, np.asarray(b, dtype=float).T).transpose(0, 2, 1)    # A b per sample
    X = motion.position[:, None, :] + arm
    w = motion.omega[:, None, :]
    V = np.empty_like(arm)                   # v + omega x arm, written out: np.cross is slower here
    V[..., 0] = w[..., 1] * arm[..., 2] - w[..., 2] * arm[..., 1]
    V[..., 1] = w[..., 2] * arm[..., 0] - w[..., 0] * arm[..., 2]
    V[..., 2] = w[..., 0] * arm[..., 1] - w[..., 1] * arm[..., 0]
    V += motion.velocity[:, None, :]
    return X, V


def rigid_kinetic(motion, mass, inertia):
    """Kinetic energy [J] per sample: m |v|^2 / 2 + omega . (A J A^T) omega / 2, J (3, 3) body frame."""
    w_body = np.einsum("nji,nj->ni", motion.rotation, motion.omega)
    return 0.5 * mass * np.sum(motion.velocity ** 2, axis=1) + 0.5 * np.einsum(
        "ni,ij,nj->n", w_body, np.asarray(inertia, dtype=float), w_body)


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
    """Adhesion energy [J] per history row (n, K*9) or (n, K, 9): sum of T . C^-1 T / 2 over the
    points in contact, C = -B at the stored contact point."""
    H = _history(H)
    n, K, _ = H.shape
    return law.released_energy(H.reshape(n * K, N_HISTORY)).reshape(n, K).sum(axis=1)


def stored_normal(H, law):
    """Normal penalty energy [J] per history row from the stored N: sum of N^2 / (2 eps_N) over the
    points in contact (exact without normal damping; ``contact_energy`` uses the gap instead)."""
    if law.d_N:
        raise ValueError(f"stored_normal needs normal_damping 0 (N = eps_N xi3); got normal_damping={law.d_N}")
    H = _history(H)
    N = np.where(H[:, :, _ACTIVE] > 0.5, H[:, :, _NORMAL], 0.0)
    return np.sum(N * N, axis=1) / (2.0 * law.eps_N)


def dissipated(H):
    """Friction dissipation and released adhesion energy [J] per history row (sum over points)."""
    return _history(H)[:, :, _DISS].sum(axis=1)


def _contact_terms(law, X, V, H):
    """The stored energy [J] per sample and the dashpots' dissipation [J] per interval (n - 1) of
    the contact of ``law``: the two parts of ``contact_energy`` before the history's dissipation
    and the cumulative sum (H as _history gives it)."""
    n, K, _ = X.shape
    x = X.reshape(n * K, 3)
    gap, normal = law.gap_and_normal(x)
    inside = gap < 0.0
    stored = 0.5 * law.eps_N * np.where(inside, gap, 0.0) ** 2
    steps = np.zeros(max(n - 1, 0))
    if law.d_N > 0.0 or law.d_T > 0.0:
        fd = np.zeros((n * K, 3))
        if np.any(inside):
            nrm = normal[inside]
            N = H.reshape(n * K, N_HISTORY)[inside, _NORMAL]
            Nd = N - law.eps_N * gap[inside]                  # dashpot part of N (force on slave: -N n)
            v = V.reshape(n * K, 3)[inside]
            vt = v - nrm * np.einsum("ki,ki->k", nrm, v)[:, None]
            fd[inside] = -Nd[:, None] * nrm - np.where(N < 0.0, law.d_T, 0.0)[:, None] * vt
        fd = fd.reshape(n, K, 3)
        steps = -np.sum(0.5 * (fd[1:] + fd[:-1]) * np.diff(X, axis=0), axis=(1, 2))
    return stored.reshape(n, K).sum(axis=1) + stored_tangential(H, law), steps


def contact_energy(law, X, V, H):
    """Stored and dissipated energy [J] per sample of the contact of ``law`` (a fixed master: X, V
    (n, K, 3) slave points in the master frame, H (n, K, 9) converged history at each sample).

    stored = sum eps_N min(gap, 0)^2 / 2 + T . C^-1 T / 2; dissipated = history dissipation +
    cumulative trapezoid of -(f_d,n + f_d,n+1)/2 . (X_n+1 - X_n) over the dashpot forces f_d =
    (total normal force - elastic normal force) - d_T v_t (loaded points), so that clipping
    N <= 0 counts as part of the dashpot."""
    H = _history(H)
    stored, steps = _contact_terms(law, np.asarray(X, dtype=float), np.asarray(V, dtype=float), H)
    return stored, dissipated(H) + np.concatenate([[0.0], np.cumsum(steps)])


def rigid_contact_energy(law, motion, b, H, chunk=128):
    """``contact_energy`` of the body-local points b (K, 3) carried by a rigid motion (RigidMotion,
    in the master frame), a block of ``chunk`` samples at a time: the points' positions and
    velocities exist for one block only, so the temporaries stay in the cache and are reused instead
    of taking fresh memory of (n, K, 3) each (the 8 x 8 block over 5.5 s: 8 MB apiece, whose page
    faults cost more than the arithmetic). The same result as contact_energy(law,
    *point_motion(motion, b), H) (the blocks' dashpot intervals joined, one cumulative sum)."""
    H = _history(H)
    n = len(motion.position)
    if chunk < 1:
        raise ValueError(f"chunk must be a positive number of samples; got {chunk}")
    stored, steps = np.empty(n), np.zeros(max(n - 1, 0))   # steps[i]: dashpot dissipation from sample i to i+1
    for a in range(0, n, chunk):
        e = min(a + chunk + 1, n)                  # one sample past the block: its last interval
        X, V = point_motion(RigidMotion(*(x[a:e] for x in motion)), b)
        stored[a:e], steps[a:e - 1] = _contact_terms(law, X, V, H[a:e])
    return stored, dissipated(H) + np.concatenate([[0.0], np.cumsum(steps)])


ROUND_OFF_FLOOR = 1e-9


def first_nonfinite(columns, t=None):
    """Where the first non-finite value of ``columns`` (name -> array of samples) appears: None when
    all are finite, else dict(column=name, index=sample, t=time [s] when t is given). The earliest
    sample wins; among columns non-finite at that sample, the first in the mapping's order."""
    first = None
    for name, a in columns.items():
        a = np.asarray(a, dtype=float)
        bad = ~np.isfinite(a.reshape(len(a), -1)).all(axis=1) if a.size else np.zeros(0, bool)
        if bad.any():
            i = int(np.argmax(bad))
            if first is None or i < first["index"]:
                first = dict(column=name, index=i)
    if first is not None and t is not None:
        first["t"] = float(np.asarray(t, dtype=float)[first["index"]])
    return first


def ledger(work_in, kinetic, potential, stored, dissipated, tolerance=ENERGY_TOLERANCE, t=None):
    """The energy ledger of a run from per-sample terms (arrays of length n).

    Returns (columns, summary): columns are the changes from the first sample (work_in, kinetic,
    potential, stored, dissipated, residual = work_in - (kinetic + potential + stored +
    dissipated)) as arrays; summary has the final values of the five terms [J], ``residual`` =
    max over the run of |residual| / scale with scale = max over the run of max(|work in|,
    |kinetic| + |potential| + |stored| + |dissipated|), at least ROUND_OFF_FLOOR of the terms'
    absolute level (0 when nothing happens at all), and
    ``energy_ok`` = residual <= tolerance (finite).

    A non-finite term anywhere (an overflowed kinetic energy, a NaN work) cannot be balanced: the
    summary then has ``energy_ok`` False, ``residual`` NaN (null in JSON) and ``energy_nonfinite``
    = dict(column, index[, t]) of its first appearance (t: the sample times [s], optional)."""
    terms = dict(work_in=work_in, kinetic=kinetic, potential=potential, stored=stored, dissipated=dissipated)
    terms = {k: np.asarray(a, dtype=float) for k, a in terms.items()}
    cols = {k: a - a[0] for k, a in terms.items()}
    res = cols["work_in"] - (cols["kinetic"] + cols["potential"] + cols["stored"] + cols["dissipated"])
    cols["residual"] = res
    bad = first_nonfinite(terms, t)
    summary = {k: float(cols[k][-1]) for k in terms}
    if bad is not None:
        summary["residual"] = float("nan")
        return cols, dict(energy=summary, energy_ok=False, energy_tolerance=tolerance,
                          energy_nonfinite=dict(bad, column="energy_" + bad["column"]))
    scale = float(np.max(np.maximum(np.abs(cols["work_in"]), np.abs(cols["kinetic"]) + np.abs(cols["potential"])
                                    + np.abs(cols["stored"]) + np.abs(cols["dissipated"]))))
    # round-off floor: changes below 1e-9 of the energies' absolute level (e.g. the normal penalty
    # energy a screw at rest holds from t = 0) are no motion; without it a run where nothing happens
    # (changes of 1e-26 J) would report a relative residual of 1
    level = max(float(np.max(np.abs(a))) for a in terms.values())
    scale = max(scale, ROUND_OFF_FLOOR * level)
    rel = float(np.max(np.abs(res)) / scale) if scale > 0.0 else 0.0
    summary["residual"] = rel
    ok = bool(math.isfinite(rel) and rel <= tolerance)
    return cols, dict(energy=summary, energy_ok=ok, energy_tolerance=tolerance)


DEFAULT_ADVICE = "reduce dt"


def warn_if_open(summary, what="run", advice=DEFAULT_ADVICE):
    """Warn (EnergyWarning, stderr by default) when a ledger summary does not close; ``advice``: what
    to try, a phrase the scene chooses (it knows which solver settings suit it)."""
    if summary.get("energy_ok", True):
        return
    bad = summary.get("energy_nonfinite") or summary.get("state_nonfinite")   # a term, else the state
    if bad is not None:
        where = f"at t = {bad['t']:.6g} s" if "t" in bad else f"at sample {bad['index']}"
        warnings.warn(f"energy ledger of this {what} cannot close: {bad['column']} is not finite {where} "
                      "(an overflow or a NaN in the state or the contact), so the results are not to be trusted; "
                      "check the parameters' magnitudes", EnergyWarning, stacklevel=outside_the_package())
        return
    warnings.warn(f"energy ledger of this {what} does not close: relative residual "
                  f"{summary['energy']['residual']:.3g} > tolerance {summary['energy_tolerance']:.3g} "
                  f"(work in {summary['energy']['work_in']:.6g} J): energy is created or lost that the "
                  f"model does not account for, so the results may be wrong; {advice} (the ledger: "
                  "docs/guide/energy_ledger.md)", EnergyWarning, stacklevel=outside_the_package())


def outside_the_package():
    """warnings.warn's stacklevel of the first caller outside exu_aniso, so that a warning names the
    user's line (a model script's RunBlock call), not one of the package's own lines."""
    import os
    import sys
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    frame, level = sys._getframe(1), 1                  # the caller of this function is level 1
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(package + os.sep):
        frame, level = frame.f_back, level + 1
    return level


def balance(work_in, kinetic, dissipation, stored):
    """Energy balance at the last sample (changes from the first sample) with the residual relative
    to max(|work in|, kinetic + dissipated + stored changes). Kept for the moving-master hard case,
    whose two bodies have no scene ledger."""
    w = float(work_in[-1] - work_in[0])
    k = float(kinetic[-1] - kinetic[0])
    d = float(dissipation[-1] - dissipation[0])
    s = float(stored[-1] - stored[0])
    residual = w - (k + d + s)
    scale = max(abs(w), abs(k) + abs(d) + abs(s), 1e-300)
    return dict(work_in=w, kinetic=k, dissipated=d, stored=s, residual=residual, relative_residual=residual / scale)
