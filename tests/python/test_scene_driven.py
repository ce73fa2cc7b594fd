"""Driven scenes: Scene(..., drive=Drive(...)) answered by the linearised driven
oscillator in closed form or by the driven RK4 kernel, each with an honest
error estimate, checked against references that share no code with the model
that answered: mpmath's Taylor ODE solver (odefun) at 30 digits for the
linear equation, SciPy's DOP853 at rtol 1e-13 for the nonlinear one."""

import mpmath as mp
import numpy as np
import pytest

import pendula

scipy_integrate = pytest.importorskip("scipy.integrate")

W0 = np.sqrt(2.0)  # the text's pendulum (g = 9.8, length = 4.9)


def _sup(r, theta, omega, w0=W0):
    return float(max(np.max(np.abs(r.theta - theta)), np.max(np.abs(r.omega - omega)) / w0))


def _dop853(theta0, omega0, t, gamma, drive, w0=W0):
    """The nonlinear driven pendulum by SciPy (rtol 1e-13: ~1e-12 rad here)."""
    f, om, ph = drive.amplitude, drive.frequency, drive.phase
    if drive.kind == "torque":

        def rhs(s, y):
            return [y[1], -gamma * y[1] - w0**2 * np.sin(y[0]) + f * np.cos(om * s + ph)]

    else:

        def rhs(s, y):
            return [y[1], -gamma * y[1] - (w0**2 + f * om**2 * np.cos(om * s + ph)) * np.sin(y[0])]

    sol = scipy_integrate.solve_ivp(
        rhs, (0.0, t[-1]), [theta0, omega0], method="DOP853", t_eval=t, rtol=1e-13, atol=1e-15
    )
    assert sol.success
    return sol.y[0], sol.y[1]


def test_driven_linear_closed_form_against_mpmath_30_digits():
    # theta'' + gamma theta' + w0^2 theta = F cos(Omega t + phi), solved by mpmath's
    # Taylor series at 30 digits, against the closed form the scene returns
    theta0, omega0, gamma = 0.05, 0.02, 0.3
    drive = pendula.Drive("torque", 0.02, 1.1, 0.4)
    t = np.array([0.0, 0.7, 2.5, 4.0, 6.0])
    r = pendula.run_model(pendula.Scene(theta0, omega0, t=t, gamma=gamma, drive=drive), "linear")
    assert r.model == "linear" and r.cost["closed_form_evals"] == t.size and r.cost["steps"] == 0
    mp.mp.dps = 30
    try:
        w2, g, f, om, ph = (mp.mpf(2), mp.mpf(gamma), mp.mpf(drive.amplitude), mp.mpf(drive.frequency), mp.mpf(0.4))
        sol = mp.odefun(lambda s, y: [y[1], -g * y[1] - w2 * y[0] + f * mp.cos(om * s + ph)], 0, [theta0, omega0])
        ref = np.array([[float(v) for v in sol(mp.mpf(float(s)))] for s in t])
    finally:
        mp.mp.dps = 15
    scale = 0.1  # rad: the motion's size
    assert np.max(np.abs(r.theta - ref[:, 0])) <= 64 * np.finfo(float).eps * scale
    assert np.max(np.abs(r.omega - ref[:, 1])) <= 64 * np.finfo(float).eps * scale * W0


@pytest.mark.parametrize(
    "theta0, omega0, force, gamma, freq",
    [
        (0.003, -0.002, 2e-3, 0.3, 1.2),  # underdamped, near resonance
        (0.002, 0.0, 1e-3, 0.05, 1.3),  # light damping
        (0.003, 0.001, 2e-3, 2.0, 0.5),  # near critical
        (0.003, 0.0, 2e-3, 4.0, 2.0),  # over-damped
        (0.002, 0.001, 1e-3, 0.0, 0.9),  # undamped, off resonance
        (0.0, 0.0, 3e-3, 0.2, 1.0),  # from rest
    ],
)
def test_small_drive_of_a_small_swing_is_answered_in_closed_form(theta0, omega0, force, gamma, freq):
    # no integration: the linear model, its estimate <= tol, true error <= estimate
    drive = pendula.Drive("torque", force, freq, 0.3)
    t = np.linspace(0.0, 12.0, 61)
    r = pendula.solve(pendula.Scene(theta0, omega0, t=t, gamma=gamma, tol=1e-6, drive=drive))
    assert r.model == "linear" and r.tol_met and "driven" in r.reason
    assert r.cost["steps"] == 0 and r.cost["rhs_evals"] == 0
    theta, omega = _dop853(theta0, omega0, t, gamma, drive)
    true = _sup(r, theta, omega)
    assert true <= r.error_estimate <= 1e-6
    # a bound, not a guess, and not vacuous: 6.6x .. 50x the true error on these (measured)
    assert r.error_estimate <= 200 * true


def test_a_larger_drive_is_integrated_with_an_honest_estimate():
    # the chaotic regime of Baker & Gollub (F = 1.15 w0^2, Omega = 2/3 w0, gamma = w0/2), w0 = 1
    drive = pendula.Drive("torque", 1.15, 2 / 3, 0.0)
    t = np.linspace(0.0, 30.0, 31)
    scene = pendula.Scene(0.2, 0.0, t=t, g=1.0, length=1.0, gamma=0.5, tol=1e-6, drive=drive)
    r = pendula.solve(scene)
    assert r.model == "rk4" and r.tol_met and r.cost["runs"] >= 2
    assert "linearised driven oscillator is off" in r.reason
    assert r.step == pytest.approx(drive.period / round(drive.period / r.step))  # N steps per drive period
    theta, omega = _dop853(0.2, 0.0, t, 0.5, drive, w0=1.0)
    true = _sup(r, theta, omega, w0=1.0)
    assert true <= r.error_estimate <= 1e-6


def test_a_pivot_drive_is_integrated():
    # Kapitza: no closed form for the pivot, the driven RK4 kernel answers
    drive = pendula.Drive("pivot", 0.1, 30.0)
    t = np.linspace(0.0, 3.0, 7)
    r = pendula.solve(pendula.Scene(0.3, t=t, gamma=0.1, tol=1e-7, drive=drive))
    assert r.model == "rk4" and r.tol_met and "pivot" in r.reason
    theta, omega = _dop853(0.3, 0.0, t, 0.1, drive)
    assert _sup(r, theta, omega) <= r.error_estimate


@pytest.mark.parametrize(
    "kw",
    [
        dict(theta0=0.5, t=np.linspace(0, 5, 11)),  # exact
        dict(theta0=0.01, t=np.linspace(0, 5, 11), gamma=0.2),  # linear
        dict(theta0=1.0, t=np.linspace(0, 5, 11), gamma=0.2, tol=1e-7),  # integrated
        dict(theta0=1.0, t=[3.0], gamma=0.2, want="final"),
    ],
)
def test_a_drive_of_amplitude_zero_is_the_undriven_scene(kw):
    plain = pendula.solve(pendula.Scene(**kw))
    zero = pendula.solve(pendula.Scene(**kw, drive=pendula.Drive("torque", 0.0, 1.3)))
    assert zero.model == plain.model and zero.reason == plain.reason
    assert zero.error_estimate == plain.error_estimate
    assert np.array_equal(zero.theta, plain.theta) and np.array_equal(zero.omega, plain.omega)


def test_wants_and_forced_models_with_a_drive():
    drive = pendula.Drive("torque", 0.01, 1.2)
    t = np.linspace(0.0, 4.0, 9)
    final = pendula.solve(pendula.Scene(0.02, t=t, gamma=0.4, drive=drive, want="final"))
    full = pendula.solve(pendula.Scene(0.02, t=t, gamma=0.4, drive=drive))
    assert final.theta.shape == (1,) and final.theta[-1] == full.theta[-1]
    energy = pendula.solve(pendula.Scene(0.02, t=t, gamma=0.4, drive=drive, want="energy"))
    assert np.allclose(energy.energy, full.omega**2 / 2 + 2 * (1 - np.cos(full.theta)), rtol=1e-10, atol=0)
    # rk4 forced on the small scene: verified, agrees with the closed form within both estimates
    rk = pendula.solve(pendula.Scene(0.02, t=t, gamma=0.4, drive=drive, tol=1e-9), model="rk4")
    assert rk.model == "rk4" and rk.tol_met
    # run_model at a fixed step: whole steps per drive period, no verification
    fixed = pendula.run_model(pendula.Scene(0.02, t=t, gamma=0.4, drive=drive), "rk4", 0.05)
    n = int(np.ceil(drive.period / 0.05))
    assert fixed.step == pytest.approx(drive.period / n, rel=1e-15) and fixed.error_estimate == 0
    assert np.max(np.abs(fixed.theta - rk.theta)) < 1e-6
    with pytest.raises(ValueError, match="setting = 5.000E[+]00 is too large"):
        # a slow drive: 8 steps per period of 21 s are too long for w0 = 1.41 (h w0 <= 1.5)
        pendula.run_model(pendula.Scene(0.02, t=t, gamma=0.4, drive=pendula.Drive("torque", 0.01, 0.3)), "rk4", 5.0)


@pytest.mark.parametrize(
    "kw, match",
    [
        (dict(want="events"), "want = events is not offered with a drive"),
        (dict(want="period"), "want = period is not offered with a drive"),
        (dict(model="exact"), "does not apply with a drive"),
        (dict(model="taylor"), "does not apply with a drive"),
        (dict(model="linear", pivot=True), "needs a torque drive"),
    ],
)
def test_what_a_driven_scene_refuses(kw, match):
    drive = pendula.Drive("pivot" if kw.pop("pivot", False) else "torque", 0.01, 1.2)
    model = kw.pop("model", None)
    with pytest.raises(ValueError, match=match):
        pendula.solve(pendula.Scene(0.02, t=[0.0, 1.0], gamma=0.4, drive=drive, **kw), model=model)


def test_drive_must_be_a_drive():
    with pytest.raises(TypeError, match="drive must be a pendula.Drive"):
        pendula.Scene(0.1, t=[1.0], drive=(1.0, 2.0))


def test_a_batch_of_driven_scenes():
    drive = pendula.Drive("torque", 0.002, 1.2, 0.1)
    t = np.linspace(0.0, 5.0, 11)
    batch = pendula.Scene([0.003, 0.002, 1.5], t=t, gamma=0.3, tol=1e-6, drive=drive)
    assert isinstance(batch, pendula.SceneBatch)
    r = pendula.solve(batch)
    assert list(r.model) == ["linear", "linear", "rk4"] and bool(r.tol_met.all())
    for i, sc in enumerate(batch.scenes):
        alone = pendula.solve(sc)
        assert np.array_equal(r.theta[i], alone.theta)
    df = r.to_pandas()
    assert len(df) == 3 * t.size
    one = pendula.solve(batch.scenes[0]).to_pandas()
    assert list(one["theta"]) == list(r.theta[0])


def test_tradeoff_lists_the_driven_models():
    drive = pendula.Drive("torque", 0.005, 1.2)
    scene = pendula.Scene(0.02, t=np.linspace(0.0, 3.0, 7), gamma=0.4, drive=drive)
    table = pendula.tradeoff(scene, rk4_steps=[0.2, 0.1], repeat=1, scipy=False)
    assert set(table.column("model")) == {"linear", "rk4"}
    with pytest.raises(ValueError, match="do not apply"):
        pendula.tradeoff(scene, models=["taylor"], repeat=1, scipy=False)
    # the closed form's row: its true error (against the driven RK4 reference) within its estimate
    row = next(r for r in table.rows if r["model"] == "linear")
    assert row["sup_error"] <= row["error_estimate"]
