"""pendula.lyapunov's ensemble and its 95 % error bound.

The reference is a long run of the same RK4 map (N = 64 steps per period,
the default): 128 orbits x 125,000 periods, with its standard error
(benchmarks/bench_driven.py --reference recomputes it; N = 128 there bounds
the step's bias).
"""

import numpy as np
import pytest

import pendula
from pendula._codes import LYAPUNOV_DEFAULT_STEPS

BG = dict(w0=1.0, gamma=0.5)  # Baker & Gollub's q = 2
CHAOS = pendula.Drive("torque", 1.15, 2 / 3)
REFERENCE, REFERENCE_SE = 0.099387, 0.000037  # N = 64, [1/s]


def test_the_reference_is_for_the_default_step():
    assert LYAPUNOV_DEFAULT_STEPS == 64


def test_short_runs_error_bounds_cover_the_long_reference():
    # 40 independent ensembles of 1000 periods: a 95 % bound should miss about 2 of them
    starts = np.linspace(-2.0, 2.0, 40)
    r = pendula.lyapunov(starts, 0.0, drive=CHAOS, **BG, periods=1000)
    lam, err = r.exponents[:, 0], r.errors[:, 0]
    assert np.all(r.ok) and np.all(err > 0)
    inside = np.abs(lam - REFERENCE) <= err
    assert inside.mean() >= 0.85, (lam, err)
    # and the bound is not inflated: about 1.96 (95 %) times the scatter of the estimates
    ratio = np.median(err) / (1.96 * lam.std(ddof=1))
    assert 0.6 < ratio < 1.6, ratio
    # the exact check: the exponents sum to -gamma (up to the RK4 error of log det at N = 64)
    assert np.max(np.abs(r.exponents.sum(axis=-1) + 0.5)) < 2e-5


def test_the_default_run_gives_three_digits():
    r = pendula.lyapunov(0.2, 0.0, drive=CHAOS, **BG)
    assert r.errors[0] <= 0.0005 and abs(r.exponents[0] - REFERENCE) <= r.errors[0], (r.exponents, r.errors)


def test_one_copy_follows_the_given_orbit_and_copies_only_average():
    one = pendula.lyapunov([0.2, 0.7], 0.0, drive=CHAOS, **BG, transient=10, periods=32, orbits=1)
    alone = pendula.lyapunov(0.7, 0.0, drive=CHAOS, **BG, transient=10, periods=32, orbits=1)
    assert np.array_equal(one.exponents[1], alone.exponents)
    three = pendula.lyapunov([0.2, 0.7], 0.0, drive=CHAOS, **BG, transient=10, periods=32, orbits=3)
    assert np.array_equal(
        three.exponents[1], pendula.lyapunov(0.7, 0.0, drive=CHAOS, **BG, transient=10, periods=32, orbits=3).exponents
    )
    assert not np.array_equal(three.exponents, one.exponents)


@pytest.mark.parametrize("orbits", [0, 9])
def test_orbits_out_of_range_is_named(orbits):
    with pytest.raises(ValueError, match="orbits"):
        pendula.lyapunov(0.2, 0.0, drive=CHAOS, **BG, periods=16, orbits=orbits)
