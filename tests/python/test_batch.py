"""pendula._batch.rk4_batch: many states per call (private entry point).

Every state must be bit-identical to pendula.rk4 for the same arguments
(0 ulps), whatever the batch shape, the thread count, or the other states in
the batch; a failing state reports its own code (the one pendula.rk4 raises
for) and leaves the others intact; a cancel request from another thread
stops the call with the finished states kept.  Accuracy itself is pendula.rk4's
(tested against mpmath in test_integrators.py); here one ensemble is also
checked against SciPy's DOP853 at rtol 1e-12.
"""

import math
import os
import threading
import time

import numpy as np
import pytest
from helpers import dop853_text_scene, finished_states_of_cancelled_batch, forked_child_exit_code, text_scene_ensemble

import pendula
from pendula._errors import ERR_DOMAIN, ERR_NONFINITE, ERR_SOLVER, ERR_UNSTABLE, OK
from pendula._many import kernels as _batch

T = np.linspace(0.0, 30.0, 121)
W0 = math.sqrt(2.0)


def mixed_states(n=53, seed=7):
    """Small and large amplitudes, rotations both ways, |theta| > 2**20 (libm
    steps), an Omega that fails the table path's bound, gamma = 0, overdamped,
    and per-state steps that do or do not divide the output spacing."""
    rng = np.random.default_rng(seed)
    th0 = rng.uniform(-3.1, 3.1, n)
    om0 = rng.uniform(-4.0, 4.0, n)
    w0 = rng.uniform(0.5, 3.0, n)
    gam = rng.uniform(0.0, 0.4, n)
    h = np.full(n, 0.05)
    gam[:5] = 0.0
    gam[5:8] = 8 * w0[5:8]
    th0[8] = 3.0e6
    om0[9] = 40.0
    om0[10] = -9.0
    h[20:27] = [0.01, 0.02, 0.03, 0.07, 0.125, 0.3, 0.0333]
    return th0, om0, w0, gam, h


def scalar(th0, om0, w0, gam, h):
    out = [pendula.rk4(T, a, b, c, d, e) for a, b, c, d, e in zip(th0, om0, w0, gam, h)]
    return np.array([r.theta for r in out]), np.array([r.omega for r in out]), np.array([r.stats["steps"] for r in out])


@pytest.mark.parametrize("threads", [1, 2, 0])
def test_bit_identical_to_rk4(threads):
    args = mixed_states()
    th, om, steps = scalar(*args)
    r = _batch.rk4_batch(T, *args, threads=threads)
    assert r.code == OK and r.message == "" and r.first_failed == -1
    assert (r.codes == OK).all()
    # 0 ulps: same operations in the same order as the scalar kernel
    assert np.array_equal(r.theta, th) and np.array_equal(r.omega, om)
    assert np.array_equal(r.steps, steps)


def test_order_of_states_does_not_matter():
    args = mixed_states()
    perm = np.random.default_rng(3).permutation(len(args[0]))
    r = _batch.rk4_batch(T, *args)
    rp = _batch.rk4_batch(T, *(a[perm] for a in args), threads=2)
    assert np.array_equal(rp.theta, r.theta[perm]) and np.array_equal(rp.omega, r.omega[perm])


@pytest.mark.parametrize("shape", [(), (1,), (7,), (3, 5), (2, 0), (0,)])
def test_shapes(shape):
    th0 = np.linspace(-1, 1, int(np.prod(shape))).reshape(shape)
    r = _batch.rk4_batch(T, th0, 0.3, W0, 0.1, 0.05)
    assert r.theta.shape == shape + (T.size,) and r.omega.shape == shape + (T.size,)
    assert r.codes.shape == shape and r.steps.shape == shape
    assert r.theta.flags.c_contiguous
    for idx in np.ndindex(shape):
        s = pendula.rk4(T, float(th0[idx]), 0.3, W0, 0.1, 0.05)
        assert np.array_equal(r.theta[idx], s.theta)


def test_broadcast():
    th0 = np.array([0.1, 0.5, 1.0])[:, None]  # (3, 1)
    gam = np.array([0.0, 0.1, 0.5, 2.0])  # (4,)
    r = _batch.rk4_batch(T, th0, 0.0, W0, gam, 0.05)
    assert r.theta.shape == (3, 4, T.size)
    for i in range(3):
        for j in range(4):
            assert np.array_equal(r.theta[i, j], pendula.rk4(T, th0[i, 0], 0.0, W0, gam[j], 0.05).theta)
    with pytest.raises(ValueError, match="broadcast"):
        _batch.rk4_batch(T, np.zeros(3), np.zeros(4), W0, 0.1, 0.05)


def test_per_state_failures():
    n = 12
    th0 = np.linspace(0.1, 1.2, n)
    w0 = np.full(n, W0)
    gam = np.full(n, 0.1)
    om0 = np.zeros(n)
    w0[2] = 100.0  # unstable for h = 0.05
    w0[5] = -1.0  # domain
    th0[7] = np.nan  # non-finite
    om0[9] = 1.7e308  # overflows during the run (solver failure)
    w0[9] = 1e-3
    gam[9] = 0.0
    before = [a.copy() for a in (th0, om0, w0, gam)]
    for threads in (1, 2):
        r = _batch.rk4_batch(T, th0, om0, w0, gam, 0.05, threads=threads)
        assert r.codes[[2, 5, 7, 9]].tolist() == [ERR_UNSTABLE, ERR_DOMAIN, ERR_NONFINITE, ERR_SOLVER]
        assert r.code == ERR_UNSTABLE and r.first_failed == 2
        assert r.message.startswith("state 3 of 12 (4 failed") and "largest stable h" in r.message
        assert not r.ok[[2, 5, 7, 9]].any() and r.ok.sum() == n - 4
        assert np.isnan(r.theta[[2, 5, 7, 9]]).all() and np.isnan(r.omega[[2, 5, 7, 9]]).all()  # never data
        for i in np.flatnonzero(r.ok):
            s = pendula.rk4(T, th0[i], om0[i], w0[i], gam[i], 0.05)
            assert np.array_equal(r.theta[i], s.theta) and np.array_equal(r.omega[i], s.omega)
    # the scalar calls fail with the same kinds
    with pytest.raises(ValueError, match="unstable"):
        pendula.rk4(T, th0[2], 0.0, w0[2], 0.1, 0.05)
    with pytest.raises(pendula.PendulaSolverError, match="non-finite"):
        pendula.rk4(T, th0[9], om0[9], w0[9], 0.0, 0.05)
    for a, b in zip(before, (th0, om0, w0, gam)):  # inputs untouched
        assert np.array_equal(a, b, equal_nan=True)


def test_overflow_mid_run_with_shared_parameters():
    """States that overflow during the run in batches sharing w0, gamma and h (the
    kernel's block-wide constants, several blocks): NaN rows and ERR_SOLVER for them,
    and every other state bit for bit pendula.rk4."""
    n = 300
    th0, om0 = np.linspace(-3.0, 3.0, n), np.linspace(-2.0, 2.0, n)
    dead = [5, 150, 299]
    om0[dead] = [1e308, -1.5e308, 1e308]
    t = np.linspace(0.0, 10.0, 41)
    for threads in (1, 2):
        r = _batch.rk4_batch(t, th0, om0, 1.3, 0.0, 0.05, threads=threads)
        assert (r.codes[dead] == ERR_SOLVER).all() and r.first_failed == 5
        assert np.isnan(r.theta[dead]).all() and np.isnan(r.omega[dead]).all()
        for i in np.flatnonzero(r.ok):
            s = pendula.rk4(t, th0[i], om0[i], 1.3, 0.0, 0.05)
            assert np.array_equal(r.theta[i], s.theta) and np.array_equal(r.omega[i], s.omega)
        assert r.ok.sum() == n - len(dead)


def test_call_level_errors():
    with pytest.raises(ValueError, match="t"):
        _batch.rk4_batch(np.array([0.0, 1.0, 1.0]), [0.1, 0.2], 0.0, W0, 0.1, 0.05)
    with pytest.raises(ValueError, match="1-D"):
        _batch.rk4_batch(np.zeros((2, 2)), [0.1], 0.0, W0, 0.1, 0.05)
    with pytest.raises(ValueError, match="threads"):
        _batch.rk4_batch(T, [0.1], 0.0, W0, 0.1, 0.05, threads=-1)
    with pytest.raises(TypeError, match="threads"):
        _batch.rk4_batch(T, [0.1], 0.0, W0, 0.1, 0.05, threads=1.5)
    with pytest.raises(TypeError, match="theta0"):
        _batch.rk4_batch(T, "x", 0.0, W0, 0.1, 0.05)
    with pytest.raises(TypeError, match="control"):
        _batch.rk4_batch(T, [0.1], 0.0, W0, 0.1, 0.05, control=np.zeros(2))


def test_cancel_from_another_thread_keeps_finished_states():
    # about 1 s of work on one thread; the flag is raised as soon as the
    # progress counter shows finished states (a fixed delay is flaky on a
    # loaded machine)
    n = 4000
    t = np.linspace(0.0, 30.0, 601)
    th0 = np.linspace(-1.0, 1.0, n)
    control = np.zeros(2, dtype=np.int64)

    def cancel_after_first_states():
        deadline = time.perf_counter() + 30.0
        while control[1] == 0 and time.perf_counter() < deadline:
            time.sleep(0.001)
        control[0] = 1

    timer = threading.Thread(target=cancel_after_first_states)
    timer.start()
    t0 = time.perf_counter()
    r = _batch.rk4_batch(t, th0, 2.0, W0, 0.1, 0.002, threads=1, control=control)
    elapsed = time.perf_counter() - t0
    timer.join()
    done = finished_states_of_cancelled_batch(r, n, control)
    for i in np.flatnonzero(done)[:: max(1, done.sum() // 5)]:
        assert np.array_equal(r.theta[i], pendula.rk4(t, th0[i], 2.0, W0, 0.1, 0.002).theta)
    assert elapsed < 5.0


def test_progress_counter_counts_every_state():
    control = np.zeros(2, dtype=np.int64)
    r = _batch.rk4_batch(T, np.linspace(0, 1, 37), 0.0, W0, 0.1, 0.05, threads=2, control=control)
    assert r.code == OK and control.tolist() == [0, 37]


def test_accuracy_against_dop853():
    # an ensemble of the text's damped scene: every state within 1e-6 rad
    th0, om0, t = text_scene_ensemble(16)
    r = _batch.rk4_batch(t, th0, om0, W0, 0.1, 0.025)
    for i in range(16):
        assert np.abs(r.theta[i] - dop853_text_scene(t, th0[i], om0[i])).max() < 1e-6


def test_openmp_flag_is_boolean():
    assert _batch.openmp() in (True, False)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")
def test_forked_child_after_threaded_parent_does_not_hang():
    # GNU OpenMP's thread pool does not survive fork: the child must not try
    # to use it (it would hang); it runs on one thread with the same results.
    assert (
        forked_child_exit_code(lambda: _batch.rk4_batch(T, np.linspace(-1, 1, 64), 2.0, W0, 0.1, 0.05, threads=2)) == 0
    )


@pytest.mark.parametrize("threads", [1, 2])
def test_out_arrays_are_filled_in_place(threads):
    """out=(theta, omega): the result's arrays are the caller's, with the bits
    of a call that allocates its own, stale contents overwritten; a state that
    fails during the run gets NaN rows there too."""
    th0, om0, w0, gam, h = mixed_states()
    om0[11], w0[11], gam[11] = 1.7e308, 1e-3, 0.0  # overflows mid-run
    want = pendula.rk4(T, th0, om0, w0, gam, h, threads=threads)
    out = (np.full((th0.size, T.size), 7.0), np.full((th0.size, T.size), -7.0))
    for _ in range(2):  # the second call writes over the first's results
        r = pendula.rk4(T, th0, om0, w0, gam, h, threads=threads, out=out)
        assert r.theta is out[0] and r.omega is out[1]
        assert np.array_equal(out[0], want.theta, equal_nan=True) and np.array_equal(out[1], want.omega, equal_nan=True)
        assert np.isnan(out[0][11]).all() and not r.ok[11] and np.array_equal(r.codes, want.codes)
    # a batch shape and one state, with and without a drive
    d = pendula.Drive("torque", 1.15, 2 / 3)
    for kw in (
        dict(theta0=[[0.1, 0.2], [0.3, 0.4]]),
        dict(theta0=0.3),
        dict(theta0=[0.1, 0.2], drive=d),
        dict(theta0=0.3, drive=d),
    ):
        want = pendula.rk4(T, omega0=0.0, w0=1.0, gamma=0.5, h=0.05, **kw)
        out = (np.full(want.theta.shape, np.nan), np.full(want.theta.shape, np.nan))
        r = pendula.rk4(T, omega0=0.0, w0=1.0, gamma=0.5, h=0.05, out=out, **kw)
        assert r.theta is out[0] and np.array_equal(out[0], want.theta) and np.array_equal(out[1], want.omega)


def test_refused_out_is_never_written():
    good = np.full((3, T.size), 5.0)
    for bad in (np.zeros((3, T.size - 1)), np.zeros((T.size, 3)).T, good):
        with pytest.raises(ValueError, match="out"):
            pendula.rk4(T, [0.1, 0.2, 0.3], 0.0, W0, 0.1, 0.05, out=(good, bad))
        assert (good == 5.0).all()


def test_state_codes_with_shared_and_repeated_parameters():
    """w0, gamma and h are checked once per run of equal values: the codes
    must still be each state's own, as the scalar call would report them."""
    th0 = np.array([0.1, np.nan, 0.3, 0.4, np.inf, 0.6])
    om0 = np.array([0.0, 0.0, -np.inf, 0.0, 0.0, 0.0])
    r = _batch.rk4_batch(T, th0, om0, W0, 0.1, 0.05)  # shared parameters, valid
    assert r.codes.tolist() == [OK, ERR_NONFINITE, ERR_NONFINITE, OK, ERR_NONFINITE, OK]
    r = _batch.rk4_batch(T, th0, om0, 100.0, 0.1, 0.05)  # shared and unstable
    assert r.codes.tolist() == [ERR_UNSTABLE, ERR_NONFINITE, ERR_NONFINITE, ERR_UNSTABLE, ERR_NONFINITE, ERR_UNSTABLE]
    # runs of equal parameters, a NaN one (never equal to the last) and a change back
    w0 = np.array([W0, W0, 100.0, np.nan, W0, -1.0])
    r = _batch.rk4_batch(T, np.full(6, 0.2), 0.0, w0, 0.1, 0.05)
    assert r.codes.tolist() == [OK, OK, ERR_UNSTABLE, ERR_NONFINITE, OK, ERR_DOMAIN]
    for w, code in zip(w0, r.codes):  # the scalar call agrees: integrated or refused
        if code == OK:
            assert np.array_equal(pendula.rk4(T, 0.2, 0.0, w, 0.1, 0.05).theta, r.theta[1])
        else:
            with pytest.raises(ValueError, match="w0|h ="):
                pendula.rk4(T, 0.2, 0.0, w, 0.1, 0.05)
