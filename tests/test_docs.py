"""The documentation site (docs/, Sphinx with MyST pages, autodoc and a sphinx-gallery of the
scripts in examples/) builds with warnings as errors, and every example runs in its quick form
(EXU_ANISO_QUICK=1), as the gallery runs it in full when the site is built."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest
from _suite import HANG_S

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = sorted(f for f in os.listdir(os.path.join(ROOT, "examples")) if f.startswith("plot_") and f.endswith(".py"))


def test_the_site_builds_without_a_warning(tmp_path):
    pytest.importorskip("sphinx")
    pytest.importorskip("myst_parser")
    pytest.importorskip("sphinx_gallery")
    # a copy of the sources: the gallery writes its pages beside them
    shutil.copytree(os.path.join(ROOT, "docs"), tmp_path / "docs", ignore=shutil.ignore_patterns("_build", "gallery"))
    shutil.copytree(os.path.join(ROOT, "examples"), tmp_path / "examples")
    env = dict(os.environ, EXU_ANISO_DOCS_NO_GALLERY="1")
    out = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", str(tmp_path / "docs"),
                          str(tmp_path / "html")], capture_output=True, text=True, env=env, timeout=HANG_S)
    assert out.returncode == 0, out.stderr[-3000:]
    pages = {p.name for p in (tmp_path / "html").rglob("*.html")}
    assert {"index.html", "install.html", "api.html", "RESULTS.html", "contact_api.html"} <= pages
    assert {e.replace(".py", ".html") for e in EXAMPLES} <= pages
    api = (tmp_path / "html" / "api.html").read_text()
    assert "MainSystemCreateAnisotropicContact" in api and "RecommendedSimulationSettings" in api


@pytest.mark.parametrize("example", EXAMPLES)
def test_example_runs_in_its_quick_form(example, tmp_path):
    env = dict(os.environ, EXU_ANISO_QUICK="1", MPLBACKEND="Agg")
    out = subprocess.run([sys.executable, os.path.join(ROOT, "examples", example)], capture_output=True, text=True,
                         env=env, cwd=tmp_path, timeout=HANG_S)
    assert out.returncode == 0, out.stderr[-3000:]
    assert "Warning" not in out.stderr, out.stderr[-3000:]


def test_the_readme_model_runs(tmp_path):
    """The README's five-minute model script runs as printed (a fresh process) and leaves its picture."""
    import re
    text = open(os.path.join(ROOT, "README.md")).read()
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=HANG_S,
                         env=dict(os.environ, MPLBACKEND="Agg"), cwd=tmp_path)
    assert out.returncode == 0, out.stderr[-3000:]
    assert (tmp_path / "final.png").stat().st_size > 10000
    # it says what happened: pushed along +y from (0.5, 0), the polar net turns the block towards the
    # origin (x falls), and friction takes most of its 0.125 J
    x, y, z, dissipated = (float(v) for v in re.findall(r"[-+]?\d*\.\d+(?:e[-+]?\d+)?", out.stdout.split("final position")[1]))
    assert x < 0.5 and 0.05 < y < 0.25 and 0.9 * 0.125 < dissipated < 0.125, out.stdout


# the pages' whole scripts (a block that starts with its imports), run as a reader copies them; the
# lines that open a window are left out (ViewSolution: a display)
_SCRIPT_PAGES = ["docs/guide/command_line.md", "docs/guide/contact_api.md", "docs/guide/reference_engine.md",
                 "docs/guide/surfaces_and_fields.md", "docs/guide/calibration.md", "docs/adding_a_surface.md",
                 "docs/adding_a_slave.md"]


_QUICK_PAGES = ("docs/guide/surfaces_and_fields.md", "docs/adding_a_slave.md")   # 1 s; the others 5 to 19 s: -m slow


def _scripts():
    import re
    out = []
    for page in _SCRIPT_PAGES:
        with open(os.path.join(ROOT, page)) as f:
            blocks = re.findall(r"```python\n(.*?)```", f.read(), re.S)
        whole = [b for b in blocks if b.lstrip().startswith(("import ", "from "))]
        marks = [] if page in _QUICK_PAGES else [pytest.mark.slow]
        out += [pytest.param(page, b, id=f"{os.path.basename(page)}-{i}", marks=marks) for i, b in enumerate(whole)]
    return out


@pytest.mark.parametrize("page,code", _scripts())
def test_the_pages_scripts_run(page, code, tmp_path):
    code = "\n".join(line for line in code.splitlines() if "ViewSolution(" not in line)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, timeout=HANG_S,
                         env=dict(os.environ, MPLBACKEND="Agg"))
    assert out.returncode == 0, f"{page}:\n{code}\n{out.stderr[-3000:]}"
    assert "Traceback" not in out.stderr and "Exception ignored" not in out.stderr, out.stderr[-3000:]


def test_the_result_folders_scripts_start(tmp_path):
    """A script kept beside its results (docs/results/*/*.py) still imports what it names: its --help
    runs (one once imported a parameter class from a module that no longer held it)."""
    import glob
    scripts = sorted(glob.glob(os.path.join(ROOT, "docs", "results", "*", "*.py")))
    assert scripts
    for script in scripts:
        out = subprocess.run([sys.executable, script, "--help"], capture_output=True, text=True, cwd=tmp_path,
                             timeout=HANG_S)
        assert out.returncode == 0 and "usage" in out.stdout, (script, out.stderr[-2000:])
