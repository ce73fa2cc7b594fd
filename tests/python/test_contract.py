"""One contract for one pendulum and for many (docs/robustness.md), checked on every surface.

Scalar calls, rk4/cvode batches, sweeps (local and on a Dask LocalCluster), scene batches and
their conversions: the same default pendulum and defaults; a failed state is NaN from the point
it failed, never a plausible number; an integer field gets a sentinel and a mask; a batch raises
only when every state failed; argument errors are ValueError naming the argument and the state
by its 0-based index; no NumPy repr in a message.
"""

import inspect
import math

import numpy as np
import pytest

import pendula
from pendula import _defaults, cli
from pendula._errors import ERR_MAXSTEPS, ERR_UNSTABLE, OK
from pendula._many import kernels

HAVE_CVODE = pendula.build_info()["cvode"]
needs_cvode = pytest.mark.skipif(not HAVE_CVODE, reason="this build has no CVODE")
T = np.linspace(0.0, 10.0, 11)
W0_TEXT = math.sqrt(9.8 / 4.9)


def _no_numpy_repr(msg):
    assert "np." not in msg and "float64(" not in msg and "int64(" not in msg, msg


# ---------------------------------------------------------------- one default pendulum, defaults once


def test_one_default_pendulum_everywhere():
    assert pendula.natural_frequency() == W0_TEXT == pendula.Scene(0.1, t=[0.0, 1.0]).w0
    assert pendula.sweep(None, 1.0, want="period").period == pendula.period(1.0)
    th = np.array([0.1, 1.0, 3.0])
    assert np.array_equal(pendula.sweep(None, th, want="period").period, pendula.period(th))
    r = pendula.sweep(T, th, h=0.01)
    assert np.array_equal(r.inputs["w0"], np.full(3, W0_TEXT)) and (r.inputs["gamma"] == 0).all()
    direct = pendula.rk4(T, th, 0.0, W0_TEXT, 0.0, 0.01)
    assert np.array_equal(r.theta, direct.theta[:, -1])


def test_sweep_takes_the_parameters_as_every_function_does():
    th = np.array([0.5, 2.0])
    by_w0 = pendula.sweep(T, th, w0=pendula.natural_frequency(9.8, 2.0), gamma=pendula.damping_rate(0.02, 0.1))
    by_text = pendula.sweep(T, th, g=9.8, length=2.0, b=0.02, mass=0.1)
    assert np.array_equal(by_w0.theta, by_text.theta) and np.array_equal(by_w0.inputs["gamma"], by_text.inputs["gamma"])
    assert np.array_equal(pendula.sweep(None, th, length=2.0, want="period").period, pendula.period(th, length=2.0))
    with pytest.raises(ValueError, match="mass"):
        pendula.sweep(T, th, b=0.02)
    with pytest.raises(ValueError, match="w0"):
        pendula.sweep(T, th, w0=1.0, g=9.8, length=2.0)  # disagree


def _default(fn, name):
    return inspect.signature(fn).parameters[name].default


def test_every_default_is_read_from_one_place():
    for fn in (pendula.cvode, kernels.cvode_batch, pendula.sweep):
        assert _default(fn, "rtol") == _defaults.CVODE_RTOL and _default(fn, "atol") == _defaults.CVODE_ATOL
        assert _default(fn, "max_steps") == _defaults.CVODE_MAX_STEPS
        assert _default(fn, "threads") is _defaults.THREADS is None
    assert _default(pendula.cvode, "method") == _default(pendula.sweep, "cvode_method") == _defaults.CVODE_METHOD
    assert _default(pendula.rk4, "max_steps") == _default(kernels.rk4_batch, "max_steps") == _defaults.RK4_MAX_STEPS
    for fn in (pendula.rk4, kernels.rk4_batch, pendula.solve, pendula.run_model):
        assert _default(fn, "threads") is None
    assert _default(pendula.Scene.__init__, "tol") == _defaults.TOL
    assert _default(pendula.sweep, "h") == _defaults.SWEEP_H
    parser = cli.build_parser()
    assert parser.parse_args(["solve", "--theta0", "0.1", "--t-end", "1"]).tol == _defaults.TOL
    assert parser.parse_args(["sweep", "--out", "x"]).h == _defaults.SWEEP_H


def test_version_is_the_build_version():
    assert pendula.__version__ == pendula.build_info()["version"] and pendula.__version__.count(".") == 2


# ---------------------------------------------------------------- failed states are NaN


def test_rk4_batch_failed_state_is_nan_and_the_others_keep_their_answers():
    r = pendula.rk4(T, [0.1, 0.2, 0.3], 0.0, [1.0, 1e4, 2.0], 0.0, 0.01)
    assert r.codes.tolist() == [OK, ERR_UNSTABLE, OK]
    assert np.isnan(r.theta[1]).all() and np.isnan(r.omega[1]).all()
    assert np.isfinite(r.theta[[0, 2]]).all()
    assert r.message.startswith("1 of 3 states failed (see codes); the first: h[1] = 0.01 is unstable")


def test_rk4_takes_a_step_per_state():
    h = np.array([0.1, 0.01, 0.001])
    r = pendula.rk4(T, 0.5, 0.0, 1.0, 0.1, h)
    for i in range(3):
        assert np.array_equal(r.theta[i], pendula.rk4(T, 0.5, 0.0, 1.0, 0.1, h[i]).theta)
    assert np.array_equal(r.inputs["h"], h)
    with pytest.raises(ValueError, match=r"^h\[2\] = -1 is out of range"):
        pendula.rk4(T, 0.5, 0.0, 1.0, 0.1, [0.1, 0.01, -1.0])


@needs_cvode
def test_cvode_batch_failed_state_keeps_what_it_reached_then_nan():
    # the second state spins fast: 200 steps carry it only part of the window
    r = pendula.cvode(T, [0.1, 3.0], [0.0, 100.0], 1.0, 0.0, max_steps=200)
    assert r.codes.tolist() == [OK, ERR_MAXSTEPS]
    reached = np.isfinite(r.theta[1])
    k = int(reached.sum())
    assert 1 <= k < T.size and reached[:k].all() and not reached[k:].any()  # kept, then NaN
    assert r.theta[1, 0] == 3.0 and np.isnan(r.omega[1, k:]).all()
    assert np.isfinite(r.theta[0]).all()


@needs_cvode
def test_cvode_events_batch_failed_state_is_nan():
    r = pendula.cvode(T, [0.1, 3.0], [0.0, 100.0], 1.0, 0.0, max_steps=200, events=True)
    assert r.codes.tolist() == [OK, ERR_MAXSTEPS] and r.events[1] is None
    assert np.isnan(r.theta[1]).all() and np.isfinite(r.theta[0]).all()


def test_sweep_failed_state_is_nan_with_no_well():
    r = pendula.sweep([0.0, 1.0], [0.0, 1.0], 0.1, w0=np.array([1.0, 1e4]))
    assert r.codes.tolist() == [OK, ERR_UNSTABLE]
    assert np.isnan(r.theta[1]) and np.isnan(r.omega[1]) and np.isfinite(r.theta[0])
    assert r.well.tolist() == [0, pendula.WELL_NONE] and r.settled.tolist() == [True, False]
    assert not r.rotating()[1]
    traj = pendula.sweep([0.0, 1.0], [0.0, 1.0], 0.1, w0=np.array([1.0, 1e4]), want="trajectory")
    assert np.isnan(traj.theta[1]).all()


def test_a_state_still_near_the_top_is_not_assigned_a_well():
    # started just below the top with no time to fall: its well is not decided at t[-1]
    r = pendula.sweep([0.0, 0.5], [np.pi - 1e-6, 0.3], 0.0, 1.0, 0.1, h=0.01)
    assert r.settled.tolist() == [False, True] and r.well.tolist() == [pendula.WELL_NONE, 0]
    # going over the top: not settled either
    r = pendula.sweep([0.0, 1.0], 0.0, 5.0, 1.0, 0.1, h=0.01)
    assert not r.settled and r.well == pendula.WELL_NONE and r.rotating()


def test_scene_batch_failed_scene_is_nan():
    r = pendula.run_model(pendula.Scene([0.3, 0.4], t=[0.0, 10.0], gamma=0.1, length=[4.9, 4.9e-4]), "rk4", 0.05)
    assert r.codes.tolist() == [OK, ERR_UNSTABLE]
    assert np.isnan(r.theta[1]).all() and np.isnan(r.omega[1]).all() and np.isnan(r.error_estimate[1])
    assert r.model[1] == "" and not r.tol_met[1] and np.isfinite(r.theta[0]).all()
    assert r.message.startswith("1 of 2 states failed (see codes); the first: state [1]: h = 0.05 is unstable")
    df = r.to_pandas()
    assert df.loc[1]["theta"].isna().all() and df.loc[0]["theta"].notna().all()


# ---------------------------------------------------------------- one rule for when a batch raises


@pytest.mark.parametrize(
    "call",
    [
        lambda: pendula.rk4(T, [0.1, 0.2], 0.0, 1e4, 0.0, 0.01),
        lambda: pendula.sweep(T, [0.1, 0.2], 0.0, 1e4, h=0.01),
        lambda: pendula.sweep(T, [0.1, 0.2], 0.0, 1e4, h=0.01, chunk_states=1),
        lambda: pendula.run_model(pendula.Scene([0.3, 0.4], t=[0.0, 10.0], length=4.9e-4), "rk4", 0.05),
    ],
    ids=["rk4", "sweep", "sweep-chunks", "scene-batch"],
)
def test_a_batch_raises_only_when_every_state_failed(call):
    with pytest.raises(
        ValueError, match=r"^every state failed \(see codes\); the first: .*\b0\.0[15] is unstable"
    ) as info:
        call()
    assert info.value.pendula_code == ERR_UNSTABLE


@needs_cvode
def test_cvode_batch_and_cvode_sweep_raise_alike_when_every_state_failed():
    for call in (
        lambda: pendula.cvode(T, [3.0, 3.1], 100.0, 1.0, 0.0, max_steps=50),
        lambda: pendula.sweep(T, [3.0, 3.1], 100.0, 1.0, method="cvode", max_steps=50),
    ):
        with pytest.raises(pendula.PendulaSolverError, match=r"^every state failed .*state \[0\]: CVODE used"):
            call()


def test_empty_batches_do_not_raise():
    assert pendula.rk4(T, np.zeros(0), 0.0, 1.0, 0.0, 0.01).codes.size == 0
    assert pendula.sweep(T, np.zeros(0)).codes.size == 0


# ---------------------------------------------------------------- argument errors: ValueError, indexed


@pytest.mark.parametrize(
    "call, pattern",
    [
        (lambda: pendula.rk4(T, [0.1, 0.2], 0.0, [1.0, -1.0], 0.0, 0.01), r"^w0\[1\] = -1 is out of range"),
        (lambda: pendula.rk4(T, [[0.1], [0.2]], 0.0, 1.0, [0.0, np.nan], 0.01), r"^gamma\[0, 1\] = NaN"),
        (lambda: pendula.sweep(T, [0.1, 0.2], 0.0, [1.0, -1.0]), r"^w0\[1\] = -1\.0 is out of range"),
        (lambda: pendula.sweep(T, [[0.1], [0.2]], 0.0, 1.0, [0.0, np.nan]), r"^gamma\[0, 1\] = nan is not finite"),
        (
            lambda: pendula.sweep(None, [0.1, 0.2], 0.0, 1.0, np.float64(0.5), want="period"),
            r"^gamma\[0\] = 0\.5 is not 0",
        ),
        (lambda: pendula.Scene([0.3, 0.4], t=[0.0, 1.0], length=[4.9, -1.0]), r"^length\[1\] = -1 is out of range"),
        (lambda: pendula.rk4(T, 0.1, 0.0, 1.0, np.float64(-1.0), 0.01), r"^gamma = -1 is out of range"),
        (lambda: pendula.rk4(T, [0.1, 0.2], 0.0, 1.0, 0.0, 0.01, threads=-1), r"^threads = -1 is out of range"),
        (lambda: pendula.sweep(T, 0.1, chunk_states=0), r"^chunk_states = 0 is out of range"),
    ],
    ids=[
        "rk4-w0",
        "rk4-2d-nan",
        "sweep-w0",
        "sweep-2d-nan",
        "sweep-period-gamma",
        "scene",
        "scalar",
        "threads",
        "chunk",
    ],
)
def test_argument_errors_name_the_argument_and_the_state(call, pattern):
    with pytest.raises(ValueError, match=pattern) as info:
        call()
    _no_numpy_repr(str(info.value))


@needs_cvode
@pytest.mark.parametrize(
    "kw, name",
    [
        (dict(max_steps=0), "max_steps"),
        (dict(max_events=0, events=True), "max_events"),
        (dict(method="rk45"), "method"),
    ],
)
def test_cvode_batch_argument_errors_are_value_errors(kw, name):
    for states in (0.1, [0.1, 0.2]):  # the scalar call and the batch answer alike
        with pytest.raises(ValueError, match=f"^{name} = ") as info:
            pendula.cvode(T, states, 0.0, 1.0, 0.0, **kw)
        assert not isinstance(info.value, pendula.PendulaSolverError)


def test_threads_none_means_the_default_everywhere():
    scene = pendula.Scene(0.1, t=[0.0, 1.0])
    for call in (
        lambda th: pendula.rk4(T, [0.1, 0.2], 0.0, 1.0, 0.0, 0.01, threads=th),
        lambda th: pendula.rk4(T, 0.1, 0.0, 1.0, 0.0, 0.01, threads=th),
        lambda th: pendula.sweep(T, [0.1, 0.2], threads=th),
        lambda th: pendula.solve(scene, threads=th),
        lambda th: pendula.solve(pendula.Scene([0.1, 0.2], t=[0.0, 1.0]), threads=th),
    ):
        a, b = call(None), call(1)
        assert np.array_equal(np.asarray(a.theta), np.asarray(b.theta))
    assert _defaults.choose_threads(None, 200 * 100) == 1  # small: one thread
    assert _defaults.choose_threads(None, 10 * _defaults.SERIAL_WORK) in (0, 1)  # large: OpenMP (1 in a fork)
    assert _defaults.choose_threads(3, 1.0) in (1, 3)


# ---------------------------------------------------------------- results carry their inputs


def test_results_convert_with_physical_coordinates():
    th, om = np.linspace(0.0, 1.0, 3), np.linspace(-1.0, 1.0, 2)
    r = pendula.sweep(T, th[:, None], om[None, :], gamma=0.1, h=0.02)
    ds = r.to_xarray()
    assert ds["theta0"].dims == ("batch_0", "batch_1") and ds["theta0"].attrs["units"] == "rad"
    assert np.array_equal(ds["theta0"].values[:, 0], th) and np.array_equal(ds["omega0"].values[0], om)
    assert float(ds["w0"][0, 0]) == W0_TEXT and float(ds["h"][0, 0]) == 0.02
    df = r.to_pandas()
    assert {"theta0", "omega0", "w0", "gamma", "h", "well", "settled", "code"} <= set(df.columns)
    b = pendula.rk4(T, th, 0.0, 1.0, 0.0, 0.01)
    assert np.array_equal(b.to_xarray()["theta0"].values, th)
    sb = pendula.solve(pendula.Scene(th, t=[0.0, 1.0], tol=1e-5))
    assert sb.to_xarray()["tol"].values.tolist() == [1e-5] * 3
    per = pendula.solve(pendula.Scene(1.0, want="period"))
    assert per.to_pandas()["period"].tolist() == [per.period] == [pendula.period(1.0)]


def test_dask_sweep_keeps_the_contract():
    distributed = pytest.importorskip("distributed")
    # in-process workers (no spawn, no sockets): the contract is the assembly's, not the transport's
    # (test_sweep.py runs the chunks in worker processes)
    with (
        distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as lc,
        distributed.Client(lc) as client,
    ):
        args = ([0.0, 1.0], [0.0, 1.0, 2.0], 0.1)
        kw = dict(w0=np.array([1.0, 1e4, 1.0]), chunk_states=1)
        remote = pendula.sweep(*args, **kw, client=client)
        local = pendula.sweep(*args, **kw)
        assert remote.codes.tolist() == [OK, ERR_UNSTABLE, OK] and np.isnan(remote.theta[1])
        assert np.array_equal(remote.theta, local.theta, equal_nan=True) and remote.message == local.message
        assert remote.well[1] == pendula.WELL_NONE
        with pytest.raises(ValueError, match="^every state failed"):
            pendula.sweep(*args, w0=1e4, chunk_states=1, client=client)
        assert pendula.sweep(None, 1.0, want="period", client=client).period == pendula.period(1.0)
