"""Fits of measured pendulums (pendula.fit_period, pendula.fit_motion).

Synthetic data from the exact models with known parameters (the elliptic
period and motion; the damped pendulum by pendula.rk4 at a step whose error,
~1e-11 rad, is far below the noise), so each estimate can be compared with the
truth in units of its own standard error.  The variational Jacobian is
checked against finite differences of an independent integration and against
mpmath's closed form; the period fit against SciPy's least squares of the same
objective and against the small-angle formula written out here.
"""

import math

import numpy as np
import pytest

import pendula

scipy = pytest.importorskip("scipy")
from scipy import optimize, special, stats  # noqa: E402

W0, LENGTH = 3.6, 0.75
G = W0**2 * LENGTH


def swing(t, theta0, omega0, w0, gamma):
    """The exact damped motion (RK4 at h = 1e-3 s: error ~1e-11 rad) or the elliptic one."""
    if gamma == 0:
        return pendula.undamped(t - t[0], theta0, omega0, w0)
    r = pendula.rk4(t - t[0], theta0, omega0, w0, gamma, h=1e-3)
    return r.theta, r.omega


# ------------------------------------------------------------------ periods


def test_period_fit_exact_data_recovers_g_and_small_angle_bias():
    th = np.radians([10.0, 30.0, 60.0, 90.0, 120.0, 150.0, 170.0])
    T = pendula.period(th, g=9.81, length=LENGTH)
    r = pendula.fit_period(th, T, sigma_period=1e-3, length=LENGTH)
    assert r["g"] == pytest.approx(9.81, rel=1e-13)
    assert r.chi2 < 1e-20 and r.dof == th.size - 1
    # the small-angle formula per point, written out: g = 4 pi^2 l / T^2
    assert np.allclose(r.small_angle["g_per_point"], 4 * np.pi**2 * LENGTH / T**2, rtol=1e-14)
    assert r.small_angle["g_per_point"][5] == pytest.approx(3.16, abs=0.01)  # the 150 degrees


def test_period_fit_matches_scipy_least_squares_and_curve_fit_errors():
    rng = np.random.default_rng(3)
    th = np.radians(np.linspace(5.0, 160.0, 12))
    sp = np.full(th.size, 2e-3)
    T = pendula.period(th, w0=W0) + rng.normal(0.0, 2e-3, th.size)
    r = pendula.fit_period(th, T, sigma_period=sp)
    f = 4 * special.ellipk(np.sin(th / 2) ** 2)  # SciPy's K, not pendula's
    popt, pcov = optimize.curve_fit(lambda x, w: f / w, th, T, p0=[3.0], sigma=sp, absolute_sigma=True)
    assert r["w0"] == pytest.approx(popt[0], rel=1e-10)
    assert r.stderr["w0"] == pytest.approx(math.sqrt(pcov[0, 0]), rel=1e-6)
    # without sigma: errors from the scatter, Student's t
    r2 = pendula.fit_period(th, T)
    popt2, pcov2 = optimize.curve_fit(lambda x, w: f / w, th, T, p0=[3.0])
    assert r2["w0"] == pytest.approx(popt2[0], rel=1e-10)
    assert r2.stderr["w0"] == pytest.approx(math.sqrt(pcov2[0, 0]), rel=1e-6)
    assert r2.interval_kind == "t" and math.isnan(r2.pvalue)


def test_period_fit_amplitude_errors_effective_variance():
    th = np.radians([20.0, 60.0, 100.0, 140.0])
    T = pendula.period(th, w0=W0)
    st = np.radians(0.5)
    r = pendula.fit_period(th, T, sigma_period=1e-3, sigma_theta0=st)
    r0 = pendula.fit_period(th, T, sigma_period=1e-3)
    assert r["w0"] == pytest.approx(W0, rel=1e-12)
    assert r.stderr["w0"] > r0.stderr["w0"]
    # dT/dtheta0 by a central difference of pendula.period, for the effective variance
    h = 1e-6
    dT = (pendula.period(th + h, w0=W0) - pendula.period(th - h, w0=W0)) / (2 * h)
    s2 = 1e-6 + (dT * st) ** 2
    f = T * W0
    se = math.sqrt(1 / np.sum(f**2 / s2)) * W0**2
    assert r.stderr["w0"] == pytest.approx(se, rel=1e-6)


def test_period_fit_finite_bob_and_length_given_g():
    th = np.radians([10.0, 50.0, 90.0])
    rb = 0.05
    leff = LENGTH + 2 * rb**2 / (5 * LENGTH)
    T = pendula.period(th, w0=math.sqrt(9.81 / leff))
    r = pendula.fit_period(th, T, sigma_period=1e-4, length=LENGTH, bob_radius=rb)
    assert r["g"] == pytest.approx(9.81, rel=1e-12)
    r2 = pendula.fit_period(th, T, sigma_period=1e-4, g=9.81, bob_radius=rb)
    assert r2["length"] == pytest.approx(LENGTH, rel=1e-12)
    # delta method vs a finite difference of the length in w0
    w0, se = r2["w0"], r2.stderr["w0"]
    ell = lambda w: 0.5 * (9.81 / w**2 + math.sqrt((9.81 / w**2) ** 2 - 1.6 * rb**2))  # noqa: E731
    d = (ell(w0 * (1 + 1e-7)) - ell(w0 * (1 - 1e-7))) / (2e-7 * w0)
    assert r2.stderr["length"] == pytest.approx(abs(d) * se, rel=1e-5)


def test_period_fit_coverage_monte_carlo():
    rng = np.random.default_rng(11)
    th = np.radians(np.linspace(10.0, 150.0, 8))
    T0 = pendula.period(th, w0=W0)
    z = []
    for _ in range(400):
        th_m = th + rng.normal(0.0, np.radians(1.0), th.size)
        r = pendula.fit_period(
            th_m, T0 + rng.normal(0.0, 2e-3, th.size), sigma_period=2e-3, sigma_theta0=np.radians(1.0), length=LENGTH
        )
        z.append((r["g"] - G) / r.stderr["g"])
    z = np.array(z)
    cover = np.mean(np.abs(z) < stats.norm.ppf(0.975))
    assert 0.90 <= cover <= 0.99, cover
    assert 0.75 < np.mean(z**2) < 1.3


# ------------------------------------------------------------------ motion


@pytest.mark.parametrize(
    "deg,gamma,noise", [(170.0, 0.0, 1e-2), (150.0, 0.1, 1e-3), (45.0, 0.3, 1e-2), (120.0, 0.02, 1e-4)]
)
def test_motion_fit_within_standard_errors(deg, gamma, noise):
    rng = np.random.default_rng(int(deg))
    t = np.sort(rng.uniform(0.0, 12.0, 300))  # uneven sampling
    th, _ = swing(t, np.radians(deg), 0.2, W0, gamma)
    r = pendula.fit_motion(
        t, th + rng.normal(0.0, noise, t.size), sigma=noise, length=LENGTH, damping="linear" if gamma else None
    )
    truth = dict(theta0=np.radians(deg), omega0=0.2, w0=W0, gamma=gamma, g=G)
    for name in r.names:
        assert abs(r[name] - truth[name]) < 4 * r.stderr[name], (name, r[name], r.stderr[name])
    assert 0.7 < r.reduced_chi2 < 1.3


def test_motion_fit_1e4_noise_recovers_g_to_1e5():
    rng = np.random.default_rng(5)
    t = np.linspace(0.0, 20.0, 800)
    th, _ = swing(t, np.radians(100.0), 0.0, W0, 0.05)
    r = pendula.fit_motion(t, th + rng.normal(0.0, 1e-4, t.size), sigma=1e-4, length=LENGTH)
    assert abs(r["g"] / G - 1) < 1e-5
    r2 = pendula.fit_motion(t, th + rng.normal(0.0, 1e-4, t.size), sigma=1e-4, g=G)
    assert abs(r2["length"] / LENGTH - 1) < 1e-5


def _sweep_case(k):
    """Case k of a random sweep of fit_motion (amplitudes 5-170 deg, w0 1-10 1/s,
    30-600 uneven samples over 1.2-15 swings, noise 1e-4..1e-2 rad), regenerated."""
    rng = np.random.default_rng(1)
    for i in range(k + 1):
        deg, gamma, w0 = rng.uniform(5, 170), rng.choice([0.0, rng.uniform(0.001, 1.0)]), rng.uniform(1, 10)
        noise, n = 10 ** rng.uniform(-4, -2), int(rng.integers(30, 600))
        span = rng.uniform(1.2, 15) * 2 * np.pi / w0
        t = np.sort(rng.uniform(0, span, n))
        om0 = rng.uniform(-0.3, 0.3) * w0
        if gamma == 0:
            th = pendula.undamped(t - t[0], np.radians(deg), om0, w0)[0]
        else:
            th = pendula.rk4(t - t[0], np.radians(deg), om0, w0, gamma, h=min(1e-3, np.pi / w0 / 1000)).theta
        if np.abs(th).max() >= np.pi:  # a rotation: the sweep drew no noise for it
            continue
        y = th + rng.normal(0, noise, n)
        if i == k:
            return t, y, noise, w0, gamma


@pytest.mark.parametrize("k", [8, 83])
def test_motion_fit_long_sparse_record_finds_the_global_minimum(k):
    # 13 and 10 swings at about 9 samples a swing, released at 139 and 130 deg: fitted
    # over the whole record at once, the start's small w0 error put the later swings
    # out of phase and the solver stopped in a local minimum (chi2/dof ~ 1e5);
    # the continuation over 3, 6, 12, ... periods finds the truth
    t, y, noise, w0, gamma = _sweep_case(k)
    assert gamma == 0 and t.size < 120
    r = pendula.fit_motion(t, y, sigma=noise, damping=None)
    assert abs(r["w0"] - w0) < 4 * r.stderr["w0"] and r.reduced_chi2 < 1.4


def test_motion_fit_with_omega_offsets_and_t_ref():
    rng = np.random.default_rng(8)
    t = np.linspace(1.0, 9.0, 250)
    th, om = swing(t, 1.2, -0.5, W0, 0.15)
    r = pendula.fit_motion(
        t,
        th + 0.03 + rng.normal(0, 1e-3, t.size),
        omega=om - 0.02 + rng.normal(0, 1e-2, t.size),
        sigma=1e-3,
        sigma_omega=1e-2,
        fit_offsets=True,
        t_ref=1.0,
    )
    truth = dict(theta0=1.2, omega0=-0.5, w0=W0, gamma=0.15, theta_offset=0.03, omega_offset=-0.02)
    assert set(r.names) == set(truth)
    for name, v in truth.items():
        assert abs(r[name] - v) < 4 * r.stderr[name], name
    assert r.residuals_omega.shape == t.shape


def test_motion_fit_coverage_monte_carlo():
    rng = np.random.default_rng(2024)
    t = np.linspace(0.0, 8.0, 160)
    th, _ = swing(t, np.radians(90.0), 0.0, W0, 0.1)
    names = ("theta0", "omega0", "w0", "gamma")
    truth = dict(theta0=np.radians(90.0), omega0=0.0, w0=W0, gamma=0.1)
    z = {n: [] for n in names}
    for _ in range(80):
        r = pendula.fit_motion(t, th + rng.normal(0.0, 5e-3, t.size), sigma=5e-3)
        for n in names:
            z[n].append((r[n] - truth[n]) / r.stderr[n])
    for n in names:
        zz = np.array(z[n])
        assert 0.85 <= np.mean(np.abs(zz) < 1.96) <= 1.0, n
        assert 0.6 < np.mean(zz**2) < 1.5, n


@pytest.mark.parametrize("unit", [1e-12, 1e-6, 1e6, 1e12])
def test_motion_fit_does_not_depend_on_the_unit_of_time(unit):
    """The same record with its clock in other units (t * unit): the fitted rates scale by
    1/unit, to 1e-9.  A w0 below 1e-10 (t * 1e12) used to be moved to 1e-10 by the least
    squares' strictly feasible start and the fit ran for minutes there."""
    rng = np.random.default_rng(4)
    t = np.linspace(0.0, 20.0, 300)
    theta = pendula.rk4(t, 0.4, 0.0, 2.0, 0.05, h=1e-3).theta + rng.normal(0.0, 1e-3, t.size)
    ref = pendula.fit_motion(t, theta, damping="linear")
    r = pendula.fit_motion(t * unit, theta, damping="linear")
    for k in ("omega0", "w0", "gamma"):
        assert r[k] * unit == pytest.approx(ref[k], rel=1e-9, abs=1e-12), k
        assert r.stderr[k] * unit == pytest.approx(ref.stderr[k], rel=1e-6), k
    assert r["theta0"] == pytest.approx(ref["theta0"], rel=1e-9)


def test_robust_loss_resists_outliers():
    rng = np.random.default_rng(4)
    t = np.linspace(0.0, 6.0, 200)
    th, _ = swing(t, 1.0, 0.0, W0, 0.1)
    y = th + rng.normal(0, 1e-3, t.size)
    y[::17] += 0.3
    plain = pendula.fit_motion(t, y, sigma=1e-3)
    robust = pendula.fit_motion(t, y, sigma=1e-3, loss="soft_l1", f_scale=3.0)
    assert abs(robust["w0"] - W0) < 0.1 * abs(plain["w0"] - W0)
    assert abs(robust["w0"] - W0) < 1e-3


# ------------------------------------------------------------- Jacobian


def _sens(t, th0, om0, w0, gamma, tol=1e-11):
    th, om, jt, jo, _, code, _ = pendula._fortran.sensitivity_f2py(t, 0.0, th0, om0, w0, gamma, tol)
    assert code == 0
    return th, om, jt, jo


def test_variational_jacobian_vs_finite_differences_of_rk4():
    t = np.linspace(0.0, 6.0, 13)
    p = np.array([2.5, 0.4, W0, 0.2])
    _, _, jt, jo = _sens(t, *p)
    for j in range(4):
        h = 1e-6 * max(1.0, abs(p[j]))
        up, dn = p.copy(), p.copy()
        up[j] += h
        dn[j] -= h
        a, b = pendula.rk4(t, *up, h=2e-4), pendula.rk4(t, *dn, h=2e-4)
        assert np.allclose(jt[:, j], (a.theta - b.theta) / (2 * h), atol=2e-7 * np.abs(jt[:, j]).max() + 1e-8)
        assert np.allclose(jo[:, j], (a.omega - b.omega) / (2 * h), atol=2e-7 * np.abs(jo[:, j]).max() + 1e-8)


def test_variational_jacobian_vs_mpmath_closed_form():
    mp = pytest.importorskip("mpmath")
    mp.mp.dps = 30
    th0, w0 = 2.8, W0  # 160 degrees, released at rest: theta = 2 asin(k sn(K - w0 t | m))

    def theta(t, a, w):
        k = mp.sin(a / 2)
        m = k * k
        return 2 * mp.asin(k * mp.ellipfun("sn", mp.ellipk(m) - w * t, m=m))

    t = np.array([0.3, 1.7, 4.2])
    _, _, jt, _ = _sens(t, th0, 0.0, w0, 0.0)
    for i, ti in enumerate(t):
        d_th0 = mp.diff(lambda a: theta(mp.mpf(ti), a, mp.mpf(w0)), mp.mpf(th0))
        d_w0 = mp.diff(lambda w: theta(mp.mpf(ti), mp.mpf(th0), w), mp.mpf(w0))
        assert jt[i, 0] == pytest.approx(float(d_th0), rel=1e-8, abs=1e-9)
        assert jt[i, 2] == pytest.approx(float(d_w0), rel=1e-8, abs=1e-9)


def test_sensitivity_values_match_the_elliptic_solution_at_tol():
    t = np.linspace(0.0, 30.0, 500)
    for tol in (1e-7, 1e-10):
        th, _, _, _ = _sens(t, np.radians(170.0), 0.0, W0, 0.0, tol)
        exact, _ = pendula.undamped(t, np.radians(170.0), 0.0, W0)
        assert np.abs(th - exact).max() < tol


# ------------------------------------------------------------- bad data


@pytest.mark.parametrize(
    "call,match",
    [
        (lambda: pendula.fit_period([0.5], [2.0]), "at least 2"),
        (lambda: pendula.fit_period([0.5, 1.0], [2.0]), "lengths must match"),
        (lambda: pendula.fit_period([0.5, 3.5], [2.0, 2.5], sigma_period=0.01), "rotates"),
        (lambda: pendula.fit_period([0.5, np.nan], [2.0, 2.5]), "not finite"),
        (lambda: pendula.fit_period([0.5, 1.0], [2.0, 2.5], length=1.0, g=9.8), "not both"),
        (lambda: pendula.fit_period([0.5, 1.0], [2.0, 2.5], sigma_theta0=0.01), "sigma_period"),
        (lambda: pendula.fit_motion(np.linspace(0, 1, 4), np.zeros(4)), "cannot determine"),
        (lambda: pendula.fit_motion(np.zeros(20), np.linspace(0, 1, 20)), "one time"),
        (lambda: pendula.fit_motion(np.linspace(0, 10, 50), np.linspace(0, 10, 50)), "rotation"),
        (lambda: pendula.fit_motion(np.linspace(0, 1, 50), np.zeros(49)), "lengths must match"),
        (lambda: pendula.fit_motion(np.linspace(0, 1, 50), np.r_[np.zeros(49), np.inf]), "not finite"),
        (lambda: pendula.fit_motion(np.linspace(1, 0, 50), np.zeros(50)), "increasing"),
        (lambda: pendula.fit_motion(np.linspace(0, 0.1, 50), 0.1 + 0.01 * np.linspace(0, 0.1, 50)), "starting period"),
    ],
)
def test_bad_data_raise_value_error_naming_the_cause(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# ------------------------------------------------------------- result


def test_result_table_repr_and_plot():
    pytest.importorskip("pandas")
    pytest.importorskip("matplotlib")
    th = np.radians([10.0, 40.0, 80.0, 120.0])
    r = pendula.fit_period(th, pendula.period(th, w0=W0) + [1e-3, -1e-3, 0, 5e-4], sigma_period=1e-3, g=9.81)
    df = r.to_pandas()
    assert list(df.index) == ["w0", "length"]
    assert df.loc["length", "ci_low"] < r["length"] < df.loc["length", "ci_high"]
    assert df.attrs["dof"] == 3
    assert "small-angle formula" in repr(r) and "length" in repr(r)
    assert np.allclose(r.correlation, [[1.0, -1.0], [-1.0, 1.0]])  # length = g/w0^2: a function of w0 alone
    data = r.to_pandas("data")
    assert np.allclose(data["residual"], data["period"] - data["period_model"])
    fig = r.plot()
    assert len(fig.axes) == 2
    t = np.linspace(0.0, 5.0, 100)
    m = pendula.fit_motion(t, swing(t, 1.0, 0.0, W0, 0.1)[0] + 1e-3 * np.sin(7 * t), sigma=1e-3)
    assert len(m.plot().axes) == 2
    assert np.allclose(m.model(t), m.data["theta"] - m.residuals)


# ------------------------------------------------------------- command line


def test_cli_fit_periods_and_swing(tmp_path):
    import io

    from pendula.cli import main

    pytest.importorskip("matplotlib")
    th = np.radians([10.0, 40.0, 80.0, 120.0, 150.0])
    per = tmp_path / "periods.csv"
    per.write_text(
        "theta0_deg,period,sigma_period\n"
        + "".join(
            f"{float(d)!r},{float(p)!r},0.001\n"
            for d, p in zip(np.degrees(th), pendula.period(th, g=9.81, length=LENGTH))
        )
    )
    out = io.StringIO()
    assert main(["fit", str(per), "--length", str(LENGTH)], out=out) == 0
    text = out.getvalue()
    assert "g " in text and "9.81" in text and "small-angle" in text
    assert (tmp_path / "periods_fit.png").read_bytes()[:4] == b"\x89PNG"
    t = np.linspace(0.0, 6.0, 120)
    sw = tmp_path / "swing.csv"
    sw.write_text(
        "t,theta\n"
        + "".join(
            f"{float(a)!r},{float(b)!r}\n" for a, b in zip(t, swing(t, 1.0, 0.0, W0, 0.1)[0] + 1e-3 * np.cos(50 * t))
        )
    )
    out = io.StringIO()
    assert main(["fit", str(sw), "--png", str(tmp_path / "s.png")], out=out) == 0
    assert "gamma" in out.getvalue() and (tmp_path / "s.png").exists()
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y\n1,2\n3,4\n")
    assert main(["fit", str(bad), "--no-png"], out=io.StringIO()) == 2
