"""How the docs build reads pendula's docstrings (used by docs/conf.py, tested by
tests/python/test_docstrings.py): the list of names whose docstrings are not numpydoc
yet, the escaping of absolute values |x| that reST would read as substitutions, and the
check that fails the build on a public callable without numpydoc sections."""
import re

_LITERAL_DIRECTIVE = re.compile(r"^\s*\.\.\s+(math|code|code-block|sourcecode|literalinclude)::")
_CODE_SPAN = re.compile(r"(``.+?``|`[^`]*`)")
CHECKED = ("function", "class", "method", "exception")   # autodoc kinds that need sections


def read_pending(path):
    """Names listed in docs/numpydoc_pending.txt (one a line, # comments); empty without it."""
    try:
        text = path.read_text()
    except FileNotFoundError:
        return set()
    return {ln.strip() for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")}


def escape_bars(lines):
    """Escape, in place, the | of absolute values in prose; leave them where reST reads no
    markup: inline code and roles (`...`, ``...``), doctest blocks (>>> up to a blank
    line), literal blocks (after ::), math and code directive bodies, and table rows."""
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


def has_sections(lines):
    """Whether a docstring has numpydoc sections (a heading underlined with ---)."""
    return any(set(ln.strip()) == {"-"} and len(ln.strip()) >= 3 for ln in lines)


def prepare(what, name, lines, pending):
    """Make one docstring (autodoc's lines, changed in place) safe for numpydoc and reST.

    Returns a warning for a public function, class or method of pendula without numpydoc
    sections that ``pending`` does not list (the docs build fails on it with -W), else None.
    Such a docstring is shown as written either way: its summary, then the rest as a
    literal block (free-form text, aligned columns).  Data, attributes and properties are
    documented by a summary and are only escaped.
    """
    if has_sections(lines) or what not in CHECKED:
        escape_bars(lines)
        return None
    short = name[len("pendula."):] if name.startswith("pendula.") else name
    warning = None
    if short not in pending and not short.rpartition(".")[2].startswith("_"):
        warning = (f"pendula.{short} has no numpydoc sections (Parameters, Returns, Raises, "
                   "Examples): write them (tests/python/test_docstrings.py lists what is missing)")
    end = lines.index("") if "" in lines else len(lines)
    summary = lines[:end]
    escape_bars(summary)
    rest = lines[end + 1:]
    lines[:end] = summary
    if any(ln.strip() for ln in rest):
        lines[end + 1:] = ["::", ""] + ["    " + ln for ln in rest]
    return warning
