"""pendula.rk4 and pendula.cvode: the nonlinear damped pendulum (text eq. 2.2).

References are independent of the library: an mpmath Taylor-series table at 30
digits (tests/data/integrators_reference.csv, from gen_integrators_reference.py),
SciPy's DOP853 at rtol 1e-13 (itself checked against the table), the exact
undamped solution (pendula.undamped, elliptic functions), the linear damped
closed form (pendula.linear_damped), the slow-manifold solution of stiff damping
and the exact undamped period 4 K(k^2)/w0 (mpmath.ellipk).
"""

import csv
import math
import pathlib

import mpmath as mp
import numpy as np
import pytest
from helpers import HAVE_CVODE, needs_cvode
from scipy.integrate import solve_ivp

import pendula
from pendula.textbook import text_listing_rk4

W0 = math.sqrt(9.8 / 4.9)  # the text's g = 9.8, l = 4.9
GAMMAS = {0.01: 0.01 / 0.1, 0.05: 0.05 / 0.1}  # b / m, m = 0.1 kg
T_TEXT = np.arange(601) * 0.05  # t = 0 .. 30 s, the text's h = 0.05
DATA = pathlib.Path(__file__).resolve().parents[1] / "data" / "integrators_reference.csv"


def mpmath_table():
    rows = [r for r in csv.reader(line for line in DATA.read_text().splitlines() if not line.startswith("#"))]
    out = {}
    for b, _, t, th, om in rows[1:]:
        out.setdefault(float(b), []).append((float(t), float(th), float(om)))
    return {b: np.array(v) for b, v in out.items()}


TABLE = mpmath_table()


def dop853(t, theta0, omega0, w0, gamma):
    w0sq = w0 * w0
    sol = solve_ivp(
        lambda _, y: [y[1], -gamma * y[1] - w0sq * math.sin(y[0])],
        (t[0], t[-1]),
        [theta0, omega0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-15,
        t_eval=t,
    )
    assert sol.success
    return sol.y[0], sol.y[1]


@pytest.fixture(scope="module")
def text_reference():
    """DOP853 (rtol 1e-13) on the 601-point grid, validated against mpmath."""
    ref = {}
    for b, gamma in GAMMAS.items():
        th, om = dop853(T_TEXT, 0.0, 2.0, W0, gamma)
        idx = np.rint(TABLE[b][:, 0] / 0.05).astype(int)
        assert np.max(np.abs(th[idx] - TABLE[b][:, 1])) < 1e-10
        assert np.max(np.abs(om[idx] - TABLE[b][:, 2])) < 1e-10
        ref[b] = (th, om)
    return ref


# ---------------------------------------------------------------- RK4 accuracy


@pytest.mark.parametrize("b", [0.01, 0.05])
def test_rk4_text_scenario_within_1e5(b, text_reference):
    res = pendula.rk4(T_TEXT, 0.0, 2.0, W0, GAMMAS[b], 0.05)
    th, om = text_reference[b]
    assert np.max(np.abs(res.theta - th)) < 1e-5
    assert np.max(np.abs(res.omega - om)) < 1e-5
    idx = np.rint(TABLE[b][:, 0] / 0.05).astype(int)
    assert np.max(np.abs(res.theta[idx] - TABLE[b][:, 1])) < 1e-5
    assert res.stats["steps"] == 600 and res.stats["rhs_evals"] == 2400
    assert res.method == "rk4" and res.events is None


def test_rk4_order_four():
    """Error at t = 10 s vs mpmath for h = 0.1 ... 0.001: least-squares slope 4 +- 0.1."""
    want = TABLE[0.01][10]
    assert want[0] == 10
    hs = np.array([0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001])
    err = []
    for h in hs:
        r = pendula.rk4([0.0, 10.0], 0.0, 2.0, W0, GAMMAS[0.01], h)
        err.append(max(abs(r.theta[1] - want[1]), abs(r.omega[1] - want[2])))
    slope = np.polyfit(np.log(hs), np.log(err), 1)[0]
    assert abs(slope - 4) < 0.1, (slope, err)
    assert err[-1] < 1e-12


def test_rk4_substeps_and_final_state():
    # outputs 1 s apart with h = 0.3: 4 equal substeps of 0.25 each
    r = pendula.rk4([0.0, 1.0, 2.0], 0.3, 0.0, W0, 0.1, 0.3)
    assert r.stats["steps"] == 8
    full = pendula.rk4(np.linspace(0, 2, 9), 0.3, 0.0, W0, 0.1, 0.25)
    assert abs(full.theta[-1] - r.theta[-1]) < 1e-15
    # final-state only: two outputs, same answer as the dense grid's last point
    t = np.arange(2001) * 0.05
    dense = pendula.rk4(t, 0.2, 0.5, W0, 0.05, 0.05)
    final = pendula.rk4([0.0, 100.0], 0.2, 0.5, W0, 0.05, 0.05)
    assert final.theta.shape == (2,)
    assert abs(final.theta[1] - dense.theta[-1]) < 1e-12
    one = pendula.rk4([3.0], 0.2, 0.5, W0, 0.05, 0.05)
    assert one.theta.tolist() == [0.2] and one.stats["steps"] == 0


# ---------------------------------------------------------------- stability


def test_rk4_max_stable_step_limits():
    assert math.isclose(pendula.rk4_max_stable_step(W0, 0.0) * W0, 2 * math.sqrt(2), rel_tol=1e-13)
    gamma = 1e4 * W0
    lam = -gamma / 2 - math.sqrt(gamma**2 / 4 - W0**2)
    limit = float(mp.findroot(lambda x: x**3 + 4 * x**2 + 12 * x + 24, -2.78))  # R(x) = 1 on x < 0
    assert math.isclose(pendula.rk4_max_stable_step(W0, gamma) * lam, limit, rel_tol=1e-12)
    for g in [0.3 * W0, 1.9 * W0]:  # complex eigenvalues: |R(h lambda)| = 1 at the limit
        h = pendula.rk4_max_stable_step(W0, g)
        lam = complex(-g / 2, math.sqrt(W0**2 - g**2 / 4))
        z = h * lam
        assert abs(abs(1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24) - 1) < 1e-12


def test_rk4_refuses_unstable_step():
    gamma = 1e4 * W0
    hmax = pendula.rk4_max_stable_step(W0, gamma)
    with pytest.raises(ValueError, match=r"h = 0\.05 is unstable.*largest stable h is 1\.96950E-04"):
        pendula.rk4(T_TEXT, 0.1, 0.0, W0, gamma, 0.05)
    ok = pendula.rk4([0.0, 2000 * hmax], 0.1, 0.0, W0, gamma, 0.99 * hmax)
    assert abs(ok.theta[1]) < 0.1
    h = 1.01 * 2 * math.sqrt(2) / W0  # gamma = 0: just beyond the imaginary-axis limit
    with pytest.raises(ValueError, match="unstable"):
        pendula.rk4([0.0, 3 * h], 0.1, 0.0, W0, 0.0, h)
    # the check is on the substep actually taken: a larger h over a fine grid is fine
    assert pendula.rk4([0.0, 1.0, 2.0], 0.1, 0.0, W0, 0.0, 10.0).stats["steps"] == 2


# ---------------------------------------------------------------- cross-checks


@pytest.mark.parametrize("theta0,omega0", [(0.5, 0.0), (2.5, 0.3), (0.0, 2.0), (0.1, 3.0)])
def test_undamped_matches_exact(theta0, omega0):
    """gamma = 0 (libration near and far from the separatrix, and rotation)."""
    t = np.linspace(0.0, 30.0, 301)
    undamped = getattr(pendula, "undamped", None)
    if undamped is not None:
        th_ex, om_ex = undamped(t, theta0, omega0, W0)
    else:  # pragma: no cover - until the undamped concern lands
        th_ex, om_ex = dop853(t, theta0, omega0, W0, 0.0)
    r = pendula.rk4(t, theta0, omega0, W0, 0.0, 0.01)
    assert np.max(np.abs(r.theta - th_ex)) < 1e-7
    if HAVE_CVODE:
        # CVODE controls local errors; the global error over ~7 periods is within
        # 1000 rtol of the angle's scale (which grows without bound in rotation)
        c = pendula.cvode(t, theta0, omega0, W0, 0.0, rtol=1e-11, atol=1e-13)
        scale = max(1.0, np.max(np.abs(th_ex)))
        assert np.max(np.abs(c.theta - th_ex)) < 1e-8 * scale
        assert np.max(np.abs(c.omega - om_ex)) < 1e-8 * scale


@pytest.mark.parametrize("ratio", [0.1, 1.0, 2.0, 5.0])
def test_small_amplitude_matches_linear_closed_form(ratio):
    """theta0 = 1e-4: the nonlinear terms are theta^3/6 ~ 2e-13 of the motion."""
    t = np.linspace(0.0, 20.0, 201)
    gamma = ratio * W0
    th_lin, om_lin = pendula.linear_damped(t, 1e-4, 2e-4, W0, gamma)
    r = pendula.rk4(t, 1e-4, 2e-4, W0, gamma, 0.01)
    assert np.max(np.abs(r.theta - th_lin)) < 5e-7 * 1e-4
    if HAVE_CVODE:
        c = pendula.cvode(t, 1e-4, 2e-4, W0, gamma, rtol=1e-11, atol=1e-17)
        assert np.max(np.abs(c.theta - th_lin)) < 1e-7 * 1e-4  # 1e4 rtol, relative


@needs_cvode
@pytest.mark.parametrize("b", [0.01, 0.05])
def test_cvode_vs_rk4_text_scenario(b, text_reference):
    c = pendula.cvode(T_TEXT, 0.0, 2.0, W0, GAMMAS[b], rtol=1e-10, atol=1e-12)
    r = pendula.rk4(T_TEXT, 0.0, 2.0, W0, GAMMAS[b], 1e-3)
    assert np.max(np.abs(c.theta - r.theta)) < 1e-7
    th, _ = text_reference[b]
    assert np.max(np.abs(c.theta - th)) < 1e-7
    assert np.max(np.abs(r.theta - th)) < 1e-10


@needs_cvode
@pytest.mark.parametrize("method", ["adams", "bdf"])
def test_cvode_methods_and_stats(method, text_reference):
    c = pendula.cvode(T_TEXT, 0.0, 2.0, W0, GAMMAS[0.05], rtol=1e-10, atol=1e-12, method=method)
    th, om = text_reference[0.05]
    assert np.max(np.abs(c.theta - th)) < 1e-6
    assert set(c.stats) == {
        "steps",
        "rhs_evals",
        "jac_evals",
        "err_test_fails",
        "nonlin_iters",
        "nonlin_fails",
        "root_evals",
    }
    assert c.stats["steps"] > 0 and c.stats["rhs_evals"] >= c.stats["steps"] and c.stats["jac_evals"] > 0
    assert c.method == method and c.t[0] == 0.0 and c.theta[0] == 0.0 and c.omega[0] == 2.0


@needs_cvode
def test_cvode_stiff_bdf():
    """gamma = 1e4 w0: BDF follows the slow manifold theta' = -(w0^2/gamma) sin(theta),
    tan(theta/2) = tan(theta0/2) exp(-w0^2 t / gamma), up to (w0/gamma)^2 = 1e-8."""
    gamma = 1e4 * W0
    t = np.array([0.0, 100.0, 1000.0, 5000.0, 20000.0])
    c = pendula.cvode(t, 0.5, 0.0, W0, gamma, rtol=1e-9, atol=1e-12, method="bdf")
    slow = 2 * np.arctan(math.tan(0.25) * np.exp(-(W0**2) * t / gamma))
    assert np.allclose(c.theta[1:], slow[1:], rtol=1e-6, atol=1e-12)
    assert c.stats["steps"] < 3000
    # Adams needs many more steps here: a small budget is reported, not overrun
    with pytest.raises(pendula.PendulaSolverError, match="max_steps = 1000"):
        pendula.cvode(t, 0.5, 0.0, W0, gamma, rtol=1e-9, atol=1e-12, method="adams", max_steps=1000)


@needs_cvode
def test_cvode_events_period():
    """gamma = 0: zero crossings every T/2 with T = 4 K(k^2)/w0, k = sin(theta0/2)."""
    theta0 = 2.0
    period = float(4 * mp.ellipk(math.sin(theta0 / 2) ** 2) / W0)
    c = pendula.cvode([0.0, 5.3 * period], theta0, 0.0, W0, 0.0, rtol=1e-11, atol=1e-13, events=True)
    tz, om = c.events.zero_crossings
    tt, th = c.events.turning_points
    assert len(tz) == 11 and len(tt) == 10 and not c.events.truncated
    assert np.max(np.abs(tz - (period / 4 + period / 2 * np.arange(11)))) < 1e-8
    assert np.max(np.abs(tt - period / 2 * np.arange(1, 11))) < 1e-8
    assert np.max(np.abs(np.abs(th) - theta0)) < 1e-8
    assert np.all(np.diff(c.events.t) > 0)
    assert c.stats["root_evals"] > 0


@needs_cvode
def test_cvode_events_decrement():
    """Small amplitude, gamma = 0.1: turning points are half a damped period pi/w_d
    apart and successive |theta| there shrink by exp(-(gamma/2) pi/w_d) (text section 2.1)."""
    gamma = 0.1
    wd = math.sqrt(W0**2 - gamma**2 / 4)
    c = pendula.cvode([0.0, 60.0], 1e-3, 0.0, W0, gamma, rtol=1e-11, atol=1e-16, events=True)
    _, th = c.events.turning_points
    ratios = np.abs(th[1:] / th[:-1])
    assert np.allclose(ratios, math.exp(-gamma * math.pi / (2 * wd)), rtol=1e-6)
    tz, _ = c.events.zero_crossings
    assert np.allclose(np.diff(tz), math.pi / wd, rtol=1e-6)


@needs_cvode
def test_cvode_events_truncated():
    c = pendula.cvode([0.0, 50.0], 0.5, 0.0, W0, 0.0, events=True, max_events=4)
    assert len(c.events.t) == 4 and c.events.truncated


# ---------------------------------------------------------------- the text's listing


def test_text_listing_drift(text_reference):
    """The printed listing (line-67 typo) drifts by over a radian; fixed, it is our RK4."""
    th_ref, _ = text_reference[0.01]
    t, th, om = text_listing_rk4(30.0, 0.05, 0.0, 2.0, W0, GAMMAS[0.01], typo=True)
    assert len(t) == 601 and abs(t[-1] - 30) < 1e-9
    drift = np.max(np.abs(th - th_ref))
    assert 1.0 < drift < 2.0
    _, th_fixed, om_fixed = text_listing_rk4(30.0, 0.05, 0.0, 2.0, W0, GAMMAS[0.01], typo=False)
    r = pendula.rk4(T_TEXT, 0.0, 2.0, W0, GAMMAS[0.01], 0.05)
    assert np.max(np.abs(th_fixed - r.theta)) < 1e-13
    assert np.max(np.abs(om_fixed - r.omega)) < 1e-13


# ---------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "kw,match",
    [
        (dict(h=0.0), "h = 0"),
        (dict(h=-0.1), "h = -0.1"),
        (dict(h=float("nan")), "h = NaN"),
        (dict(w0=0.0), "w0 = 0"),
        (dict(w0=-1.0), "w0 = -1"),
        (dict(gamma=-0.5), "gamma = -0.5"),
        (dict(t=[0.0, 1.0, 1.0]), "strictly increasing"),
        (dict(t=[0.0, 2.0, 1.0]), "strictly increasing"),
        (dict(t=[0.0, float("nan")]), r"t\[1\] = NaN"),
        (dict(t=[0.0, float("inf")]), "t"),
        (dict(t=[]), "at least 1"),
        (dict(t=[[0.0, 1.0]]), "1-D"),
        (dict(theta0=float("inf")), "theta0"),
    ],
)
def test_rk4_bad_input(kw, match):
    args = dict(t=[0.0, 1.0], theta0=0.1, omega0=0.0, w0=W0, gamma=0.1, h=0.01)
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        pendula.rk4(**args)


def test_rk4_type_errors_and_input_untouched():
    with pytest.raises(TypeError):
        pendula.rk4("abc", 0.1, 0.0, W0, 0.1, 0.01)
    with pytest.raises(TypeError, match="h"):
        pendula.rk4([0.0, 1.0], 0.1, 0.0, W0, 0.1, "0.01")
    # an array h is a step per state (a batch), as in sweep
    assert pendula.rk4([0.0, 1.0], 0.1, 0.0, W0, 0.1, [0.01, 0.02]).theta.shape == (2, 2)
    t = np.array([0.0, 0.5, 1.0])
    keep = t.copy()
    r = pendula.rk4(t, 0.1, 0.0, W0, 0.1, 0.01)
    assert np.array_equal(t, keep) and r.t is not t


@needs_cvode
@pytest.mark.parametrize(
    "kw,exc,match",
    [
        (dict(rtol=0.0), ValueError, "rtol = 0"),
        (dict(rtol=-1e-8), ValueError, "rtol"),
        (dict(atol=-1e-10), ValueError, "atol = -1e-10"),
        (dict(w0=0.0), ValueError, "w0 = 0"),
        (dict(gamma=-1.0), ValueError, "gamma = -1"),
        (dict(t=[0.0, 1.0, 0.5]), ValueError, "strictly increasing"),
        (dict(t=[0.0, float("nan")]), ValueError, "NaN"),
        (dict(method="rk45"), ValueError, "method"),
        (dict(max_steps=0), ValueError, "max_steps"),
        (dict(max_steps=1.5), TypeError, "max_steps"),
        (dict(events="yes"), TypeError, "events"),
        (dict(events=True, max_events=0), ValueError, "max_events"),
        (dict(events=True, max_events=10**8), ValueError, "max_events"),
    ],
)
def test_cvode_bad_input(kw, exc, match):
    args = dict(t=[0.0, 1.0], theta0=0.1, omega0=0.0, w0=W0, gamma=0.1)
    args.update(kw)
    with pytest.raises(exc, match=match):
        pendula.cvode(**args)


@needs_cvode
def test_cvode_solver_failure_is_an_exception():
    with pytest.raises(pendula.PendulaSolverError, match="CV_TOO_MUCH_ACC"):
        pendula.cvode([0.0, 1.0], 0.1, 0.1, W0, 0.1, rtol=1e-30, atol=1e-30)


@pytest.mark.skipif(HAVE_CVODE, reason="this build has CVODE; the unavailable path is tested without it")
def test_cvode_unavailable_raises():
    with pytest.raises(NotImplementedError, match="CVODE is not available"):
        pendula.cvode([0.0, 1.0], 0.1, 0.0, W0, 0.1)


def test_cvode_in_the_library_agrees_with_build_info():
    # build_info() reads meson's configuration; the glue asks the compiled
    # Fortran library (cvode_available): they must tell the same story.
    assert bool(pendula._fortran.cvode_available_f2py()) == pendula.build_info()["cvode"]
