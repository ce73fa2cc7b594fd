"""Helpers shared by the Python test modules (imported as `helpers`; pytest
puts this folder on sys.path because tests/python has no __init__.py)."""

import importlib.util
import os
import pathlib
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import pendula

#: The source tree (tests that read sources or data skip without it).
ROOT = pathlib.Path(__file__).resolve().parents[2]


def load_file(path):
    """The Python file at ``path`` as a module named after it, loaded from the file
    (tools/, benchmarks/ and examples/ are not packages): no sys.path edit."""
    path = pathlib.Path(path)
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_generator(name):
    """tools/gen/<name>.py (a reference generator whose mpmath functions tests
    reuse) as a module."""
    return load_file(ROOT / "tools" / "gen" / f"{name}.py")


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


def text_scene_ensemble(n, seed=11):
    """n states near the text's damped scene (theta0 ~ U(-0.1, 0.1) rad, Omega0 ~
    U(1.9, 2.1) rad/s) and the times t = 0, 0.05, ..., 30 s."""
    rng = np.random.default_rng(seed)
    return rng.uniform(-0.1, 0.1, n), rng.uniform(1.9, 2.1, n), np.linspace(0.0, 30.0, 601)


def dop853_text_scene(t, theta0, omega0):
    """theta [rad] at t of theta'' = -0.1 theta' - 2 sin(theta) (the text's scene,
    w0 = sqrt(2) 1/s, gamma = 0.1 1/s) by SciPy's DOP853 at rtol 1e-12, atol 1e-13:
    an independent reference for the batch integrators."""
    from scipy.integrate import solve_ivp

    ref = solve_ivp(
        lambda _, y: [y[1], -0.1 * y[1] - 2.0 * np.sin(y[0])],
        (t[0], t[-1]),
        [theta0, omega0],
        method="DOP853",
        t_eval=t,
        rtol=1e-12,
        atol=1e-13,
    )
    return ref.y[0]


def forked_child_exit_code(call):
    """Run call() (a result with .theta) here, then fork: the child runs it again
    (SIGALRM ends it after 20 s if it hangs) and exits 0 when its theta equals the
    parent's bit for bit, 3 when it differs, 1 on an exception.  Returns that code."""
    r = call()
    pid = os.fork()
    if pid == 0:  # child
        code = 1
        try:
            signal.alarm(20)
            code = 0 if np.array_equal(call().theta, r.theta) else 3
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    return os.waitstatus_to_exitcode(status)


def interrupt_child(args, wait, timeout):
    """Start `python -c args...` (unbuffered), wait for its first line "started",
    sleep `wait` s and send SIGINT.  Returns (the monotonic time of the signal,
    the child's return code, its stdout, its stderr)."""
    p = subprocess.Popen(
        [sys.executable, "-c", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=dict(os.environ, PYTHONUNBUFFERED="1"),
    )
    try:
        assert p.stdout.readline().strip() == "started"
        time.sleep(wait)
        sent = time.monotonic()
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=timeout)
    finally:
        if p.poll() is None:
            p.kill()
    return sent, p.returncode, out, err


def finished_states_of_cancelled_batch(r, n, control):
    """Check a batch result (n states) cancelled mid-run through `control`: code
    ERR_CANCELLED naming the cancel, every state OK or cancelled, some but not all
    finished, the progress counter equal to the finished count, theta NaN for the
    others (a state without an answer is never a number).  Returns the mask of finished states."""
    from pendula._errors import ERR_CANCELLED, OK

    assert r.code == ERR_CANCELLED and "cancelled" in r.message
    done = r.codes == OK
    assert ((r.codes == OK) | (r.codes == ERR_CANCELLED)).all()
    assert 0 < done.sum() < n, "the flag should land mid-run"
    assert control[1] == done.sum()  # progress counts finished states
    assert np.isnan(r.theta[~done]).all()
    return done
