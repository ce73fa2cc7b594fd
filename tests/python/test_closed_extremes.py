"""Closed forms at the edges of the double range: no intermediate overflow or
underflow may turn a representable answer into +-inf, NaN or garbage.

References are mpmath at 60 digits from the exact double inputs.  Contract
tested here (also in the docstrings): whenever the true value is a finite
double (|v| <= DBL_MAX) the result is finite and within the stated error;
when the true value is beyond DBL_MAX the result is +-inf of the right sign
(never NaN); values below the normal range come out as gradual underflow
(absolute error a few subnormal ulps) or 0.
"""

import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import pendula

EPS = np.finfo(float).eps
HUGE = np.finfo(float).max
TINY = np.finfo(float).tiny
SUB = 5e-324
mp.mp.dps = 60


def _lin_ref(t, th0, om0, w0, gamma):
    """theta, Omega of theta'' + gamma theta' + w0^2 theta = 0 (text eq. 2.4), in mpmath."""
    t, th0, om0, w0, a = (mp.mpf(x) for x in (t, th0, om0, w0, gamma))
    a = a / 2
    d = a * a - w0 * w0
    if d > 0:
        k = mp.sqrt(d)
        c, s = mp.cosh(k * t), mp.sinh(k * t) / k
    elif d < 0:
        k = mp.sqrt(-d)
        c, s = mp.cos(k * t), mp.sin(k * t) / k
    else:
        c, s = mp.mpf(1), t
    e = mp.exp(-a * t)
    return e * (th0 * c + (om0 + a * th0) * s), e * (om0 * c - (w0 * w0 * th0 + a * om0) * s)


def _env_ref(t, th0, om0, w0, gamma):
    t, th0, om0, w0, a = (mp.mpf(x) for x in (t, th0, om0, w0, gamma))
    a = a / 2
    wd = mp.sqrt(w0 * w0 - a * a)
    return mp.sqrt(th0**2 + ((om0 + a * th0) / wd) ** 2) * mp.exp(-a * t)


# the smallest magnitude that rounds to inf
OVERFLOW = mp.mpf(2) ** 1024 - mp.mpf(2) ** 970


def _check(got, true, scale, tol, what):
    """got (double) against true (mpf); error allowed tol * scale (mpf) + 4 subnormal ulps.

    Within that error of the overflow threshold either a finite value or inf is right."""
    if math.isinf(got) and abs(true) + tol * scale + 4 * SUB >= OVERFLOW and (got > 0) == (true > 0):
        return
    if abs(true) >= OVERFLOW:
        assert math.isinf(got) and (got > 0) == (true > 0), f"{what}: true {mp.nstr(true, 17)} overflows, got {got}"
        return
    assert math.isfinite(got), f"{what}: got {got}, true {mp.nstr(true, 17)} is representable"
    err = abs(mp.mpf(got) - true)
    assert err <= tol * scale + 4 * SUB, (
        f"{what}: got {got!r}, true {mp.nstr(true, 20)}, err/scale {mp.nstr(err / scale, 3)}"
    )


def _check_linear(t, th0, om0, w0, gamma, tol=64 * EPS):
    theta, omega = pendula.linear_damped(t, th0, om0, w0, gamma)
    rth, rom = _lin_ref(t, th0, om0, w0, gamma)
    rate = max(mp.mpf(w0), mp.mpf(gamma))
    # the documented error norm |theta| + |Omega|/max(w0, gamma), times (1 + phase) for the condition
    cond = 1 + rate * mp.mpf(t)
    scale = (abs(rth) + abs(rom) / rate) * cond
    args = f"linear_damped({t!r}, {th0!r}, {om0!r}, {w0!r}, {gamma!r})"
    _check(theta, rth, scale, tol, args + " theta")
    _check(omega, rom, scale * rate, tol, args + " omega")


# ---------------------------------------------------------------- reproducers


def test_small_angle_tiny_w0_is_the_free_motion():
    # w0 t underflows and omega0/w0 overflows: the limit theta0 + omega0 t
    theta, omega = pendula.small_angle(1.5, 1.0, 0.3, 5e-324)
    assert theta == 1.45 and omega == 0.3
    assert pendula.undamped(1.5, 1.0, 0.3, 5e-324) == (theta, omega)


def test_linear_damped_huge_theta0_reproducer():
    theta, omega = pendula.linear_damped(1.5, HUGE, 0.5, 1.4, 0.3)
    assert abs(omega - -1.7570279627426679e308) <= 4 * EPS * 1.7570279627426679e308
    env = pendula.linear_damped_envelope(1.5, HUGE, 0.5, 1.4, 0.3)
    assert abs(env - 1.4437981519278456e308) <= 4 * EPS * 1.4437981519278456e308
    _check_linear(1.5, HUGE, 0.5, 1.4, 0.3)


# ---------------------------------------------------------------- extreme grids

_BIG = (HUGE, -HUGE, 1e308, 1e300, 1e200)
_SMALL = (TINY, 1e-310, SUB, 1e-300)


@pytest.mark.parametrize(
    "th0,om0",
    [(x, 0.5) for x in _BIG + _SMALL]
    + [(1.0, x) for x in _BIG + _SMALL]
    + [(HUGE, -HUGE), (HUGE, HUGE), (SUB, -SUB), (0.0, HUGE)],
)
@pytest.mark.parametrize(
    "w0,gamma",
    [
        (1.4, 0.3),
        (1.4, 2.8),
        (1.4, 2.8 * (1 + 1e-9)),
        (1.4, 1e6),
        (1.4, 0.0),
        (1e300, 1e-300),
        (1e-150, 1e-150),
        (1e-150, 3e-150),
        (1e150, 1e150),
    ],
)
@pytest.mark.parametrize("tau", [0.0, 1e-310, 1e-8, 0.7, 12.0])
def test_linear_damped_extremes(th0, om0, w0, gamma, tau):
    """Every regime at states and rates near overflow, near underflow and subnormal."""
    t = tau / max(w0, gamma)
    _check_linear(t, th0, om0, w0, gamma)


@pytest.mark.parametrize(
    "th0,om0,w0,gamma",
    [
        (HUGE, 0.5, 1.4, 0.3),
        (HUGE, HUGE, 1.4, 0.3),
        (1.0, HUGE, 1e-300, 1e-300),
        (SUB, 1.0, 1.0, 0.5),
        (1.0, 1e300, 1e-10, 1e-12),
        (-HUGE, 1e308, 1e100, 1e100),
    ],
)
@pytest.mark.parametrize("tau", [0.0, 1e-300, 0.5, 30.0])
def test_linear_damped_envelope_extremes(th0, om0, w0, gamma, tau):
    t = tau / max(w0, gamma)
    true = _env_ref(t, th0, om0, w0, gamma)
    _check(
        pendula.linear_damped_envelope(t, th0, om0, w0, gamma),
        true,
        true,
        16 * EPS,
        f"linear_damped_envelope({t!r}, {th0!r}, {om0!r}, {w0!r}, {gamma!r})",
    )


@pytest.mark.parametrize("th0", [1.0, -2.5, 1e-300, SUB, 0.0])
@pytest.mark.parametrize("om0", [0.3, -HUGE, 1e300, SUB, 0.0])
@pytest.mark.parametrize("w0", [SUB, 1e-310, 1e-300, 1.0, 1e300, HUGE])
@pytest.mark.parametrize("tau", [0.0, SUB, 1e-300, 1e-9, 0.8, 40.0])
def test_small_angle_extremes(th0, om0, w0, tau):
    """theta0 cos(w0 t) + (omega0/w0) sin(w0 t) and its rate, |theta0| < pi (no 2 pi N shift)."""
    t = tau / w0 if tau / w0 < HUGE else tau
    theta, omega = pendula.small_angle(t, th0, om0, w0)
    T, TH, OM, W = (mp.mpf(x) for x in (t, th0, om0, w0))
    x = W * T
    rth = TH * mp.cos(x) + OM * (mp.sin(x) / W if x else T)
    rom = -TH * W * mp.sin(x) + OM * mp.cos(x)
    cond = 1 + x
    scale = (abs(TH) + abs(OM) / W) * cond
    args = f"small_angle({t!r}, {th0!r}, {om0!r}, {w0!r})"
    _check(theta, rth, min(scale, abs(TH) + abs(OM * T)) if x < 1e-8 else scale, 16 * EPS, args + " theta")
    _check(omega, rom, (abs(TH) * W + abs(OM)) * cond, 16 * EPS, args + " omega")


@pytest.mark.parametrize("g", [SUB, 1e-310, TINY, 1e-300, 9.8, 1e300, 1e308, HUGE])
@pytest.mark.parametrize("length", [SUB, 1e-310, TINY, 1e-300, 4.9, 1e300, 1e308, HUGE])
def test_natural_frequency_extremes(g, length):
    """sqrt(g/l) for positive finite g, l: nonzero, within 1 ulp (1 subnormal ulp below the
    normal range); ValueError naming g and length when the root itself is beyond DBL_MAX
    (g/l > 2**2048)."""
    _check_natural_frequency(g, length)


def _check_natural_frequency(g, length):
    true = mp.sqrt(mp.mpf(g) / mp.mpf(length))
    if true > HUGE:
        with pytest.raises(ValueError, match=r"\bg\b.*\blength\b"):
            pendula.natural_frequency(g, length)
        return
    w0 = pendula.natural_frequency(g, length)
    assert w0 > 0
    _check(w0, true, true, EPS, f"natural_frequency({g!r}, {length!r})")


# ---------------------------------------------------------------- properties


def _signed_log(lo, hi):
    return st.tuples(st.floats(lo, hi), st.booleans()).map(lambda p: (-1 if p[1] else 1) * 10.0 ** p[0])


def _log(lo, hi):
    return st.floats(lo, hi).map(lambda e: 10.0**e)


@settings(max_examples=400, deadline=None)
# Rates below ~1e-150 are left out, and states whose products with the rates
# (a Omega0, w0^2 theta0) underflow: those lose digits (known, not yet fixed).
@given(
    th0=_signed_log(-323, 308.2),
    om0=_signed_log(-323, 308.2),
    w0=_log(-150, 150),
    gamma=st.one_of(st.just(0.0), _log(-150, 150)),
    tau=_log(-320, 1.3),
)
def test_linear_damped_finite_when_representable(th0, om0, w0, gamma, tau):
    """Wide log-uniform magnitudes: a representable true value gives a finite, accurate result."""
    assume(math.isfinite(th0) and math.isfinite(om0))
    # known gap, not yet fixed: rate^2 theta0 or rate Omega0 below the normal range
    # (w0^2 theta0, a Omega0 underflow in the set-up) costs digits
    rate = max(w0, gamma)
    assume(abs(th0) * rate * rate > 1e-300 and abs(om0) * rate > 1e-300)
    assume(abs(th0) * w0 * w0 > 1e-300 and abs(om0) * w0 > 1e-300)  # w0^2 theta0 itself, not only the larger rate's
    _check_linear(tau / max(w0, gamma), th0, om0, w0, gamma)


@settings(max_examples=400, deadline=None)
@given(th0=_signed_log(-323, 0.4), om0=_signed_log(-323, 308.2), w0=_log(-323, 308.2), tau=_log(-320, 1.3))
def test_small_angle_finite_when_representable(th0, om0, w0, tau):
    assume(math.isfinite(om0) and math.isfinite(w0) and w0 > 0)
    t = tau / w0
    assume(math.isfinite(t))
    theta, omega = pendula.small_angle(t, th0, om0, w0)
    T, TH, OM, W = (mp.mpf(x) for x in (t, th0, om0, w0))
    x = W * T
    rth = TH * mp.cos(x) + OM * mp.sin(x) / W
    rom = -TH * W * mp.sin(x) + OM * mp.cos(x)
    _check(theta, rth, (abs(TH) + abs(OM) * min(T, 1 / W)) * (1 + x), 16 * EPS, "theta")
    _check(omega, rom, (abs(TH) * W + abs(OM)) * (1 + x), 16 * EPS, "omega")


@settings(max_examples=300, deadline=None)
@given(g=_log(-323, 308.2), length=_log(-323, 308.2))
def test_natural_frequency_finite_property(g, length):
    assume(math.isfinite(g) and math.isfinite(length) and g > 0 and length > 0)
    _check_natural_frequency(g, length)
