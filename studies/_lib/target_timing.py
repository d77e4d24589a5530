"""How the speed targets (``targets``) are timed: ``measure`` builds and solves every model they
declare and times the compiled call (``CallBench``), and forms one row per target.

How it is timed: every model (ours, yardsticks, floors) is built afresh, solved once for 5 steps
untimed (kernels compiled or loaded), then in every repeat all of them are built and solved one
after the other, and the compiled calls timed, in the same order (interleaved repeats). A figure
is the process CPU time of the whole solve (rejected steps included; model building excluded) per
nominal step t_end / dt, per body where the row says so; medians over the repeats with min and
max beside them. A ratio is formed repeat by repeat (ours_i / yardstick_i, measured within
seconds of each other) and reported as the median with min and max of those ratios; a target is
met when the median ratio is at most the target. Process CPU time does not grow when other
processes share the core (wall time is kept beside it in ``targets.csv``)."""
from __future__ import annotations

import math
import time
from collections import namedtuple

import numpy as np

from exu_aniso.models.block import BuildBlock
from exu_aniso.engines.exudyn_adapter.runner import SolveTimed
from exu_aniso.scenes.block import BlockParams

from .targets import CALL_LAYOUTS, CALLS, CALLS_QUICK, TARGETS, CallFit, PerBody, runs_of

T_END, T_END_QUICK, DT = 0.5, 0.05, 1e-3
WARM_STEPS = 5


def timed_solve(model):
    """(process CPU time [s], wall time [s], steps, Newton iterations) of solving a built model."""
    c0, w0 = time.process_time(), time.perf_counter()
    _, steps, iters, _ = SolveTimed(model["mbs"], model["simulationSettings"], model["solverType"])
    return time.process_time() - c0, time.perf_counter() - w0, steps, iters


class CallBench:
    """The compiled call of the full block's contact set on each layout of CALL_LAYOUTS, after 20
    steps of sliding: ``time()`` gives, per layout, the CPU time of one force callback as Exudyn calls
    it in Python (q, q_t as lists), of the compiled entry alone with the force's packed arguments
    (mode 0), and of the native force callback (the package's default: Exudyn calls a C++ function
    that calls the compiled kernel, ``_native.call_force`` calling it as Exudyn does), each over a
    batch of ``calls`` calls; NaN for the native call where the extension is not built."""

    def __init__(self, calls, layouts=CALL_LAYOUTS):
        from exu_aniso.engines.exudyn_adapter import commit, contact_set
        self.calls, self.items = calls, []
        for points in layouts:
            model = BuildBlock(BlockParams(model="full", points=points, t_end=0.02))
            timed_solve(model)
            mbs = model["mbs"]
            cs = mbs.variables[commit.SETS_KEY][0]
            if not isinstance(cs, contact_set.CompiledSet) or getattr(cs, "_force_args", None) is None:
                raise RuntimeError(f"CallBench: the block's contact set on {points!r} is not a compiled set "
                                   "with packed force arguments (contact_set.CompiledSet._force_args)")
            # the state of the last residual: the solve's end (Exudyn's Current coordinates); the native
            # callbacks leave the set's Python clock (cs._t) at the solve's first call
            ti = model["simulationSettings"].timeIntegration
            q, q_t, t = list(cs._q), list(cs._q_t), float(ti.endTime)

            def callback(cs=cs, mbs=mbs, t=t, q=q, q_t=q_t):
                cs.force_in_place(mbs, t, 0, q, q_t)                # the function Exudyn calls

            def entry(cs=cs):
                cs._entry(*cs._force_args)                          # mode 0: the force, unboxing + kernel

            def native_call(calls, cs=cs, mbs=mbs, t=t, q=q, q_t=q_t):
                from exu_aniso.engines.exudyn_adapter import _native
                clock = cs._native.clock                            # armed in the step of the last residual
                saved = clock.copy()
                clock[:2] = (t - cs._dt, 1.0)
                _native.call_force(mbs, cs.oContact, t, q, q_t, calls)
                clock[:] = saved

            native = native_call if cs._native is not None else None
            callback()                                              # loads the history of the step at t
            entry()
            assert cs._force_args[0] == 0 and cs._t == t
            if native is not None:
                before = cs.native_calls()
                native(1)
                if cs.native_calls()[0] != before[0] + 1:
                    raise RuntimeError(f"CallBench: the native force call on {points!r} went to Python")
            self.items.append(dict(points=points, K=cs.K, in_contact=int(np.sum(cs.pk.Hn[:, 7] > 0)),
                                   callback=callback, entry=entry, native=native, model=model))

    def time(self):
        """One repeat: {points: (callback_s, entry_s, native_s)} per call, CPU time."""
        out = {}
        for it in self.items:
            res = []
            for fn in (it["callback"], it["entry"]):
                c0 = time.process_time()
                for _ in range(self.calls):
                    fn()
                res.append((time.process_time() - c0) / self.calls)
            if it["native"] is None:
                res.append(float("nan"))
            else:
                c0 = time.process_time()
                it["native"](self.calls)
                res.append((time.process_time() - c0) / self.calls)
            out[it["points"]] = tuple(res)
        return out


def _stats(x):
    x = np.asarray(x, dtype=float)
    return float(np.median(x)), float(np.min(x)), float(np.max(x))


Results = namedtuple("Results", "rows calls t_end repeats")


def measure(quick=False, repeats=5, targets=None, t_end=None, calls=None, layouts=CALL_LAYOUTS):
    """Measure the targets (module doc); returns Results(rows: one dict per target, calls: one dict
    per call layout, t_end, repeats). t_end, calls and layouts override the defaults (tests)."""
    targets = TARGETS if targets is None else targets
    t_end = t_end if t_end is not None else (T_END_QUICK if quick else T_END)
    dt = DT
    nominal = int(round(t_end / dt))
    runs = runs_of(targets)
    want_calls = any(isinstance(t.build, CallFit) for t in targets)
    for r in runs:                                     # warm-up: kernels compiled or loaded, untimed
        timed_solve(r.build(WARM_STEPS * dt, dt))
    bench = CallBench(calls or (CALLS_QUICK if quick else CALLS), layouts) if want_calls else None
    times = {r.name: [] for r in runs}
    call_times = []
    for _ in range(repeats):                           # interleaved: every model once per repeat
        for r in runs:
            model = r.build(t_end, dt)
            times[r.name].append(timed_solve(model))
            del model
        if bench is not None:
            call_times.append(bench.time())
    # (repeats, 4): cpu, wall, steps, Newton iterations
    T = {name: np.array(ts, dtype=float) for name, ts in times.items()}
    calls_rows, fits = _call_rows(bench, call_times) if bench is not None else ([], None)
    rows = [_row(t, T, nominal, t_end, repeats, fits) for t in targets]
    return Results(rows, calls_rows, t_end, repeats)


def _call_rows(bench, call_times):
    """Per layout: callback, entry and native medians [min, max] [us]; per repeat a least-squares fit
    of the entry's and of the native call's time over K: fixed + per-point cost. The targets take the
    native call's fit (the call Exudyn makes at the package's default), the entry's without the
    extension."""
    K = np.array([it["K"] for it in bench.items], dtype=float)

    def fit(col):
        out = []
        for rep in call_times:
            y = np.array([rep[it["points"]][col] for it in bench.items]) * 1e6
            b, a = np.polyfit(K, y, 1) if len(K) > 1 and np.all(np.isfinite(y)) else (float("nan"), y[0])
            out.append((a, b))
        return np.array(out, dtype=float)

    fits = {"entry": fit(1), "native": fit(2)}
    rows = []
    for it in bench.items:
        r = dict(points=it["points"], K=it["K"], in_contact=it["in_contact"])
        for col, name in enumerate(("callback", "entry", "native")):
            m, lo, hi = _stats([rep[it["points"]][col] * 1e6 for rep in call_times])
            r.update({f"{name}_us": m, f"{name}_min_us": lo, f"{name}_max_us": hi})
        rows.append(r)
    for name, f in fits.items():
        fixed, per_point = _stats(f[:, 0]), _stats(f[:, 1])
        for r in rows:
            r.update({f"{name}_fixed_us": fixed[0], f"{name}_fixed_min_us": fixed[1],
                      f"{name}_fixed_max_us": fixed[2], f"{name}_per_point_us": per_point[0],
                      f"{name}_per_point_min_us": per_point[1], f"{name}_per_point_max_us": per_point[2]})
    use = fits["native"] if np.all(np.isfinite(fits["native"])) else fits["entry"]
    return rows, dict(fixed=use[:, 0], per_point=use[:, 1])


def _met(value, target):
    """value <= target; None for a row without a target."""
    return None if math.isnan(target) else bool(value <= target)


def _row(t, T, nominal, t_end, repeats, fits):
    nan = float("nan")
    target = nan if t.target is None else float(t.target)
    row = dict(scene=t.label, target=target, t_end=t_end, nominal_steps=nominal, repeats=repeats)
    if isinstance(t.build, CallFit):
        v = fits[t.build.part]
        m, lo, hi = _stats(v)
        row.update(kind="absolute", unit="us/call" if t.build.part == "fixed" else "us/point",
                   yardstick="none", ours_us=m, ours_min_us=lo, ours_max_us=hi, met=_met(m, target))
        for k in ("yardstick_us", "yardstick_min_us", "yardstick_max_us", "ratio", "ratio_min", "ratio_max",
                  "ours_newton", "yardstick_newton", "floor_us", "floor_min_us", "floor_max_us",
                  "floor_newton", "cube_us", "ours_minus_floor_us", "floor_minus_cube_us", "ours_wall_us",
                  "yardstick_wall_us", "ratio_wall", "ours_steps"):
            row[k] = nan
        row.update(floor="", cube="")
        return row
    per_body = isinstance(t.yardstick, PerBody)
    y = t.yardstick.run if per_body else t.yardstick
    o = t.build

    def per(run, col=0):                     # per nominal step (and body), per repeat [us]
        return T[run.name][:, col] / nominal / (run.bodies if per_body else 1) * 1e6

    def newton(run):
        return float(np.median(T[run.name][:, 3] / T[run.name][:, 2]))

    ours, yard = per(o), per(y)
    ratio = ours / yard
    (om, o0, o1), (ym, y0, y1), (rm, r0, r1) = _stats(ours), _stats(yard), _stats(ratio)
    row.update(kind="ratio", unit="us/body/step" if per_body else "us/step", yardstick=y.name,
               ours_us=om, ours_min_us=o0, ours_max_us=o1, yardstick_us=ym, yardstick_min_us=y0,
               yardstick_max_us=y1, ratio=rm, ratio_min=r0, ratio_max=r1, met=_met(rm, target),
               ours_newton=newton(o), yardstick_newton=newton(y),
               ours_wall_us=float(np.median(per(o, 1))), yardstick_wall_us=float(np.median(per(y, 1))),
               ratio_wall=float(np.median(per(o, 1) / per(y, 1))),
               ours_steps=float(np.median(T[o.name][:, 2])))
    if o.floor is not None:
        f, c = per(o.floor), per(o.cube)
        fm, f0, f1 = _stats(f)
        row.update(floor=o.floor.name, cube=o.cube.name, floor_us=fm, floor_min_us=f0, floor_max_us=f1,
                   floor_newton=newton(o.floor), cube_us=float(np.median(c)),
                   ours_minus_floor_us=float(np.median(ours - f)),
                   floor_minus_cube_us=float(np.median(f - c)))
    else:
        row.update(floor="", cube="", floor_us=nan, floor_min_us=nan, floor_max_us=nan, floor_newton=nan,
                   cube_us=nan, ours_minus_floor_us=nan, floor_minus_cube_us=nan)
    return row
