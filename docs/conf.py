"""Sphinx configuration of the sbmf-friction documentation site.

Build (with the ``docs`` extra installed): ``python -m sphinx -W -b html docs OUT``. The Markdown
pages are read by myst-parser, the API reference comes from the numpy-style docstrings (autodoc +
numpydoc), and the gallery under ``examples/`` is executed on every build by sphinx-gallery, so
its figures and numbers are those of the installed code.
"""

import os
import sys
from importlib.metadata import version as _version
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
# the examples read the shipped instrument files relative to the repository
os.environ.setdefault("SBMF_REPO", str(ROOT))

project = "sbmf-friction"
author = "the sbmf-friction developers"
copyright = "2026, the sbmf-friction developers"  # noqa: A001
release = _version("sbmf-friction")
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "auto_examples/*.ipynb", "auto_examples/*.py", "**.zip"]

# Markdown: anchors for the pages' section links, $...$ maths as the pages write it
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]
# The pages link to files of the repository outside docs/ (benchmark scripts, results, sources)
# that the site does not host; they stay plain links, not cross-references that must resolve.
suppress_warnings = ["myst.xref_missing"]

autosummary_generate = True
autodoc_typehints = "none"  # numpydoc's Parameters sections carry the types
autodoc_default_options = {"members": False}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",  # every example runs during the build
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
}

html_theme = "furo"
html_title = f"sbmf-friction {release}"
