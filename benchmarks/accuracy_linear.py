"""Accuracy of the linear damped pendulum against mpmath: the table of docs/guide/linear.md.

The reference and the error measure are the tests' (tests/python/test_linear_damped.py:
mpmath at 50 digits at the exact double inputs; error / (eps (size + cond)) with
size = |theta| + |Omega|/max(w0, gamma), cond = sum |x d theta/dx| over t, theta0, Omega0,
w0, gamma, and an allowance of 2^-1022 for results that underflow).  Rows: the tests'
grid per gamma/w0 (their times and initial states), then two seeded sweeps of this
script's own: gamma/w0 over [1e-10, 1e8] and within 1e-3 of critical, and extreme
scales (w0 in [1e-100, 1e100], theta0, Omega0/w0 in [1e-50, 1e50]).  Then the text's own
formulas (figs 10-13: eqs 2.27-2.29 over-damped, 2.45-2.47 critical) against pendula on the
figures' grids, and both against mpmath at gamma = 2 w0 (1 + 1e-12).  Lives in
benchmarks/ beside the speed tables (it shares their command line and --out files,
harness.py); it takes about ten seconds.

    python benchmarks/accuracy_linear.py [--out DIR]     (writes DIR/accuracy_linear.md)
"""

import math

import harness
import numpy as np

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
        pts = [
            (t, th0, om0, w0, ratio * w0)
            for w0 in (math.sqrt(2.0), 0.37)
            for th0, om0 in T.ICS
            for t in T._grid(w0, ratio)
        ]
        e = _measure(*map(np.array, zip(*pts)))
        rows.append([f"{label}", len(pts), f"{e[:, 0].max():.2f}", _g(np.median(e[:, 0])), _g(e[:, 1].max())])
    return rows


def _sweep(seed, n, log_w0, log_scale, p_far, log_far, log_near, p_zero, log_wt):
    """n seeded states and times: gamma/w0 log-uniform (probability p_far) or 2(1 +- 10^x)."""
    rng = np.random.default_rng(seed)
    w0 = 10 ** rng.uniform(*log_w0, n)
    ratio = np.where(
        rng.random(n) < p_far,
        10 ** rng.uniform(*log_far, n),
        2 * (1 + rng.choice([-1, 1], n) * 10 ** rng.uniform(*log_near, n)),
    )
    ratio[rng.random(n) < p_zero] = 0
    t = 10 ** rng.uniform(*log_wt, n) / w0
    th0 = rng.uniform(-1, 1, n) * 10 ** rng.uniform(-log_scale, log_scale, n)
    om0 = rng.uniform(-1, 1, n) * w0 * 10 ** rng.uniform(-log_scale, log_scale, n)
    return t, th0, om0, w0, ratio * w0


def sweep_rows():
    sweeps = [
        (
            "seeded sweep: γ/w0 ∈ [1e-10, 1e8] and within 1e-3 of critical, w0 ∈ [1e-3, 1e3]",
            _sweep(20261201, 300, (-3, 3), 0, 0.5, (-10, 8), (-16, -3), 0.0, (-6, 4)),
        ),
        (
            "extreme scales: w0 ∈ [1e-100, 1e100], θ0, Ω0/w0 ∈ [1e-50, 1e50]",
            _sweep(20261202, 400, (-100, 100), 50, 0.3, (-15, 12), (-16, 0), 0.05, (-8, 6)),
        ),
    ]
    rows = []
    for label, args in sweeps:
        e = _measure(*args)
        rows.append([label, len(e), f"{e[:, 0].max():.2f}", _g(np.median(e[:, 0])), "—"])
    return rows


def text_rows():
    """pendula vs the text's formulas on figs 10-13 (two periods, 1000 points, theta0 = 0.1 or 0,
    Omega0 = 0, +-0.5 rad/s): worst |difference| / (eps scale), scale = |theta| + |Omega|/gamma
    plus 1e-3 of the initial state's size; then near critical, each against mpmath."""
    w0, t = T.W0_TEXT, T.T_TEXT
    over = [(f, 0.1, om) for f in (3.0, 5.0) for om in (0.0, 0.5, -0.5)] + [(3.0, 0.0, 0.5)]
    worst = {"over": 0.0, "critical": 0.0}
    for kind, f, th0, om0 in [("over", *c) for c in over] + [("critical", 2.0, 0.1, om) for om in (0.0, 0.5, -0.5)]:
        gama = f * w0
        text = T._text_overdamped(th0, om0, gama) if kind == "over" else T._text_critical(th0, om0)
        ours = pendula.linear_damped(t, th0, om0, w0, gama)
        scale = np.abs(text[0]) + np.abs(text[1]) / gama + 1e-3 * (abs(th0) + abs(om0) / gama)
        diff = np.maximum(np.abs(ours[0] - text[0]), np.abs(ours[1] - text[1]) / gama)
        worst[kind] = max(worst[kind], float((diff / scale).max() / T.EPS))
    gama, tt = 2 * w0 * (1 + 1e-12), t[::50]
    ref = np.array([float(T.reference(x, 0.1, 0.5, w0, gama)[0]) for x in tt])
    rel = lambda th: float(np.max(np.abs(th - ref) / np.abs(ref)))  # noqa: E731
    return [
        ["figs 10–12: pendula vs eqs 2.27–2.29, eps·scale", 7 * len(t), f"{worst['over']:.2f}"],
        ["fig 13: pendula vs eqs 2.45–2.47, eps·scale", 3 * len(t), f"{worst['critical']:.2f}"],
        [
            "γ = 2w0(1 + 1e-12): eq. 2.29 vs mpmath, relative",
            len(tt),
            f"{rel(T._text_overdamped(0.1, 0.5, gama)[0][::50]):.1e}",
        ],
        [
            "γ = 2w0(1 + 1e-12): pendula vs mpmath, relative",
            len(tt),
            f"{rel(pendula.linear_damped(tt, 0.1, 0.5, w0, gama)[0]):.1e}",
        ],
    ]


def main():
    args = harness.parser(
        __doc__, "(no effect: the measurement takes seconds)", "write accuracy_linear.md into DIR"
    ).parse_args()
    rows = grid_rows() + sweep_rows()
    head = ["γ/w0", "points", "worst [eps·(size + cond)]", "median [eps·(size + cond)]", "worst [eps·size]"]
    text = text_rows()
    md = "\n\n".join(
        [harness.markdown_table(head, rows), harness.markdown_table(["the text's formulas", "points", "worst"], text)]
    )
    print(md)
    harness.write_outputs(
        args.out,
        "accuracy_linear",
        md,
        [
            (["gamma/w0", "points", "worst cond", "median cond", "worst size"], rows),
            (["comparison", "points", "worst"], text),
        ],
    )


if __name__ == "__main__":
    main()
