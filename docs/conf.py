"""Sphinx configuration of the pendula documentation (built by tools/build_docs.sh).

The Python API pages are generated from pendula.__all__ and the docstrings
(autosummary + numpydoc); the example gallery is written by tools/docs_gallery.py,
which runs each examples/python/*.py in quick mode; the Fortran API is a FORD site
copied under fortran/ by tools/build_docs.sh and linked from fortran.md.
"""
import importlib.util
import os
import pathlib

import pendula  # the installed (or staged) package being documented

HERE = pathlib.Path(__file__).resolve().parent

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
    # tools/docs_gallery.py, loaded from its file (tools/ is not a package)
    spec = importlib.util.spec_from_file_location("docs_gallery", HERE.parent / "tools" / "docs_gallery.py")
    docs_gallery = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(docs_gallery)

    docs_gallery.write_api_list(HERE / "api" / "index.rst")
    docs_gallery.write_ensembles_slot(HERE / "guide" / "ensembles.md", HERE / "ensembles.md")
    if os.environ.get("PENDULA_DOCS_GALLERY", "run") != "skip":
        docs_gallery.write_gallery(HERE / "gallery", HERE.parent / "examples" / "python")


def _plain_docstrings(app, what, name, obj, options, lines):
    """Make docstrings safe for reST before numpydoc reads them.

    A docstring with numpydoc sections gets its |x| (absolute values, which reST would
    read as substitutions) escaped.  One without sections (free-form text, aligned
    columns) is shown as written: its summary line, then the rest as a literal block.
    """
    numpydoc_style = any(set(ln.strip()) == {"-"} and len(ln.strip()) >= 3 for ln in lines)
    if numpydoc_style:
        for i, line in enumerate(lines):
            if "|" in line and not line.lstrip().startswith(("+", "|", "=")):
                lines[i] = line.replace("|", "\\|")
        return
    end = lines.index("") if "" in lines else len(lines)
    lines[:end] = [ln.replace("|", "\\|") for ln in lines[:end]]
    rest = lines[end + 1:]
    if any(ln.strip() for ln in rest):
        lines[end + 1:] = ["::", ""] + ["    " + ln for ln in rest]


def setup(app):
    # before numpydoc (priority 500) turns sections into fields
    app.connect("autodoc-process-docstring", _plain_docstrings, priority=400)


_generate()
