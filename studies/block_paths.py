"""Block paths on a polar-orthotropic plane (paper 000, Fig. 1): sweep of the adhesion ratio
eps_r / eps_phi x return map x drive, Exudyn engine, planar model (x, y, theta; held normal load).

The block starts at (x0, y0) = (0.5, 0) m and is driven along +y (drive_angle 90 deg, i.e. along
e_phi at the start). The geometric mean sqrt(eps_r eps_phi) of the total adhesion stiffnesses is
kept fixed at 1e4 N/m (the package default 1e5 / 1e3 is ratio 100), so ratio and 1 / ratio have
the same pair of stiffnesses, only swapped between the radial and the circumferential direction;
the friction is isotropic (mu_r = mu_phi = 0.3), so every difference between the maps comes from B.

Writes ``paths.csv`` (every path downsampled to about 200 points), ``summary.csv`` (one row per case),
``xcheck.csv`` (a few cases run with both engines), ``paths.png``, ``spread.png`` and ``report.md``.
Usage: python studies/block_paths.py [--quick] [--serial] [--out DIR]
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
from exu_aniso.scenes.base import summary_float  # noqa: E402

NAME = "block_paths"
MAPS = ("seed", "exact", "radial")
DRIVES = ("displacement", "force")
GEOMETRIC_MEAN = 1e4          # sqrt(eps_r eps_phi) [N/m], total over the contact points
R0 = 0.5                      # start radius [m] (x0)
MU = 0.3
NORMAL_LOAD = 9.81
FORCE_FACTOR = 1.05           # force drive: P = 1.05 mu N (must exceed the friction limit to slide at all)
# the scene; everything not named here is the BlockParams default (see `exu-aniso params block`)
SCENE = dict(x0=R0, y0=0.0, adhesion="polar", friction="polar", mu_1=MU, mu_2=MU, normal_load=NORMAL_LOAD,
             drive_angle=90.0, drive_speed=0.1, drive_stiffness=1e3, force=FORCE_FACTOR * MU * NORMAL_LOAD,
             t_end=4.5, dt=1e-3, model="planar", solver="trapezoidal")
N_PATH = 200                  # points per path in paths.csv
# near-circle criterion: spread (r_max - r_min) / r_mean <= SPREAD_MAX and |swept angle| >= SWEPT_MIN
SPREAD_MAX = 0.02
SWEPT_MIN = 60.0
ESCAPE = 0.05                 # the path "escapes" when r first exceeds (1 + ESCAPE) r0
# engine parity tolerance on positions/radii [m]: planar exact/radial agree to Newton tolerance
# (README "Parity"); the seed map cuts steps differently in the two engines (discontinuous map)
XCHECK_TOL = {"exact": 1e-6 * R0, "radial": 1e-6 * R0, "seed": 1e-2 * R0}


def params_for(ratio, return_map, drive, **over):
    from exu_aniso.scenes.block import BlockParams
    s = math.sqrt(ratio)
    return BlockParams(**{**SCENE, "eps_1": GEOMETRIC_MEAN * s, "eps_2": GEOMETRIC_MEAN / s,
                          "return_map": return_map, "drive": drive, **over})


def path_measures(tr, ratio, return_map, drive):
    """Shape of a path: radii, spread, angle swept about the origin, escape angle, quasi-static radius."""
    x, y = np.asarray(tr["x"]), np.asarray(tr["y"])
    r = np.hypot(x, y)
    phi = np.unwrap(np.arctan2(y, x))
    swept = math.degrees(phi[-1] - phi[0])
    out = np.nonzero(r > (1.0 + ESCAPE) * r[0])[0]
    escape = math.degrees(phi[out[0]] - phi[0]) if len(out) else float("nan")
    # quasi-static radial map, isotropic F, pull along +y from (r0, 0): slip ∝ C^-1 T gives
    # dr / (r dphi) = tan(phi) / ratio, i.e. r cos(phi)^(1/ratio) = r0 (valid for |phi| < 90 deg)
    r_qs = float("nan")
    if return_map == "radial" and drive == "displacement" and abs(phi[-1]) < 0.5 * math.pi:
        r_qs = r[0] * math.cos(phi[-1]) ** (-1.0 / ratio)
    return dict(r=r, swept=swept, escape=escape, r_qs=r_qs, spread=float((r.max() - r.min()) / r.mean()))


def run_case(case):
    """One Exudyn run; returns summary numbers and the downsampled path."""
    from exu_aniso.models.block import RunBlock
    p = params_for(case["ratio"], case["return_map"], case["drive"])
    res = RunBlock(p)
    tr, s = res.trajectory, res.summary
    m = path_measures(tr, case["ratio"], case["return_map"], case["drive"])
    idx = np.unique(np.linspace(0, len(tr["t"]) - 1, N_PATH).round().astype(int))
    return dict(summary=s, info=res.info, swept=m["swept"], escape=m["escape"], r_qs=m["r_qs"], spread=m["spread"],
                r_end=float(m["r"][-1]), path=[(float(tr["t"][i]), float(tr["x"][i]), float(tr["y"][i])) for i in idx])


XKEYS = ("x_end", "y_end", "r_min", "r_max", "r_mean")


def run_xcheck(case):
    """Same parameters through Exudyn and the numpy reference; max difference of the path measures."""
    from exu_aniso.models.block import RunBlock
    from exu_aniso.scenes.block import simulate_block
    p = params_for(case["ratio"], case["return_map"], case["drive"], t_end=case["t_end"])
    a, b = RunBlock(p).summary, simulate_block(p).summary
    return dict(exudyn=a, reference=b, diff=max(abs(a[k] - b[k]) for k in XKEYS))


SUMMARY_COLUMNS = ["ratio [-]", "eps_r [N/m]", "eps_phi [N/m]", "return_map [-]", "drive [-]", "r_min [m]",
                   "r_max [m]", "r_mean [m]", "spread [-]", "swept [deg]", "heading [deg]", "rotation [deg]",
                   "r_end [m]", "r_quasistatic [m]", "escape_angle [deg]", "near_circle [-]", "newton_per_step [-]",
                   "steps [-]", "step_reductions [-]", "dissipated [J]", "wall [s]"]
XCHECK_COLUMNS = ["ratio [-]", "return_map [-]", "drive [-]", "t_end [s]", "r_mean_exudyn [m]",
                  "r_mean_reference [m]", "spread_exudyn [-]", "spread_reference [-]", "max_diff [m]", "tol [m]",
                  "ok [-]"]


def compute(args):
    ratios = [0.1, 1.0, 100.0] if args.quick else [float(v) for v in np.logspace(-2, 2, 9)]
    drives = ("displacement",) if args.quick else DRIVES
    cases = [dict(ratio=q, return_map=rm, drive=d) for d in drives for rm in MAPS for q in ratios]
    xcases = ([dict(ratio=100.0, return_map="radial", drive="displacement", t_end=0.5)] if args.quick else
              [dict(ratio=100.0, return_map=rm, drive="displacement", t_end=SCENE["t_end"]) for rm in MAPS]
              + [dict(ratio=100.0, return_map="radial", drive="force", t_end=SCENE["t_end"]),
                 dict(ratio=0.1, return_map="exact", drive="displacement", t_end=SCENE["t_end"])])
    results = sl.sweep(run_case, cases, args)
    xres = sl.sweep(run_xcheck, xcases, args)

    rows, prow = [], []
    for c, r in zip(cases, results):
        s, info = r["summary"], r["info"]
        s_ = math.sqrt(c["ratio"])
        near = int(r["spread"] <= SPREAD_MAX and abs(r["swept"]) >= SWEPT_MIN)
        rows.append([c["ratio"], GEOMETRIC_MEAN * s_, GEOMETRIC_MEAN / s_, c["return_map"], c["drive"], s["r_min"],
                     s["r_max"], s["r_mean"], r["spread"], r["swept"], summary_float(s, "heading_deg"), math.degrees(s["theta_end"]),
                     r["r_end"], r["r_qs"], r["escape"], near, s["newton_iterations"] / s["steps"], s["steps"],
                     info["accepted_steps"] - info["nominal_steps"], s["dissipated_energy"], s["wall_s"]])
        prow += [[c["ratio"], c["return_map"], c["drive"], t, x, y] for t, x, y in r["path"]]
    sl.table(os.path.join(args.out, "summary.csv"), SUMMARY_COLUMNS, rows)
    sl.table(os.path.join(args.out, "paths.csv"), ["ratio [-]", "return_map [-]", "drive [-]", "t [s]", "x [m]",
                                                     "y [m]"], prow)
    xrows = []
    for c, r in zip(xcases, xres):
        e, f = r["exudyn"], r["reference"]
        tol = XCHECK_TOL[c["return_map"]]
        xrows.append([c["ratio"], c["return_map"], c["drive"], c["t_end"], e["r_mean"], f["r_mean"],
                      (e["r_max"] - e["r_min"]) / e["r_mean"], (f["r_max"] - f["r_min"]) / f["r_mean"], r["diff"], tol,
                      int(r["diff"] <= tol)])
    sl.table(os.path.join(args.out, "xcheck.csv"), XCHECK_COLUMNS, xrows)


# ----------------------------------------------------------------------------------------------
# figures and report, from the CSV files

def _rows(tab, **match):
    n = len(next(iter(tab.values())))
    return [i for i in range(n) if all(tab[k][i] == v for k, v in match.items())]


def plot(args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    P = sl.read_table(os.path.join(args.out, "paths.csv"))
    S = sl.read_table(os.path.join(args.out, "summary.csv"))
    drives = [d for d in DRIVES if d in set(S["drive [-]"])]
    ratios = sorted(set(S["ratio [-]"]))
    cmap = plt.get_cmap("viridis")
    fig, axes = plt.subplots(len(drives), len(MAPS), figsize=(4.2 * len(MAPS), 4.0 * len(drives)), squeeze=False)
    for i, d in enumerate(drives):
        for j, rm in enumerate(MAPS):
            ax = axes[i, j]
            phi = np.linspace(0, 2 * np.pi, 200)
            ax.plot(R0 * np.cos(phi), R0 * np.sin(phi), ":", color="0.6", lw=0.8)
            ax.plot([0], [0], "k+", ms=12, mew=2)
            for k, q in enumerate(ratios):
                idx = _rows(P, **{"ratio [-]": q, "return_map [-]": rm, "drive [-]": d})
                ax.plot([P["x [m]"][n] for n in idx], [P["y [m]"][n] for n in idx],
                        color=cmap(k / max(1, len(ratios) - 1)), lw=1.3, label=f"{q:.3g}")
            ax.set_xlim(-0.9, 1.2)
            ax.set_ylim(-0.3, 1.2)
            ax.set_aspect("equal")
            ax.set_title(f"{rm} map, {d} drive", fontsize=10)
            ax.set_xlabel("x [m]")
            ax.set_ylabel("y [m]")
            ax.grid(alpha=0.3)
    axes[0, 0].legend(title="eps_r/eps_phi", fontsize=7, loc="upper left")
    fig.suptitle("block paths (origin +, start circle dotted; driven along +y from (0.5, 0); window clipped)")
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "paths.png"), dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(1, len(drives), figsize=(5.2 * len(drives), 4.0), squeeze=False)
    for i, d in enumerate(drives):
        ax = axes[0, i]
        for rm, mk in zip(MAPS, "os^"):
            idx = _rows(S, **{"return_map [-]": rm, "drive [-]": d})
            ax.loglog([S["ratio [-]"][n] for n in idx], [S["spread [-]"][n] for n in idx], mk + "-", label=rm)
        ax.axhline(SPREAD_MAX, color="k", ls="--", lw=0.8, label=f"near-circle bound {SPREAD_MAX}")
        ax.set_xlabel("eps_r / eps_phi [-]")
        ax.set_ylabel("spread (r_max - r_min) / r_mean [-]")
        ax.set_title(f"{d} drive")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "spread.png"), dpi=110)
    plt.close(fig)


def report(args, timer):
    S = sl.read_table(os.path.join(args.out, "summary.csv"))
    X = sl.read_table(os.path.join(args.out, "xcheck.csv"))
    n = len(S["ratio [-]"])
    show = ["ratio [-]", "return_map [-]", "drive [-]", "spread [-]", "swept [deg]", "r_end [m]", "rotation [deg]",
            "escape_angle [deg]", "newton_per_step [-]", "step_reductions [-]", "wall [s]"]
    order = sorted(range(n), key=lambda i: (S["drive [-]"][i], S["return_map [-]"][i], S["ratio [-]"][i]))
    main = sl.markdown_table(show, [[S[c][i] for c in show] for i in order])
    near = [i for i in order if S["near_circle [-]"][i] == 1]
    near_txt = (sl.markdown_table(["ratio [-]", "return_map [-]", "drive [-]", "spread [-]", "swept [deg]"],
                                  [[S[c][i] for c in ("ratio [-]", "return_map [-]", "drive [-]", "spread [-]",
                                                      "swept [deg]")] for i in near])
                if near else "No case meets the criterion.\n")
    qs = [i for i in order if S["return_map [-]"][i] == "radial" and S["drive [-]"][i] == "displacement"]
    qs_cols = ["ratio [-]", "swept [deg]", "r_end [m]", "r_quasistatic [m]"]
    qs_txt = sl.markdown_table(qs_cols + ["rel_diff [-]"],
                               [[S[c][i] for c in qs_cols] + [S["r_end [m]"][i] / S["r_quasistatic [m]"][i] - 1.0]
                                for i in qs])
    xt = sl.markdown_table(list(X), [[X[c][i] for c in X] for i in range(len(X["ratio [-]"]))])
    dmax = max(X["max_diff [m]"])
    esc_bound = math.degrees(math.asin(1.0 / FORCE_FACTOR))
    # force-driven runs whose displacement-driven twin stays on the circle (never escapes): there the
    # escape is caused by the force drive, not by the drift of the rail itself
    parts = []
    for rm in ("radial", "seed"):
        e = [S["escape_angle [deg]"][i] for i in order if S["drive [-]"][i] == "force" and S["return_map [-]"][i] == rm
             and S["escape_angle [deg]"][i] == S["escape_angle [deg]"][i]
             and any(S["escape_angle [deg]"][k] != S["escape_angle [deg]"][k] for k in order
                     if S["drive [-]"][k] == "displacement" and S["return_map [-]"][k] == rm
                     and S["ratio [-]"][k] == S["ratio [-]"][i])]
        if e:
            parts.append(f"{rm} {min(e):.1f} ... {max(e):.1f} deg")
    force_txt = (f"Escape angles (r first above {1 + ESCAPE:g} r0) of the force-driven runs whose displacement-driven "
                 f"twin stays on the circle: {'; '.join(parts)}; all below the quasi-static bound asin(mu N / P) = "
                 f"{esc_bound:.1f} deg, the difference being the centripetal part (and, for seed, a friction force "
                 f"that is not opposite to the slip: those blocks also spin, see the rotation column)."
                 if parts else "(No force-drive rows in this run.)")
    body = f"""
**Scene.** Planar block model (x, y, theta; normal load 9.81 N held by the penetration), Exudyn engine,
trapezoidal rule, dt = {SCENE['dt']:g} s, t_end = {SCENE['t_end']:g} s, 4 corner points, polar adhesion and polar
friction about the origin with mu_r = mu_phi = {MU:g} (isotropic friction, so only B is anisotropic). The block
starts at (0.5, 0) m and is driven along +y: `displacement` = spring {SCENE['drive_stiffness']:g} N/m along +y to a
driver moving at {SCENE['drive_speed']:g} m/s (driver travel {SCENE['drive_speed'] * SCENE['t_end']:g} m, the paper's
incremental horizontal displacement), `force` = constant P = {FORCE_FACTOR:g} mu N = {SCENE['force']:.3f} N along +y.
The ratio eps_r/eps_phi is swept with **sqrt(eps_r eps_phi) = {GEOMETRIC_MEAN:g} N/m fixed**: ratio q and 1/q then
have the same two stiffnesses, swapped between the directions, so the sweep isolates the direction of the
anisotropy; ratio 100 is the package default (1e5, 1e3). spread = (r_max - r_min) / r_mean of the distance of the
centre from the origin; swept = change of the polar angle of the centre; rotation = final block angle theta.

![block paths per return map and drive](./paths.png)

![spread vs ratio](./spread.png)

### Near-circular paths

Criterion: spread <= {SPREAD_MAX:g} while sweeping |angle| >= {SWEPT_MIN:g} deg about the origin.

{near_txt}
### Mechanism per return map

* **radial** (`T = |N| T_tr / |T_tr|_F`): the trial increment is `-C du`, so in steady sliding the slip moves
  along `C^-1 T` -- the adhesion tensor steers. With a pull along +y at polar angle phi the friction must hold
  the radial part P sin(phi); the matching radial slip is only (T_r / T_phi) / ratio of the circumferential slip,
  so the stiff radial adhesion pins the radius: quasi-statically dr / (r dphi) = tan(phi) / ratio, i.e.
  **r cos(phi)^(1/ratio) = r0** (isotropic ratio 1: x = r0, the straight line). The table compares this with
  the displacement-driven radial runs; it holds while inertia and the stick-slip oscillation of the drive
  spring are small (the run departs from it late, when the polar velocity grows as 1/cos(phi)).
  For ratio < 1 the soft direction is radial and the block slides outward along it; there the block also
  turns strongly (rotation column) and the point-block formula no longer applies.

{qs_txt}
* **exact** (`(I + kappa C F) T = T_tr`): the associated flow makes the slip follow `F T`; B drops out of steady
  sliding, and with isotropic F the friction opposes the velocity. The block follows the pull on the straight
  line x = 0.5 m for every ratio (equal spread for all ratios); B acts only in the short sticking phase.
* **seed** (`T ∝ B F T_tr`): each step multiplies the traction by C F, a power iteration toward the stiff
  eigen-direction of C F (radial for ratio > 1); the friction force turns radial and acts as a rail, so the radius
  is pinned even tighter than with the radial map at large ratios. But the map jumps at Phi = 0+ (it does not
  return T_tr at the stick/slip boundary), so every stick/slip transition of the drive spring throws the traction
  sideways: Newton fails there and the step is cut (column step_reductions), and the rail strength depends on
  the step size (see the return-map study).

### Force vs displacement drive

The displacement drive is quasi-static: the spring force stays near the friction limit mu N and the block
follows the rail as far as the driver goes (the swept angle is set by the driver travel). A constant force must
exceed mu N to slide at all, so the block accelerates without bound; the friction can hold the outward
component P sin(phi) plus the centripetal force m v^2/r only while their sum stays below mu N, so every
force-driven path leaves the circle and ends up moving along the pull (heading near 90 deg), whatever the map.
Exact-map force runs go straight (x = 0.5 m), as the displacement ones do. {force_txt}

### All cases

wall = Exudyn solve time of the case (measured while other jobs shared the cores: compare within one run only);
step_reductions = accepted steps beyond t_end / dt (Exudyn halves a step whose Newton fails).

{main}
### Cross-check against the reference engine

Same parameters in `exu_aniso.scenes.block.simulate_block` (numpy, Lie-group trapezoidal, analytic Jacobian);
max_diff = max |difference| of x_end, y_end, r_min, r_max, r_mean. Tolerance {XCHECK_TOL['radial']:g} m for
exact/radial (parity to Newton tolerance), {XCHECK_TOL['seed']:g} m for seed (the engines cut steps differently at
the seed map's jumps). Largest difference in this run: {dmax:.3g} m.

{xt}"""
    sl.finish(args, timer, body, "Block paths on a polar-orthotropic plane (paper 1, Fig. 1)")


def main(argv=None):
    args = sl.parse_args(NAME, __doc__.splitlines()[0], argv)
    timer = sl.Timer()
    compute(args)
    plot(args)
    report(args, timer)


if __name__ == "__main__":
    main()
