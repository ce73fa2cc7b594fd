"""The public batch API of rk4 and cvode: arrays of states broadcast like NumPy.

Every state of a batch must equal the scalar call for that state bit for bit
(theta, omega, stats), for any batch shape (0-d, 1-D, 2-D, broadcast, empty)
and thread count; per-state failures are reported per state and never cost
the other states their answers; a batch whose every state failed raises.
"""

import numpy as np
import pytest
from helpers import HAVE_CVODE

import pendula
from pendula._errors import ERR_MAXSTEPS, ERR_UNSTABLE, OK

T = np.linspace(0.0, 30.0, 61)
# text's damped scene plus a rotating start and an extreme angle
TH0 = np.array([[0.0, 0.3, 3.1], [-2.0, 1e-8, np.pi]])
OM0 = np.array([2.0, 0.0, -4.0])

needs_cvode = pytest.mark.skipif(not HAVE_CVODE, reason="this build has no CVODE")


def _scalar(fn, th, om, w0, gam, **kw):
    return fn(T, float(th), float(om), float(w0), float(gam), **kw)


def _check_states(res, fn, th0, om0, w0, gam, **kw):
    shape = np.broadcast_shapes(np.shape(th0), np.shape(om0), np.shape(w0), np.shape(gam))
    assert res.theta.shape == shape + (T.size,) and res.omega.shape == res.theta.shape
    assert res.codes.shape == shape and res.ok.all() and res.message == ""
    b = [np.broadcast_to(x, shape) for x in (th0, om0, w0, gam)]
    for idx in np.ndindex(shape):
        s = _scalar(fn, *(x[idx] for x in b), **kw)
        assert np.array_equal(res.theta[idx], s.theta) and np.array_equal(res.omega[idx], s.omega), idx
        assert {k: int(v[idx]) for k, v in res.stats.items()} == s.stats


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("shape", ["1-D", "2-D", "broadcast"])
def test_rk4_batch_is_the_scalar_call_bit_for_bit(shape, threads):
    th0, om0, w0, gam = {
        "1-D": (TH0[0], 0.5, 1.4, 0.1),
        "2-D": (TH0, 0.5, 1.4, np.full((2, 3), 0.1)),
        "broadcast": (TH0[:, :1], OM0, np.array([1.4, 2.0, 0.7]), 0.05),
    }[shape]
    res = pendula.rk4(T, th0, om0, w0, gam, 0.05, threads=threads)
    assert isinstance(res, pendula.BatchIntegrationResult) and res.method == "rk4"
    _check_states(res, pendula.rk4, th0, om0, w0, gam, h=0.05)


@needs_cvode
@pytest.mark.parametrize("threads", [1, 2])
def test_cvode_batch_is_the_scalar_call_bit_for_bit(threads):
    res = pendula.cvode(T, TH0, OM0, 1.4, [[0.1], [0.0]], threads=threads)
    assert res.method == "adams"
    _check_states(res, pendula.cvode, TH0, OM0, 1.4, np.array([[0.1], [0.0]]))


@needs_cvode
def test_cvode_batch_events_per_state():
    res = pendula.cvode(T, TH0[0], 0.0, 1.4, 0.1, events=True, threads=2)
    assert res.events.shape == (3,)
    for i, th in enumerate(TH0[0]):
        s = pendula.cvode(T, float(th), 0.0, 1.4, 0.1, events=True)
        assert np.array_equal(res.theta[i], s.theta)
        assert np.array_equal(res.events[i].t, s.events.t) and np.array_equal(res.events[i].kind, s.events.kind)


def test_zero_d_input_is_the_scalar_path():
    # a 0-d batch is a scalar call: same type, same answer (theta.shape == () + (n_t,))
    r0 = pendula.rk4(T, np.float64(0.3), np.array(0.5), 1.4, 0.1, 0.05)
    r = pendula.rk4(T, 0.3, 0.5, 1.4, 0.1, 0.05)
    assert type(r0) is type(r) is pendula.IntegrationResult
    assert np.array_equal(r0.theta, r.theta) and r0.stats == r.stats


@pytest.mark.parametrize("fn", ["rk4", "cvode"])
def test_empty_batch(fn):
    if fn == "cvode" and not HAVE_CVODE:
        pytest.skip("no CVODE")
    kw = {"h": 0.05} if fn == "rk4" else {}
    res = getattr(pendula, fn)(T, np.zeros((0, 3)), 0.0, 1.4, 0.1, **kw)
    assert res.theta.shape == (0, 3, T.size) and res.codes.shape == (0, 3)
    assert all(v.shape == (0, 3) for v in res.stats.values())


def test_rk4_mixed_failures_keep_the_other_states():
    # w0 = 100 makes h = 0.05 unstable (largest stable h ~ 2.8/100)
    w0 = np.array([1.4, 100.0, 2.0, 100.0])
    res = pendula.rk4(T, 0.3, 0.0, w0, 0.1, 0.05)
    assert res.codes.tolist() == [OK, ERR_UNSTABLE, OK, ERR_UNSTABLE]
    assert res.ok.tolist() == [True, False, True, False] and res.first_failed == 1
    assert res.message.startswith("2 of 4 states failed (see codes); the first: h[1] = 0.05 is unstable")
    assert np.isnan(res.theta[[1, 3]]).all() and np.isnan(res.omega[[1, 3]]).all()  # never data
    for i in (0, 2):
        assert np.array_equal(res.theta[i], pendula.rk4(T, 0.3, 0.0, w0[i], 0.1, 0.05).theta)


def test_rk4_max_steps_is_per_state():
    # 600 steps of h = 0.05 over 30 s: a budget of 599 refuses each state alone
    res = pendula.rk4(T, [0.1, 0.2], 0.0, 1.4, 0.1, 0.05, max_steps=600)
    assert res.ok.all()
    with pytest.raises(ValueError, match="every state failed"):
        pendula.rk4(T, [0.1, 0.2], 0.0, 1.4, 0.1, 0.05, max_steps=599)


@needs_cvode
def test_cvode_mixed_failures_and_all_failed():
    w0 = np.array([1.4, 200.0])
    res = pendula.cvode(T, 0.3, 0.0, w0, 0.1, max_steps=3000)
    assert res.codes.tolist() == [OK, ERR_MAXSTEPS] and "max_steps" in res.message
    assert np.array_equal(res.theta[0], pendula.cvode(T, 0.3, 0.0, 1.4, 0.1, max_steps=3000).theta)
    with pytest.raises(pendula.PendulaSolverError, match="every state failed"):
        pendula.cvode(T, 0.3, 0.0, [200.0, 300.0], 0.1, max_steps=3000)


def test_bad_value_in_one_state_raises_naming_state_and_argument():
    with pytest.raises(ValueError, match=r"^w0\[2\] = -1 is out of range"):
        pendula.rk4(T, 0.3, 0.0, [1.0, 2.0, -1.0, 3.0], 0.1, 0.05)
    with pytest.raises(ValueError, match=r"^w0\[1, 0\] = -1 is out of range"):
        pendula.cvode(T, [[0.3], [0.2]], 0.0, [[1.0], [-1.0]], 0.1) if pendula.build_info()["cvode"] else pendula.rk4(
            T, [[0.3], [0.2]], 0.0, [[1.0], [-1.0]], 0.1, 0.05
        )
    with pytest.raises(ValueError, match="broadcast"):
        pendula.rk4(T, [0.1, 0.2], [0.0, 0.1, 0.2], 1.4, 0.1, 0.05)


def test_inputs_are_not_modified():
    th0 = TH0.copy()
    pendula.rk4(T, th0, 0.0, 1.4, 0.1, 0.05)
    assert np.array_equal(th0, TH0)


def test_progress_callback_counts_states():
    seen = []
    res = pendula.rk4(
        T, np.linspace(0, 1, 50), 0.0, 1.4, 0.1, 0.05, progress=lambda done, total: seen.append((done, total))
    )
    assert res.ok.all() and seen and seen[-1] == (50, 50)
    assert all(total == 50 and 0 <= done <= 50 for done, total in seen)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)


# ---- scenes -------------------------------------------------------------------

TS = np.linspace(0.0, 20.0, 41)


def _scene_states(batch_kw, shape):
    b = {k: np.broadcast_to(v, shape) for k, v in batch_kw.items()}
    return [(idx, {k: float(v[idx]) for k, v in b.items()}) for idx in np.ndindex(shape)]


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("fn", ["solve", "run_model"])
def test_scene_batch_is_the_scalar_solve_bit_for_bit(fn, threads):
    kw = dict(theta0=np.array([[0.2, 1.0, 3.0]]), gamma=np.array([[0.0], [0.1]]), tol=1e-7)
    batch = pendula.Scene(t=TS, **kw)
    assert isinstance(batch, pendula.SceneBatch) and batch.shape == (2, 3)
    call = (
        (lambda s, **k: pendula.solve(s, **k))
        if fn == "solve"
        else (lambda s, **k: pendula.run_model(s, "rk4", 0.01, **k))
    )
    res = call(batch, threads=threads)
    assert res.ok.all() and res.theta.shape == (2, 3, TS.size) and res.message == ""
    for idx, one in _scene_states(kw, (2, 3)):
        s = call(pendula.Scene(t=TS, **one))
        assert res.model[idx] == s.model and res.error_estimate[idx] == s.error_estimate
        assert np.array_equal(res.theta[idx], s.theta) and np.array_equal(res.omega[idx], s.omega)
        assert res.results[idx].reason == s.reason


def test_scene_batch_wants_and_scalar_t():
    res = pendula.solve(pendula.Scene([0.5, 2.0], want="period"))
    assert res.period.shape == (2,) and res.theta is None
    assert res.period[1] == pendula.solve(pendula.Scene(2.0, want="period")).period
    res = pendula.solve(pendula.Scene([0.5, 2.0], t=3.0, want="energy"))
    assert res.energy.shape == (2, 1)
    assert res.energy[0, 0] == pendula.solve(pendula.Scene(0.5, t=3.0, want="energy")).energy[0]
    final = pendula.solve(pendula.Scene([0.5, 2.0], t=[0.0, 3.0], want="final"))
    assert final.theta.shape == final.omega.shape == final.t.shape == (2, 1)


def test_scene_batch_mixed_failures_and_all_failed():
    # length 4.9e-4 m: w0 = 141 1/s, so the RK4 step 0.05 s is unstable for that scene alone
    mixed = pendula.run_model(pendula.Scene([0.3, 0.4], t=[0.0, 10.0], gamma=0.1, length=[4.9, 4.9e-4]), "rk4", 0.05)
    assert mixed.codes[0] == OK and mixed.codes[1] == ERR_UNSTABLE and mixed.first_failed == 1
    assert mixed.message.startswith("1 of 2 states failed (see codes); the first: state [1]: h = 0.05 is unstable")
    assert "unstable" in mixed.messages[1]
    assert mixed.messages[0] == "" and mixed.model[1] == "" and np.isnan(mixed.error_estimate[1])
    assert mixed.results[1] is None and np.isnan(mixed.theta[1]).all() and not mixed.tol_met[1]
    single = pendula.run_model(pendula.Scene(0.3, t=[0.0, 10.0], gamma=0.1), "rk4", 0.05)
    assert np.array_equal(mixed.theta[0], single.theta)
    with pytest.raises(ValueError, match="every state failed"):
        pendula.run_model(pendula.Scene([0.3, 0.4], t=[0.0, 10.0], gamma=0.1, length=4.9e-4), "rk4", 0.05)


def test_scene_batch_bad_state_names_state_and_argument():
    with pytest.raises(ValueError, match=r"^length\[1\] = -1 is out of range"):
        pendula.Scene([0.3, 0.4], t=TS, length=[4.9, -1.0])


def test_scene_batch_empty_and_progress():
    res = pendula.solve(pendula.Scene(np.zeros(0), t=TS))
    assert res.codes.shape == (0,) and res.results.shape == (0,)
    seen = []
    res = pendula.solve(
        pendula.Scene(np.linspace(0.1, 1.0, 7), t=TS, gamma=0.1),
        progress=lambda done, total: seen.append((done, total)),
        threads=2,
    )
    assert res.ok.all() and seen[-1] == (7, 7)


def test_tradeoff_of_a_batch_is_one_table_per_scene():
    tables = pendula.tradeoff(pendula.Scene([0.2, 1.0], t=TS), models=["exact", "rk4"], rk4_steps=[0.05], repeat=1)
    assert tables.shape == (2,)
    one = pendula.tradeoff(pendula.Scene(1.0, t=TS), models=["exact", "rk4"], rk4_steps=[0.05], repeat=1)
    assert tables[1].column("sup_error") == one.column("sup_error")


def test_scenes_and_scene_batches_pickle():
    import pickle

    s = pendula.Scene(0.3, t=TS, gamma=0.1)
    assert repr(pickle.loads(pickle.dumps(s))) == repr(s)
    b = pickle.loads(pickle.dumps(pendula.Scene([0.3, 0.4], t=TS)))
    assert np.array_equal(pendula.solve(b).theta, pendula.solve(pendula.Scene([0.3, 0.4], t=TS)).theta)
    with pytest.raises(TypeError, match="theta0"):
        pendula.Scene()
