"""Sphinx configuration of exu_aniso's documentation site.

Build: ``pip install ".[test]"`` (or ``".[docs]"``), then ``sphinx-build -W docs docs/_build/html``.
The pages are Markdown (MyST); the API reference comes from the docstrings (autodoc); the gallery
runs the scripts in ``examples/`` and keeps their figures (sphinx-gallery). With the environment
variable ``EXU_ANISO_DOCS_NO_GALLERY=1`` the examples are listed but not run (the test suite
builds the site that way and runs the examples on their own, in their quick form).
"""
import os
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, ROOT)

project = "exu_aniso"
author = "exu_aniso developers"
copyright = "2026, exu_aniso developers"

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.mathjax", "sphinx_gallery.gen_gallery"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
# the studies' own report files are assembled into RESULTS.md (their figures are linked from there)
exclude_patterns = ["_build", "results/**", "sg_execution_times.rst", "gallery/*.md5", "gallery/*.py", "gallery/*.ipynb",
                    "gallery/*.zip", "gallery/sg_execution_times.rst"]
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3
# the generated pages of long reports repeat headings (one per study): no duplicate-label noise
suppress_warnings = ["myst.header"]

autodoc_member_order = "bysource"
autodoc_typehints = "none"
autodoc_default_options = {"members": False}

html_theme = "alabaster"
html_title = "exu_aniso"
html_theme_options = {"description": "Anisotropic frictional contact for Exudyn", "page_width": "1100px",
                      "sidebar_width": "240px"}

sphinx_gallery_conf = {
    "examples_dirs": os.path.join(ROOT, "examples"),
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",
    "plot_gallery": "False" if os.environ.get("EXU_ANISO_DOCS_NO_GALLERY") == "1" else "True",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
}


def _docstring_as_written(app, what, name, obj, options, lines):
    """The package's docstrings are plain text (formulas such as |N| and T.F T, aligned argument
    lists), not reStructuredText: each is shown as written, in a literal block."""
    if lines:
        lines[:] = ["::", ""] + ["    " + line for line in lines] + [""]


def setup(app):
    app.connect("autodoc-process-docstring", _docstring_as_written)
