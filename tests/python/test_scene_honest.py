"""Scenes report what they achieved: the event times are inside the estimate and tol_met, the
integrators count events as scenes do, and the model choice is graded against references
that share no code with pendula (mpmath at 40 digits)."""

import mpmath as mp
import numpy as np
import pytest

import pendula
from pendula._codes import EVENT_TURNING, EVENT_ZERO


def _turn_time(omega0, w0):
    """Time of one turn of the undamped rotation from theta = 0 at Omega0 (mpmath, 40 digits)."""
    mp.mp.dps = 40
    w0 = mp.mpf(w0)
    return mp.quad(lambda x: 1 / mp.sqrt(mp.mpf(omega0) ** 2 - 4 * w0**2 * mp.sin(x / 2) ** 2), [0, mp.pi, 2 * mp.pi])


def test_cvode_events_count_every_pass_through_the_bottom():
    """cvode(events=True) uses the scenes' definition: a rotation crosses theta = 0 mod 2 pi once
    per turn (before, only the unwrapped theta = 0 at the start counted, i.e. none)."""
    if not pendula.have_cvode():
        pytest.skip("no CVODE in this build")
    turn = _turn_time(3.0, 1.0)
    r = pendula.cvode([0.0, 20.0], 0.0, 3.0, 1.0, 0.0, rtol=1e-11, atol=1e-13, events=True)
    expect = [float(j * turn) for j in range(1, 100) if j * turn <= 20.0]
    assert len(expect) >= 8
    assert list(r.events.kind) == [EVENT_ZERO] * len(expect)
    assert np.max(np.abs(r.events.t - expect)) <= 1e-8
    np.testing.assert_allclose(r.events.theta, 2 * np.pi * np.arange(1, len(expect) + 1), atol=1e-8)
    # a swing about theta = -2 pi: its passes through the bottom are at -2 pi
    r = pendula.cvode([0.0, 10.0], -2 * np.pi + 0.3, 0.0, 1.0, 0.0, rtol=1e-11, atol=1e-13, events=True)
    zeros = r.events.kind == EVENT_ZERO
    assert np.count_nonzero(zeros) >= 3
    np.testing.assert_allclose(r.events.theta[zeros], -2 * np.pi, atol=1e-8)


@pytest.mark.parametrize(
    "theta0, gamma, tol",
    [(3.0, 0.0, 1e-10), (3.0, 0.01, 1e-10), (np.pi - 1e-6, 0.0, 1e-9), (np.pi - 1e-6, 0.0, 1e-4), (2.5, 0.01, 1e-12)],
)
def test_events_fold_the_event_time_error_into_the_estimate(theta0, gamma, tol):
    """want = events: tol bounds the event times [s]; error_estimate covers event_time_error and
    tol_met is error_estimate <= tol.  Turning points near the top (here at 2K, 4K with
    K ~ 15.9 s) are slow, so their times carry most of the error."""
    s = pendula.Scene(theta0=theta0, t=[70.0], g=9.8, length=9.8, gamma=gamma, want="events", tol=tol)
    r = pendula.solve(s)
    assert r.error_estimate >= r.event_time_error > 0
    assert r.tol_met == (r.error_estimate <= tol)
    if not r.tol_met:
        assert "tol NOT met" in r.reason
    if gamma == 0:
        # turning points at 2 j K(m)/w0, m = sin^2(theta0/2), w0 = 1
        mp.mp.dps = 40
        k = mp.ellipk(mp.sin(mp.mpf(theta0) / 2) ** 2)
        turning = r.events.t[r.events.kind == EVENT_TURNING]
        expect = [float(2 * j * k) for j in range(1, len(turning) + 1)]
        assert len(turning) >= 1 and 2 * (len(turning) + 1) * k > 70
        assert np.max(np.abs(turning - expect)) <= r.event_time_error


def test_events_near_the_top_report_tol_not_met_when_the_times_are_not_within_it():
    # the exact solution places turning points at the top by its phase (a few
    # 1e-13 s here, checked against mpmath above): a tol below that is not met
    s = pendula.Scene(theta0=np.pi - 1e-6, t=[70.0], g=9.8, length=9.8, want="events", tol=1e-14)
    r = pendula.solve(s)
    assert r.event_time_error > 1e-14 and not r.tol_met
    assert "tol NOT met" in r.reason


def test_a_scene_beyond_the_budget_is_refused_up_front():
    """1e10 s at tol 1e-10 with gamma = 1e-7: the part before the hand-over alone (some 1e8
    periods) is beyond the budget for every integrator (at gamma = 1e-6 the Taylor series now
    answers in ~4e7 steps).  The refusal is the prediction's ("needs"), not a run that spent
    the budget ("used the whole step budget")."""
    if not pendula.have_cvode():
        pytest.skip("no CVODE in this build")
    with pytest.raises(pendula.PendulaSolverError, match="needs .* steps") as info:
        pendula.solve(pendula.Scene(1.0, t=[0, 1e10], gamma=1e-7, tol=1e-10))
    assert "max_steps" in str(info.value) and "used the whole" not in str(info.value)


def test_a_swing_near_the_top_at_a_tol_below_rk4_and_cvode_floors_is_met():
    """A swing to 3 rad at tol 1.6e-12: below RK4's predicted rounding and CVODE's rtol floor,
    the Taylor series answers in one run, with tol met and the true error (mpmath's Taylor
    solver at 25 digits, w0 = 1) within its estimate."""
    tol = 1.6e-12
    s = pendula.Scene(theta0=3.0, t=np.linspace(0.0, 9.0, 5), g=9.8, length=9.8, gamma=0.02, tol=tol)
    r = pendula.solve(s)
    assert r.model == "taylor" and r.tol_met and r.cost["runs"] == 1, r.reason
    mp.mp.dps = 25
    f = mp.odefun(lambda t, y: [y[1], -mp.mpf(0.02) * y[1] - mp.sin(y[0])], 0, [mp.mpf(3.0), 0])
    err = max(max(abs(float(f(ti)[0]) - th), abs(float(f(ti)[1]) - om)) for ti, th, om in zip(s.t, r.theta, r.omega))
    assert err <= r.error_estimate <= tol


@pytest.mark.parametrize(
    "theta0, tol, model", [(1e-4, 1e-8, "small_angle"), (1e-2, 1e-8, "exact"), (0.0, 1e-12, "small_angle")]
)
def test_period_prefers_small_angle_when_its_error_fits(theta0, tol, model):
    """want = period: 2 pi/w0 is answered whenever its phase error w0 |T - T0| fits tol (mpmath
    K at 40 digits: T = 4 K(m)/w0, m = sin^2(theta0/2)); the exact period otherwise."""
    s = pendula.Scene(theta0=theta0, want="period", g=9.8, length=9.8, tol=tol)
    r = pendula.solve(s)
    assert r.model == model and r.tol_met, r.reason
    mp.mp.dps = 40
    true = abs(float(4 * mp.ellipk(mp.sin(mp.mpf(theta0) / 2) ** 2) - mp.mpf(r.period)))
    assert true <= r.error_estimate <= tol


@pytest.mark.parametrize("theta0, omega0", [(1.0, 0.0), (3.0, 0.0), (np.pi - 1e-6, 0.0), (0.0, 3.0)])
def test_period_estimate_is_a_phase(theta0, omega0):
    """The exact period's estimate is w0 |dT| [rad] over one period (T = 4 K(m)/w0 for a swing,
    2 K(1/m)/(w0 sqrt(m)) per turn of a rotation; mpmath at 40 digits, g/l = 2.3 so that w0 is
    rounded), not a relative error: it bounds the true phase error."""
    s = pendula.Scene(theta0=theta0, omega0=omega0, want="period", g=2.3, length=1.0, tol=1e-30)
    r = pendula.solve(s)
    assert r.model == "exact"
    mp.mp.dps = 40
    w0 = mp.sqrt(mp.mpf(2.3))
    m = mp.sin(mp.mpf(theta0) / 2) ** 2 + (mp.mpf(omega0) / (2 * w0)) ** 2
    true_t = 4 * mp.ellipk(m) / w0 if m < 1 else 2 * mp.ellipk(1 / m) / (w0 * mp.sqrt(m))
    assert float(w0 * abs(mp.mpf(r.period) - true_t)) <= r.error_estimate <= 1e-11
    assert r.error_estimate >= 16 * np.finfo(float).eps * float(w0 * true_t)
