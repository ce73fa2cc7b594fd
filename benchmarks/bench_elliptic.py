"""Benchmark pendula's elliptic functions against scipy.special in the same run.

Prints ns/point (best of several interleaved repeats, process CPU time so that
other processes on a shared machine disturb the figures less) and throughput ratios (SciPy time /
pendula time, > 1 means pendula is faster) on N points (default 1e6):

  ellipj   random (u, m): u ~ U(-10, 10), m ~ U(0, 1)
  ellipj   random (u, m): |u| ~ U(20, 1000) of random sign, m ~ U(0, 1)  (many periods;
           its cost is also printed relative to the |u| <= 10 row)
  ellipj   scalar m = 0.7, u ~ U(-10, 10)         (pendulum time series)
  ellipk   m ~ U(0, 1)
  ellipe   m ~ U(0, 1)
  ellipf   phi ~ U(-pi/2, pi/2), m ~ U(0, 1)      (scipy: ellipkinc)

Usage: python3 benchmarks/bench_elliptic.py [--quick] [--n N] [--out DIR]
"""

import time

import harness
import numpy as np
import scipy
import scipy.special as sc

import pendula

LARGE_U = "ellipj random (u, m), 20 <= abs(u) <= 1000"


def cases(n, rng):
    u = rng.uniform(-10, 10, n)
    m = rng.uniform(0, 1, n)
    ubig = rng.uniform(20, 1000, n) * rng.choice([-1.0, 1.0], n)
    phi = rng.uniform(-np.pi / 2, np.pi / 2, n)
    return [
        ("ellipj random (u, m)", lambda: pendula.ellipj(u, m), lambda: sc.ellipj(u, m)),
        (LARGE_U, lambda: pendula.ellipj(ubig, m), lambda: sc.ellipj(ubig, m)),
        ("ellipj scalar m, array u", lambda: pendula.ellipj(u, 0.7), lambda: sc.ellipj(u, 0.7)),
        ("ellipk", lambda: pendula.ellipk(m), lambda: sc.ellipk(m)),
        ("ellipe", lambda: pendula.ellipe(m), lambda: sc.ellipe(m)),
        ("ellipf", lambda: pendula.ellipf(phi, m), lambda: sc.ellipkinc(phi, m)),
    ]


def main(argv=None):
    ap = harness.parser(__doc__, "1e5 points, 3 repeats (a few seconds)", "also write elliptic_bench.md and .csv there")
    args, n, repeat = harness.parse_with_sizes(ap, argv, "points per case (default 1e6)")
    rng = np.random.default_rng(1)
    rows = []
    for _, fp, fs in cases(1000, rng):  # warm up (imports, plan code paths)
        fp(), fs()
    for name, fp, fs in cases(n, rng):
        # CPU time: other processes' load does not count
        tp, ts = harness.best_times_interleaved([fp, fs], repeat, clock=time.process_time, warm_up=False)
        tp, ts = tp / n * 1e9, ts / n * 1e9
        rows.append((name, tp, ts, ts / tp))
    text = f"pendula vs scipy {scipy.__version__}\n\n" + harness.markdown_table(
        ["function", "pendula ns/pt", "scipy ns/pt", "speed-up"],
        [(name, f"{tp:.1f}", f"{ts:.1f}", f"{r:.2f}x") for name, tp, ts, r in rows],
    )
    tpp = {name: t for name, t, _, _ in rows}
    text += f"\n\nellipj cost at |u| in [20, 1000] / at |u| <= 10: {tpp[LARGE_U] / tpp['ellipj random (u, m)']:.2f}"
    print(text)
    harness.write_outputs(
        args.out,
        "elliptic_bench",
        text,
        [
            (
                ["function", "pendula_ns", "scipy_ns", "speedup"],
                [(name, f"{tp:.2f}", f"{ts:.2f}", f"{r:.3f}") for name, tp, ts, r in rows],
            )
        ],
    )


if __name__ == "__main__":
    main()
