"""Scenes that start at or a few ulps from an unstable equilibrium (theta0 = fl(k pi), k odd).

The data as given is exact: theta0 = fl(pi) is pi - 1.2246e-16, a libration
whose turning points sit 1.2e-16 rad below the top, reached every 2 K(m)/w0
with 1 - m ~ 4e-33.  The references take theta0, Omega0, g and l exactly as
doubles and evaluate the pendulum with mpmath at 90 digits (the DLMF 22
formulas of scene_grid, independent of pendula's elliptic code; 1 - m needs
the digits).  Errors are in the scenes' measure max(|d theta|, |d Omega|/w0)
[rad], event times in s.
"""

import mpmath as mp
import numpy as np
import pytest
from scene_grid import mp_undamped

import pendula
from pendula._codes import EVENT_TURNING, EVENT_ZERO

DPS = 90
# starts at the top: fl(k pi) for odd k, a few ulps off it, and plainly off it
TOPS = [np.pi, 3 * np.pi, -5 * np.pi, np.pi - 1e-8, np.pi + 3e-12]
DATA = [(9.8, 9.8), (3.432, 5.917)]  # w0 = 1 exactly; w0 rounded (its residual matters)


def _w0(g, length):
    with mp.workdps(DPS):
        return mp.sqrt(mp.mpf(g) / mp.mpf(length))


def _half_period_and_quarter(theta0, w):
    """(2 K(m)/w0, K(m)/w0) as mpf for a start at rest, m = sin^2(theta_r/2)."""
    with mp.workdps(DPS):
        th = mp.mpf(theta0)
        r = th - 2 * mp.pi * mp.nint(th / (2 * mp.pi))
        k = mp.ellipk(mp.sin(r / 2) ** 2)
        return 2 * k / w, k / w


@pytest.mark.parametrize("g,length", DATA)
@pytest.mark.parametrize("theta0", TOPS)
def test_undamped_state_from_the_top_is_exact_with_an_honest_estimate(theta0, g, length):
    w = _w0(g, length)
    t = np.linspace(0.0, 300.0, 41)
    tol = 1e-9
    res = pendula.solve(pendula.Scene(theta0=theta0, t=t, g=g, length=length, tol=tol))
    th, om = mp_undamped(t, theta0, 0.0, w, dps=DPS)
    err = max(np.max(np.abs(res.theta - th)), np.max(np.abs(res.omega - om)) / float(w))
    assert res.model == "exact" and res.tol_met
    # the estimate is the rounding of the exact solution (~1e-12 here), not radians
    assert err <= res.error_estimate <= tol


@pytest.mark.parametrize("g,length", DATA)
@pytest.mark.parametrize("theta0", TOPS)
def test_undamped_events_from_the_top_sit_at_the_phases_k_k(theta0, g, length):
    """Zero crossings at (2j+1) K/w0, turning points (at the top) at 2j K/w0:
    their times are off by the phase error, not by the state error over a
    vanishing speed (the estimate was ~1e17 s)."""
    w = _w0(g, length)
    tol = 1e-9
    res = pendula.solve(pendula.Scene(theta0=theta0, t=[300.0], g=g, length=length, tol=tol, want="events"))
    half, quarter = _half_period_and_quarter(theta0, w)
    ev = res.events
    assert len(ev.t) >= 3
    with mp.workdps(DPS):
        expect = []
        for j in range(len(ev.t)):
            # quarter, 2 quarters, 3 quarters, ...: zero, turning, zero, turning
            expect.append(quarter * (j + 1))
        kinds = [EVENT_ZERO if j % 2 == 0 else EVENT_TURNING for j in range(len(ev.t))]
        err = max(float(abs(mp.mpf(a) - b)) for a, b in zip(ev.t, expect))
    assert list(ev.kind) == kinds
    assert float(quarter * (len(ev.t) + 1)) > 300.0
    assert res.tol_met
    assert err <= res.event_time_error <= tol
    assert half > 0


@pytest.mark.parametrize("theta0", TOPS)
def test_undamped_period_and_energy_from_the_top(theta0):
    g, length = DATA[1]
    w = _w0(g, length)
    per = pendula.solve(pendula.Scene(theta0=theta0, t=[1.0], g=g, length=length, tol=1e-9, want="period"))
    half, _ = _half_period_and_quarter(theta0, w)
    with mp.workdps(DPS):
        perr = float(w * abs(mp.mpf(per.period) - 2 * half))
    assert per.tol_met and perr <= per.error_estimate <= 1e-9
    t = np.linspace(0.0, 50.0, 6)
    en = pendula.solve(pendula.Scene(theta0=theta0, t=t, g=g, length=length, tol=1e-12, want="energy"))
    with mp.workdps(DPS):
        e_ref = w**2 * (1 - mp.cos(mp.mpf(theta0)))
        eerr = max(float(abs(mp.mpf(e) - e_ref) / w**2) for e in np.atleast_1d(en.energy))
    assert en.tol_met and eerr <= en.error_estimate


# --- damped: the hang integrated in top-centred coordinates -------------------------------

W0 = 1.0  # g = l = 9.8
DAMPED = [
    (np.pi, 0.0, 0.5),
    (3 * np.pi, 0.0, 3.0),
    (-5 * np.pi, 0.0, 1.2),
    (np.pi - 1e-8, 0.0, 0.5),
    (np.pi + 3e-12, 0.0, 2.0),
    (np.pi, 2e-11, 0.3),
]


def _top_reference(t, theta0, omega0, gamma, rtol):
    """theta, Omega at t and the events, by SciPy's DOP853 in phi = k pi - theta (phi0 from
    mpmath: the exact distance of the double theta0 to k pi), back to theta in mpmath."""
    from scipy.integrate import solve_ivp

    k = int(round(theta0 / np.pi))
    with mp.workdps(40):
        kpi = k * mp.pi
        phi0 = float(kpi - mp.mpf(theta0))

    def rhs(_, y):
        return [y[1], -gamma * y[1] + W0**2 * np.sin(y[0])]

    def bottom(_, y):  # theta = 2 pi j  <=>  phi = pi mod 2 pi (k odd)
        return np.sin((y[0] - np.pi) / 2)

    def turning(_, y):
        return y[1]

    sol = solve_ivp(
        rhs,
        (0, t[-1]),
        [phi0, -omega0],
        method="DOP853",
        t_eval=t,
        rtol=rtol,
        atol=1e-40,
        first_step=1e-3,
        events=[bottom, turning],
    )
    assert sol.success
    with mp.workdps(40):
        th = np.array([float(kpi - mp.mpf(x)) for x in sol.y[0]])
    ev = sorted(
        [(x, EVENT_ZERO) for x in sol.t_events[0] if x > 0] + [(x, EVENT_TURNING) for x in sol.t_events[1] if x > 0]
    )
    return th, -sol.y[1], ev


@pytest.mark.parametrize("theta0,omega0,gamma", DAMPED)
@pytest.mark.parametrize("want", ["state", "final", "energy"])
def test_damped_start_at_the_top_is_accurate_and_honest(theta0, omega0, gamma, want):
    t = np.linspace(0.0, 60.0, 121)
    tol = 1e-8
    res = pendula.solve(
        pendula.Scene(
            theta0=theta0,
            omega0=omega0,
            t=t if want != "final" else 60.0,
            g=9.8,
            length=9.8,
            gamma=gamma,
            tol=tol,
            want=want,
        )
    )
    _assert_honest_top(res, t, theta0, omega0, gamma, tol, want)


def _assert_honest_top(res, t, theta0, omega0, gamma, tol, want):
    # res answers from the top, within tol, its true error (against the reference, itself
    # checked by a run 100x looser) within its estimate
    th, om, _ = _top_reference(t, theta0, omega0, gamma, 1e-13)
    th2, om2, _ = _top_reference(t, theta0, omega0, gamma, 1e-11)
    assert max(np.max(np.abs(th - th2)), np.max(np.abs(om - om2))) <= tol / 20
    if want == "final":
        err = max(abs(res.theta[-1] - th[-1]), abs(res.omega[-1] - om[-1]))
    elif want == "energy":
        err = np.max(np.abs(res.energy - (om**2 / 2 + W0**2 * (1 - np.cos(th)))))
    else:
        err = max(np.max(np.abs(res.theta - th)), np.max(np.abs(res.omega - om)))
    assert "from a top" in res.reason and res.tol_met
    assert err <= res.error_estimate <= tol
    print(
        f"theta0={theta0!r} gamma={gamma} want={want}: err {err:.2e} estimate {res.error_estimate:.2e} "
        f"steps {res.cost['steps']}"
    )


@pytest.mark.parametrize("theta0,omega0,gamma", DAMPED)
def test_damped_events_from_the_top(theta0, omega0, gamma):
    tol = 1e-7
    res = pendula.solve(
        pendula.Scene(theta0=theta0, omega0=omega0, t=[40.0], g=9.8, length=9.8, gamma=gamma, tol=tol, want="events")
    )
    _, _, ev = _top_reference(np.array([40.0]), theta0, omega0, gamma, 1e-13)
    assert list(res.events.kind) == [k for _, k in ev]
    err = max((abs(a - b) for a, (b, _) in zip(res.events.t, ev)), default=0.0)
    assert "from a top" in res.reason and res.tol_met
    assert err <= res.event_time_error <= tol


def test_top_start_in_theta_loses_what_phi_keeps():
    # the same scene forced to CVODE in theta: the hang is not resolved (the
    # start's 1.2e-16 rad is rounding there), and it says so
    s = pendula.Scene(theta0=np.pi, t=np.linspace(0, 60, 61), g=9.8, length=9.8, gamma=0.5, tol=1e-8)
    top = pendula.solve(s)
    th, _, _ = _top_reference(np.linspace(0, 60, 61), np.pi, 0.0, 0.5, 1e-13)
    assert np.max(np.abs(top.theta - th)) <= top.error_estimate <= 1e-8


# --- overdamped hangs: the step follows the growing mode, the check halves every interval ---------


def _lp_lm(gamma):
    """The saddle's rates at w0 = W0: lp > 0 (growing), lm < 0 (decaying)."""
    lm = -(gamma / 2 + np.hypot(gamma / 2, W0))
    return W0**2 / -lm, lm


@pytest.mark.parametrize(
    "theta0,gamma,tend,tol",
    [(np.pi, 6.0, 5.0, 1e-9), (np.pi - 1e-3, 5.0, 8.0, 1e-5), (-3 * np.pi + 2e-4, 12.0, 30.0, 1e-7)],
)
@pytest.mark.parametrize("spacing", [0.15, 1.0])
def test_overdamped_hang_step_from_the_growing_rate_and_honest(theta0, gamma, tend, tol, spacing):
    """Overdamped (gamma > 2 w0), the motion about the top is a e^(lp t) + b e^(lm t) with
    -lm >> lp: the step is sized by lp and bounded by 1/(-lm) for the check run's stability
    (it was ~1/(-lm) times a fourth root of the target, 50x smaller than a fixed step meeting
    tol).  Outputs 0.15 s apart are denser than that step: the check at 2h must still halve
    the substeps on every interval, else both runs take one substep there, agree exactly
    and the estimate is the rounding alone (it was 7e-16 for an error of 1.7e-10)."""
    t = np.arange(0.0, tend + spacing / 2, spacing)
    res = pendula.solve(pendula.Scene(theta0=theta0, t=t, g=9.8, length=9.8, gamma=gamma, tol=tol))
    th, om, _ = _top_reference(t, theta0, 0.0, gamma, 1e-13)
    th2, om2, _ = _top_reference(t, theta0, 0.0, gamma, 1e-11)
    assert max(np.max(np.abs(th - th2)), np.max(np.abs(om - om2))) <= tol / 20
    err = max(np.max(np.abs(res.theta - th)), np.max(np.abs(res.omega - om)))
    assert "from a top" in res.reason and res.tol_met
    assert err <= res.error_estimate <= tol
    lp, lm = _lp_lm(gamma)
    # the hang's step: at most 1/(-lm) (stability of the run at 2h), and not
    # pinned below it by the decaying rate: here >= 1/4 of that bound
    assert 0.25 / -lm <= res.step <= 1 / -lm * (1 + 1e-12)
    print(
        f"theta0={theta0!r} gamma={gamma} spacing={spacing}: err {err:.2e} estimate "
        f"{res.error_estimate:.2e} step {res.step:.3g} (1/lp {1 / lp:.3g}) steps {res.cost['steps']}"
    )


@pytest.mark.parametrize("theta0,gamma", [(np.pi, 0.05), (-3 * np.pi + 1e-9, 0.02), (np.pi - 2e-5, 0.1)])
@pytest.mark.parametrize("want", ["state", "energy"])
def test_light_damping_after_the_hang_is_honest(theta0, gamma, want):
    """Light damping brings the motion back near the top ~sqrt(4 gamma/w0) below the separatrix,
    which amplifies an error of the state handed over across the flow; the part along it (most of
    the hang's RK4 error: a shift in time) is carried without that factor.  Both must stay inside
    the estimate over several returns."""
    t = np.linspace(0.0, 40.0, 81)
    tol = 1e-7
    res = pendula.solve(pendula.Scene(theta0=theta0, t=t, g=9.8, length=9.8, gamma=gamma, tol=tol, want=want))
    _assert_honest_top(res, t, theta0, 0.0, gamma, tol, want)


@pytest.mark.parametrize("theta0,gamma", [(np.pi, 0.5), (-5 * np.pi, 2.0), (np.pi - 1e-8, 0.5)])
def test_damped_hang_in_closed_form_is_honest_at_tight_tol(theta0, gamma):
    """Deep in the hang the linear motion about the top answers in closed form
    (its nonlinearity bounded by |phi|**3/6): outputs inside that stretch, in
    the RK4 stretch after it and past the hand-over stay within the estimate."""
    t = np.linspace(0.0, 60.0, 241)
    tol = 2e-9  # the DOP853 reference is good to ~5e-11 here
    res = pendula.solve(pendula.Scene(theta0=theta0, t=t, g=9.8, length=9.8, gamma=gamma, tol=tol))
    assert "from a top: closed form to t = " in res.reason
    _assert_honest_top(res, t, theta0, 0.0, gamma, tol, "state")
