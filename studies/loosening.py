"""Loosening: the nut's bearing ring dragged across the plate while a torque turns it, its spin rate and
its slip onset against the ring integral, and the preloaded joint shaken across the bolt (its uniform
rings' rotation per slip path, the full nut's preload lost per radian), under step refinement (speed
against error); the full nut's departure from the uniform rings; a 1000-cycle run's ledger.

Usage: python studies/loosening.py [--quick] [--serial] [--out DIR]
"""
from __future__ import annotations

import os
import sys
import warnings

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)
from _lib.studylib import (Timer, finish, markdown_table, parse_args, plot_error_against_wall, read_table,  # noqa: E402
                           sweep, table)

from exu_aniso.scenes.loosening import LooseningParams  # noqa: E402

DTS = [1e-3, 4e-4, 2e-4, 1e-4, 5e-5]
FULL_DTS = [4e-4, 2e-4, 1e-4, 5e-5]
FULL = dict(case="joint", model="full")
ONSET = dict(drag="ramp", force_rate=1e3, t_end=1.14)      # the onset of the page: 2 N m, 1 kN/s
FOUR = 0.005 + 4 / 12.5                                    # four cycles of the shaking after the preload's rise
CASES = {   # case -> (its parameters beyond dt, the summary key held to its closed form)
    "spin": (dict(), "spin_rate"),
    "onset": (ONSET, "onset_force"),
    "joint_rings": (dict(case="joint", t_end=FOUR), "rotation_per_path"),
    "joint_full": (dict(FULL, t_end=0.005 + 8 / 12.5), "preload_loss_per_radian"),
}


def run_case(c):
    """One Exudyn run: the measured value, its closed form, the relative error, the cost."""
    from exu_aniso.models.loosening import RunLoosening
    kw, key = CASES[c["case"]]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = RunLoosening(LooseningParams(dt=c["dt"], **kw)).summary
    m, t = s[key], s[key + "_theory"]
    nan = float("nan")
    return dict(measured=nan if m is None else m, theory=t, error=nan if m is None else (m - t) / abs(t),
                residual=s["energy"]["residual"], ok=s["energy_ok"], wall=s["wall_s"], steps=s["steps"])


COLS = ["case [-]", "dt [s]", "measured [-]", "theory [-]", "error [-]", "energy_residual [-]", "wall [s]",
        "steps [-]"]


def main(argv=None):
    args = parse_args("loosening", __doc__.splitlines()[0], argv)
    timer = Timer()
    dts = DTS[1:4] if args.quick else DTS
    full_dts = FULL_DTS[:2] if args.quick else FULL_DTS
    cases = ([dict(case=k, dt=dt) for k in ("spin", "onset", "joint_rings") for dt in dts]
             + [dict(case="joint_full", dt=dt) for dt in full_dts])
    out = sweep(run_case, cases, args)
    wedge = [dict(model=m, flank_angle=b) for b in (0.0, 60.0) for m in ("rings", "full")]
    departure = sweep(run_departure, wedge, args)
    cycles = 20 if args.quick else 1000        # the quick form: one short run
    long = run_long(dict(cycles=cycles))
    dep_path = table(os.path.join(args.out, "departure.csv"), DEP_COLS,
                     [[c["flank_angle"], c["model"]] + [o[k] for k in DEP_KEYS] for c, o in zip(wedge, departure)])
    long_path = table(os.path.join(args.out, "long_run.csv"), LONG_COLS,
                      [["joint rings", cycles, long["steps"], long["rotation"], long["residual"], long["ok"]]])
    path = table(os.path.join(args.out, "refinement.csv"), COLS,
                 [[c["case"], c["dt"], o["measured"], o["theory"], o["error"], o["residual"], o["wall"], o["steps"]]
                  for c, o in zip(cases, out)])
    T = read_table(path)
    rows = [[T[c][i] for c in COLS] for i in range(len(cases))]
    fig = plot_error_against_wall(args.out, "refinement.csv", "case [-]", tuple(CASES), "loosening.png")
    D, L = read_table(dep_path), read_table(long_path)
    p = LooseningParams()
    closes = "within" if L["energy_ok [-]"][0] else "OUTSIDE"
    body = f"""
Scene: `exu_aniso/scenes/loosening.py` (LooseningParams; Exudyn model `exu_aniso/models/loosening.py`), its case
`bearing`: an M10 nut's bearing ring ({p.points} points on r_K = {1e3 * p.bearing_radius:g} mm) pressed by
{p.preload:g} N, mu = {p.mu_bearing:g}, turned by {p.torque:g} N m; the closed forms are the ring integral of
Coulomb friction (`exu_aniso/scenes/threads.py`).

* **spin**: dragged across at {p.slip_speed:g} m/s (`exu-aniso run loosening --set dt=DT`): the spin rate
  [rad/s] over the run's last half against omega = s v / r with G(s) = T / (mu N r);
* **onset**: pushed by a force rising at 1 kN/s (`--set drag=ramp --set force_rate=1e3 --set t_end=1.14`):
  the force [N] at which the ring runs away (1 cm/s) against mu N D(G^-1(T / (mu N r))).

* **joint_rings**: the joint (`--set case=joint`: the nut shaken by {1e3 * p.shake_displacement:g} mm at
  {p.shake_frequency:g} Hz, an M10 60 degree thread, mu {p.mu_thread:g} / {p.mu_bearing:g}), its uniform rings
  over four cycles: the rotation per metre of slip path against the torque balance of two sliding rings;
* **joint_full**: the nut on the bolt's helicoid and the plate on the joint's spring ({p.joint_stiffness:g}
  N/m), eight cycles: the preload lost per radian against the
  joint's and the contacts' stiffness times P / (2 pi).

{markdown_table(COLS, rows, fmt="{:.5g}")}
![error against wall time](./{fig})

{verdict(T)}

**The full nut against the uniform rings** (four cycles at dt {p.dt:g} s):
the rotation per cycle and per metre of slip path (over the intervals where no point of either ring sticks,
and over the whole path), the sliding share of the time, the thread's open share of its point-samples and the
flank's load spread ((max - min) / mean over its points at the cycles' ends).

{markdown_table(DEP_COLS, [[D[c][i] for c in DEP_COLS] for i in range(len(wedge))], fmt="{:.4g}")}

**A {cycles}-cycle run** (`exu-aniso run loosening --set case=joint --set t_end={0.005 + cycles / 12.5:g}`, the
default rings model at dt {p.dt:g} s): {int(L["steps [-]"][0])} steps; the nut turns {L["rotation [rad]"][0]:.1f} rad,
for the rings hold their loads (the full nut comes loose long before), and the energy ledger's residual is at most
{L["energy_residual [-]"][0]:.2g} of the largest energy term ({closes} its tolerance).
Its speed against Exudyn's C++ springs is in the benchmark's section "A long run" (`python studies/benchmarks.py`).
"""
    finish(args, timer, body, "Loosening: a bearing ring's spin and slip onset against the ring integral")
    return 0


DEP_KEYS = ["rotation_per_cycle", "rotation_per_path", "rotation_per_path_all", "rotation_per_path_theory",
            "sliding_share", "thread_open_share", "flank_load_spread"]
DEP_COLS = ["flank_angle [deg]", "model [-]", "rotation_per_cycle [rad]", "rotation_per_path [rad/m]",
            "rotation_per_path_all [rad/m]", "rotation_per_path_theory [rad/m]", "sliding_share [-]",
            "thread_open_share [-]", "flank_load_spread [-]"]
LONG_COLS = ["model [-]", "cycles [-]", "steps [-]", "rotation [rad]", "energy_residual [-]", "energy_ok [-]"]


def run_departure(c):
    """The rings and the full nut over four cycles: the summary's keys DEP_KEYS."""
    from exu_aniso.models.loosening import RunLoosening
    kw = FULL if c["model"] == "full" else dict(case="joint")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = RunLoosening(LooseningParams(flank_angle=c["flank_angle"], t_end=FOUR, **kw)).summary
    return {k: s[k] for k in DEP_KEYS}


def run_long(c):
    """The long run of the default joint (``cycles`` cycles): its steps, its turn and its ledger."""
    from exu_aniso.models.loosening import RunLoosening
    s = RunLoosening(LooseningParams(case="joint", t_end=0.005 + c["cycles"] / 12.5)).summary
    return dict(steps=s["steps"], rotation=s["rotation"], residual=s["energy"]["residual"], ok=s["energy_ok"])


def unresolved(T):
    """The joint rings' steps that do not resolve the shaking: where the error exceeds 1e-3, with the
    ledger's residual."""
    bad = [(T["dt [s]"][i], T["error [-]"][i], T["energy_residual [-]"][i]) for i, c in enumerate(T["case [-]"])
           if c == "joint_rings" and not abs(T["error [-]"][i]) < 1e-3]
    if not bad:
        return "every step resolves the shaking."
    return " ".join(f"at dt {dt:g} s the step does not resolve the nut's reversals: it lies {e:+.3g} off, and its "
                    f"energy ledger, open by {r:.3g}, warns." for dt, e, r in bad)


def verdict(T):
    """The report's reading of the table, from its numbers."""
    def rows(case):
        return [(T["dt [s]"][i], T["error [-]"][i], T["wall [s]"][i]) for i, c in enumerate(T["case [-]"]) if c == case]
    spin = rows("spin")
    onset = [abs(e) for _, e, _ in rows("onset")]
    rings, full = rows("joint_rings"), rows("joint_full")
    walls = [w for _, _, w in spin]
    floor = min(abs(e) for _, e, _ in spin)
    return (f"The spin rate's error falls with the step to a floor of {floor:.2g}, while every solve takes "
            f"{1e3 * min(walls):.0f} to {1e3 * max(walls):.0f} ms: the step costs nothing to speak of here, so the "
            f"default takes dt = {LooseningParams().dt:g} s, where the error has reached its floor. The onset "
            f"lies within {max(onset):.2g} of its closed form at every step: what limits it is the runaway "
            f"speed that marks it (1 cm/s) and the force's rise, not the step. The joint's uniform rings meet "
            f"their torque balance within {max(abs(e) for dt, e, _ in rings if dt <= 4e-4):.2g} at dt 4e-4 and below, "
            f"so the default dt serves them too; " + unresolved(T) + " The full nut's preload loss per radian lies "
            + ", ".join(f"{e:+.2g} at {dt:g} s" for dt, e, _ in full)
            + " off its closed form (a line through eight cycle ends).")


if __name__ == "__main__":
    sys.exit(main())
