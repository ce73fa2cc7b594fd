"""Out of memory is an error, never a crash: outputs are predicted and refused up
front with their size (MemoryError), allocations the Fortran core cannot make
come back as PENDULA_ERR_MEMORY, a scene batch shares one time grid, and event
storage grows with the events found.

The out-of-memory cases run in a child Python whose address space is capped
(resource.setrlimit(RLIMIT_AS), as `ulimit -v` does) a little above what it
already uses, so that they fail fast and cannot disturb this process or the
machine; the child must exit normally (no signal) after a MemoryError naming
the size.
"""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

import pendula
from pendula import _codes, _errors, _scene_call
from pendula import scene as scene_mod

resource = pytest.importorskip("resource")  # POSIX only

# What the child runs before the case: pendula imported (and its OpenMP pool
# started) first, then the cap: VmSize now + HEADROOM.
_PRELUDE = """
import re, resource, time
import numpy as np, pendula
pendula.rk4([0.0, 1.0], np.zeros(2), 0.0, 1.0, 0.0, h=0.1, threads=2)   # threads' stacks counted
def cap(headroom):
    vm = int(re.search(r"VmSize:\\s+(\\d+) kB", open("/proc/self/status").read()).group(1)) * 1024
    resource.setrlimit(resource.RLIMIT_AS, (vm + headroom, vm + headroom))
"""


def _child(body, timeout=60):
    code = _PRELUDE + textwrap.dedent(body)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout)
    assert r.returncode >= 0, f"killed by signal {-r.returncode}: {r.stderr[-2000:]}"
    return r


def _expect_memory_error(body, *words):
    r = _child(body)
    assert r.returncode == 0, r.stderr[-3000:]
    out = r.stdout
    assert "MemoryError:" in out, out + r.stderr[-2000:]
    for w in words:
        assert w in out, out
    return out


def _linux():
    try:
        open("/proc/self/status").close()
        return True
    except OSError:
        return False


linux = pytest.mark.skipif(not _linux(), reason="reads /proc/self/status")


# ---------------------------------------------------------------- the code and its exception


def test_memory_code_maps_to_memory_error():
    assert _codes.ERR_MEMORY not in (
        _codes.OK,
        _codes.ERR_NONFINITE,
        _codes.ERR_DOMAIN,
        _codes.ERR_SIZE,
        _codes.ERR_ORDER,
        _codes.ERR_UNSTABLE,
        _codes.ERR_SOLVER,
        _codes.ERR_UNAVAILABLE,
        _codes.ERR_MAXSTEPS,
        _codes.ERR_CANCELLED,
    )
    with pytest.raises(MemoryError, match="out of memory: the outputs need 1.5 GiB") as info:
        _errors.raise_for_status(_codes.ERR_MEMORY, b"out of memory: the outputs need 1.5 GiB  ")
    assert info.value.pendula_code == _codes.ERR_MEMORY


# ---------------------------------------------------------------- refused up front, in a capped child


@linux
def test_scene_whose_times_the_core_cannot_copy_is_a_memory_error():
    # t fits once (made before the cap) and in Python's checked copy, not a third
    # time in Fortran's scene_init: the core's check_alloc, not a segfault
    _expect_memory_error(
        """
        t = np.arange(40_000_000, dtype=float) * 1e-6
        cap(400 * 2**20)
        try:
            pendula.Scene(0.1, t=t)
            print("no error")
        except MemoryError as exc:
            print("MemoryError:", exc)
        """,
        "the output times t need",
        "305 MiB",
        "40000000 values of 8 bytes",
    )


@linux
def test_scene_batch_shares_its_time_grid_and_refuses_its_solve_up_front():
    # the reproducer of the crash: 4000 scenes x 1e5 times; built in a few MB now
    # (one t for all); its solve (4000 x 1e5 x 4 series, twice) refused before any scene runs
    _expect_memory_error(
        """
        cap(1500 * 2**20)
        b = pendula.Scene(np.zeros(4000), t=np.linspace(0, 1, 100000))
        assert all(s.t is b.t for s in b.scenes.flat)
        start = time.perf_counter()
        try:
            pendula.solve(b)
            print("no error")
        except MemoryError as exc:
            print("MemoryError:", exc, "after", time.perf_counter() - start, "s")
        """,
        "the results of 4000 scenes x 100000 output times",
        "GiB",
    )


@linux
@pytest.mark.parametrize(
    "call",
    [
        "pendula.sweep(t, np.zeros(4000), want='trajectory', h=0.01)",
        "pendula.sweep(t, np.zeros(4000), want='trajectory', method='cvode')",
        "pendula.rk4(t, np.zeros(4000), 0.0, 1.0, 0.0, h=0.01)",
        "pendula.cvode(t, np.zeros(4000), 0.0, 1.0, 0.0)",
    ],
)
def test_batch_outputs_refused_up_front_with_their_size(call):
    if "cvode" in call and not pendula.build_info()["cvode"]:
        pytest.skip("no CVODE in this build")
    out = _expect_memory_error(
        f"""
        t = np.linspace(0, 1, 100000)
        cap(1000 * 2**20)
        start = time.perf_counter()
        try:
            {call}
            print("no error")
        except MemoryError as exc:
            print("MemoryError:", exc, "after", time.perf_counter() - start, "s")
        """,
        "the outputs theta and omega of 4000 states x 100000 times need 5.96 GiB",
    )
    # up front: no chunk of work was done (the old sweep computed for 8 s first)
    assert float(out.split("after")[-1].split()[0]) < 2.0, out


@linux
@pytest.mark.parametrize(
    "call, words",
    [
        ("pendula.rk4(t, 0.1, 0.0, 1.0, 0.0, h=0.01)", "the outputs theta and omega of 20000000 times (the size of t)"),
        (
            "pendula.rk4(t, 0.1, 0.0, 1.0, 0.0, h=0.01, drive=pendula.Drive('torque', 0.1, 1.0))",
            "the outputs theta and omega of 20000000 times (the size of t) need 305 MiB (320000000 bytes)",
        ),
        ("pendula.cvode(t, 0.1, 0.0, 1.0, 0.0)", "the outputs theta and omega of 20000000 times (the size of t)"),
    ],
)
def test_one_state_outputs_refused_with_their_size(call, words):
    # one state over a long grid: theta and omega (f2py allocates them before
    # the call) do not fit; the error names t's size and the bytes, as a batch's does
    if "cvode" in call and not pendula.build_info()["cvode"]:
        pytest.skip("no CVODE in this build")
    _expect_memory_error(
        f"""
        t = np.linspace(0, 1, 20_000_000)
        cap(200 * 2**20)  # room for a copy of t, not for theta and omega too
        try:
            {call}
            print("no error")
        except MemoryError as exc:
            print("MemoryError:", exc)
        """,
        words,
        "bytes",
    )


# ---------------------------------------------------------------- sweep chunks and outputs


def test_trajectory_sweep_fills_its_outputs_in_place_and_chunks_long_grids(monkeypatch):
    from pendula import _memory

    t = np.linspace(0.0, 2.0, 201)
    th = np.linspace(-1, 1, 7)
    direct = pendula.rk4(t, th, 0.0, 1.3, 0.1, h=0.01)
    monkeypatch.setattr(_memory, "CHUNK_BYTES", 2 * 8 * 201 * 3)  # 3 states of trajectory per chunk
    r = pendula.sweep(t, th, 0.0, 1.3, 0.1, want="trajectory", h=0.01)
    assert r.n_chunks == 3
    assert np.array_equal(r.theta, direct.theta) and np.array_equal(r.omega, direct.omega)
    f = pendula.sweep(t, th, 0.0, 1.3, 0.1, h=0.01)
    assert f.n_chunks == 3 and np.array_equal(f.theta, direct.theta[:, -1])


# ---------------------------------------------------------------- events: storage grows with them


def test_event_slots_grow_with_the_events_found(monkeypatch):
    # a window with more events than the first slots: solved once more with exact room,
    # the same events as a solve that had room at once
    s = pendula.Scene(theta0=0.4, t=[40 * 2 * np.pi / np.sqrt(2)], gamma=0.02, tol=1e-7, want="events")
    full = pendula.solve(s)
    n = len(full.events.t)
    assert n > 100
    calls = []
    real = scene_mod._scene.scene_solve_f2py

    def counted(*args):
        calls.append(args[11])  # m, the event slots
        return real(*args)

    monkeypatch.setattr(_scene_call, "_FIRST_EVENT_SLOTS", 16)  # the slots live with the call
    monkeypatch.setattr(scene_mod._scene, "scene_solve_f2py", counted)
    grown = pendula.solve(s)
    assert calls == [16, n]
    assert np.array_equal(grown.events.t, full.events.t) and np.array_equal(grown.events.kind, full.events.kind)


@linux
def test_events_over_a_long_window_need_memory_for_the_events_not_the_bound():
    # a decaying swing over 1e9 s: the bound is ~1e9 events (28 GB of slots, allocated up
    # front before); the motion has a few thousand before it decays to nothing
    r = _child("""
        s = pendula.Scene(theta0=0.1, t=[1e9], gamma=1.0, tol=1e-3, want="events")   # the linear closed form
        print("bound", int(pendula.scene._scene.scene_event_bound_f2py(s.w0, 1e9, 0.1, 0.0)))
        cap(300 * 2**20)
        res = pendula.solve(s)
        print("events", len(res.events.t))
        """)
    assert r.returncode == 0, r.stderr[-3000:]
    words = dict(line.split() for line in r.stdout.splitlines())
    assert int(words["bound"]) > 10**8 and 0 < int(words["events"]) < 10**5
