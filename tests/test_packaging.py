"""Packaging: every folder of exu_aniso with Python modules is a package that pyproject.toml's
package discovery finds, so a plain `pip install .` (what CI and the quick start do) installs it. A
missed folder imports fine from the source tree and fails only after a non-editable install."""
from __future__ import annotations

import os
import tomllib

from setuptools import find_packages

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_every_subpackage_is_installed():
    with open(os.path.join(ROOT, "pyproject.toml"), "rb") as f:
        include = tomllib.load(f)["tool"]["setuptools"]["packages"]["find"]["include"]
    installed = set(find_packages(where=ROOT, include=include))
    folders = set()
    for folder, dirs, files in os.walk(os.path.join(ROOT, "exu_aniso")):
        dirs[:] = [d for d in dirs if d != "__pycache__"]
        if any(f.endswith(".py") for f in files):
            folders.add(os.path.relpath(folder, ROOT).replace(os.sep, "."))
    assert {"exu_aniso", "exu_aniso.models", "exu_aniso.kernel", "exu_aniso.engines.exudyn_adapter"} <= folders
    assert folders <= installed, f"not found by pyproject.toml's package discovery: {sorted(folders - installed)}"
