"""The elastic screw in a hole with a spiral net: the twist along the shank against the shaft's closed
form as the mesh is refined, and speed against error of the flexible screw (mesh, basis, modes).

Usage: python studies/fe_screw.py [--quick] [--serial] [--out DIR]

Static: the shank's mesh clamped at its head under equal ring torques (scenes.fe_screw.static_twist)
against the closed form (twist_closed_form), the largest difference along the shank in units of the
tip's twist, on meshes from 1 x 8 x 4 to 4 x 64 x 16 cells (r x theta x z): the twist's error is the
polygonal section's (cells_theta); cells_r and cells_z hardly change it. Dynamic: the scene's runs
(REFERENCE_T_END s, one after the other: their solve wall times compare) on meshes and bases -- 12
and 24 clamped eigenmodes, Craig-Bampton (every thread coordinate's static mode) on meshes of 8 to
32 cells around -- each with the share of the thread's static compliance its basis keeps
(contact_compliance_share), its mean torque, advance per revolution and tip twist against the
reference (the finest Craig-Bampton run, REFERENCE: its basis holds the full mesh's static response to
any thread load, the full body's in steady sliding) and the tip twist against the closed form; and the
rigid screw with the same points (scenes.fe_screw.rigid_screw) beside each.
"""
from __future__ import annotations

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)
from _lib.studylib import (Timer, finish, markdown_table, parse_args, read_table, sweep, table,  # noqa: E402
                          with_args)

import numpy as np  # noqa: E402


REFERENCE_T_END = 0.3
"""Simulated time of the study's runs [s]: the summary averages the last half, 0.15 s of steady
sliding (the rings slide from the first steps, started pressed in)."""

REFERENCE = dict(label="1x32x2, CB", cells=(1, 32, 2), params=dict(basis="craig_bampton", modes=0))
"""The converged reference: the finest mesh whose Craig-Bampton run is affordable here (192 static
modes; 576 coordinates off the head, beyond what model=full runs in reasonable time)."""


def mesh_params(cells, **kw):
    from exu_aniso.scenes.fe_screw import FeScrewParams
    return FeScrewParams(cells_r=cells[0], cells_theta=cells[1], cells_z=cells[2], **kw)


def static_case(case):
    """The static FE twist of one mesh against the closed form (unit torque)."""
    from exu_aniso.scenes.fe_screw import fe_screw_mesh, static_twist, twist_closed_form
    p = mesh_params(case["cells"], basis="eigenmodes", modes=1)          # the mesh alone: no basis is built
    fe, closed = static_twist(p, 1.0), twist_closed_form(p, 1.0)
    return dict(error=float(np.max(np.abs(fe - closed)) / abs(closed[0])), tip_ratio=float(fe[0] / closed[0]),
                coordinates=fe_screw_mesh(p).number_of_coordinates)


def run_case(case):
    """One fe_screw run and the rigid screw with its points: the figures of the speed-against-error table."""
    import warnings

    from exu_aniso.fe import BasisWarning
    from exu_aniso.models.fe_screw import RunFeScrew
    from exu_aniso.models.screw import RunScrew
    from exu_aniso.scenes.fe_screw import fe_screw_mesh, rigid_screw, static_twist
    p = mesh_params(case["cells"], **case["params"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BasisWarning)         # the table shows the share
        res = RunFeScrew(p)
    s = res.summary
    rigid = RunScrew(rigid_screw(p, fe_screw_mesh(p).total_mass)).summary
    fe = static_twist(p, s["torque_mean"])
    return dict(wall_s=s["wall_s"], steps=s["steps"], share=s["contact_compliance_share"], torque_mean=s["torque_mean"], twist_tip=s["twist_tip"],
                twist_static=float(fe[0]), twist_closed=s["twist_tip_theory"], torque_rigid=rigid["torque_mean"],
                advance=s["advance_per_rev"], advance_rigid=rigid["advance_per_rev"],
                residual=s["energy"]["residual"], energy_ok=s["energy_ok"], profile=s["twist_profile"],
                theory=s["twist_profile_theory"])


def cases_of(quick):
    """The dynamic runs: (label, cells, params); the reference last."""
    eig = lambda m: dict(basis="eigenmodes", modes=m)      # noqa: E731
    cb = dict(basis="craig_bampton", modes=0)
    if quick:
        return [dict(label="1x8x4, 12 eig", cells=(1, 8, 4), params=eig(12)),
                dict(label="1x8x2, CB", cells=(1, 8, 2), params=cb)]
    return [dict(label="1x8x4, 12 eig", cells=(1, 8, 4), params=eig(12)),
            dict(label="1x8x4, 24 eig", cells=(1, 8, 4), params=eig(24)),
            dict(label="1x24x2, 24 eig", cells=(1, 24, 2), params=eig(24)),
            dict(label="1x8x4, CB", cells=(1, 8, 4), params=cb),
            dict(label="1x8x4, CB + 12 eig", cells=(1, 8, 4), params=dict(basis="craig_bampton", modes=12)),
            dict(label="1x16x2, CB", cells=(1, 16, 2), params=cb),
            dict(label="1x20x2, CB", cells=(1, 20, 2), params=cb),
            dict(label="1x24x2, CB", cells=(1, 24, 2), params=cb),
            dict(label="2x24x2, CB", cells=(2, 24, 2), params=cb),
            dict(label="1x24x3, CB", cells=(1, 24, 3), params=cb),
            REFERENCE]


def is_default(case):
    """True for the scene's default mesh and basis (FE_SCREW_PARAMS)."""
    from exu_aniso.scenes.fe_screw import FeScrewParams
    p, d = mesh_params(case["cells"], **case["params"]), FeScrewParams()
    return all(getattr(p, k) == getattr(d, k) for k in ("cells_r", "cells_theta", "cells_z", "model", "basis", "modes"))


def main(argv=None):
    args = parse_args("fe_screw", __doc__.splitlines()[0], argv)
    timer = Timer()
    q = args.quick
    static_meshes = [(1, 8, 4), (1, 12, 6)] if q else [(1, 8, 4), (1, 12, 6), (1, 16, 2), (1, 24, 2), (1, 24, 4),
                                                       (2, 16, 8), (1, 32, 2), (2, 24, 8), (3, 32, 12), (4, 48, 16),
                                                       (4, 64, 16)]
    S = sweep(static_case, [dict(cells=c) for c in static_meshes], args)
    spath = table(os.path.join(args.out, "static_twist.csv"),
                  ["mesh (r x theta x z) [-]", "coordinates [-]", "tip_twist / closed_form [-]", "largest_error [-]"],
                  [["x".join(map(str, c)), r["coordinates"], r["tip_ratio"], r["error"]] for c, r in zip(static_meshes, S)])
    t_end = dict(t_end=REFERENCE_T_END)
    cases = [dict(c, params=dict(c["params"], **t_end)) for c in cases_of(q)]
    serial = with_args(args, serial=True)
    R = sweep(run_case, cases, serial)
    ref = R[-1]
    rows = []
    for c, r in zip(cases, R):
        rows.append([c["label"] + (" (default)" if is_default(c) else ""), r["wall_s"], r["share"],
                     r["torque_mean"] / ref["torque_mean"] - 1.0, r["advance"] / ref["advance"] - 1.0,
                     r["twist_tip"] / ref["twist_tip"] - 1.0, r["twist_tip"] / r["twist_closed"] - 1.0,
                     r["twist_tip"] / r["twist_static"] - 1.0, r["torque_mean"] / r["torque_rigid"] - 1.0,
                     r["advance"] / r["advance_rigid"] - 1.0, r["residual"], "yes" if r["energy_ok"] else "no"])
    dpath = table(os.path.join(args.out, "speed_error.csv"),
                  ["shank (mesh, basis) [-]", "solve_wall [s]", "compliance_share [-]", "torque_vs_reference [-]",
                   "advance_vs_reference [-]", "twist_vs_reference [-]", "twist_vs_closed_form [-]",
                   "twist_vs_static_FE [-]", "torque_vs_rigid [-]", "advance_vs_rigid [-]", "energy_residual [-]",
                   "energy_ok [-]"], rows)
    fig = plot(args.out, static_meshes, S, cases, R)
    body, ok = report(read_table(spath), read_table(dpath), fig, cases[-1]["label"], t_end["t_end"])
    finish(args, timer, body, "Elastic screw: the twist along the shank and speed against error")
    return 0 if ok else 1


def plot(out, static_meshes, S, cases, R):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from exu_aniso.util.output import atomic_write
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(15, 4.5))
    a.loglog([r["coordinates"] for r in S], [r["error"] for r in S], "o-")
    for m, r in zip(static_meshes, S):
        a.annotate("x".join(map(str, m)), (r["coordinates"], r["error"]), fontsize=7)
    a.set_xlabel("coordinates of the mesh [-]")
    a.set_ylabel("largest |FE - closed form| / |closed form at the tip| [-]")
    a.set_title("static twist under equal ring torques", fontsize=9)
    for case, r in zip(cases, R):
        if case["params"].get("basis") != "craig_bampton" or case["params"].get("modes"):
            continue
        s = np.linspace(0.0, 1.0, len(r["profile"]))
        line, = b.plot(s, 1e3 * np.asarray(r["profile"]), "s-", ms=4, label=case["label"])
        b.plot(s, 1e3 * np.asarray(r["theory"]), "--", color=line.get_color(), lw=0.8)
    b.set_xlabel("distance from the tip / length [-]")
    b.set_ylabel("rotation against the head [mrad]")
    b.set_title("twist along the shank (dashed: the closed form)", fontsize=9)
    b.legend(fontsize=7)
    ref = R[-1]
    for i, (case, r) in enumerate(zip(cases[:-1], R[:-1])):
        err = max(abs(r[k] / ref[k] - 1.0) for k in ("torque_mean", "advance", "twist_tip"))
        eig = case["params"].get("basis") == "eigenmodes"
        default = is_default(case)
        c.loglog(r["wall_s"], max(err, 1e-6), "s" if eig else "o", color="C3" if default else ("C1" if eig else "C0"),
                 ms=11 if default else 6, mfc="none" if default else None)
        c.annotate(case["label"] + (" (default)" if default else ""), (r["wall_s"], max(err, 1e-6)), fontsize=6)
    c.axhline(0.01, color="k", lw=0.8, ls=":", label="1 % bar")
    c.plot([], [], "s", color="C1", label="clamped eigenmodes")
    c.plot([], [], "o", color="C0", label="Craig-Bampton")
    c.plot([], [], "o", color="C3", mfc="none", ms=11, label="the default")
    c.set_xlabel("solve wall time [s]")
    c.set_ylabel("largest error of torque, advance, tip twist vs the reference [-]")
    c.set_title(f"speed against error (reference: {cases[-1]['label']})", fontsize=9)
    c.legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(out, "fe_screw.png")
    atomic_write(path, lambda f: fig.savefig(f, dpi=110, format="png"))
    plt.close(fig)
    return "fe_screw.png"


def report(St, Dt, fig, reference, t_end):
    cols, dcols = list(St), list(Dt)
    srow = [[St[c][i] for c in cols] for i in range(len(St[cols[0]]))]
    drow = [[Dt[c][i] for c in dcols] for i in range(len(Dt[dcols[0]]))]
    ok = all(v == "yes" for v in Dt["energy_ok [-]"])
    err = St["largest_error [-]"]
    text = (f"The static FE twist approaches the shaft's closed form as the mesh is refined: its largest error along "
            f"the shank goes from {err[0]:.3g} to {err[-1]:.3g} of the tip's twist (the polygonal section: "
            f"cells_theta; cells_r and cells_z hardly change it). The runs ({t_end} s each, one after the other) are "
            f"set against the reference {reference} (Craig-Bampton: its basis holds the full mesh's static response "
            f"to any thread load), the tip twist also against the closed form and against the static FE twist of "
            f"its own mesh under the run's mean torque (what the basis misses); compliance_share is the share of "
            f"the thread nodes' static compliance the basis keeps (below 0.9 the run warns).\n\n")
    body = (text + markdown_table(cols, srow) + "\n\n" + markdown_table(dcols, drow)
            + f"\n\n![twist and speed](./{fig})\n")
    return body, ok


if __name__ == "__main__":
    raise SystemExit(main())
