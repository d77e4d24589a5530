"""The command line under random valid parameters, as an adversarial user would drive it (slow set).

For every scene, cases draw each parameter at random (half of them kept at their default) inside its
rule, with short runs; a draw the parameter class refuses is drawn again, so every case is valid
input. Each case runs ``exu-aniso run`` in a fresh process on both engines where the scene has
both, and checks what must hold for any input:

* no traceback; exit 0, or 1 with ``"complete": false`` and a reason in summary.json;
* summary.json is strict JSON (no NaN or Infinity);
* ``energy_ok`` false exactly when an EnergyWarning is printed;
* the ledger's residual column is work in - (kinetic + potential + stored + dissipated) of the
  file's own columns (1e-9 of the largest term);
* parity: where both engines ran, every trajectory column the two share agrees at every sample to
  PARITY_RTOL of the largest value of the columns of its unit (both engines take the same steps:
  scenes.time_grid).

Every failure prints its seed and the command that reproduces it. ``FUZZ_CLI_CASES`` (default 2)
sets the cases per scene, ``FUZZ_CLI_SEED`` the base seed (default: 2026).

Run: ``pytest -m slow tests/test_fuzz_cli.py -s``.
"""
from __future__ import annotations

import csv
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from exu_aniso.catalog import SCENES
from _suite import HANG_S

pytest.importorskip("exudyn")

CASES = int(os.environ.get("FUZZ_CLI_CASES", "2"))
SEED = int(os.environ.get("FUZZ_CLI_SEED", "2026"))
# Stick/slip switches amplify a round-off difference between the engines' Newton iterates (the full
# block's rotation: 3e-3 in tests/test_exudyn_scenes.py); random parameters meet such switches.
PARITY_RTOL = 5e-3
RUN_TIMEOUT_S = HANG_S
# time per case: a short run of the scene (share of its default t_end), and dt around its default
T_SHARE = (0.05, 0.2)


def _draw(rng, name, default, rule):
    """One random value (as the string a user types) inside the rule, around the default."""
    if isinstance(rule, tuple):
        return str(rng.choice(rule))
    if "grid" in str(rule):
        return str(rng.choice(["center", "corners", "grid:2", "grid:3"]))
    if rule == "int >= 1":
        return str(int(rng.integers(1, max(2, min(2 * int(default), 12)) + 1)))
    if rule in ("(-90, 90)", "(-45, 45)"):
        half = 60.0 if rule == "(-90, 90)" else 30.0
        return repr(float(rng.uniform(-half, half)))
    d = float(default)
    if d == 0.0:
        if rule == ">= 0":
            return "0" if rng.random() < 0.5 else repr(float(10.0 ** rng.uniform(-2, 1)))
        return repr(float(rng.uniform(-1.0, 1.0)))
    return repr(d * float(10.0 ** rng.uniform(-0.5, 0.5)))


def random_case(scene, rng):
    """{name: string} of a valid parameter set with a short run (the class accepts it)."""
    cls = SCENES[scene].Params
    table = cls.TABLE
    for _ in range(500):
        sets = {n: _draw(rng, n, d, r) for n, (d, _, _, r) in table.items()
                if n not in ("t_end", "dt") and rng.random() < 0.5}
        sets["t_end"] = repr(float(table["t_end"][0]) * float(rng.uniform(*T_SHARE)))
        sets["dt"] = repr(float(table["dt"][0]) * float(10.0 ** rng.uniform(-0.3, 0.3)))
        try:
            cls.from_strings(sets)
        except ValueError:
            continue
        return sets
    raise AssertionError(f"no valid random {scene} case in 500 draws")


def _run(scene, engine, sets, out):
    args = ["run", scene, "--engine", engine, "--out", str(out), "--quiet"]
    for k, v in sets.items():
        args += ["--set", f"{k}={v}"]
    code = f"import sys; from exu_aniso.cli import main; sys.exit(main({args!r}))"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=RUN_TIMEOUT_S,
                       cwd=str(out.parent))
    return p.returncode, p.stderr, "exu-aniso " + " ".join(a if " " not in a else repr(a) for a in args)


def _no_constant(name):
    raise ValueError(f"summary.json holds {name}: not strict JSON")


def _csv(path):
    with open(path) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    return {k: np.array([float(r[i]) for r in rows[1:]]) for i, k in enumerate(rows[0])}


def check_run(rc, err, out, why):
    assert "Traceback" not in err, f"{why}: traceback\n{err[-3000:]}"
    summary = json.loads((out / "summary.json").read_text(), parse_constant=_no_constant)
    if rc != 0:
        assert rc == 1, f"{why}: exit {rc} for valid input\n{err[-2000:]}"
        assert summary["complete"] is False and summary.get("failure"), f"{why}: exit 1 without a reason"
        return summary, None
    assert summary["complete"] is True, why
    warned = "EnergyWarning" in err
    assert summary["energy_ok"] is (not warned), f"{why}: energy_ok {summary['energy_ok']} but warning {warned}"
    c = _csv(out / "trajectory.csv")
    terms = [c["energy_" + k] for k in ("work_in", "kinetic", "potential", "stored", "dissipated")]
    scale = max(float(np.max(np.abs(a))) for a in terms) or 1.0
    res = terms[0] - (terms[1] + terms[2] + terms[3] + terms[4])
    assert np.max(np.abs(res - c["energy_residual"])) <= 1e-9 * scale, f"{why}: residual column"
    return summary, c


@pytest.mark.slow
@pytest.mark.parametrize("scene", list(SCENES))
def test_random_valid_parameters(scene, tmp_path):
    engines = ("exudyn", "reference") if SCENES[scene].reference is not None else ("exudyn",)
    rng = np.random.default_rng([SEED, list(SCENES).index(scene)])
    for case in range(CASES):
        sets = random_case(scene, rng)
        runs = {}
        for engine in engines:
            out = tmp_path / f"{case}-{engine}"
            rc, err, cmd = _run(scene, engine, sets, out)
            why = f"seed {SEED} case {case}: {cmd}"
            print(f"\n{why}: exit {rc}")
            runs[engine] = check_run(rc, err, out, why)
        # compared where both kept their nominal step: a run whose solver cut a step is written at the
        # first sample at or after each output time, which the two engines' different cuts put apart
        # (the seed map's stick/slip jump cuts Exudyn's steps more often than the reference's)
        if len(runs) == 2 and all(c is not None and not s.get("step_reductions") for s, c in runs.values()):
            a, b = runs["exudyn"][1], runs["reference"][1]
            # relative to the largest value of any column of the same unit: a lateral motion of round-off
            # size (1e-17 m beside an advance of 1e-3 m) is compared with the advance, not with itself
            units = SCENES[scene].columns
            unit_scale = {}
            for k in set(a) & set(b):
                u = units.get(k, k)
                unit_scale[u] = max(unit_scale.get(u, 1e-300), float(np.max(np.abs(b[k]))))
            assert np.allclose(a["t"], b["t"], rtol=0, atol=1e-12), f"{why}: time grids differ"
            for k in sorted(set(a) & set(b) - {"t"}):
                if k.startswith("energy_") or k in ("h", "newton_iterations"):
                    continue
                scale = unit_scale[units[k]]
                e = float(np.max(np.abs(a[k] - b[k]))) / scale
                assert e <= PARITY_RTOL, \
                    f"seed {SEED} case {case} ({sets}): {k} differs by {e:.3g} relative between the engines"
