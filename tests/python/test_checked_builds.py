"""Checked builds, run by the normal test command.

1. tools/checked-build.sh: the Fortran library and Fortran tests built with
   -fcheck=all -ffpe-trap=invalid,zero,overflow -g (meson -Dchecked=true), then
   `meson test --suite fortran`.
2. tools/memcheck.sh: every Fortran test program under valgrind memcheck
   (--leak-check=full): zero errors, zero definite/indirect leaks.

Both build in their own folders (build/checked, build/memcheck) from the source
tree beside this file.  They are slow (a build each, valgrind ~30x), so they
carry the `slow` marker: `pytest -m "not slow"` deselects them.
"""

import os
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOOLS = ROOT / "tools"

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(
        not (TOOLS / "checked-build.sh").is_file() or not (ROOT / "meson.build").is_file(),
        reason="needs the source tree (tools/, meson.build)",
    ),
    pytest.mark.skipif(
        shutil.which("meson") is None or shutil.which("gfortran") is None or shutil.which("ninja") is None,
        reason="needs meson, ninja and gfortran",
    ),
]


def _run(script, build_dir):
    env = dict(os.environ)
    env.setdefault("PENDULA_TEST_QUICK", "1")
    proc = subprocess.run(
        ["bash", str(TOOLS / script), str(ROOT / build_dir)],
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        timeout=1500,
    )
    print(proc.stdout[-6000:])
    return proc


def test_checked_build_runs_fortran_tests_clean():
    proc = _run("checked-build.sh", "build/checked")
    assert proc.returncode == 0, f"checked build leg failed:\n{proc.stdout[-4000:]}"
    assert "Fortran suite PASSED" in proc.stdout


@pytest.mark.skipif(shutil.which("valgrind") is None, reason="valgrind not installed (apt-get install valgrind)")
def test_memcheck_fortran_tests_clean():
    proc = _run("memcheck.sh", "build/memcheck")
    assert proc.returncode == 0, f"memcheck leg failed:\n{proc.stdout[-4000:]}"
    assert "memcheck: PASSED" in proc.stdout
