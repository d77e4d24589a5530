"""Benchmark suite: wall time per step and per simulated second, Newton
iterations per step and cost per contact-point evaluation of both scenes, across the number of
contact points K, return map, model, Jacobian, solver and implementation (Exudyn, the numpy
reference, later the fast path); the cost of the contact law itself per point; and our step cost
as a ratio to Exudyn's C++ spring-dampers at the same points (``studies/_lib/baseline.py``;
``studies/baseline.py`` measures that table alone).

    python studies/benchmarks.py [--quick] [--repeats N] [--out DIR]

Benchmarks always run SERIAL (``--serial`` is implied, ``--processes`` and ``--mpi`` are refused):
timings from parallel workers share cores and are meaningless. Every timing is the median over repeats (>= 3 quick, >= 5 full); ratios are
formed from medians measured in the same run, never from absolute times of different runs.
The cost measure is the PROCESS CPU TIME of the solve (``time.process_time`` around
``SolveDynamic``, or around ``simulate_*`` for the reference; model building excluded). For these
single-threaded runs it equals the wall time on an idle core, but unlike wall time it does not
grow when other processes share the machine; the solver's own wall time is kept beside it in
``benchmarks.csv`` (``wall_per_step``), and so is the fastest repeat (``cpu_per_step_min``, the
least disturbed measure, which the test of linear growth uses).

Settings: a *setting* is (implementation, factor variation); an implementation is a name ->
(engine, dict of Build*/simulate_* keyword options) in ``IMPLEMENTATIONS``
(``studies/_lib/implementations.py``), and a variation is a dict of BlockParams/ScrewParams
overrides plus a dict of keyword options. Another implementation of the adapter is one more line in
``IMPLEMENTATIONS`` (as "exudyn-numpy" is).

Outputs (``--out``, default docs/results/benchmarks): ``benchmarks.csv`` (one row per setting),
``kernel.csv`` (law cost per point), ``baseline.csv`` (ours / C++ baseline), ``targets.csv`` (the speed
targets, ``studies/_lib/targets.py``: each scene / a cube on as many C++ springs at Exudyn's defaults,
median [min-max] of interleaved repeats, with its floor; the compiled call's fixed and per-point cost),
``force_call.csv`` (one force call of a contact set on K = 1 to 256 points, and the fit), ``scale.csv`` (M cubes: one set each, one group, C++ springs,
the floor; ``studies/_lib/scale.py``), ``memory.csv`` (peak memory), ``long_run.csv`` (the shaken joint for
1000 cycles against its C++ yardstick and floor; ``studies/_lib/long_run.py``), ``benchmarks.json``
(fits of cost = a + b K with R^2, ratios; machine-readable), ``cost_vs_points.png``, ``report.md``.
"""
from __future__ import annotations

import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

from _lib import baseline, long_run, scale, studylib, target_tables, target_timing  # noqa: E402
from _lib.implementations import IMPLEMENTATIONS  # noqa: E402
from _lib.studylib import finish, markdown_table, parse_args, read_table, sweep, table, write_json  # noqa: E402

# ----------------------------------------------------------------------------------------------
# settings

# implementation name -> (engine, Build* / simulate_* options): studies/_lib/implementations.py
# (shared with work_precision.py; add the fast path there)

# base scenes of the benchmark (defaults of the scenes otherwise: polar block with the radial map
# and the displacement drive, spiral screw with the rotation drive)
BASE = {"block": dict(points="corners"), "screw": dict()}

# number of contact points: block "center" + N x N grids, screw rings x points_per_ring
K_LAYOUTS = {
    "block": [dict(points="center")] + [dict(points=f"grid:{n}") for n in (2, 3, 4, 5, 6, 8)],
    "screw": [dict(rings=r, points_per_ring=n) for r, n in ((1, 1), (1, 4), (2, 4), (2, 8), (4, 8), (4, 16))],
}
K_LAYOUTS_QUICK = {
    "block": [dict(points="center"), dict(points="grid:2"), dict(points="grid:4"), dict(points="grid:8")],
    "screw": [dict(rings=1, points_per_ring=1), dict(rings=2, points_per_ring=4), dict(rings=4, points_per_ring=16)],
}


def variations(scene, quick):
    """(factor, value, param overrides, options) varied one at a time around the base scene."""
    out = [("base", "base", {}, {})]
    # the reduced screw evaluates ONE representative point by symmetry (BuildScrew symmetry=True,
    # its default); the K sweep switches that off so that every point of the layout is evaluated
    k_opts = {"symmetry": False} if scene == "screw" else {}
    for lay in (K_LAYOUTS_QUICK if quick else K_LAYOUTS)[scene]:
        out.append(("K", lay.get("points") or f"{lay['rings']}x{lay['points_per_ring']}", lay, dict(k_opts)))
    for m in ("seed", "exact"):          # radial is the base
        out.append(("return_map", m, {"return_map": m}, {}))
    out.append(("model", "full", {"model": "full"}, {}))
    out.append(("jacobian", "numerical", {}, {"jacobian": "numerical"}))
    out.append(("solver", "generalized_alpha", {"solver": "generalized_alpha"}, {}))
    return out


# Build* options that the reference does not take (dropped for engine "reference")
EXUDYN_ONLY = ("implementation", "symmetry", "nodeType")


def n_points(scene, p):
    from exu_aniso.scenes.block import block_points
    from exu_aniso.scenes.screw import screw_points
    return len(block_points(p) if scene == "block" else screw_points(p))


def make_params(scene, overrides):
    from exu_aniso.scenes.block import BlockParams
    from exu_aniso.scenes.screw import ScrewParams
    return (BlockParams if scene == "block" else ScrewParams)(**overrides)


def run_setting(scene, engine, p, options):
    """One simulation; returns (cpu_s, wall_s, steps, newton_iterations, contact implementation,
    number of contact points evaluated).

    cpu_s: process CPU time of the solve (Exudyn: SolveDynamic only; reference: the whole
    simulate_* call, whose setup is negligible); wall_s: the solver's own wall time."""
    if engine == "exudyn":
        from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
        if scene == "block":
            from exu_aniso.models.block import BuildBlock as build
        else:
            from exu_aniso.models.screw import BuildScrew as build
        model = build(p, **options)
        c0 = time.process_time()
        wall, steps, iters, _ = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
        return (time.process_time() - c0, wall, steps, iters, model["contact"].get("implementation", "numpy"),
                len(model["contact"]["points"]))
    from exu_aniso.scenes.block import simulate_block
    from exu_aniso.scenes.screw import simulate_screw
    options = {k: v for k, v in options.items() if k not in EXUDYN_ONLY}
    c0 = time.process_time()
    r = (simulate_block if scene == "block" else simulate_screw)(p, **options)
    cpu = time.process_time() - c0
    s = r.summary
    return cpu, float(s["wall_s"]), int(s["steps"]), int(s["newton_iterations"]), "numpy", n_points(scene, p)


def warm_up(scene, engine, p, options):
    """A 5-step run of the same setting before timing (first-call costs: imports, numba cache)."""
    run_setting(scene, engine, p.with_overrides(t_end=5 * p.dt), options)


def bench_case(case):
    """Median timings of one setting over case['repeats'] runs (module level: sweep needs it)."""
    p = make_params(case["scene"], case["params"])
    K = n_points(case["scene"], p)
    runs = []
    err = ""
    impl = ""
    for i in range(case["repeats"]):
        try:
            if i == 0:
                warm_up(case["scene"], case["engine"], p, case["options"])
            *timing, impl, K = run_setting(case["scene"], case["engine"], p, case["options"])
            runs.append(timing)
        except Exception as e:          # a setting that fails is reported, not fatal
            err = f"{type(e).__name__}: {str(e).splitlines()[0][:80]}"
            break
    if not runs or err:
        nan = float("nan")
        return dict(K=K, steps=0, newton_per_step=nan, step_s=nan, step_min_s=nan, wall_step_s=nan, sim_second_s=nan,
                    point_eval_s=nan, status=err, contact_impl=impl)
    R = np.array(runs, dtype=float)
    cpu, wall, steps, iters = R[:, 0], R[:, 1], R[:, 2], R[:, 3]
    return dict(K=K, steps=int(np.median(steps)), newton_per_step=float(np.median(iters / steps)),
                step_s=float(np.median(cpu / steps)), step_min_s=float(np.min(cpu / steps)),
                wall_step_s=float(np.median(wall / steps)),
                sim_second_s=float(np.median(cpu / p.t_end)), point_eval_s=float(np.median(cpu / (iters * K))),
                status="ok", contact_impl=impl)


def kernel_case(case):
    """Cost of ContactLaw.evaluate (projection + fields + return map + tangent) per point, for K
    points all sliding (anchors 1 mm behind) or all sticking (anchors 1 nm behind)."""
    from exu_aniso import Adhesion, ContactLaw, Friction, Plane
    rng = np.random.default_rng(0)
    K = case["K"]
    law = ContactLaw(Plane(), Adhesion.polar(1e4, 1e3, 1e-3), Friction.polar(0.2, 0.6, 1e-3), 1e6,
                     return_map=case["map"])
    x = np.c_[rng.uniform(0.2, 1.0, (K, 2)), -1e-5 * np.ones(K)]
    H = law.initial_history(K)
    H[:, 2:4] = x[:, :2] - (1e-3 if case["state"] == "slide" else 1e-9)
    H[:, 4] = 1.0
    inner = max(1, case.get("calls", 400) // K)
    times = []
    for _ in range(case["repeats"]):
        t0 = time.process_time()
        for _ in range(inner):
            law.evaluate(x, None, H)
        times.append((time.process_time() - t0) / inner)
    st = law.evaluate(x, None, H).status
    expect = 2 if case["state"] == "slide" else 1
    return dict(per_point_s=float(np.median(times)) / K, call_s=float(np.median(times)),
                all_in_state=bool(np.all(st == expect)))


# ----------------------------------------------------------------------------------------------
# analysis

def linear_fit(K, y):
    """Least squares y = a + b K; returns a, b, R^2."""
    K, y = np.asarray(K, float), np.asarray(y, float)
    b, a = np.polyfit(K, y, 1)
    res = y - (a + b * K)
    ss = float(np.sum((y - y.mean()) ** 2))
    return float(a), float(b), float(1.0 - np.sum(res ** 2) / ss) if ss > 0 else float("nan")


BENCH_COLUMNS = ["scene [-]", "implementation [-]", "engine [-]", "contact_impl [-]", "factor [-]", "value [-]", "model [-]",
                 "return_map [-]", "solver [-]", "jacobian [-]", "K [-]", "t_end [s]", "steps [-]", "newton_per_step [-]",
                 "cpu_per_step [s]", "cpu_per_sim_second [s/s]", "cpu_per_point_eval [s]",
                 "wall_per_step [s]", "cpu_per_step_min [s]",
                 "relative_to_base [-]", "repeats [-]", "status [-]"]
KERNEL_COLUMNS = ["return_map [-]", "state [-]", "K [-]", "per_point [s]", "per_call [s]",
                  "per_point_vs_K1 [-]", "repeats [-]"]
BASE_COLUMNS = baseline.BASE_COLUMNS


def fits_from_csv(path):
    """cost per step = a + b K per (scene, implementation) from the K rows of benchmarks.csv."""
    T = read_table(path)
    out = []
    keys = sorted({(s, i) for s, i in zip(T["scene [-]"], T["implementation [-]"])})
    for scene, impl in keys:
        idx = [j for j in range(len(T["K [-]"])) if T["scene [-]"][j] == scene and T["implementation [-]"][j] == impl
               and T["factor [-]"][j] == "K" and T["status [-]"][j] == "ok"]
        K = np.array([T["K [-]"][j] for j in idx])
        y = np.array([T["cpu_per_step [s]"][j] for j in idx])
        if len(set(K.tolist())) < 2:
            continue
        a, b, r2 = linear_fit(K, y)
        out.append(dict(scene=scene, implementation=impl, a_s=a, b_s_per_point=b, r2=r2,
                        K_min=int(K.min()), K_max=int(K.max()), n=len(K)))
    return out


def plot(out, fits):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    T = read_table(os.path.join(out, "benchmarks.csv"))
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, scene in zip(axes, ("block", "screw")):
        for f in fits:
            if f["scene"] != scene:
                continue
            idx = [j for j in range(len(T["K [-]"])) if T["scene [-]"][j] == scene
                   and T["implementation [-]"][j] == f["implementation"] and T["factor [-]"][j] == "K"
                   and T["status [-]"][j] == "ok"]
            K = np.array([T["K [-]"][j] for j in idx])
            y = np.array([T["cpu_per_step [s]"][j] for j in idx]) * 1e3
            line, = ax.plot(K, y, "o", label=f"{f['implementation']}")
            kk = np.linspace(0, K.max(), 50)
            ax.plot(kk, (f["a_s"] + f["b_s_per_point"] * kk) * 1e3, "-", color=line.get_color(),
                    label=f"fit {f['a_s'] * 1e3:.3g} + {f['b_s_per_point'] * 1e6:.3g}e-3 K ms, R² {f['r2']:.3f}")
        ax.set_xlabel("contact points K [-]")
        ax.set_ylabel("CPU time per step [ms]")
        ax.set_title(f"{scene}: cost per step vs contact points")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(out, "cost_vs_points.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


# ----------------------------------------------------------------------------------------------

def main(argv=None):
    timer = studylib.Timer()

    def extra(ap):
        ap.add_argument("--repeats", type=int, default=None, help="timing repeats (default 3 quick, 5 full)")
    args = parse_args("benchmarks", __doc__.splitlines()[0], argv, extra, parallel=False)   # serial timings
    reps = args.repeats or (3 if args.quick else 5)
    if reps < 3:
        raise ValueError(f"--repeats must be >= 3 (medians); got {reps}")
    t_end, dt = (0.05, 1e-3) if args.quick else (0.2, 1e-3)

    # 1. scenes across settings
    cases = []
    for scene in ("block", "screw"):
        for impl, (engine, impl_opts) in IMPLEMENTATIONS.items():
            for factor, value, ov, opts in variations(scene, args.quick):
                if args.quick and impl != "exudyn" and factor not in ("base", "K"):
                    continue                 # quick: other implementations only for the K fit
                params = dict(BASE[scene], t_end=t_end, dt=dt)
                params.update(ov)
                cases.append(dict(scene=scene, implementation=impl, engine=engine, factor=factor, value=value,
                                  params=params, options={**impl_opts, **opts}, repeats=reps))
    results = sweep(bench_case, cases, args)
    base_cost = {(c["scene"], c["implementation"]): r["step_s"] for c, r in zip(cases, results)
                 if c["factor"] == "base"}
    rows = []
    for c, r in zip(cases, results):
        p = make_params(c["scene"], c["params"])
        rows.append([c["scene"], c["implementation"], c["engine"], r["contact_impl"], c["factor"], c["value"], p.model, p.return_map,
                     p.solver, c["options"].get("jacobian", "analytic"), r["K"], p.t_end, r["steps"], r["newton_per_step"],
                     r["step_s"], r["sim_second_s"], r["point_eval_s"], r["wall_step_s"], r["step_min_s"],
                     r["step_s"] / base_cost[(c["scene"], c["implementation"])], reps, r["status"] or "failed"])
    bench_csv = table(os.path.join(args.out, "benchmarks.csv"), BENCH_COLUMNS, rows)

    # 2. the law alone, per point
    kcases = [dict(map=m, state=s, K=K, repeats=max(reps, 5), calls=100 if args.quick else 400) for m in ("seed", "exact", "radial")
              for s in ("slide", "stick") for K in (1, 64)]
    kres = sweep(kernel_case, kcases, args)
    k1 = {(c["map"], c["state"]): r["per_point_s"] for c, r in zip(kcases, kres) if c["K"] == 1}
    for c, r in zip(kcases, kres):
        if not r["all_in_state"]:
            raise RuntimeError(f"kernel case {c}: not every point in state {c['state']}")
    table(os.path.join(args.out, "kernel.csv"), KERNEL_COLUMNS,
          [[c["map"], c["state"], c["K"], r["per_point_s"], r["call_s"], r["per_point_s"] / k1[(c["map"], c["state"])],
            c["repeats"]] for c, r in zip(kcases, kres)])

    # 3. ours / C++ baseline (studies/_lib/baseline.py), interleaved repeats in the same run
    bcases = []
    for impl, (engine, opts) in IMPLEMENTATIONS.items():
        if engine == "exudyn" and (impl == "exudyn" or not args.quick):
            bcases += baseline.ratio_cases(args.quick, reps, opts)
    bres = sweep(baseline.ratio_case, bcases, args)
    table(os.path.join(args.out, "baseline.csv"), BASE_COLUMNS, baseline.table_rows(bres))

    # 4. the speed targets: each scene against a cube on as many C++ springs, the floors, the compiled
    # call (studies/_lib/targets.py), all in interleaved repeats
    tres = target_timing.measure(args.quick, reps)
    table(os.path.join(args.out, "targets.csv"), target_tables.TARGET_COLUMNS,
          target_tables.target_table_rows(tres.rows))
    fres = tres.calls
    table(os.path.join(args.out, "force_call.csv"), target_tables.FORCE_CALL_COLUMNS,
          target_tables.force_call_table_rows(fres))

    # 5. scale with the model: M cubes, one set each or one group, against C++ springs; peak memory
    sres = scale.scale_rows(args.quick, reps)
    table(os.path.join(args.out, "scale.csv"), scale.SCALE_COLUMNS, scale.scale_table_rows(sres))
    mres = scale.memory_rows(args.quick)
    table(os.path.join(args.out, "memory.csv"), scale.MEMORY_COLUMNS, scale.memory_table_rows(mres))

    # 6. a long run: the shaken joint for 1000 cycles against its C++ yardstick and floor (studies/_lib/long_run.py)
    lpath = table(os.path.join(args.out, "long_run.csv"), long_run.LONG_COLUMNS, long_run.measure(args.quick))
    LR = read_table(lpath)
    long_rows = [[LR[c][j] for c in long_run.LONG_COLUMNS] for j in range(len(LR["model [-]"]))]

    # analysis from the CSV files written above
    fits = fits_from_csv(bench_csv)
    B = read_table(os.path.join(args.out, "baseline.csv"))
    ratios = {}
    T = read_table(bench_csv)
    for j in range(len(T["K [-]"])):
        if T["factor [-]"][j] not in ("base", "K"):
            ratios[f"{T['scene [-]'][j]}/{T['implementation [-]'][j]}/{T['factor [-]'][j]}={T['value [-]'][j]}"] = \
                T["relative_to_base [-]"][j]
    impls = list(IMPLEMENTATIONS)
    engine_ratio = {}
    for scene in ("block", "screw"):
        for impl in impls[1:]:
            a = [T["cpu_per_step [s]"][j] for j in range(len(T["K [-]"])) if T["scene [-]"][j] == scene
                 and T["implementation [-]"][j] == impl and T["factor [-]"][j] == "base"]
            b = [T["cpu_per_step [s]"][j] for j in range(len(T["K [-]"])) if T["scene [-]"][j] == scene
                 and T["implementation [-]"][j] == impls[0] and T["factor [-]"][j] == "base"]
            engine_ratio[f"{scene}: {impl}/{impls[0]}"] = a[0] / b[0]
    write_json(os.path.join(args.out, "benchmarks.json"),
               dict(fits=fits, relative_to_base=ratios, implementation_ratios=engine_ratio,
                    baseline=[dict(zip([c.split(" [")[0] for c in BASE_COLUMNS], row))
                              for row in zip(*[B[c] for c in BASE_COLUMNS])],
                    repeats=reps, t_end_s=t_end, dt_s=dt, serial=True))
    png = plot(args.out, fits)

    # printed tables
    print("\ncost per step = a + b K (least squares over the K layouts):")
    for f in fits:
        print(f"  {f['scene']:5s} {f['implementation']:10s} a = {f['a_s'] * 1e3:8.4f} ms, b = {f['b_s_per_point'] * 1e6:8.3f} "
              f"us/point, R^2 = {f['r2']:.4f} (K {f['K_min']}..{f['K_max']}, {f['n']} layouts)"
              + ("  -> cost grows linearly with contact points" if f["b_s_per_point"] > 0 and f["r2"] > 0.9 else ""))
    print("\nsettings (median over repeats):")
    print(f"  {'scene':5s} {'impl':10s} {'contact':8s} {'factor':10s} {'value':18s} {'K':>3s} {'ms/step':>8s} "
          f"{'Newton/step':>11s} {'us/pt-eval':>10s} {'x base':>7s}")
    for row in rows:
        r = dict(zip(BENCH_COLUMNS, row))
        print(f"  {r['scene [-]']:5s} {r['implementation [-]']:10s} {r['contact_impl [-]']:8s} {r['factor [-]']:10s} "
              f"{str(r['value [-]']):18s} {r['K [-]']:3d} {r['cpu_per_step [s]'] * 1e3:8.3f} "
              f"{r['newton_per_step [-]']:11.2f} {r['cpu_per_point_eval [s]'] * 1e6:10.2f} "
              f"{r['relative_to_base [-]']:7.2f} {r['status [-]'] if r['status [-]'] != 'ok' else ''}")
    print("\nlaw cost per point (ContactLaw.evaluate with tangent):")
    K_ = read_table(os.path.join(args.out, "kernel.csv"))
    for j in range(len(K_["K [-]"])):
        print(f"  {K_['return_map [-]'][j]:7s} {K_['state [-]'][j]:6s} K={int(K_['K [-]'][j]):3d} "
              f"{K_['per_point [s]'][j] * 1e6:8.2f} us/point")
    print("\nours / C++ baseline (same scene, solver and step):")
    baseline.print_ratio_table(bres)
    print("\nspeed targets (ours at the package's settings / a cube on as many C++ springs at Exudyn's "
          "defaults):")
    target_tables.print_targets(tres.rows)
    print("\none force call of the full block's contact set (CPU time, median over repeats):")
    for r in fres:
        print(f"  {r['points']:8s} K={r['K']:3d} Python callback {r['callback_us']:7.2f} us, "
              f"entry from Python {r['entry_us']:7.3f} us, native call {r['native_us']:7.3f} us")
    print(f"  native call = {fres[0]['native_fixed_us']:.3f} us + {fres[0]['native_per_point_us']:.4f} us per "
          f"point; entry from Python = {fres[0]['entry_fixed_us']:.3f} us + {fres[0]['entry_per_point_us']:.4f} us "
          "per point (fits per repeat, median)")
    print("\nscale: M cubes, per body and step (ours at the package's settings, springs at Exudyn's defaults):")
    for r in sres:
        print(f"  M={r['bodies']:3d} {r['contact']:8s} {r['per_body_us']:8.2f} us/body/step  x{r['per_body_vs_fewest']:.2f} "
              f"vs fewest  {r['ratio_to_springs']:6.2f} x springs  {r['newton_per_step']:.2f} Newton/step  "
              f"{r['force_calls_per_newton']:.2f} force callbacks/Newton it.")
    print("\npeak memory (fresh process, one group):")
    for r in mres:
        print(f"  {r['bodies']:3d} bodies {r['points']:5d} points {r['steps']:4d} steps history sensor "
              f"{'on ' if r['store_history'] else 'off'}: {r['built_mb']:7.1f} MB after building, {r['peak_mb']:7.1f} MB peak")

    # report
    fit_rows = [[f["scene"], f["implementation"], f["a_s"] * 1e3, f["b_s_per_point"] * 1e6, f["r2"],
                 f"{f['K_min']}..{f['K_max']}"] for f in fits]
    sel = [j for j in range(len(T["K [-]"])) if T["factor [-]"][j] != "K"]
    set_rows = [[T["scene [-]"][j], T["implementation [-]"][j], T["factor [-]"][j], T["value [-]"][j],
                 int(T["K [-]"][j]), T["cpu_per_step [s]"][j] * 1e3, T["cpu_per_sim_second [s/s]"][j],
                 T["newton_per_step [-]"][j], T["cpu_per_point_eval [s]"][j] * 1e6, T["relative_to_base [-]"][j]]
                for j in sel]
    ker_rows = [[K_["return_map [-]"][j], K_["state [-]"][j], int(K_["K [-]"][j]), K_["per_point [s]"][j] * 1e6,
                 K_["per_point_vs_K1 [-]"][j]] for j in range(len(K_["K [-]"]))]
    base_rows = [[B["scene [-]"][j], B["model [-]"][j], B["drive [-]"][j], B["contact_impl [-]"][j], int(B["K [-]"][j]),
                  B["ours_per_step [s]"][j] * 1e3, B["baseline_per_step [s]"][j] * 1e3, B["ours_over_baseline [-]"][j],
                  B["ours_newton_per_step [-]"][j], B["baseline_newton_per_step [-]"][j],
                  B["ours_over_baseline_per_newton [-]"][j]] for j in range(len(B["K [-]"]))]
    body = f"""Timing of both scenes (t_end = {t_end} s, dt = {dt} s, base: block with 4 corner points, screw with
its default 3 x 8 layout; defaults otherwise), medians over {reps} serial repeats. K is the number of
contact points evaluated: Exudyn's reduced screw evaluates one representative point by symmetry
(`BuildScrew(symmetry=True)`, its default), so its K sweep runs with `symmetry=False`. Cost = process CPU time of the solve (model building
excluded; equals wall time on an idle core, robust on a shared machine). Per-point-evaluation
cost = CPU time / (Newton iterations x K): an upper bound that includes solver and body overhead. Files: `benchmarks.csv`, `kernel.csv`,
`baseline.csv`, `benchmarks.json`.

### Cost grows linearly with the number of contact points

Least-squares fit of the CPU time per step over the point layouts, cost = a + b K:

{markdown_table(["scene", "implementation", "a [ms]", "b [us/point]", "R^2", "K"], fit_rows)}
![cost per step vs contact points](./{os.path.basename(png)})

### Settings, one factor varied at a time (ratio to the base setting of the same implementation)

{markdown_table(["scene", "impl.", "factor", "value", "K", "ms/step", "s per sim. s", "Newton/step",
                 "us per point-eval", "x base"], set_rows)}
### The law alone (`ContactLaw.evaluate` with tangent, polar fields)

{markdown_table(["map", "state", "K", "us/point", "per point vs K=1"], ker_rows)}
### Ours / Exudyn C++ spring-dampers at the same points (`studies/baseline.py`)

Same bodies, drives, sensors, solver and step; the baseline replaces the contact by linear
spring-dampers with our per-point stiffnesses (our law in pure stick with isotropic adhesion).
With "C++ load" and the default spring drives (C++ items) the contact is the only Python user function in ours;
the screw's torque load (0.02 N m) keeps it sticking, where our law is the baseline's linear spring.

{markdown_table(["scene", "model", "drive", "contact", "K", "ours ms/step", "C++ ms/step", "ours/C++", "Newton/step ours",
                 "Newton/step C++", "ours/C++ per Newton it."], base_rows)}
### Speed targets

{target_tables.markdown(tres)}
### Scale with the model

{scale.scale_markdown(sres, reps)}
Peak resident memory of a fresh process that builds one group and solves it (`memory.csv`); the
history sensor's data is 9 numbers per point and step:

{markdown_table(["bodies", "points", "steps", "history sensor", "MB after building", "MB peak", "history sensor data MB"],
                [[r["bodies"], r["points"], r["steps"], "on" if r["store_history"] else "off", r["built_mb"],
                  r["peak_mb"], r["history_mb"]] for r in mres])}
### A long run: the shaken joint for {long_rows[0][2]} cycles

The loosening scene's joint (`exu-aniso run loosening --set case=joint --set t_end=T`: the rings model, 48
points, dt 1e-4 s) against the same planar nut on as many C++ springs, shaken by C++ items, at Exudyn's
defaults and at the scene's settings, and the floor (the latter with the contact's items and empty callbacks;
`studies/_lib/long_run.py`). Process CPU time and wall time of the solve alone, medians [min-max] of
{long_rows[0][-1]} interleaved repeats; ours / this repeat by repeat.

{markdown_table(["model", "settings", "steps", "cpu [s]", "min", "max", "wall [s]", "ours / this", "min", "max"],
                [[r[0], r[1], int(r[3]), r[4], r[5], r[6], r[7], r[10], r[11], r[12]] for r in long_rows],
                fmt="{:.3g}")}"""
    finish(args, timer, body, "Benchmarks: cost per step, per point, and against Exudyn's C++ springs")
    return 0


if __name__ == "__main__":
    sys.exit(main())
