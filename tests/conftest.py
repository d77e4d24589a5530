"""Shared test helpers."""
import os
import subprocess
import sys

import pytest
from _suite import HANG_S

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture(scope="session")
def quick_study():
    """run(name, out, timeout=HANG_S, args=(), **kw): run ``studies/NAME.py --quick --serial --out OUT
    [args]`` from the repository root (check=True; stdout dropped unless kw says otherwise);
    returns the CompletedProcess. The scripts put studies/ first on sys.path (for their private
    helpers in studies/_lib) and import the installed package."""
    def run(name, out, timeout=HANG_S, args=(), **kw):
        kw.setdefault("stdout", None if "capture_output" in kw else subprocess.DEVNULL)
        return subprocess.run([sys.executable, os.path.join("studies", f"{name}.py"), "--quick", "--serial",
                               "--out", str(out), *args], cwd=ROOT, check=True, timeout=timeout, **kw)
    return run
