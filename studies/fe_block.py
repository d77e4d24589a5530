"""The elastic block on the polar-orthotropic plane: the paper's family of motions over eps_r /
eps_phi with the rigid block scene's path under the same drive beside each, and speed against error
of the flexible body (mesh and basis).

Usage: python studies/fe_block.py [--quick] [--serial] [--out DIR]

Paths: the scene's defaults (the bottom nodes' static modes on a 3 x 3 x 3 mesh, pressed 1 mm, then
pulled 0.1 m along +y from (0.5, 0) by the block scene's drive, free across and about the vertical)
with eps_r / eps_phi swept over four decades, 0.01 to 100, at sqrt(eps_r eps_phi) = 1e5 N/m fixed
(q and 1/q have the same two stiffnesses, swapped); beside each, the rigid block scene under the same
drive (``scenes.fe_block.rigid_limit``: its stiff limit, on the reference engine). Speed against
error: the full mesh in the floating frame (every coordinate off the top face) on 2 and 3 cells per
X
eigenmodes alone, each against the full mesh on 3 cells (the bottom's path and the drive's force
at the end); the solve's wall time of each run, run one after the other.
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
    """One fe_block run: the summary's figures, the bottom centre's path and the rigid block's."""
    import warnings
    from exu_aniso.models.fe_block import RunFeBlock
    from exu_aniso.scenes.block import simulate_block
    from exu_aniso.scenes.fe_block import FeBlockParams, rigid_block
    p = FeBlockParams(**case["params"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                # the eigenmode bases warn; the share is in the table
        res = RunFeBlock(p)
    s, tr = res.summary, res.trajectory
    out = dict(steer_end=s["steer_end"], r_bottom_end=s["r_bottom_end"], yaw_end=s["yaw_end"],
               drive_force_end=s["drive_force_end"], force_z_end=s["force_z_end"],
               slip_fraction_end=s["slip_fraction_end"], wall_s=s["wall_s"], steps=s["steps"],
               residual=s["energy"]["residual"], energy_ok=s["energy_ok"], share=s["contact_compliance_share"],
               t=np.asarray(tr["t"]).tolist(), x=np.asarray(tr["x_bottom"]).tolist(),
               y=np.asarray(tr["y_bottom"]).tolist())
    if case.get("rigid"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")            # its ledger's residual is in the table
            rigid = simulate_block(rigid_block(p))
        out.update(x_rigid=np.asarray(rigid.trajectory["x"]).tolist(), y_rigid=np.asarray(rigid.trajectory["y"]).tolist(),
                   rigid_residual=rigid.summary["energy"]["residual"])
    return out


def _path_error(a, b):
    """Largest distance [m] between two runs' bottom paths at the same times."""
    return float(np.hypot(np.asarray(a["x"]) - b["x"], np.asarray(a["y"]) - b["y"]).max())


def main(argv=None):
    args = parse_args("fe_block", __doc__.splitlines()[0], argv)
    timer = Timer()
    q = args.quick
    short = dict(cells=1) if q else {}
    ratios = (0.01, 100.0) if q else (0.01, 0.1, 1.0, 10.0, 100.0)
    path_cases = [dict(params=dict(eps_r=GEOMETRIC_MEAN * math.sqrt(r), eps_phi=GEOMETRIC_MEAN / math.sqrt(r),
                                   **short), ratio=r, rigid=True) for r in ratios]
    P = sweep(run_case, path_cases, args)
    ppath = table(os.path.join(args.out, "paths.csv"),
                  ["eps_r/eps_phi [-]", "steer_end [m]", "r_bottom_end [m]", "r_rigid_end [m]", "yaw_end [rad]",
                   "slip_fraction_end [-]", "energy_residual [-]", "energy_ok [-]", "rigid_energy_residual [-]"],
                  [[c["ratio"], r["steer_end"], r["r_bottom_end"], math.hypot(r["x_rigid"][-1], r["y_rigid"][-1]),
                    r["yaw_end"], r["slip_fraction_end"], r["residual"], "yes" if r["energy_ok"] else "no",
                    r["rigid_residual"]]
                   for c, r in zip(path_cases, P)])
    # speed against error: one after the other (their wall times compare)
    base = dict(t_end=0.6, t_press=0.1, travel=0.02) if q else {}
    conv = [dict(label=f"full, {n} cells", params=dict(base, cells=n, model="full")) for n in ((1,) if q else (2, 3))]
    conv += [dict(label=f"static modes, {n} cells", params=dict(base, cells=n, model="reduced"))
             for n in ((1,) if q else (2, 3, 4, 5, 6))]
    reference = len(conv) - 1                   # the finest: static modes hold the full mesh at the contact
    cells = 1 if q else 3
    conv += [dict(label=f"{m} eigenmodes, {cells} cells",
                  params=dict(base, cells=cells, model="reduced", basis="eigenmodes", modes=m))
             for m in ((6,) if q else (6, 24))]
    C = sweep(run_case, conv, with_args(args, serial=True))
    ref = C[reference]
    rows = [[c["label"], r["wall_s"], r["steps"], r["share"], _path_error(r, ref),
             abs(r["drive_force_end"] / ref["drive_force_end"] - 1.0), abs(r["force_z_end"] / ref["force_z_end"] - 1.0),
             r["residual"]] for c, r in zip(conv, C)]
    cpath = table(os.path.join(args.out, "convergence.csv"),
                  ["body [-]", "solve_wall [s]", "steps [-]", "compliance_share [-]", "path_error [m]",
                   "drive_force_error [-]", "normal_force_error [-]", "energy_residual [-]"], rows)
    fig = plot(args.out, path_cases, P, conv, C, reference)
    body, ok = report(read_table(ppath), read_table(cpath), fig, conv[reference]["label"])
    finish(args, timer, body, "Elastic block on the polar-orthotropic plane: the family of motions and speed "
                              "against error")
    return 0 if ok else 1


def plot(out, path_cases, P, conv, C, reference):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from exu_aniso.util.output import atomic_write
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.6))
    phi = np.linspace(-0.5, 0.5, 200)
    a.plot(0.5 * np.cos(phi), 0.5 * np.sin(phi), color="0.8", lw=0.8, label="circle about the origin")
    for k, (c, r) in enumerate(zip(path_cases, P)):
        a.plot(r["x"], r["y"], color=f"C{k}", lw=1.4, label=f"FE, eps_r/eps_phi = {c['ratio']:g}")
        a.plot(r["x_rigid"], r["y_rigid"], color=f"C{k}", lw=0.9, ls="--")
    a.plot([], [], "k--", lw=0.9, label="rigid block scene, same drive")
    xs = np.concatenate([r["x"] for r in P] + [r["x_rigid"] for r in P])
    ys = np.concatenate([r["y"] for r in P] + [r["y_rigid"] for r in P])
    a.set_xlim(xs.min() - 0.02, xs.max() + 0.02)
    a.set_ylim(ys.min() - 0.02, ys.max() + 0.02)
    a.set_aspect("equal")
    a.set_xlabel("x of the bottom face's centre [m]")
    a.set_ylabel("y [m]")
    a.set_title("the net steers the block (pulled along +y)", fontsize=9)
    a.legend(fontsize=6, loc="upper right")
    sel = [i for i in range(len(conv)) if i != reference]
    xs = [C[i]["wall_s"] for i in sel]
    ys = [max(_path_error(C[i], C[reference]), 1e-12) for i in sel]
    b.loglog(xs, ys, "o")
    for i, x, y in zip(sel, xs, ys):
        b.annotate(conv[i]["label"] + (" (default)" if conv[i]["label"].startswith("static modes, 4") else ""),
                   (x, y), fontsize=6)
    b.set_xlabel("solve wall time [s]")
    b.set_ylabel("bottom's path: largest distance [m]")
    b.set_title(f"speed against error (against {conv[reference]['label']})", fontsize=9)
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
    text = (f"The bottom centre's offset across the drive at the end (`steer_end`, > 0: towards the origin) goes "
            f"from {steer[lo]:.3g} m at eps_r/eps_phi = {lo:g} (an outward drift) to {steer[hi]:.3g} m at {hi:g} "
            f"(along the circle); the dashed lines are the rigid block scene under the same drive, the FE block's "
            f"stiff limit (its normal force eps_n w, the elastic block's far less: the same shapes, not the same "
            f"times). The rigid runs' ledgers leave up to {max(Pt['rigid_energy_residual [-]']):.2g} of the work "
            f"(polar B's hypo-elastic part, which no potential stores: the same at dt / 4, and 4e-12 at "
            f"eps_r = eps_phi). Speed against error: every body against {reference}; the default is the static "
            f"modes on 4 cells.\n\n")
    body = (text + markdown_table(cols, prow) + "\n\n" + markdown_table(ccols, crow) + f"\n\n![paths and speed](./{fig})\n")
    return body, ok


if __name__ == "__main__":
    raise SystemExit(main())
