"""os.fork() while other threads are inside pendula's error paths.

A forked child inherits only the forking thread: any lock another thread held
at that moment stays locked in the child for ever.  Library code that formats a
number into an error message with an internal WRITE takes libgfortran's unit
lock, so a child forked while a thread is inside such a message blocks on its
first own message (about 1 fork in 100 did before the messages were formatted
without I/O by pendula_format).

Three threads hammer the error paths (RK4 refusing an unstable step, CVODE and
Scene with bad input, an elliptic function out of its domain, linear_damped
with a bad argument) while the main thread forks 400 times.  Each child calls
the same error paths once, then ``os._exit(0)``; the parent waits for it with a
timeout and counts the children that did not finish (killed after the timeout).
The test fails if any child hangs or exits with a non-zero status.
"""

from __future__ import annotations

import importlib
import importlib.machinery
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from helpers import HAVE_CVODE

import pendula

ROOT = Path(__file__).resolve().parents[2]

# An I/O statement (internal or external) or a STOP, which writes to stderr:
# each takes a libgfortran lock.
IO_STATEMENT = re.compile(
    r"\b(write|read|open|close|inquire|flush|backspace|rewind|endfile|wait)\s*\("
    r"|\bprint\s*(\*|\d|'|\")|\b(error\s+)?stop\b",
    re.IGNORECASE,
)

N_FORKS = 400
N_THREADS = 3
CHILD_TIMEOUT = 3.0  # s; a child normally finishes in a few ms
T = np.linspace(0.0, 10.0, 5)


STRING_LITERAL = re.compile(r"'[^']*'|\"[^\"]*\"")


def _code_without_comments_and_strings(line):
    """The Fortran statement text of a line: string literals emptied, the
    comment after '!' dropped."""
    return STRING_LITERAL.sub("''", line).split("!", 1)[0]


def io_statements(root):
    """(file, line number, line) of every I/O or STOP statement in the library
    sources (src/) and the f2py glue (python/f2py/)."""
    found = []
    sources = [
        f
        for pattern in ("*.f90", "*.F90", "*.inc")
        for f in (*(root / "src").rglob(pattern), *(root / "python" / "f2py").glob(pattern))
    ]
    for f in sorted(sources):
        for k, line in enumerate(f.read_text().splitlines(), 1):
            if IO_STATEMENT.search(_code_without_comments_and_strings(line)):
                found.append((str(f.relative_to(root)), k, line.strip()))
    return found


def test_no_io_statement_in_library_code():
    """Library code formats numbers with pendula_format, never with an internal
    WRITE (nor any other I/O): a WRITE in an error path reopens the fork hang."""
    assert len(list((ROOT / "src").rglob("*.f90"))) > 10 and (ROOT / "python" / "f2py").is_dir()
    assert io_statements(ROOT) == []


def test_the_io_scan_finds_io_statements(tmp_path):
    """The scan is not blind: it finds the statement forms it must, and ignores
    comments and message text."""
    (tmp_path / "src").mkdir()
    (tmp_path / "python" / "f2py").mkdir(parents=True)
    (tmp_path / "src" / "a.f90").write_text(
        "    write (buf, '(i0)') n\n"
        "    if (x > 0) read(buf(3:), *) e\n"
        "    PRINT *, x\n"
        "    error stop 1\n"
        "    ! write (buf, '(i0)') n is what we avoid\n"
        "    s = 'cannot read (or write (x)) this'  ! print *, 'no'\n"
    )
    (tmp_path / "python" / "f2py" / "b.f90").write_text("  call x(); write(*,*) 1\n")
    assert [(f[:3], k) for f, k, _ in io_statements(tmp_path)] == [
        ("pyt", 1),
        ("src", 1),
        ("src", 2),
        ("src", 3),
        ("src", 4),
    ]


def _glue_error_calls():
    """The same error paths through the f2py glue directly: the GIL is released
    for almost the whole call, so a thread is inside the message formatting at a
    fork far more often than through the Python layer's validation (through the
    public API about 4 forks in 1,000 hung on the old code, through the glue
    about 18 in 1,000)."""
    glue = importlib.import_module("pendula._fortran")
    _codes = importlib.import_module("pendula._codes")
    t, one = T, np.array([0.0, 1.0])
    ctl = np.zeros(2, dtype=np.int64)  # the cancel/progress array (pendula_control), never set
    calls = [
        lambda: glue.rk4_f2py(t, 0.5, 0.0, 2.0, 0.1, 5.0, 2e9, ctl),
        lambda: glue.linear_damped_one_f2py(one, 0.5, 0.0, -2.0, 0.1),
        lambda: glue.scene_physics_f2py(9.8, 4.9, 0.1, 1.0, 0.5, 1, 1, 1),
        lambda: glue.scene_check_f2py(t, 0.5, 0.0, 2.0, 0.1, -1.0, 1, 0, 0, 1, 0.0, 1.0, 0.0),  # no drive
        lambda: glue.ellip_ke_f2py(_codes.GLUE_ELLIPK, np.array([2.0, 3.0]), np.empty(2)),
    ]
    if HAVE_CVODE:
        calls += [
            lambda: glue.cvode_f2py(t, 0.5, 0.0, 2.0, 0.1, -1.0, 1e-10, 1, 1e7, 0, ctl),
            lambda: glue.cvode_f2py(t, 0.5, 0.0, 2.0, 0.1, 1e-8, 1e-10, 1, 2.0, 0, ctl),
        ]
    return calls


def _public_error_calls():
    """Public calls that each end in a formatted error message (the elliptic
    entry in a domain error)."""
    calls = [
        lambda: pendula.rk4(T, 0.5, 0.0, 2.0, 0.1, h=5.0),  # unstable step
        lambda: pendula.linear_damped([1.0, 2.0], 0.5, 0.0, [2.0, -np.inf], 0.1),
        lambda: pendula.linear_damped(1.0, 0.5, 0.0, -2.0, 0.1),
        lambda: pendula.Scene(theta0=0.5, gamma=0.1, mass=1.0, b=0.5),  # gamma and b/mass disagree
        lambda: pendula.Scene(theta0=0.5, g=-1.0),
        lambda: pendula.ellipk(2.0),
    ]
    if HAVE_CVODE:
        calls += [
            lambda: pendula.cvode(T, 0.5, 0.0, 2.0, 0.1, rtol=-1.0),
            lambda: pendula.cvode(T, 0.5, 0.0, 2.0, 0.1, max_steps=2),  # solver gives up: message with t
        ]
    return calls


def _run(call):
    try:
        call()
    except (ValueError, RuntimeError, ArithmeticError):
        pass


def test_every_error_path_reports_an_error():
    """The hammered calls really reach an error path (else the fork test below
    could not fail)."""
    for call in _public_error_calls():
        with pytest.raises((ValueError, RuntimeError), match=r"\S"):
            call()
    for call in _glue_error_calls()[:4]:
        out = call()
        assert out[-2] != 0 and out[-1].strip(), out[-2:]


@pytest.mark.skipif(
    not hasattr(os, "fork") or sys.platform == "darwin", reason="os.fork() with threads needs a POSIX fork (Linux)"
)
def test_fork_while_threads_format_error_messages():
    calls = _glue_error_calls()
    child_calls = _public_error_calls()
    stop = threading.Event()

    crashed = []  # a hammer that dies (e.g. a glue signature changed) would leave the forks unhammered

    def hammer(offset):
        i = offset
        try:
            while not stop.is_set():
                _run(calls[i % len(calls)])
                i += 1
        except Exception as exc:
            crashed.append(repr(exc))

    threads = [threading.Thread(target=hammer, args=(k,), daemon=True) for k in range(N_THREADS)]
    for th in threads:
        th.start()
    hung, failed = 0, 0
    try:
        for _ in range(N_FORKS):
            pid = os.fork()
            if pid == 0:  # child: one call into each error path, then leave at once
                try:
                    for call in child_calls:
                        _run(call)
                finally:
                    os._exit(0)
            deadline = time.monotonic() + CHILD_TIMEOUT
            while True:
                done, status = os.waitpid(pid, os.WNOHANG)
                if done:
                    if not (os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0):
                        failed += 1
                    break
                if time.monotonic() > deadline:
                    hung += 1
                    os.kill(pid, signal.SIGKILL)
                    os.waitpid(pid, 0)
                    break
                time.sleep(0.001)
    finally:
        stop.set()
        for th in threads:
            th.join()
    assert not crashed, f"hammer threads died: {crashed[:2]}"
    assert (hung, failed) == (0, 0), f"{hung} of {N_FORKS} forked children hung and {failed} failed"


def test_extensions_call_no_libgfortran_io():
    """The built extensions (library + glue, linked statically) import none of
    libgfortran's I/O-statement or STOP entry points: the source scan above
    cannot miss an I/O statement that the compiler sees.  (Before
    pendula_format, five of the six extensions imported seven of them.)"""
    nm = shutil.which("nm")
    if nm is None:
        pytest.skip("no nm on PATH to list the extensions' undefined symbols")
    folder = Path(pendula.__file__).parent
    found = [p for s in importlib.machinery.EXTENSION_SUFFIXES for p in folder.glob("_*" + s)]
    assert found, f"no extension modules in {folder}"
    io = re.compile(r"^_gfortran_(st_|transfer_|stop|error_stop)")
    bad = {}
    for path in found:
        out = subprocess.run(
            [nm, "-D", "--undefined-only", str(path)], capture_output=True, text=True, check=True
        ).stdout
        names = [line.split()[-1] for line in out.splitlines() if line.strip()]
        hits = [n for n in names if io.match(n)]
        if hits:
            bad[path.name] = hits
    assert bad == {}
