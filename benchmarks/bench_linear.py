"""Speed and accuracy of pendula.linear_damped against numpy and SciPy.

The numpy baseline evaluates the text's own formulas, vectorised: eqs 2.27-2.29
(over-damped), eqs 2.45-2.47 (critical) and, for the under-damped case the text
leaves empty, the textbook e^{-gamma t/2}(theta0 cos + (Omega0 + gamma theta0/2)/omega_d sin).
The SciPy baseline is the batched matrix exponential scipy.linalg.expm of
[[0, 1], [-w0^2, -gamma]] t applied to (theta0, Omega0) (timed at N = 1000 only:
it costs tens of microseconds per point; --quick times it on 200 points).  All three are timed in the
same run on the same points (best of several repeats), and their errors are
measured against mpmath (50 digits) on a sample of the points, in units of
eps * (|theta| + |Omega|/max(w0, gamma)).

    python benchmarks/bench_linear.py [--quick] [--out DIR]

Prints a table and, with --out, writes bench_linear.md and bench_linear.csv there.
"""

from __future__ import annotations

import math
import platform

import harness
import mpmath as mp
import numpy as np

import pendula

try:
    import scipy.linalg
except ImportError:  # pragma: no cover
    scipy = None

EPS = np.finfo(float).eps
W0 = math.sqrt(9.8 / 4.9)
REGIMES = {
    "under (gamma = 0.5 w0)": 0.5,
    "critical (gamma = 2 w0)": 2.0,
    "near-critical (2 w0 (1 + 1e-12))": 2 * (1 + 1e-12),
    "over (gamma = 3 w0)": 3.0,
    "over (gamma = 1e6 w0)": 1e6,
}


def numpy_text(t, th0, om0, w0, gamma):
    """The text's formulas (eqs 2.27-2.29, 2.45-2.47) and the textbook under-damped one."""
    a = gamma / 2.0
    if gamma > 2 * w0:
        beta = np.sqrt(gamma**2 / 4.0 - w0**2)
        l1, l2 = -a - beta, -a + beta
        A = (th0 * l2 - om0) / (l2 - l1)
        B = (om0 - th0 * l1) / (l2 - l1)
        e1, e2 = np.exp(l1 * t), np.exp(l2 * t)
        return A * e1 + B * e2, A * l1 * e1 + B * l2 * e2
    if gamma == 2 * w0:
        lam = -a
        B = om0 - th0 * lam
        e = np.exp(lam * t)
        return e * (th0 + B * t), e * (om0 + B * lam * t)
    wd = np.sqrt(w0**2 - a**2)
    e = np.exp(-a * t)
    c, s = np.cos(wd * t), np.sin(wd * t)
    return (e * (th0 * c + (om0 + a * th0) / wd * s), e * (om0 * c - (w0**2 * th0 + a * om0) / wd * s))


def scipy_expm(t, th0, om0, w0, gamma):
    m = np.array([[0.0, 1.0], [-(w0**2), -gamma]])
    e = scipy.linalg.expm(t[:, None, None] * m)
    return e[:, 0, 0] * th0 + e[:, 0, 1] * om0, e[:, 1, 0] * th0 + e[:, 1, 1] * om0


def reference(t, th0, om0, w0, gamma):
    with mp.workdps(50):
        t, th0, om0, w0, g = (mp.mpf(float(x)) for x in (t, th0, om0, w0, gamma))
        a = g / 2
        d = a * a - w0 * w0
        e = mp.exp(-a * t)
        if d == 0:
            ec, es = e, e * t
        else:
            sq = mp.sqrt(mp.mpc(d))
            ec, es = e * mp.cosh(sq * t).real, e * (mp.sinh(sq * t) / sq).real
        return th0 * ec + (om0 + a * th0) * es, om0 * ec - (w0 * w0 * th0 + a * om0) * es


def max_error(fn, t, th0, om0, w0, gamma):
    th, om = fn(t, th0, om0, w0, gamma)
    m = max(w0, gamma)
    worst = 0.0
    for x, a, b in zip(t, th, om):
        rt, ro = reference(x, th0, om0, w0, gamma)
        size = abs(rt) + abs(ro) / m
        if size < 1e-290:
            continue
        err = max(abs(mp.mpf(float(a)) - rt), abs(mp.mpf(float(b)) - ro) / m) / size
        worst = max(worst, float(err / EPS))
    return worst


def main(argv=None):
    ap = harness.parser(__doc__, "small sizes, few repeats (a few seconds)", "also write bench_linear.md/.csv here")
    args = ap.parse_args(argv)
    sizes = [1_000, 100_000] if args.quick else [1_000, 100_000, 1_000_000]
    repeats = 3 if args.quick else 7
    th0, om0 = 0.1, 0.5
    rows = []
    for label, ratio in REGIMES.items():
        gamma = ratio * W0
        # A window of 8 decay times of the slow mode (at most 40 periods).
        slow = pendula.damping_regime(W0, gamma).decay_slow
        tmax = min(8.0 / slow, 40 * 2 * math.pi / W0)
        sample = np.linspace(0.0, tmax, 25 if args.quick else 200)
        err_p = max_error(lambda *a: pendula.linear_damped(*a), sample, th0, om0, W0, gamma)
        err_n = max_error(numpy_text, sample, th0, om0, W0, gamma)
        err_s = max_error(scipy_expm, sample, th0, om0, W0, gamma) if scipy else math.nan
        for n in sizes:
            t = np.linspace(0.0, tmax, n)
            tp, tn = harness.best_times_interleaved(
                [lambda: pendula.linear_damped(t, th0, om0, W0, gamma), lambda: numpy_text(t, th0, om0, W0, gamma)],
                repeats,
            )
            ts = math.nan
            if scipy and n == sizes[0]:
                ts_n = 200 if args.quick else n
                ts = harness.best_time(lambda: scipy_expm(t[:ts_n], th0, om0, W0, gamma), 2) * n / ts_n
            rows.append(
                dict(
                    regime=label,
                    n=n,
                    pendula_ns=1e9 * tp / n,
                    numpy_text_ns=1e9 * tn / n,
                    scipy_expm_ns=1e9 * ts / n,
                    ratio_numpy=tn / tp,
                    ratio_scipy=ts / tp,
                    err_pendula=err_p,
                    err_numpy_text=err_n,
                    err_scipy_expm=err_s,
                )
            )
    head = [
        "regime",
        "N",
        "pendula ns/pt",
        "numpy text ns/pt",
        "scipy expm ns/pt",
        "numpy/pendula",
        "scipy/pendula",
        "err pendula",
        "err text",
        "err expm",
    ]
    fmt = lambda r: [
        r["regime"],
        f"{r['n']:,}",
        f"{r['pendula_ns']:.1f}",
        f"{r['numpy_text_ns']:.1f}",  # noqa: E731
        f"{r['scipy_expm_ns']:.0f}",
        f"{r['ratio_numpy']:.2f}",
        f"{r['ratio_scipy']:.0f}",
        f"{r['err_pendula']:.3g}",
        f"{r['err_numpy_text']:.3g}",
        f"{r['err_scipy_expm']:.3g}",
    ]
    text = "\n".join(
        [
            "# pendula.linear_damped: speed and accuracy",
            "",
            f"pendula.linear_damped vs numpy (text formulas) and scipy.linalg.expm, this run; "
            f"{platform.machine()}, numpy {np.__version__}.",
            "ns per point (best of repeats); ratios > 1 mean pendula is faster. Errors: max over "
            "a sample vs mpmath (50 digits), in eps * (|theta| + |Omega|/max(w0, gamma)).",
            "",
            harness.markdown_table(head, [fmt(r) for r in rows]),
        ]
    )
    print(text)
    harness.write_outputs(args.out, "bench_linear", text, [(list(rows[0]), [list(r.values()) for r in rows])])


if __name__ == "__main__":
    main()
