"""Peers side by side: our Exudyn models against MuJoCo on two cases.

    python studies/peers.py [--quick] [--repeats N] [--out DIR]

MuJoCo comes with the optional ``bench`` extra (``pip install ".[bench]"`` = mujoco). Without it
(with ``--quick`` or not) the study still runs our side; every MuJoCo row of the tables carries
the status "MuJoCo not installed: pip install '.[bench]'" and no numbers, the report says so, and
the exit code is 0.

1. Orthotropic sliding. A 1 kg box on the plane, friction mu = 0.2 along x and 0.6 along y
   (constant axes), pulled from rest by a constant 10 N at 45 deg from x, gravity 9.81. With the
   associated (maximum-dissipation) law the friction traction lies on the ellipse
   sqrt(T.F T) = |N|, F = diag(1/mu_x^2, 1/mu_y^2), with the slip direction along its normal, so the
   friction force for the sliding direction v is -|N| F^-1 v / sqrt(v.F^-1 v); from rest the box
   slides along the constant heading where pull + friction is parallel to v
   (``orthotropic_heading``, root found with brentq). Ours: ``RunBlock`` (planar model, one contact
   point at the centre, exact return map, trapezoidal rule) at several steps; MuJoCo: the box of
   ``_lib.mujoco_models.BoxOnPlane`` (explicit contact pair, elliptic and pyramidal cones) at its default
   step 0.002 s and smaller ones. Error = heading of the end velocity (t = 1 s) minus the analytic
   heading; also the heading of the displacement over the second half. Wall time per simulated
   second = median over the repeats of the stepping time (ours: SolveDynamic; MuJoCo: mj_step).
   A pull of 4 N along x (above mu_x N) and along y (below mu_y N) checks that the friction pair
   is oriented as intended (MuJoCo's contact frame for a plane is t1 = +y, t2 = -x).
2. Thread. MuJoCo's nut on bolt (SDF plugins, ``_lib.mujoco_models.NutOnBolt``) spun at 1 rev/s by a
   velocity actuator against our screw scene (``RunScrew``, reduced model, rotation drive at
   1 rev/s); advance per revolution (fit of z against the angle over the second half) against
   each model's pitch, and wall time per simulated second (median over the repeats).

Timed cases run one after the other in this process (``--serial`` is implied, ``--processes`` and
``--mpi`` are refused; a process pool would let the engines compete for the cores). Each case first makes one untimed run (trajectory,
warm-up), then ``--repeats`` timed runs; the cheap sliding cases go on until at least 1 s (quick:
0.3 s) of stepping time is measured (at most 200 runs), so a short load spike from other
processes on a shared machine does not set the median. The thread cases of the two engines
alternate.
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

from _lib.studylib import Timer, finish, markdown_table, parse_args, read_table, sweep, table  # noqa: E402

from exu_aniso.scenes.block import orthotropic_heading  # noqa: E402  (re-exported for tests/test_peers.py)
from exu_aniso.scenes.base import summary_float  # noqa: E402

NAME = "peers"

# the sliding case
MASS = 1.0                  # kg
GRAVITY = 9.81              # m/s^2
MU_X, MU_Y = 0.2, 0.6       # friction along x and along y
PULL = 10.0                 # N
PULL_ANGLE = 45.0           # deg from x
SLIDE_T = 1.0               # s simulated
TARGET_DEG = 0.05           # heading error target of ours [deg]
TARGET_SLIDE_RATIO = 2.0    # ours wall / MuJoCo wall per simulated second (at most)
TARGET_THREAD_RATIO = 0.1   # ours wall / MuJoCo wall per simulated second (at most)
SPIN = 2.0 * math.pi        # rad/s, both thread models
MAX_REPEATS = 200           # cap of the timing repeats of the cheap sliding cases
MUJOCO_MISSING = "MuJoCo not installed: pip install '.[bench]'"
MUJOCO_KINDS = ("frame_check", "slide_mujoco", "thread_mujoco")
NAN = float("nan")


def mujoco_problem():
    """None if mujoco imports, else the status of the MuJoCo rows (MUJOCO_MISSING if it is absent)."""
    try:
        import mujoco  # noqa: F401
    except ImportError:
        return MUJOCO_MISSING
    except Exception as exc:       # installed but broken (e.g. its shared library does not load)
        return f"MuJoCo does not import ({type(exc).__name__}: {exc}); reinstall: pip install '.[bench]'"
    return None


def analytic_heading_deg():
    return math.degrees(orthotropic_heading(math.radians(PULL_ANGLE), PULL, MASS * GRAVITY, MU_X, MU_Y))


def _wrap_deg(a):
    return (a + 180.0) % 360.0 - 180.0


# ----------------------------------------------------------------------------------------------
# case functions (module level: run by studylib.sweep)

EPS_T = 1e5                 # N/m, our (isotropic) sticking stiffness of the sliding case


def _ours_block_params(dt, points="center", eps=EPS_T):
    from exu_aniso.scenes.block import BlockParams
    return BlockParams(mass=MASS, normal_load=MASS * GRAVITY, points=points, adhesion="orthotropic", eps_1=eps,
                       eps_2=eps, friction="orthotropic", mu_1=MU_X, mu_2=MU_Y, friction_angle=0.0,
                       return_map="exact", drive="force", drive_angle=PULL_ANGLE, force=PULL, t_end=SLIDE_T, dt=dt,
                       model="planar", solver="trapezoidal")


def _time_runs(run, repeats, min_time=0.0):
    """Call ``run() -> (wall_s, cpu_s)`` at least ``repeats`` times, and on until the wall times add
    up to ``min_time`` [s] (at most MAX_REPEATS runs); returns (median wall, median CPU, runs)."""
    walls, cpus = [], []
    while len(walls) < repeats or (sum(walls) < min_time and len(walls) < MAX_REPEATS):
        w, c = run()
        walls.append(w)
        cpus.append(c)
    return float(np.median(walls)), float(np.median(cpus)), len(walls)


def _solve_ours(build, p):
    """Build one of our models (not timed) and solve it: (wall, CPU) time of the solve [s]."""
    from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
    model = build(p)
    c0 = time.process_time()
    wall = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])[0]
    return wall, time.process_time() - c0


def slide_ours(case):
    """Our block at step dt: heading errors (first run, which is also the warm-up) and median
    solve time per simulated second of the timed runs."""
    from exu_aniso.models.block import BuildBlock, RunBlock
    p = _ours_block_params(case["dt"], case.get("points", "center"), case.get("eps", EPS_T))
    r = RunBlock(p)
    tr = r.trajectory
    j = int(np.argmin(np.abs(tr["t"] - 0.5 * SLIDE_T)))
    path = math.degrees(math.atan2(tr["y"][-1] - tr["y"][j], tr["x"][-1] - tr["x"][j]))
    heading = summary_float(r.summary, "heading_deg")
    wall, cpu, n = _time_runs(lambda: _solve_ours(BuildBlock, p), case["repeats"], case.get("min_time", 0.0))
    ref = analytic_heading_deg()
    return dict(engine="exudyn", setting=f"planar, {p.points}, exact map, trapezoidal", cone="-", dt=p.dt, eps=p.eps_1,
                lift=float("nan"), heading=heading, heading_error=_wrap_deg(heading - ref),
                path_heading_error=_wrap_deg(path - ref), wall_per_sim_s=wall / SLIDE_T, cpu_per_sim_s=cpu / SLIDE_T,
                steps=r.summary["steps"], newton=r.summary["newton_iterations"], airborne=float("nan"), repeats=n,
                status="ok")


def slide_mujoco(case):
    """MuJoCo's box at step dt with the given cone: heading errors, share of steps without contact,
    median stepping time per simulated second."""
    import mujoco
    from _lib import mujoco_models as M
    imp = case.get("impratio")
    model, data, _ = M.BoxOnPlane(MU_X, MU_Y, cone=case["cone"], dt=case["dt"], mass=MASS, impratio=imp)
    diag = M.SlideBox(model, data, PULL, math.radians(PULL_ANGLE), SLIDE_T, count_airborne=True)
    last = {}

    def run():
        mujoco.mj_resetData(model, data)
        last.update(M.SlideBox(model, data, PULL, math.radians(PULL_ANGLE), SLIDE_T))
        return last["wall_s"], last["cpu_s"]

    wall, cpu, n = _time_runs(run, case["repeats"], case.get("min_time", 0.0))
    r = last
    ref = analytic_heading_deg()
    heading = math.degrees(math.atan2(r["vy"], r["vx"]))
    path = math.degrees(math.atan2(r["y"] - r["y_mid"], r["x"] - r["x_mid"]))
    setting = "free box, explicit pair" + ("" if imp is None else f", impratio {imp:g}")
    return dict(engine="mujoco", setting=setting, cone=case["cone"], dt=case["dt"], heading=heading,
                eps=float("nan"), lift=diag["max_lift"],
                heading_error=_wrap_deg(heading - ref), path_heading_error=_wrap_deg(path - ref),
                wall_per_sim_s=wall / SLIDE_T, cpu_per_sim_s=cpu / SLIDE_T, steps=r["steps"], newton=float("nan"),
                airborne=diag["airborne_fraction"], repeats=n, status="ok")


def frame_check(case):
    """MuJoCo's contact frame of the box on the plane, and pulls of 4 N along x and y (elliptic cone):
    along x (mu_x N = 1.96 N < 4 N) the box must slide with a = (4 - mu_x m g) / m, along y
    (mu_y N = 5.89 N > 4 N) it must stick."""
    from _lib import mujoco_models as M
    force, T = 4.0, 0.5
    rows = []
    for direction, angle, mu in (("x", 0.0, MU_X), ("y", 0.5 * math.pi, MU_Y)):
        model, data, frame = M.BoxOnPlane(MU_X, MU_Y, cone="elliptic", dt=0.002, mass=MASS)
        r = M.SlideBox(model, data, force, angle, T)
        v = r["vx"] * math.cos(angle) + r["vy"] * math.sin(angle)
        # mean acceleration over the second half from the positions (s = v_end T/2 - a (T/2)^2 / 2)
        s = (r["x"] - r["x_mid"]) * math.cos(angle) + (r["y"] - r["y_mid"]) * math.sin(angle)
        a = 2.0 * (v * 0.5 * T - s) / (0.5 * T) ** 2
        rows.append(dict(direction=direction, force=force, mu=mu,
                         expected=max(force - mu * MASS * GRAVITY, 0.0) / MASS, measured=a, v_end=v))
    return dict(frame=np.asarray(frame).tolist(), pulls=rows, status="ok")


def _fit_advance(t, angle, z):
    late = t >= 0.5 * t[-1]
    return float(np.polyfit(angle[late], z[late], 1)[0] * 2.0 * math.pi)


def _decimate(n, keep=300):
    return np.unique(np.r_[np.arange(0, n, max(1, n // keep)), n - 1])


def thread_ours(case):
    """Our screw (reduced model, rotation drive at 1 rev/s): advance per revolution, median wall
    time of the solve per simulated second, trajectory of the first run."""
    from exu_aniso.models.screw import BuildScrew, RunScrew
    from exu_aniso.scenes.screw import ScrewParams, pitch
    p = ScrewParams(t_end=case["t_end"], rotation_speed=SPIN, drive="rotation", model="reduced", **case["params"])
    r = RunScrew(p, contactOutputs=False)        # trajectory and warm-up, not timed
    tr = r.trajectory
    adv = _fit_advance(tr["t"], tr["angle"], tr["z"])
    k = _decimate(len(tr["t"]))
    traj = dict(t=tr["t"][k].tolist(), angle=tr["angle"][k].tolist(), advance=(tr["z"][k] - tr["z"][0]).tolist())
    wall, cpu, n = _time_runs(lambda: _solve_ours(BuildScrew, p), case["repeats"])
    K = p.rings * p.points_per_ring
    return dict(engine="exudyn", setting=case["label"] + f" ({K} points, dt {p.dt:g} s, {p.return_map} map)",
                label=case["label"], dt=p.dt, pitch=pitch(p), advance_per_rev=adv,
                wall_per_sim_s=wall / p.t_end, cpu_per_sim_s=cpu / p.t_end, steps=r.summary["steps"], repeats=n,
                traj=traj, status="ok")


def thread_mujoco(case):
    """MuJoCo's nut on bolt spun at -1 rev/s (screwing down): advance per revolution, median
    stepping time per simulated second, trajectory of the first run."""
    import mujoco
    from _lib import mujoco_models as M
    model, data = M.NutOnBolt(**case["params"])
    r = M.SpinNut(model, data, -SPIN, case["t_end"])
    adv = _fit_advance(r["t"], r["angle"], r["z"])
    k = _decimate(len(r["t"]))
    traj = dict(t=r["t"][k].tolist(), angle=r["angle"][k].tolist(), advance=(r["z"][k] - r["z"][0]).tolist())
    def run():
        mujoco.mj_resetData(model, data)
        q = M.SpinNut(model, data, -SPIN, case["t_end"], record=False)
        return q["wall_s"], q["cpu_s"]

    wall, cpu, n = _time_runs(run, case["repeats"])
    o = model.opt
    return dict(engine="mujoco", setting=case["label"] + f" (sdf {o.sdf_iterations}/{o.sdf_initpoints}, "
                f"dt {o.timestep:g} s)", label=case["label"], dt=float(o.timestep), pitch=M.BOLT_PITCH,
                advance_per_rev=adv, wall_per_sim_s=wall / case["t_end"], cpu_per_sim_s=cpu / case["t_end"],
                steps=r["steps"], repeats=n, traj=traj, xy_drift=r["xy_drift"], status="ok")


CASE_FUNCTIONS = {"slide_ours": slide_ours, "slide_mujoco": slide_mujoco, "frame_check": frame_check,
                  "thread_ours": thread_ours, "thread_mujoco": thread_mujoco}


def run_case(case):
    return CASE_FUNCTIONS[case["kind"]](case)


def not_run(case, status):
    """The row of a MuJoCo case that could not run (mujoco missing): its settings, no numbers."""
    if case["kind"] == "frame_check":
        pulls = [dict(direction=d, force=4.0, mu=mu, expected=max(4.0 - mu * MASS * GRAVITY, 0.0) / MASS, measured=NAN,
                      v_end=NAN) for d, mu in (("x", MU_X), ("y", MU_Y))]
        return dict(frame=[[NAN] * 3] * 3, pulls=pulls, status=status)
    if case["kind"] == "slide_mujoco":
        imp = case.get("impratio")
        return dict(engine="mujoco", setting="free box, explicit pair" + ("" if imp is None else f", impratio {imp:g}"),
                    cone=case["cone"], dt=case["dt"], heading=NAN, eps=NAN, lift=NAN, heading_error=NAN,
                    path_heading_error=NAN, wall_per_sim_s=NAN, cpu_per_sim_s=NAN, steps=NAN, newton=NAN, airborne=NAN,
                    repeats=0, status=status)
    return dict(engine="mujoco", setting=case["label"], label=case["label"], dt=case["params"].get("dt", NAN), pitch=NAN,
                advance_per_rev=NAN, wall_per_sim_s=NAN, cpu_per_sim_s=NAN, steps=NAN, repeats=0,
                traj=dict(t=[], angle=[], advance=[]), status=status)


def cases(quick, repeats):
    if quick:
        ours_dt, mj_dt, T = [0.1, 0.05], [0.002], 0.3
        ours_thread = [("default", {})]
        mj_thread = [("example", {})]
    else:
        ours_dt, mj_dt, T = [0.5, 0.25, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001], [0.002, 0.001, 5e-4, 2e-4, 1e-4], 2.0
        ours_thread = [("default", {}), ("cheap", dict(rings=1, points_per_ring=4, dt=5e-3)),
                       ("stiff thread", dict(eps_2=1e8, mu_2=5.0, dt=2e-3))]
        mj_thread = [("example", {}), ("coarse SDF", dict(sdf_iterations=5, sdf_initpoints=20)),
                     ("coarse SDF, large step", dict(sdf_iterations=5, sdf_initpoints=20, dt=0.005))]
    out = [dict(kind="frame_check")]
    mt = 0.3 if quick else 1.0      # cheap sliding cases: repeat until this much time is measured [s]
    out += [dict(kind="slide_ours", dt=dt, repeats=repeats, min_time=mt) for dt in ours_dt]
    if not quick:
        out.append(dict(kind="slide_ours", dt=0.05, points="corners", repeats=repeats, min_time=mt))
        out += [dict(kind="slide_ours", dt=0.001, eps=e, repeats=repeats, min_time=mt) for e in (1e4, 1e6)]
    out += [dict(kind="slide_mujoco", cone=c, dt=dt, repeats=repeats, min_time=mt) for c in ("elliptic", "pyramidal")
            for dt in mj_dt]
    if not quick:
        out.append(dict(kind="slide_mujoco", cone="elliptic", dt=0.002, impratio=10.0, repeats=repeats, min_time=mt))
    for (lo, po), (lm, pm) in zip(ours_thread, mj_thread):   # alternate the engines
        out.append(dict(kind="thread_ours", label=lo, params=po, t_end=T, repeats=repeats))
        out.append(dict(kind="thread_mujoco", label=lm, params=pm, t_end=T, repeats=repeats))
    return out


# ----------------------------------------------------------------------------------------------
# tables, figures, report

SLIDE_COLS = ["engine [-]", "setting [-]", "cone [-]", "dt [s]", "adhesion_stiffness [N/m]", "heading [deg]",
              "heading_error [deg]", "path_heading_error [deg]", "wall_per_sim_s [s/s]", "cpu_per_sim_s [s/s]",
              "steps [-]", "newton_iterations [-]", "airborne_fraction [-]", "max_lift [m]", "repeats [-]",
              "status [-]"]
THREAD_COLS = ["engine [-]", "setting [-]", "dt [s]", "pitch [m]", "advance_per_rev [m]", "advance_ratio [-]",
               "wall_per_sim_s [s/s]", "cpu_per_sim_s [s/s]", "steps [-]", "repeats [-]", "status [-]"]
TRAJ_COLS = ["engine [-]", "setting [-]", "t [s]", "angle [rad]", "advance [m]", "advance [pitch]",
             "revolutions [-]"]
RATIO_COLS = ["case [-]", "ours [-]", "mujoco [-]", "ours_error [-]", "mujoco_error [-]", "ours_wall_per_sim_s [s/s]",
              "mujoco_wall_per_sim_s [s/s]", "ratio [-]", "cpu_ratio [-]", "target_ratio [-]", "met [-]"]


def _count(v):
    return v if v != v else int(v)          # NaN (a case that did not run) stays NaN


def write_tables(out, results):
    frame = next(r for r in results if "frame" in r)
    table(os.path.join(out, "tangent_frame.csv"), ["row [-]", "x [-]", "y [-]", "z [-]", "status [-]"],
          [[name, *map(float, v), frame["status"]] for name, v in zip(("normal", "t1", "t2"), frame["frame"])])
    table(os.path.join(out, "frame_check.csv"),
          ["pull_direction [-]", "force [N]", "mu_along_pull [-]", "expected_acceleration [m/s^2]",
           "measured_acceleration [m/s^2]", "end_speed [m/s]", "status [-]"],
          [[p["direction"], p["force"], p["mu"], p["expected"], p["measured"], p["v_end"], frame["status"]]
           for p in frame["pulls"]])
    slide = [r for r in results if "heading" in r]
    table(os.path.join(out, "slide.csv"), SLIDE_COLS,
          [[r["engine"], r["setting"], r["cone"], float(r["dt"]), float(r["eps"]), r["heading"], r["heading_error"],
            r["path_heading_error"], r["wall_per_sim_s"], r["cpu_per_sim_s"], _count(r["steps"]), r["newton"],
            r["airborne"], r["lift"], r["repeats"], r["status"]] for r in slide])
    thread = [r for r in results if "advance_per_rev" in r]
    table(os.path.join(out, "thread.csv"), THREAD_COLS,
          [[r["engine"], r["setting"], float(r["dt"]), float(r["pitch"]), r["advance_per_rev"],
            r["advance_per_rev"] / r["pitch"], r["wall_per_sim_s"], r["cpu_per_sim_s"], _count(r["steps"]),
            r["repeats"], r["status"]] for r in thread])
    rows = []
    for r in thread:
        tr = r["traj"]
        for t, a, z in zip(tr["t"], tr["angle"], tr["advance"]):
            rows.append([r["engine"], r["label"], float(t), float(a), float(z), float(z) / r["pitch"],
                         float(a) / (2.0 * math.pi)])
    table(os.path.join(out, "thread_trajectory.csv"), TRAJ_COLS, rows)


def ratio_rows(out):
    """Ratio table from slide.csv and thread.csv: ours / MuJoCo wall time per simulated second."""
    S = read_table(os.path.join(out, "slide.csv"))
    n = len(S["engine [-]"])
    rows = []
    ours = [i for i in range(n) if S["engine [-]"][i] == "exudyn" and "center" in S["setting [-]"][i]
            and S["adhesion_stiffness [N/m]"][i] == EPS_T]
    mj = [i for i in range(n) if S["engine [-]"][i] == "mujoco" and S["cone [-]"][i] == "elliptic"
          and S["dt [s]"][i] == 0.002 and "impratio" not in S["setting [-]"][i]]
    ok = [i for i in ours if abs(S["heading_error [deg]"][i]) < TARGET_DEG]
    pick = max(ok, key=lambda i: S["dt [s]"][i]) if ok else min(ours, key=lambda i: abs(S["heading_error [deg]"][i]))
    if mj:
        j = mj[0]
        ratio = S["wall_per_sim_s [s/s]"][pick] / S["wall_per_sim_s [s/s]"][j]
        met = abs(S["heading_error [deg]"][pick]) < TARGET_DEG and ratio <= TARGET_SLIDE_RATIO
        ran = S["status [-]"][j] == "ok"
        rows.append(["sliding (heading)", f"dt {S['dt [s]'][pick]:g} s (largest step with error < {TARGET_DEG:g} deg)",
                     f"elliptic, default dt {S['dt [s]'][j]:g} s",
                     f"{S['heading_error [deg]'][pick]:.3g} deg", f"{S['heading_error [deg]'][j]:.3g} deg" if ran else "-",
                     S["wall_per_sim_s [s/s]"][pick], S["wall_per_sim_s [s/s]"][j], ratio,
                     S["cpu_per_sim_s [s/s]"][pick] / S["cpu_per_sim_s [s/s]"][j], TARGET_SLIDE_RATIO,
                     ("yes" if met else "no") if ran else S["status [-]"][j]])
    T = read_table(os.path.join(out, "thread.csv"))
    m = len(T["engine [-]"])
    o = [i for i in range(m) if T["engine [-]"][i] == "exudyn"]
    u = [i for i in range(m) if T["engine [-]"][i] == "mujoco"]
    pairs = [(i, u[0]) for i in o]                           # each of ours against MuJoCo's example settings
    if len(o) > 1 and len(u) > 1:                            # cheapest against cheapest
        pairs.append((min(o, key=lambda i: T["wall_per_sim_s [s/s]"][i]),
                      min(u, key=lambda i: T["wall_per_sim_s [s/s]"][i])))
    for i, j in pairs:
        ratio = T["wall_per_sim_s [s/s]"][i] / T["wall_per_sim_s [s/s]"][j]
        ran = T["status [-]"][j] == "ok"
        rows.append(["thread (advance/rev)", T["setting [-]"][i], T["setting [-]"][j],
                     f"{T['advance_ratio [-]'][i] - 1.0:+.2%} of pitch",
                     f"{T['advance_ratio [-]'][j] - 1.0:+.2%} of pitch" if ran else "-",
                     T["wall_per_sim_s [s/s]"][i], T["wall_per_sim_s [s/s]"][j], ratio,
                     T["cpu_per_sim_s [s/s]"][i] / T["cpu_per_sim_s [s/s]"][j], TARGET_THREAD_RATIO,
                     ("yes" if ratio <= TARGET_THREAD_RATIO else "no") if ran else T["status [-]"][j]])
    table(os.path.join(out, "ratio.csv"), RATIO_COLS, rows)
    return rows


def plot(out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    S = read_table(os.path.join(out, "slide.csv"))
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    groups = {}
    for i, eng in enumerate(S["engine [-]"]):
        if S["status [-]"][i] != "ok":                  # not run (MuJoCo missing): nothing to draw
            continue
        if eng == "exudyn" and S["adhesion_stiffness [N/m]"][i] != EPS_T:
            key = "ours, other adhesion stiffness"
        elif eng == "exudyn" and "corners" in S["setting [-]"][i]:
            key = "ours, 4 corner points"
        elif eng == "exudyn":
            key = "ours (Exudyn), centre point, exact map"
        elif "impratio" in S["setting [-]"][i]:
            key = "MuJoCo elliptic, impratio 10"
        else:
            key = f"MuJoCo {S['cone [-]'][i]}"
        groups.setdefault(key, []).append(i)
    markers = {"ours (Exudyn), centre point, exact map": "o-", "ours, 4 corner points": "s",
               "ours, other adhesion stiffness": "x",
               "MuJoCo elliptic": "^-", "MuJoCo pyramidal": "v-", "MuJoCo elliptic, impratio 10": "D"}
    for key, idx in groups.items():
        idx = sorted(idx, key=lambda i: S["wall_per_sim_s [s/s]"][i])
        x = [S["wall_per_sim_s [s/s]"][i] for i in idx]
        y = [max(abs(S["heading_error [deg]"][i]), 1e-6) for i in idx]
        ax.loglog(x, y, markers.get(key, "x-"), label=key)
        for i, xi, yi in zip(idx, x, y):
            lab = f"{S['dt [s]'][i]:g}"
            if key == "ours, other adhesion stiffness":
                lab += f", eps {S['adhesion_stiffness [N/m]'][i]:g} N/m"
            ax.annotate(lab, (xi, yi), textcoords="offset points", xytext=(4, 3), fontsize=7)
    ax.axhline(TARGET_DEG, color="grey", ls="--", lw=0.8, label=f"target {TARGET_DEG:g} deg")
    ax.set_xlabel("wall time per simulated second [s/s]")
    ax.set_ylabel("|heading error| at t = 1 s [deg]")
    missing = sorted({st for st in S["status [-]"] if st != "ok"})
    ax.set_title(f"orthotropic sliding (mu {MU_X:g} / {MU_Y:g}, pull {PULL_ANGLE:g} deg); labels: dt [s]; "
                 f"ours: adhesion {EPS_T:g} N/m unless labelled" + "".join(f"\n{m}" for m in missing), fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "slide_work_precision.png"), dpi=120)
    plt.close(fig)

    D = read_table(os.path.join(out, "thread_trajectory.csv"))
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    series = {}
    for i, (e, s) in enumerate(zip(D["engine [-]"], D["setting [-]"])):
        series.setdefault((e, s), []).append(i)
    for (e, s), idx in series.items():
        t = np.array([D["t [s]"][i] for i in idx])
        adv = np.array([D["advance [pitch]"][i] for i in idx])
        rev = np.array([D["revolutions [-]"][i] for i in idx])
        name = ("ours" if e == "exudyn" else "MuJoCo") + f" {s}"
        line, = ax.plot(t, adv, label=f"{name}: advance / pitch")
        ax.plot(t, rev - rev[0], ls=":", color=line.get_color(), label=f"{name}: revolutions turned")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("axial advance [pitches]  /  rotation [rev]")
    ax.set_title("thread: advance vs time (ours: +1 rev/s; MuJoCo nut: -1 rev/s, screwing down)", fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "thread_advance.png"), dpi=120)
    plt.close(fig)


def report(out, mujoco_version=None):
    """report.md body from the CSV files; mujoco_version None: MuJoCo did not run (its rows carry
    their status and no numbers)."""
    S = read_table(os.path.join(out, "slide.csv"))
    F = read_table(os.path.join(out, "frame_check.csv"))
    TF = read_table(os.path.join(out, "tangent_frame.csv"))
    T = read_table(os.path.join(out, "thread.csv"))
    R = read_table(os.path.join(out, "ratio.csv"))
    ref = analytic_heading_deg()
    ran = mujoco_version is not None
    missing = sorted({st for st in S["status [-]"] + T["status [-]"] if st != "ok"})

    def rows(tab, cols):
        n = len(tab[cols[0]])
        return [[tab[c][i] for c in cols] for i in range(n)]

    def cols(tab):            # the status column only where some row did not run
        return [c for c in tab if c != "status [-]" or any(v != "ok" for v in tab[c])]

    n = len(S["engine [-]"])
    mj = [i for i in range(n) if S["engine [-]"][i] == "mujoco" and S["status [-]"][i] == "ok"]
    air = [S["airborne_fraction [-]"][i] for i in mj]
    lift = [S["max_lift [m]"][i] for i in mj]
    ell = [abs(S["heading_error [deg]"][i]) for i in mj if S["cone [-]"][i] == "elliptic"]
    pyr = [S["heading_error [deg]"][i] for i in mj if S["cone [-]"][i] == "pyramidal"]
    ours = [i for i in range(n) if S["engine [-]"][i] == "exudyn" and "center" in S["setting [-]"][i]
            and S["adhesion_stiffness [N/m]"][i] == EPS_T]
    band = [i for i in ours if 0.02 <= S["dt [s]"][i] <= 0.25]
    order = (np.polyfit(np.log([S["dt [s]"][i] for i in band]),
                        np.log([abs(S["heading_error [deg]"][i]) for i in band]), 1)[0] if len(band) >= 2 else float("nan"))
    small = min(ours, key=lambda i: S["dt [s]"][i])
    eps_rows = [i for i in range(n) if S["engine [-]"][i] == "exudyn" and S["dt [s]"][i] == S["dt [s]"][small]
                and "center" in S["setting [-]"][i]]
    eps_text = ", ".join(f"{abs(S['heading_error [deg]'][i]):.2g} deg at {S['adhesion_stiffness [N/m]'][i]:g} N/m"
                         for i in sorted(eps_rows, key=lambda i: S["adhesion_stiffness [N/m]"][i]))
    thr = [i for i in range(len(T["engine [-]"])) if T["engine [-]"][i] == "exudyn"]
    mjt = [i for i in range(len(T["engine [-]"])) if T["engine [-]"][i] == "mujoco" and T["status [-]"][i] == "ok"]
    met = R["met [-]"]
    t1 = [TF[c][1] for c in ("x [-]", "y [-]", "z [-]")]
    t2 = [TF[c][2] for c in ("x [-]", "y [-]", "z [-]")]
    if ran:
        intro = f"MuJoCo {mujoco_version} against our Exudyn models, same run, same machine;"
        frame = f"""MuJoCo's tangent frame of the plane-box contact, read from `data.contact.frame`: t1 = {t1}, t2 = {t2}.
It follows from the normal alone (rotating the plane about its normal does not change it), so
`friction="f1 f2"` puts f1 along y: `BoxOnPlane` writes the pair as `friction="{MU_Y:g} {MU_X:g} ..."`. Check with
a 4 N pull (elliptic cone, 0.5 s; acceleration over the second half):"""
    else:
        intro = (f"**{'; '.join(missing)}.** This run measured our side only: every MuJoCo row below carries that "
                 "status and no numbers, and the ratio table has no ratios. Our Exudyn models:")
        frame = ("MuJoCo's tangent frame of the plane-box contact and the check with a 4 N pull (elliptic cone, "
                 "0.5 s) need MuJoCo; expected accelerations only:")
    hops = (f"""`airborne_fraction` is the share of MuJoCo steps with no active contact and `max_lift` the largest
height of the box above its resting height: the sliding box hops, without contact in
{min(air):.0%} to {max(air):.0%} of the steps, with a largest lift between {min(lift) * 1e3:.2g} and {max(lift) * 1e3:.2g} mm, in
every MuJoCo case of the table. The pull then acts without friction and the
heading leans towards the pull: MuJoCo's elliptic-cone error stays between {min(ell):.2g} and {max(ell):.2g} deg
and does not shrink with the step; the pyramidal cone's error lies between {min(pyr):+.2g} and {max(pyr):+.2g} deg.
""" if ran and ell and pyr else "")
    nut = (f"""MuJoCo's nut follows its rigid thread to {max(abs(T["advance_ratio [-]"][i] - 1) for i in mjt):.2%} of the
pitch in every setting. """ if mjt else "")
    body = f"""{intro} timed cases run one
after the other, each after one untimed warm-up run (median of the timed runs, `repeats` column;
MuJoCo: `mj_step` only, ours: `SolveDynamic` only; model building is not timed in either).
`cpu_per_sim_s` is the CPU time of the same runs (`time.process_time`); on a shared machine under
load it is the steadier of the two (`cpu_ratio` in the ratio table); the targets are judged on wall
time.

### 1. Orthotropic sliding

1 kg box, mu = {MU_X:g} along x and {MU_Y:g} along y, pull {PULL:g} N at {PULL_ANGLE:g} deg from x, g = {GRAVITY:g} m/s^2,
from rest for {SLIDE_T:g} s. Analytic heading (associated law, `orthotropic_heading`, brentq): **{ref:.6f} deg**.
Error = heading of the end velocity minus that; `path_heading_error` = heading of the displacement over
the second half.

{frame}

{markdown_table(cols(F), rows(F, cols(F)))}
{markdown_table(cols(S), rows(S, cols(S)))}
![heading error vs wall time per simulated second](./slide_work_precision.png)

{hops}Ours is the trapezoidal rule on the planar model: once sliding it integrates the constant
acceleration exactly, the error comes from the stick-slip onset and falls with the step at the
observed order {order:.2f} (fit over 0.02 s <= dt <= 0.25 s). At small steps a floor remains: the
elastic stick phase of the penalty adhesion, which the rigid analytic answer does not have; it
shrinks with the adhesion stiffness ({eps_text}, dt {S["dt [s]"][small]:g} s).

### 2. Thread

MuJoCo: nut and bolt of `model/plugin/sdf/nutbolt.xml` (SDF plugins shipped in the wheel, pitch
1/12 m, radius 0.26 m), free joint, spun at 1 rev/s by a velocity actuator (screwing down).
Ours: `RunScrew` reduced model (rotation + axial), torsional spring to a driver at 1 rev/s.

{markdown_table(cols(T), rows(T, cols(T)))}
![advance vs time](./thread_advance.png)

Advance per revolution: {nut + "Ours" if nut else "ours"} tends to the pitch only as the thread gets stiff across the helix
(ratio r = eps_1/eps_2 -> 0 with a high cross-thread friction; "stiff thread" row); with the
default r = 0.01 the slip along the helix makes it {min(T["advance_ratio [-]"][i] for i in thr) - 1:+.2%} of the pitch: the
physics of the spiral net, not a discretisation error (settings with r = 0.01 in the table:
{", ".join(f"{T['advance_ratio [-]'][i] - 1:+.2%} at dt {T['dt [s]'][i]:g} s" for i in thr if "stiff" not in T["setting [-]"][i])}).

### Ratio table (ours / MuJoCo wall time per simulated second)

Targets: sliding, ours < {TARGET_DEG:g} deg at <= {TARGET_SLIDE_RATIO:g}x MuJoCo's time at its default step; thread, ours
<= {TARGET_THREAD_RATIO:g}x MuJoCo's time. Met in {sum(m == "yes" for m in met)} of {len(met)} rows{"" if ran else " (MuJoCo did not run)"}.

{markdown_table(list(R), rows(R, list(R)))}
"""
    return body


def main(argv=None):
    args = parse_args(NAME, __doc__.splitlines()[0], argv,
                      extra=lambda ap: ap.add_argument("--repeats", type=int, default=None,
                                                       help="timing repeats per case (default 5; --quick: 2)"),
                      parallel=False)     # timed cases: no process pool (see the module doc)
    timer = Timer()
    repeats = args.repeats or (2 if args.quick else 5)
    if repeats < 1:
        raise SystemExit(f"{NAME}: --repeats must be >= 1; got {repeats}")
    problem = mujoco_problem()
    todo = cases(args.quick, repeats)
    if problem:
        print(f"{NAME}: {problem}; running our side only (the MuJoCo rows carry this status)", file=sys.stderr,
              flush=True)
    run = [c for c in todo if not (problem and c["kind"] in MUJOCO_KINDS)]
    done = iter(sweep(run_case, run, args))
    results = [not_run(c, problem) if problem and c["kind"] in MUJOCO_KINDS else next(done) for c in todo]
    write_tables(args.out, results)
    ratio_rows(args.out)
    plot(args.out)
    version = None
    if not problem:
        import mujoco
        version = mujoco.__version__
    finish(args, timer, report(args.out, version), "Peers: MuJoCo side by side")
    return 0


if __name__ == "__main__":
    sys.exit(main())
