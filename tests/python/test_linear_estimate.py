"""The linear model's a priori nonlinearity estimate (src/scene/pendula_scene_estimates.f90:
linear_estimate) against its documented formula evaluated independently with mpmath at 40
digits: the phase-drift sup (underdamped) and the Green's-function bound (over-damped and
critical), whose maxima pendula takes in closed form and the references find by a dense grid
refined by golden-section search.  The estimate is LINEAR_SAFETY (pendula._codes) times the
bound plus a rounding term 16 eps scale (1 + (w0 + gamma) T).

Tolerances: 1e-12 relative (the closed forms round to a few ulps; the references' maxima are
located to ~1e-25 in t, so their values are good to far better than that).
"""

import mpmath as mp
import numpy as np
import pytest

import pendula
from pendula import _codes

EPS = np.finfo(float).eps
SAFETY = _codes.LINEAR_SAFETY  # the Fortran SCENE_LINEAR_SAFETY
REL = 1e-12


def _estimate(theta0, omega0, gamma, tend):
    """The linear model's estimate for w0 = 1 (g = length) over [0, tend]."""
    s = pendula.Scene(theta0, omega0=omega0, t=[tend], g=9.8, length=9.8, gamma=gamma)
    assert s.w0 == 1.0
    return pendula.run_model(s, "linear").error_estimate


def _rounding(theta0, omega0, gamma, tend):
    return 16 * EPS * (abs(theta0) + abs(omega0)) * (1 + (1 + gamma) * tend)


def _sup(f, tend, n=1000):
    """max of f over [0, tend]: the best points of a uniform and a geometric grid, each
    refined by golden-section search between its neighbours (f unimodal there)."""
    tend = mp.mpf(tend)
    grid = sorted(
        set(
            [tend * i / n for i in range(n + 1)]
            + [tend * mp.mpf(10) ** (-12 + 12 * mp.mpf(i) / n) for i in range(n + 1)]
        )
    )
    vals = [f(t) for t in grid]
    best = max(vals)
    order = sorted(range(len(grid)), key=lambda i: -vals[i])[:4]
    invphi = (mp.sqrt(5) - 1) / 2
    for i in order:
        lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
        for _ in range(110):
            c = hi - invphi * (hi - lo)
            d = lo + invphi * (hi - lo)
            if f(c) >= f(d):
                hi = d
            else:
                lo = c
        best = max(best, f(lo), f(hi))
    return best


def _drift_sup(theta0, omega0, gamma, tend):
    """Phase-drift estimate (a): sup over t of R e^(-a t) c min(2, phi(t)) + (R e^(-a t))^3/16,
    phi(t) = R^2 (1 - e^(-gamma t))/(16 w_d gamma) (w0 = 1), and its value on the uniform
    400-point grid that pendula sampled before the sup was taken in closed form."""
    mp.mp.dps = 40
    g = mp.mpf(gamma)
    a = g / 2
    wd = mp.sqrt(1 - a**2)
    r = mp.sqrt(mp.mpf(theta0) ** 2 + ((mp.mpf(omega0) + a * theta0) / wd) ** 2)
    c = max(mp.mpf(1), wd + a)

    def f(t):
        amp = r * mp.exp(-a * t)
        phi = r**2 * (-mp.expm1(-g * t)) / (16 * wd * g) if g > 0 else r**2 * t / (16 * wd)
        return amp * c * min(mp.mpf(2), phi) + amp**3 / 16

    sampled = max(f(mp.mpf(tend) * i / 400) for i in range(401))
    return _sup(f, tend), sampled


def _green_bound(theta0, omega0, gamma, tend):
    """Green's-function estimate (b), over-damped or critical (w0 = 1):
    max|theta_lin|^3/6 max(int_0^T G, 2 max G) with G(s) = e^(-a s) sinh(beta s)/beta."""
    mp.mp.dps = 40
    g = mp.mpf(gamma)
    a = g / 2
    beta = mp.sqrt(a**2 - 1)

    def shc(t):  # sinh(beta t)/beta, t at beta = 0
        return mp.sinh(beta * t) / beta if beta > 0 else t

    def theta(t):
        return mp.exp(-a * t) * (theta0 * mp.cosh(beta * t) + (omega0 + a * theta0) * shc(t))

    def green(t):
        return mp.exp(-a * t) * shc(t)

    b = _sup(lambda t: abs(theta(t)), tend)
    ig = mp.quad(green, [0, min(1 / a, mp.mpf(tend)), tend])
    return b**3 / 6 * max(ig, 2 * _sup(green, tend))


# (theta0, omega0, gamma, tend), w0 = 1, where the drift estimate is the smaller: the sup at
# the cubic's stationary point (most), where the drift saturates (phi reaches 2: gamma 1e-6
# and 1e-3 over long windows), at the window's end (a short window), at t = 0 (damping so
# strong that the drift never outgrows the decay), and where the decay is so fast that 400
# uniform samples straddle the peak (gamma tend ~ 500 .. 4500).
DRIFT_CASES = [
    (0.3, 0.0, 0.01, 200.0),
    (0.3, 0.1, 0.05, 50.0),
    (1.0, 0.0, 1e-6, 1e4),
    (0.05, 0.0, 0.002, 3000.0),
    (0.0, -0.02, 0.13, 3700.0),
    (2e-5, -1e-5, 0.75, 6000.0),
    (0.8, -0.1, 0.43, 1400.0),
    (0.5, 0.2, 0.3, 30.0),
    (0.2, 0.0, 1e-3, 40.0),
    (1.0, 0.0, 1e-3, 5000.0),
    (0.4, 0.0, 1.2, 20.0),
]


@pytest.mark.parametrize("theta0, omega0, gamma, tend", DRIFT_CASES)
def test_underdamped_estimate_is_the_drift_sup(theta0, omega0, gamma, tend):
    """Drift-dominated scenes: the estimate is 1.5 times the sup of the drift formula (never
    below a sample of it: the former 400-point sampling missed up to ~25 % of the sup where
    gamma tend is large)."""
    e = _estimate(theta0, omega0, gamma, tend)
    sup, sampled = _drift_sup(theta0, omega0, gamma, tend)
    rnd = _rounding(theta0, omega0, gamma, tend)
    assert abs(e - (SAFETY * float(sup) + rnd)) <= REL * e, (e, float(sup))
    assert e - rnd >= SAFETY * float(sampled) * (1 - 1e-14)


# (theta0, omega0, gamma/2 - 1, tend): a hump inside the window, one beyond it, none (a
# start moving towards the bottom), an overshoot through the bottom, a start at rest, from
# critical damping exactly to heavy damping.
GREEN_CASES = [
    (0.0, 0.3, 0.0, 10.0),
    (0.2, 0.1, 0.0, 0.3),
    (0.2, -0.1, 0.0, 10.0),
    (0.2, -0.9, 0.0, 10.0),
    (0.4, 0.0, 1e-16, 8.0),
    (0.1, 0.2, 1e-12, 6.0),
    (-0.3, 1.1, 1e-9, 5.0),
    (0.1, 0.2, 1e-6, 6.0),
    (0.3, -0.7, 0.1, 20.0),
    (0.0, 0.5, 2.0, 3.0),
    (0.6, -5.0, 30.0, 200.0),
    (0.0, 40.0, 100.0, 0.05),
]


@pytest.mark.parametrize("theta0, omega0, excess, tend", GREEN_CASES)
def test_overdamped_estimate_is_the_green_bound(theta0, omega0, excess, tend):
    """Over-damped and critical scenes: the estimate is 1.5 times the Green's-function bound
    with max|theta_lin| and max G taken exactly (pendula: at their humps, in closed form)."""
    gamma = 2 * (1 + excess)
    e = _estimate(theta0, omega0, gamma, tend)
    bound = float(_green_bound(theta0, omega0, gamma, tend))
    rnd = _rounding(theta0, omega0, gamma, tend)
    assert abs(e - (SAFETY * bound + rnd)) <= REL * e, (e, bound)


@pytest.mark.parametrize("theta0, omega0", [(1e-3, 0.0), (0.0, 1e-3), (0.3, -0.5), (0.2, 0.1)])
def test_estimate_is_continuous_into_critical_damping_from_above(theta0, omega0):
    """gamma = 2 w0 (1 + delta): the humps' closed forms switch to their series at small
    beta and to the exact critical form at delta = 0; the estimate moves like delta (measured:
    by 1.0 .. 2.1 delta relative here), with no jump at the switches."""
    crit = _estimate(theta0, omega0, 2.0, 7.0)
    for delta in [EPS, 1e-13, 1e-10, 1e-8, 1e-6]:
        e = _estimate(theta0, omega0, 2 * (1 + delta), 7.0)
        assert abs(e - crit) <= (4 * delta + 1e-15) * crit, delta
