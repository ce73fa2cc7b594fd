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
  ellipk   near m = 1: 1 - m = 10**U(-15, -1), passed as m (scipy: ellipk(m) too)
  ellipe   near m = 1: the same m
  ellipkm1 near m = 1: p = 1 - m = 10**U(-15, -1) itself (scipy: ellipkm1(p))
  ellipf   phi ~ U(-pi/2, pi/2), m ~ U(0, 1)      (scipy: ellipkinc)

and Boost.Math's double-precision F (ellint_1 with promote_double<false>) on the same
distribution, through the C++ peer benchmarks/ellipf_boost_peer.cpp compiled here
with c++ -O2 (skipped without a C++ compiler or the Boost headers), its CPU time
taken in turns with pendula's.  The targets, as ratios of this run, close the table.

Usage: python3 benchmarks/bench_elliptic.py [--quick] [--n N] [--out DIR]
"""

import os
import pathlib
import shutil
import subprocess
import tempfile
import time

import harness
import numpy as np
import scipy
import scipy.special as sc

import pendula

LARGE_U = "ellipj random (u, m), 20 <= abs(u) <= 1000"
HERE = pathlib.Path(__file__).resolve().parent
# (target, row, goal): speed-up >= goal in this run
TARGETS = [
    ("ellipj >= 3x SciPy", "ellipj random (u, m)", 3.0),
    ("ellipf >= 2x SciPy", "ellipf", 2.0),
    ("ellipk >= 1.2x SciPy, uniform m", "ellipk", 1.2),
    ("ellipe >= 1.2x SciPy, uniform m", "ellipe", 1.2),
    ("ellipk >= 1.0x SciPy near m = 1", "ellipk near m = 1", 1.0),
    ("ellipe >= 1.0x SciPy near m = 1", "ellipe near m = 1", 1.0),
]


def cases(n, rng):
    u = rng.uniform(-10, 10, n)
    m = rng.uniform(0, 1, n)
    ubig = rng.uniform(20, 1000, n) * rng.choice([-1.0, 1.0], n)
    phi = rng.uniform(-np.pi / 2, np.pi / 2, n)
    p_near = 10 ** rng.uniform(-15, -1, n)
    near = 1 - p_near
    return [
        ("ellipj random (u, m)", lambda: pendula.ellipj(u, m), lambda: sc.ellipj(u, m)),
        (LARGE_U, lambda: pendula.ellipj(ubig, m), lambda: sc.ellipj(ubig, m)),
        ("ellipj scalar m, array u", lambda: pendula.ellipj(u, 0.7), lambda: sc.ellipj(u, 0.7)),
        ("ellipk", lambda: pendula.ellipk(m), lambda: sc.ellipk(m)),
        ("ellipe", lambda: pendula.ellipe(m), lambda: sc.ellipe(m)),
        ("ellipk near m = 1", lambda: pendula.ellipk(near), lambda: sc.ellipk(near)),
        ("ellipe near m = 1", lambda: pendula.ellipe(near), lambda: sc.ellipe(near)),
        ("ellipkm1 near m = 1", lambda: pendula.ellipkm1(p_near), lambda: sc.ellipkm1(p_near)),
        ("ellipf", lambda: pendula.ellipf(phi, m), lambda: sc.ellipkinc(phi, m)),
    ]


def boost_peer(n, repeat, rng):
    """(pendula ns/pt, Boost ns/pt, how) for F on phi ~ U(-pi/2, pi/2), m ~ U(0, 1), the
    peer's CPU time and pendula's taken in turns; (None, None, why) without the peer."""
    cxx = shutil.which(os.environ.get("CXX", "c++"))
    if cxx is None:
        return None, None, "no C++ compiler"
    phi = rng.uniform(-np.pi / 2, np.pi / 2, n)
    m = rng.uniform(0, 1, n)
    with tempfile.TemporaryDirectory() as tmp:
        exe = pathlib.Path(tmp) / "ellipf_boost_peer"
        build = subprocess.run(
            [cxx, "-O2", str(HERE / "ellipf_boost_peer.cpp"), "-o", str(exe)], capture_output=True, text=True
        )
        if build.returncode != 0:
            return None, None, "Boost peer not built (Boost.Math headers missing?)"
        tp = tb = float("inf")
        for _ in range(3):  # in turns: the machine's load falls on both
            run = subprocess.run(
                [str(exe), str(n), str(max(1, repeat // 3))], check=True, capture_output=True, text=True
            )
            tb = min(tb, float(run.stdout.split()[0]))
            tp = min(
                tp, harness.best_time(lambda: pendula.ellipf(phi, m), max(1, repeat // 3), clock=time.process_time)
            )
    return tp / n * 1e9, tb / n * 1e9, "Boost.Math ellint_1, double (promote_double<false>), c++ -O2"


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
    tp, tb, how = boost_peer(n, repeat, rng)
    if tp is None:
        text += f"\n\nBoost peer: skipped ({how})"
    else:
        text += "\n\nF against Boost (" + how + "), same inputs' distribution, taken in turns:\n\n"
        text += harness.markdown_table(
            ["function", "pendula ns/pt", "Boost ns/pt", "speed-up"],
            [("ellipf", f"{tp:.1f}", f"{tb:.1f}", f"{tb / tp:.2f}x")],
        )
    speed = {name: r for name, _, _, r in rows}
    cells = [(t, f">= {g:g}x", f"{speed[row]:.2f}x", "yes" if speed[row] >= g else "no") for t, row, g in TARGETS]
    if tp is not None:
        cells.append(("ellipf faster than Boost's double F", "> 1x", f"{tb / tp:.2f}x", "yes" if tb > tp else "no"))
    text += "\n\nThe targets, as ratios measured in this run:\n\n" + harness.markdown_table(
        ["target", "goal", "measured", "met"], cells
    )
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
