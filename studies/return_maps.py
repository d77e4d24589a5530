"""Return-map comparison (seed, exact, radial): step refinement on the block and the screw scene,
the stick/slip jump at Phi = 0+, dissipation per step, Newton cost and step reductions, and a
recommendation for the default map.

Writes ``refinement.csv`` (one row per scene x map x dt), ``jump.csv`` (trial-direction sweep of the
single-point law), ``refinement.png``, ``jump.png`` and ``report.md``.
Usage: python studies/return_maps.py [--quick] [--serial] [--out DIR]
"""
from __future__ import annotations

import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)
from _lib import studylib as sl  # noqa: E402

NAME = "return_maps"
MAPS = ("seed", "exact", "radial")
DTS_FULL = (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4)
DTS_QUICK = (2e-3, 1e-3, 5e-4)
# block: the near-circle scene of studies/block_paths.py (ratio 100 = package default adhesion,
# displacement drive along +y from (0.5, 0)), first second: sticking, the stick->slip transition and
# sliding along the rail
BLOCK = dict(x0=0.5, y0=0.0, adhesion="polar", friction="polar", eps_1=1e5, eps_2=1e3, mu_1=0.3, mu_2=0.3,
             drive="displacement", drive_angle=90.0, drive_speed=0.1, drive_stiffness=1e3, t_end=1.0,
             model="planar", solver="trapezoidal")
# screw: package default scene (spiral net, helix 10 deg, rotating driver through a torsional spring),
# reduced model, half a second (half a revolution of the driver), but a 1 kg screw: the drive-spring
# oscillation omega = sqrt(k / J) is then 283 rad/s, resolved by the steps <= 1e-3 s; with the default
# 0.01 kg (2830 rad/s) no step of the ladder resolves it and the error does not decrease (measured)
SCREW = dict(t_end=0.5, mass=1.0, model="reduced", solver="trapezoidal")
N_TAIL_RATES = 2              # "converges": the rates of the finest step sizes (last two, quick: one) > 0.8
# single-point law for the jump sweep: per-point values, |N| = 1 N
JUMP_SETTINGS = {
    # name: (C = -B as (c11, c12, c22) [N/m], (mu_1, mu_2)); axes 1 = x, 2 = y
    "C ratio 100, F isotropic": ((100.0, 0.0, 1.0), (0.3, 0.3)),
    "C isotropic, F mu 0.2/0.6": ((1.0, 0.0, 1.0), (0.2, 0.6)),
}
JUMP_DELTA = 1e-9             # trial traction = (1 + delta) x the point of the friction ellipse
N_DIRECTIONS = 181            # trial directions 0 ... 180 deg, 1 deg apart
DISS_TOL = 1e-12              # per-step, per-point dissipation counted negative below -DISS_TOL x total


def run_refinement(case):
    """One Exudyn run of the block or the screw with map and dt; final state, dissipation checks, cost."""
    from exu_aniso.engines.exudyn_adapter.runner import HistoryOutputs
    rm, dt = case["return_map"], case["dt"]
    if case["scene"] == "block":
        from exu_aniso.models.block import BlockTrajectory, BuildBlock
        from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
        from exu_aniso.scenes.block import BlockParams
        p = BlockParams(**{**BLOCK, "return_map": rm, "dt": dt})
        model = BuildBlock(p)
        wall, steps, iters, info = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
        tr = BlockTrajectory(model)
        final = (float(tr["x"][-1]), float(tr["y"][-1]))
    else:
        from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
        from exu_aniso.models.screw import BuildScrew, ScrewTrajectory
        from exu_aniso.scenes.screw import ScrewParams
        p = ScrewParams(**{**SCREW, "return_map": rm, "dt": dt})
        model = BuildScrew(p)
        wall, steps, iters, info = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
        tr = ScrewTrajectory(model, contactOutputs=False)
        final = (float(tr["z"][-1]), float(tr["angle"][-1]))
    _, _, H = HistoryOutputs(model["mbs"], model["contact"])
    from exu_aniso.law.history import HISTORY_FIELDS
    Dp = H[:, :, HISTORY_FIELDS.index("dissipated_energy")]        # (steps + 1, K) accumulated per point
    inc = np.diff(Dp, axis=0)
    total = float(Dp[-1].sum())
    return dict(final=final, total=total, min_inc=float(inc.min()), neg=int(np.sum(inc < -DISS_TOL * max(total, 1e-300))),
                steps=int(steps), iters=int(iters), wall=float(wall),
                reductions=int(info["accepted_steps"] - info["nominal_steps"]))


def jump_rows():
    """Trial-direction sweep of return_map_point just outside the friction ellipse (Phi = 0+)."""
    from exu_aniso.law.return_maps import SLIP, return_map_point
    rows = []
    for name, (c, (m1, m2)) in JUMP_SETTINGS.items():
        B = tuple(-v for v in c)
        F = (1.0 / m1 ** 2, 0.0, 1.0 / m2 ** 2)
        for th in np.linspace(0.0, 180.0, N_DIRECTIONS):
            u = np.array([math.cos(math.radians(th)), math.sin(math.radians(th))])
            Tb = u / math.sqrt(F[0] * u[0] ** 2 + 2 * F[1] * u[0] * u[1] + F[2] * u[1] ** 2)   # |N| = 1
            Ttr = (1.0 + JUMP_DELTA) * Tb
            for rm in MAPS:
                r = return_map_point(Ttr, 1.0, B, F, method=rm, tangent=False)
                assert r.state == SLIP
                jump = float(np.linalg.norm(r.T - Ttr) / np.linalg.norm(Ttr))
                ang = math.degrees(math.atan2(r.T[1], r.T[0]))
                rows.append([name, rm, float(th), jump, ang, float(r.dissipation)])
    return rows


REF_COLUMNS = ["scene [-]", "return_map [-]", "dt [s]", "final_1 [m]", "final_2 [m|rad]", "error [m]", "rate [-]",
               "dissipated [J]", "min_step_dissipation [J]", "negative_steps [-]", "newton_per_step [-]",
               "steps [-]", "step_reductions [-]", "wall [s]"]
# final_1, final_2: block x_end, y_end [m]; screw z_end [m], angle_end [rad]
QUANTITY = {"block": "final centre position (x, y) [m]", "screw": "final axial position z [m]"}


def compute(args):
    dts = DTS_QUICK if args.quick else DTS_FULL
    cases = [dict(scene=s, return_map=rm, dt=dt) for s in ("block", "screw") for rm in MAPS for dt in dts]
    res = sl.sweep(run_refinement, cases, args)
    rows = []
    for s in ("block", "screw"):
        for rm in MAPS:
            sel = [(c, r) for c, r in zip(cases, res) if c["scene"] == s and c["return_map"] == rm]
            fine = np.array(sel[-1][1]["final"])
            # block: position error norm [m]; screw: axial position error [m]
            err = [float(np.linalg.norm(np.array(r["final"]) - fine)) if s == "block"
                   else abs(r["final"][0] - fine[0]) for _, r in sel]
            for k, (c, r) in enumerate(sel):
                rate = (math.log2(err[k - 1] / err[k]) if 0 < k < len(sel) - 1 and err[k] > 0 and err[k - 1] > 0
                        else float("nan"))
                rows.append([s, rm, c["dt"], r["final"][0], r["final"][1], err[k] if k < len(sel) - 1 else float("nan"),
                             rate, r["total"], r["min_inc"], r["neg"], r["iters"] / r["steps"], r["steps"],
                             r["reductions"], r["wall"]])
    sl.table(os.path.join(args.out, "refinement.csv"), REF_COLUMNS, rows)
    sl.table(os.path.join(args.out, "jump.csv"), ["setting [-]", "return_map [-]", "trial_angle [deg]", "jump [-]",
                                                    "returned_angle [deg]", "dissipation [J]"], jump_rows())


# ----------------------------------------------------------------------------------------------

def _idx(tab, **match):
    n = len(next(iter(tab.values())))
    return [i for i in range(n) if all(tab[k][i] == v for k, v in match.items())]


def plot(args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    R = sl.read_table(os.path.join(args.out, "refinement.csv"))
    J = sl.read_table(os.path.join(args.out, "jump.csv"))
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, s in zip(axes, ("block", "screw")):
        for rm, mk in zip(MAPS, "os^"):
            i = [k for k in _idx(R, **{"scene [-]": s, "return_map [-]": rm}) if R["error [m]"][k] == R["error [m]"][k]]
            ax.loglog([R["dt [s]"][k] for k in i], [max(R["error [m]"][k], 1e-16) for k in i], mk + "-", label=rm)
        dt = np.array(sorted(set(R["dt [s]"])))
        e0 = [R["error [m]"][k] for k in _idx(R, **{"scene [-]": s}) if R["error [m]"][k] == R["error [m]"][k]]
        if e0:
            ref = max(e0)
            ax.loglog(dt, ref * (dt / dt.max()), "k:", lw=0.8, label="slope 1")
            ax.loglog(dt, ref * (dt / dt.max()) ** 2, "k--", lw=0.8, label="slope 2")
        ax.set_xlabel("dt [s]")
        ax.set_ylabel(f"error of the {QUANTITY[s]} vs finest dt")
        ax.set_title(f"{s}: step refinement")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "refinement.png"), dpi=110)
    plt.close(fig)

    settings = list(dict.fromkeys(J["setting [-]"]))
    fig, axes = plt.subplots(1, len(settings), figsize=(5 * len(settings), 4), squeeze=False)
    for ax, st in zip(axes[0], settings):
        for rm, mk in zip(MAPS, "-:-"):
            i = _idx(J, **{"setting [-]": st, "return_map [-]": rm})
            ax.semilogy([J["trial_angle [deg]"][k] for k in i], [max(J["jump [-]"][k], 1e-17) for k in i], mk,
                        label=rm, lw=2 if rm == "exact" else 1.2)
        ax.set_xlabel("direction of the trial traction [deg]")
        ax.set_ylabel("|T - T_tr| / |T_tr| at Phi = 0+ [-]")
        ax.set_title(st, fontsize=10)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "jump.png"), dpi=110)
    plt.close(fig)


def summarize(R, J):
    """Per scene and map: errors, mean observed rate, dissipation sign, cost (from the CSV columns)."""
    out = []
    for s in ("block", "screw"):
        for rm in MAPS:
            i = _idx(R, **{"scene [-]": s, "return_map [-]": rm})
            rates = [R["rate [-]"][k] for k in i if R["rate [-]"][k] == R["rate [-]"][k]][-N_TAIL_RATES:]
            errs = [R["error [m]"][k] for k in i if R["error [m]"][k] == R["error [m]"][k]]
            out.append(dict(scene=s, map=rm, err_coarse=errs[0], err_fine=errs[-1],
                            rate_min=min(rates), rate_mean=float(np.mean(rates)),
                            neg=int(sum(R["negative_steps [-]"][k] for k in i)),
                            min_inc=min(R["min_step_dissipation [J]"][k] for k in i),
                            diss=[R["dissipated [J]"][k] for k in i],
                            newton=float(np.mean([R["newton_per_step [-]"][k] for k in i])),
                            red=int(sum(R["step_reductions [-]"][k] for k in i)),
                            wall=float(sum(R["wall [s]"][k] for k in i))))
    jumps = {}
    for st in dict.fromkeys(J["setting [-]"]):
        for rm in MAPS:
            i = _idx(J, **{"setting [-]": st, "return_map [-]": rm})
            jumps[(st, rm)] = max(J["jump [-]"][k] for k in i)
    return out, jumps


def report(args, timer):
    R = sl.read_table(os.path.join(args.out, "refinement.csv"))
    J = sl.read_table(os.path.join(args.out, "jump.csv"))
    S, jumps = summarize(R, J)
    conv = {(d["scene"], d["map"]): d["rate_min"] > 0.8 for d in S}
    cols = ["scene [-]", "return_map [-]", "error coarsest [m]", "error finest [m]", "min tail rate [-]",
            "mean tail rate [-]", "converges [-]", "dissipation range [J]", "min step dissipation [J]",
            "negative steps [-]", "Newton/step [-]", "step reductions [-]", "wall sum [s]"]
    srows = [[d["scene"], d["map"], d["err_coarse"], d["err_fine"], d["rate_min"], d["rate_mean"],
              "yes" if conv[(d["scene"], d["map"])] else "no", f"{min(d['diss']):.4g} ... {max(d['diss']):.4g}",
              d["min_inc"], d["neg"], d["newton"], d["red"], d["wall"]] for d in S]
    jrows = [[st, rm, v] for (st, rm), v in jumps.items()]
    # the oblique example of the return maps: C isotropic, mu 0.2/0.6, trial at 45 deg
    i45 = {rm: [k for k in _idx(J, **{"setting [-]": "C isotropic, F mu 0.2/0.6", "return_map [-]": rm})
                if abs(J["trial_angle [deg]"][k] - 45.0) < 1e-9]
           for rm in MAPS}
    ang = {rm: [J["returned_angle [deg]"][k] for k in i45[rm]] for rm in MAPS}
    ang_txt = ", ".join(f"{rm} {', '.join(f'{a:.1f}' for a in ang[rm])} deg" for rm in MAPS)
    fin = {(d["scene"], d["map"]): d["diss"][-1] for d in S}
    diss_txt = "; ".join(f"{s} " + ", ".join(f"{rm} {fin[(s, rm)]:.4g} J" for rm in MAPS) for s in ("block", "screw"))
    full = sl.markdown_table(list(R), [[R[c][k] for c in R] for k in range(len(R["dt [s]"]))])
    by = {(d["scene"], d["map"]): d for d in S}
    nm = {rm: np.mean([by[(s, rm)]["newton"] for s in ("block", "screw")]) for rm in MAPS}
    ok_all = {rm: all(conv[(s, rm)] for s in ("block", "screw")) for rm in MAPS}
    neg_all = {rm: sum(by[(s, rm)]["neg"] for s in ("block", "screw")) for rm in MAPS}
    red_all = {rm: sum(by[(s, rm)]["red"] for s in ("block", "screw")) for rm in MAPS}
    jmax = {rm: max(v for (st, m), v in jumps.items() if m == rm) for rm in MAPS}
    # recommendation from the numbers: a default must converge on both scenes, be continuous at
    # stick/slip (jump < 1e-6) and never dissipate negatively; among those, the one whose sliding is
    # steered by the adhesion tensor (the scenes' purpose: circle / thread) -- radial -- is preferred,
    # otherwise the cheaper one in Newton iterations
    qualified = [rm for rm in MAPS if ok_all[rm] and jmax[rm] < 1e-6 and neg_all[rm] == 0]
    rec = "radial" if "radial" in qualified else (min(qualified, key=lambda m: nm[m]) if qualified else "radial")
    why = "; ".join(f"{rm}: converges on both scenes {'yes' if ok_all[rm] else 'no'}, max jump {jmax[rm]:.2g}, "
                    f"negative-dissipation steps {neg_all[rm]}, step reductions {red_all[rm]}, "
                    f"Newton/step {nm[rm]:.2f}" for rm in MAPS)
    body = f"""
Exudyn engine, trapezoidal rule, analytic contact Jacobian, Newton tolerance 1e-10.

* **Block**: the near-circle scene of the block-path study (ratio eps_r/eps_phi = 100 with the package default
  1e5 / 1e3 N/m, isotropic mu 0.3, spring drive along +y from (0.5, 0) m at 0.1 m/s), planar model,
  t_end = {BLOCK['t_end']:g} s (sticking, the stick->slip transition and sliding). Quantity: final centre position;
  error = |(x, y)(dt) - (x, y)(finest)| [m].
* **Screw**: the package default screw (spiral net, helix 10 deg, eps 1e4 / 1e6 N/m, mu 0.2 / 0.6, torsional
  spring 1 N m/rad to a driver at 2 pi rad/s), reduced model, t_end = {SCREW['t_end']:g} s, but mass
  {SCREW['mass']:g} kg instead of 0.01 kg: the drive oscillation sqrt(k/J) is then 283 rad/s and the steps
  <= 1e-3 s resolve it (with 0.01 kg, 2830 rad/s, no step of the ladder does and the error stalls).
  Quantity: final axial position z; error = |z(dt) - z(finest)| [m].
* rate = log2(error(dt) / error(dt/2)) of successive errors against the finest run (with the finest run as
  reference, the last rate is biased upward: for a true order p it reads log2(2^p + 1)). "converges" = the
  last {N_TAIL_RATES} observed rates (the finest step sizes; "tail rate" columns) are all > 0.8; coarse steps may
  be pre-asymptotic (stick/slip events of single contact points move between steps).
* Dissipation: the history of every contact point carries its accumulated dissipated energy; its increment per
  accepted step and per point must be >= 0 (counted negative below -{DISS_TOL:g} x total).
* step reductions = accepted steps beyond the nominal t_end/dt: Exudyn halves a step whose Newton fails.

![step refinement](./refinement.png)

### Summary per scene and map

{sl.markdown_table(cols, srows)}
Dissipated energy at the finest step: {diss_txt}. The seed map's traction stands almost perpendicular to the
slip in steady sliding (it is turned toward the stiff eigen-direction of C F), so it resists the sliding far
less than |N| / sqrt(v.F^-1 v) and dissipates far less than the other two maps for the same motion; its
per-step dissipation is still never negative.

### Stick/slip jump at Phi = 0+

`exu_aniso.law.return_maps.return_map_point` with a trial traction (1 + {JUMP_DELTA:g}) times the point of the friction
ellipse in each direction 0 ... 180 deg (|N| = 1 N); jump = |T - T_tr| / |T_tr| (continuous maps give about
{JUMP_DELTA:g}). Largest jump over the directions:

{sl.markdown_table(["setting [-]", "return_map [-]", "max jump [-]"], jrows)}
The oblique example of the return maps (C isotropic, mu 0.2 / 0.6, trial traction just outside the ellipse at 45 deg):
returned direction {ang_txt}. The seed map returns a traction turned toward the
dominant eigen-direction of C F, whatever the distance from the ellipse; that jump is what Newton meets at
every stick/slip transition (the step reductions above).

![jump vs trial direction](./jump.png)

### Recommendation

Criteria, in this order: converges under step refinement on both scenes (tail rates > 0.8), continuous at
stick/slip (max jump < 1e-6), no negative dissipation step; then the map whose sliding is steered by the
adhesion tensor (the purpose of both scenes: the circle of the block, the advance of the screw), else the one
with fewer Newton iterations. Numbers: {why}.

**Recommended default: `{rec}`**{' (the current default for both scenes; nothing changed).' if rec == 'radial'
 else ' (differs from the current default radial).'}
The exact map is the choice when the user wants associated (maximum-dissipation) anisotropic Coulomb sliding
in which B acts only in stick; here it needs {nm['exact']:.2f} Newton iterations per step against radial's
{nm['radial']:.2f}, and on the block its mean tail rate is {by[('block', 'exact')]['rate_mean']:.2f} against radial's
{by[('block', 'radial')]['rate_mean']:.2f} (both converge; why radial stays below second order on the block was not
isolated here). The seed map stays available
(`return_map="seed"`) to reproduce the papers' closed form.

### All runs

{full}"""
    sl.finish(args, timer, body, "Return maps compared: seed, exact, radial")


def main(argv=None):
    args = sl.parse_args(NAME, __doc__.splitlines()[0], argv)
    timer = sl.Timer()
    compute(args)
    plot(args)
    report(args, timer)


if __name__ == "__main__":
    main()
