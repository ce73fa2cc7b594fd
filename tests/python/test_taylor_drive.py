"""The Taylor model with a drive (pendula.Drive: a torque F cos(Omega t + phi) or a
vertically driven pivot): against independent references (SciPy's DOP853 at rtol
1e-13 and mpmath's Taylor method at 25 digits), the error estimate bounding the
true error, batches bit-identical to the scalar call."""

import math

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import pendula

W0, GAMMA = 1.3, 0.2


def _rhs(kind, amp, freq, phase):
    if kind == "torque":
        return lambda s, y: [y[1], -GAMMA * y[1] - W0**2 * math.sin(y[0]) + amp * math.cos(freq * s + phase)]
    return lambda s, y: [y[1], -GAMMA * y[1] - (W0**2 + amp * freq**2 * math.cos(freq * s + phase)) * math.sin(y[0])]


def _scipy(t, th0, om0, drive):
    sol = solve_ivp(
        _rhs(drive.kind, drive.amplitude, drive.frequency, drive.phase),
        (t[0], t[-1]),
        [th0, om0],
        method="DOP853",
        t_eval=t,
        rtol=1e-13,
        atol=1e-15,
    )
    return sol.y[0], sol.y[1]


def _error(r, th, om):
    return float(np.max(np.maximum(abs(r.theta - th), abs(r.omega - om) / W0)))


DRIVES = [
    pendula.Drive("torque", 1.2, 0.7, 0.3),
    pendula.Drive("torque", 0.4, 3.0, -1.0),
    pendula.Drive("pivot", 0.3, 2.0, 0.5),
]


@pytest.mark.parametrize("drive", DRIVES, ids=lambda d: f"{d.kind}-{d.frequency}")
@pytest.mark.parametrize("tol", [1e-6, 1e-9])
def test_driven_taylor_against_dop853(drive, tol):
    # a short window: the estimate grows by Gronwall's bound, exp((w0 + gamma) t)
    # (a driven pendulum may be chaotic: no shear model), which is honest but fast
    t = np.linspace(0.0, 4.0, 17)
    r = pendula.taylor(t, 1.0, 0.2, W0, GAMMA, tol=tol, drive=drive)
    th, om = _scipy(t, 1.0, 0.2, drive)
    # DOP853 at rtol 1e-13 is good to ~1e-11 here: far below these tolerances
    assert _error(r, th, om) <= max(r.error.max(), 1e-10)
    assert r.error.max() <= tol


def test_driven_taylor_against_mpmath_at_25_digits():
    d = pendula.Drive("torque", 1.2, 0.7, 0.3)
    t = np.linspace(0.0, 1.5, 4)
    r = pendula.taylor(t, 1.0, 0.2, W0, GAMMA, tol=1e-13, drive=d)
    with mp.workdps(25):
        f = lambda s, y: [
            y[1],
            -mp.mpf(GAMMA) * y[1]
            - mp.mpf(W0) ** 2 * mp.sin(y[0])
            + mp.mpf(d.amplitude) * mp.cos(mp.mpf(d.frequency) * s + mp.mpf(d.phase)),
        ]
        sol = mp.odefun(f, 0, [mp.mpf(1.0), mp.mpf(0.2)])
        ref = [sol(mp.mpf(x)) for x in t]
    err = max(max(abs(float(y[0] - a)), abs(float(y[1] - b)) / W0) for y, a, b in zip(ref, r.theta, r.omega))
    assert err <= r.error.max() <= 1e-13


def test_a_zero_drive_is_the_free_pendulum():
    t = np.linspace(0.0, 20.0, 41)
    free = pendula.taylor(t, 2.0, 0.0, W0, GAMMA, tol=1e-12)
    zero = pendula.taylor(t, 2.0, 0.0, W0, GAMMA, tol=1e-12, drive=pendula.Drive("torque", 0.0, 1.0))
    assert np.max(abs(free.theta - zero.theta)) <= free.error.max() + zero.error.max()


def test_the_drive_phase_is_absolute_time():
    # starting at t0 = 5 with phase phi is the run from 0 with phase phi + 5 Omega, shifted
    d = pendula.Drive("torque", 1.0, 0.9, 0.2)
    t = np.linspace(5.0, 15.0, 11)
    a = pendula.taylor(t, 0.5, 0.0, W0, GAMMA, tol=1e-11, drive=d)
    b = pendula.taylor(t - 5.0, 0.5, 0.0, W0, GAMMA, tol=1e-11, drive=pendula.Drive("torque", 1.0, 0.9, 0.2 + 4.5))
    assert np.max(abs(a.theta - b.theta)) <= a.error.max() + b.error.max()


def test_batch_with_a_drive_is_bit_identical_to_the_scalar_call():
    d = pendula.Drive("pivot", 0.2, 3.0)
    t = np.linspace(0.0, 10.0, 21)
    th0 = np.array([0.3, 1.5, 2.8])
    b = pendula.taylor(t, th0, 0.1, W0, GAMMA, tol=1e-10, drive=d, threads=2)
    for i, x in enumerate(th0):
        r = pendula.taylor(t, float(x), 0.1, W0, GAMMA, tol=1e-10, drive=d)
        assert np.array_equal(b.theta[i], r.theta) and np.array_equal(b.error[i], r.error)
    ev = pendula.taylor(t, th0, 0.1, W0, GAMMA, tol=1e-10, drive=d, events=True)
    assert np.array_equal(ev.theta, b.theta)


def test_drive_must_be_a_drive():
    with pytest.raises(TypeError, match="drive"):
        pendula.taylor([0.0, 1.0], 1.0, 0.0, 1.0, 0.0, drive=(1, 1.0, 1.0))
