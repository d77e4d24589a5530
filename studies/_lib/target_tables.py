"""The speed targets' tables, from what ``target_timing.measure`` returns: the columns and rows of
``targets.csv`` and ``force_call.csv``, the table printed at the end of a run and the report's
section (markdown)."""
from __future__ import annotations

import math

import numpy as np

from .studylib import markdown_table


TARGET_COLUMNS = [
    "scene [-]", "kind [-]", "unit [-]", "yardstick [-]", "ours [us]", "ours_min [us]", "ours_max [us]",
    "yardstick_per_step [us]", "yardstick_min [us]", "yardstick_max [us]", "ratio [-]", "ratio_min [-]",
    "ratio_max [-]", "target [-]", "met [-]", "ours_newton_per_step [-]", "yardstick_newton_per_step [-]",
    "floor [us]", "floor_min [us]", "floor_max [us]", "floor_newton_per_step [-]", "cube [us]",
    "ours_minus_floor [us]", "floor_minus_cube [us]", "ours_wall [us]", "yardstick_wall [us]",
    "ratio_wall [-]", "ours_steps [-]", "nominal_steps [-]", "t_end [s]", "repeats [-]", "floor_model [-]",
    "cube_model [-]"]

_KEYS = ["scene", "kind", "unit", "yardstick", "ours_us", "ours_min_us", "ours_max_us", "yardstick_us",
         "yardstick_min_us", "yardstick_max_us", "ratio", "ratio_min", "ratio_max", "target", "met",
         "ours_newton", "yardstick_newton", "floor_us", "floor_min_us", "floor_max_us", "floor_newton",
         "cube_us", "ours_minus_floor_us", "floor_minus_cube_us", "ours_wall_us", "yardstick_wall_us",
         "ratio_wall", "ours_steps", "nominal_steps", "t_end", "repeats", "floor", "cube"]


def target_table_rows(rows):
    return [[r[k] for k in _KEYS] for r in rows]


def _spread(m, lo, hi, fmt="{:.1f}"):
    if not np.isfinite(m):
        return "-"
    return f"{fmt.format(m)} [{fmt.format(lo)}-{fmt.format(hi)}]"


HEAD = ["scene", "ours us median [min-max]", "yardstick", "yardstick us median [min-max]",
        "ratio median [min-max]", "target", "met", "Newton/step ours, yardstick", "floor us median [min-max]",
        "ours - floor us", "floor - cube us"]


def _cells(r):
    """Display cells of one row (HEAD)."""
    met = "-" if r["met"] is None else "yes" if r["met"] else "**no**"
    if r["kind"] == "absolute":
        return [r["scene"], _spread(r["ours_us"], r["ours_min_us"], r["ours_max_us"], "{:.3f}"),
                "none (absolute)", "-", "-", f"{r['target']:g} us", met, "-", "-", "-", "-"]
    floor = np.isfinite(r["floor_us"])
    return [r["scene"], _spread(r["ours_us"], r["ours_min_us"], r["ours_max_us"]), r["yardstick"],
            _spread(r["yardstick_us"], r["yardstick_min_us"], r["yardstick_max_us"]),
            _spread(r["ratio"], r["ratio_min"], r["ratio_max"], "{:.2f}"),
            "-" if math.isnan(r["target"]) else f"{r['target']:g}x", met,
            f"{r['ours_newton']:.2f}, {r['yardstick_newton']:.2f}",
            _spread(r["floor_us"], r["floor_min_us"], r["floor_max_us"]) if floor else "-",
            f"{r['ours_minus_floor_us']:.1f}" if floor else "-",
            f"{r['floor_minus_cube_us']:.1f}" if floor else "-"]


def print_targets(rows, file=None):
    """The table (HEAD) as aligned text."""
    cells = [[c.replace("**", "") for c in _cells(r)] for r in rows]
    width = [max(len(h), *(len(c[j]) for c in cells)) for j, h in enumerate(HEAD)]
    for line in [HEAD] + cells:
        print("  ".join(c.ljust(w) for c, w in zip(line, width)).rstrip(), file=file)


def markdown(res):
    """The targets as a report section (markdown)."""
    rows, calls = res.rows, res.calls
    text = (f"Process CPU time of the whole solve (rejected steps included) per nominal step (per body "
            f"and step where the row says so): median [min-max] of {res.repeats} interleaved repeats, "
            f"t_end = {res.t_end:g} s, dt = 1 ms. Ours at the package's settings; the yardstick (a rigid "
            "cube on as many C++ `CartesianSpringDamper`s as the scene has contact points; 64 such cubes "
            "for the 64 cubes; for the moving master the block on the fixed plane, or with its plate beside it where "
            "the row says so; for the per-body rows the "
            "same contact at 8 cubes) at Exudyn's defaults; ratio = ours / yardstick formed repeat by "
            "repeat, median [min-max]; met: median ratio <= target. Floor: the yardstick's C++ model plus "
            "the scene's contact items with user functions that do nothing (ours - floor: what the contact "
            "adds; floor - cube: Exudyn's price of calling Python). Files: `targets.csv`, "
            "`force_call.csv`.\n\n"
            + markdown_table(HEAD, [_cells(r) for r in rows]))
    if calls:
        c = calls[0]
        fixed = _spread(c["entry_fixed_us"], c["entry_fixed_min_us"], c["entry_fixed_max_us"], "{:.3f}")
        slope = _spread(c["entry_per_point_us"], c["entry_per_point_min_us"], c["entry_per_point_max_us"],
                        "{:.4f}")
        nfixed = _spread(c["native_fixed_us"], c["native_fixed_min_us"], c["native_fixed_max_us"], "{:.3f}")
        nslope = _spread(c["native_per_point_us"], c["native_per_point_min_us"], c["native_per_point_max_us"],
                         "{:.4f}")
        text += ("\nThe compiled call on the plane (the full block's contact set after 20 steps of sliding): "
                 "CPU time of one force callback as Exudyn calls it in Python (q, q_t as lists), of the "
                 "compiled entry called from Python (mode 0: unboxing its packed arguments and the kernel), "
                 "and of the native force callback as Exudyn calls it (the package's default: a C++ function "
                 "that calls the compiled kernel on its stored arguments; the targets' rows), median "
                 "[min-max] over the repeats, each a batch of calls; least-squares fit per repeat: native = "
                 f"{nfixed} us + {nslope} us per point; entry from Python = {fixed} us + {slope} us per "
                 "point.\n\n"
                 + markdown_table(["points", "K", "in contact", "Python callback us", "entry from Python us",
                                   "native call us"],
                                  [[r["points"], r["K"], r["in_contact"]]
                                   + [_spread(r[f"{n}_us"], r[f"{n}_min_us"], r[f"{n}_max_us"], "{:.3f}")
                                      for n in ("callback", "entry", "native")]
                                   for r in calls]))
    return text


_CALL_FIELDS = ["callback", "callback_min", "callback_max", "entry", "entry_min", "entry_max", "entry_fixed",
                "entry_fixed_min", "entry_fixed_max", "entry_per_point", "entry_per_point_min",
                "entry_per_point_max", "native", "native_min", "native_max", "native_fixed", "native_fixed_min",
                "native_fixed_max", "native_per_point", "native_per_point_min", "native_per_point_max"]
FORCE_CALL_COLUMNS = ["points [-]", "K [-]", "in_contact [-]"] + [f"{f} [us]" for f in _CALL_FIELDS]


def force_call_table_rows(rows):
    return [[r["points"], r["K"], r["in_contact"]] + [r[f + "_us"] for f in _CALL_FIELDS] for r in rows]
