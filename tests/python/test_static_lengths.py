"""No Fortran function returns a deferred-length character result.

gfortran 12 (Debian bookworm, the CI compiler) compiles every call of a
function whose result is ``character(len=:), allocatable`` with the result's
length in a *static* variable at the call site (``static integer(kind=8)
slen.N`` in -fdump-tree-original), also with -fopenmp and in pure functions.
Two threads at the same call site race on it: messages came out garbled or
truncated ("w0 = -1e- is out of range") when Python threads hit errors at
once.  The library's text functions therefore return explicit lengths
(computed by specification functions) and build text in local deferred-length
variables or fixed buffers, which are safe; tests/fortran/test_threads_messages
checks the texts under OpenMP.  This scan keeps the pattern from coming back.
"""

import re

from helpers import ROOT, needs_source

_FUNCTION = re.compile(
    r"^\s*(?:(?:pure|elemental|impure|recursive|module)\s+)*function\s+(\w+)\s*\([^)]*\)"
    r"(?:.*?\bresult\s*\(\s*(\w+)\s*\))?",
    re.I,
)
_END = re.compile(r"^\s*end\s+function\b", re.I)
_DEFERRED = re.compile(r"^\s*character\s*\(\s*len\s*=\s*:\s*\)\s*,\s*allocatable\s*::\s*(.*)$", re.I)


def deferred_results(text):
    """Names of the functions in Fortran source `text` whose result is
    declared ``character(len=:), allocatable`` (continuations joined)."""
    lines = re.sub(r"&\s*\n\s*&?", " ", text).splitlines()
    found, current = [], None
    for line in lines:
        code = line.split("!", 1)[0]
        match = _FUNCTION.match(code)
        if match:
            current = (match.group(1), (match.group(2) or match.group(1)).lower())
        elif _END.match(code):
            current = None
        elif current:
            decl = _DEFERRED.match(code)
            if decl and current[1] in {n.strip().lower() for n in decl.group(1).split(",")}:
                found.append(current[0])
    return found


def test_scan_finds_a_deferred_result():
    """The scan sees both spellings of a result (named and result(...))."""
    source = """
  pure function name_of(code) result(s)
    integer, intent(in) :: code
    character(len=:), allocatable :: s
    s = 'x'
  end function name_of
  function other(code)
    integer, intent(in) :: code
    character(len=:), allocatable :: work, other
  end function other
  subroutine fine(s)
    character(len=:), allocatable, intent(out) :: s
  end subroutine fine
  function fixed(x) &
      result(s)
    real, intent(in) :: x
    character(len=len_trim('ab')) :: s
    character(len=:), allocatable :: work
  end function fixed
"""
    assert deferred_results(source) == ["name_of", "other"]


@needs_source
def test_no_function_returns_deferred_length_character():
    """Every Fortran source of the library and of the f2py glue is free of
    functions with a ``character(len=:), allocatable`` result (why: the module
    docstring)."""
    paths = [p for folder in ("src", "python/f2py") for p in (ROOT / folder).rglob("*") if p.suffix.lower() == ".f90"]
    assert len(paths) > 30
    bad = {str(p.relative_to(ROOT)): names for p in paths if (names := deferred_results(p.read_text()))}
    assert not bad, f"functions with a deferred-length character result: {bad}"
