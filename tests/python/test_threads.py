"""Thread safety.

1. Every public entry point (the table of test_bad_input.py, so a new function
   is covered as soon as it has its bad-input entry) called concurrently from a
   thread pool, in shuffled order and with different inputs per call, returns
   results bit-for-bit identical to the serial calls.  The Fortran core has no
   SAVE or module state that changes; this test would catch it if it had.
2. The f2py layer releases the GIL (``!f2py threadsafe``) for the long-running
   entry points of ``LONG``: while one thread is inside a long Fortran call, a
   pure-Python counter thread keeps running.  If the GIL were held, the counter
   would stand still for the whole call (it could only run in the few
   switch intervals around it).  A control call that holds the GIL shows the
   measurement can fail.
"""

from __future__ import annotations

import concurrent.futures as cf
import random
import sys
import threading
import time

import numpy as np
import pytest
from api_table import ALL_CASES, API, NONNEG, POS, REAL, _call, _materialise, _walk_numbers
from helpers import HAVE_CVODE, ROOT, fortran_statements

import pendula

N_ARRAY = 2_000


def _varied_kwargs(fname, seed):
    """The entry's valid call, array arguments widened to N_ARRAY varied values
    (scaled towards zero by at most 5 %, which keeps every domain)."""
    entry = API[fname]
    kw = {}
    rng = np.random.default_rng(seed)
    for k, v in entry.valid.items():
        spec = entry.args.get(k)
        if spec is not None and spec.array and spec.kind in (REAL, POS, NONNEG) and np.ndim(v) == 0:
            kw[k] = float(v) * (1 - 0.05 * rng.random(N_ARRAY))
        else:
            kw[k] = _materialise(v)
    return kw


def _deterministic(result):
    """The result without wall-clock measurements (keys/attributes naming a time
    of the run: 'wall_time', 'python_wall_time'), which legitimately differ."""
    if isinstance(result, dict):
        return {k: _deterministic(v) for k, v in result.items() if "wall" not in str(k)}
    if isinstance(result, (list, tuple)):
        return type(result)(_deterministic(v) for v in result)
    if hasattr(result, "__dict__") and not isinstance(result, (np.ndarray, type)):
        return {k: _deterministic(v) for k, v in vars(result).items() if not k.startswith("_") and "wall" not in k}
    return result


def _flatten(result):
    return np.array(list(_walk_numbers(_deterministic(result))), dtype=complex)


def _entries():
    out = []
    for name, entry in sorted(API.items()):
        if entry.needs_cvode and not HAVE_CVODE:
            continue
        out.append(name)
    return out


def test_concurrent_calls_equal_serial_calls():
    names = _entries()
    jobs = [(name, seed) for name in names for seed in range(3)]
    serial = {}
    for name, seed in jobs:
        serial[name, seed] = _flatten(_call(name, _varied_kwargs(name, seed)))

    def run(job):
        name, seed = job
        return job, _flatten(_call(name, _varied_kwargs(name, seed)))

    work = jobs * 4
    random.Random(1234).shuffle(work)
    with cf.ThreadPoolExecutor(max_workers=4) as pool:
        for job, got in pool.map(run, work):
            want = serial[job]
            assert got.shape == want.shape, f"{job}: result size differs between threaded and serial call"
            assert np.array_equal(got, want, equal_nan=True), (
                f"{job}: threaded result differs from the serial one (shared state in the call?)"
            )


def _outcome(case):
    kwargs = {k: _materialise(v) for k, v in API[case.func].valid.items()}
    kwargs.update(case.others)
    kwargs[case.arg] = case.value
    try:
        return ("ok", _flatten(_call(case.func, kwargs)).tobytes())
    except Exception as exc:  # noqa: BLE001 - the outcome is what is compared
        return (type(exc).__name__, str(exc))


def test_concurrent_failures_equal_serial_failures():
    # Error paths too: a message or status kept anywhere but in the call's own
    # variables (e.g. a SUNDIALS error handler writing to shared storage) would
    # mix up messages between threads.
    cases = [c for c in ALL_CASES if not (API[c.func].needs_cvode and not HAVE_CVODE)]
    cases = cases[::5] + [c for c in cases if c.func == "cvode"]
    serial = [_outcome(c) for c in cases]
    work = list(range(len(cases))) * 3
    random.Random(99).shuffle(work)
    with cf.ThreadPoolExecutor(max_workers=4) as pool:
        for i, got in zip(work, pool.map(lambda i: _outcome(cases[i]), work)):
            assert got == serial[i], f"{cases[i].id}: threaded outcome {got!r} != serial {serial[i]!r}"


# ---- GIL release ------------------------------------------------------------------------------------
# name -> (callable with no arguments making one long call (~0.1-0.5 s)).
def _long_small_angle_period():
    w0 = np.linspace(0.5, 2.0, 1_500_000)
    return lambda: pendula.small_angle_period(w0)


def _long(fn, **kw):
    return lambda: lambda: fn(**kw)


_T = np.linspace(0.0, 200.0, 2_000_000)  # ~60 ms a call: long enough to see the counter run
_U = np.linspace(-50.0, 50.0, 400_000)
LONG = {
    "small_angle_period": _long_small_angle_period,
    "period_series": _long(pendula.period_series, m=np.linspace(0.0, 1.0, 1_500_000), w0=1.4),
    "undamped": _long(pendula.undamped, t=_T, theta0=2.0, omega0=0.3, w0=1.4),
    "linear_damped": _long(pendula.linear_damped, t=_T, theta0=0.1, omega0=0.5, w0=1.4, gamma=0.3),
    "ellipj": _long(pendula.ellipj, u=_U, m=np.full(_U.size, 0.7)),
    "ellipf": _long(pendula.ellipf, phi=_U, m=0.7),
    "rk4": _long(pendula.rk4, t=np.array([0.0, 15000.0]), theta0=0.0, omega0=2.0, w0=1.4, gamma=0.1, h=0.005),
    "run_model": lambda: (
        lambda: pendula.run_model(
            pendula.Scene(theta0=1.0, t=np.linspace(0, 400.0, 100), gamma=0.1, tol=1e-9), "rk4", 2e-4
        )
    ),
}
if HAVE_CVODE:
    LONG["cvode"] = _long(
        pendula.cvode, t=np.array([0.0, 20000.0]), theta0=0.0, omega0=2.0, w0=1.4, gamma=0.01, rtol=1e-11, atol=1e-13
    )


def _counter_share(call):
    """Duration of call() and how much of its free-running rate a pure-Python
    counter thread kept meanwhile (0 when the call holds the GIL throughout)."""
    old = sys.getswitchinterval()
    sys.setswitchinterval(0.001)
    try:
        stop = threading.Event()
        count = [0]

        def counter():
            while not stop.is_set():
                count[0] += 1

        th = threading.Thread(target=counter)
        th.start()
        time.sleep(0.02)
        # The counter's free rate, measured the same way while this thread sleeps.
        s0 = time.perf_counter()
        f0 = count[0]
        time.sleep(0.1)
        free_rate = (count[0] - f0) / (time.perf_counter() - s0)
        t0 = time.perf_counter()
        c0 = count[0]
        call()
        c1 = count[0]
        dt = time.perf_counter() - t0
        stop.set()
        th.join()
    finally:
        sys.setswitchinterval(old)
    return dt, (c1 - c0) / (free_rate * dt)


# A call that released the GIL leaves the counter a core of its own on an idle
# machine (share ~1) and half of one when the machine's other core is busy; a
# call that holds the GIL leaves it ~0 (the control below measures it).  Load
# from outside the run comes and goes, so the best of a few tries is judged.
MIN_SHARE = 0.15
TRIES = 3


def _shares(call):
    """Duration of the last try and the counter's share in each try, stopping
    at the first above MIN_SHARE."""
    shares = []
    for _ in range(TRIES):
        dt, share = _counter_share(call)
        shares.append(share)
        if share > MIN_SHARE:
            break
    return dt, shares


def test_gil_holding_call_stops_the_counter():
    # The measurement can fail: a C call made with the GIL held (ctypes.PyDLL
    # keeps it) leaves the counter a few per cent at most, in every try.
    ctypes = pytest.importorskip("ctypes")
    try:
        usleep = ctypes.PyDLL(None).usleep
    except (OSError, AttributeError):
        pytest.skip("no usleep in this C library")
    _, shares = _shares(lambda: usleep(100_000))
    assert len(shares) == TRIES and max(shares) < MIN_SHARE, (
        f"a GIL-holding 100 ms call left the counter {', '.join(f'{s:.1%}' for s in shares)} of its free rate"
    )


@pytest.mark.parametrize("name", sorted(LONG))
def test_long_call_releases_the_gil(name):
    call = LONG[name]()
    call()  # warm up (page faults, first-call costs)
    dt, shares = _shares(call)
    if dt < 0.02:
        pytest.skip(f"{name}: the long call took only {dt * 1e3:.1f} ms; enlarge it in LONG")
    text = ", ".join(f"{s:.1%}" for s in shares)
    print(f"\n{name}: call {dt * 1e3:.0f} ms, counter ran {text} of its free rate")
    assert max(shares) > MIN_SHARE, (
        f"{name}: a pure-Python thread was blocked during the Fortran call in {len(shares)} tries "
        f"(ran {text} of its free rate): the f2py routine holds the GIL; add `!f2py threadsafe`"
    )


# ---- static audit: no saved state in the Fortran sources ------------------------------------------
import re  # noqa: E402


def saved_state(path):
    """Findings: SAVE attributes/statements, DATA statements, module variables,
    initialised local variables (implicit SAVE)."""
    findings = []
    scope = []  # stack: 'module-spec', 'proc', 'type', 'interface'
    for no, st in fortran_statements(path.read_text()):
        low = st.lower()
        head = re.sub(r"^(?:(?:pure|elemental|impure|recursive|module|non_recursive)\s+)+", "", low)
        if re.match(r"end\s*(module|submodule)\b", low) or low == "end":
            scope.clear() if low != "end" else (scope.pop() if scope else None)
            continue
        if re.match(r"end\s*(subroutine|function|program|procedure)\b", low):
            if scope:
                scope.pop()
            continue
        if re.match(r"end\s*type\b", low) or re.match(r"end\s*interface\b", low):
            if scope:
                scope.pop()
            continue
        if re.match(r"(sub)?module\s+(?!procedure)\w+", low) and not low.startswith("module procedure"):
            scope = ["module-spec"]
            continue
        if re.match(r"contains\b", low):
            continue
        if re.match(r"((abstract\s+)?interface)\b", low):
            scope.append("interface")
            continue
        if re.match(r"type\s*(,[^:]*)?::\s*\w+|type\s+\w+\s*$", low):
            scope.append("type")
            continue
        if re.match(r"(program|subroutine|(?:[\w()=*, ]+\s+)?function)\s+\w+", head) and not re.match(
            r"(real|integer|logical|character|type|class|complex)\b[^:]*::", head
        ):
            scope.append("proc")
            continue
        where = scope[-1] if scope else "proc"
        if where in ("type", "interface"):
            continue
        if re.match(r"save\b", low) or re.search(r",\s*save\b", low.split("::")[0] if "::" in low else ""):
            findings.append((no, "SAVE", st))
            continue
        if re.match(r"data\s", low):
            findings.append((no, "DATA statement (implicit SAVE)", st))
            continue
        if "::" not in st or re.match(r"(use|public|private|import|procedure|generic|namelist)\b", low):
            continue
        attrs, ents = low.split("::", 1)
        if not re.match(r"\s*(real|integer|logical|character|type|class|complex|double)\b", attrs):
            continue
        if "parameter" in attrs:
            continue
        if where == "module-spec":
            findings.append((no, "module variable", st))
        elif "=" in ents:
            findings.append((no, "initialised local variable (implicit SAVE)", st))
    return findings


def _fortran_sources():
    # .F90 and .inc: pendula_cvode.F90 and the stand-in it includes
    src = [p for p in (ROOT / "src").rglob("*") if p.suffix in (".f90", ".F90", ".inc")]
    return sorted(src + list((ROOT / "python" / "f2py").glob("*.f90")))


@pytest.mark.skipif(not (ROOT / "src").is_dir(), reason="needs the source tree")
def test_fortran_sources_have_no_saved_state():
    bad = []
    for path in _fortran_sources():
        for no, what, st in saved_state(path):
            bad.append(f"{path.relative_to(ROOT)}:{no}: {what}: {st}")
    assert not bad, "state that survives a call (not thread-safe):\n" + "\n".join(bad)


def test_audit_detects_saved_state(tmp_path):
    # The audit itself must be able to fail.
    f = tmp_path / "m.f90"
    f.write_text(
        "module m\n  implicit none\n  real :: counter\n  integer, parameter :: k = 1\n"
        "  type :: t\n    integer :: code = 0\n  end type t\ncontains\n"
        "  subroutine s(x)\n    real, intent(inout) :: x\n    integer :: calls = 0\n"
        "    real, save :: last\n    character(len=*), parameter :: nm = 'x'\n"
        "    calls = calls + 1\n    x = x + 1\n  end subroutine s\nend module m\n"
    )
    kinds = [w for _, w, _ in saved_state(f)]
    assert kinds == ["module variable", "initialised local variable (implicit SAVE)", "SAVE"], kinds


# f2py routines that return at once (no loop, no integrator) may keep the GIL.
F2PY_GIL_EXEMPT = {"cvode_available_f2py": "returns a build constant"}


@pytest.mark.skipif(not (ROOT / "python" / "f2py").is_dir(), reason="needs the source tree")
def test_every_f2py_routine_releases_the_gil():
    missing = []
    n = 0
    for path in sorted((ROOT / "python" / "f2py").glob("*.f90")):
        name, threadsafe = None, False
        for line in path.read_text().splitlines():
            m = re.match(r"\s*subroutine\s+(\w+)", line, re.I)
            if m:
                name, threadsafe = m.group(1).lower(), False
                n += 1
            elif re.match(r"\s*!f2py\s+threadsafe\b", line, re.I):
                threadsafe = True
            elif re.match(r"\s*end\s*subroutine\b", line, re.I) and name:
                if not threadsafe and name not in F2PY_GIL_EXEMPT:
                    missing.append(f"{path.relative_to(ROOT)}: {name}")
                name = None
    assert n > 10, "found too few f2py routines"
    assert not missing, "f2py routines without `!f2py threadsafe` (they hold the GIL):\n" + "\n".join(missing)
