"""Accuracy of the linear damped pendulum against mpmath: the table of docs/guide/linear.md.

The reference and the error measure are the tests' (tests/python/test_linear_damped.py:
mpmath at 50 digits at the exact double inputs; error / (eps (size + cond)) with
size = |theta| + |Omega|/max(w0, gamma), cond = sum |x d theta/dx| over t, theta0, Omega0,
w0, gamma, and an allowance of 2^-1022 for results that underflow).  Rows: the tests'
grid per gamma/w0 (their times and initial states), then two seeded sweeps of this
script's own: gamma/w0 over [1e-10, 1e8] and within 1e-3 of critical, and extreme
scales (w0 in [1e-100, 1e100], theta0, Omega0/w0 in [1e-50, 1e50]).  Lives in
benchmarks/ beside the speed tables (it shares their command line and --out files,
harness.py); it takes about ten seconds.

    python benchmarks/accuracy_linear.py [--out DIR]     (writes DIR/accuracy_linear.md)
"""
import math

import numpy as np

import harness
import pendula

T = harness.load_test_module("test_linear_damped")


def _g(x):
    """Two significant digits, exponent without + and leading zeros (1.8e3)."""
    return f"{x:.2g}".replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")


def _measure(t, th0, om0, w0, g):
    """[(error / (eps (size + cond)), error / (eps size))] at each point."""
    th, om = pendula.linear_damped(t, th0, om0, w0, g)
    return np.array([T.error_ratio(*args) for args in zip(t, th0, om0, w0, g, th, om)])


def grid_rows():
    rows = []
    for label, ratio in T.RATIOS.items():
        pts = [(t, th0, om0, w0, ratio * w0) for w0 in (math.sqrt(2.0), 0.37)
               for th0, om0 in T.ICS for t in T._grid(w0, ratio)]
        e = _measure(*map(np.array, zip(*pts)))
        rows.append([f"{label}", len(pts), f"{e[:, 0].max():.2f}", _g(np.median(e[:, 0])),
                     _g(e[:, 1].max())])
    return rows


def _sweep(seed, n, log_w0, log_scale, p_far, log_far, log_near, p_zero, log_wt):
    """n seeded states and times: gamma/w0 log-uniform (probability p_far) or 2(1 +- 10^x)."""
    rng = np.random.default_rng(seed)
    w0 = 10 ** rng.uniform(*log_w0, n)
    ratio = np.where(rng.random(n) < p_far, 10 ** rng.uniform(*log_far, n),
                     2 * (1 + rng.choice([-1, 1], n) * 10 ** rng.uniform(*log_near, n)))
    ratio[rng.random(n) < p_zero] = 0
    t = 10 ** rng.uniform(*log_wt, n) / w0
    th0 = rng.uniform(-1, 1, n) * 10 ** rng.uniform(-log_scale, log_scale, n)
    om0 = rng.uniform(-1, 1, n) * w0 * 10 ** rng.uniform(-log_scale, log_scale, n)
    return t, th0, om0, w0, ratio * w0


def sweep_rows():
    sweeps = [("seeded sweep: γ/w0 ∈ [1e-10, 1e8] and within 1e-3 of critical, w0 ∈ [1e-3, 1e3]",
               _sweep(20261201, 300, (-3, 3), 0, 0.5, (-10, 8), (-16, -3), 0.0, (-6, 4))),
              ("extreme scales: w0 ∈ [1e-100, 1e100], θ0, Ω0/w0 ∈ [1e-50, 1e50]",
               _sweep(20261202, 400, (-100, 100), 50, 0.3, (-15, 12), (-16, 0), 0.05, (-8, 6)))]
    rows = []
    for label, args in sweeps:
        e = _measure(*args)
        rows.append([label, len(e), f"{e[:, 0].max():.2f}", _g(np.median(e[:, 0])), "—"])
    return rows


def main():
    args = harness.parser(__doc__, "(no effect: the measurement takes seconds)", "write accuracy_linear.md into DIR").parse_args()
    rows = grid_rows() + sweep_rows()
    head = ["γ/w0", "points", "worst [eps·(size + cond)]", "median [eps·(size + cond)]", "worst [eps·size]"]
    md = harness.markdown_table(head, rows)
    print(md)
    harness.write_outputs(args.out, "accuracy_linear", md,
                          [(["gamma/w0", "points", "worst cond", "median cond", "worst size"], rows)])


if __name__ == "__main__":
    main()
