"""The elastic block on the polar-orthotropic plane: the bottom's path for different eps_r / eps_phi
(the first paper's figure), and speed against error of the flexible body (mesh size, full and
reduced bodies, modes).

Usage: python studies/fe_block.py [--quick] [--serial] [--out DIR]

Paths: the scene's defaults (a 3 x 3 x 3 mesh pressed 1 mm, then moved 0.1 m along +y from
(0.5, 0)) with eps_r / eps_phi swept at sqrt(eps_r eps_phi) = 1e5 N/m fixed (as the rigid block's
study: q and 1/q have the same two stiffnesses, swapped). Speed against error: the full body on
1 to 5 cells per edge, the reduced body with the faces' Craig-Bampton static modes on 1 to 3 cells
and with free-free eigenmodes on 3 cells, each against the full body on 5 cells (steer_end, the
normal force at the end); the solve's wall time of each run, run one after the other.
"""
from __future__ import annotations

import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)
from _lib.studylib import (Timer, finish, markdown_table, parse_args, read_table, sweep, table,  # noqa: E402
                          with_args)

import numpy as np  # noqa: E402

GEOMETRIC_MEAN = 1e5          # sqrt(eps_r eps_phi) [N/m] of the path sweep (the scene's default's)


def run_case(case):
    """One fe_block run: the summary's figures and the bottom centre's offset from the top."""
    from exu_aniso.models.fe_block import RunFeBlock
    from exu_aniso.scenes.fe_block import FeBlockParams
    res = RunFeBlock(FeBlockParams(**case["params"]))
    s, tr = res.summary, res.trajectory
    return dict(steer_end=s["steer_end"], lag_end=s["lag_end"], force_z_end=s["force_z_end"],
                force_ratio_end=s["force_ratio_end"], slip_fraction_end=s["slip_fraction_end"],
                wall_s=s["wall_s"], steps=s["steps"], residual=s["energy"]["residual"], energy_ok=s["energy_ok"],
                travel=(np.asarray(tr["y_top"]) - tr["y_top"][0]).tolist(),
                across=(np.asarray(tr["x_bottom"]) - tr["x_top"]).tolist(),
                coordinates=res.info.get("coordinates"))


def main(argv=None):
    args = parse_args("fe_block", __doc__.splitlines()[0], argv)
    timer = Timer()
    q = args.quick
    short = dict(cells=1, t_end=0.6, t_press=0.1, travel=0.02) if q else {}
    ratios = (0.1, 100.0) if q else (0.01, 0.1, 1.0, 10.0, 100.0)
    path_cases = [dict(params=dict(eps_r=GEOMETRIC_MEAN * math.sqrt(r), eps_phi=GEOMETRIC_MEAN / math.sqrt(r),
                                   **short), ratio=r) for r in ratios]
    P = sweep(run_case, path_cases, args)
    ppath = table(os.path.join(args.out, "paths.csv"),
                  ["eps_r/eps_phi [-]", "steer_end [m]", "lag_end [m]", "force_ratio_end [-]", "slip_fraction_end [-]",
                   "energy_residual [-]", "energy_ok [-]"],
                  [[c["ratio"], r["steer_end"], r["lag_end"], r["force_ratio_end"], r["slip_fraction_end"],
                    r["residual"], "yes" if r["energy_ok"] else "no"] for c, r in zip(path_cases, P)])
    # speed against error: one after the other (their wall times compare)
    base = dict(cells=2, t_end=0.6, t_press=0.1, travel=0.02) if q else {}
    full_cells = (1, 2) if q else (1, 2, 3, 4, 5)
    conv = [dict(label=f"full, {n} cells", params=dict(base, cells=n)) for n in full_cells]
    conv += [dict(label=f"reduced, Craig-Bampton, {n} cells", params=dict(base, cells=n, model="reduced"))
             for n in ((1,) if q else (1, 2, 3))]
    conv += [dict(label=f"reduced, {m} eigenmodes, {base.get('cells', 3)} cells",
                  params=dict(base, model="reduced", basis="eigenmodes", modes=m)) for m in ((6,) if q else (6, 24))]
    serial = with_args(args, serial=True)
    C = sweep(run_case, conv, serial)
    ref = C[len(full_cells) - 1]
    rows = []
    for c, r in zip(conv, C):
        rows.append([c["label"], r["wall_s"], r["steps"], abs(r["steer_end"] - ref["steer_end"]),
                     abs(r["force_z_end"] / ref["force_z_end"] - 1.0), r["residual"]])
    cpath = table(os.path.join(args.out, "convergence.csv"),
                  ["body [-]", "solve_wall [s]", "steps [-]", "steer_error [m]", "normal_force_error [-]",
                   "energy_residual [-]"], rows)
    fig = plot(args.out, path_cases, P, conv, C, full_cells)
    body, ok = report(read_table(ppath), read_table(cpath), fig, conv[len(full_cells) - 1]["label"])
    finish(args, timer, body, "Elastic block on the polar-orthotropic plane: paths and speed against error")
    return 0 if ok else 1


def plot(out, path_cases, P, conv, C, full_cells):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from exu_aniso.util.output import atomic_write
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.3))
    for c, r in zip(path_cases, P):
        a.plot(1e3 * np.asarray(r["across"]), np.asarray(r["travel"]), label=f"eps_r/eps_phi = {c['ratio']:g}")
    a.axvline(0.0, color="k", lw=0.6, ls="--")
    a.set_xlabel("bottom centre - top, along x (towards the origin < 0) [mm]")
    a.set_ylabel("top's travel along +y [m]")
    a.set_title("the bottom steered by the net", fontsize=9)
    a.legend(fontsize=7)
    ref = len(full_cells) - 1                          # the reference itself (error 0) is not drawn
    for mark, sel in (("o-", range(ref)), ("s", range(len(full_cells), len(conv)))):
        xs = [C[i]["wall_s"] for i in sel]
        ys = [max(abs(C[i]["steer_end"] - C[ref]["steer_end"]), 1e-12) for i in sel]
        b.loglog(xs, ys, mark, label="full body" if mark == "o-" else "reduced bodies")
        for i, x, y in zip(sel, xs, ys):
            b.annotate(conv[i]["label"].replace("reduced, ", ""), (x, y), fontsize=6)
    b.set_xlabel("solve wall time [s]")
    b.set_ylabel(f"|steer_end - {conv[ref]['label']}| [m]")
    b.set_title("speed against error", fontsize=9)
    b.legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(out, "fe_block.png")
    atomic_write(path, lambda f: fig.savefig(f, dpi=110, format="png"))
    plt.close(fig)
    return "fe_block.png"


def report(Pt, Ct, fig, reference):
    cols = list(Pt)
    prow = [[Pt[c][i] for c in cols] for i in range(len(Pt[cols[0]]))]
    ccols = list(Ct)
    crow = [[Ct[c][i] for c in ccols] for i in range(len(Ct[ccols[0]]))]
    ok = all(v == "yes" for v in Pt["energy_ok [-]"])
    steer = dict(zip(Pt["eps_r/eps_phi [-]"], Pt["steer_end [m]"]))
    lo, hi = min(steer), max(steer)
    text = (f"The bottom centre's offset across the travel at the end (`steer_end`, > 0: towards the origin) goes "
            f"from {steer[lo]:.3g} m at eps_r/eps_phi = {lo:g} to {steer[hi]:.3g} m at {hi:g}: the net steers the "
            f"elastic block's bottom as it steers the rigid block. Speed against error: every body against "
            f"{reference}.\n\n")
    body = (text + markdown_table(cols, prow) + "\n\n" + markdown_table(ccols, crow) + f"\n\n![paths and speed](./{fig})\n")
    return body, ok


if __name__ == "__main__":
    raise SystemExit(main())
