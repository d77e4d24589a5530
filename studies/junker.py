"""Junker: the loosening's joint on a flexible shank (Timoshenko beam elements, clamped at the head and
guided at the nut) shaken across at the plate, as a Junker test shakes it: the critical amplitude
against preload, friction and clamp length beside its closed form, against the shank lumped at its end
without shear, and against the number of elements; the loosening rate against the amplitude on a square
and a 60 degree thread.

Usage: python studies/junker.py [--quick] [--serial] [--out DIR]
"""
from __future__ import annotations

import os
import sys
import time
import warnings

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)
from _lib.studylib import Timer, finish, markdown_table, parse_args, read_table, sweep, table  # noqa: E402

import numpy as np  # noqa: E402

from exu_aniso.scenes.bolted_joint import joint_closed_forms, shank_matrices  # noqa: E402
from exu_aniso.scenes.loosening import LooseningParams  # noqa: E402

BASE = dict(case="joint", model="full", shank="fe_beam")
BISECTIONS = 9
QUICK_BISECTIONS = 7            # --quick: from a bracket of +-10 % about the closed form (the full form's is +-50 %)
RATE_CYCLES, QUICK_RATE_CYCLES = 8, 4
CONVERGED_ELEMENTS = 64         # the shank's eigenfrequency's reference


def _run(**values):
    from exu_aniso.models.loosening import RunLoosening
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return RunLoosening(LooseningParams(**{**BASE, **values})).summary


def first_frequency(p):
    """The lowest eigenfrequency [Hz] of the shank with the bolt's end (bolt_mass at its guided end) in
    one plane: from the shank's matrices (``bolted_joint.shank_matrices``), no Exudyn."""
    M, _, K, tip = shank_matrices(p)
    m = M.shape[0] // 2
    M = M[:m, :m].copy()
    M[tip[0], tip[0]] += p.bolt_mass
    return float(np.sqrt(np.linalg.eigvals(np.linalg.solve(M, K[:m, :m])).real.min()) / (2.0 * np.pi))


def critical(c):
    """The plate's shift at the bearing's slip onset, bracketed by bisecting the shaker's amplitude over
    BISECTIONS two-cycle runs (the largest shift of a run whose ring never slid whole, the smallest of
    one whose ring did), against mu_K F (1 / k_shank + 1 / k_stick); c["quick"]: QUICK_BISECTIONS from a
    narrower start."""
    values = dict(preload=c["preload"], mu_bearing=c["mu"], mu_thread=c["mu"], clamp_length=c["clamp_length"],
                  shank=c["shank"], shank_elements=c["elements"], t_end=0.005 + 2 / 12.5)
    p = LooseningParams(**{**BASE, **values})
    theory = joint_closed_forms(p)["critical_amplitude_theory"]
    spring = p.mu_bearing * p.preload / p.drag_stiffness          # the shaker's spring stretches by this at the onset
    width, bisections = (0.1, QUICK_BISECTIONS) if c.get("quick") else (0.5, BISECTIONS)
    lo, hi = [(1.0 - width) * theory, None], [(1.0 + width) * theory + 2.0 * spring, None]
    t0 = time.perf_counter()
    for _ in range(bisections):
        mid = 0.5 * (lo[0] + hi[0])
        s = _run(shake_displacement=mid, **values)
        (hi if s["bearing_slid"] else lo)[:] = [mid, s["plate_amplitude"]]
    nan = float("nan")
    measured = 0.5 * (lo[1] + hi[1]) if lo[1] is not None and hi[1] is not None else nan
    return dict(below=nan if lo[1] is None else lo[1], above=nan if hi[1] is None else hi[1], measured=measured,
                theory=theory, error=(measured - theory) / theory, wall=time.perf_counter() - t0,
                frequency=first_frequency(p))


def task(c):
    """A case of the study's sweep: c["task"] is "critical" or "rate"."""
    return TASKS[c["task"]](c)


def rate(c):
    """c["cycles"] cycles at the shaker's amplitude: the turn per cycle, the rings' sliding shares, the
    preload at the end."""
    s = _run(flank_angle=c["flank"], shake_displacement=c["amplitude"], t_end=0.005 + c["cycles"] / 12.5)
    return dict(plate=s["plate_amplitude"], per_cycle=s["rotation_per_cycle"], thread=s["thread_slip_share"],
                bearing=s["bearing_slip_share"], preload=s["preload_end"], ok=s["energy_ok"])


TASKS = {"critical": critical, "rate": rate}
CRIT_COLS = ["shank [-]", "preload [N]", "mu [-]", "clamp_length [m]", "below [m]", "above [m]", "measured [m]",
             "theory [m]", "error [-]", "wall [s]"]
ELEMENT_COLS = ["shank_elements [-]", "measured [m]", "error [-]", "run_wall [s]", "first_frequency [Hz]",
                "frequency_error [-]"]
TIMED_REPEATS = 3


def run_walls(counts, repeats):
    """The wall time [s] of one two-cycle run shaken by 80 um (above the default joint's onset) for each
    element count: the median of ``repeats`` runs made in this process, interleaved (one count after the
    other, repeated)."""
    walls = {n: [] for n in counts}
    for _ in range(repeats):
        for n in counts:
            walls[n].append(_run(shank_elements=n, shake_displacement=8e-5, t_end=0.005 + 2 / 12.5)["wall_s"])
    return {n: float(np.median(w)) for n, w in walls.items()}


RATE_COLS = ["flank_angle [deg]", "amplitude [m]", "plate_amplitude [m]", "rotation_per_cycle [rad]",
             "thread_slip_share [-]", "bearing_slip_share [-]", "preload_end [N]", "energy_ok [-]"]


def main(argv=None):
    args = parse_args("junker", __doc__.splitlines()[0], argv)
    timer = Timer()
    p = LooseningParams(**BASE)
    base = dict(preload=p.preload, mu=p.mu_bearing, clamp_length=p.clamp_length, shank="fe_beam",
                elements=p.shank_elements)
    grid = ([{**base, "preload": F, "mu": mu} for F in (5e3, 1e4, 1.5e4) for mu in (0.08, 0.12, 0.16)]
            + [{**base, "clamp_length": L} for L in (0.02, 0.045)]
            + [{**base, "clamp_length": L, "shank": "guided_beam"} for L in (0.02, p.clamp_length, 0.045)])
    refined = [{**base, "elements": n} for n in (2, 4, 8)]
    amplitudes = (6e-5, 1.1e-4) if args.quick else (4e-5, 6e-5, 8e-5, 1.1e-4, 1.5e-4, 2e-4)
    if args.quick:
        grid, refined = [dict(g, quick=True) for g in grid[4:5] + grid[-2:-1]], [dict(refined[0], quick=True)]
    cycles = QUICK_RATE_CYCLES if args.quick else RATE_CYCLES
    shakes = [dict(flank=b, amplitude=a, cycles=cycles) for b in (0.0, 60.0) for a in amplitudes]
    found = sweep(task, [dict(c, task="critical") for c in grid + refined] + [dict(c, task="rate") for c in shakes],
                  args)                           # one pool for both
    crit, fine, rates = found[:len(grid)], found[len(grid):len(grid) + len(refined)], found[len(grid) + len(refined):]
    cpath = table(os.path.join(args.out, "critical_amplitude.csv"), CRIT_COLS,
                  [[c["shank"], c["preload"], c["mu"], c["clamp_length"], o["below"], o["above"], o["measured"],
                    o["theory"], o["error"], o["wall"]] for c, o in zip(grid, crit)])
    reference = first_frequency(LooseningParams(**{**BASE, "shank_elements": CONVERGED_ELEMENTS}))
    at_base = sorted(((c["elements"], o) for c, o in zip(grid + refined, crit + fine)
                      if {k: v for k, v in c.items() if k != "quick"} == {**base, "elements": c["elements"]}),
                     key=lambda row: row[0])
    walls = run_walls([n for n, _ in at_base], 1 if args.quick else TIMED_REPEATS)
    epath = table(os.path.join(args.out, "shank_elements.csv"), ELEMENT_COLS,
                  [[n, o["measured"], o["error"], walls[n], o["frequency"], o["frequency"] / reference - 1.0]
                   for n, o in at_base])
    rpath = table(os.path.join(args.out, "loosening_rate.csv"), RATE_COLS,
                  [[c["flank"], c["amplitude"], o["plate"], o["per_cycle"], o["thread"], o["bearing"], o["preload"],
                    o["ok"]] for c, o in zip(shakes, rates)])
    C, E, R = read_table(cpath), read_table(epath), read_table(rpath)
    body = f"""
Scene: `exu_aniso/scenes/loosening.py`, its joint (`exu_aniso/scenes/bolted_joint.py`) with the full nut on a
flexible shank: `exu-aniso run loosening --set case=joint --set model=full --set shank=fe_beam`. An M10 bolt's
threaded end moves across on its shank, {p.shank_elements} Timoshenko beam element(s) of {1e3 * p.clamp_length:g} mm
({1e3 * p.shank_diameter:g} mm, E {p.youngs_modulus:g} Pa, nu {p.poissons_ratio:g}) clamped at the head and guided at
the nut, and the plate is shaken at {p.shake_frequency:g} Hz. `shank=guided_beam` lumps the shank at its end on
12 E I / L^3, without shear.

**The critical amplitude** (two cycles a run; the shaker's amplitude bisected
{QUICK_BISECTIONS if args.quick else BISECTIONS} times): the plate's
largest shift in the last run whose bearing ring never slid as a whole (below) and in the first whose ring did
(above), their mean against mu_K F (1 / k_shank + 1 / k_stick) (theory), with k_shank the guided beam's lateral
stiffness, 1 / (L^3 / (12 E I) + L / (kappa G A)) for the elements, 12 E I / L^3 for the lumped shank.

{markdown_table(CRIT_COLS, [[C[c][i] for c in CRIT_COLS] for i in range(len(grid))], fmt="{:.4g}")}

{crit_verdict(C)}

**The shank's elements** (the default joint; speed against error): the bracketed onset and its error against
the closed form, the wall time of one two-cycle run at 80 um (the median of {TIMED_REPEATS} interleaved runs in one
process; `wall_s` of the run's summary, the solve alone), and the lowest eigenfrequency of the shank with the bolt's
end against {CONVERGED_ELEMENTS} elements' ({reference:.6g} Hz).

{markdown_table(ELEMENT_COLS, [[E[c][i] for c in ELEMENT_COLS] for i in range(len(E[ELEMENT_COLS[0]]))],
                fmt="{:.4g}")}

{element_verdict(E, p)}

**The loosening rate against the amplitude** ({cycles} cycles at mu {p.mu_bearing:g}, {p.preload:g} N):

{markdown_table(RATE_COLS, [[R[c][i] for c in RATE_COLS] for i in range(len(shakes))], fmt="{:.4g}")}

{rate_verdict(R, C)}

**Beside published Junker tests.** Junker (SAE Technical Paper 690055, 1969) shook joints across on the machine
that carries his name and found that they loosen once the transverse displacement makes the joint slip
completely in its bearing face and thread, that this critical displacement grows with the preload and with a
more elastic (longer, thinner) bolt, and that above it the loosening speeds up with the amplitude. Yamamoto and
Kasei (Bulletin of the Japan Society of Precision Engineering 18, 1984) explained the turning by the torque
balance of the pitch against the thread's and bearing's friction while both slide sideways (the scene's
`model=rings`). Pai and Hess (Engineering Failure Analysis 9, 2002) showed with finite elements that
localized slip below complete slip also turns a nut loose, slowly. The model reproduces the critical
amplitude at the bearing, its growth with preload, friction and clamp length, and on the square thread the
loosening above it that grows with the amplitude; below it the nut turns by micro-slip only (above). It does
not reproduce the 60 degree thread loosening through the bolt's bending: the model's flanks have no radial play and the guided shank's end does not tilt in the nut, the two ways a real bolt's
thread slips. Nor does it model wear or fretting of the faces, the settling (embedding) of the preload, a
yielding thread, or friction that changes over the cycles.
"""
    finish(args, timer, body, "Junker: the critical amplitude of a flexible bolt and the loosening above it")
    return 0


def element_verdict(E, p):
    """The report's reading of the elements' table, from its numbers."""
    n, m, f = E["shank_elements [-]"], E["measured [m]"], E["frequency_error [-]"]
    spread = (max(m) - min(m)) / m[0]
    return (f"From {n[0]:g} to {n[-1]:g} elements the onset moves by {spread:.2g} of its value and the lowest "
            f"eigenfrequency by {abs(f[0]):.2g}: the element is exact for a beam loaded at its ends only, and at "
            f"{p.shake_frequency:g} Hz the shank's mass does not count. The default, `shank_elements` "
            f"{p.shank_elements}, is the cheapest right model.")


def crit_verdict(C):
    """The report's reading of the critical amplitudes, from its numbers."""
    d = LooseningParams()
    rows = list(zip(C["shank [-]"], C["preload [N]"], C["mu [-]"], C["clamp_length [m]"], C["measured [m]"],
                    C["error [-]"]))
    beam = [r for r in rows if r[0] == "fe_beam"]
    by_mu = {}
    for _, _, mu, L, _, e in beam:
        if L == d.clamp_length:
            by_mu.setdefault(mu, []).append(e)
    mus = ", ".join(f"{min(v):+.2g} to {max(v):+.2g} at mu {mu:g}" for mu, v in sorted(by_mu.items()))
    lengths = "".join(f", {e:+.2g} at {1e3 * L:g} mm" for _, _, _, L, _, e in beam if L != d.clamp_length)
    at = {(s, L): (m, e) for s, F, mu, L, m, e in rows if F == d.preload and mu == d.mu_bearing}
    both = sorted(L for s, L in at if s == "guided_beam" and ("fe_beam", L) in at)
    shear = ", ".join(f"{at[('fe_beam', L)][0] / at[('guided_beam', L)][0]:.3f} at {1e3 * L:g} mm" for L in both)
    lumped = ", ".join(f"{at[('guided_beam', L)][1]:+.2g} at {1e3 * L:g} mm" for L in both)
    ratios = [at[("fe_beam", L)][0] / at[("guided_beam", L)][0] for L in both]
    shorter = (", the more the shorter the shank, where shear takes a larger share of the end's shift"
               if len(ratios) > 1 and all(a > b for a, b in zip(ratios, ratios[1:])) else "")
    return (f"On the elements the bracketed onset lies {mus} off the closed form at the {1e3 * d.clamp_length:g} mm "
            f"shank (the same share at every preload: linear in F){lengths}; from "
            f"{1e6 * min(r[4] for r in beam):.1f} to {1e6 * max(r[4] for r in beam):.1f} um. The shank's shear "
            f"raises the onset over the lumped shank's by a factor {shear}{shorter}; the lumped shank meets its own "
            f"closed form ({lumped}). The "
            f"closed form leaves out two things. The bearing ring holds part of the pitch's torque in its elastic "
            f"stick when the shaking starts (the nut twists until both rings share F P / (2 pi)), and a ring that "
            f"holds a torque slides under less force than mu F, the more so as mu falls: the onset comes early at "
            f"low mu. And the thread gives a little sideways between the nut and the bolt's end, which counts the "
            f"more the stiffer the shank.")


def rate_verdict(R, C):
    """The report's reading of the loosening rates, from its numbers (C: the critical amplitudes')."""
    d = LooseningParams(**BASE)
    onset = next(m for s, F, mu, L, m in zip(C["shank [-]"], C["preload [N]"], C["mu [-]"], C["clamp_length [m]"],
                                             C["measured [m]"])
                 if (s, F, mu, L) == (d.shank, d.preload, d.mu_bearing, d.clamp_length))
    rows = list(zip(R["flank_angle [deg]"], R["plate_amplitude [m]"], R["rotation_per_cycle [rad]"]))
    square = [r for b, _, r in rows if b == 0.0]
    metric = [r for b, _, r in rows if b == 60.0]
    below = [abs(r) for _, a, r in rows if a < onset]
    return (f"On the square thread the nut turns loose by {max(square):.3g} rad per cycle at the largest amplitude and "
            f"by {min(square):.3g} at the smallest; on the 60 degree thread at most by {max(map(abs, metric)):.2g} rad "
            f"per cycle at any amplitude: its thread does not slip. Below the critical amplitude (the plate's shift "
            f"under {1e6 * onset:.1f} um) the nut turns by at most {max(below):.2g} rad per cycle on either thread.")


if __name__ == "__main__":
    sys.exit(main())
