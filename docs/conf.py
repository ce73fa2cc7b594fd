"""Sphinx configuration of the pendula documentation (built by tools/build_docs.sh).

The Python API pages are generated from pendula.__all__ and the docstrings
(autosummary + numpydoc); the example gallery is written by tools/docs_gallery.py,
which runs each examples/python/*.py in quick mode; the Fortran API is a FORD site
copied under fortran/ by tools/build_docs.sh and linked from fortran.md.
"""
import os
import pathlib
import re
import sys

from sphinx.util import logging

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tools"))

import pendula  # noqa: E402  the installed (or staged) package being documented

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
    import docs_gallery  # tools/docs_gallery.py

    docs_gallery.write_api_list(HERE / "api" / "index.rst")
    docs_gallery.write_ensembles_slot(HERE / "guide" / "ensembles.md", HERE / "ensembles.md")
    if os.environ.get("PENDULA_DOCS_GALLERY", "run") != "skip":
        docs_gallery.write_gallery(HERE / "gallery", HERE.parent / "examples" / "python")
    else:
        docs_gallery.write_gallery_placeholder(HERE / "gallery")


# Public names whose docstrings are not numpydoc yet: rendered as written (literal block)
# instead of failing the build.  The same list drives tests/python/test_docstrings.py.
PENDING = {ln.strip() for ln in (HERE / "numpydoc_pending.txt").read_text().splitlines()
           if ln.strip() and not ln.lstrip().startswith("#")} \
    if (HERE / "numpydoc_pending.txt").exists() else set()
_LITERAL_DIRECTIVE = re.compile(r"^\s*\.\.\s+(math|code|code-block|sourcecode|literalinclude)::")
_CODE_SPAN = re.compile(r"(``.+?``|`[^`]*`)")


def _escape_bars(lines):
    """Escape the | of absolute values (|x|, which reST reads as a substitution) in prose;
    leave them alone where reST does not read markup: inline code and roles (`...`),
    doctest blocks (>>> up to a blank line), literal blocks (after ::) and math/code
    directive bodies, and table rows."""
    literal_indent = None    # indent of the line that opened a literal block or directive
    doctest = False
    for i, line in enumerate(lines):
        stripped = line.strip()
        indent = len(line) - len(line.lstrip())
        if literal_indent is not None:
            if not stripped or indent > literal_indent:
                continue
            literal_indent = None
        if doctest:
            if stripped:
                continue
            doctest = False
        if stripped.startswith(">>>"):
            doctest = True
            continue
        if stripped.endswith("::") and (stripped == "::" or not stripped.startswith("..")
                                        or _LITERAL_DIRECTIVE.match(line)):
            literal_indent = indent
        if "|" not in line or stripped.startswith(("+", "|", "=")):
            continue
        parts = _CODE_SPAN.split(line)
        lines[i] = "".join(p if p.startswith("`") else p.replace("|", "\\|") for p in parts)


def _numpydoc_or_pending(app, what, name, obj, options, lines):
    """Check and prepare each docstring before numpydoc reads it.

    A docstring with numpydoc sections gets its |x| escaped (see _escape_bars).  A public
    function, class or method without sections fails the build (a warning; -W makes it an
    error) unless docs/numpydoc_pending.txt lists it: those are shown as written, their
    summary line and then the rest as a literal block (free-form text, aligned columns).
    Data and attributes (constants, dataclass fields) and properties are documented by a
    summary; they only get the escaping.
    """
    numpydoc_style = any(set(ln.strip()) == {"-"} and len(ln.strip()) >= 3 for ln in lines)
    short = name[len("pendula."):] if name.startswith("pendula.") else name
    if numpydoc_style or what not in ("function", "class", "method", "exception"):
        _escape_bars(lines)
        return
    if short not in PENDING and not short.rpartition(".")[2].startswith("_"):
        logger.warning("pendula.%s has no numpydoc sections (Parameters, Returns, Raises, "
                       "Examples): write them (tests/python/test_docstrings.py lists what "
                       "is missing)", short, location=name)
    end = lines.index("") if "" in lines else len(lines)
    lines[:end] = [ln.replace("|", "\\|") for ln in lines[:end]]
    rest = lines[end + 1:]
    if any(ln.strip() for ln in rest):
        lines[end + 1:] = ["::", ""] + ["    " + ln for ln in rest]


def setup(app):
    # before numpydoc (priority 500) turns sections into fields
    app.connect("autodoc-process-docstring", _numpydoc_or_pending, priority=400)


_generate()
