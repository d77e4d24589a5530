"""Screw driving: advance per revolution and driving torque of a screw in a spiral-orthotropic hole.

Sweeps r = eps_1/eps_2 (adhesion along / across the helix) and the helix angle for the three return
maps under the rotation drive (torsional spring to a driver at rotation_speed), compares with the
closed-form steady sliding state (exu_aniso.scenes.screw.steady_sliding), records time histories
under the rotation and torque drives, finds the sticking threshold of the torque drive, and
cross-checks a few cases with the full 6-DOF model and the reference engine.

Usage: python studies/screw_driving.py [--quick] [--serial] [--out DIR]
"""
from __future__ import annotations

import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)
from _lib.studylib import Timer, finish, markdown_table, parse_args, read_table, sweep, table  # noqa: E402

from exu_aniso.calibration import steady_sliding  # noqa: E402
from exu_aniso.engines.failure import SimulationFailure  # noqa: E402
from exu_aniso.scenes.screw import ScrewParams, pitch  # noqa: E402
from exu_aniso.scenes.base import summary_float

MAPS = ("radial", "exact", "seed")
EPS_1 = 1e4          # N/m, along the helix, fixed; eps_2 = eps_1 / r


def base_params(quick):
    """Scene of every run: defaults, generalized-alpha (damps the unresolved torsional oscillation of the
    drive spring, ~2.8e3 rad/s), fewer points and a shorter run in quick mode."""
    kw = dict(solver="generalized_alpha", eps_1=EPS_1, t_end=0.5)
    if quick:
        kw.update(rings=2, points_per_ring=4, t_end=0.3)
    return ScrewParams(**kw)


def _run(p, engine):
    if engine == "reference":
        from exu_aniso.scenes.screw import simulate_screw
        return simulate_screw(p)
    from exu_aniso.models.screw import RunScrew
    return RunScrew(p, contactOutputs=False)


def run_case(case):
    """One simulation; case: dict(kind, params (dict of ScrewParams overrides), engine, ...)."""
    p = ScrewParams(**case["params"])
    failed = ""
    try:
        res = _run(p, case.get("engine", "exudyn"))
    except SimulationFailure as failure:     # a cross-check that fails is reported, not hidden
        if case["kind"] != "check" or failure.partial is None:
            raise
        res, failed = failure.partial, str(failure).splitlines()[0]
    s, tr = res.summary, res.trajectory
    out = dict(summary=dict(s), pitch=pitch(p), failed=failed)
    try:
        cf = steady_sliding(p)
        out.update(cf_ratio=cf.advance_ratio, cf_torque=cf.torque)
    except ValueError:                       # seed map: no closed form
        out.update(cf_ratio=float("nan"), cf_torque=float("nan"))
    if p.drive == "rotation":
        cf_p = p.with_overrides(return_map="radial") if p.return_map == "seed" else p
        out["cf_torque_any"] = steady_sliding(cf_p).torque
    if case["kind"] == "history":
        idx = np.unique(np.linspace(0, len(tr["t"]) - 1, 250).astype(int))
        out["traj"] = {k: np.asarray(tr[k])[idx].tolist() for k in ("t", "angle", "z", "torque", "omega")}
    if case["kind"] == "torque":
        t, ang = np.asarray(tr["t"]), np.asarray(tr["angle"])
        late = t >= 0.6 * t[-1]
        out["late_rotation"] = float(ang[-1] - ang[late][0])
        out["max_angle"] = float(ang.max())
        out["dissipated"] = float(s["dissipated_energy"])
    return out


def build_cases(quick):
    b = base_params(quick).as_dict()
    cases = []
    # time histories: rotation drive (r and map), torque drive (below / above the sliding torque)
    hist = [("radial", 1e-3), ("radial", 0.1), ("radial", 1.0), ("exact", 0.01), ("seed", 0.1)]
    if quick:
        hist = [("radial", 1e-2), ("exact", 1e-2)]
    for rm, r in hist:
        cases.append(dict(kind="history", label=f"rotation {rm} r={r:g}",
                          params=dict(b, return_map=rm, eps_2=EPS_1 / r)))
    bt = dict(b, drive="torque", dt=1e-4, t_end=0.06 if not quick else 0.03, eps_2=EPS_1 / 0.01)
    ts = steady_sliding(ScrewParams(**bt)).torque
    for f in ((0.9, 1.1) if not quick else (1.1,)):
        cases.append(dict(kind="history", label=f"torque {f:g} T_slide radial r=0.01",
                          params=dict(bt, torque=f * ts)))
    # advance per revolution and torque vs r
    rs = np.logspace(-3, 0, 10) if not quick else np.array([1e-3, 1e-1, 1.0])
    for rm in (MAPS if not quick else ("radial", "exact")):
        for r in rs:
            cases.append(dict(kind="r", map=rm, r=float(r), params=dict(b, return_map=rm, eps_2=EPS_1 / float(r))))
    # vs helix angle
    angles = (2.0, 5.0, 10.0, 15.0, 20.0, 30.0) if not quick else (5.0, 30.0)
    for rm in (MAPS if not quick else ("radial",)):
        for r in ((0.01, 0.1) if not quick else (0.1,)):
            for a in angles:
                cases.append(dict(kind="helix", map=rm, r=r, helix=a,
                                  params=dict(b, return_map=rm, eps_2=EPS_1 / r, helix_angle=a)))
    # torque drive: sticking threshold (sustained sliding) and transient slip under a torque step
    factors = (0.3, 0.45, 0.55, 0.7, 0.9, 0.95, 1.02, 1.05, 1.1) if not quick else (0.9, 1.1)
    bt2 = dict(bt, rings=b["rings"], points_per_ring=b["points_per_ring"], t_end=0.06 if not quick else 0.03)
    for rm in (("radial", "exact") if not quick else ("radial",)):
        ts_m = steady_sliding(ScrewParams(**dict(bt2, return_map=rm))).torque
        for f in factors:
            cases.append(dict(kind="torque", map=rm, factor=f, params=dict(bt2, return_map=rm, torque=f * ts_m)))
    # cross-check: engines and models
    checks = [("radial", 0.01), ("exact", 0.1), ("seed", 0.1)] if not quick else [("radial", 0.01)]
    for rm, r in checks:
        for engine in ("exudyn", "reference"):
            for model in (("reduced", "full") if not quick else ("reduced",)):
                cases.append(dict(kind="check", map=rm, r=r, engine=engine, model=model,
                                  params=dict(b, return_map=rm, eps_2=EPS_1 / r, model=model)))
    return cases


def main(argv=None):
    args = parse_args("screw_driving", __doc__.splitlines()[0], argv)
    timer = Timer()
    cases = build_cases(args.quick)
    results = sweep(run_case, cases, args)
    out = args.out
    R = list(zip(cases, results))

    # ---- CSV files
    rows = []
    for c, o in R:
        if c["kind"] == "history":
            tr = o["traj"]
            for i in range(len(tr["t"])):
                rows.append([c["label"], tr["t"][i], tr["angle"][i], tr["z"][i], tr["z"][i] / o["pitch"],
                             tr["torque"][i], tr["omega"][i]])
    table(os.path.join(out, "histories.csv"), ["case [-]", "t [s]", "angle [rad]", "z [m]", "z/pitch [-]",
                                               "drive_torque [N m]", "omega [rad/s]"], rows)

    def sweep_rows(kind, keys):
        rows = []
        for c, o in R:
            if c["kind"] == kind:
                s = o["summary"]
                rows.append([c[k] for k in keys] + [summary_float(s, "advance_per_rev") / o["pitch"], o["cf_ratio"],
                                                    s["torque_mean"], o["cf_torque"], o["cf_torque_any"],
                                                    s["wall_s"]])
        return rows
    tail = ["advance/pitch [-]", "advance/pitch_closed_form [-]", "torque_mean [N m]", "torque_closed_form [N m]",
            "torque_sliding_limit [N m]", "wall [s]"]
    table(os.path.join(out, "r_sweep.csv"), ["map [-]", "r [-]"] + tail, sweep_rows("r", ["map", "r"]))
    table(os.path.join(out, "helix_sweep.csv"), ["map [-]", "r [-]", "helix_angle [deg]"] + tail,
          sweep_rows("helix", ["map", "r", "helix"]))
    rows = []
    for c, o in R:
        if c["kind"] == "torque":
            rows.append([c["map"], c["factor"], c["params"]["torque"], o["cf_torque"], o["max_angle"],
                         o["late_rotation"], o["dissipated"], int(o["late_rotation"] > 0.5),
                         int(o["dissipated"] > 0.0)])
    table(os.path.join(out, "torque_drive.csv"),
          ["map [-]", "torque/T_slide [-]", "torque [N m]", "T_slide_closed_form [N m]", "max_angle [rad]",
           "late_rotation [rad]", "dissipated_energy [J]", "sliding_at_end [-]", "slipped_at_all [-]"], rows)
    rows = []
    for c, o in R:
        if c["kind"] == "check":
            s = o["summary"]
            rows.append([c["map"], c["r"], c["engine"], c["model"], summary_float(s, "advance_per_rev") / o["pitch"],
                         s["torque_mean"], summary_float(s, "wall_s"), o["failed"]])
    table(os.path.join(out, "crosscheck.csv"), ["map [-]", "r [-]", "engine [-]", "model [-]", "advance/pitch [-]",
                                                "torque_mean [N m]", "wall [s]", "failed [-]"], rows)

    figs = plot(out)
    report = make_report(out, figs, args.quick)
    finish(args, timer, report, "Screw driving: advance per revolution and torque")
    return 0


def _by(col, key):
    """Indices of rows grouped by the values of column key (in order of appearance)."""
    groups = {}
    for i, v in enumerate(col[key]):
        groups.setdefault(v, []).append(i)
    return groups


YLIM = (-0.15, 1.85)   # advance/pitch axis; seed outliers are drawn at the edge as triangles


def _clipped(ax, x, y, color, label):
    """Points outside YLIM drawn at the edge (triangles), the others as circles."""
    x, y = np.asarray(x), np.asarray(y)
    inside = (y >= YLIM[0]) & (y <= YLIM[1])
    l, = ax.plot(x[inside], y[inside], "o", color=color, label=label)
    for sel, edge, mk in ((y > YLIM[1], YLIM[1], "^"), (y < YLIM[0], YLIM[0], "v")):
        if sel.any():
            ax.plot(x[sel], np.full(sel.sum(), edge), mk, color=l.get_color(), label=f"{label}: off scale")
    return l


def plot(out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figs = {}
    H = read_table(os.path.join(out, "histories.csv"))
    fig, ax = plt.subplots(1, 3, figsize=(14, 4))
    for label, idx in _by(H, "case [-]").items():
        t = np.array(H["t [s]"])[idx]
        k = 2 if label.startswith("torque") else 0
        if k == 0:
            ax[0].plot(t, np.array(H["angle [rad]"])[idx] / (2 * math.pi), label=label)
            ax[1].plot(t, np.array(H["z/pitch [-]"])[idx], label=label)
        else:
            ax[2].plot(t, np.array(H["angle [rad]"])[idx] / (2 * math.pi), label=label + " (turns)")
            ax[2].plot(t, np.array(H["z/pitch [-]"])[idx], "--", label=label + " (z/pitch)")
    ax[0].set(xlabel="t [s]", ylabel="rotation [turns]", title="rotation drive: screw rotation")
    ax[1].set(xlabel="t [s]", ylabel="z / pitch [-]", title="rotation drive: axial advance")
    ax[2].set(xlabel="t [s]", ylabel="turns, z/pitch [-]", title="torque drive (step torque)")
    for a in ax:
        a.grid(True, alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    figs["histories"] = "histories.png"
    fig.savefig(os.path.join(out, figs["histories"]), dpi=110)
    plt.close(fig)

    S = read_table(os.path.join(out, "r_sweep.csv"))
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for rm, idx in _by(S, "map [-]").items():
        r = np.array(S["r [-]"])[idx]
        l = _clipped(ax[0], r, np.array(S["advance/pitch [-]"])[idx], None, f"{rm} (simulation)")
        cf = np.array(S["advance/pitch_closed_form [-]"])[idx]
        if np.all(np.isfinite(cf)):
            ax[0].semilogx(r, cf, "-", color=l.get_color(), label=f"{rm} (closed form)")
        ax[1].semilogx(r, np.array(S["torque_mean [N m]"])[idx], "o-", color=l.get_color(), label=rm)
    ax[1].semilogx(np.array(S["r [-]"]), np.array(S["torque_sliding_limit [N m]"]), "k--",
                   label="closed-form sliding torque")
    ax[0].axhline(1.0, color="k", lw=0.8, ls=":")
    ax[0].set_xscale("log")
    ax[0].set_ylim(*YLIM)
    ax[0].set(xlabel="r = eps_1 / eps_2 [-]", ylabel="advance per revolution / pitch [-]",
              title="thread limit: advance/pitch -> 1 as r -> 0")
    ax[1].set(xlabel="r = eps_1 / eps_2 [-]", ylabel="mean drive torque while sliding [N m]", title="torque needed")
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    figs["r_sweep"] = "r_sweep.png"
    fig.savefig(os.path.join(out, figs["r_sweep"]), dpi=110)
    plt.close(fig)

    A = read_table(os.path.join(out, "helix_sweep.csv"))
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    keys = [f"{m} r={r:g}" for m, r in zip(A["map [-]"], A["r [-]"])]
    groups = {}
    for i, k in enumerate(keys):
        groups.setdefault(k, []).append(i)
    for k, idx in groups.items():
        a_ = np.array(A["helix_angle [deg]"])[idx]
        l = _clipped(ax[0], a_, np.array(A["advance/pitch [-]"])[idx], None, k)
        cf = np.array(A["advance/pitch_closed_form [-]"])[idx]
        if np.all(np.isfinite(cf)):
            ax[0].plot(a_, cf, "-", color=l.get_color())
        ax[1].plot(a_, np.array(A["torque_mean [N m]"])[idx], "o", color=l.get_color(), label=k)
    order = np.argsort(A["helix_angle [deg]"])
    ax[1].plot(np.array(A["helix_angle [deg]"])[order], np.array(A["torque_sliding_limit [N m]"])[order], "k-",
               label="closed-form sliding torque")
    ax[0].set_ylim(*YLIM)
    ax[0].set(xlabel="helix angle [deg]", ylabel="advance per revolution / pitch [-]",
              title="advance vs helix angle (lines: closed form)")
    ax[1].set(xlabel="helix angle [deg]", ylabel="mean drive torque while sliding [N m]", title="torque needed")
    for a in ax:
        a.grid(True, alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    figs["helix_sweep"] = "helix_sweep.png"
    fig.savefig(os.path.join(out, figs["helix_sweep"]), dpi=110)
    plt.close(fig)

    T = read_table(os.path.join(out, "torque_drive.csv"))
    fig, ax = plt.subplots(figsize=(6, 4))
    for rm, idx in _by(T, "map [-]").items():
        ax.semilogy(np.array(T["torque/T_slide [-]"])[idx], np.maximum(np.array(T["max_angle [rad]"])[idx], 1e-4),
                    "o-", label=f"{rm}: max rotation")
    ax.axvline(1.0, color="k", ls="--", lw=0.8, label="closed-form sliding torque")
    ax.axvline(0.5, color="gray", ls=":", lw=0.8, label="T_slide / 2 (step-load overshoot)")
    ax.set(xlabel="applied torque / closed-form sliding torque [-]", ylabel="max rotation [rad]",
           title="torque drive: stick or slide")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    figs["torque_drive"] = "torque_drive.png"
    fig.savefig(os.path.join(out, figs["torque_drive"]), dpi=110)
    plt.close(fig)
    return figs


def _rows(T, cols):
    return [[T[c][i] for c in cols] for i in range(len(T[cols[0]]))]


def make_report(out, figs, quick):
    S = read_table(os.path.join(out, "r_sweep.csv"))
    A = read_table(os.path.join(out, "helix_sweep.csv"))
    T = read_table(os.path.join(out, "torque_drive.csv"))
    C = read_table(os.path.join(out, "crosscheck.csv"))
    b = base_params(quick)
    cf = steady_sliding(b.with_overrides(eps_2=b.eps_1 / 0.01))
    cols = ["map [-]", "r [-]", "advance/pitch [-]", "advance/pitch_closed_form [-]", "torque_mean [N m]",
            "torque_closed_form [N m]", "wall [s]"]
    # thread limit: simulated advance/pitch at the smallest r per map
    lim = []
    for rm, idx in _by(S, "map [-]").items():
        i = idx[int(np.argmin(np.array(S["r [-]"])[idx]))]
        j = idx[int(np.argmax(np.array(S["r [-]"])[idx]))]
        lim.append([rm, S["r [-]"][i], S["advance/pitch [-]"][i], S["r [-]"][j], S["advance/pitch [-]"][j]])
    # torque threshold per map
    thr = []
    for rm, idx in _by(T, "map [-]").items():
        f = np.array(T["torque/T_slide [-]"])[idx]
        slide = np.array(T["sliding_at_end [-]"])[idx] > 0
        slip = np.array(T["slipped_at_all [-]"])[idx] > 0
        thr.append([rm, float(f[~slide].max()) if (~slide).any() else float("nan"),
                    float(f[slide].min()) if slide.any() else float("nan"),
                    float(f[~slip].max()) if (~slip).any() else float("nan"),
                    float(f[slip].min()) if slip.any() else float("nan")])
    err_adv = [abs(a - c) for a, c, m in zip(S["advance/pitch [-]"], S["advance/pitch_closed_form [-]"],
                                              S["map [-]"]) if m != "seed"]
    err_tq = [abs(a / c - 1) for a, c, m in zip(S["torque_mean [N m]"], S["torque_closed_form [N m]"],
                                                S["map [-]"]) if m != "seed"]
    sd = [i for i, m in enumerate(S["map [-]"]) if m == "seed"]
    if sd:
        i0 = sd[int(np.argmin([S["r [-]"][i] for i in sd]))]
        seed_small = (f"at r = {S['r [-]'][i0]:.3g} the mean torque is {S['torque_mean [N m]'][i0]:.3g} N m, "
                      f"{S['torque_mean [N m]'][i0] / S['torque_sliding_limit [N m]'][i0]:.3g} of M, at "
                      f"advance/pitch {S['advance/pitch [-]'][i0]:.4g}")
        vals = [S["advance/pitch [-]"][i] for i in sd]
        seed_range = f"over the sweep, advance/pitch ranges from {min(vals):.3g} to {max(vals):.3g}"
    else:
        seed_small = seed_range = "(the seed map is not run in quick mode)"
    dev, failures = {}, []
    for i, m in enumerate(C["map [-]"]):
        if C["failed [-]"][i]:
            failures.append(f"{m} map, {C['engine [-]'][i]} engine, {C['model [-]'][i]} model: {C['failed [-]'][i]}")
            continue
        dev.setdefault(m, []).append((C["advance/pitch [-]"][i], C["torque_mean [N m]"][i]))
    spread = {m: (np.ptp([v[0] for v in d]), np.ptp([v[1] for v in d]) / np.mean([v[1] for v in d]))
              for m, d in dev.items()}
    good = [m for m in spread if m != "seed"]
    check_text = ("For " + " and ".join(good) + ", the engines and models agree: the largest spread is "
                  f"{max(spread[m][0] for m in good):.2g} in advance/pitch and {max(spread[m][1] for m in good):.2g} "
                  f"(relative) in torque. The full screw stays centred over these runs (t_end = {b.t_end} s) because "
                  "the point rings are symmetric and the scene's default normal damping "
                  f"({b.normal_damping:g} N s/m) damps its lateral mode; without damping that mode flutters "
                  "under friction (Hard cases, stability table).")
    if "seed" in spread:
        check_text += (f" The seed map's values spread by {spread['seed'][0]:.2g} in advance/pitch and "
                       f"{spread['seed'][1]:.2g} in torque across engines and models. Its steady state is not unique "
                       "(rail), and the engines halve different steps at its stick/slip discontinuity.")
    if failures:
        check_text += (" Failed, left out of the spreads (partial runs): " + "; ".join(failures) + ". The seed map's "
                       "stick/slip jump can leave Newton without a root; Exudyn then cuts the step to its minimum "
                       "and stops with that message (the reference accepts its best iterate instead).")
    text = f"""
Scene: `ScrewParams` defaults (hole radius {b.radius} m, helix angle {b.helix_angle} deg, pitch {pitch(b):.4g} m,
normal force eps_n * interference = {cf.normal_force:.4g} N, mu_1 = {b.mu_1} along / mu_2 = {b.mu_2} across the
helix, rotation drive: torsional spring {b.drive_stiffness} N m/rad to a driver at {b.rotation_speed:.4g} rad/s),
eps_1 = {b.eps_1:g} N/m along the helix fixed and eps_2 = eps_1 / r; {b.rings} x {b.points_per_ring} points,
dt = {b.dt} s, t_end = {b.t_end} s, generalized-alpha (rho_inf 0.8: it damps the unresolved torsional
oscillation of the drive spring, which the trapezoidal rule keeps forever and which then moves the fitted advance
by up to about 1 %). Reduced model (2 DOF) on the Exudyn engine unless stated. Advance per revolution = slope of
z over the screw angle over the last half of the run, normalised by the pitch 2 pi R tan(alpha); torque = mean drive
torque over the last half.

**Closed form** (`exu_aniso.scenes.screw.steady_sliding`, derived in its docstring): in steady sliding the axial
force balance makes the traction purely circumferential (no axial load). On the friction ellipse this gives the
sliding torque `M = (R + delta) eps_n delta / sqrt(cos^2 a / mu_1^2 + sin^2 a / mu_2^2)` =
{cf.torque:.5g} N m, for every r and for both the radial and the exact map. The slip direction is
`C^-1 T` (radial) or `F T` (exact), which gives

    advance / pitch = (1 - r) / (1 + r tan^2 a),   r = eps_1/eps_2 (radial)  or  r = (mu_1/mu_2)^2 (exact).

Over the radial and exact runs of the r sweep the simulated advance/pitch differs from this by at most
{max(err_adv):.2g} (absolute), and the torque by at most {max(err_tq):.2g} (relative).

### What the user learns

* **How stiff across the helix must the adhesion be?** With the radial map (adhesion steers the sliding),
  advance/pitch = (1 - r)/(1 + r tan^2 a). It is about 1 - r (1 + tan^2 a), so the deficit is linear in r:
  {", ".join(f"r = {r:g} gives {100 * (1 - r) / (1 + r * math.tan(math.radians(b.helix_angle)) ** 2):.4g} %"
             for r in (0.1, 0.01, 1e-3))} of the pitch. Isotropic adhesion
  (r = 1) gives no advance: the screw just turns in the hole.
* **How much torque?** The sliding torque does not depend on the adhesion. It is set by the friction
  coefficients, the normal force and the helix angle (`M` above). Raising the helix angle from 2 to 30 deg mixes
  more of the high cross-helix friction mu_2 into the circumferential direction, and the torque rises.
* **Differences between maps.** *Radial*: B steers the kinematics, F sets the torque. This is the thread
  behaviour of paper 001, Fig. 2. *Exact* (maximum dissipation): B matters only while sticking. The advance is
  set by mu_1/mu_2 alone ({(1 - (b.mu_1 / b.mu_2) ** 2) / (1 + (b.mu_1 / b.mu_2) ** 2 * math.tan(math.radians(b.helix_angle)) ** 2):.4g}
  of the pitch for these coefficients, flat in r). To get a thread from the exact map, make the friction
  anisotropic (mu_1 << mu_2). *Seed*: the friction force settles on the dominant eigenvector of C F (the "rail").
  At small r that is the cross-helix direction, so the screw rides the thread with only part of the friction
  torque: {seed_small}.
  At r near 1 the force lies along the helix, and the axial motion is left to the penalty dynamics. The advance
  becomes erratic and depends on the step size: {seed_range}.
  The seed map does not give a usable sliding torque, and the calibration does not offer it.

### Thread limit

{markdown_table(["map", "smallest r", "advance/pitch there", "largest r", "advance/pitch there"], lim)}
![advance per revolution and torque vs r](./{figs["r_sweep"]})

### Advance per revolution and torque vs r (rotation drive, helix angle {b.helix_angle} deg)

{markdown_table(cols, _rows(S, cols))}
### vs helix angle

{markdown_table(["map [-]", "r [-]", "helix_angle [deg]"] + cols[2:], _rows(A, ["map [-]", "r [-]", "helix_angle [deg]"] + cols[2:]))}
![advance and torque vs helix angle](./{figs["helix_sweep"]})

### Torque drive: when does the screw stick?

A constant torque is switched on at t = 0 (radial/exact map, r = 0.01, dt = 1e-4 s). *Sliding at end*: the screw
still turns more than 0.5 rad over the last 40 % of the run. *Slipped at all*: energy was dissipated.
The closed-form sliding torque M is the threshold of sustained sliding: below it the screw comes to rest
(after a transient), above it it accelerates. A torque STEP slips already above about M/2. The
undamped elastic response to a suddenly applied load overshoots to twice its static value, so the stick traction
touches the friction limit at M/2. A slowly ramped torque would stay stuck up to M.

{markdown_table(["map", "largest torque/M still sticking at end", "smallest torque/M sliding at end",
                 "largest torque/M with no slip", "smallest torque/M with slip"], thr)}
{markdown_table(["map [-]", "torque/T_slide [-]", "max_angle [rad]", "late_rotation [rad]", "dissipated_energy [J]"],
                _rows(T, ["map [-]", "torque/T_slide [-]", "max_angle [rad]", "late_rotation [rad]",
                          "dissipated_energy [J]"]))}
![torque drive](./{figs["torque_drive"]})

### Time histories

![time histories](./{figs["histories"]})

### Cross-check: Exudyn vs reference engine, reduced vs full model

{markdown_table(list(C), _rows(C, list(C)), fmt="{:.6g}")}
{check_text}
"""
    return text


if __name__ == "__main__":
    sys.exit(main())
