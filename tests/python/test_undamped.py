"""The undamped pendulum in closed form: accuracy, invariants, special cases, API.

References are INDEPENDENT of the library: mpmath at 60 digits from the exact
double inputs (tools/gen/gen_undamped_reference.py, whose closed form is
cross-checked there against a direct Taylor integration of the ODE), the
text's own expressions (1.52) and (1.66) evaluated in mpmath, and invariants
(energy, time reversal, turning points).
"""

import math

import mpmath as mp
import numpy as np
import pytest
from helpers import load_generator

import pendula

ref = load_generator("gen_undamped_reference")  # the mpmath references and their table
EPS = np.finfo(float).eps
# Tests that use states many turns from the bottom on purpose (2 pi N shifts,
# reduction of huge angles): the degrees warning is expected there, not tested.
LARGE_ANGLES = pytest.mark.filterwarnings("ignore::pendula.AngleWarning")
REGIME_CODES = {1: "libration", 2: "separatrix", 3: "rotation"}


@pytest.fixture(scope="module")
def table():
    return ref.read_table()


def _ratios(got, want, cond):
    # |error| / (eps * cond), with a floor of one eps*|want| (the output's own rounding)
    return np.abs(got - want) / (EPS * (cond + np.abs(want)) + 1e-300)


# ---------------------------------------------------------------- accuracy
def test_reference_table_cond_scaled(table):
    """12048 (state, t): 6000 libration + 6000 rotation with |1 - m| in 1e-15..1e2, 48 exact
    separatrix; t over +-100 periods.  |dtheta|, |domega| <= 16 eps cond (+ eps |ref|)."""
    d = table
    th, om = pendula.undamped(d["t"], d["theta0"], d["omega0"], d["w0"])
    rt = _ratios(th, d["theta"], d["cond_theta"])
    ro = _ratios(om, d["omega"], d["cond_omega"])
    lines = []
    for code, name in REGIME_CODES.items():
        s = d["regime"] == code
        lines.append(f"{name}: n={s.sum()} worst err/(eps cond) theta {rt[s].max():.3g} omega {ro[s].max():.3g}")
    print("\n".join(lines))
    assert set(np.unique(d["regime"])) == {1.0, 2.0, 3.0}
    gap = np.abs(d["one_minus_m"][d["regime"] != 2])
    assert gap.min() < 2e-15 and gap.max() > 50  # the table covers the specified range
    assert rt.max() <= 16, lines
    assert ro.max() <= 16, lines


def test_reference_table_one_state_path(table):
    """The same rows through the one-state/many-times path (Jacobi plan from 32 times on,
    blocked, vectorised atan): each state's times are tiled to >= 32 points."""
    d = table
    keys = np.stack([d["theta0"], d["omega0"], d["w0"]], axis=1)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    th = np.empty_like(d["t"])
    om = np.empty_like(d["t"])
    for g, i in enumerate(first):
        rows = np.nonzero(inverse.reshape(-1) == g)[0]
        tt = np.tile(d["t"][rows], 32 // len(rows) + 1)
        a, b = pendula.undamped(tt, d["theta0"][i], d["omega0"][i], d["w0"][i])
        th[rows], om[rows] = a[: len(rows)], b[: len(rows)]
        assert np.array_equal(a[len(rows) : 2 * len(rows)], a[: len(rows)])
    assert _ratios(th, d["theta"], d["cond_theta"]).max() <= 16
    assert _ratios(om, d["omega"], d["cond_omega"]).max() <= 16
    assert np.abs(th - d["theta"]).max() <= 1e-11


def test_reference_table_plain_figures(table):
    """Absolute error over 100 periods: the target is <= 1e-11 rad for |1 - m| >= 1e-6.
    Because 1 - m is computed from double-double cos(theta0/2) and Omega0/(2 w0), the
    same holds down to |1 - m| = 1e-15 (measured worst ~8e-13 rad)."""
    d = table
    th, om = pendula.undamped(d["t"], d["theta0"], d["omega0"], d["w0"])
    err = np.abs(th - d["theta"])
    far = np.abs(d["one_minus_m"]) >= 1e-6
    assert err[far].max() <= 1e-11
    assert err.max() <= 1e-11
    # omega in rad/s scales with w0 (up to 10 1/s here)
    assert np.max(np.abs(om - d["omega"]) / d["w0"]) <= 1e-11


def test_live_mpmath_random_states():
    """A fresh random subset computed here (not from the table), all three regimes."""
    rng = np.random.default_rng(4)
    worst = 0.0
    for i in range(24):
        regime = 1 if i % 2 == 0 else 3
        theta0, omega0, w0 = ref.random_state(rng, regime, rng.uniform(-14, 0 if regime == 1 else 2))
        with mp.workdps(ref.DPS):
            per = float(ref.State(theta0, omega0, w0).period)
        times = ref.sample_times(rng, per, 3)
        rows, st = ref.reference(theta0, omega0, w0, times)
        th, om = pendula.undamped(np.array(times), theta0, omega0, w0)
        for j, (tr, orf, ct, co) in enumerate(rows):
            worst = max(
                worst,
                abs(th[j] - float(tr)) / (EPS * (float(ct) + abs(float(tr)))),
                abs(om[j] - float(orf)) / (EPS * (float(co) + abs(float(orf))) + 1e-300),
            )
    assert worst <= 16


def test_slow_hug_of_the_top():
    """theta0 = pi - 1e-10, Omega0 = 0: m = 1 - 2.5e-21; T = 4 K(m)/w0 vs mpmath to 1e-12."""
    theta0 = math.pi - 1e-10
    for w0 in (1.0, math.sqrt(2.0), 0.37):
        T = pendula.period(theta0, 0.0, w0)
        with mp.workdps(60):
            m = mp.sin(mp.mpf(theta0) / 2) ** 2
            T_ref = 4 * mp.ellipk(m) / mp.mpf(w0)
        assert abs(T / float(T_ref) - 1) <= 1e-12
        # it hugs the top for most of the half period, then swings through the bottom
        th, om = pendula.undamped(np.array([0.05, 0.25, 0.5, 0.75, 1.0]) * T, theta0, 0.0, w0)
        assert th[0] > math.pi - 1e-7  # still near the top at T/20
        assert abs(th[1]) < 1e-9 and om[1] < -1.99 * w0  # bottom at T/4, full speed 2 w0
        assert abs(th[2] + theta0) < 1e-9  # -theta0 at T/2
        assert abs(th[3]) < 1e-9 and om[3] > 1.99 * w0
        assert abs(th[4] - theta0) < 1e-9  # back after one period
        # and against mpmath over 10 periods
        times = list(np.linspace(-10 * T, 10 * T, 23))
        rows, _ = ref.reference(theta0, 0.0, w0, times)
        th, om = pendula.undamped(np.array(times), theta0, 0.0, w0)
        assert np.max(np.abs(th - [float(r[0]) for r in rows])) <= 1e-12
        assert np.max(np.abs(om - [float(r[1]) for r in rows])) <= 1e-12 * w0
    # the exact double pi itself: 1 - m = cos(pi_double/2)^2 = 3.7e-33, still libration
    m, mc = pendula.elliptic_parameter(math.pi, 0.0)
    assert pendula.regime(math.pi) == "libration"
    assert abs(mc / 3.749399456654644e-33 - 1) < 1e-14


# ---------------------------------------------------------------- the text's special cases
@pytest.mark.parametrize(
    "theta0", [0.01 * math.pi, 0.1 * math.pi, 0.25 * math.pi, 0.5 * math.pi, 0.75 * math.pi, 0.9 * math.pi]
)
def test_eq_1_52_omega0_zero(theta0):
    """Omega0 = 0: theta = 2 asin{ sin(theta0/2) sn[K(k^2) - w0 t, k^2] } (eq. 1.52)."""
    w0 = math.sqrt(2.0)  # the text's g = 9.8, l = 4.9
    t = np.linspace(0, 20, 41)
    th, _ = pendula.undamped(t, theta0, 0.0, w0)
    with mp.workdps(40):
        k = mp.sin(mp.mpf(theta0) / 2)
        K = mp.ellipk(k**2)
        want = [float(2 * mp.asin(k * mp.ellipfun("sn", K - mp.mpf(w0) * mp.mpf(x), m=k**2))) for x in t]
    assert np.max(np.abs(th - want)) <= 16 * EPS * (1 + np.max(np.abs(t)) * 2 * w0)


@pytest.mark.parametrize("ratio", [1.0 / 2, 1.5 / 2, 1.9 / 2, 1.999 / 2])
def test_eq_1_66_theta0_zero(ratio):
    """theta0 = 0, v0 = l Omega0 <= 2 sqrt(g l): theta = 2 asin{ sin(theta_max/2) sn[w0 t, k^2] }
    with sin(theta_max/2) = v0/(2 w0 l) (eqs 1.57, 1.66; the text's fig 9 speeds)."""
    w0, length = math.sqrt(2.0), 4.9
    v0 = 2 * ratio * w0 * length
    omega0 = v0 / length
    t = np.linspace(-10, 30, 81)
    th, om = pendula.undamped(t, 0.0, omega0, w0)
    with mp.workdps(40):
        k = mp.mpf(omega0) / (2 * mp.mpf(w0))
        want = [float(2 * mp.asin(k * mp.ellipfun("sn", mp.mpf(w0) * mp.mpf(x), m=k**2))) for x in t]
        want_om = [float(2 * k * mp.mpf(w0) * mp.ellipfun("cn", mp.mpf(w0) * mp.mpf(x), m=k**2)) for x in t]
    assert np.max(np.abs(th - want)) <= 16 * EPS * (1 + 30 * 2 * w0) * 10
    assert np.max(np.abs(om - want_om)) <= 16 * EPS * (1 + 30 * 2 * w0) * 10 * w0
    amp = pendula.amplitude(0.0, omega0, w0)
    with mp.workdps(40):
        amp_ref = 2 * mp.asin(mp.mpf(omega0) / (2 * mp.mpf(w0)))  # eq. 1.60 at the exact inputs
    assert abs(amp - float(amp_ref)) <= 4 * EPS


def test_separatrix_exact_and_overflow_free():
    """theta0 = 0, Omega0 = 2 w0: m == 1 exactly; theta = 4 atan(tanh(w0 t/2)), any t."""
    for w0 in (1.0, 0.25, 3.0):
        assert pendula.regime(0.0, 2 * w0, w0) == "separatrix"
        assert pendula.period(0.0, 2 * w0, w0) == math.inf
        assert pendula.amplitude(0.0, 2 * w0, w0) == math.pi
        t = np.array([-1e308, -1e5, -30.0, -1.0, 0.0, 0.5, 2.0, 40.0, 1e5, 1e308])
        th, om = pendula.undamped(t, 0.0, 2 * w0, w0)
        assert np.all(np.isfinite(th)) and np.all(np.isfinite(om))
        with mp.workdps(30):
            want = [float(4 * mp.atan(mp.tanh(mp.mpf(w0) * mp.mpf(x) / 2))) for x in t]
            want_om = [float(2 * mp.mpf(w0) * mp.sech(mp.mpf(w0) * mp.mpf(x))) for x in t]
        assert np.max(np.abs(th - want)) <= 4 * EPS * math.pi
        assert np.max(np.abs(om - want_om)) <= 4 * EPS * 2 * w0
        th2, om2 = pendula.undamped(t, 0.0, -2 * w0, w0)
        assert np.array_equal(th2, -th) and np.array_equal(om2, -om)


# ---------------------------------------------------------------- invariants
def _states(rng, n):
    out = []
    for i in range(n):
        regime = 1 if i % 2 == 0 else 3
        out.append(ref.random_state(rng, regime, rng.uniform(-12, 0 if regime == 1 else 2)))
    return out


@LARGE_ANGLES
def test_energy_is_constant():
    """E(theta(t), Omega(t)) = E(theta0, Omega0) over 100 periods to a few eps, beyond the
    unavoidable part from rounding theta and Omega to doubles (a rotating pendulum's
    theta reaches hundreds of rad, whose ulp alone moves E by w0^2 |sin theta| ulp(theta))."""
    rng = np.random.default_rng(11)
    worst = 0.0
    for theta0, omega0, w0 in _states(rng, 60):
        T = pendula.period(theta0, omega0, w0)
        t = np.sort(rng.uniform(-100 * T, 100 * T, 50))
        th, om = pendula.undamped(t, theta0, omega0, w0)
        e = pendula.energy(th, om, w0)
        e0 = pendula.energy(theta0, omega0, w0)
        rounding = w0**2 * np.abs(np.sin(th) * th) + om**2 + e0  # |dE/dx x| over theta, Omega
        worst = max(worst, np.max(np.abs(e - e0) / (EPS * rounding)))
    print(f"worst energy drift: {worst:.3g} eps x (E + |theta dE/dtheta| + |Omega dE/dOmega|)")
    assert worst <= 8


def test_energy_api():
    w0 = 1.7
    assert pendula.energy(0.0, 0.0, w0) == 0.0
    assert abs(pendula.energy(math.pi, 0.0, w0) - 2 * w0**2) <= 2 * EPS * 2 * w0**2  # separatrix energy
    th, om = 0.3, -0.8
    assert abs(pendula.energy(th, om, w0) - (om**2 / 2 + w0**2 * (1 - math.cos(th)))) <= 4 * EPS
    # tiny angles: no cancellation in 1 - cos
    assert abs(pendula.energy(1e-10, 0.0, 1.0) / 5e-21 - 1) <= 4 * EPS
    m, mc = pendula.elliptic_parameter(th, om, w0)
    assert abs(2 * w0**2 * m / pendula.energy(th, om, w0) - 1) <= 4 * EPS
    assert abs(m + mc - 1) <= 4 * EPS


@LARGE_ANGLES
def test_time_reversal_and_mirror():
    """theta(-t; theta0, Omega0) = theta(t; theta0, -Omega0), Omega flips; and
    theta(t; -theta0, -Omega0) = -theta(t; theta0, Omega0)."""
    rng = np.random.default_rng(12)
    for theta0, omega0, w0 in _states(rng, 40):
        T = pendula.period(theta0, omega0, w0)
        t = rng.uniform(-50 * T, 50 * T, 20)
        a, ao = pendula.undamped(-t, theta0, omega0, w0)
        b, bo = pendula.undamped(t, theta0, -omega0, w0)
        np.testing.assert_allclose(a, b, rtol=2 * EPS, atol=2 * EPS)
        np.testing.assert_allclose(ao, -bo, rtol=2 * EPS, atol=2 * EPS * w0)
        c, co = pendula.undamped(t, -theta0, -omega0, w0)
        d, do = pendula.undamped(t, theta0, omega0, w0)
        np.testing.assert_allclose(c, -d, rtol=2 * EPS, atol=2 * EPS)
        np.testing.assert_allclose(co, -do, rtol=2 * EPS, atol=2 * EPS * w0)


def test_initial_state_is_returned():
    rng = np.random.default_rng(13)
    for theta0, omega0, w0 in _states(rng, 200):
        th, om = pendula.undamped(0.0, theta0, omega0, w0)
        assert abs(th - theta0) <= 2 * EPS * max(abs(theta0), 1)
        assert abs(om - omega0) <= 4 * EPS * max(abs(omega0), w0)


@LARGE_ANGLES
def test_period_is_time_between_turning_points():
    """Libration: Omega = 0 at the turning points; successive ones on the same side are T apart.
    Rotation: theta(t + T) - theta(t) = 2 pi s exactly one turn."""
    from scipy.optimize import brentq

    rng = np.random.default_rng(14)
    for theta0, omega0, w0 in _states(rng, 30):
        T = pendula.period(theta0, omega0, w0)
        if pendula.regime(theta0, omega0, w0) == "libration":
            omega = lambda t: pendula.undamped(t, theta0, omega0, w0)[1]  # noqa: E731
            grid = np.linspace(0, 2.2 * T, 800)
            o = pendula.undamped(grid, theta0, omega0, w0)[1]
            idx = np.nonzero(np.sign(o[:-1]) * np.sign(o[1:]) < 0)[0]
            zeros = [brentq(omega, grid[i], grid[i + 1], xtol=1e-15 * T, rtol=4 * EPS) for i in idx]
            assert len(zeros) >= 4
            assert abs((zeros[2] - zeros[0]) / T - 1) <= 1e-11
            assert abs((zeros[1] - zeros[0]) / T - 0.5) <= 1e-11
            th = pendula.undamped(np.array(zeros), theta0, omega0, w0)[0]
            amp = pendula.amplitude(theta0, omega0, w0)
            centre = 2 * math.pi * round(theta0 / (2 * math.pi))
            np.testing.assert_allclose(np.abs(th - centre), amp, rtol=1e-10)
        else:
            t = rng.uniform(-20 * T, 20 * T, 10)
            a = pendula.undamped(t, theta0, omega0, w0)[0]
            b = pendula.undamped(t + T, theta0, omega0, w0)[0]
            np.testing.assert_allclose(
                b - a, 2 * math.pi * math.copysign(1, omega0), rtol=0, atol=64 * EPS * (np.max(np.abs(a)) + 10)
            )


@LARGE_ANGLES
def test_period_api_and_regimes():
    w0 = math.sqrt(2.0)
    assert pendula.period(0.0, 0.0, w0) == pytest.approx(2 * math.pi / w0, rel=1e-15)  # small-angle limit
    T = pendula.period(np.array([0.1, 1.0, 2.0]), 0.0, w0)
    with mp.workdps(30):
        want = [float(4 * mp.ellipk(mp.sin(mp.mpf(x) / 2) ** 2) / mp.mpf(w0)) for x in (0.1, 1.0, 2.0)]
    np.testing.assert_allclose(T, want, rtol=4 * EPS)  # eq. 1.53
    # the same energy reached from (theta0, Omega0) has the same period
    th0 = 1.0
    m, _ = pendula.elliptic_parameter(th0, 0.0, w0)
    om0 = 2 * w0 * math.sqrt(m - math.sin(0.4) ** 2)
    assert pendula.period(0.8, om0, w0) == pytest.approx(pendula.period(th0, 0.0, w0), rel=1e-13)
    # rotation: one turn takes 2 K(1/m)/(k w0)
    with mp.workdps(30):
        k = mp.mpf(5.0) / (2 * mp.mpf(w0))
        want = float(2 * mp.ellipk(1 / k**2) / (k * mp.mpf(w0)))
    assert pendula.period(0.0, 5.0, w0) == pytest.approx(want, rel=4 * EPS)
    assert list(pendula.regime(0.0, np.array([1.0, 2 * w0, 4.0]), w0)) == ["libration", "separatrix", "rotation"]
    assert pendula.amplitude(0.0, 4.0, w0) == math.inf
    assert pendula.amplitude(1.0, 0.0, w0) == pytest.approx(1.0, rel=2 * EPS)
    assert pendula.amplitude(7.0, 0.0, w0) == pytest.approx(abs(7.0 - 2 * math.pi), rel=1e-14)


def test_rotation_counts_turns():
    w0 = 1.0
    T = pendula.period(0.0, 3.0, w0)
    th, _ = pendula.undamped(np.arange(0, 101) * T, 0.0, 3.0, w0)
    np.testing.assert_allclose(th, 2 * math.pi * np.arange(0, 101), rtol=0, atol=1e-12)
    th, _ = pendula.undamped(np.arange(0, 101) * T, 0.0, -3.0, w0)
    np.testing.assert_allclose(th, -2 * math.pi * np.arange(0, 101), rtol=0, atol=1e-12)
    # theta0 several turns away: results continuous with theta0
    th, om = pendula.undamped(np.array([0.0, 1e-3]), 4 * math.pi + 0.3, 0.2, w0)
    assert abs(th[0] - (4 * math.pi + 0.3)) <= 2 * EPS * 13 and abs(th[1] - th[0]) < 1e-3


def test_huge_times_finite_and_within_cond():
    """t far beyond 100 periods (up to 1e308): finite, in range, and within 16 eps cond where
    mpmath can still say something (t = 1e12, 1e15)."""
    for theta0, omega0, w0 in [(0.5, 0.1, 3.0), (0.0, 7.0, 3.0), (math.pi - 1e-10, 0.0, 1.0), (0.3, -2.0000001, 1.0)]:
        times = [1e12, -1e15]
        rows, _ = ref.reference(theta0, omega0, w0, times)
        th, om = pendula.undamped(np.array(times), theta0, omega0, w0)
        for j, (tr, orf, ct, co) in enumerate(rows):
            assert abs(th[j] - float(tr)) <= 16 * EPS * (float(ct) + abs(float(tr)))
            assert abs(om[j] - float(orf)) <= 16 * EPS * (float(co) + abs(float(orf)))
        big = np.array([1e20, -1e20, 1e300, 1e308, -1e308])
        th, om = pendula.undamped(big, theta0, omega0, w0)
        if pendula.regime(theta0, omega0, w0) == "rotation":
            # theta ~ 2 pi t/T itself exceeds the double range at |t| = 1e308: +-inf, signed right
            T = pendula.period(theta0, omega0, w0)
            fits = np.abs(big) < 1e308 / (2 * math.pi / T)
            assert np.all(np.isfinite(th[fits])) and np.all(np.sign(th[~fits]) == np.sign(big[~fits]))
        else:
            assert np.all(np.isfinite(th))
        assert np.all(np.isfinite(om))
        assert np.all(np.abs(om) <= 2 * math.sqrt(pendula.elliptic_parameter(theta0, omega0, w0)[0]) * w0 * (1 + 1e-15))
        ths, oms = pendula.small_angle(big, theta0, omega0, w0)
        assert np.all(np.isfinite(ths)) and np.all(np.isfinite(oms))


# ---------------------------------------------------------------- small-angle model and its bound
@LARGE_ANGLES
def test_small_angle_formula():
    t = np.linspace(-5, 5, 11)
    th, om = pendula.small_angle(t, 0.2, -0.3, 1.5)
    np.testing.assert_allclose(th, 0.2 * np.cos(1.5 * t) + (-0.3 / 1.5) * np.sin(1.5 * t), rtol=0, atol=4 * EPS)
    np.testing.assert_allclose(om, -0.2 * 1.5 * np.sin(1.5 * t) - 0.3 * np.cos(1.5 * t), rtol=0, atol=4 * EPS)
    # about the nearest stable equilibrium 2 pi N
    th2, _ = pendula.small_angle(t, 0.2 + 2 * math.pi, -0.3, 1.5)
    np.testing.assert_allclose(th2 - 2 * math.pi, th, rtol=0, atol=16 * EPS)
    # and it agrees with the exact motion for tiny amplitudes
    ex, _ = pendula.undamped(t, 1e-6, 0.0, 1.5)
    sa, _ = pendula.small_angle(t, 1e-6, 0.0, 1.5)
    np.testing.assert_allclose(sa, ex, rtol=0, atol=1e-18 * 2)


def test_small_angle_bound_holds_and_is_tight():
    """Over random librating states: max_{|t|<=tmax} |small_angle - undamped| <= bound(tmax),
    for theta and Omega, and the bound is within a modest factor of the truth."""
    rng = np.random.default_rng(21)
    looseness = []
    for _ in range(150):
        m = 10.0 ** rng.uniform(-8, -0.05)
        f = rng.uniform()
        theta0 = 2 * math.asin(math.sqrt(f * m)) * rng.choice([-1, 1])
        w0 = 10.0 ** rng.uniform(-1, 1)
        omega0 = 2 * w0 * math.sqrt((1 - f) * m) * rng.choice([-1, 1])
        T0 = 2 * math.pi / w0
        tmax = T0 * 10.0 ** rng.uniform(-1, 2.5)
        t = np.linspace(-tmax, tmax, 4001)
        ex, exo = pendula.undamped(t, theta0, omega0, w0)
        sa, sao = pendula.small_angle(t, theta0, omega0, w0)
        bt, bo = pendula.small_angle_error(tmax, theta0, omega0, w0)
        err_t, err_o = np.max(np.abs(sa - ex)), np.max(np.abs(sao - exo))
        assert err_t <= bt, (theta0, omega0, w0, tmax, err_t, bt)
        assert err_o <= bo, (theta0, omega0, w0, tmax, err_o, bo)
        looseness.append(bt / err_t)
    print(f"bound / true max error: median {np.median(looseness):.3g}, max {np.max(looseness):.3g}")
    assert np.median(looseness) < 2.5
    # the bound grows with tmax and reflects the phase drift m/4 w0 t
    b = pendula.small_angle_error(np.array([1.0, 10.0, 100.0, 1000.0]), 0.1, 0.0, 1.0)[0]
    assert np.all(np.diff(b) >= 0)
    assert b[-1] == pytest.approx(
        2 * 0.1 * math.sin(min(math.pi, (1 - math.pi / (2 * float(mp.ellipk(math.sin(0.05) ** 2)))) * 1000) / 2),
        rel=0.05,
    )


def test_small_angle_bound_outside_libration_and_at_rest():
    assert pendula.small_angle_error(1.0, 0.0, 3.0, 1.0) == (math.inf, math.inf)
    assert pendula.small_angle_error(1.0, 0.0, 2.0, 1.0) == (math.inf, math.inf)
    assert pendula.small_angle_error(1e6, 0.0, 0.0, 1.0) == (0.0, 0.0)


@pytest.mark.parametrize(
    "theta0, omega0", [(1e-146, 1e-146), (1e-160, 0.0), (-1e-200, 3e-201), (0.0, 1e-250), (1e-310, 0.0), (5e-324, 0.0)]
)
def test_small_angle_bound_holds_for_tiny_states(theta0, omega0):
    """States whose m = k^2 is lost to the subnormal range: the model and the exact motion
    still differ by their roundings, and the bound (once 0 there) covers them, within a few
    hundred times the truth."""
    w0, tmax = 1.3, 10.0
    t = np.linspace(-tmax, tmax, 4001)
    ex, exo = pendula.undamped(t, theta0, omega0, w0)
    sa, sao = pendula.small_angle(t, theta0, omega0, w0)
    bt, bo = pendula.small_angle_error(tmax, theta0, omega0, w0)
    err_t, err_o = np.max(np.abs(sa - ex)), np.max(np.abs(sao - exo))
    assert 0 < err_t <= bt and 0 < err_o <= bo, (err_t, bt, err_o, bo)
    assert bt <= 1000 * max(err_t, 5e-324) and bo <= 1000 * max(err_o, 5e-324)


def test_fourier_series_of_the_angle():
    """The bound rests on theta = 8 sum q^(n+1/2)/((2n+1)(1+q^(2n+1))) sin((2n+1) pi u/(2K))."""
    with mp.workdps(30):
        for m in (mp.mpf("0.01"), mp.mpf("0.5"), mp.mpf("0.99")):
            K, q = mp.ellipk(m), mp.qfrom(m=m)
            for u in (mp.mpf("0.3"), mp.mpf("1.7")):
                lhs = 2 * mp.asin(mp.sqrt(m) * mp.ellipfun("sn", u, m=m))
                rhs = 8 * mp.nsum(
                    lambda n: (
                        q ** (n + 0.5)
                        / ((2 * n + 1) * (1 + q ** (2 * n + 1)))
                        * mp.sin((2 * n + 1) * mp.pi * u / (2 * K))
                    ),
                    [0, mp.inf],
                )
                assert abs(lhs - rhs) < mp.mpf("1e-25")


# ---------------------------------------------------------------- equilibria
def test_equilibria():
    n = np.arange(-3, 5)
    w0 = 1.3
    theta, lam, kind = pendula.equilibria(n, w0)
    np.testing.assert_allclose(theta, n * math.pi, rtol=EPS)
    assert list(kind) == ["saddle" if k % 2 else "centre" for k in n]
    for k, l2 in zip(n, lam):
        jac = np.array([[0.0, 1.0], [-(w0**2) * math.cos(k * math.pi), 0.0]])
        want = np.sort_complex(np.linalg.eigvals(jac))
        np.testing.assert_allclose(np.sort_complex(l2), want, atol=1e-15)
    t0, l0, k0 = pendula.equilibria(0, w0)
    assert t0 == 0.0 and k0 == "centre" and l0[0] == 1.3j and l0[1] == -1.3j
    t1, l1, k1 = pendula.equilibria(1, w0)
    assert t1 == math.pi and k1 == "saddle" and l1[0] == 1.3 and l1[1] == -1.3
    # an equilibrium start stays put
    th, om = pendula.undamped(np.array([0.0, 5.0, 1e6]), 0.0, 0.0, w0)
    assert np.all(th == 0.0) and np.all(om == 0.0)
    with pytest.raises(TypeError):
        pendula.equilibria(0.5, w0)
    with pytest.raises(ValueError, match="w0"):
        pendula.equilibria(1, -1.0)


# ---------------------------------------------------------------- many states at once
def _mixed_states(n=3000, seed=11):
    """Random libration and rotation states (|theta0| up to 20 rad), Omega0 = 0, states within
    1e-3..1e-15 of the separatrix on both sides, the exact separatrix, huge theta0."""
    rng = np.random.default_rng(seed)
    th = rng.uniform(-20, 20, n)
    w0 = rng.uniform(0.2, 3.2, n)
    om = rng.uniform(-3, 3, n)
    om[: n // 4] = 0.0
    near = slice(n // 4, n // 2)
    gap = 10.0 ** rng.uniform(-15, -3, n // 4) * rng.choice([-1.0, 1.0], n // 4)
    om[near] = 2 * w0[near] * np.cos(np.remainder(th[near] + np.pi, 2 * np.pi) / 2 - np.pi / 2) * (1 + gap)
    th = np.concatenate([th, [0.0, 0.0, 1e20, -3e15]])
    om = np.concatenate([om, [2.0, -1.0, 0.3, -0.7]])
    w0 = np.concatenate([w0, [1.0, 0.5, 1.2, 2.0]])
    return th, om, w0


@LARGE_ANGLES
def test_state_properties_over_arrays_equal_scalar_calls():
    """period, amplitude, elliptic_parameter, regime and undamped over arrays are, element by
    element and bit for bit, the scalar calls (one kernel; no vectorised libm inside it); the
    properties agree with each other: separatrix states have infinite period."""
    th, om, w0 = _mixed_states()
    per, amp = pendula.period(th, om, w0), pendula.amplitude(th, om, w0)
    m, mc = pendula.elliptic_parameter(th, om, w0)
    reg = pendula.regime(th, om, w0)
    assert set(reg) == {"libration", "separatrix", "rotation"}
    for i in range(0, len(th), 7):
        args = (float(th[i]), float(om[i]), float(w0[i]))
        assert per[i] == pendula.period(*args) and amp[i] == pendula.amplitude(*args)
        assert (m[i], mc[i]) == pendula.elliptic_parameter(*args) and reg[i] == pendula.regime(*args)
    assert np.all(np.isinf(per[reg == "separatrix"])) and np.all(np.isfinite(per[reg != "separatrix"]))
    assert np.array_equal(reg == "libration", mc > 0) and np.array_equal(reg == "rotation", mc < 0)
    # the rotation's amplitude is +inf, the libration's below pi
    assert np.all(amp[reg == "rotation"] == np.inf) and np.all(amp[reg == "libration"] <= np.pi)
    # scalars are passed to the kernel as one value for every state: the same numbers
    assert np.array_equal(
        pendula.period(th, 0.25, 1.3), pendula.period(th, np.full_like(th, 0.25), np.full_like(th, 1.3))
    )
    a = pendula.undamped(2.5, th, om, 1.3)
    b = pendula.undamped(np.full_like(th, 2.5), th, om, np.full_like(th, 1.3))
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    # undamped: a scalar call, or one state at a few times (< 32: no plan), is the same
    # evaluation as the element of the many-state call, bit for bit
    t = np.random.default_rng(5).uniform(-300, 300, len(th))
    a = pendula.undamped(t, th, om, w0)
    for i in range(0, len(th), 7):
        assert pendula.undamped(float(t[i]), float(th[i]), float(om[i]), float(w0[i])) == (a[0][i], a[1][i])
    few = pendula.undamped(t[:20], float(th[3]), float(om[3]), float(w0[3]))
    both = pendula.undamped(t[:20], np.full(20, th[3]), om[3], w0[3])
    assert np.array_equal(few[0], both[0]) and np.array_equal(few[1], both[1])
    # broadcasting: a 2-D grid of theta0 x Omega0 equals the flat call
    g = pendula.period(th[:40, None], om[None, :30], 1.3)
    assert np.array_equal(g, pendula.period(np.repeat(th[:40], 30), np.tile(om[:30], 40), 1.3).reshape(40, 30))


def test_reference_table_many_states_in_runs(table):
    """The reference rows through the many-state path with every state repeated in a run of
    40 consecutive elements (the run gets a Jacobi plan, decided in Fortran; the table's own
    rows, a few per state, take light motions in test_reference_table_cond_scaled): 16 eps cond."""
    d = table
    idx = np.arange(len(d["t"]))
    reps = 40
    # each row's state 40 times in a row, at the row's time
    tt = np.repeat(d["t"][:, None], reps, axis=1)
    th, om = pendula.undamped(tt, d["theta0"][:, None], d["omega0"][:, None], d["w0"][:, None])
    assert th.shape == (len(idx), reps)
    assert _ratios(th[:, 0], d["theta"], d["cond_theta"]).max() <= 16
    assert _ratios(om[:, 0], d["omega"], d["cond_omega"]).max() <= 16
    assert np.all(th == th[:, :1]) and np.all(om == om[:, :1])


# ---------------------------------------------------------------- API: broadcasting, scalars, bad input
def test_broadcasting_and_scalars():
    th, om = pendula.undamped(1.0, 0.5, 0.1, 2.0)
    assert isinstance(th, float) and isinstance(om, float)
    t = np.array([3.0, -1.0, 0.5, -7.5])  # unsorted, negative
    th, om = pendula.undamped(t[:, None], np.array([0.1, 2.0, 3.1]), 0.0, 1.0)
    assert th.shape == (4, 3) and om.shape == (4, 3)
    for j, theta0 in enumerate([0.1, 2.0, 3.1]):
        for i, ti in enumerate(t):
            a, b = pendula.undamped(float(ti), theta0, 0.0, 1.0)
            assert th[i, j] == a and om[i, j] == b
    p = pendula.period([[0.1], [1.0]], [0.0, 1.0, 3.0], 1.0)
    assert p.shape == (2, 3)
    assert isinstance(pendula.regime(0.1), str)
    assert pendula.regime([[0.1, 0.2]]).shape == (1, 2)
    e = pendula.small_angle_error([1.0, 2.0], 0.1)
    assert e[0].shape == (2,)
    x = np.array([0.1, 0.2])
    x0 = x.copy()
    pendula.undamped(x, x, x, 1.0)
    assert np.array_equal(x, x0)


@pytest.mark.parametrize(
    "fn,args,name",
    [
        (pendula.undamped, (1.0, math.nan, 0.0, 1.0), "theta0"),
        (pendula.undamped, (1.0, 0.1, math.inf, 1.0), "omega0"),
        (pendula.undamped, (1.0, 0.1, 0.0, 0.0), "w0"),
        (pendula.undamped, (1.0, 0.1, 0.0, -2.0), "w0"),
        (pendula.undamped, (np.array([1.0, math.nan]), 0.1, 0.0, 1.0), "t"),
        (pendula.small_angle, (math.inf, 0.1, 0.0, 1.0), "t"),
        (pendula.small_angle, (1.0, 0.1, 0.0, math.nan), "w0"),
        (pendula.small_angle_error, (math.nan, 0.1, 0.0, 1.0), "tmax"),
        (pendula.period, (math.nan,), "theta0"),
        (pendula.amplitude, (0.1, 0.0, -1.0), "w0"),
        (pendula.regime, (0.1, math.nan), "omega0"),
        (pendula.energy, (0.1, 0.0, 0.0), "w0"),
        (pendula.energy, (math.nan, 0.0, 1.0), "theta"),
        (pendula.elliptic_parameter, (0.1, 0.0, math.inf), "w0"),
    ],
)
def test_bad_input_names_the_argument(fn, args, name):
    with pytest.raises(ValueError, match=rf"^{name}(\[\d+\])? ="):
        fn(*args)


def test_type_and_shape_errors():
    with pytest.raises(TypeError):
        pendula.undamped("1", 0.1)
    with pytest.raises(TypeError):
        pendula.undamped(1.0, 0.1 + 1j)
    with pytest.raises(ValueError, match="broadcast"):
        pendula.undamped(np.zeros(3), np.zeros(2))


def test_empty_arrays_give_empty_results():
    e = np.array([])
    for fn in (pendula.undamped, pendula.small_angle):
        th, om = fn(e, 0.1, 0.0, 1.0)
        assert th.shape == (0,) and om.shape == (0,)
        th, om = fn(1.0, np.zeros((2, 0)))
        assert th.shape == (2, 0)
    assert pendula.period(e).shape == (0,) and pendula.regime(e).shape == (0,)
    assert pendula.small_angle_error(e, 0.1)[0].shape == (0,)
    assert pendula.energy(e, 0.0).shape == (0,)
    theta, lam, kind = pendula.equilibria(np.array([], dtype=int))
    assert theta.shape == (0,) and lam.shape == (0, 2) and kind.shape == (0,)


def test_huge_theta0_reduced_exactly():
    """|theta0| up to 1e300: reduced about 2 pi N exactly (libm's reduction beyond 2^40)."""
    for th0 in (1e13, -3e15, 1e20, 1e300, -1e300, 2.0**40 + 0.5):
        with mp.workdps(400):
            x = mp.mpf(th0)
            red = x - 2 * mp.pi * mp.nint(x / (2 * mp.pi))
            m_ref = float(mp.sin(red / 2) ** 2 + (mp.mpf(0.3) / mp.mpf(2.4)) ** 2)
        m, mc = pendula.elliptic_parameter(th0, 0.3, 1.2)
        assert abs(m - m_ref) <= 4 * EPS
        th, om = pendula.undamped(np.array([0.0, 1.0, -5.0]), th0, 0.3, 1.2)
        assert np.all(np.isfinite(th)) and np.all(np.isfinite(om))
        assert th[0] == th0 and abs(om[0] - 0.3) <= 4 * EPS


def test_half_angle_cosine_against_mpmath():
    """1 - m = cos^2(theta0/2) and m = sin^2(theta0/2) for Omega0 = 0 (the period's parameter,
    taken by a polynomial cosine and sine instead of libm's) within 2.5 eps of mpmath's: each
    within 1 ulp, relatively accurate up to theta0 = +-pi, over random angles, angles next to
    +-pi and tiny ones; the array call and the scalar calls agree bit for bit."""
    rng = np.random.default_rng(26)
    th = np.concatenate(
        [
            rng.uniform(-math.pi, math.pi, 1500),
            math.pi - 10 ** rng.uniform(-15, 0, 300),
            10 ** rng.uniform(-300, 0, 200),
        ]
    )
    th = th[np.abs(th) < math.pi] * rng.choice([-1.0, 1.0], th.size)
    mc = pendula.elliptic_parameter(th, 0.0, 1.0)[1]
    with mp.workdps(40):
        want = np.array([float(mp.cos(mp.mpf(float(x)) / 2) ** 2) for x in th])
    worst = float(np.max(np.abs(mc - want) / want)) / EPS
    assert worst <= 2.5, worst
    # m = sin^2(theta0/2) from the polynomial sine, likewise (where the square is normal)
    m = pendula.elliptic_parameter(th, 0.0, 1.0)[0]
    big = np.abs(th) > 1e-150
    with mp.workdps(40):
        want = np.array([float(mp.sin(mp.mpf(float(x)) / 2) ** 2) for x in th[big]])
    worst = float(np.max(np.abs(m[big] - want) / want)) / EPS
    assert worst <= 2.5, worst
    per = pendula.period(th, 0.0, 1.0)
    assert all(per[i] == pendula.period(float(th[i]), 0.0, 1.0) for i in range(0, th.size, 37))
    assert np.array_equal(per, pendula.period(th, np.zeros_like(th), np.ones_like(th)))


def test_amplitude_against_mpmath_down_to_subnormal_states():
    """amplitude = 2 asin(k), k^2 = sin^2(theta0/2) + (Omega0/(2 w0))^2 (eq. 1.60 for any
    state), within 3 ulps of mpmath's at the exact inputs: random librations, angles next
    to pi, and tiny states whose m = k^2 underflows (the amplitude, about |theta0|, does
    not: it is still accurate to an ulp there, down to subnormal angles); the array call
    and the scalar calls agree bit for bit."""
    rng = np.random.default_rng(60)
    n = 400
    th = np.concatenate(
        [
            rng.uniform(-math.pi, math.pi, n),
            math.pi - 10 ** rng.uniform(-15, -1, n),
            10 ** rng.uniform(-320, -1, n) * rng.choice([-1.0, 1.0], n),
            rng.uniform(-0.3, 0.3, n),
        ]
    )
    om = np.concatenate(
        [
            rng.uniform(-0.5, 0.5, n),
            np.zeros(n),
            np.where(rng.random(n) < 0.5, 0.0, th[2 * n : 3 * n]),
            rng.uniform(-2, 2, n),
        ]
    )
    w0 = 1.3
    amp = pendula.amplitude(th, om, w0)
    lib = np.isfinite(amp)
    assert lib.sum() > 3 * n
    with mp.workdps(50):
        want = np.array(
            [
                float(2 * mp.asin(mp.sqrt(mp.sin(mp.mpf(a) / 2) ** 2 + (mp.mpf(b) / (2 * mp.mpf(w0))) ** 2)))
                for a, b in zip(th[lib], om[lib])
            ]
        )
    ulps = np.abs(amp[lib] - want) / np.spacing(want)
    assert ulps.max() <= 3, (ulps.max(), th[lib][np.argmax(ulps)], om[lib][np.argmax(ulps)])
    assert all(amp[i] == pendula.amplitude(float(th[i]), float(om[i]), w0) for i in range(0, th.size, 7))
    # tiny states: the amplitude and the energy w0^2 theta0^2 / 2 do not underflow with m
    assert pendula.amplitude(1e-200, 0.0, w0) == 1e-200
    assert abs(pendula.energy(1e-200, 0.0, 1e150) / 5e-101 - 1) <= 4 * EPS
