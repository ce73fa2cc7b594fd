"""Event scenes: the sample grid the events are placed on is as fine as the motion needs,
and no finer; its spacing comes from the swing about the nearest bottom 2 pi k, not from
the raw angle (theta0 = 4 pi + 0.01 is a 0.01 rad swing).  Event times are checked against
benchmarks/scene_reference.py's Taylor integrator (order 30, ~60 digits, with its events:
kinds 1 turning point, 2 zero crossing)."""
import pathlib

import mpmath as mp
import numpy as np
import pytest

import pendula
from helpers import load_file

_BENCH = pathlib.Path(__file__).resolve().parents[2] / "benchmarks"
ref = load_file(_BENCH / "scene_reference.py")

KW = dict(omega0=0.0, g=9.8, length=4.9, gamma=0.3, t=[0.0, 10.0], tol=1e-8, want="events")


def _true_event_error(r, theta0, g, length, gamma, t_end, omega0=0.0):
    w0 = ref.exact_w0(g, length)
    res = ref.Taylor(w0, gamma, relative=True).solve([0.0, t_end], theta0, omega0, events=True)
    kinds = [pendula.integrate.TURNING_POINT if k == 1 else pendula.integrate.ZERO_CROSSING for k in res[3]]
    if len(r.events.t) != len(kinds) or list(r.events.kind) != kinds:
        return np.inf
    return max((float(abs(mp.mpf(a) - b)) for a, b in zip(r.events.t, res[2])), default=0.0)


@pytest.mark.parametrize("k", [2, -3])
def test_event_grid_follows_the_swing_not_the_multiple_of_two_pi(k):
    """The same 0.01 rad swing about 0 and about 2 pi k: the same grid (equal RK4 work at a
    fixed step) and the same event times, to the rounding of theta0 (eps |2 pi k| over the
    rate, ~1e-13 s).  The grid used to be sized for a |2 pi k| rad swing: 7x denser at k = 2."""
    near = pendula.run_model(pendula.Scene(theta0=0.01, **KW), "rk4", 0.01)
    far = pendula.run_model(pendula.Scene(theta0=2 * k * np.pi + 0.01, **KW), "rk4", 0.01)
    assert far.cost["rhs_evals"] == near.cost["rhs_evals"]
    assert len(far.events.t) == len(near.events.t) > 0
    assert list(far.events.kind) == list(near.events.kind)
    np.testing.assert_allclose(far.events.t, near.events.t, rtol=0, atol=1e-11)


@pytest.mark.parametrize("theta0", [4 * np.pi + 0.01, -2 * np.pi - 0.2])
def test_events_about_a_far_bottom_are_honest(theta0):
    """solve() near 2 pi k: the reported event-time error (finite: the count is verified)
    bounds the true one, and tol_met says whether it fits tol."""
    r = pendula.solve(pendula.Scene(theta0=theta0, **KW))
    err = _true_event_error(r, theta0, KW["g"], KW["length"], KW["gamma"], KW["t"][-1])
    assert err <= r.event_time_error < np.inf
    assert r.tol_met == (r.error_estimate <= KW["tol"])
