"""Every public name has a numpydoc docstring that teaches, and its Examples run.

What is checked, per name of ``pendula.__all__`` and per public method and property of
the public classes (one test per name, so a failure names what to fix):

* the docstring parses with numpydoc and passes numpydoc's own validation
  (``numpydoc.validate``) for the codes in ``CHECKS``: a summary, no unknown or misplaced
  section, every signature parameter documented and every documented parameter in the
  signature (with a description), Returns when the code returns a value (Yields for a
  generator), Examples for callables (not for properties: they read like attributes);
* classes may document their constructor arguments under Parameters or Attributes
  (result containers are built by pendula, read by users); each documented one exists;
* Raises names every exception the function raises on bad input: for the numerical entry
  points, the exception types of their bad-input cases in ``api_table`` (which
  test_bad_input.py checks they raise); for other callables, Raises is required when their
  source raises or checks arguments through ``pendula._arrays``;
* constants (``TURNING_POINT``, ...) have no docstring of their own (an int's ``__doc__`` is
  int's): their home is an attribute docstring under the assignment (what autodoc shows on
  their API page, read here with Sphinx's ``ModuleAnalyzer``), and another public docstring
  names them (the result that carries them);
* the Examples run as doctests (ELLIPSIS, NORMALIZE_WHITESPACE, NumPy's print options fixed,
  ``np`` and ``pendula`` imported beforehand as in NumPy's own docstrings).

The docs build applies the same rule (tools/docs_docstrings.py): a public callable without
numpydoc sections fails it.
"""

import ast
import doctest
import inspect
import textwrap

import numpy as np
import pytest
from api_table import ALL_CASES, API
from helpers import ROOT, load_file

import pendula

pytest.importorskip("numpydoc")
from numpydoc.docscrape import get_doc_object  # noqa: E402
from numpydoc.validate import validate  # noqa: E402

#: numpydoc.validate codes every public docstring must pass.
CHECKS = {
    "GL08": "no docstring",
    "GL06": "unknown section",
    "GL07": "sections in the wrong order",
    "SS01": "no summary",
    "PR01": "signature parameters not documented",
    "PR02": "documented parameters not in the signature",
    "PR07": "parameter without description",
    "RT01": "no Returns section though the code returns a value",
    "RT03": "return value without description",
    "YD01": "no Yields section for a generator",
    "EX01": "no Examples section",
}


DOCS = load_file(ROOT / "tools" / "docs_docstrings.py")  # the docs build's own code


def _is_constant(obj):
    return isinstance(obj, (int, float, str)) and not isinstance(obj, bool)


def _members(cls):
    """Public methods and properties a user reaches on cls, defined in pendula (not by
    object, Exception or the dataclass machinery)."""
    out = {}
    for klass in reversed(cls.__mro__):
        if not klass.__module__.startswith("pendula"):
            continue
        for name, value in vars(klass).items():
            if name.startswith("_"):
                continue
            if isinstance(value, property) or inspect.isfunction(value):
                out[name] = value
            elif isinstance(value, (staticmethod, classmethod)):
                out[name] = value.__func__
    return out


def _public():
    """[(test name, object, kind)] with kind in constant, class, function, method, property."""
    items = []
    for name in sorted(pendula.__all__):
        obj = getattr(pendula, name)
        if _is_constant(obj):
            items.append((name, obj, "constant"))
        elif inspect.isclass(obj):
            items.append((name, obj, "class"))
            for mname, member in sorted(_members(obj).items()):
                kind = "property" if isinstance(member, property) else "method"
                items.append((f"{name}.{mname}", member, kind))
        else:
            items.append((name, obj, "function"))
    return items


PUBLIC = _public()
DOCUMENTED = [p for p in PUBLIC if p[2] != "constant"]
CONSTANTS = [p for p in PUBLIC if p[2] == "constant"]


def _raises_on_bad_input():
    """{function: exception class names} from api_table's bad-input cases."""
    out = {}
    for case in ALL_CASES:
        if isinstance(case.expect, type) and issubclass(case.expect, Exception):
            out.setdefault(case.func, set()).add(case.expect.__name__)
    return out


RAISES = _raises_on_bad_input()


def _source_raises(obj):
    """Whether obj's own source raises or checks its arguments with pendula._arrays."""
    func = obj.fget if isinstance(obj, property) else obj
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(func)))
    except (OSError, TypeError):
        return False
    checkers = {"as_real", "real_scalar", "check_size", "integer_arg", "raise_for_status"}
    for node in ast.walk(tree):
        if isinstance(node, ast.Raise):
            return True
        if isinstance(node, ast.Call):
            f = node.func
            called = f.id if isinstance(f, ast.Name) else getattr(f, "attr", "")
            if called in checkers or called.startswith("check_"):
                return True
    return False


def _signature_params(obj):
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    return [
        p.name
        for p in sig.parameters.values()
        if p.name not in ("self", "cls") and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
    ]


def _entry_names(entry):
    """The names of one Parameters/Attributes entry: numpydoc allows ``theta, omega : ndarray``."""
    return [n.strip() for n in entry.name.split(":")[0].split(",") if n.strip()]


def _takes_var_positional(obj):
    """True for a constructor taking *args, or one without a signature (a builtin
    exception's: its message has no parameter name to match)."""
    try:
        return any(p.kind == p.VAR_POSITIONAL for p in inspect.signature(obj).parameters.values())
    except (TypeError, ValueError):
        return True


def _problems(name, obj, kind):
    """What the docstring of one public object lacks (empty when it teaches)."""
    what = {"class": "class", "method": "method", "property": "property"}.get(kind, "function")
    doc = get_doc_object(obj, what=what)
    report = validate(doc)
    skip = set()
    if kind == "class":
        skip |= {"PR01", "PR02", "RT01", "YD01"}  # checked below (Attributes count)
    if kind == "property":
        skip |= {"PR01", "PR02", "RT01", "EX01"}  # attribute-like: a summary suffices
    found = [f"{code} ({CHECKS[code]}): {msg}" for code, msg in report["errors"] if code in CHECKS and code not in skip]
    if not doc["Summary"]:
        return found or ["no summary"]
    if kind == "class":
        documented = {n for sec in ("Parameters", "Attributes") for p in doc[sec] for n in _entry_names(p)}
        params = _signature_params(obj)
        missing = [p for p in params if p not in documented]
        unknown = (
            []
            if _takes_var_positional(obj)
            else [n for p in doc["Parameters"] for n in _entry_names(p) if n not in params]
        )
        if missing:
            found.append(f"constructor arguments not under Parameters or Attributes: {missing}")
        if unknown:
            found.append(f"Parameters not in the constructor: {unknown}")
    if kind in ("function", "method", "class"):
        raised = {r.type.strip() for r in doc["Raises"]}
        raised |= {n.strip() for r in doc["Raises"] for n in r.type.split(",")}
        must = RAISES.get(name, set()) if name in API else set()
        if must - raised:
            found.append(f"Raises lacks {sorted(must - raised)} (its bad-input cases in api_table)")
        if not must and not doc["Raises"] and kind != "class" and _source_raises(obj):
            found.append("no Raises section though the source raises or checks arguments")
    return found


@pytest.mark.parametrize("name, obj, kind", [pytest.param(*p, id=p[0]) for p in DOCUMENTED])
def test_numpydoc_sections(name, obj, kind):
    problems = _problems(name, obj, kind)
    assert not problems, f"pendula.{name}:\n  " + "\n  ".join(problems)


def _attribute_docs():
    """{(module, name): attribute docstring} of pendula's modules, as autodoc reads them."""
    from sphinx.pycode import ModuleAnalyzer

    out = {}
    for _, obj, _kind in PUBLIC:
        mod = getattr(obj, "__module__", None)
        if mod and mod.startswith("pendula") and mod not in {m for m, _ in out}:
            for (scope, attr), lines in ModuleAnalyzer.for_module(mod).find_attr_docs().items():
                if not scope:
                    out[(mod, attr)] = "\n".join(lines).strip()
    return out


@pytest.mark.parametrize("name, value, kind", [pytest.param(*c, id=c[0]) for c in CONSTANTS])
def test_constant_has_documented_home(name, value, kind):
    pytest.importorskip("sphinx")
    docs = {attr: text for (_mod, attr), text in _attribute_docs().items() if text}
    assert name in docs, f"pendula.{name} needs an attribute docstring under its assignment (what its API page shows)"
    users = [n for n, obj, k in PUBLIC if k != "constant" and name in (inspect.getdoc(obj) or "")]
    assert users, f"no public docstring names pendula.{name} (the result that carries it)"


def _doctests(obj, name):
    finder = doctest.DocTestFinder(recurse=False, exclude_empty=True)
    globs = {"np": np, "pendula": pendula}
    tests = finder.find(obj, f"pendula.{name}", globs=globs, module=False)
    return [t for t in tests if t.examples]


@pytest.mark.parametrize("name, obj, kind", [pytest.param(*p, id=p[0]) for p in DOCUMENTED])
def test_examples_run(name, obj, kind, tmp_path, monkeypatch):
    func = obj.fget if isinstance(obj, property) else obj
    tests = _doctests(func, name)
    if not tests:
        pytest.skip("no Examples (test_numpydoc_sections reports a missing section)")
    monkeypatch.chdir(tmp_path)  # examples that write files write them here
    monkeypatch.setenv("MPLBACKEND", "Agg")
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    with np.printoptions(
        precision=8,
        threshold=1000,
        edgeitems=3,
        linewidth=75,
        suppress=False,
        floatmode="maxprec",
        sign="-",
        legacy=False,
    ):
        for test in tests:
            runner.run(test)
    assert runner.failures == 0, f"pendula.{name}: {runner.failures} example(s) gave other output"


def _sample(theta0, w0=1.0):
    r"""Return the small-angle period of a pendulum.

    The period of :math:`\theta'' + w_0^2 \theta = 0` does not depend on
    :math:`|\theta_0|`.

    Parameters
    ----------
    theta0 : float
        Initial angle [rad]; any finite real.
    w0 : float, optional
        Natural angular frequency [1/s], > 0.

    Returns
    -------
    float
        :math:`2\pi/w_0` [s].

    Raises
    ------
    ValueError
        If `w0` is not > 0.

    Examples
    --------
    >>> round(_sample(0.1, w0=2.0), 6)
    3.141593
    """
    if not w0 > 0:
        raise ValueError("w0 must be > 0")
    return 2 * np.pi / w0


def _bare(theta0, w0=1.0):
    """Small-angle period; theta0 [rad], w0 [1/s]."""
    if not w0 > 0:
        raise ValueError("w0 must be > 0")
    return 2 * np.pi / w0


def test_checks_accept_a_teaching_docstring_and_reject_a_bare_one():
    assert _problems("_sample", _sample, "function") == []
    codes = " ".join(_problems("_bare", _bare, "function"))
    for what in ("PR01", "RT01", "EX01", "no Raises"):
        assert what in codes
    (test,) = _doctests(_sample, "_sample")
    test.globs["_sample"] = _sample
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    runner.run(test)
    assert runner.failures == 0 and runner.tries == 1


def test_docs_build_escapes_absolute_values_only_in_prose():
    """What the docs build does to a docstring before numpydoc reads it (docs/conf.py)."""
    lines = [
        "Summary with |x|.",
        "",
        "Text |x - y| and ``|g|`` and :math:`|w_0|`.",
        "",
        ".. math::",
        "",
        "    |w_0| > 0",
        "",
        "After |t|::",
        "",
        "    |literal|",
        "",
        ">>> abs(-1)   # |x|",
        "1",
        "",
        "Parameters",
        "----------",
    ]
    assert DOCS.prepare("function", "pendula.f", lines) is None
    assert lines[0] == "Summary with \\|x\\|."
    assert lines[2] == "Text \\|x - y\\| and ``|g|`` and :math:`|w_0|`."
    assert lines[6] == "    |w_0| > 0" and lines[10] == "    |literal|"
    assert lines[8] == "After \\|t\\|::"
    assert lines[12] == ">>> abs(-1)   # |x|"


def test_docs_build_warns_on_a_callable_without_sections():
    bare = ["Summary |x|.", "", "free text", "  aligned |columns|"]
    assert "pendula.f has no numpydoc sections" in DOCS.prepare("function", "pendula.f", list(bare))
    assert "pendula.C.m has no numpydoc sections" in DOCS.prepare("method", "pendula.C.m", list(bare))
    assert DOCS.prepare("method", "pendula.C.__init__", list(bare)) is None
    assert DOCS.prepare("data", "pendula.CONST", list(bare)) is None
