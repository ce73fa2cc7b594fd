"""Scenes do only the work their answer needs (issue: "model only what a scene requires").

Work is counted, never timed: closed-form evaluations, RK4 steps, the model chosen.  Each
case also checks the answer against an independent reference or an invariant, so that a
cheaper path never buys its economy with accuracy.
"""

import mpmath as mp
import numpy as np
import pytest
from helpers import ROOT, load_file

import pendula
from pendula._codes import TAYLOR_STEP_COST

ref = load_file(ROOT / "benchmarks" / "scene_reference.py")


def test_exact_answer_is_the_same_with_and_without_a_jacobi_plan():
    """One output gets a light motion (ellipjm1 per point), 256 outputs a tabulated plan:
    at the same times the two agree to a few ulps, also at the top where the plan's table
    is ~20x dearer (the plan is only built where it pays)."""
    for theta0, omega0 in [(2.5, 0.3), (np.pi, 0.0), (-np.pi, 1.8e-11), (0.1, 4.0)]:
        many = np.linspace(0.0, 3.0, 256)
        a = pendula.solve(pendula.Scene(theta0, omega0, t=many, tol=1e-6), model="exact")
        for i in (1, 97, 255):
            b = pendula.solve(pendula.Scene(theta0, omega0, t=[many[i]], tol=1e-6), model="exact")
            scale = abs(a.theta[i]) + 2 * np.pi
            assert abs(b.theta[0] - a.theta[i]) <= 16 * np.finfo(float).eps * scale, (theta0, i)
            assert abs(b.omega[0] - a.omega[i]) <= 16 * np.finfo(float).eps * (abs(a.omega[i]) + 1)


def test_top_start_with_one_output_is_exact_and_cheap():
    """theta0 = fl(pi): one output costs one closed-form evaluation, and the answer is
    the elliptic solution (mpmath, exact data) to the reported estimate."""
    t = 0.25753737533165993
    g, length = 12.843, 0.861
    s = pendula.Scene(theta0=np.pi, omega0=0.0, t=t, g=g, length=length, tol=5.55e-4, want="theta")
    r = pendula.solve(s)
    assert r.model == "exact" and r.tol_met
    assert r.cost["closed_form_evals"] == 1
    th, _, _ = ref.undamped([t], np.pi, 0.0, ref.exact_w0(g, length))
    assert abs(mp.mpf(float(r.theta[0])) - th[0]) <= max(r.error_estimate, 1e-15)


def test_small_angle_events_are_skipped_when_their_times_would_miss_tol():
    """A 9e-4 rad swing: the small-angle state bound (3e-8 rad) meets tol, but its event
    times are off by that bound over the rate at the events (2.3e-5 s > tol): the solve goes
    straight to the exact solution, with no small-angle events computed first."""
    s = pendula.Scene(
        theta0=0.000893261630311742,
        omega0=0.0,
        g=1.242,
        length=0.597,
        t=np.linspace(0.0, 468.98, 13),
        tol=2.15e-07,
        want="events",
    )
    r = pendula.solve(s)
    assert r.model == "exact" and r.tol_met, r.reason
    assert "event times" in r.reason
    alone = pendula.run_model(s, "exact")
    assert r.cost["closed_form_evals"] == alone.cost["closed_form_evals"]
    np.testing.assert_array_equal(r.events.t, alone.events.t)
    # turning points a half period apart, the period from the elliptic solution
    period = pendula.period(s.theta0, 0.0, s.w0)
    turns = r.events.t[r.events.kind == pendula.integrate.TURNING_POINT]
    assert np.max(np.abs(np.diff(turns) - period / 2)) <= 1e-9


def test_an_output_at_t0_does_not_force_the_whole_decay_to_tol():
    """Outputs at t = 0 and after the motion has decayed by e^-100: the output at t = 0 is
    the initial state itself, so the integrated part before the hand-over runs at the
    loosened tolerance (it took h = 0.003 there, 57x more steps, when t = 0 counted)."""
    kw = dict(
        theta0=-1.055204151935069,
        omega0=-1.1239455931787095,
        g=5.278,
        length=0.785,
        gamma=5.1859683296246395,
        tol=1.87e-10,
        want="state",
    )
    late = np.linspace(51.27, 256.33, 5)
    with0 = pendula.solve(pendula.Scene(t=np.concatenate([[0.0], late]), **kw))
    without = pendula.solve(pendula.Scene(t=late, **kw))
    assert with0.tol_met and without.tol_met
    assert with0.step == without.step
    assert with0.theta[0] == kw["theta0"] and with0.omega[0] == kw["omega0"]
    np.testing.assert_array_equal(with0.theta[1:], without.theta)


@pytest.mark.parametrize("gamma_over_2w0", [1.0, 1.0 - 1e-9, 1.0 + 1e-6])
def test_critically_damped_handover_succeeds_at_the_first_try(gamma_over_2w0):
    """Near critical damping the decay is (1 + w0 t) e^(-w0 t), slower than e^(-w0 t): the
    predicted hand-over time counts the polynomial factor, so the first try succeeds (at
    most one RK4 pair and its refinement, 4 runs; a too early prediction failed and cost
    a second try: 8 runs, twice the steps).  RK4 is forced: the auto choice is the Taylor
    series up to the hand-over (one run, ~20 steps of ~16 RK4 steps each against RK4's
    ~1600), which must be cheaper than RK4's hand-over in counted work and as honest."""
    w0 = pendula.Scene(0.0, want="period").w0
    s = pendula.Scene(
        theta0=-1.2, omega0=-0.03, t=np.linspace(0, 20, 89), gamma=2 * w0 * gamma_over_2w0, tol=6.8e-8, want="state"
    )
    th, om = ref.Taylor(ref.exact_w0(9.8, 4.9), s.gamma).solve(list(s.t), s.theta0, s.omega0)[:2]

    def error(r):
        pairs = zip(r.theta, r.omega, th, om)
        return max(max(abs(mp.mpf(float(a)) - x), abs(mp.mpf(float(b)) - y) / w0) for a, b, x, y in pairs)

    r = pendula.solve(s, model="rk4")
    assert r.model == "rk4" and r.tol_met and "decayed by" in r.reason, r.reason
    assert r.cost["runs"] <= 4, r.cost
    assert error(r) <= r.error_estimate
    auto = pendula.solve(s)
    assert auto.model == "taylor" and auto.tol_met and "decayed by" in auto.reason, auto.reason
    assert auto.cost["runs"] == 1 and auto.cost["steps"] * TAYLOR_STEP_COST < r.cost["steps"] / 2, (auto.cost, r.cost)
    assert error(auto) <= auto.error_estimate <= s.tol


def test_rk4_refinement_progresses_when_outputs_are_denser_than_the_step():
    """28 outputs 0.02 s apart and an a priori step of 0.137 s: every interval took two
    substeps whatever h above 0.01, so refining h from the h^4 law changed nothing and four
    identical pairs failed before CVODE took over.  The refinement now works from the step
    the run took; RK4 meets tol, and reports that step."""
    grid = load_file(ROOT / "benchmarks" / "scene_grid_draw.py")
    sc = grid.draw()[359]
    s = pendula.Scene(
        theta0=sc["theta0"],
        omega0=sc["omega0"],
        t=sc["t"],
        g=sc["g"],
        length=sc["length"],
        gamma=sc["gamma"],
        tol=sc["tol"],
        want="state",
    )
    r = pendula.solve(s)
    assert r.model == "rk4" and r.tol_met, r.reason
    assert r.step <= np.max(np.diff(np.concatenate([[0.0], s.t]))) / 2
    th, om = ref.Taylor(ref.exact_w0(sc["g"], sc["length"]), s.gamma).solve(list(s.t), s.theta0, s.omega0)[:2]
    err = max(
        max(abs(mp.mpf(float(a)) - x), abs(mp.mpf(float(b)) - y) / s.w0) for a, b, x, y in zip(r.theta, r.omega, th, om)
    )
    assert err <= r.error_estimate <= s.tol


@pytest.mark.parametrize(
    "theta0, omega0, gamma_over_2w0",
    [
        (-3.141592331462198, 0.0, 1.0),  # 3e-7 rad from the top, critical damping
        (2.0, -1.0, 1.0),  # moving towards the bottom, inside the sector
        (-2.5, 0.3, 3.0),  # over-damped, moving towards the bottom
        (-1.0, 0.0, 1.0 + 1e-9),
    ],
)
def test_no_events_when_the_sector_traps_the_motion(theta0, omega0, gamma_over_2w0):
    """gamma >= 2 w0 and a start in the sector 0 <= -Omega sign(theta) <= lambda |theta|
    (|theta| < pi): the pendulum never leaves it (d(Omega + lambda theta)/dt = w0^2 (theta - sin
    theta) >= 0 on its edge), so there is no event after t = 0.  The solve says so at once
    (it integrated the hang at the top for 20 s, or the whole window, to find nothing); a
    Taylor integration of the pendulum itself finds no sign change of theta or Omega."""
    w0 = pendula.Scene(0.0, want="period").w0
    gamma = 2 * w0 * gamma_over_2w0
    s = pendula.Scene(theta0, omega0, t=60.0, gamma=gamma, tol=1e-10, want="events")
    r = pendula.solve(s)
    assert r.model == "linear" and r.tol_met and "never leaves" in r.reason, r.reason
    assert r.events.t.size == 0 and r.event_time_error == 0
    t = list(np.linspace(0.0, 60.0, 121)[1:])
    th, om = ref.Taylor(ref.exact_w0(9.8, 4.9), gamma).solve(t, theta0, omega0)[:2]
    assert all(x * theta0 > 0 for x in th)
    assert all(v * theta0 <= 0 for v in om)


def test_outside_the_sector_the_events_are_found():
    """Thrown away from the bottom (Omega0 theta0 > 0) or just under critical damping, the
    theorem does not apply and the events come from the integrated motion."""
    w0 = pendula.Scene(0.0, want="period").w0
    for theta0, omega0, g in [(1.0, 0.5, 2 * w0), (1.0, 0.0, 2 * w0 * (1 - 1e-3))]:
        r = pendula.solve(pendula.Scene(theta0, omega0, t=60.0, gamma=g, tol=1e-8, want="events"))
        assert "never leaves" not in r.reason


def test_an_oscillation_that_decays_below_the_doubles_before_its_next_event_is_verified():
    """Damped just under critical, the first zero crossing comes ~700 s after the start, long
    after the motion has decayed below the smallest double: the phase of the next event is
    known in closed form, so the scan that stops at the underflow still verifies that none
    lies in the window (it used to report the count unverified and integrate the whole window
    again, 420 ms instead of under 1)."""
    grid = load_file(ROOT / "benchmarks" / "scene_grid_draw.py")
    sc = grid.draw()[155]
    s = pendula.Scene(
        theta0=sc["theta0"],
        omega0=sc["omega0"],
        t=sc["t"],
        g=sc["g"],
        length=sc["length"],
        gamma=sc["gamma"],
        tol=sc["tol"],
        want="events",
    )
    r = pendula.solve(s)
    assert r.tol_met and r.events.t.size == 0, r.reason
    assert "the linear closed form" in r.reason
    assert r.cost["steps"] < 1e5
