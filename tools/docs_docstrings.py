"""How the docs build reads pendula's docstrings (used by docs/conf.py, tested by
tests/python/test_docstrings.py): the escaping of absolute values |x| that reST would
read as substitutions, and the check that fails the build on a public callable without
numpydoc sections."""

import re

_LITERAL_DIRECTIVE = re.compile(r"^\s*\.\.\s+(math|code|code-block|sourcecode|literalinclude)::")
_CODE_SPAN = re.compile(r"(``.+?``|`[^`]*`)")
CHECKED = ("function", "class", "method", "exception")  # autodoc kinds that need sections


def escape_bars(lines):
    """Escape, in place, the | of absolute values in prose; leave them where reST reads no
    markup: inline code and roles (`...`, ``...``), doctest blocks (>>> up to a blank
    line), literal blocks (after ::), math and code directive bodies, and table rows."""
    literal_indent = None  # indent of the line that opened a literal block or directive
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
        if stripped.endswith("::") and (
            stripped == "::" or not stripped.startswith("..") or _LITERAL_DIRECTIVE.match(line)
        ):
            literal_indent = indent
        if "|" not in line or stripped.startswith(("+", "|", "=")):
            continue
        parts = _CODE_SPAN.split(line)
        lines[i] = "".join(p if p.startswith("`") else p.replace("|", "\\|") for p in parts)


def has_sections(lines):
    """Whether a docstring has numpydoc sections (a heading underlined with ---)."""
    return any(set(ln.strip()) == {"-"} and len(ln.strip()) >= 3 for ln in lines)


def prepare(what, name, lines):
    """Make one docstring (autodoc's lines, changed in place) safe for numpydoc and reST.

    Returns a warning for a public function, class or method of pendula without numpydoc
    sections (the docs build fails on it with -W), else None.  Data, attributes and
    properties are documented by a summary and are only escaped.
    """
    escape_bars(lines)
    short = name[len("pendula.") :] if name.startswith("pendula.") else name
    if has_sections(lines) or what not in CHECKED or short.rpartition(".")[2].startswith("_"):
        return None
    return (
        f"pendula.{short} has no numpydoc sections (Parameters, Returns, Raises, "
        "Examples): write them (tests/python/test_docstrings.py lists what is missing)"
    )
