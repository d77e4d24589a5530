"""Work-precision diagrams: error against CPU time, log-log, for both scenes.

    python studies/work_precision.py [--quick] [--repeats N] [--out DIR]

One curve per *family* (a setting with the step size varied): solver (trapezoidal,
generalized-alpha), return map (seed, exact, radial), model (planar/full block, reduced/full
screw), Newton (full Newton against the package's modified Newton), implementation (every entry of ``IMPLEMENTATIONS`` in ``studies/_lib/implementations.py``:
Exudyn, the numpy reference, later the fast path) and the oracle scenes. Errors:

* against a converged fine solution of the SAME family (smallest dt / 4). Block: largest distance
  between the centre paths [m]; screw: largest displacement error of a point on the hole radius,
  sqrt((R d psi)^2 + dz^2) [m]; both also relative to the largest displacement of the fine run;
  the fine trajectory is interpolated linearly to the coarse times (exact where the grids nest);
* against analytic oracles where they exist (tests/test_reference.py, tests/test_exudyn_scenes.py):
  ``harmonic`` (isotropic stick, spring drive: forced oscillator y = A t - A/w sin(w t)),
  ``coulomb`` (isotropic sliding under a constant pull: acceleration (P - mu m g)/m),
  ``heading`` (constant orthotropic friction, exact map: steady sliding direction where pull plus
  friction -|N| F^-1 v / sqrt(v.F^-1 v) is parallel to v), ``pitch`` (nearly rigid thread: advance
  per revolution -> pitch). The oracle errors of the last three contain the penalty (model) error,
  so they level off where the time error falls below it.

Cost: process CPU time of the whole run (median over repeats; serial, as for the benchmarks:
``--processes`` and ``--mpi`` are refused).
Outputs: ``work_precision.csv``, ``orders.csv`` (observed order and ratios per family),
``work_precision.png`` (error vs CPU time), ``error_vs_dt.png``, ``report.md``.
"""
from __future__ import annotations

import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

from _lib import studylib  # noqa: E402
from _lib.implementations import IMPLEMENTATIONS  # noqa: E402
from _lib.studylib import finish, markdown_table, parse_args, read_table, sweep, table  # noqa: E402

from exu_aniso.scenes.block import orthotropic_heading  # noqa: E402
from exu_aniso.scenes.block import BlockParams  # noqa: E402
from exu_aniso.scenes.screw import ScrewParams, pitch
from exu_aniso.scenes.base import summary_float

# ----------------------------------------------------------------------------------------------
# families

BLOCK_BASE = dict(points="corners")          # defaults otherwise: polar, radial, displacement drive
SCREW_BASE = dict()                          # spiral net, radial, rotation drive

ORACLE_SCENES = {
    "harmonic": ("block", dict(adhesion="isotropic", eps_1=1e3, friction="isotropic", mu_1=10.0, drive="displacement",
                               drive_stiffness=1e3, drive_speed=0.1, drive_angle=90.0, points="corners")),
    "coulomb": ("block", dict(adhesion="isotropic", friction="isotropic", mu_1=0.3, eps_1=1e5, drive="force", force=5.0,
                              drive_angle=90.0, return_map="exact", points="corners")),
    "heading": ("block", dict(adhesion="isotropic", eps_1=1e5, friction="orthotropic", mu_1=0.2, mu_2=0.6,
                              friction_angle=0.0, return_map="exact", drive="force", force=10.0, drive_angle=45.0,
                              points="center")),
    "pitch": ("screw", dict(eps_1=1e3, eps_2=1e7, mu_1=0.2, mu_2=5.0, return_map="radial", drive="rotation")),
}


def families(quick):
    """name -> dict(scene, engine, params, options, oracle)."""
    out = {}
    for scene, base in (("block", BLOCK_BASE), ("screw", SCREW_BASE)):
        full = "full"
        for impl, (engine, opts) in IMPLEMENTATIONS.items():
            out[f"{scene} {impl}"] = dict(scene=scene, engine=engine, params=dict(base), options=dict(opts),
                                          oracle="", family="implementation")
        exu_opts = IMPLEMENTATIONS["exudyn"][1]
        out[f"{scene} generalized_alpha"] = dict(scene=scene, engine="exudyn", params=dict(base, solver="generalized_alpha"),
                                                 options=dict(exu_opts), oracle="", family="solver")
        for m in ("seed", "exact"):
            out[f"{scene} {m}"] = dict(scene=scene, engine="exudyn", params=dict(base, return_map=m),
                                       options=dict(exu_opts), oracle="", family="return_map")
        out[f"{scene} {full}"] = dict(scene=scene, engine="exudyn", params=dict(base, model=full),
                                      options=dict(exu_opts), oracle="", family="model")
        # the Newton of every step: full Newton against the package's modified Newton (README "Solver settings")
        out[f"{scene} full_newton"] = dict(scene=scene, engine="exudyn", params=dict(base),
                                           options=dict(exu_opts, newton="full"), oracle="", family="newton")
    for name, (scene, ov) in ORACLE_SCENES.items():
        out[f"{scene} oracle {name}"] = dict(scene=scene, engine="exudyn", params=dict(ov),
                                             options=dict(IMPLEMENTATIONS["exudyn"][1]), oracle=name, family="oracle")
    out["block oracle harmonic generalized_alpha"] = dict(out["block oracle harmonic"], family="oracle")
    out["block oracle harmonic generalized_alpha"]["params"] = dict(ORACLE_SCENES["harmonic"][1],
                                                                     solver="generalized_alpha")
    if quick:   # quick: the default Exudyn route only (the others agree with it to Newton tolerance)
        out = {k: v for k, v in out.items() if v["family"] != "implementation" or k.endswith(" exudyn")}
    return out


def step_sizes(scene, quick):
    """Coarse steps of a curve; the fine solution uses the smallest / 4."""
    if scene == "block":
        return [4e-3, 2e-3, 1e-3] if quick else [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4]
    # the screw's stiff thread modes (axial ~1e4 rad/s, torsional ~1.4e3 rad/s) are resolved only
    # below ~1e-4 s: the error stays flat above (see the report), so the screw curves reach lower
    return [1.25e-4, 6.25e-5, 3.125e-5] if quick else [1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5]


def t_end_for(scene, quick):
    return {"block": 0.1 if quick else 0.5, "screw": 0.02 if quick else 0.1}[scene]


# ----------------------------------------------------------------------------------------------
# one run

def _run(scene, engine, p, options):
    if engine == "exudyn":
        if scene == "block":
            from exu_aniso.models.block import RunBlock
            return RunBlock(p, **options)
        from exu_aniso.models.screw import RunScrew
        return RunScrew(p, contactOutputs=False, **options)
    from exu_aniso.scenes.block import simulate_block
    from exu_aniso.scenes.screw import simulate_screw
    return (simulate_block if scene == "block" else simulate_screw)(p, **options)


def wp_case(case):
    """Run one family at one dt (repeats for the CPU time); returns the trajectory and costs."""
    P = BlockParams if case["scene"] == "block" else ScrewParams
    p = P(**case["params"], t_end=case["t_end"], dt=case["dt"])
    cpu = []
    r = None
    for _ in range(case["repeats"]):
        c0 = time.process_time()
        try:
            r = _run(case["scene"], case["engine"], p, case["options"])
        except Exception as e:           # reported in the CSV, not fatal
            return dict(ok=False, error=f"{type(e).__name__}: {str(e).splitlines()[0][:80]}")
        cpu.append(time.process_time() - c0)
    keys = ("t", "x", "y", "vx", "vy") if case["scene"] == "block" else ("t", "angle", "z")
    out = dict(ok=True, cpu_s=float(np.median(cpu)), steps=int(r.summary["steps"]),
               newton=int(r.summary["newton_iterations"]), traj={k: np.asarray(r.trajectory[k]) for k in keys})
    if case["scene"] == "screw":
        out["advance_per_rev"] = summary_float(r.summary, "advance_per_rev")
    return out


def warm_case(case):
    """Untimed short run per engine before the timed ones (imports, numba cache)."""
    _run(case["scene"], case["engine"], (BlockParams if case["scene"] == "block" else ScrewParams)(
        **case["params"], t_end=5e-3, dt=1e-3), case["options"])
    return True


# ----------------------------------------------------------------------------------------------
# errors

def displacement(scene, tr, p):
    """(n, 2) displacement used for the error: block (x, y); screw (R psi, z)."""
    if scene == "block":
        return np.column_stack([tr["x"], tr["y"]])
    return np.column_stack([p.radius * tr["angle"], tr["z"]])


def error_to_fine(scene, coarse, fine, p):
    a, b = displacement(scene, coarse, p), displacement(scene, fine, p)
    bi = np.column_stack([np.interp(coarse["t"], fine["t"], b[:, j]) for j in range(2)])
    err = float(np.max(np.linalg.norm(a - bi, axis=1)))
    scale = float(np.max(np.linalg.norm(b - b[0], axis=1)))
    return err, err / scale if scale > 0 else float("nan")


def oracle_error(name, res, p):
    """Relative error against the analytic oracle (NaN without one)."""
    tr = res["traj"]
    t = tr["t"]
    late = t >= 0.5 * t[-1]
    if name == "harmonic":
        A = p.drive_stiffness * p.drive_speed / (p.drive_stiffness + p.eps_1)
        w = math.sqrt((p.drive_stiffness + p.eps_1) / p.mass)
        exact = A * t - A / w * np.sin(w * t)
        return float(np.max(np.abs(tr["y"] - p.y0 - exact)) / np.max(np.abs(exact)))
    if name == "coulomb":
        a = np.polyfit(t[late], tr["vy"][late], 1)[0]
        a_exact = (p.force - p.mu_1 * p.normal_load) / p.mass
        return float(abs(a - a_exact) / a_exact)
    if name == "heading":
        i = int(np.argmax(late))
        dvx, dvy = tr["vx"][-1] - tr["vx"][i], tr["vy"][-1] - tr["vy"][i]
        beta = orthotropic_heading(math.radians(p.drive_angle), p.force, p.normal_load, p.mu_1, p.mu_2)
        return float(abs(math.atan2(dvy, dvx) - beta) / beta)
    if name == "pitch":
        return float(abs(res["advance_per_rev"] / pitch(p) - 1.0))
    return float("nan")


def observed_order(dts, errs, last=3):
    """Slope of log(error) over log(dt) over the ``last`` smallest steps (the asymptotic range)."""
    order = np.argsort(dts)[:last]
    dts, errs = np.asarray(dts, float)[order], np.asarray(errs, float)[order]
    ok = np.isfinite(errs) & (errs > 0)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(dts[ok]), np.log(errs[ok]), 1)[0])


# ----------------------------------------------------------------------------------------------
# plots (from the CSV)

def plots(out, csv_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    T = read_table(csv_path)
    fams = list(dict.fromkeys(T["family [-]"]))
    paths = []
    for fname, xkey, xlabel in (("work_precision.png", "cpu [s]", "CPU time of the run [s]"),
                                ("error_vs_dt.png", "dt [s]", "time step dt [s]")):
        fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
        for ax, scene in zip(axes, ("block", "screw")):
            for f in fams:
                idx = [j for j in range(len(T["dt [s]"])) if T["family [-]"][j] == f and T["scene [-]"][j] == scene
                       and T["kind [-]"][j] == "coarse" and T["status [-]"][j] == "ok"]
                if not idx:
                    continue
                x = [T[xkey][j] for j in idx]
                y = [T["error_rel [-]"][j] for j in idx]
                style = "--" if T["family_kind [-]"][idx[0]] == "oracle" else "-"
                line, = ax.loglog(x, y, "o" + style, ms=4, label=f.replace(scene + " ", ""))
                # oracle errors at round-off (Coulomb: the trapezoidal rule is exact for a constant
                # acceleration) are left out of the plot; they are in the CSV
                xo = [xv for xv, j in zip(x, idx) if T["oracle_error_rel [-]"][j] > 1e-12]
                yo = [T["oracle_error_rel [-]"][j] for j in idx if T["oracle_error_rel [-]"][j] > 1e-12]
                if yo:
                    ax.loglog(xo, yo, "x:", color=line.get_color(), ms=5, label=f.replace(scene + " ", "") + " vs oracle")
            ax.set_xlabel(xlabel)
            ax.set_ylabel("relative error [-] (vs fine: o; vs oracle: x)")
            ax.set_title(f"{scene}")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=6, ncol=2)
        fig.tight_layout()
        path = os.path.join(out, fname)
        fig.savefig(path, dpi=120)
        plt.close(fig)
        paths.append(path)
    return paths


# ----------------------------------------------------------------------------------------------

COLUMNS = ["family [-]", "scene [-]", "family_kind [-]", "engine [-]", "model [-]", "return_map [-]", "solver [-]",
           "kind [-]", "dt [s]", "t_end [s]", "steps [-]", "newton [-]", "cpu [s]", "cpu_per_step [s]", "error [m]",
           "error_rel [-]", "oracle [-]", "oracle_error_rel [-]", "repeats [-]", "status [-]"]
ORDER_COLUMNS = ["family [-]", "scene [-]", "family_kind [-]", "observed_order [-]", "oracle_order [-]",
                 "error_rel_at_dt_min [-]", "oracle_error_rel_at_dt_min [-]", "cpu_at_dt_min [s]",
                 "cpu_vs_base_at_dt_min [-]", "error_vs_base_at_dt_min [-]", "decreasing [-]"]


def main(argv=None):
    timer = studylib.Timer()

    def extra(ap):
        ap.add_argument("--repeats", type=int, default=None, help="timing repeats per point (default 1 quick, 3 full)")
    args = parse_args("work_precision", __doc__.splitlines()[0], argv, extra, parallel=False)  # serial CPU times
    reps = args.repeats or (1 if args.quick else 3)
    fams = families(args.quick)
    cases = []
    for name, f in fams.items():
        dts = step_sizes(f["scene"], args.quick)
        for dt in dts:
            cases.append(dict(f, name=name, dt=dt, kind="coarse", repeats=reps, t_end=t_end_for(f["scene"], args.quick)))
        cases.append(dict(f, name=name, dt=min(dts) / 4, kind="fine", repeats=1, t_end=t_end_for(f["scene"], args.quick)))
    warm = {(c["scene"], c["engine"]): c for c in cases}
    sweep(warm_case, list(warm.values()), args, progress=False)
    res = sweep(wp_case, cases, args)
    fine = {c["name"]: r for c, r in zip(cases, res) if c["kind"] == "fine"}
    rows = []
    for c, r in zip(cases, res):
        P = BlockParams if c["scene"] == "block" else ScrewParams
        p = P(**c["params"], t_end=c["t_end"], dt=c["dt"])
        if not r["ok"]:
            rows.append([c["name"], c["scene"], c["family"], c["engine"], p.model, p.return_map, p.solver, c["kind"],
                         c["dt"], c["t_end"], 0, 0] + [float("nan")] * 4 + [c["oracle"] or "-", float("nan"),
                                                                            c["repeats"], r["error"]])
            continue
        fr = fine[c["name"]]
        err, rel = error_to_fine(c["scene"], r["traj"], fr["traj"], p) if fr["ok"] else (float("nan"),) * 2
        rows.append([c["name"], c["scene"], c["family"], c["engine"], p.model, p.return_map, p.solver, c["kind"],
                     c["dt"], c["t_end"], r["steps"], r["newton"], r["cpu_s"], r["cpu_s"] / r["steps"], err, rel,
                     c["oracle"] or "-", oracle_error(c["oracle"], r, p), c["repeats"], "ok"])
    csv_path = table(os.path.join(args.out, "work_precision.csv"), COLUMNS, rows)

    # orders and ratios from the CSV
    T = read_table(csv_path)
    n = len(T["dt [s]"])
    orows = []
    for name in fams:
        idx = [j for j in range(n) if T["family [-]"][j] == name and T["kind [-]"][j] == "coarse"]
        dts = [T["dt [s]"][j] for j in idx]
        errs = [T["error_rel [-]"][j] for j in idx]
        oerr = [T["oracle_error_rel [-]"][j] for j in idx]
        jmin = idx[int(np.argmin(dts))]
        scene = T["scene [-]"][jmin]
        base = f"{scene} exudyn"
        jb = [j for j in range(n) if T["family [-]"][j] == base and T["kind [-]"][j] == "coarse"
              and T["dt [s]"][j] == T["dt [s]"][jmin]][0]
        e_sorted = [e for _, e in sorted(zip(dts, errs))]
        decreasing = all(np.isfinite(e_sorted)) and all(a < b for a, b in zip(e_sorted, e_sorted[1:]))
        orows.append([name, scene, T["family_kind [-]"][jmin], observed_order(dts, errs), observed_order(dts, oerr),
                      T["error_rel [-]"][jmin], T["oracle_error_rel [-]"][jmin], T["cpu [s]"][jmin],
                      T["cpu [s]"][jmin] / T["cpu [s]"][jb], T["error_rel [-]"][jmin] / T["error_rel [-]"][jb],
                      "yes" if decreasing else "no"])
    table(os.path.join(args.out, "orders.csv"), ORDER_COLUMNS, orows)
    pngs = plots(args.out, csv_path)

    O = read_table(os.path.join(args.out, "orders.csv"))
    print(f"\n{'family':42s} {'order':>6s} {'oracle order':>12s} {'err@dtmin':>10s} {'oracle err':>10s} "
          f"{'CPU@dtmin [s]':>13s} {'CPU/base':>8s} {'err/base':>9s} {'decreasing':>10s}")
    for j in range(len(O["family [-]"])):
        print(f"{O['family [-]'][j]:42s} {O['observed_order [-]'][j]:6.2f} {O['oracle_order [-]'][j]:12.2f} "
              f"{O['error_rel_at_dt_min [-]'][j]:10.2e} {O['oracle_error_rel_at_dt_min [-]'][j]:10.2e} "
              f"{O['cpu_at_dt_min [s]'][j]:13.3f} {O['cpu_vs_base_at_dt_min [-]'][j]:8.2f} "
              f"{O['error_vs_base_at_dt_min [-]'][j]:9.2e} {O['decreasing [-]'][j]:>10s}")
    orows_md = [[O[c][j] for c in ORDER_COLUMNS] for j in range(len(O["family [-]"]))]
    T_rows = [[T["family [-]"][j], T["dt [s]"][j], int(T["steps [-]"][j]), T["cpu [s]"][j], T["error_rel [-]"][j],
               T["oracle_error_rel [-]"][j], T["status [-]"][j]] for j in range(n) if T["kind [-]"][j] == "coarse"]
    body = f"""Relative error against CPU time for each family (one setting, step size varied), errors against
the fine solution of the same family (smallest dt / 4) and, for the oracle scenes, against the analytic
oracle (see the module docstring of `studies/work_precision.py`). Block error: largest distance
between the centre paths over the run, relative to the largest displacement; screw error: largest
displacement error of a point on the hole radius, sqrt((R d psi)^2 + dz^2), relative likewise.
Simulated time: block {t_end_for("block", args.quick)} s, screw {t_end_for("screw", args.quick)} s; CPU time =
process CPU time of the run, median over {reps} serial repeat(s). Files: `work_precision.csv`, `orders.csv`.

![error vs CPU time](./{os.path.basename(pngs[0])})

(Oracle errors below 1e-12, i.e. round-off, are in the CSV but not drawn.)

![error vs step size](./{os.path.basename(pngs[1])})

### Observed orders and ratios at the smallest coarse step

`observed_order`: slope of log(error) over log(dt) over the three smallest steps (against the fine
solution; `oracle_order` against the oracle); `cpu_vs_base` and `error_vs_base`: this family
over the base family of its scene (`block exudyn` / `screw exudyn`) at the same dt; `decreasing`:
the error falls at every halving of dt.

{markdown_table([c.split(" [")[0] for c in ORDER_COLUMNS], orows_md)}
### All points

{markdown_table(["family", "dt [s]", "steps", "CPU [s]", "error vs fine [-]", "error vs oracle [-]", "status"], T_rows)}"""
    finish(args, timer, body, "Work-precision: error against CPU time")
    return 0


if __name__ == "__main__":
    sys.exit(main())
