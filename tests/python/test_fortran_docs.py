"""Every dummy argument of every public Fortran procedure carries a doc comment
that the FORD site (docs/fortran/pendula.md) renders: `!<` at the end of the
declaration or on the lines right after it, or `!>` on the lines right above
it.  Users calling pendula from Fortran read its argument lists there.

Public procedures are the names in the modules' `public` statements and the
specific procedures of public generic interfaces; files pulled in by
`include`/`#include` are read as part of their module (the FORD site is built
from the preprocessed source, so the no-CVODE stand-ins are what it shows).
A declaration of several arguments needs one comment naming each of them
(FORD shows that one comment for every one of them), and FORD drops a `!<`
comment of two or more lines after such a declaration.
"""

import re

from helpers import ROOT, needs_source

SRC = ROOT / "src"

_HEADER = re.compile(
    r"^\s*(?:(?:pure|elemental|impure|recursive|module|non_recursive)\s+|"
    r"(?:(?:real|integer|logical|complex|character|type)\s*(?:\([^)]*\))?\s+))*"
    r"(subroutine|function)\s+(\w+)\s*(?:\(([^)]*)\))?",
    re.I,
)
_END = re.compile(r"^\s*end\s+(subroutine|function|module|interface)\b", re.I)
_MODULE = re.compile(r"^\s*module\s+(?!procedure\b)(\w+)\s*$", re.I)
_INTERFACE = re.compile(r"^\s*(?:abstract\s+)?interface\b\s*(\w+)?", re.I)
_INCLUDE = re.compile(r"""^\s*#?\s*include\s+['"]([\w.]+)['"]""", re.I)


def _code(line):
    """The line without its comment (no `!` inside the strings this scan needs)."""
    return re.sub(r"""(['"]).*?\1""", lambda m: "x" * len(m.group(0)), line).split("!")[0]


def _lines(path):
    """Physical lines of path with include files expanded in place."""
    out = []
    for line in path.read_text().splitlines():
        m = _INCLUDE.match(line)
        if m and (path.parent / m.group(1)).is_file() and m.group(1) != "pendula_msg_len.inc":
            out.extend(_lines(path.parent / m.group(1)))
        else:
            out.append(line)
    return out


def _statements(lines):
    """(first, last, joined code) of each statement, continuation lines joined."""
    i = 0
    while i < len(lines):
        first = i
        code = _code(lines[i])
        while code.rstrip().endswith("&") and i + 1 < len(lines):
            i += 1
            code = code.rstrip()[:-1] + " " + _code(lines[i]).lstrip().lstrip("&")
        yield first, i, code
        i += 1


def _names(text):
    """Comma-separated names at parenthesis depth 0 (entity list)."""
    depth, cur, out = 0, "", []
    for ch in text:
        depth += ch in "(["
        depth -= ch in ")]"
        if ch == "," and depth == 0:
            out.append(cur)
            cur = ""
        else:
            cur += ch
    out.append(cur)
    return [re.match(r"\s*(\w*)", n).group(1).lower() for n in out if n.strip()]


def _documented(lines, first, last, single=True):
    """The doc comment of the statement on lines first..last ('' if none).
    After a declaration of several names FORD keeps one `!<` line but drops
    two or more (the FORD build of this tree shows it), so such a statement
    counts as documented only by `!>` above, `!<` on its line, or one `!<`
    line after it."""
    doc = []
    j = first - 1
    while j >= 0 and lines[j].lstrip().startswith("!>"):
        doc.append(lines[j])
        j -= 1
    m = re.search(r"!<.*", lines[last])
    if m:
        doc.append(m.group(0))
    j = last + 1
    while j < len(lines) and lines[j].lstrip().startswith("!<"):
        j += 1
    if single or j == last + 2:
        doc.extend(lines[last + 1 : j])
    return " ".join(doc)


def _scan(path):
    """Yield (procedure, argument, documented) for the public procedures of path."""
    lines = _lines(path)
    stmts = list(_statements(lines))
    public, generics, procs = set(), {}, []
    in_module, generic = False, None
    stack = []  # open procedures: [name, dummies, {arg: doc}, interface depth at its start]
    iface_depth = 0
    for first, last, code in stmts:
        low = code.strip().lower()
        if not low:
            continue
        if _MODULE.match(low):
            in_module = True
            continue
        if not in_module:
            continue
        m = re.match(r"public\s*(?:::)?\s*(.*)", low)
        if m and not stack:
            public.update(_names(m.group(1)))
            continue
        m = _INTERFACE.match(low)
        if m and not low.startswith("interface assignment"):
            iface_depth += 1
            if not stack and m.group(1):
                generic = m.group(1).lower()
            continue
        if re.match(r"end\s+interface\b", low):
            iface_depth -= 1
            generic = None
            continue
        m = re.match(r"module\s+procedure\s*(?:::)?\s*(.*)", low)
        if m and generic:
            generics.setdefault(generic, set()).update(_names(m.group(1)))
            continue
        m = _HEADER.match(low)
        if m and not low.startswith("end"):
            name = m.group(2).lower()
            if stack and iface_depth:
                # a dummy procedure declared by an interface body inside a procedure
                outer = stack[-1]
                if name in outer[1] and name not in outer[2]:
                    outer[2][name] = _documented(lines, first, last)
            stack.append([name, _names(m.group(3) or ""), {}, iface_depth])
            continue
        m = _END.match(low)
        if m and m.group(1).lower() in ("subroutine", "function"):
            name, dummies, docs, depth = stack.pop()
            if not stack and not depth:
                procs.append((name, dummies, docs))
            continue
        if stack and "::" in low:
            proc = stack[-1]
            names = _names(low.split("::", 1)[1])
            decl = [n for n in names if n in proc[1]]
            doc = _documented(lines, first, last, len(names) == 1) if decl else ""
            for arg in decl:
                if arg in proc[2]:
                    continue
                ok = bool(doc.strip("!<> "))
                if ok and len(decl) > 1:
                    ok = bool(re.search(rf"\b{arg}\b", doc, re.I))
                proc[2][arg] = doc if ok else ""
    wanted = set(public)
    for gen, specifics in generics.items():
        if gen in public:
            wanted |= specifics
    for name, dummies, docs in procs:
        if name in wanted:
            for arg in dummies:
                if arg and arg != "*":
                    yield name, arg, bool(docs.get(arg))


def undocumented():
    """{(file under src/, procedure, argument)} of all undocumented arguments, and the count checked."""
    missing, total = set(), 0
    for path in sorted(SRC.rglob("*")):
        if path.suffix not in (".f90", ".F90"):
            continue
        rel = path.relative_to(SRC).as_posix()
        for proc, arg, ok in _scan(path):
            total += 1
            if not ok:
                missing.add((rel, proc, arg))
    return missing, total


@needs_source
def test_public_arguments_are_documented():
    missing, total = undocumented()
    assert total > 500  # the scan found the API (a broken parser would find nothing)
    missing = sorted(missing)
    assert missing == [], f"{len(missing)} arguments without a doc comment: {missing}"


if __name__ == "__main__":
    for item in sorted(undocumented()[0]):
        print(*item, sep="\t")
