"""pendula.build_info(): what meson configured, checked against the files it names."""

import re
import shutil
import subprocess
from pathlib import Path

import pytest

import pendula


def _header_version(include_dir):
    text = (Path(include_dir) / "sundials" / "sundials_config.h").read_text()
    return re.search(r'#define SUNDIALS_VERSION "([^"]+)"', text).group(1)


def test_sundials_entry_matches_the_linked_libraries():
    info = pendula.build_info()
    s = info["sundials"]
    assert set(s) == {"version", "origin", "prefix", "optimised"}
    assert info["cvode"] == pendula.have_cvode() == (s["origin"] != "none")
    if s["origin"] == "none":
        assert s["version"] is None and s["prefix"] is None and s["optimised"] is None
    elif s["origin"] == "prefix":
        prefix = Path(s["prefix"])
        assert (prefix / "lib" / "libsundials_cvode.a").is_file()
        assert s["version"] == _header_version(prefix / "include")
        # tools/build_sundials.sh stamps its (optimised) builds
        assert s["optimised"] == (True if list(prefix.glob(".pendula-sundials-recipe-*")) else None)
    else:
        assert s["origin"] == "system" and s["prefix"] is None
        assert s["version"] == _header_version("/usr/include")
        assert s["optimised"] in (False, None)


def test_compiler_entry():
    c = pendula.build_info()["compiler"]
    assert c["buildtype"] in {"plain", "debug", "debugoptimized", "release", "minsize", "custom"}
    assert c["optimization"] in {"plain", "0", "g", "1", "2", "3", "s"}
    # IEEE semantics are part of the contract: never -ffast-math
    assert "-ffast-math" not in c["fortran_args"]
    assert "-fno-trapping-math" in c["fortran_args"]
    gfortran = shutil.which("gfortran")
    if gfortran is None:
        pytest.skip("no gfortran on PATH to compare with")
    # built on this machine (quick start, pip install .): the gfortran on PATH
    out = subprocess.run([gfortran, "-dumpfullversion"], capture_output=True, text=True).stdout
    assert c["fortran"] == "gcc " + out.strip()


def test_build_info_is_a_copy():
    info = pendula.build_info()
    info["sundials"]["origin"] = "changed"
    info["compiler"]["fortran_args"].append("-x")
    again = pendula.build_info()
    assert again["sundials"]["origin"] != "changed"
    assert "-x" not in again["compiler"]["fortran_args"]
