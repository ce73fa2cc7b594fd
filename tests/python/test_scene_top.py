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

import pendula
from pendula._codes import EVENT_TURNING, EVENT_ZERO
from scene_grid import mp_undamped

DPS = 90
# starts at the top: fl(k pi) for odd k, a few ulps off it, and plainly off it
TOPS = [np.pi, 3 * np.pi, -5 * np.pi, np.pi - 1e-8, np.pi + 3e-12]
DATA = [(9.8, 9.8), (3.432, 5.917)]     # w0 = 1 exactly; w0 rounded (its residual matters)


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
        e_ref = w ** 2 * (1 - mp.cos(mp.mpf(theta0)))
        eerr = max(float(abs(mp.mpf(e) - e_ref) / w ** 2) for e in np.atleast_1d(en.energy))
    assert en.tol_met and eerr <= en.error_estimate
