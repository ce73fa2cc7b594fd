"""pendula._batch.cvode_batch: many CVODE states per call (private entry point).

Every state must be bit-identical to pendula.cvode for the same arguments
(0 ulps in theta and omega, every counter equal), whatever the batch shape,
the thread count, the method, or the states that ran before it on the same
reused solver; a failing state reports the code of the exception pendula.cvode
raises for it and leaves the others intact; a cancel request from another
thread stops the call with the finished states kept.  Accuracy is
pendula.cvode's (tested in test_integrators.py); one ensemble of the text's
damped scene is also checked against SciPy's DOP853 at rtol 1e-12.
"""

import math
import os
import threading
import time

import numpy as np
import pytest
from helpers import dop853_text_scene, finished_states_of_cancelled_batch, forked_child_exit_code, text_scene_ensemble

import pendula
from pendula._errors import ERR_DOMAIN, ERR_MAXSTEPS, ERR_NONFINITE, ERR_SOLVER, OK
from pendula._many import kernels as _batch

pytestmark = pytest.mark.skipif(not pendula.have_cvode(), reason="this build has no CVODE")

T = np.linspace(0.0, 30.0, 121)
W0 = math.sqrt(2.0)
REFUSED = -1  # pendula.cvode raised ValueError: ERR_NONFINITE or ERR_DOMAIN


def mixed_states(n=40, seed=3):
    """Small and large amplitudes, rotations both ways, gamma = 0 and
    overdamped, rtol 1e-4..1e-10 with atol > 0 and atol = 0 interleaved, and
    failures: a NaN omega0, w0 = 0, rotations that exhaust a budget of 1000
    steps, rtol = 1e-300 (CVODE: too much accuracy)."""
    rng = np.random.default_rng(seed)
    th0 = rng.uniform(-3.1, 3.1, n)
    om0 = rng.uniform(-4.0, 4.0, n)
    w0 = rng.uniform(0.5, 3.0, n)
    gam = rng.uniform(0.0, 0.4, n)
    rtol = 10.0 ** -rng.integers(4, 11, n)
    atol = np.where(np.arange(n) % 3 == 0, 0.0, rtol * 1e-2)
    gam[:4] = 0.0
    gam[4:7] = 8 * w0[4:7]
    om0[[9, 29]] = [40.0, -35.0]
    rtol[[9, 29]] = 1e-10
    om0[16] = np.nan
    w0[21] = 0.0
    rtol[25], atol[25] = 1e-300, 0.0
    return th0, om0, w0, gam, rtol, atol


def scalar(t, th0, om0, w0, gam, rtol, atol, method="adams", max_steps=1000):
    """pendula.cvode per state: (theta, omega, stats, code) with the code of the error raised."""
    out = []
    for a in zip(th0, om0, w0, gam, rtol, atol):
        try:
            r = pendula.cvode(t, *a[:4], rtol=a[4], atol=a[5], method=method, max_steps=max_steps)
            out.append((r.theta, r.omega, r.stats, OK))
        except pendula.PendulaSolverError as e:
            out.append((None, None, None, ERR_MAXSTEPS if "budget" in str(e) else ERR_SOLVER))
        except ValueError:
            out.append((None, None, None, REFUSED))
    return out


def assert_identical(r, ref):
    codes = r.codes.reshape(-1)
    for i, (th, om, st, code) in enumerate(ref):
        assert codes[i] in (ERR_NONFINITE, ERR_DOMAIN) if code == REFUSED else codes[i] == code, f"state {i}"
        if code != OK:
            continue
        j = np.unravel_index(i, r.codes.shape)
        assert np.array_equal(r.theta[j].view(np.int64), th.view(np.int64)), f"state {i}"
        assert np.array_equal(r.omega[j].view(np.int64), om.view(np.int64)), f"state {i}"
        assert {k: int(v[j]) for k, v in r.stats.items()} == st, f"state {i}"


@pytest.mark.parametrize("method", ["adams", "bdf"])
@pytest.mark.parametrize("threads", [1, 2])
def test_bit_identical_to_cvode_with_failures_in_the_middle(method, threads):
    args = mixed_states()
    ref = scalar(T, *args, method=method)
    r = _batch.cvode_batch(T, *args, method=method, max_steps=1000, threads=threads)
    codes = [c for *_, c in ref]
    assert codes.count(ERR_MAXSTEPS) >= 2 and codes.count(ERR_SOLVER) == 1
    assert codes.count(REFUSED) == 2 and sorted(r.codes[[16, 21]]) == [ERR_NONFINITE, ERR_DOMAIN]
    assert_identical(r, ref)
    first = codes.index(next(c for c in codes if c != OK))
    assert r.first_failed == first and r.code == r.codes[first] != OK
    assert r.message.startswith(f"state {first + 1} of 40 (")
    assert r.method == method and (r.steps == r.stats["steps"]).all()


def test_failed_state_is_nan_from_its_failure_on():
    # the Fortran batch writes NaN (not cvode_solve's zeros) after a state's
    # failure time: the outputs reached are kept, bit for bit as in a run with
    # a budget large enough; a refused state is NaN throughout
    args = mixed_states()
    r = _batch.cvode_batch(T, *args, max_steps=1000, threads=1)
    full = _batch.cvode_batch(T, *args, max_steps=10**6, threads=1)
    budget = np.flatnonzero(r.codes == ERR_MAXSTEPS)
    assert budget.size >= 2
    for i in budget:
        nan = np.isnan(r.theta[i])
        k = int(np.argmax(nan))
        assert 0 < k and nan[k:].all() and not nan[:k].any() and np.isnan(r.omega[i, k:]).all(), f"state {i}"
        assert full.codes[i] == OK and np.array_equal(r.theta[i, :k], full.theta[i, :k]), f"state {i}"
    for i in (16, 21):
        assert np.isnan(r.theta[i]).all() and np.isnan(r.omega[i]).all()


def test_order_of_states_does_not_matter():
    # each state follows a different predecessor on the reused solver
    args = mixed_states()
    r = _batch.cvode_batch(T, *args, max_steps=1000, threads=1)
    rev = _batch.cvode_batch(T, *(a[::-1] for a in args), max_steps=1000, threads=1)
    assert np.array_equal(r.theta[::-1].view(np.int64), rev.theta.view(np.int64))
    assert np.array_equal(r.codes[::-1], rev.codes)
    for k in r.stats:
        assert np.array_equal(r.stats[k][::-1], rev.stats[k])


@pytest.mark.parametrize("shape", [(), (0,), (1,), (5,), (2, 3), (3, 0)])
def test_shapes(shape):
    th0 = np.linspace(0.1, 1.0, int(np.prod(shape))).reshape(shape)
    r = _batch.cvode_batch(T, th0, 0.5, W0, 0.1)
    assert r.theta.shape == shape + T.shape and r.omega.shape == shape + T.shape
    assert r.codes.shape == shape and all(v.shape == shape for v in r.stats.values())
    assert r.code == OK and r.first_failed == -1
    flat = r.theta.reshape(-1, T.size)
    for i, x in enumerate(th0.reshape(-1)):
        assert np.array_equal(flat[i], pendula.cvode(T, x, 0.5, W0, 0.1).theta)


def test_broadcast_of_parameters_and_tolerances():
    th0 = np.array([[0.1], [0.5]])
    rtol = np.array([1e-6, 1e-8, 1e-10])
    r = _batch.cvode_batch(T, th0, 0.0, W0, 0.1, rtol=rtol, atol=0.0)
    assert r.theta.shape == (2, 3, T.size)
    for a in range(2):
        for b in range(3):
            ref = pendula.cvode(T, th0[a, 0], 0.0, W0, 0.1, rtol=rtol[b], atol=0.0)
            assert np.array_equal(r.theta[a, b], ref.theta) and r.stats["rhs_evals"][a, b] == ref.stats["rhs_evals"]


def test_one_output_time_is_the_start():
    r = _batch.cvode_batch([2.0], [0.1, 0.2], [1.0, 3.0], W0, 0.1)
    assert r.theta.tolist() == [[0.1], [0.2]] and r.omega.tolist() == [[1.0], [3.0]]
    assert (r.steps == 0).all() and r.code == OK


def test_call_level_errors():
    with pytest.raises(ValueError, match="method"):
        _batch.cvode_batch(T, [0.1], 0.0, W0, 0.1, method="rk45")
    with pytest.raises(ValueError, match="max_steps"):
        _batch.cvode_batch(T, [0.1], 0.0, W0, 0.1, max_steps=0)
    with pytest.raises(TypeError, match="max_steps"):
        _batch.cvode_batch(T, [0.1], 0.0, W0, 0.1, max_steps=10.5)
    with pytest.raises(ValueError, match="events"):
        _batch.cvode_batch(T, [0.1], 0.0, W0, 0.1, events=True)
    with pytest.raises(TypeError, match="events"):
        _batch.cvode_batch(T, [0.1], 0.0, W0, 0.1, events=1)
    with pytest.raises(ValueError, match="broadcast"):
        _batch.cvode_batch(T, [0.1, 0.2], [0.0, 1.0, 2.0], W0, 0.1)
    with pytest.raises(ValueError, match="threads"):
        _batch.cvode_batch(T, [0.1], 0.0, W0, 0.1, threads=-1)
    with pytest.raises(ValueError, match="increasing"):
        _batch.cvode_batch([0.0, 2.0, 1.0], [0.1], 0.0, W0, 0.1)
    with pytest.raises(ValueError, match="overflows"):
        _batch.cvode_batch([-1e308, 1e308], [0.1], 0.0, W0, 0.1)
    with pytest.raises(TypeError, match="control"):
        _batch.cvode_batch(T, [0.1], 0.0, W0, 0.1, control=np.zeros(2))


def test_inputs_are_not_modified():
    th0 = np.array([0.1, 0.2])
    rtol = np.array([1e-8, 1e-6])
    _batch.cvode_batch(T, th0, 0.0, W0, 0.1, rtol=rtol)
    assert th0.tolist() == [0.1, 0.2] and rtol.tolist() == [1e-8, 1e-6]


def test_cancel_from_another_thread_keeps_finished_states():
    # about 1.5 s of work on one thread; the flag is raised after 0.2 s
    n = 3000
    t = np.linspace(0.0, 30.0, 601)
    th0 = np.linspace(-1.0, 1.0, n)
    control = np.zeros(2, dtype=np.int64)
    timer = threading.Timer(0.2, lambda: control.__setitem__(0, 1))
    timer.start()
    t0 = time.perf_counter()
    r = _batch.cvode_batch(t, th0, 2.0, W0, 0.1, rtol=1e-9, atol=1e-11, threads=1, control=control)
    elapsed = time.perf_counter() - t0
    timer.join()
    done = finished_states_of_cancelled_batch(r, n, control)
    assert (r.steps[~done] == 0).all()
    for i in np.flatnonzero(done)[:: max(1, done.sum() // 5)]:
        assert np.array_equal(r.theta[i], pendula.cvode(t, th0[i], 2.0, W0, 0.1, rtol=1e-9, atol=1e-11).theta)
    assert elapsed < 5.0


def test_progress_counter_counts_every_state():
    control = np.zeros(2, dtype=np.int64)
    r = _batch.cvode_batch(T, np.linspace(0, 1, 37), 0.0, W0, 0.1, threads=2, control=control)
    assert r.code == OK and control.tolist() == [0, 37]


def test_accuracy_of_the_text_scene_against_dop853():
    # an ensemble of the text's damped scene: every state within 1e-6 rad
    th0, om0, t = text_scene_ensemble(12)
    r = _batch.cvode_batch(t, th0, om0, W0, 0.1, rtol=1e-9, atol=1e-11)
    for i in range(12):
        assert np.abs(r.theta[i] - dop853_text_scene(t, th0[i], om0[i])).max() < 1e-6


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")
def test_forked_child_after_threaded_parent_does_not_hang():
    # GNU OpenMP's thread pool does not survive fork: the child runs its
    # batch on one thread, with the same results bit for bit.
    th0 = np.linspace(-1, 1, 16)
    assert forked_child_exit_code(lambda: _batch.cvode_batch(T, th0, 2.0, W0, 0.1, threads=2)) == 0
