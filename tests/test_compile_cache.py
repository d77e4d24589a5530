"""The kernel cache (exu_aniso.util.numba_cache) is keyed on exactly the sources a kernel is built from:
an edit of a file no kernel is built from, or of a docstring, recompiles nothing; an edit of a
surface recompiles that surface's kernels only; a stale kernel never runs. Each check runs a copy of
the package in a subprocess with a cache of its own, and reads numba's own cache statistics of the
projection (geometry.core.project) on two surfaces, with its result."""
import json
import os
import shutil
import subprocess
import sys

import pytest
from _suite import HANG_S

import exu_aniso
from exu_aniso.kernel import compiling, law_call
from exu_aniso.kernel.nodes import NODE_KINDS

# project a point 5 m from the centre of a unit sphere and 4 m above a plane: numba's hits and misses
# of geometry.core.project (its cache statistics) and the gap per surface
_PROBE = """
import json
from exu_aniso.geometry import core, Plane, Sphere
out = {}
for name, surface in (("plane", Plane()), ("sphere", Sphere(1.0))):
    before = core.project.stats.cache_hits.copy(), core.project.stats.cache_misses.copy()
    gap = surface.gap_and_normal((0.0, 3.0, 4.0))[0]
    hits = sum(core.project.stats.cache_hits.values()) - sum(before[0].values())
    misses = sum(core.project.stats.cache_misses.values()) - sum(before[1].values())
    out[name] = [hits, misses, gap]
print(json.dumps(out))
"""


@pytest.fixture
def package_copy(tmp_path):
    """(run, edit): run() runs the probe on a copy of the package with a cache of its own and returns
    {surface: [cache hits, cache misses, gap]}; edit(relative path, old, new) edits the copy."""
    root = tmp_path / "src"
    shutil.copytree(os.path.dirname(exu_aniso.__file__), root / "exu_aniso",
                    ignore=shutil.ignore_patterns("__pycache__", "*.so"))
    env = dict(os.environ, PYTHONPATH=str(root), NUMBA_CACHE_DIR=str(tmp_path / "cache"))

    def run():
        done = subprocess.run([sys.executable, "-c", _PROBE], env=env, cwd=tmp_path, capture_output=True,
                              text=True, check=True)
        return json.loads(done.stdout.strip().splitlines()[-1])

    def edit(rel, old, new):
        path = root / "exu_aniso" / rel
        text = path.read_text()
        assert old in text, (rel, old)
        path.write_text(text.replace(old, new, 1))
    edit.root = root
    return run, edit


def test_edits_recompile_what_they_change_only(package_copy):
    run, edit = package_copy
    first = run()
    assert [first["plane"][:2], first["sphere"][:2]] == [[0, 1], [0, 1]], first       # compiled once each
    assert first["sphere"][2] == pytest.approx(4.0) and first["plane"][2] == pytest.approx(4.0)
    # a scene, the command line and a docstring of a shared kernel source: nothing recompiles
    edit("scenes/block.py", '"""', '"""An edited docstring.\n\n')
    edit("cli.py", "import argparse\n", "import argparse\nEDITED = 1\n")
    edit("geometry/core.py", '"""Closest point projection', '"""An edited docstring. Closest point projection')
    second = run()
    assert [second["plane"][:2], second["sphere"][:2]] == [[1, 0], [1, 0]], second
    # the sphere's chart: its kernels recompile, the plane's do not, and the new chart is what runs
    edit("geometry/sphere.py", "    R = p.radius\n", "    R = 2.0 * p.radius\n")
    third = run()
    assert third["plane"][:2] == [1, 0] and third["sphere"][:2] == [0, 1], third
    assert third["sphere"][2] == pytest.approx(3.0)                                    # not a stale kernel
    # a shared kernel source's code: every kernel recompiles
    edit("geometry/core.py", "PROJECTION_MAXIT = 50", "PROJECTION_MAXIT = 51")
    fourth = run()
    assert [fourth["plane"][:2], fourth["sphere"][:2]] == [[0, 1], [0, 1]], fourth
    # a surface's parameter type renamed: the index that names the old type cannot be read, and is an
    # empty one (everything in it recompiles; no error)
    path = edit.root / "exu_aniso" / "geometry" / "sphere.py"
    path.write_text(path.read_text().replace("SphereParams", "BallParams"))
    fifth = run()
    assert [fifth["plane"][:2], fifth["sphere"][:2]] == [[0, 1], [0, 1]], fifth
    assert fifth["sphere"][2] == pytest.approx(3.0)


def test_kernel_sources_are_the_lower_layers():
    """The shared kernel sources: the modules that import numba and the package modules they import;
    no engine, scene, model, command line or study among them; every surface module keyed alone."""
    from exu_aniso.util import numba_cache
    shared = numba_cache.SOURCES.kernel_sources
    assert {"kernel/point.py", "kernel/sets.py", "geometry/core.py", "fields/nets.py", "law/return_maps.py",
            "law/history.py"} <= set(shared)
    assert not [s for s in shared if s.split("/")[0] in ("engines", "scenes", "models", "cli.py", "catalog.py")]
    assert numba_cache.SOURCES.surface_modules == {
        f"geometry/{m}.py" for m in ("plane", "cylinder", "cone", "sphere", "torus", "helicoid", "revolution",
                                     "parametric")}
    # the parametric surface imports the surface of revolution's helpers: keyed on both
    assert numba_cache.SOURCES.surface_hash("exu_aniso.geometry.parametric") != numba_cache.SOURCES._combine(
        ["geometry/parametric.py"])


def test_a_law_is_keyed_on_its_surface_and_a_set_kernel_on_none():
    """A law's compiled code (kernel.law_call.law_entry, its bundle behind a pointer) is keyed on its
    surface's module, so an edit of the sphere recompiles the sphere's laws; a set's kernel, which
    calls the law through its address, on no surface at all, so such an edit leaves it be."""
    import numpy as np
    from numba import typeof, types

    from exu_aniso import Adhesion, ContactLaw, Friction, Sphere
    from exu_aniso.util import numba_cache
    bundle = law_call.law_bundle(ContactLaw(Sphere(1.0), Adhesion.isotropic(1e3), Friction.isotropic(0.3), 1e5))
    law_sig = (types.CPointer(typeof(bundle)),) + law_call.LAW_ARGS
    assert numba_cache.signature_surfaces(law_sig) == (numba_cache.SOURCES.surface_hash("exu_aniso.geometry.sphere"),)
    set_args = (0, np.zeros(3), law_call.LawCall(0, 0), NODE_KINDS["RigidBody2D"])
    assert numba_cache.signature_surfaces(tuple(typeof(a) for a in set_args)) == ()


def test_compile_estimate_is_the_measured_one():
    """The compile times the announcement quotes (kernel.compiling.COMPILE_SECONDS: a law's, a fixed
    master's set kernel's and a moving master's) are the ranges measured by studies/compile_times.py
    in docs/results/compile_times/compile_times.json, rounded outward to whole seconds."""
    path = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "docs", "results",
                        "compile_times", "compile_times.json")
    with open(path) as f:
        kernels = json.load(f)["kernels"]
    assert {k["kind"] for k in kernels} == set(compiling.COMPILE_SECONDS)
    for which in compiling.COMPILE_SECONDS:
        measured = [k["seconds"] for k in kernels if k["kind"] == which]
        assert compiling.COMPILE_SECONDS[which] == (int(min(measured)), int(max(measured)) + 1), which


@pytest.mark.slow
def test_compile_times_quick(tmp_path, quick_study):
    """studies/compile_times.py --quick: the block compiled from an empty cache in a fresh process, its
    law and its set kernel named and timed, and the functions its cache then holds."""
    quick_study("compile_times", tmp_path)
    with open(tmp_path / "compile_times.json") as f:
        out = json.load(f)
    (row,) = out["scenes"]
    assert row["scene"] == "block" and row["cached_functions"] > 10
    law, kernel = out["kernels"]
    assert law["kernel"] == "the contact law for CartesianPlane, PolarNet adhesion, PolarNet friction, radial map"
    assert law["kind"] == "law"
    assert kernel["kernel"] == "the contact set kernel for a RigidBody2D node" and kernel["kind"] == "fixed"
    assert 0.0 < law["seconds"] + kernel["seconds"] < row["wall_s"]
    assert "Compile times" in (tmp_path / "report.md").read_text()


def test_compile_command_compiles_once(tmp_path):
    """exu-aniso compile block from an empty cache compiles the block's law and its set kernel and says so; again,
    it compiles none (the cache holds it)."""
    # the package this test imports (a source checkout or the installed copy)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"),
               PYTHONPATH=os.path.dirname(os.path.dirname(exu_aniso.__file__)))
    said = []
    for _ in range(2):
        done = subprocess.run([sys.executable, "-m", "exu_aniso.cli", "compile", "block"], env=env, cwd=tmp_path,
                              capture_output=True, text=True, timeout=HANG_S)
        assert done.returncode == 0, done.stderr
        said.append(done.stderr)
    assert "the contact kernels of block: 2 compiled" in said[0], said[0]     # its law and its set kernel
    assert "compiling the contact law for CartesianPlane, PolarNet adhesion" in said[0]
    assert "compiling the contact set kernel for a RigidBody2D node" in said[0]
    assert "the contact kernels of block: 0 compiled" in said[1] and "compiling" not in said[1], said[1]
    bad = subprocess.run([sys.executable, "-m", "exu_aniso.cli", "compile", "nonesuch"], env=env, cwd=tmp_path,
                         capture_output=True, text=True, timeout=HANG_S)
    assert bad.returncode == 2 and "no scene 'nonesuch'" in bad.stderr
