"""Long calls stop on Ctrl-C, report progress, and refuse absurd budgets up front.

A child process starts a long rk4 / cvode / solve(Scene) call (one state or
a batch of states on two threads); the parent
sends SIGINT after ~0.3 s.  The child must raise KeyboardInterrupt promptly
(latency measured with the shared monotonic clock; the bound asserted is a
generous 2 s for a loaded 2-core machine, the design target is 0.5 s), then
run the same kind of call again (shorter) in the same process and get the
answer of a fresh process bit for bit: no broken state.
"""

import json
import os
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest
from helpers import HAVE_CVODE, interrupt_child

import pendula
from pendula._errors import ERR_CANCELLED

_CHILD = textwrap.dedent("""
    import json, sys, time
    import numpy as np
    import pendula

    kind = sys.argv[1]

    def call(long):
        if kind == "rk4":
            t = [0.0, 1e6] if long else [0.0, 50.0]
            r = pendula.rk4(t, 0.0, 2.0, 1.4, 0.1, 1e-3)
        elif kind == "cvode":
            t = [0.0, 1e8] if long else [0.0, 50.0]
            r = pendula.cvode(t, 0.0, 2.0, 1.4, 0.0, rtol=1e-12, atol=1e-14)
        elif kind == "rk4_batch":   # 8 states on 2 OpenMP threads
            t = [0.0, 1e6] if long else [0.0, 50.0]
            r = pendula.rk4(t, np.linspace(0.0, 1.0, 8), 2.0, 1.4, 0.1, 1e-3, threads=2)
        elif kind == "cvode_batch":
            t = [0.0, 1e8] if long else [0.0, 50.0]
            r = pendula.cvode(t, np.linspace(0.0, 1.0, 4), 2.0, 1.4, 0.0, rtol=1e-12, atol=1e-14, threads=2)
        elif kind == "solve_batch":   # a pool of 2 threads over the scalar solve
            t = [0.0, 1e6] if long else [0.0, 100.0]
            # gamma = 1e-5: no decay to hand over to the linear form within 1e6 s
            r = pendula.solve(pendula.Scene(np.linspace(0.5, 1.0, 4), t=t, gamma=1e-5, tol=1e-10), threads=2)
        elif kind == "solve":
            t = [0.0, 1e6] if long else [0.0, 100.0]
            r = pendula.solve(pendula.Scene(1.0, t=t, gamma=1e-5, tol=1e-10))
        elif kind == "solve_top":   # a hang at the top: millions of RK4 substeps in one interval
            t = [0.0, 34722.6] if long else [0.0, 50.0]
            r = pendula.solve(pendula.Scene(np.pi, t=t, g=4.776, length=6.674, gamma=28.64, tol=1e-12,
                                            want="final"))
        elif kind == "run_model":
            t = [0.0, 1e5] if long else [0.0, 10.0]
            r = pendula.run_model(pendula.Scene(1.0, t=t, gamma=0.1), "rk4", 1e-4)
        else:   # tradeoff: 1e8 RK4 steps per repeat when long
            t = np.linspace(0.0, 1000.0 if long else 10.0, 11)
            table = pendula.tradeoff(pendula.Scene(1.0, t=t), models=["rk4"], rk4_steps=[1e-5 if long else 1e-3],
                                     repeat=1)
            return [row["sup_error"] for row in table.rows]
        return [float(np.ravel(r.theta)[-1]), float(np.ravel(r.omega)[-1])]

    if sys.argv[2] == "short":
        print(json.dumps({"again": call(False)}), flush=True)
        sys.exit(0)
    print("started", flush=True)
    try:
        call(True)
        print(json.dumps({"finished": True}), flush=True)
    except KeyboardInterrupt:
        caught = time.monotonic()
        print(json.dumps({"caught": caught, "again": call(False)}), flush=True)
""")

_ENV = dict(os.environ, PYTHONUNBUFFERED="1")


def _child(kind, mode):
    return subprocess.Popen(
        [sys.executable, "-c", _CHILD, kind, mode], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=_ENV
    )


@pytest.mark.parametrize(
    "kind", ["rk4", "cvode", "solve", "solve_top", "run_model", "tradeoff", "rk4_batch", "cvode_batch", "solve_batch"]
)
def test_sigint_stops_a_long_call_and_leaves_nothing_broken(kind):
    if kind.startswith("cvode") and not HAVE_CVODE:
        pytest.skip("this build has no CVODE")
    sent, code, out, err = interrupt_child([_CHILD, kind, "long"], wait=0.3, timeout=60)
    assert code == 0, err
    res = json.loads(out.strip().splitlines()[-1])
    assert "caught" in res, f"the long {kind} call was not interrupted: {res}"
    latency = res["caught"] - sent
    print(f"{kind}: SIGINT -> KeyboardInterrupt in {latency * 1e3:.2f} ms")
    assert 0 <= latency < 2.0
    # the same call again in the interrupted process == a fresh process, bit for bit
    fresh = _child(kind, "short")
    fout, ferr = fresh.communicate(timeout=120)
    assert fresh.returncode == 0, ferr
    assert res["again"] == json.loads(fout.strip().splitlines()[-1])["again"]


def _rk4_raw(t, h, control, max_steps=2e9):
    return pendula._fortran.rk4_f2py(np.asarray(t, float), 0.0, 2.0, 1.4, 0.1, h, max_steps, control)


def test_rk4_progress_counts_every_step_and_results_are_unchanged():
    t = np.linspace(0.0, 30.0, 601)
    plain = pendula.rk4(t, 0.0, 2.0, 1.4, 0.1, 0.01)
    control = np.zeros(2, np.int64)
    theta, omega, stats, code, _ = _rk4_raw(t, 0.01, control)
    assert code == 0
    assert control[0] == 0 and control[1] == stats[0] == 3000  # 5 substeps x 600 intervals
    assert np.array_equal(theta, plain.theta) and np.array_equal(omega, plain.omega)


def test_a_preset_cancel_flag_stops_rk4_at_the_first_poll():
    control = np.array([1, 0], np.int64)
    theta, omega, stats, code, msg = _rk4_raw([0.0, 100.0], 1e-3, control)
    assert code == ERR_CANCELLED and b"cancelled" in bytes(msg)
    assert stats[0] == control[1] == 4096  # one poll block, then stop
    assert not theta.any() and not omega.any()  # no half-done answer


def test_a_preset_cancel_flag_stops_cvode():
    if not HAVE_CVODE:
        pytest.skip("this build has no CVODE")
    control = np.array([1, 0], np.int64)
    out = pendula._fortran.cvode_f2py(np.array([0.0, 1e4]), 0.0, 2.0, 1.4, 0.0, 1e-10, 1e-12, 1, 1e7, 0, control)
    code, msg = out[-2], out[-1]
    assert code == ERR_CANCELLED and b"cancelled" in bytes(msg)
    assert control[1] == 256  # the first poll


def test_progress_callback_sees_a_monotone_count_up_to_the_steps():
    seen = []
    t = [0.0, 3000.0]
    r = pendula.rk4(t, 0.0, 2.0, 1.4, 0.1, 1e-3, progress=lambda done, total: seen.append((done, total)))
    assert r.stats["steps"] == 3_000_000
    assert seen and seen[-1] == (3_000_000, 3_000_002)
    assert all(a[0] <= b[0] for a, b in zip(seen, seen[1:]))
    assert np.array_equal(r.theta, pendula.rk4(t, 0.0, 2.0, 1.4, 0.1, 1e-3).theta)


def test_progress_callback_for_cvode_and_solve():
    if not HAVE_CVODE:
        pytest.skip("this build has no CVODE")
    seen = []
    r = pendula.cvode([0.0, 100.0], 0.0, 2.0, 1.4, 0.1, progress=lambda d, n: seen.append((d, n)))
    assert seen[-1] == (r.stats["rhs_evals"], None)
    seen.clear()
    s = pendula.solve(pendula.Scene(1.0, t=[0.0, 100.0], gamma=0.1, tol=1e-10), progress=lambda d, n: seen.append(d))
    assert s.model in ("rk4", "taylor") and seen[-1] == s.cost["steps"]


def test_progress_true_without_tqdm_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    with pytest.raises(ImportError, match="tqdm"):
        pendula.rk4([0.0, 1.0], 0.0, 2.0, 1.4, 0.1, 0.01, progress=True)


def test_bad_progress_and_max_steps_are_named():
    with pytest.raises(TypeError, match="progress"):
        pendula.rk4([0.0, 1.0], 0.0, 2.0, 1.4, 0.1, 0.01, progress="yes")
    with pytest.raises(ValueError, match="max_steps"):
        pendula.rk4([0.0, 1.0], 0.0, 2.0, 1.4, 0.1, 0.01, max_steps=0)
    with pytest.raises(TypeError, match="max_steps"):
        pendula.solve(pendula.Scene(1.0, t=[0.0, 1.0]), max_steps=1.5)


def test_budgets_refuse_up_front():
    start = time.perf_counter()
    with pytest.raises(ValueError, match="max_steps = 2"):
        pendula.rk4([0.0, 1e9], 0.0, 2.0, 1.4, 0.1, 0.05)  # 2e10 steps
    with pytest.raises(ValueError, match="max_steps = 1000"):
        pendula.rk4([0.0, 100.0], 0.0, 2.0, 1.4, 0.1, 0.05, max_steps=1000)
    assert pendula.rk4([0.0, 100.0], 0.0, 2.0, 1.4, 0.1, 0.05, max_steps=2000).stats["steps"] == 2000
    if HAVE_CVODE:
        # gamma = 1e-9: the swing never decays within the window, CVODE would need ~2e9 steps
        with pytest.raises(pendula.PendulaSolverError, match="shorten the window or raise max_steps"):
            pendula.solve(pendula.Scene(1.0, t=[0.0, 1e9], gamma=1e-9, tol=1e-10))
        # gamma = 0.1: the motion decays, the linear closed form takes over: answered at once
        r = pendula.solve(pendula.Scene(1.0, t=[0.0, 1e9], gamma=0.1, tol=1e-10, want="final"))
        assert r.tol_met and abs(r.theta) < 1e-10
    with pytest.raises(pendula.PendulaSolverError, match="raise max_steps"):
        pendula.solve(pendula.Scene(1.0, t=[0.0, 100.0], gamma=0.1, tol=1e-10), model="rk4", max_steps=1000)
    with pytest.raises(ValueError, match="raise max_steps"):
        pendula.run_model(pendula.Scene(1.0, t=[0.0, 100.0], gamma=0.1), "rk4", 0.01, max_steps=1000)
    assert time.perf_counter() - start < 5  # refused, not attempted


def test_an_exception_in_the_progress_callback_stops_the_run():
    # 1e9 steps (~30 s) if the worker ran on; the callback's error must stop it.
    def boom(done, total):
        if done > 0:
            raise ZeroDivisionError("stop here")

    start = time.perf_counter()
    with pytest.raises(ZeroDivisionError, match="stop here"):
        pendula.rk4([0.0, 1e6], 0.0, 2.0, 1.4, 0.1, 1e-3, progress=boom)
    assert time.perf_counter() - start < 5
    assert pendula.rk4([0.0, 1.0], 0.0, 2.0, 1.4, 0.1, 0.01).stats["steps"] == 100
