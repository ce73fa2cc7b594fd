"""Scenes graded against references that share no code with pendula.

Undamped references: mpmath's complete elliptic integral K at 40 digits.
Damped references: mpmath's Taylor-series ODE solver (odefun) at 25 digits,
its events placed by mpmath's findroot on that solution.  Every test asserts
that the true error is <= tol and <= the error the scene reports.
"""

import mpmath as mp
import numpy as np
import pytest

import pendula
from pendula._codes import EVENT_TURNING, EVENT_ZERO


def _damped_reference(theta0, omega0, w0, gamma):
    mp.mp.dps = 25
    w0, gamma = mp.mpf(w0), mp.mpf(gamma)
    return mp.odefun(lambda t, y: [y[1], -gamma * y[1] - w0**2 * mp.sin(y[0])], 0, [mp.mpf(theta0), mp.mpf(omega0)])


def _reference_event_times(f, events):
    """The reference event of each kind nearest each reported one."""
    out = []
    for te, kind in zip(events.t, events.kind):
        if kind == EVENT_TURNING:
            root = mp.findroot(lambda t: f(t)[1], mp.mpf(te))
        else:
            root = mp.findroot(lambda t: mp.sin(f(t)[0] / 2), mp.mpf(te))
        out.append(root)
    return out


@pytest.mark.parametrize("gamma, model", [(11.0, "rk4"), (2.0, "rk4"), (2.0, None)])
def test_event_times_of_heavily_and_critically_damped_scenes(gamma, model):
    """The samples the events are placed on resolve derivatives of order max(w0, gamma)^4, and
    the reported event-time error includes the interpolation between them (w0 = 1 here)."""
    tol = 1.2e-10
    s = pendula.Scene(theta0=1.0, omega0=3.0, t=[3.0], g=9.8, length=9.8, gamma=gamma, want="events", tol=tol)
    assert s.w0 == 1.0
    r = pendula.solve(s, model=model)
    assert r.tol_met and len(r.events.t) >= 1
    f = _damped_reference(1.0, 3.0, 1.0, gamma)
    ref = _reference_event_times(f, r.events)
    dt = max(abs(float(a - b)) for a, b in zip(ref, r.events.t))
    assert dt <= r.event_time_error
    assert dt <= tol  # seconds; w0 = 1, so also in units of 1/w0
    for te, th in zip(ref, r.events.theta):
        assert abs(float(f(te)[0]) - th) <= tol


def test_linear_estimate_is_seamless_across_critical_damping():
    """Just below gamma = 2 w0 the linear model's amplitude R ~ 1/w_d blows up; its estimate
    must not: it stays within a few times its value at and above critical damping, and
    bounds the true error on both sides (w0 = 1)."""
    tol = 1e-8
    t = np.linspace(0.0, 10.0, 6)
    estimates = []
    for gamma in [2 * (1 - 1e-6), 2 * (1 - 1e-16), 2.0, 2 * (1 + 1e-9)]:
        s = pendula.Scene(theta0=1e-3, t=t, g=9.8, length=9.8, gamma=gamma, tol=tol)
        r = pendula.solve(s)
        assert r.model == "linear" and r.tol_met, (gamma, r.reason)
        f = _damped_reference(1e-3, 0.0, 1.0, gamma)
        err = max(max(abs(float(f(ti)[0]) - th), abs(float(f(ti)[1]) - om)) for ti, th, om in zip(t, r.theta, r.omega))
        assert err <= r.error_estimate <= tol, gamma
        estimates.append(r.error_estimate)
    assert max(estimates) <= 10 * min(estimates)


def _libration_quarter(theta0, w0):
    """K(m)/w0 at 40 digits: a quarter period of the swing from rest at theta0."""
    mp.mp.dps = 40
    return mp.ellipk(mp.sin(mp.mpf(theta0) / 2) ** 2) / w0


@pytest.mark.parametrize("model", ["rk4", "cvode"])
def test_run_model_integrators_compute_events_and_refuse_period(model):
    if model == "cvode" and not pendula.have_cvode():
        pytest.skip("no CVODE in this build")
    s = pendula.Scene(theta0=0.3, t=[10.0], g=9.8, length=9.8, want="events", tol=1e-8)
    r = pendula.run_model(s, model, 1e-3 if model == "rk4" else 1e-11)
    q = _libration_quarter(0.3, 1.0)
    # from rest at theta0 > 0: bottom at (2j+1) K, turning points at 2 j K
    expect_t, expect_k = [], []
    for j in range(1, 20):
        tj = float(j * q)
        if tj <= 10.0:
            expect_t.append(tj)
            expect_k.append(EVENT_ZERO if j % 2 else EVENT_TURNING)
    np.testing.assert_array_equal(r.events.kind, expect_k)
    assert np.max(np.abs(r.events.t - expect_t)) <= 1e-7
    with pytest.raises(ValueError, match="period"):
        pendula.run_model(pendula.Scene(theta0=0.3, want="period"), model, 1e-3)


def test_energy_of_an_exact_separatrix_start_meets_tol():
    """E = 2 w0^2 exactly (theta0 = 0, Omega0 = 2 w0, w0 = 1): the conserved energy carries
    only its rounding, not the trajectory's ill-conditioning near the separatrix."""
    s = pendula.Scene(theta0=0.0, omega0=2.0, t=[1.0, 2.0], g=9.8, length=9.8, want="energy", tol=1e-12)
    r = pendula.solve(s)
    assert r.tol_met, r.reason
    assert np.all(r.energy == 2.0)  # the exact value, 2 w0^2
    assert r.error_estimate <= 1e-14


def test_zero_crossings_are_passes_through_the_bottom():
    """A swing about theta = 2 pi passes the bottom at (2j+1) K/w0 (mpmath K, 40 digits), and a
    rotation once per turn; the bound on the number of events counts the turns."""
    tol = 1e-10
    for model in [None, "rk4"]:
        s = pendula.Scene(theta0=2 * np.pi + 0.3, t=[10.0], g=9.8, length=9.8, want="events", tol=tol)
        r = pendula.solve(s, model=model)
        zeros = r.events.t[r.events.kind == EVENT_ZERO]
        q = _libration_quarter(0.3, 1.0)
        expect = [float((2 * j + 1) * q) for j in range(10) if (2 * j + 1) * q <= 10.0]
        assert len(zeros) == len(expect) >= 3, model
        assert np.max(np.abs(zeros - expect)) <= max(r.event_time_error, 1e-12)
        assert np.max(np.abs(zeros - expect)) <= tol
        np.testing.assert_allclose(r.events.theta[r.events.kind == EVENT_ZERO], 2 * np.pi, atol=1e-9)
    # rotation, w0 = 1, Omega0 = 3: a turn takes int_0^{2 pi} dtheta / sqrt(9 - 4 sin^2(theta/2))
    mp.mp.dps = 40
    turn = float(mp.quad(lambda x: 1 / mp.sqrt(9 - 4 * mp.sin(x / 2) ** 2), [0, 2 * mp.pi]))
    s = pendula.Scene(theta0=0.0, omega0=3.0, t=[20.0], g=9.8, length=9.8, want="events", tol=tol)
    r = pendula.solve(s)
    expect = [j * turn for j in range(1, 100) if j * turn <= 20.0]
    assert list(r.events.kind) == [EVENT_ZERO] * len(expect) and len(expect) >= 5
    assert np.max(np.abs(r.events.t - expect)) <= max(r.event_time_error, 1e-12)


@pytest.mark.parametrize(
    "turns, swing, g, length, tend, tol",
    [
        (0, 0.000893261630311742, 1.242, 0.597, 468.98, 2.2e-7),  # grid scene 288's data
        (2, 8.1e-8, 19.263, 1.817, 2.0, 4.3e-7),  # a swing of 1e-7 rad about 4 pi (scene 97)
    ],
)
def test_small_swing_events_meet_tol_when_the_small_angle_times_do_not(turns, swing, g, length, tend, tol):
    """The small-angle state bound meets tol, but an event time's error is that bound over the
    rate w0 |sin theta| ~ w0 swing at a turning point: the solve answers with the exact elliptic
    solution instead.  Reference: from rest, bottom passes at (2j+1) K/w0 and turning points at
    2j K/w0 (mpmath K at 40 digits of the swing as stored)."""
    theta0 = 2 * np.pi * turns + swing
    s = pendula.Scene(theta0=theta0, t=[tend], g=g, length=length, want="events", tol=tol)
    r = pendula.solve(s)
    assert r.model == "exact" and r.tol_met, r.reason
    sa = pendula.run_model(s, "small_angle", None)
    assert sa.event_time_error > tol  # the case this guards: small-angle times miss tol
    mp.mp.dps = 40
    w0 = mp.sqrt(mp.mpf(g) / mp.mpf(length))
    q = _libration_quarter(mp.mpf(theta0) - 2 * turns * mp.pi, w0)  # the swing about the true 2 pi k
    expect_t, expect_k = [], []
    for j in range(1, 100000):
        if j * q > tend:
            break
        expect_t.append(j * q)
        expect_k.append(EVENT_ZERO if j % 2 else EVENT_TURNING)
    assert len(expect_t) >= 3
    np.testing.assert_array_equal(r.events.kind, expect_k)
    err = max(float(abs(mp.mpf(a) - b)) for a, b in zip(r.events.t, expect_t))
    assert err <= r.event_time_error <= tol  # seconds
