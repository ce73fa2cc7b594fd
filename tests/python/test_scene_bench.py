"""The reference machinery of benchmarks/bench_scenes.py (benchmarks/scene_reference.py),
checked against independent mpmath solutions -- not pendula's honesty (that is
the benchmark's job, and not a test).

Tolerances: 1e-25 absolute in theta [rad] and Omega/w0, and in event times
w0 t; the Taylor integrator keeps a 1e-30 tail per step in ~60-digit fixed
point, the elliptic reference works at 40 digits.
"""

import pathlib

import mpmath as mp
import pytest
from helpers import load_file

_PATH = pathlib.Path(__file__).resolve().parents[2] / "benchmarks" / "scene_reference.py"
ref = load_file(_PATH)

TOL = mp.mpf("1e-25")
W0 = ref.exact_w0(9.81, 2.3)  # irrational: the data as given, not fl(sqrt)


def _gap(a, b, scale=1):
    return max(abs(x - y) / scale for x, y in zip(a, b))


@pytest.mark.parametrize(
    "theta0, omega0",
    [
        (1.0, 0.0),  # libration from rest
        (3.0, 0.5),  # large libration
        (0.3, -5.0),  # rotation, backwards
        (-4 * 3.141592653589793 + 0.5, 0.1),  # start shifted by -2 pi 2
        (2.0, 2 * float(W0) * 0.99999),  # just over the separatrix
    ],
)
def test_taylor_matches_elliptic_undamped(theta0, omega0):
    t = [0.0, 0.37, 3.0, 11.0]
    th, om, _ = ref.undamped(t, theta0, omega0, W0)
    tay = ref.Taylor(W0, 0)
    th2, om2 = tay.solve(t, theta0, omega0)
    assert _gap(th, th2) < TOL
    assert _gap(om, om2, W0) < TOL


def test_elliptic_reference_solves_the_equation():
    # independent of the Taylor code: energy conserved and theta' = Omega by a central difference
    theta0, omega0 = 2.5, -1.0
    f = lambda x: ref.undamped([x], theta0, omega0, W0)[0][0]
    with mp.workdps(40):
        for x in (mp.mpf("0.5"), mp.mpf("7.25")):
            th, om, _ = ref.undamped([x], theta0, omega0, W0)
            h = mp.mpf("1e-12")  # central difference: error ~ h^2 theta''' / 6 ~ 1e-24
            assert abs((f(x + h) - f(x - h)) / (2 * h) - om[0]) < mp.mpf("1e-22")
            e = om[0] ** 2 / 2 + W0**2 * (1 - mp.cos(th[0]))
            e0 = mp.mpf(omega0) ** 2 / 2 + W0**2 * (1 - mp.cos(mp.mpf(theta0)))
            assert abs(e - e0) < mp.mpf("1e-35")


@pytest.mark.parametrize("gamma", [0.3, 2 * float(W0), 9.0])
def test_taylor_matches_mpmath_odefun_damped(gamma):
    theta0, omega0 = 2.8, 1.0
    t = [0.25, 1.0, 1.5]
    tay = ref.Taylor(W0, gamma)
    th, om = tay.solve(t, theta0, omega0)
    with mp.workdps(35):
        g = mp.mpf(gamma)
        sol = mp.odefun(lambda _, y: [y[1], -g * y[1] - W0**2 * mp.sin(y[0])], 0, [mp.mpf(theta0), mp.mpf(omega0)])
        ys = [sol(mp.mpf(x)) for x in t]
    assert _gap(th, [y[0] for y in ys]) < TOL
    assert _gap(om, [y[1] for y in ys], W0) < TOL


@pytest.mark.parametrize("gamma", [1.5, 2 * float(W0), 40.0])
def test_linear_handover_matches_taylor(gamma):
    # the settled motion handed to the linear solution agrees with integrating on
    t = [5.0, 20.0, 40.0]
    theta0, omega0 = 1.0 + 2 * 3.141592653589793, 0.0
    th, om = ref.Taylor(W0, gamma).solve(t, theta0, omega0)
    th2, om2 = ref.Taylor(W0, gamma).solve(t, theta0, omega0, handover=False)
    assert _gap(th, th2) < TOL
    assert _gap(om, om2, W0) < TOL


def test_taylor_events_match_elliptic_times():
    # from rest at theta0 = 1: u0 = K, turning points at w0 t = 2jK, zero crossings at K + 2jK
    theta0 = 1.0
    with mp.workdps(40):
        m = mp.sin(mp.mpf(theta0) / 2) ** 2
        K = mp.ellipk(m)
        t_end = 9 * K / W0 + mp.mpf("0.1")
        expect = sorted([(2 * j * K / W0, 1) for j in range(1, 5)] + [((2 * j + 1) * K / W0, 2) for j in range(5)])
    _, _, times, kinds = ref.Taylor(W0, 0, relative=True).solve([float(t_end)], theta0, 0.0, events=True)
    assert kinds == [k for _, k in expect]
    assert max(abs(a - b) * W0 for a, (b, _) in zip(times, expect)) < TOL


def test_budget_is_enforced():
    with pytest.raises(ref.BudgetExceeded):
        ref.Taylor(W0, 0, max_steps=50).solve([1000.0], 1.0, 0.0)
