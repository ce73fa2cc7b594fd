"""Helpers shared by the Python test modules (imported as `helpers`; pytest
puts this folder on sys.path because tests/python has no __init__.py)."""
import pathlib

import pytest

import pendula

#: The source tree (tests that read sources or data skip without it).
ROOT = pathlib.Path(__file__).resolve().parents[2]

#: Marks a test that reads the source tree.
needs_source = pytest.mark.skipif(not (ROOT / "src").is_dir(), reason="needs the source tree")

#: Whether this build has SUNDIALS CVODE, asked the one way (build_info).
HAVE_CVODE = pendula.build_info()["cvode"]

#: Marks a test that needs CVODE.
needs_cvode = pytest.mark.skipif(not HAVE_CVODE, reason="this pendula build has no SUNDIALS CVODE")


def fortran_statements(text):
    """Fortran free-form source as (line number, statement) with comments
    stripped and & continuations joined (good enough for declarations)."""
    out, buf, start = [], "", None
    for no, raw in enumerate(text.splitlines(), 1):
        line, quote = [], None
        for ch in raw:
            if quote:
                line.append(ch)
                if ch == quote:
                    quote = None
            elif ch in "'\"":
                quote = ch
                line.append(ch)
            elif ch == "!":
                break
            else:
                line.append(ch)
        s = "".join(line).strip()
        if not s:
            continue
        if buf and s.startswith("&"):
            s = s[1:]
        if start is None:
            start = no
        if s.endswith("&"):
            buf += s[:-1] + " "
            continue
        buf += s
        for stmt in buf.split(";"):
            if stmt.strip():
                out.append((start, stmt.strip()))
        buf, start = "", None
    return out
