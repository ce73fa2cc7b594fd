"""The seeded grid of scenes of benchmarks/bench_scenes.py (plain data, no pendula).

Scene i (of 432, seed 17) takes
- its damping from i mod 4: undamped (two classes of four), gamma/w0
  log-uniform in [1e-4, 100], or critical 2 w0 (1 + s d) with d in
  {0, 1e-12, 1e-9, 1e-6} and s = +-1 (w0 = sqrt(g/l) exactly, in mpmath);
- its start from (i // 4) mod 6: small |theta0| = 10^U(-8, -2); medium U(0.01, 2);
  near the top pi - 10^U(-8, -1); exactly pi (omega0 = 0 or tiny); a rotation with
  energy parameter m = 10^U(0, 1); separatrix-adjacent m = 1 +- 10^U(-14, -3)
  (omega0 from m, rounded to double); classes 0-2 get a random omega0 half the time;
- a shift theta0 + 2 pi k, k in +-1..3, one time in four;
- g = U(1, 25) and l = 10^U(-1, 1) rounded to 3 decimals (so w0 is irrational);
- a window of 10^U(-1, 4) small-angle periods 2 pi/w0, tol = 10^U(-10, -2);
- want: uniformly one of the wants that apply (period only when undamped);
- time grid: uniform, shifted (from a random start), random, geometric
  (from 1e-6 of the window) or scalar, with 2 .. 200 points.
"""

import math

import mpmath as mp
import numpy as np

WANTS = ("state", "theta", "final", "energy", "period", "events")
GRIDS = ("uniform", "shifted", "random", "geometric", "scalar")
START = ("small", "medium", "near_top", "top", "rotation", "separatrix")


def _grid(rng, kind, t_end):
    n = int(round(10 ** rng.uniform(np.log10(2), np.log10(200))))
    if kind == "scalar":
        return t_end
    if kind == "uniform":
        t = np.linspace(0.0, t_end, n)
    elif kind == "shifted":
        t = np.linspace(t_end * rng.uniform(0.05, 0.95), t_end, n)
    elif kind == "random":
        t = np.unique(np.append(rng.uniform(0, t_end, n - 1), t_end))
    else:
        t = np.geomspace(t_end * 1e-6, t_end, n)
    t[-1] = t_end
    return t


def draw(n=432, seed=17):
    """The grid: a list of dicts (theta0, omega0, g, length, gamma, t, tol, want, and
    the labels damping, start, shift, grid, periods)."""
    rng = np.random.default_rng(seed)
    scenes = []
    for i in range(n):
        g = round(rng.uniform(1, 25), 3)
        length = round(10 ** rng.uniform(-1, 1), 3)
        with mp.workdps(40):
            w0 = mp.sqrt(mp.mpf(g) / mp.mpf(length))
            dclass = i % 4
            if dclass < 2:
                gamma, damping = 0.0, "undamped"
            elif dclass == 2:
                gamma, damping = float(w0 * 10 ** rng.uniform(-4, 2)), "damped"
            else:
                d = [0, 1e-12, 1e-9, 1e-6][rng.integers(4)] * rng.choice([-1, 1])
                gamma, damping = float(2 * w0 * (1 + mp.mpf(d))), f"critical{d:+.0e}"
            start = START[(i // 4) % 6]
            sgn = rng.choice([-1.0, 1.0])
            omega0 = 0.0
            if start == "small":
                theta0 = sgn * 10 ** rng.uniform(-8, -2)
            elif start == "medium":
                theta0 = sgn * rng.uniform(0.01, 2)
            elif start == "near_top":
                theta0 = sgn * (math.pi - 10 ** rng.uniform(-8, -1))
            elif start == "top":
                theta0 = sgn * math.pi
                omega0 = 0.0 if rng.uniform() < 0.5 else float(w0 * 10 ** rng.uniform(-12, -6))
            else:
                if start == "rotation":
                    m = mp.mpf(10) ** rng.uniform(0, 1)
                    theta0 = rng.uniform(-math.pi, math.pi)
                else:
                    m = 1 + rng.choice([-1, 1]) * mp.mpf(10) ** rng.uniform(-14, -3)
                    theta0 = rng.uniform(-2.5, 2.5)
                omega0 = float(sgn * 2 * w0 * mp.sqrt(m - mp.sin(mp.mpf(theta0) / 2) ** 2))
            if start in ("small", "medium", "near_top") and rng.uniform() < 0.5:
                omega0 = float(w0 * abs(theta0) * rng.uniform(-1, 1))
            shift = 0
            if rng.uniform() < 0.25:
                shift = int(rng.choice([-3, -2, -1, 1, 2, 3]))
                theta0 = float(theta0 + 2 * math.pi * shift)
            periods = 10 ** rng.uniform(-1, 4)
            t_end = float(periods * 2 * mp.pi / w0)
        tol = 10 ** rng.uniform(-10, -2)
        wants = WANTS if gamma == 0 else WANTS[:4] + WANTS[5:]
        want = wants[rng.integers(len(wants))]
        grid = GRIDS[rng.integers(len(GRIDS))]
        t = _grid(rng, grid, t_end)
        scenes.append(
            dict(
                id=i,
                theta0=float(theta0),
                omega0=float(omega0),
                g=g,
                length=length,
                gamma=gamma,
                t=t,
                tol=float(tol),
                want=want,
                damping=damping,
                start=start,
                shift=shift,
                grid=grid,
                periods=float(periods),
            )
        )
    return scenes
