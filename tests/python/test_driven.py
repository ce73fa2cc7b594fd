"""The driven pendulum from Python (pendula.driven, pendula.chaos): against
independent references -- the exact undamped pendulum and pendula.rk4 when
the drive is off, SciPy's DOP853 for a driven trajectory and for finite-time
Lyapunov exponents, the Floquet multipliers of the Newton orbit, the sum rule
lambda1 + lambda2 = -gamma, Kapitza's stability threshold, the linear closed
form -- plus fourth-order convergence, batch == single state bit for bit, and
refused input."""

import math

import numpy as np
import pytest

import pendula

BG = dict(w0=1.0, gamma=0.5)  # Baker & Gollub's q = 2
CHAOS = pendula.Drive("torque", 1.15, 2 / 3)
PERIOD1 = pendula.Drive("torque", 0.9, 2 / 3)
PERIOD2 = pendula.Drive("torque", 1.07, 2 / 3)


def _rhs(kind, amp, freq, phase, w0, gamma):
    def f(t, y):
        th, om = y[0], y[1]
        c = math.cos(freq * t + phase)
        p = w0 * w0 + (amp * freq * freq * c if kind == "pivot" else 0.0)
        q = amp * c if kind == "torque" else 0.0
        out = [om, q - gamma * om - p * math.sin(th)]
        if len(y) > 2:  # two tangent vectors (variational equations)
            for i in (2, 4):
                out += [y[i + 1], -gamma * y[i + 1] - p * math.cos(th) * y[i]]
        return out

    return f


def test_drive_off_is_the_undamped_and_damped_pendulum():
    t = np.linspace(0.0, 20.0, 41)
    d = pendula.Drive("torque", 0.0, 0.7, 0.2)
    r = pendula.driven(t, 2.0, 0.3, drive=d, w0=1.3, steps_per_period=8000)
    th, om = pendula.undamped(t, 2.0, 0.3, 1.3)
    assert np.max(np.abs(r.theta - th)) < 2e-12 and np.max(np.abs(r.omega - om)) < 2e-12
    p = pendula.Drive("pivot", 0.0, 0.7)
    r = pendula.driven(t, 2.0, 0.3, drive=p, w0=1.3, gamma=0.4, steps_per_period=8000)
    ref = pendula.rk4(t, 2.0, 0.3, 1.3, 0.4, 1e-3)
    assert np.max(np.abs(r.theta - ref.theta)) < 1e-11


def test_driven_against_dop853_and_order_four():
    scipy = pytest.importorskip("scipy.integrate")
    t = np.array([0.0, 5.0, 12.3, 25.0])
    sol = scipy.solve_ivp(
        _rhs("torque", 1.15, 2 / 3, 0.3, 1.0, 0.5),
        (0, 25.0),
        [0.2, 0.0],
        method="DOP853",
        t_eval=t,
        rtol=1e-13,
        atol=1e-13,
    )
    d = pendula.Drive("torque", 1.15, 2 / 3, 0.3)
    errs = []
    for n in (80, 160, 320):
        r = pendula.driven(t, 0.2, 0.0, drive=d, w0=1.0, gamma=0.5, steps_per_period=n, error=(n == 80))
        errs.append(np.max(np.abs(r.theta - sol.y[0])))
        if n == 80:
            ratio = np.abs(r.theta - sol.y[0])[1:] / r.theta_err[1:]
            assert np.all((ratio > 0.7) & (ratio < 1.3)), ratio  # Richardson estimate is honest
    assert 14 < errs[0] / errs[1] < 19 and 14 < errs[1] / errs[2] < 18, errs  # 2**4 = 16
    assert errs[2] < 1e-7


def test_a_start_a_million_periods_later_is_the_same_motion():
    # The drive phase of every stage is the start's phase plus an integer
    # count of half steps: a start at t0 = 1e6 T repeats the motion from 0 up
    # to the rounding of t0 itself (Omega ulp(t0) ~ 1e-9 rad), not h * steps.
    d = pendula.Drive("torque", 0.9, 2 / 3)
    T = d.period
    a = pendula.driven([0.0, 3 * T], 0.4, 0.1, drive=d, w0=1.0, gamma=0.5, steps_per_period=32)
    b = pendula.driven([1e6 * T, (1e6 + 3) * T], 0.4, 0.1, drive=d, w0=1.0, gamma=0.5, steps_per_period=32)
    assert abs(a.theta[-1] - b.theta[-1]) < 2 * d.frequency * np.spacing(1e6 * T) * 3


def test_batch_equals_single_state_bit_for_bit():
    t = [0.0, 1.0, 9.5, 30.0]
    th0 = np.linspace(-3, 3, 11)
    r = pendula.driven(t, th0, 0.1, drive=CHAOS, w0=1.0, gamma=0.3, threads=2)
    for i, x in enumerate(th0):
        one = pendula.driven(t, x, 0.1, drive=CHAOS, w0=1.0, gamma=0.3, threads=1)
        assert np.array_equal(one.theta, r.theta[i]) and np.array_equal(one.omega, r.omega[i])
    ly = pendula.lyapunov(th0[:9], 0.0, drive=CHAOS, w0=1.0, gamma=0.5, periods=32, threads=2)
    assert np.array_equal(
        pendula.lyapunov(th0[4], 0.0, drive=CHAOS, w0=1.0, gamma=0.5, periods=32).exponents, ly.exponents[4]
    )


def test_lyapunov_sum_rule_and_finite_time_exponents_against_scipy():
    scipy = pytest.importorskip("scipy.integrate")
    r = pendula.lyapunov(
        [0.2, 1.0, -2.0], 0.0, drive=CHAOS, w0=1.0, gamma=0.5, transient=0, periods=32, steps_per_period=2000
    )
    assert np.max(np.abs(r.exponents.sum(axis=-1) + 0.5)) < 1e-10
    # finite-time exponents over 16 periods from the same start, Gram-Schmidt each period, DOP853
    # reference (a regular orbit: on the chaotic one the two trajectories part by e^19 in 16 periods)
    T = PERIOD1.period
    y = np.array([0.2, 0.0, 1.0, 0.0, 0.0, 1.0])
    logs = np.zeros(2)
    f = _rhs("torque", 0.9, 2 / 3, 0.0, 1.0, 0.5)
    for k in range(16):
        y = scipy.solve_ivp(f, (k * T, (k + 1) * T), y, method="DOP853", rtol=1e-12, atol=1e-12).y[:, -1]
        v1, v2 = y[2:4], y[4:6]
        r11 = np.hypot(*v1)
        v1 = v1 / r11
        v2 = v2 - (v1 @ v2) * v1
        r22 = np.hypot(*v2)
        logs += np.log([r11, r22])
        y = np.concatenate([y[:2], v1, v2 / r22])
    ref = logs / (16 * T)
    got = pendula.lyapunov(
        0.2, 0.0, drive=PERIOD1, w0=1.0, gamma=0.5, transient=0, periods=16, steps_per_period=1024, orbits=1
    )
    assert np.max(np.abs(got.exponents - ref)) < 1e-9, (got.exponents, ref)


def test_periodic_orbit_floquet_multipliers_give_the_lyapunov_exponents():
    o = pendula.periodic_orbits(0.2, 0.0, drive=PERIOD1, **BG)
    assert int(o.period) == 1 and bool(o.stable) and o.residual <= 1e-10
    ly = pendula.lyapunov(0.2, 0.0, drive=PERIOD1, transient=200, periods=2000, steps_per_period=128, **BG)
    assert np.allclose(ly.exponents, o.floquet_exponents, rtol=0, atol=1e-4)
    assert np.all(ly.errors < 1e-3)
    # Floquet multipliers multiply to exp(-gamma T) (Liouville), up to the RK4 error
    assert abs(np.prod(o.multipliers).real - math.exp(-0.5 * PERIOD1.period)) < 1e-6
    two = pendula.periodic_orbits(0.2, 0.0, drive=PERIOD2, **BG)
    assert int(two.period) == 2
    again = pendula.find_periodic_orbit(two.theta, two.omega, drive=PERIOD2, period=2, **BG)
    assert abs(again.theta - two.theta) < 1e-9


def test_kapitza_inverted_pendulum_threshold():
    # stable iff (a/l)^2 Omega^2 / 2 > w0^2 (Kapitza; Landau & Lifshitz section 30), fast drive Omega = 20 w0
    above = pendula.find_periodic_orbit(np.pi, 0.0, drive=pendula.Drive("pivot", 0.1, 20.0), w0=1.0, gamma=0.1)
    below = pendula.find_periodic_orbit(np.pi, 0.0, drive=pendula.Drive("pivot", 0.05, 20.0), w0=1.0, gamma=0.1)
    assert bool(above.stable) and not bool(below.stable)
    # and an integration from near the top stays there
    r = pendula.driven(
        np.linspace(0, 60, 7), np.pi - 0.1, 0.0, drive=pendula.Drive("pivot", 0.1, 20.0), w0=1.0, gamma=0.1
    )
    assert np.all(np.abs(r.theta - np.pi) < 0.2)


def test_linear_closed_form_and_resonance():
    d = pendula.Drive("torque", 1e-5, 1.3, 0.4)
    t = np.linspace(0, 20, 50)
    th, om = pendula.driven_linear(t, 2e-5, 0.0, drive=d, w0=1.0, gamma=0.2)
    r = pendula.driven(t, 2e-5, 0.0, drive=d, w0=1.0, gamma=0.2, steps_per_period=1000)
    assert np.max(np.abs(th - r.theta)) < 1e-13 and np.max(np.abs(om - r.omega)) < 1e-13
    f = np.array([0.5, 1.0, 2.0])
    gain, lag = pendula.resonance_curve(f, w0=1.0, gamma=0.2)
    assert np.allclose(gain, 1 / np.hypot(1 - f**2, 0.2 * f), rtol=1e-15)
    assert np.allclose(lag, np.arctan2(0.2 * f, 1 - f**2), rtol=1e-15)


def test_sections_bifurcation_and_basins():
    b = pendula.bifurcation("amplitude", [0.9, 1.07, 1.15], drive=CHAOS, transient=300, points=6, **BG)
    assert b.theta.shape == (3, 6) and np.all(np.abs(b.theta) <= np.pi)
    assert np.ptp(b.theta[0]) < 1e-8  # period 1
    assert abs(b.theta[1, 2] - b.theta[1, 0]) < 1e-6 < abs(b.theta[1, 1] - b.theta[1, 0])  # period 2
    df = b.to_pandas()
    assert list(df.columns)[:4] == ["amplitude", "k", "theta", "omega"] and len(df) == 18
    assert (df["w0"] == 1.0).all() and (df["gamma"] == 0.5).all() and (df["code"] == 0).all()  # its inputs
    g = pendula.basins(np.linspace(-3, 3, 6)[:, None], np.linspace(-2, 2, 4)[None, :], drive=PERIOD1, **BG)
    assert g.labels.shape == (6, 4)
    assert np.array_equal(g.labels == pendula.UNSETTLED, g.period == 0)
    assert set(np.unique(g.labels[g.labels > 0])) <= set(range(1, len(g.attractors["period"]) + 1))
    # a running attractor is reported by its mean angular velocity
    run = pendula.poincare(0.0, 3.0, drive=pendula.Drive("torque", 1.5, 1.0), w0=1.0, gamma=0.3, points=20)
    assert abs(run.rotation_number) in (0.0, 1.0) or abs(abs(run.rotation_number) - 1) < 1e-9


def test_progress_callback_counts_states():
    seen = []
    pendula.lyapunov(
        np.zeros(20), 0.0, drive=CHAOS, w0=1.0, gamma=0.5, periods=16, progress=lambda d, n: seen.append((d, n))
    )
    assert seen and seen[-1] == (20, 20)


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: pendula.Drive("spring", 1.0, 1.0), "kind"),
        (lambda: pendula.Drive("torque", math.nan, 1.0), "amplitude"),
        (lambda: pendula.Drive("torque", 1.0, 0.0), "frequency"),
        (lambda: pendula.driven([0, 1], 0.0, 0.0, drive=CHAOS, w0=-1.0), "w0"),
        (lambda: pendula.driven([0, 1], 0.0, 0.0, drive=CHAOS, w0=1.0, gamma=-1.0), "gamma"),
        (lambda: pendula.driven([1, 0], 0.0, 0.0, drive=CHAOS), "t"),
        (lambda: pendula.driven([0, 1], math.inf, 0.0, drive=CHAOS), "theta0"),
        (
            lambda: pendula.driven([0, 1], 0.0, 0.0, drive=pendula.Drive("torque", 1, 0.01), steps_per_period=8),
            "steps_per_period",
        ),
        (lambda: pendula.lyapunov(0.0, 0.0, drive=CHAOS, periods=3), "periods"),
        (lambda: pendula.poincare(0.0, 0.0, drive=CHAOS, points=0), "points"),
        (lambda: pendula.bifurcation("mass", [1.0], drive=CHAOS), "parameter"),
        (lambda: pendula.bifurcation("gamma", [-1.0], drive=CHAOS), "gamma"),
        (lambda: pendula.basins(0.0, 0.0, drive=CHAOS, tol=0.0), "tol"),
        (lambda: pendula.periodic_orbits(0.0, 0.0, drive=CHAOS, nmax=0), "nmax"),
        (lambda: pendula.driven_linear([0.0], 0.0, 0.0, drive=pendula.Drive("pivot", 0.1, 1.0)), "pivot"),
        (lambda: pendula.resonance_curve(-1.0), "frequency"),
    ],
)
def test_bad_input_raises_value_error_naming_the_argument(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_drive_must_be_a_drive():
    with pytest.raises(TypeError, match="drive"):
        pendula.driven([0, 1], 0.0, 0.0, drive=(1.0, 1.0))


def test_cancel_flag_stops_a_batch_and_says_so():
    # the control array of pendula_control, raised before the call: every state unfinished
    from pendula import _fortran
    from pendula._codes import DRIVE_TORQUE, ERR_CANCELLED

    control = np.array([1, 0], dtype=np.int64)
    out = _fortran.lyapunov_f2py(
        np.zeros(16), [0.0], [1.0], [0.5], DRIVE_TORQUE, [1.15], [2 / 3], [0.0], 32, 0, 64, 8, 1, control
    )
    codes, code = out[2], out[4]
    assert code == ERR_CANCELLED and np.all(codes == ERR_CANCELLED)


@pytest.mark.parametrize(
    "cmd, files",
    [
        (["poincare", "--points", "50", "--transient", "20"], ["poincare.npz", "poincare.csv", "poincare.png"]),
        (
            ["bifurcation", "--values", "0.9", "1.1", "5", "--points", "4", "--transient", "20", "--no-png"],
            ["bifurcation.npz", "bifurcation.csv"],
        ),
        (["lyapunov", "--theta0", "0.2", "1.0", "--periods", "32", "--no-png"], ["lyapunov.npz", "lyapunov.csv"]),
        (
            [
                "basins",
                "--amplitude",
                "0.9",
                "--theta0",
                "-3",
                "3",
                "4",
                "--omega0",
                "-1",
                "1",
                "3",
                "--transient",
                "20",
                "--no-png",
            ],
            ["basins.npz", "basins.csv"],
        ),
    ],
)
def test_command_line_writes_its_files(tmp_path, cmd, files):
    import io

    from pendula.cli import main

    if "--no-png" not in cmd:
        pytest.importorskip("matplotlib")
    out = io.StringIO()
    assert main(cmd + ["--out", str(tmp_path / "o")], out=out) == 0, out.getvalue()
    for name in files:
        assert (tmp_path / "o" / name).stat().st_size > 0
    assert main(["lyapunov", "--periods", "3", "--out", str(tmp_path / "x")], out=io.StringIO()) == 2
