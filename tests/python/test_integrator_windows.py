"""Integrators at the edges of their valid input: pure relative tolerance
(cvode atol = 0) and output windows that are tiny, far from t = 0, or wider
than a double can span.

References are independent of CVODE: the exact undamped solution
(pendula.undamped, elliptic functions), the second-order Taylor expansion of
the ODE over a window too short for any higher term to reach a double's
precision, and RK4 at a step 1000x below the one that already meets 1e-10.
"""

import math

import numpy as np
import pytest
from helpers import HAVE_CVODE, needs_cvode

import pendula

W0 = math.sqrt(2.0)


def _normwise(theta, omega, ref_theta, ref_omega, w0):
    """max over t of |error| / |state| in the norm max(|theta|, |Omega|/w0)."""
    err = np.maximum(np.abs(theta - ref_theta), np.abs(omega - ref_omega) / w0)
    size = np.maximum(np.abs(ref_theta), np.abs(ref_omega) / w0)
    return float(np.max(err / size))


@needs_cvode
@pytest.mark.parametrize("method", ["adams", "bdf"])
def test_atol_zero_from_the_texts_start_is_relative(method):
    # theta0 = 0 made CVODE refuse atol = 0 ("Initial ewt has component(s) equal to zero")
    t = np.linspace(0.0, 30.0, 301)
    for rtol in (1e-6, 1e-10):
        res = pendula.cvode(t, 0.0, 2.0, W0, 0.0, rtol=rtol, atol=0.0, method=method)
        th, om = pendula.undamped(t, 0.0, 2.0, W0)
        rel = _normwise(res.theta, res.omega, th, om, W0)
        # a local tolerance is not a global error: measured 36-779 rtol over 30 s
        # (~7 periods); componentwise control with atol = 1e-12 measured 14-571 rtol
        assert rel < 1000 * rtol, (method, rtol, rel)


@needs_cvode
def test_atol_zero_keeps_relative_accuracy_as_the_motion_decays():
    # gamma = 0.5: the state decays by about e**-20 over 80 s.  atol = 0 keeps the
    # error relative to the state; a fixed atol of 1e-10 is the state's own size by the end.
    t = np.array([0.0, 20.0, 40.0, 60.0, 80.0])
    ref = pendula.rk4(t, 0.0, 2.0, W0, 0.5, 1e-4)  # h**4 ~ 1e-16: far below rtol
    check = pendula.rk4(t, 0.0, 2.0, W0, 0.5, 2e-4)
    assert _normwise(check.theta, check.omega, ref.theta, ref.omega, W0) < 1e-11
    rel = pendula.cvode(t, 0.0, 2.0, W0, 0.5, rtol=1e-10, atol=0.0)
    err_rel = [
        _normwise(rel.theta[i : i + 1], rel.omega[i : i + 1], ref.theta[i : i + 1], ref.omega[i : i + 1], W0)
        for i in range(1, t.size)
    ]
    assert max(err_rel) < 1e-7, err_rel
    fixed = pendula.cvode(t, 0.0, 2.0, W0, 0.5, rtol=1e-10, atol=1e-10)
    err_fixed = _normwise(fixed.theta[-1:], fixed.omega[-1:], ref.theta[-1:], ref.omega[-1:], W0)
    assert err_fixed > 100 * err_rel[-1]  # what atol = 0 is for


@needs_cvode
def test_atol_zero_at_rest():
    # the exact solution is zero: weights must stay finite (no NaN from 0 * inf)
    res = pendula.cvode([0.0, 1.0, 2.0], 0.0, 0.0, W0, 0.1, atol=0.0)
    assert np.all(res.theta == 0) and np.all(res.omega == 0)


def _integrators():
    out = [("rk4", lambda t, th0, om0, g: pendula.rk4(t, th0, om0, W0, g, 0.05))]
    if HAVE_CVODE:
        # pure relative control: a state of 1e-300 rad is resolved, not lost below atol
        out.append(("cvode", lambda t, th0, om0, g: pendula.cvode(t, th0, om0, W0, g, rtol=1e-10, atol=0.0)))
    return out


@pytest.mark.parametrize("name,run", _integrators(), ids=[n for n, _ in _integrators()])
@pytest.mark.parametrize("span", [1e-300, 5e-324, 1e-170, 1e-30, 1e-20, 2.0**-64, 1e-12])
def test_tiny_windows(name, run, span):
    # Over a window this short theta = theta0 + Omega0 s - a s**2/2, Omega = Omega0 + a s,
    # a = -(gamma Omega0 + w0**2 sin theta0); the next terms are below a double's resolution.
    gamma = 0.1
    for th0, om0 in ((0.0, 2.0), (1.0, 0.0)):
        res = run([0.0, span], th0, om0, gamma)
        a = -(gamma * om0 + W0**2 * math.sin(th0))
        th_ref = th0 + om0 * span + a * span * span / 2
        om_ref = om0 + a * span
        assert res.theta[0] == th0 and res.omega[0] == om0
        # RK4 is exact to rounding here; CVODE to its tolerance
        tol = 4 * np.spacing(abs(th_ref)) if name == "rk4" else 1e-9 * abs(th_ref)
        assert abs(res.theta[1] - th_ref) <= tol + 1e-323, (name, span, res.theta)
        # Omega0 = 0: Omega(s) = a s itself, to the integrator's relative tolerance
        tol = 1e-7 * abs(om_ref) if om0 == 0 else 4 * np.spacing(abs(om_ref))
        assert abs(res.omega[1] - om_ref) <= tol + 1e-323, (name, span, res.omega)


@pytest.mark.parametrize("name,run", _integrators(), ids=[n for n, _ in _integrators()])
@pytest.mark.parametrize("t0", [1.0, 1e10, -3e5])
def test_windows_of_one_ulp_far_from_zero(name, run, t0):
    # t(1) = 1 and t(2) one ulp later: CVODE refused (CV_TOO_CLOSE) because it
    # measured the window against |t|; the ODE is autonomous, so only t - t(1) matters.
    t = np.array([t0, np.nextafter(t0, np.inf), np.nextafter(np.nextafter(t0, np.inf), np.inf)])
    res = run(t, 0.0, 2.0, 0.1)
    s = t - t[0]
    a = -0.1 * 2.0  # Omega'(t(1)); the next Taylor terms are below 2e-11 relative here
    assert np.allclose(res.theta, 2.0 * s + a * s * s / 2, rtol=1e-10, atol=0)
    assert np.allclose(res.omega, 2.0 + a * s, rtol=1e-10, atol=0)


@needs_cvode
def test_events_keep_their_times_with_a_shifted_origin():
    # events are located in CVODE's shifted time and returned in the user's
    t = np.linspace(100.0, 130.0, 7)
    a = pendula.cvode(t, 0.3, 0.0, W0, 0.0, rtol=1e-11, atol=1e-13, events=True)
    b = pendula.cvode(t - 100.0, 0.3, 0.0, W0, 0.0, rtol=1e-11, atol=1e-13, events=True)
    assert a.events.t.size == b.events.t.size > 10
    assert np.allclose(a.events.t - 100.0, b.events.t, rtol=0, atol=1e-12)
    assert np.all((a.events.t > 100.0) & (a.events.t <= 130.0))


@pytest.mark.parametrize("name,run", _integrators(), ids=[n for n, _ in _integrators()])
def test_window_wider_than_a_double_is_refused_naming_t(name, run):
    with pytest.raises(ValueError, match=r"\bt\b"):
        run([-1e308, 1e308], 0.1, 0.0, 0.1)
