"""Scenes near the separatrix take the energy of the data as given.

w0 = fl(sqrt(g/l)) is off by up to half an ulp; near the separatrix 1 - m is
so ill-conditioned in w0 that this half-ulp decided libration against
rotation (errors of radians with estimates of 1e-13, and T = +inf for a
rotation of T = 27.79 s).  The reference takes g and l exactly as given (as
doubles) and evaluates the pendulum with mpmath at 40 digits (scene_grid's
DLMF 22 formulas, independent of pendula's elliptic code).
"""

import mpmath as mp
import numpy as np
import pytest
from scene_grid import mp_undamped

import pendula

DATA = [(9.8, 4.9), (9.81, 1.7), (3.7, 0.3)]
# (theta0, relative offset of Omega0 from the separatrix's 2 w0 cos(theta0/2), computed in doubles)
STARTS = [(0.0, 0.0), (0.0, 1e-16), (0.0, -1e-16), (0.7, 0.0), (2.0, 3e-16), (-1.0, -2e-16)]


def _exact_w0(g, length):
    with mp.workdps(40):
        return mp.sqrt(mp.mpf(g) / mp.mpf(length))


@pytest.mark.parametrize("g,length", DATA)
@pytest.mark.parametrize("theta0,offset", STARTS)
def test_state_near_separatrix_uses_the_data_as_given(g, length, theta0, offset):
    w0 = float(np.sqrt(g / length))
    omega0 = 2 * w0 * np.cos(theta0 / 2) * (1 + offset)
    t = np.linspace(0, 30 * 2 * np.pi / w0, 61)
    tol = 1e-6
    res = pendula.solve(pendula.Scene(theta0=theta0, omega0=omega0, t=t, g=g, length=length, tol=tol))
    th, om = mp_undamped(t, theta0, omega0, _exact_w0(g, length), dps=40)
    err = max(np.max(np.abs(res.theta - th)), np.max(np.abs(res.omega - om)) / w0)
    assert res.tol_met
    assert err <= tol
    assert err <= res.error_estimate


def test_separatrix_of_the_rounded_w0_is_a_rotation_of_the_data():
    # Omega0 = -2 fl(sqrt 2): fl(sqrt 2) > sqrt 2, so |Omega0| > 2 sqrt(g/l) and the
    # pendulum goes over the top, once every 27.79 s (mpmath: 2 K(1/m)/(k w0))
    w0 = float(np.sqrt(2.0))
    res = pendula.solve(pendula.Scene(theta0=0.0, omega0=-2 * w0, want="period", tol=1e-10))
    with mp.workdps(40):
        w = _exact_w0(9.8, 4.9)
        m = (mp.mpf(-2 * w0) / (2 * w)) ** 2
        ref = float(2 * mp.ellipk(1 / m) / (mp.sqrt(m) * w))
    assert abs(ref - 27.790154467309035) < 1e-12
    err = abs(res.period - ref)
    assert err <= 1e-10 * ref
    assert err <= res.error_estimate * ref + 4 * np.finfo(float).eps * ref


def test_w0_residual_is_the_rounding_of_the_root():
    # the residual the scene carries is sqrt(g/l) - w0 to ~eps^2 w0 (mpmath at 40 digits)
    for g, length in DATA + [(2.5, 2.5), (1e-200, 3e-5), (7e250, 0.2)]:
        s = pendula.Scene(theta0=0.1, t=1.0, g=g, length=length)
        with mp.workdps(40):
            ref = float(_exact_w0(g, length) - mp.mpf(s.w0))
        assert abs(s._w0lo - ref) <= 1e-30 * s.w0 + 1e-3 * abs(ref)
    # g/l beyond the double-double's safe range (exponents past 900): no residual
    assert pendula.Scene(theta0=0.1, t=1.0, g=1e-300, length=3e-5)._w0lo == 0.0
