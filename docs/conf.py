"""Sphinx configuration of the pendula documentation (built by tools/build_docs.sh).

The Python API pages are generated from pendula.__all__ and the docstrings
(autosummary + numpydoc); the example gallery is written by tools/docs_gallery.py,
which runs each examples/python/*.py in quick mode; the Fortran API is a FORD site
copied under fortran/ by tools/build_docs.sh and linked from fortran.md.
"""

import importlib.util
import os
import pathlib
import shutil

from sphinx.util import logging

import pendula  # the installed (or staged) package being documented

HERE = pathlib.Path(__file__).resolve().parent


def _tool(name):
    """A module of tools/ loaded from its file (tools/ is not a package; no sys.path edit)."""
    spec = importlib.util.spec_from_file_location(name, HERE.parent / "tools" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


docs_docstrings = _tool("docs_docstrings")
logger = logging.getLogger("pendula.docs")

project = "pendula"
author = "the pendula authors"
copyright = "the pendula authors (MIT licence)"
release = getattr(pendula, "__version__", "")

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.intersphinx",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "_generated", "fortran", "ensembles.md", "gallery/_out"]
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3
autosummary_generate = True
autodoc_default_options = {"members": True}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
intersphinx_mapping = {}
html_theme = "alabaster"
html_title = "pendula"
html_static_path = []
# The generated pages (gallery, API list) are written before the build reads
# the sources; see _generate below.
suppress_warnings = ["myst.header"]


def _generate():
    """Write the generated pages.  Runs when this file is read, before Sphinx looks for
    source files: autosummary writes its stubs only for pages that exist by then."""
    docs_gallery = _tool("docs_gallery")

    # autosummary never deletes a stub: one left by a removed name would be read as a page
    shutil.rmtree(HERE / "api" / "generated", ignore_errors=True)
    docs_gallery.write_api_list(HERE / "api" / "index.rst")
    docs_gallery.write_ensembles_slot(HERE / "guide" / "ensembles.md", HERE / "ensembles.md")
    if os.environ.get("PENDULA_DOCS_GALLERY", "run") != "skip":
        docs_gallery.write_gallery(HERE / "gallery", HERE.parent / "examples" / "python")
    else:
        docs_gallery.write_gallery_placeholder(HERE / "gallery")


def _numpydoc_only(app, what, name, obj, options, lines):
    """Escape |x| for reST before numpydoc reads a docstring; warn (with -W: fail) on a
    public callable without numpydoc sections."""
    warning = docs_docstrings.prepare(what, name, lines)
    if warning:
        logger.warning("%s", warning, location=name)


def setup(app):
    # before numpydoc (priority 500) turns sections into fields
    app.connect("autodoc-process-docstring", _numpydoc_only, priority=400)


_generate()
