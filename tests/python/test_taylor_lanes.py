"""pendula.taylor batches: the block kernel (states side by side, one SIMD lane
each, a finished lane refilled with the next state) gives every state the
scalar call's bits, across block and chunk boundaries, with mixed parameters,
orders and step sizes, failing states amid good ones, and a drive, on every
kernel path (runtime CPU dispatch) this machine has."""

import os
import subprocess
import sys

import numpy as np
import pytest

import pendula
from pendula._codes import ERR_MAXSTEPS, OK

T = np.linspace(0.0, 12.0, 97)


def _states(n, seed=3):
    rng = np.random.default_rng(seed)
    return dict(
        theta0=rng.uniform(-3.1, 3.1, n),
        omega0=rng.uniform(-2.0, 2.0, n),
        w0=rng.uniform(0.3, 3.0, n),
        gamma=rng.choice([0.0, 0.05, 0.5, 3.0], n),
        tol=rng.choice([1e-6, 1e-9, 1e-12, 1e-14], n),
    )


def _assert_scalar_bits(b, s, i, **kw):
    r = pendula.taylor(T, *(float(s[k][i]) for k in ("theta0", "omega0", "w0", "gamma")), tol=float(s["tol"][i]), **kw)
    assert np.array_equal(b.theta[i], r.theta) and np.array_equal(b.omega[i], r.omega)
    assert np.array_equal(b.error[i], r.error)
    assert b.stats["steps"][i] == r.stats["steps"] and b.stats["order"][i] == r.stats["order"]


@pytest.mark.parametrize("threads", [1, 2])
def test_batch_is_the_scalar_call_bit_for_bit_across_blocks(threads):
    # 43 states: not a multiple of the block, orders from ~8 to ~39, steps from a few to hundreds
    s = _states(43)
    b = pendula.taylor(T, **{k: v for k, v in s.items() if k != "tol"}, tol=s["tol"], threads=threads)
    assert b.ok.all()
    assert np.unique(b.stats["order"]).size >= 4 and np.ptp(b.stats["steps"]) > 20
    for i in range(43):
        _assert_scalar_bits(b, s, i)


def test_failing_states_amid_good_ones_leave_the_others_untouched():
    s = _states(21, seed=5)
    s["w0"][[2, 9, 10, 17]] = 40.0  # these need far more steps than the budget
    budget = 60
    b = pendula.taylor(T, **{k: v for k, v in s.items() if k != "tol"}, tol=s["tol"], max_steps=budget)
    bad = b.codes != OK
    assert np.all(bad[[2, 9, 10, 17]]) and np.all(b.codes[bad] == ERR_MAXSTEPS) and np.sum(~bad) >= 8
    assert np.all(np.isnan(b.theta[bad]))
    for i in np.flatnonzero(~bad):
        _assert_scalar_bits(b, s, i, max_steps=budget)


def test_a_single_state_and_a_single_output_time():
    s = _states(9)
    b = pendula.taylor(T[:1], s["theta0"], s["omega0"], s["w0"], s["gamma"], tol=s["tol"])
    assert np.array_equal(b.theta[:, 0], s["theta0"]) and np.all(b.error == 0)
    b1 = pendula.taylor(T, s["theta0"][:1], 0.5, 1.2, 0.1, tol=1e-11)
    r = pendula.taylor(T, float(s["theta0"][0]), 0.5, 1.2, 0.1, tol=1e-11)
    assert np.array_equal(b1.theta[0], r.theta) and np.array_equal(b1.error[0], r.error)


def test_backwards_batch_is_the_scalar_call():
    s = _states(11, seed=8)
    s["gamma"] = np.minimum(s["gamma"], 0.05)  # backwards, damping pumps energy in
    tb = T[::-1].copy()
    b = pendula.taylor(tb, **{k: v for k, v in s.items() if k != "tol"}, tol=s["tol"])
    for i in range(11):
        r = pendula.taylor(tb, *(float(s[k][i]) for k in ("theta0", "omega0", "w0", "gamma")), tol=float(s["tol"][i]))
        assert np.array_equal(b.theta[i], r.theta) and np.array_equal(b.error[i], r.error)


def test_driven_batch_across_blocks_is_the_scalar_call():
    d = pendula.Drive("torque", 0.7, 1.3, 0.4)
    s = _states(11, seed=9)
    b = pendula.taylor(T, s["theta0"], s["omega0"], 1.4, 0.2, tol=1e-10, drive=d)
    for i in range(11):
        r = pendula.taylor(T, float(s["theta0"][i]), float(s["omega0"][i]), 1.4, 0.2, tol=1e-10, drive=d)
        assert np.array_equal(b.theta[i], r.theta) and np.array_equal(b.error[i], r.error)


def test_progress_counts_states_and_a_raised_cancel_flag_stops_every_state():
    from pendula import _fortran
    from pendula._codes import ERR_CANCELLED

    s = _states(13)
    args = [s[k] for k in ("theta0", "omega0", "w0", "gamma", "tol")]
    control = np.zeros(2, dtype=np.int64)
    out = _fortran.taylor_batch_f2py(T, *args, 1e9, 1, control, 0, 0.0, 1.0, 0.0)
    assert int(out[-2]) == OK and control[1] == 13
    control = np.array([1, 0], dtype=np.int64)
    out = _fortran.taylor_batch_f2py(T, *args, 1e9, 2, control, 0, 0.0, 1.0, 0.0)
    assert int(out[-2]) == ERR_CANCELLED and np.all(out[3] == ERR_CANCELLED)
    # a failed state's theta, omega and error: quiet NaN, as every Fortran batch writes them
    assert np.isnan(out[0]).all() and np.isnan(out[1]).all() and np.isnan(out[2]).all()


_PATH_SCRIPT = r"""
import sys
import numpy as np
import pendula
sys.path.insert(0, sys.argv[2])
from test_taylor_lanes import T, _states
s = _states(23, seed=11)
b = pendula.taylor(T, **{k: v for k, v in s.items() if k != "tol"}, tol=s["tol"], threads=1)
np.savez(sys.argv[1], theta=b.theta, omega=b.omega, error=b.error, path=pendula.build_info()["kernel"]["path"])
"""


def test_every_kernel_path_gives_the_scalar_bits(tmp_path):
    s = _states(23, seed=11)
    ref = [
        pendula.taylor(T, *(float(s[k][i]) for k in ("theta0", "omega0", "w0", "gamma")), tol=float(s["tol"][i]))
        for i in range(23)
    ]
    for path in pendula.build_info()["kernel"]["available"]:
        out = tmp_path / f"{path}.npz"
        env = dict(os.environ, PENDULA_KERNEL=path)
        here = os.path.dirname(os.path.abspath(__file__))
        subprocess.run([sys.executable, "-c", _PATH_SCRIPT, str(out), here], env=env, check=True, timeout=120)
        got = np.load(out)
        assert str(got["path"]) == path
        for i, r in enumerate(ref):
            for key in ("theta", "omega", "error"):
                assert np.array_equal(got[key][i], getattr(r, key)), (path, key, i)
