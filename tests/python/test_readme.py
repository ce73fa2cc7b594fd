"""The README's snippets run, so they cannot rot: its Python block as a doctest, its
Fortran program compiled against the meson build of the library and run; and the README
stays within its size budget."""

import doctest
import re
import subprocess

from helpers import ROOT
from test_properties import _fortran_program

import pendula  # noqa: F401  (the doctest imports it too; fail early if it is missing)

README = ROOT / "README.md"


def _blocks(lang):
    return re.findall(r"^```%s\n(.*?)^```" % lang, README.read_text(), flags=re.S | re.M)


def test_readme_size_budget():
    assert README.stat().st_size <= 10 * 1024


def test_readme_python_snippet_runs_as_doctest():
    (block,) = _blocks("python")
    test = doctest.DocTestParser().get_doctest(block, {}, "README.md", str(README), 0)
    assert len(test.examples) >= 5
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    runner.run(test)
    assert runner.failures == 0, "the README's Python snippet no longer gives what it shows"


def test_readme_fortran_snippet_compiles_and_runs(tmp_path_factory):
    (block,) = _blocks("fortran")
    exe = _fortran_program(tmp_path_factory, "readme_demo", block)
    out = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60, check=True).stdout
    w0, t0 = (float(x) for x in out.split())
    # the text's w0 = sqrt(g/l) = sqrt(2) 1/s and T0 = 2 pi/w0 (eq. 1.8), to the 8 printed decimals
    assert abs(w0 - 2**0.5) < 1e-8
    assert abs(t0 - 2 * 3.141592653589793 / 2**0.5) < 1e-8
