"""The figures the documentation quotes, against their result files and rerun.

    python studies/claims.py [--rerun] [--quick] [--out DIR]

Two kinds of figure. A **speed figure** is quoted as "median [min-max]" of interleaved repeats (the
speed targets and the command line's cost on docs/guide/speed.md, the Newton settings on
docs/guide/settings.md, the native callbacks' table on docs/native_callbacks.md) with the row of a
committed result file it comes from (the file names the command that makes it). A **run figure**
is a number of one ``exu-aniso run ...`` summary.json quoted in the text (``RUNS``): the runs are
deterministic, a repeat gives the same digits, so it has no spread. Without ``--rerun`` this checks
that every page quotes its file as it stands and says every run figure as registered; with
``--rerun`` it also runs each speed claim's study afresh (``python studies/STUDY.py --out
DIR/STUDY``, ``--quick`` for the short form, whose figures are not comparable) and prints the new
median beside the quoted one with whether it lands inside the quoted spread, and runs each command
line once and prints its figure beside the quoted digits (exit 1 when they differ). Speed figures
move with the machine's load (up to about 10 % on a ratio from hour to hour on the 2-core machine of
the figures), so a rerun can land outside the spread of a quiet hour; the spread says how far one
run of the command scatters. docs/RESULTS.md is not listed here: it is generated whole by
``python studies/run_all.py``, every section naming its command. Writes ``claims.csv`` and
``report.md`` with ``--rerun`` (default ``studies/results/claims``).
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import subprocess
import sys
from dataclasses import dataclass

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


@dataclass(frozen=True)
class Claim:
    """A quoted figure: the page, the study and its result file, the row (key column, value; more
    pairs in ``also``), the figure's column (its _min and _max beside it), how the page prints it
    and the factor from the file's unit to the page's."""
    page: str
    study: str
    file: str
    key: str
    row: str
    column: str
    fmt: str = "{:.2f}"
    also: tuple = ()
    scale: float = 1.0
    spread: tuple = ()      # the min and max columns when they are not COLUMN_min, COLUMN_max

    def columns(self):
        """The file's median, min and max columns of the figure."""
        if self.spread:
            return (self.column,) + tuple(self.spread)
        base, unit = self.column.rsplit(" ", 1)
        return tuple(f"{base}{s} {unit}" for s in ("", "_min", "_max"))


@dataclass(frozen=True)
class RunClaim:
    """A figure of one command line run, quoted on a page: ``exu-aniso run ARGS`` and the value
    ``value(summary)`` of its summary.json, printed with ``fmt`` where ``{}`` stands in ``text``
    (the page's words around it). The runs are deterministic: a repeat on one machine gives the same
    digits (they move with the versions of Exudyn, numpy and numba), so the figure has no spread and
    ``quoted`` is its digits as the page prints them."""
    page: str
    args: tuple
    text: str
    quoted: str
    value: object
    fmt: str

    def command(self):
        return "exu-aniso run " + " ".join(self.args)


SPEED = "docs/guide/speed.md"
_TARGET_ROWS = ["full block, 4 corners", "full block, 8 x 8 grid", "64 cubes, one contact set each",
                "64 cubes, one group", "64 cubes, one group, undamped (the corners chatter)",
                "one contact set each: per body, 64 / 8 cubes", "one group: per body, 64 / 8 cubes",
                "reduced screw (default ScrewParams)", "moving master (full block, 4 corners, on a free plate)",
                "the moving master's plate alone: the fixed-plane block with the free plate beside it",
                "moving master against the same two bodies with the contact on the fixed plane",
                "user's 4-point body in a spherical bowl (Sphere)", "user's 4-point body down a conical trough (Cone)"]
CLAIMS = ([Claim(SPEED, "benchmarks", "targets.csv", "scene [-]", r, "ratio [-]") for r in _TARGET_ROWS]
          # the long run: the shaken joint for 1000 cycles, its CPU time [s] and ours over its yardstick's
          + [Claim(SPEED, "benchmarks", "long_run.csv", "model [-]", m, "cpu [s]", "{:.1f}", (("settings [-]", s),))
             for m, s in (("ours", "ours"), ("C++ springs", "exudyn"), ("C++ springs", "ours"), ("floor", "ours"))]
          + [Claim(SPEED, "benchmarks", "long_run.csv", "model [-]", m, "ours_over_this [-]", "{:.2f}",
                   (("settings [-]", s),), spread=("ratio_min [-]", "ratio_max [-]"))
             for m, s in (("C++ springs", "exudyn"), ("C++ springs", "ours"), ("floor", "ours"))]
          + [Claim(SPEED, "benchmarks", "targets.csv", "scene [-]",
                   "compiled call on the plane, as Exudyn makes it: " + part, "ours [us]", "{:.3f}")
             for part in ("fixed part [us]", "per point [us]")]
          + [Claim(SPEED, "cli_cost", "cli_cost.csv", "overrides [-]", r, c, f)
             for r in ("model=full points=corners", "model=full points=grid:8", "defaults")
             for c, f in (("total [us]", "{:.1f}"), ("ratio [-]", "{:.2f}"))]
          # the solver settings' table: us per step of each scene at each of five Newton settings
          + [Claim("docs/guide/settings.md", "newton_settings", "newton_settings.csv", "settings [-]", setting,
                   "cpu_per_step [s]", "{:.1f}", (("scene [-]", scene), ("model [-]", model), ("points [-]", points)),
                   1e6)
             for scene, model, points in (("block", "planar", "corners"), ("block", "full", "corners"),
                                          ("block", "full", "grid:8"), ("screw", "reduced", "3 x 8"),
                                          ("screw", "full", "3 x 8"))
             for setting in ("full_newton_1e-10", "package", "package_1e-8", "exudyn", "jacobian_per_step")]
          # the native callbacks' table: us per step with Python and with native callbacks
          + [Claim("docs/native_callbacks.md", "native_callbacks", "native_callbacks.csv", "scene [-]", scene,
                   f"{kind}_per_step [s]", "{:.1f}", (("layout [-]", layout),), 1e6,
                   (f"{kind}_min [s]", f"{kind}_max [s]"))
             for scene, layout in (("block", "corners"), ("block", "grid:8"), ("screw", "default"),
                                   ("particle", "default"))
             for kind in ("python", "native")])

_FASTENING = ("fastening",)
_UNTIGHTEN = ("fastening", "--set", "reverse_time=1.5", "--set", "t_end=1.7")
_NUTRUNNER = ("fastening", "--set", "tool=nutrunner", "--set", "shutoff_torque=20", "--set", "tool_inertia=1e-2",
              "--set")
_ONSET = ("loosening", "--set", "drag=ramp", "--set", "force_rate=1e3", "--set", "t_end=1.14")
_JOINT = ("loosening", "--set", "case=joint", "--set", "t_end=0.325")
_JOINT_SQUARE = ("loosening", "--set", "case=joint", "--set", "flank_angle=0", "--set", "t_end=0.645")
_FULL = ("loosening", "--set", "case=joint", "--set", "model=full", "--set", "t_end=0.645")
_FULL_SQUARE = _FULL + ("--set", "flank_angle=0")
_FULL_LOOSE = _FULL[:-1] + ("t_end=8.005",)
_COARSE = ("loosening", "--set", "case=joint", "--set", "dt=1e-3", "--set", "t_end=0.325")
_UM = dict(plate_amplitude=1e6, critical_amplitude_theory=1e6)     # the page's um
_BEAM = _FULL[:-1] + ("t_end=0.165", "--set", "shank=guided_beam", "--set")
_BEAM_LONG = _FULL[:-1] + ("t_end=0.645", "--set", "shank=guided_beam", "--set", "shake_displacement=110e-6")
_THREAD = _JOINT + ("--set", "mu_bearing=1e-6")
_FE_BEAM = _FULL[:-1] + ("t_end=0.165", "--set", "shank=fe_beam", "--set")
_FE_BEAM_LONG = _FULL[:-1] + ("t_end=0.645", "--set", "shank=fe_beam", "--set", "shake_displacement=110e-6")
_SOFT = _NUTRUNNER + ("rotation_speed=10", "--set", "joint_stiffness=2e6", "--set", "t_end=2.9")
_QUASI_STATIC = [("capstan", "--set", f"ramp_rate={r}", "--set", f"dt=2.5e-4/{r}", "--set", f"t_end={t}")
                 for r, t in (("5.5", "0.7"), ("12.4", "0.4"))]
_OFF_AXIS_B = ("particle", "--set", "adhesion=orthotropic", "--set", "eps_2=1e4", "--set", "net_angle=30", "--set")


def _nut_error(s):
    """The nut's descent acceleration off its closed form, as the page prints it (1.8e-5)."""
    return f"{abs(s['descent_acceleration'] / s['descent_acceleration_theory'] - 1):.1e}".replace("e-0", "e-")


def _feeder_error(s):
    """The feeder's transport velocity off its theory [%]."""
    return 100 * (s["transport_velocity"] / s["transport_velocity_theory"] - 1)


RUNS = [
    RunClaim("docs/guide/conventions.md", ("block", "--set", "return_map=exact"), "heading {} deg against", "90",
             lambda s: s["heading_deg"], "{:.0f}"),
    RunClaim("docs/guide/conventions.md", ("block",), "heading 90 deg against {} deg", "112.9",
             lambda s: s["heading_deg"], "{:.1f}"),
    RunClaim("docs/guide/scenes.md", _FASTENING, "T/F = {} mm", "1.66203",
             lambda s: 1e3 * s["torque_per_clamp_force"], "{:.5f}"),
    RunClaim("docs/guide/scenes.md", _FASTENING, "against the formula's {}", "1.66223",
             lambda s: 1e3 * s["torque_per_clamp_force_theory"], "{:.5f}"),
    RunClaim("docs/guide/scenes.md", _FASTENING, "seating at {} deg", "30.0112",
             lambda s: s["seating_angle"], "{:.4f}"),
    RunClaim("docs/guide/scenes.md", _FASTENING, "against the theory's {}", "30.0112",
             lambda s: s["seating_angle_theory"], "{:.4f}"),
    RunClaim("docs/guide/scenes.md", _FASTENING, "gives mu_thread {} for", "0.1211",
             lambda s: s["mu_thread_iso16047"], "{:.4f}"),
    RunClaim("docs/guide/scenes.md", _FASTENING, "tilt {} deg with either head", "0.0032",
             lambda s: s["tilt_max_deg"], "{:.4f}"),
    RunClaim("docs/guide/scenes.md", ("feeder",), "lies within 20 % of it: {} % on the defaults", "-12.3",
             lambda s: 100 * (s["transport_velocity"] / s["transport_velocity_theory"] - 1), "{:.1f}"),
    RunClaim("docs/guide/scenes.md", ("capstan",), "T_out / T_in = {} against", "2.5660",
             lambda s: s["tension_ratio"], "{:.4f}"),
    RunClaim("docs/guide/scenes.md", ("capstan",), "against exp(0.3 pi) = {}.", "2.5663",
             lambda s: s["tension_ratio_theory"], "{:.4f}"),
    RunClaim("docs/guide/scenes.md", ("fe_block",), "(`steer_end` {} m:", "0.00971",
             lambda s: s["steer_end"], "{:.5f}"),
    RunClaim("docs/guide/scenes.md", ("fe_block",), "`yaw_end` {} rad)", "0.196",
             lambda s: s["yaw_end"], "{:.3f}"),
    RunClaim("docs/guide/scenes.md", ("fe_block",), "the ledger closes to {} (polar B's", "1.1e-3",
             lambda s: f"{s['energy']['residual']:.1e}".replace("e-0", "e-"), "{}"),
    RunClaim("docs/guide/scenes.md", ("fe_screw",), "advance is {} mm per revolution", "5.48238",
             lambda s: 1e3 * s["advance_per_rev"], "{:.5f}"),
    RunClaim("docs/guide/scenes.md", ("fe_screw",), "and the mean torque {} N m (the", "0.098848",
             lambda s: s["torque_mean"], "{:.6f}"),
    RunClaim("docs/guide/scenes.md", ("fe_screw",), "{} times the closed form's 0.923", "1.00",
             lambda s: s["twist_ratio"], "{:.2f}"),
    RunClaim("docs/guide/scenes.md", ("fe_screw",), "the ledger closes to {}, solved in", "4.8e-7",
             lambda s: f"{s['energy']['residual']:.1e}".replace("e-0", "e-"), "{}"),
    RunClaim("docs/guide/command_line.md", ("capstan",), "(the capstan's default run: {} steps cut", "118",
             lambda s: s["step_reductions"], "{:d}"),
    RunClaim("docs/guide/command_line.md", ("capstan",), "steps cut between t = 0 and {} s", "0.0147",
             lambda s: s["reduced_between"][1], "{:.4f}"),
    RunClaim("docs/guide/command_line.md", ("capstan",), "dashpot, {} steps where", "2049",
             lambda s: s["steps"], "{:d}"),
    RunClaim("docs/guide/command_line.md", ("capstan",), "steps where {} were planned; `exu-aniso run capstan`", "1946",
             lambda s: s["nominal_steps"], "{:d}"),
    # where the closed forms hold: runs just outside their domains
    RunClaim("docs/guide/scenes.md", ("capstan", "--set", "bending_stiffness=3e-4"), "misses exp(0.3 pi) by {}e-3",
             "-1.11", lambda s: 1e3 * (s["tension_ratio"] / math.exp(0.3 * math.pi) - 1), "{:.2f}"),
    RunClaim("docs/guide/scenes.md", _QUASI_STATIC[0], "t_end=0.7` misses it by {}e-3", "+1.94",
             lambda s: 1e3 * (s["tension_ratio"] / math.exp(0.3 * math.pi) - 1), "{:+.2f}"),
    RunClaim("docs/guide/scenes.md", _QUASI_STATIC[1], "t_end=0.4` by {}e-3", "+2.44",
             lambda s: 1e3 * (s["tension_ratio"] / math.exp(0.3 * math.pi) - 1), "{:+.2f}"),
    RunClaim("docs/guide/scenes.md", ("feeder", "--set", "eps_1=8.1e6"), "(f_stick / f = 64) lies {} % off", "-3.84",
             _feeder_error, "{:.2f}"),
    RunClaim("docs/guide/scenes.md", ("feeder", "--set", "mu_1=0.9"), "mu_1=0.9`: {} %)", "-0.29", _feeder_error,
             "{:.2f}"),
    RunClaim("docs/guide/scenes.md", ("feeder", "--set", "normal_damping_ratio=2"), "lies {} % off; without it",
             "-11.7", _feeder_error, "{:.1f}"),
    RunClaim("docs/guide/scenes.md", ("feeder", "--set", "normal_damping_ratio=0"), "normal_damping_ratio=0`: {} %)",
             "-17.3", _feeder_error, "{:.1f}"),
    RunClaim("docs/guide/surfaces_and_fields.md", _OFF_AXIS_B + ("return_map=radial",), "leaves the sphere at {} deg",
             "47.61", lambda s: s["departure_angle_deg"], "{:.2f}"),
    RunClaim("docs/guide/surfaces_and_fields.md", _OFF_AXIS_B + ("return_map=seed",), "the seed map at {} deg",
             "46.58", lambda s: s["departure_angle_deg"], "{:.2f}"),
    RunClaim("docs/guide/surfaces_and_fields.md", ("particle",), "against the oracle's {} deg", "51.45",
             lambda s: s["departure_angle_deg_theory"], "{:.2f}"),
    RunClaim("docs/guide/surfaces_and_fields.md", ("particle", "--set", "tangential_damping=1e-3"),
             "tangential_damping=1e-3` leaves at {} deg", "51.497", lambda s: s["departure_angle_deg"], "{:.3f}"),
    # the nut
    RunClaim("docs/guide/scenes.md", ("nut",), "a descent acceleration of {} m/s^2", "-0.0069190",
             lambda s: s["descent_acceleration"], "{:.7f}"),
    RunClaim("docs/guide/scenes.md", ("nut",), "against the closed form's {}, 1.8e-5 off", "-0.0069189",
             lambda s: s["descent_acceleration_theory"], "{:.7f}"),
    RunClaim("docs/guide/scenes.md", ("nut",), "-0.0069189, {} off", "1.8e-5",
             _nut_error, "{}"),
    RunClaim("docs/guide/scenes.md", ("nut", "--set", "mu_thread=0.1"), "it holds (`held` {}:", "true",
             lambda s: "true" if s["held"] else "false", "{}"),
    RunClaim("docs/guide/scenes.md", ("nut", "--set", "model=full", "--set", "dt=1e-4"), "x 8 points) lies {} % off",
             "0.18", lambda s: 100 * abs(s["descent_acceleration"] / s["descent_acceleration_theory"] - 1), "{:.2f}"),
    # untightening
    RunClaim("docs/guide/scenes.md", _UNTIGHTEN, "breaks loose at {} N m", "26.4010", lambda s: s["break_loose_torque"],
             "{:.4f}"),
    RunClaim("docs/guide/scenes.md", _UNTIGHTEN, "N m under {} N against", "22297",
             lambda s: s["break_loose_clamp_force"], "{:.0f}"),
    RunClaim("docs/guide/scenes.md", _UNTIGHTEN, "the closed form's {} N m and", "26.4037",
             lambda s: s["break_loose_torque_theory"], "{:.4f}"),
    RunClaim("docs/guide/scenes.md", _UNTIGHTEN, "VDI 2230's {} N m", "26.5093",
             lambda s: s["break_loose_torque_vdi2230"], "{:.4f}"),
    # the nutrunner on a hard and a soft joint
    RunClaim("docs/guide/scenes.md", _NUTRUNNER + ("rotation_speed=5", "--set", "t_end=0.42"), "overshoots by {} N m",
             "3.0550", lambda s: s["torque_overshoot"], "{:.4f}"),
    RunClaim("docs/guide/scenes.md", _NUTRUNNER + ("rotation_speed=5", "--set", "t_end=0.42"),
             "omega sqrt(J k_T) = {} N m on a hard joint", "3.0737", lambda s: s["torque_overshoot_theory"], "{:.4f}"),
    RunClaim("docs/guide/scenes.md", _NUTRUNNER + ("rotation_speed=5", "--set", "t_end=0.42"),
             "hard joint ({} deg from half to full)", "14.86", lambda s: s["joint_angle_half_to_full"], "{:.2f}"),
    RunClaim("docs/guide/scenes.md", _SOFT, "a soft joint ({} deg)", "722.3", lambda s: s["joint_angle_half_to_full"],
             "{:.1f}"),
    RunClaim("docs/guide/scenes.md", _SOFT, "it overshoots by {} N m against", "0.8846",
             lambda s: s["torque_overshoot"], "{:.4f}"),
    RunClaim("docs/guide/scenes.md", _SOFT, "N m against {} N m (`tests", "0.8903",
             lambda s: s["torque_overshoot_theory"], "{:.4f}"),
    # the loosening's bearing ring
    RunClaim("docs/guide/scenes.md", ("loosening",), "spins at {} rad/s against", "1.481632",
             lambda s: s["spin_rate"], "{:.6f}"),
    RunClaim("docs/guide/scenes.md", ("loosening",), "ring integral's {} rad/s", "1.481631",
             lambda s: s["spin_rate_theory"], "{:.6f}"),
    RunClaim("docs/guide/scenes.md", _ONSET, "starts to slide at {} N against", "1125.2", lambda s: s["onset_force"],
             "{:.1f}"),
    RunClaim("docs/guide/scenes.md", _ONSET, "N against {} N. Shaken", "1124.7", lambda s: s["onset_force_theory"],
             "{:.1f}"),
    # the loosening's joint: the uniform rings against the torque balance, the full nut's preload and departure
    RunClaim("docs/guide/scenes.md", _COARSE + ("--set", "solver=trapezoidal"), "its energy ledger is open by {} and",
             "0.83", lambda s: s["energy"]["residual"], "{:.2f}"),
    *[RunClaim("docs/guide/scenes.md", args, text, quoted, (lambda k, f: lambda s: f * s[k])(key, _UM.get(key, 1.0)),
               fmt)
      for args, text, quoted, key, fmt in (
          (_JOINT, "(four cycles) turns {} rad per metre", "58.397", "rotation_per_path", "{:.3f}"),
          (_JOINT, "of slip path against the balance's {}, and", "58.368", "rotation_per_path_theory", "{:.3f}"),
          (_JOINT, "its loop's plateau is {} of the preload", "0.251683", "slide_force_per_preload", "{:.6f}"),
          (_JOINT, "of the preload against {}; the square", "0.251687", "slide_force_per_preload_theory", "{:.6f}"),
          (_JOINT_SQUARE, "--set t_end=0.645`) turns {} against", "61.165", "rotation_per_path", "{:.3f}"),
          (_JOINT_SQUARE, "turns 61.165 against {} (`tests", "61.119", "rotation_per_path_theory", "{:.3f}"),
          (_FULL, "dt 1e-4) loses {} N of preload", "23335", "preload_loss_per_radian", "{:.0f}"),
          (_FULL, "against the closed form's {} N/rad", "23328", "preload_loss_per_radian_theory", "{:.0f}"),
          (_FULL_SQUARE, "(`--set flank_angle=0`) {} against", "23404.5", "preload_loss_per_radian", "{:.1f}"),
          (_FULL_SQUARE, "23404.5 against {} (`tests", "23404.5", "preload_loss_per_radian_theory", "{:.1f}"),
          (_FULL_LOOSE, "a tenth) at cycle {}, and the run", "26.0", "cycles_to_loose", "{:.1f}"),
          (_FULL, "are open in {} of their samples", "0.62", "thread_open_share", "{:.2f}"),
          (_FULL_SQUARE, "({} on the square one)", "0.56", "thread_open_share", "{:.2f}"),
          (_FULL, "load spreads over {} times its mean", "1.55", "flank_load_spread", "{:.2f}"),
          (_FULL_SQUARE, "most loaded point ({}), and", "1.52", "flank_load_spread", "{:.2f}"),
          (_FULL, "no sticking point only {} of the time", "0.31", "sliding_share", "{:.2f}"),
          (_FULL_SQUARE, "of the time ({}). Per cycle", "0.45", "sliding_share", "{:.2f}"),
          (_FULL, "Per cycle it turns {} rad where", "0.0114", "rotation_per_cycle", "{:.4f}"),
          (_JOINT, "the uniform rings turn {} (square", "0.0395", "rotation_per_cycle", "{:.4f}"),
          (_FULL_SQUARE, "(square {} against 0.0419)", "0.0255", "rotation_per_cycle", "{:.4f}"),
          (_JOINT_SQUARE, "0.0255 against {}): the wedge", "0.0419", "rotation_per_cycle", "{:.4f}"),
          (_FULL, "path it turns {} rad/m against", "30.9", "rotation_per_path_all", "{:.1f}"),
          (_FULL_SQUARE, "(square {} against 61.1)", "33.6", "rotation_per_path_all", "{:.1f}"),
          (_FULL, "sideways force is {} of the preload", "0.821", "slide_force_per_preload", "{:.3f}"),
          (_COARSE, "--set t_end=0.325`) the rings turn {} rad per metre", "58.390", "rotation_per_path", "{:.3f}"),
          (_COARSE + ("--set", "solver=trapezoidal"), "the same run turns {}, its energy", "2826463", "rotation_per_path",
           "{:.0f}"),
          (_BEAM + ("shake_displacement=65e-6",), "shifts the plate by {} um and the ring never", "53.70",
           "plate_amplitude", "{:.2f}"),
          (_BEAM + ("shake_displacement=66e-6",), "66 um shifts it by {} um and it does", "54.57",
           "plate_amplitude", "{:.2f}"),
          (_BEAM + ("shake_displacement=65e-6",), "the closed form says {} um", "53.88",
           "critical_amplitude_theory", "{:.2f}"),
          (_BEAM_LONG, "the bearing slides in {} of its point-samples", "0.43", "bearing_slip_share", "{:.2f}"),
          (_BEAM_LONG, "and the nut turns {} rad in all", "0.00033", "rotation", "{:.5f}"),
          (_BEAM_LONG + ("--set", "flank_angle=0"), "at the thread too ({} of its point-samples)", "0.48",
           "thread_slip_share", "{:.2f}"),
          (_BEAM_LONG + ("--set", "flank_angle=0"), "turns loose by {} rad per cycle", "0.0042",
           "rotation_per_cycle", "{:.4f}"),
          (_THREAD, "--set case=joint --set mu_bearing=1e-6 --set t_end=0.325` slides at {} F", "0.119285",
           "slide_force_per_preload", "{:.6f}"),
          (_THREAD, "h: {} F.", "0.119272", "slide_force_per_preload_theory", "{:.6f}"),
          (_THREAD + ("--set", "flank_angle=0"), "flank_angle=0`: {} against", "0.098066", "slide_force_per_preload",
           "{:.6f}"),
          (_THREAD + ("--set", "flank_angle=0"), "against {}) and turns", "0.098014",
           "slide_force_per_preload_theory", "{:.6f}"),
          (_THREAD, "and turns {} rad per metre of slip path against", "156.57", "rotation_per_path", "{:.2f}"),
          (_THREAD, "rad per metre of slip path against {}. Shaken", "156.67", "rotation_per_path_theory", "{:.2f}"),
          (_THREAD[:-3] + ("t_end=0.645", "--set", "mu_bearing=1e-6", "--set", "shake_displacement=3e-6"),
           "and the nut turns {} rad per cycle (", "4.3e-19", "rotation_per_cycle", "{:.1e}"),
          (_FE_BEAM + ("shake_displacement=73e-6",), "rises to {} um", "62.54", "critical_amplitude_theory",
           "{:.2f}"),
          (_FE_BEAM + ("shake_displacement=73e-6",), "shifts the plate by {} um and the ring never slides whole",
           "61.72", "plate_amplitude", "{:.2f}"),
          (_FE_BEAM + ("shake_displacement=74e-6",), "74 um shifts it by {} um and it does (", "62.60",
           "plate_amplitude", "{:.2f}"),
          (_FE_BEAM_LONG, "(the nut turns {} rad in all)", "0.00033", "rotation", "{:.5f}"),
          (_FE_BEAM_LONG + ("--set", "flank_angle=0"), "turns loose by {} rad per cycle, against the lumped",
           "0.0035", "rotation_per_cycle", "{:.4f}"),
      )],
]


def _read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def figure(rows, claim):
    """(median, min, max) of the claim's row in the rows of its file."""
    for r in rows:
        if r[claim.key] == claim.row and all(r[k] == v for k, v in claim.also):
            return tuple(claim.scale * float(r[c]) for c in claim.columns())
    raise KeyError(f"{claim.file}: no row {claim.key} = {claim.row!r} {dict(claim.also)}")


def quoted_text(claim, values):
    med, lo, hi = (claim.fmt.format(v) for v in values)
    return f"{med} [{lo}-{hi}]"


def _words(text):
    """The text with every run of white space one blank (a page breaks its lines anywhere)."""
    return " ".join(text.split())


def _page(pages, name):
    if name not in pages:
        with open(os.path.join(ROOT, name)) as f:
            pages[name] = _words(f.read())
    return pages[name]


def check_runs():
    """[(run claim, the page's text with the quoted figure, found on the page)] for every run claim."""
    pages = {}
    return [(c, c.text.format(c.quoted), c.text.format(c.quoted) in _page(pages, c.page)) for c in RUNS]


def rerun_runs(out_dir):
    """Run each run claim's command once (one run per distinct command) into out_dir/runs/K;
    [(run claim, the figure as the page would print it now)]."""
    summaries = {}
    for args in dict.fromkeys(c.args for c in RUNS):
        folder = os.path.join(out_dir, "runs", str(len(summaries)))
        cmd = [sys.executable, "-c", "import sys; from exu_aniso.cli import main; sys.exit(main())",
               "run", *args, "--out", folder]
        print("claims: exu-aniso " + " ".join(cmd[3:]), flush=True)
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(folder, "summary.json")) as f:
            summaries[args] = json.load(f)
    return [(c, c.fmt.format(c.value(summaries[c.args]))) for c in RUNS]


def check_pages(results=os.path.join(ROOT, "docs", "results")):
    """[(claim, quoted (median, min, max), the text, found on the page)] for every claim."""
    out, pages, files = [], {}, {}
    for c in CLAIMS:
        page = _page(pages, c.page)
        rows = files.setdefault((c.study, c.file), _read(os.path.join(results, c.study, c.file)))
        values = figure(rows, c)
        text = quoted_text(c, values)
        out.append((c, values, text, text in page))
    return out


def rerun(out_dir, quick):
    """Run each claim's study once into out_dir/STUDY; {study: its output folder}."""
    done = {}
    for study in dict.fromkeys(c.study for c in CLAIMS):
        folder = os.path.join(out_dir, study)
        cmd = [sys.executable, os.path.join(HERE, f"{study}.py"), "--out", folder] + (["--quick"] if quick else [])
        print("claims: " + " ".join(cmd), flush=True)
        subprocess.run(cmd, check=True)
        done[study] = folder
    return done


def main(argv=None):
    ap = argparse.ArgumentParser(prog="studies/claims.py", description=__doc__.splitlines()[0])
    ap.add_argument("--rerun", action="store_true", help="run the studies and the command lines afresh and compare")
    ap.add_argument("--quick", action="store_true", help="with --rerun: the studies' short forms (not comparable)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "claims"))
    a = ap.parse_args(argv)
    checked, runs = check_pages(), check_runs()
    missing = [(c, text) for c, _, text, found in checked if not found]
    for c, text in missing:
        print(f"claims: {c.page} does not quote {c.file} {c.row!r} {c.column} as it stands: {text}", file=sys.stderr)
    absent = [(c, text) for c, text, found in runs if not found]
    for c, text in absent:
        print(f"claims: {c.page} does not say {text!r} ({c.command()})", file=sys.stderr)
    failed = 1 if missing or absent else 0
    if not a.rerun:
        print(f"claims: {len(checked) - len(missing)} of {len(checked)} quoted figures are their result files'; "
              f"{len(runs) - len(absent)} of {len(runs)} figures of command line runs are on their pages "
              "(rerun them with --rerun)")
        return failed
    folders = rerun(a.out, a.quick)
    head = ["page", "source", "row", "column", "quoted median [min-max]", "rerun", "inside the spread"]
    lines = []
    for c, values, text, _ in checked:
        new = figure(_read(os.path.join(folders[c.study], c.file)), c)[0]
        inside = values[1] <= new <= values[2]
        row = ", ".join([c.row] + [v for _, v in c.also])
        lines.append([c.page, c.file, row, c.column, text, c.fmt.format(new), "yes" if inside else "no"])
    for c, new in rerun_runs(a.out):
        same = new == c.quoted
        failed |= not same
        lines.append([c.page, c.command(), c.text.replace("{}", "..."), "summary.json", c.quoted + " (deterministic)",
                      new, "yes" if same else "no"])
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "claims.csv"), "w", newline="") as f:
        csv.writer(f).writerows([head] + lines)
    report = "| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n" + "\n".join(
        "| " + " | ".join(r) + " |" for r in lines)
    with open(os.path.join(a.out, "report.md"), "w") as f:
        f.write("## The quoted figures, rerun\n\n`python studies/claims.py --rerun`"
                + (" --quick" if a.quick else "") + "\n\n" + report + "\n")
    print(report)
    return failed


if __name__ == "__main__":
    raise SystemExit(main())
