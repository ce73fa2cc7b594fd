"""Linear damped pendulum: accuracy against mpmath at 50 digits.

Reference: the exact solution of theta'' + gamma theta' + w0^2 theta = 0 at the
exact double inputs, evaluated in mpmath (50 digits) through the complex
square root of D = gamma^2/4 - w0^2 (no regime split), and itself checked
against mpmath's matrix exponential expm([[0, 1], [-w0^2, -gamma]]).

Error measure (the specification's): with size = |theta| + |Omega|/m, m = max(w0, gamma),
and the condition numbers cond_theta = sum_x |x d theta/dx|, x in {t, theta0,
Omega0, w0, gamma} (derivatives at 50 digits: exact for t, theta0, Omega0,
mpmath.diff for w0, gamma), require
    |d theta|   <= 16 eps (size + cond_theta)   + floor
    |d Omega|/m <= 16 eps (size + cond_Omega/m) + floor/m
where floor = 2^-1022 (the smallest normal double) is subtracted from |d theta|
and |d Omega| (before dividing by m): results below the normal range may
underflow to subnormals or 0.
"""

import math
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest

import pendula

EPS = np.finfo(float).eps
FLOOR = np.finfo(float).tiny
DPS = 50

RATIOS = {
    "0": 0.0,
    "1e-8": 1e-8,
    "0.5": 0.5,
    "2(1-1e-12)": 2 * (1 - 1e-12),
    "2(1+1e-12)": 2 * (1 + 1e-12),
    "2(1-1e-6)": 2 * (1 - 1e-6),
    "2(1+1e-6)": 2 * (1 + 1e-6),
    "2": 2.0,
    "3": 3.0,
    "5": 5.0,
    "1e3": 1e3,
    "1e6": 1e6,
}
W0T = [0.0, 1e-7, 1e-3, 0.05, 0.2, 0.5, 0.9, 1.3, 2.0, 3.7, 7.0, 15.0, 40.0, 120.0, 600.0, 1e3, 3e3, 1e4]
ICS = [(0.1, 0.0), (0.1, 0.5), (0.1, -0.5), (0.0, 0.5), (-0.7, 0.3)]


# ---- the reference ----------------------------------------------------------
def _parts(t, w0, g):
    a = g / 2
    d = a * a - w0 * w0
    e = mp.exp(-a * t)
    if d == 0:
        return e, e * t, a
    sq = mp.sqrt(mp.mpc(d))
    return e * mp.cosh(sq * t).real, e * (mp.sinh(sq * t) / sq).real, a


def _state(t, th0, om0, w0, g):
    ec, es, a = _parts(t, w0, g)
    return th0 * ec + (om0 + a * th0) * es, om0 * ec - (w0 * w0 * th0 + a * om0) * es


def reference(t, th0, om0, w0, g):
    """theta, Omega, cond_theta, cond_Omega at the exact double inputs (mpmath)."""
    with mp.workdps(DPS):
        t, th0, om0, w0, g = (mp.mpf(float(x)) for x in (t, th0, om0, w0, g))
        th, om = _state(t, th0, om0, w0, g)
        ec, es, a = _parts(t, w0, g)
        c_th = abs(th0 * (ec + a * es)) + abs(om0 * es) + abs(t * om)
        c_om = abs(th0 * w0 * w0 * es) + abs(om0 * (ec - a * es)) + abs(t * (g * om + w0 * w0 * th))
        for k in (0, 1):
            dg = mp.diff(lambda x: _state(t, th0, om0, w0, x)[k], g)
            dw = mp.diff(lambda x: _state(t, th0, om0, w0, x)[k], w0)
            if k == 0:
                c_th += abs(g * dg) + abs(w0 * dw)
            else:
                c_om += abs(g * dg) + abs(w0 * dw)
        return th, om, c_th, c_om


def error_ratio(t, th0, om0, w0, g, th, om):
    """max over theta, Omega of error / (eps (size + cond)), with the underflow floor."""
    rth, rom, cth, com = reference(t, th0, om0, w0, g)
    m = max(w0, g)
    size = abs(rth) + abs(rom) / m
    e_th = abs(mp.mpf(th) - rth)
    e_om = abs(mp.mpf(om) - rom)
    # The underflow allowance applies to theta and Omega themselves.
    r_th = max(e_th - FLOOR, 0) / (EPS * (size + cth))
    r_om = max(e_om - FLOOR, 0) / m / (EPS * (size + com / m))
    rel = max(e_th, e_om / m) / size if size > 1e-300 else mp.mpf(0)
    return float(max(r_th, r_om)), float(rel / EPS)


def _grid(w0, ratio):
    g = ratio * w0
    ts = {wt / w0 for wt in W0T}
    if g > 0:
        ts |= {x / g for x in (0.3, 1.0, 2.5, 8.0)}  # the fast scale 1/gamma
    info = pendula.damping_regime(w0, g)
    if info.regime == "overdamped":
        ts |= {x / info.decay_slow for x in (0.5, 3.0, 30.0)}  # the slow mode 1/|lambda2|
        ts |= {x / info.beta for x in (0.45, 0.5, 0.55)}  # where the series hands over
    return sorted(ts)


@pytest.mark.parametrize("label", list(RATIOS))
def test_accuracy_against_mpmath(label):
    ratio = RATIOS[label]
    worst = (0.0, None)
    worst_rel = 0.0
    n = 0
    for w0 in (math.sqrt(2.0), 0.37):
        g = ratio * w0
        ts = np.array(_grid(w0, ratio))
        for th0, om0 in ICS:
            th, om = pendula.linear_damped(ts, th0, om0, w0, g)
            assert np.all(np.isfinite(th)) and np.all(np.isfinite(om))
            for t, a, b in zip(ts, th, om):
                r, rel = error_ratio(t, th0, om0, w0, g, a, b)
                n += 1
                worst_rel = max(worst_rel, rel)
                if r > worst[0]:
                    worst = (r, (t, th0, om0, w0, g))
    print(
        f"gamma/w0 = {label}: {n} points, worst error = {worst[0]:.3f} eps (size + cond) "
        f"at (t, theta0, omega0, w0, gamma) = {worst[1]}; worst error / size = {worst_rel:.3g} eps"
    )
    assert worst[0] <= 16, f"error {worst[0]:.2f} eps (size + cond) at {worst[1]}"


def test_random_sweep_against_mpmath():
    # Seeded sweep: gamma/w0 log-uniform over [1e-10, 1e8] and within 1e-3 of
    # critical on either side, w0 over [1e-3, 1e3], w0 t over [1e-6, 1e4].
    rng = np.random.default_rng(20261122)
    n = 300
    w0 = 10 ** rng.uniform(-3, 3, n)
    ratio = np.where(
        rng.random(n) < 0.5,
        10 ** rng.uniform(-10, 8, n),
        2 * (1 + rng.choice([-1, 1], n) * 10 ** rng.uniform(-16, -3, n)),
    )
    g = ratio * w0
    t = 10 ** rng.uniform(-6, 4, n) / w0
    th0 = rng.uniform(-1, 1, n)
    om0 = rng.uniform(-1, 1, n) * w0
    th, om = pendula.linear_damped(t, th0, om0, w0, g)
    worst = max((error_ratio(*args)[0], args) for args in zip(t, th0, om0, w0, g, th, om))
    print(f"random sweep: {n} points, worst error = {worst[0]:.3f} eps (size + cond) at {worst[1][:5]}")
    assert worst[0] <= 16


def test_extreme_scales_sweep_against_mpmath():
    # Seeded sweep over extreme scales: w0 in [1e-100, 1e100], theta0 and
    # Omega0/w0 in [1e-50, 1e50], w0 t in [1e-8, 1e6]; answers down to the
    # subnormal range keep their digits (e^{-at} is split as m 2^n).
    rng = np.random.default_rng(6)
    n = 400
    w0 = 10 ** rng.uniform(-100, 100, n)
    ratio = np.where(
        rng.random(n) < 0.3,
        10 ** rng.uniform(-15, 12, n),
        2 * (1 + rng.choice([-1, 1], n) * 10 ** rng.uniform(-16, 0, n)),
    )
    ratio[rng.random(n) < 0.05] = 0
    g = ratio * w0
    t = 10 ** rng.uniform(-8, 6, n) / w0
    th0 = rng.uniform(-1, 1, n) * 10 ** rng.uniform(-50, 50, n)
    om0 = rng.uniform(-1, 1, n) * w0 * 10 ** rng.uniform(-50, 50, n)
    th, om = pendula.linear_damped(t, th0, om0, w0, g)
    assert np.all(np.isfinite(th)) and np.all(np.isfinite(om))
    worst = max((error_ratio(*args)[0], args) for args in zip(t, th0, om0, w0, g, th, om))
    print(f"extreme scales: {n} points, worst error = {worst[0]:.3f} eps (size + cond) at {worst[1][:5]}")
    assert worst[0] <= 16


def test_reference_matches_matrix_exponential():
    # The reference itself against mpmath.expm of [[0, 1], [-w0^2, -gamma]] t.
    for ratio in (0.0, 0.5, 2.0, 2 * (1 + 1e-12), 3.0, 1e3):
        w0 = math.sqrt(2.0)
        g = ratio * w0
        for t in (0.3, 2.0, 9.0):
            with mp.workdps(DPS):
                mw0, mg, mt = mp.mpf(w0), mp.mpf(g), mp.mpf(t)
                e = mp.expm(mp.matrix([[0, 1], [-(mw0**2), -mg]]) * mt)
                th_e = e[0, 0] * mp.mpf(0.1) + e[0, 1] * mp.mpf(0.5)
                om_e = e[1, 0] * mp.mpf(0.1) + e[1, 1] * mp.mpf(0.5)
                th, om, _, _ = reference(t, 0.1, 0.5, w0, g)
                assert abs(th - th_e) <= mp.mpf(10) ** -35 * (abs(th) + abs(om))
                assert abs(om - om_e) <= mp.mpf(10) ** -35 * (abs(th) + abs(om))


def test_huge_gamma_t_underflows_gracefully():
    # gamma t up to 1e300 in every regime: finite; where the answer is
    # representable it still meets the accuracy bound.
    cases = []
    for w0 in (1e-3, 1.0, 1e3):
        for ratio in (1e-8, 0.5, 2.0, 2 * (1 + 1e-6), 5.0, 1e6):
            for gt in (1e2, 1e5, 1e20, 1e100, 1e200, 1e300):
                if math.isfinite(gt / (ratio * w0)):
                    cases.append((gt / (ratio * w0), w0, ratio * w0))
    for g, t in ((1e300, 1.0), (1e150, 1e150), (1.0, 1e300), (1e-300, 1e300)):
        cases.append((t, 1.0, g))
    t, w0, g = (np.array(x) for x in zip(*cases))
    th, om = pendula.linear_damped(t, 0.1, -0.5, w0, g)
    assert np.all(np.isfinite(th)) and np.all(np.isfinite(om))
    for i in range(len(t)):
        r, _ = error_ratio(t[i], 0.1, -0.5, w0[i], g[i], th[i], om[i])
        assert r <= 16, (t[i], w0[i], g[i], th[i], om[i], r)


def test_gamma_zero_is_small_angle_solution_bit_for_bit():
    t = np.linspace(0, 200, 2001)
    for w0 in (math.sqrt(2.0), 0.3, 17.0):
        for th0, om0 in ICS:
            th, om = pendula.linear_damped(t, th0, om0, w0, 0.0)
            want_th = [th0 * math.cos(w0 * x) + (om0 / w0) * math.sin(w0 * x) for x in t]
            want_om = [om0 * math.cos(w0 * x) - (w0 * th0) * math.sin(w0 * x) for x in t]
            assert np.array_equal(th, want_th) and np.array_equal(om, want_om)


# ---- the text (figs 10-13): its own formulas, where well conditioned ---------
W0_TEXT = float(np.sqrt(9.8 / 4.9))
T_TEXT = np.arange(0.0, 2 * 2 * np.pi / W0_TEXT, 2 * 2 * np.pi / W0_TEXT / 1000)


def _text_overdamped(th0, om0, gama):
    w0 = W0_TEXT
    beta = np.sqrt(gama**2 / 4.0 - w0**2)
    l1, l2 = -gama / 2.0 - beta, -gama / 2.0 + beta
    a = (th0 * l2 - om0) / (l2 - l1)
    b = (om0 - th0 * l1) / (l2 - l1)
    return (
        a * np.exp(l1 * T_TEXT) + b * np.exp(l2 * T_TEXT),
        a * l1 * np.exp(l1 * T_TEXT) + b * l2 * np.exp(l2 * T_TEXT),
    )


def _text_critical(th0, om0):
    lam = -2.0 * W0_TEXT / 2.0
    a, b = th0, om0 - th0 * lam
    c, d = a * lam + b, b * lam
    return np.exp(lam * T_TEXT) * (a + b * T_TEXT), np.exp(lam * T_TEXT) * (c + d * T_TEXT)


@pytest.mark.parametrize(
    "factor, th0, om0", [(f, 0.1, om) for f in (3.0, 5.0) for om in (0.0, 0.5, -0.5)] + [(3.0, 0.0, 0.5)]
)
def test_text_overdamped_figures(factor, th0, om0):
    gama = factor * W0_TEXT
    want_th, want_om = _text_overdamped(th0, om0, gama)
    th, om = pendula.linear_damped(T_TEXT, th0, om0, W0_TEXT, gama)
    scale = np.abs(want_th) + np.abs(want_om) / gama + 1e-3 * (abs(th0) + abs(om0) / gama)
    assert np.max(np.abs(th - want_th) / scale) <= 64 * EPS
    assert np.max(np.abs(om - want_om) / gama / scale) <= 64 * EPS


@pytest.mark.parametrize("om0", [0.0, 0.5, -0.5])
def test_text_critical_figure(om0):
    want_th, want_om = _text_critical(0.1, om0)
    th, om = pendula.linear_damped(T_TEXT, 0.1, om0, W0_TEXT, 2.0 * W0_TEXT)
    scale = np.abs(want_th) + np.abs(want_om) / (2 * W0_TEXT) + 1e-4
    assert np.max(np.abs(th - want_th) / scale) <= 64 * EPS
    assert np.max(np.abs(om - want_om) / scale) <= 64 * EPS * 2 * W0_TEXT


def test_text_formula_fails_near_critical_where_ours_does_not():
    # At gamma = 2 w0 (1 + 1e-12) eq. 2.29 divides by 2 beta ~ 2.8e-6 w0 and
    # loses 5 digits; the library keeps the bound.
    gama = 2 * W0_TEXT * (1 + 1e-12)
    t = T_TEXT[::50]
    text_th, _ = _text_overdamped(0.1, 0.5, gama)
    text_th = text_th[::50]
    ours, om = pendula.linear_damped(t, 0.1, 0.5, W0_TEXT, gama)
    ref = np.array([float(reference(x, 0.1, 0.5, W0_TEXT, gama)[0]) for x in t])
    assert np.max(np.abs(text_th - ref) / np.abs(ref)) > 1e4 * EPS
    assert np.max(np.abs(ours - ref) / np.abs(ref)) < 16 * EPS


# ---- regime numbers ---------------------------------------------------------
def test_damping_regime_numbers():
    w0 = math.sqrt(2.0)
    r = pendula.damping_regime(w0, 0.5 * w0)
    assert r.regime == "underdamped"
    with mp.workdps(DPS):
        wd = mp.sqrt(mp.mpf(w0) ** 2 - (mp.mpf(0.5 * w0) / 2) ** 2)
        assert abs(r.omega_d - wd) <= 2 * EPS * wd
        assert abs(r.log_decrement - mp.pi * mp.mpf(0.5 * w0) / wd) <= 4 * EPS * r.log_decrement
        assert abs(r.damped_period - 2 * mp.pi / wd) <= 4 * EPS * r.damped_period
    assert r.lambda1 == complex(-0.25 * w0, -r.omega_d) and r.lambda2 == r.lambda1.conjugate()
    assert r.quality_factor == pytest.approx(2.0, rel=2 * EPS)
    assert r.decay_slow == r.decay_fast == 0.25 * w0
    assert r.gamma_critical == 2 * w0 and r.damping_ratio == pytest.approx(0.25, rel=EPS)

    c = pendula.damping_regime(w0, 2 * w0)
    assert c.regime == "critical" and c.lambda1 == c.lambda2 == complex(-w0, 0)
    assert math.isinf(c.log_decrement) and math.isinf(c.damped_period)

    for ratio in (3.0, 1e6, 1e12):
        o = pendula.damping_regime(w0, ratio * w0)
        assert o.regime == "overdamped"
        with mp.workdps(DPS):
            a = mp.mpf(ratio * w0) / 2
            beta = mp.sqrt(a * a - mp.mpf(w0) ** 2)
            assert abs(o.beta - beta) <= 4 * EPS * beta
            assert abs(o.lambda1.real + a + beta) <= 4 * EPS * (a + beta)
            l2 = -a + beta
            assert abs(o.lambda2.real - l2) <= 4 * EPS * abs(l2)  # no cancellation at 1e12
            assert abs(o.decay_slow + l2) <= 4 * EPS * abs(l2)
    z = pendula.damping_regime(1.0, 0.0)
    assert math.isinf(z.quality_factor) and z.log_decrement == 0 and z.omega_d == 1.0


def test_envelope_and_decrement():
    w0, g = math.sqrt(2.0), 0.2 * math.sqrt(2.0)
    t = np.linspace(0, 40, 4001)
    th, _ = pendula.linear_damped(t, 0.1, 0.5, w0, g)
    env = pendula.linear_damped_envelope(t, 0.1, 0.5, w0, g)
    assert np.all(np.abs(th) <= env * (1 + 8 * EPS))
    assert np.min((env - np.abs(th)) / env) < 1e-4
    r = pendula.damping_regime(w0, g)
    th1, _ = pendula.linear_damped(1.0, 0.1, 0.5, w0, g)
    th2, _ = pendula.linear_damped(1.0 + r.damped_period, 0.1, 0.5, w0, g)
    assert math.log(th1 / th2) == pytest.approx(r.log_decrement, rel=1e-13)
    assert pendula.linear_damped_envelope(1.0, 0.1, 0.5, w0, 3 * w0) == 0.0


# ---- Python API --------------------------------------------------------------
def test_broadcasting_scalars_and_input_untouched():
    t = np.linspace(0, 5, 6).reshape(2, 3)
    g = np.array([[0.0], [3.0]])
    t_copy, g_copy = t.copy(), g.copy()
    th, om = pendula.linear_damped(t, 0.1, 0.5, 1.0, g)
    assert th.shape == om.shape == (2, 3)
    assert np.array_equal(t, t_copy) and np.array_equal(g, g_copy)
    th00, om00 = pendula.linear_damped(t[1, 2], 0.1, 0.5, 1.0, 3.0)
    assert isinstance(th00, float) and isinstance(om00, float)
    assert th00 == th[1, 2] and om00 == om[1, 2]
    assert pendula.linear_damped(0.0, 0.1, 0.5, 1.0, 3.0) == (0.1, 0.5)
    # One trajectory (scalar parameters, set up once) and the fully broadcast
    # path (parameter arrays) give the same bits.
    t = np.linspace(0, 30, 301)
    for g in (0.0, 0.7, 2.0, 2.0 * (1 + 1e-9), 5.0):
        a = pendula.linear_damped(t, 0.1, -0.5, 1.0, g)
        b = pendula.linear_damped(t, np.full(t.shape, 0.1), -0.5, 1.0, np.full(t.shape, g))
        assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(gamma=-1.0), "gamma"),
        (dict(w0=0.0), "w0"),
        (dict(w0=-2.0), "w0"),
        (dict(theta0=float("nan")), "theta0"),
        (dict(omega0=float("inf")), "omega0"),
        (dict(t=-1.0), "t"),
        (dict(t=float("nan")), "t"),
        (dict(gamma=float("inf")), "gamma"),
        (dict(w0=np.array([1.0, float("nan")])), "w0"),
    ],
)
def test_bad_input_names_the_argument(kwargs, name):
    args = dict(t=1.0, theta0=0.1, omega0=0.5, w0=1.0, gamma=0.5)
    args.update(kwargs)
    with pytest.raises(ValueError) as err:
        pendula.linear_damped(**args)
    assert str(err.value).startswith(name)
    with pytest.raises(ValueError):
        pendula.linear_damped_envelope(**args)
    if name in ("w0", "gamma") and np.ndim(kwargs[name]) == 0:
        with pytest.raises(ValueError) as err:
            pendula.damping_regime(args["w0"], args["gamma"])
        assert str(err.value).startswith(name)


def test_bad_types():
    with pytest.raises(TypeError):
        pendula.linear_damped("1", 0.1, 0.5, 1.0, 0.5)
    with pytest.raises(TypeError):
        pendula.damping_regime(np.array([1.0, 2.0]), 0.5)
    with pytest.raises(ValueError):
        pendula.linear_damped(np.zeros(3), 0.1, 0.5, np.ones(2), 0.5)


def test_python_matches_fortran_table():
    # tests/data/linear_damped_python.csv: values of this function recorded by
    # gen_linear_table.py; tests/fortran/test_linear_damped.f90 checks the
    # native Fortran evaluation against the same rows within 1 ulp.
    path = Path(__file__).resolve().parents[1] / "data" / "linear_damped_python.csv"
    rows = np.loadtxt(path, delimiter=",", comments="#")
    th, om = pendula.linear_damped(*rows[:, :5].T)
    ulp_th = np.abs(th - rows[:, 5]) / np.spacing(np.abs(rows[:, 5]))
    ulp_om = np.abs(om - rows[:, 6]) / np.spacing(np.abs(rows[:, 6]))
    assert max(ulp_th.max(), ulp_om.max()) <= 1
