"""Benchmark pendula.undamped against the text's listing expression, same run.

Speed: theta(t) at N times (default 1e6) for one state, versus the text's
listings 1.3/1.4 (eq. 1.52)

    theta = 2*arcsin(k*scipy.special.ellipj(K - w0*t, k*k)[0]),  K = ellipk(k*k)

(K computed once, outside the timing, as the listing does).  pendula returns
theta AND Omega; the listing only theta.  Ratio = listing time / pendula time.

Accuracy: the same two against mpmath (60 digits, at the exact double inputs)
for Omega0 = 0 and theta0 = pi - delta over two periods.  The listing forms
k*k = sin^2(theta0/2) in double, so 1 - m is lost near the top (delta <~ 1e-8
gives m == 1 exactly and K = inf: NaN), and 2 asin(k sn) loses half the digits
at the turning points; pendula passes 1 - m = cos^2(theta0/2) to the
complement forms and uses cos(theta/2) = dn.  Rotation states are timed too
(the listing has no answer there).

Many states (the closed forms over arrays, one call each): `period`,
`amplitude`, `elliptic_parameter` and `regime` over N amplitudes against the
SciPy form of the period, 4*ellipkm1(cos(theta0/2)**2)/w0 (and the same
formula on pendula.ellipkm1); `undamped` over M distinct libration states, one
time each, against SciPy's vectorised closed form as a user writes it (eq. 1.52
generalised to Omega0):

    m = sin(theta0/2)**2 + (Omega0/(2 w0))**2,  u0 = ellipkinc(phi0, m),
    phi0 = arctan2(sin(theta0/2), Omega0/(2 w0))   (u0 = ellipk(m) for Omega0 = 0)
    sn, cn, dn, _ = ellipj(w0 t + u0, m);  theta = 2 arcsin(sqrt(m) sn),  Omega = 2 sqrt(m) w0 cn

for t within one period (|w0 t| <~ 4K) and over 0..100 s.  Ratio = pendula / SciPy, in process CPU time (the
per-core cost when other processes share the machine).
The targets, printed as same-run ratios at the end of that table: `period` no
slower than the SciPy form (ratio <= 1) and `undamped` at least 3x faster than
SciPy's closed form (ratio <= 1/3).

Usage: python3 benchmarks/bench_undamped.py [--quick] [--n N] [--out DIR]
"""

import math
import time

import harness
import mpmath as mp
import numpy as np
import scipy
import scipy.special as sc

import pendula

ref = harness.load_generator("gen_undamped_reference")


def listing(t, theta0, w0):
    """The text's expression (eq. 1.52, listings 1.3/1.4), Omega0 = 0 only."""
    k = np.sin(theta0 / 2)
    K = sc.ellipk(k * k)
    return lambda: 2 * np.arcsin(k * sc.ellipj(K - w0 * t, k * k)[0])


def speed_rows(n, repeat, rng):
    w0 = math.sqrt(2.0)
    rows = []
    for label, theta0 in [
        ("theta0 = 0.25 pi", 0.25 * math.pi),
        ("theta0 = 0.75 pi", 0.75 * math.pi),
        ("theta0 = 0.999 pi", 0.999 * math.pi),
    ]:
        T = pendula.period(theta0, 0.0, w0)
        t = np.sort(rng.uniform(0, 100 * T, n))
        tp, ts = harness.best_times_interleaved(
            [lambda: pendula.undamped(t, theta0, 0.0, w0), listing(t, theta0, w0)], repeat
        )
        rows.append((f"libration, {label}", tp / n * 1e9, ts / n * 1e9))
    for label, omega0 in [("rotation, Omega0 = 3 w0", 3 * w0), ("rotation, 1 - m = -1e-12", 2 * w0 * (1 + 5e-13))]:
        T = pendula.period(0.0, omega0, w0)
        t = np.sort(rng.uniform(0, 100 * T, n))
        tp = harness.best_time(lambda: pendula.undamped(t, 0.0, omega0, w0), repeat) / n * 1e9
        rows.append((label, tp, float("nan")))
    return rows


def scipy_period(theta0, w0, ellipkm1=sc.ellipkm1):
    return lambda: 4 * ellipkm1(np.cos(theta0 / 2) ** 2) / w0


def scipy_undamped(t, theta0, omega0, w0):
    """The user's vectorised closed form for libration (see the module text)."""

    def run():
        s, q = np.sin(theta0 / 2), omega0 / (2 * w0)
        m = s * s + q * q
        u0 = sc.ellipkinc(np.arctan2(s, q), m)
        sn, cn, _, _ = sc.ellipj(w0 * t + u0, m)
        k = np.sqrt(m)
        return 2 * np.arcsin(k * sn), 2 * k * w0 * cn

    return run


def many_state_rows(n, m, repeat, rng):
    """(name, pendula ns/pt, reference ns/pt, reference name) for the closed forms over arrays."""
    w0 = math.sqrt(2.0)
    cpu = time.process_time
    th = rng.uniform(-3.1, 3.1, n)
    ref = scipy_period(th, w0)
    rows = []
    tk, ts = harness.best_times_interleaved([scipy_period(th, w0, pendula.ellipkm1), ref], repeat, clock=cpu)
    rows.append(("4*ellipkm1(cos^2(theta0/2))/w0 on pendula.ellipkm1", tk / n * 1e9, ts / n * 1e9, "SciPy form"))
    for fn in (pendula.period, pendula.amplitude, pendula.elliptic_parameter, pendula.regime):
        tp, ts = harness.best_times_interleaved([lambda: fn(th, 0.0, w0), ref], repeat, clock=cpu)
        rows.append((f"{fn.__name__}, {n} amplitudes", tp / n * 1e9, ts / n * 1e9, "SciPy period"))
    # libration states: theta0 in (-3, 3), |Omega0| below the separatrix speed 2 w0 cos(theta0/2)
    th = rng.uniform(-3.0, 3.0, m)
    om = 2 * w0 * np.cos(th / 2) * rng.uniform(-0.99, 0.99, m)
    per = pendula.period(th, om, w0)
    worst = 0.0
    for label, t in (("t within one period", rng.uniform(0, 1, m) * per), ("t in 0..100 s", rng.uniform(0, 100, m))):
        # at least 7 interleaved pairs (a pair costs a tenth of a second): the best of 3
        # (--quick) is too noisy a minimum for a ratio target
        tp, ts = harness.best_times_interleaved(
            [lambda: pendula.undamped(t, th, om, w0), scipy_undamped(t, th, om, w0)], max(repeat, 7), clock=cpu
        )
        rows.append((f"undamped, {m} distinct states, {label}", tp / m * 1e9, ts / m * 1e9, "SciPy closed form"))
        worst = max(
            worst, float(np.max(np.abs(pendula.undamped(t, th, om, w0)[0] - scipy_undamped(t, th, om, w0)()[0])))
        )
    return rows, worst


def target_rows(many):
    """(target, goal, measured ratio, met) from the many-state rows of this run:
    period over the amplitudes no slower than the SciPy form (time ratio <= 1),
    undamped over distinct states >= 3x faster than SciPy's closed form."""
    cells = []
    for name, tp, ts, _ in many:
        if name.startswith("period,"):
            cells.append(
                (
                    "period / SciPy 4*ellipkm1(cos^2(theta0/2))/w0 (time ratio)",
                    "<= 1",
                    f"{tp / ts:.2f}",
                    "yes" if tp <= ts else "no",
                )
            )
        elif name.startswith("undamped,"):
            cells.append(
                (
                    f"SciPy closed form / undamped (speed-up), {name.split(', ', 2)[2]}",
                    ">= 3",
                    f"{ts / tp:.2f}x",
                    "yes" if ts >= 3 * tp else "no",
                )
            )
    return cells


def accuracy_rows(npts):
    w0 = math.sqrt(2.0)
    rows = []
    for delta in (1e-1, 1e-3, 1e-5, 1e-7, 1e-8, 1e-10, 1e-12):
        theta0 = math.pi - delta
        with mp.workdps(ref.DPS):
            st = ref.State(theta0, 0.0, w0)
            T = float(st.period)
            t = np.linspace(0, 2 * T, npts)
            want = np.array([float(st.at(x)[0]) for x in t])
        ours = pendula.undamped(t, theta0, 0.0, w0)[0]
        with np.errstate(all="ignore"):
            theirs = listing(t, theta0, w0)()
        e_ours = float(np.max(np.abs(ours - want)))
        e_list = float(np.max(np.abs(theirs - want))) if np.all(np.isfinite(theirs)) else float("nan")
        nan_frac = float(np.mean(~np.isfinite(theirs)))
        rows.append((delta, e_ours, e_list, nan_frac))
    return rows


def main(argv=None):
    ap = harness.parser(
        __doc__, "1e5 points, 3 repeats, fewer reference points", "also write undamped_bench.md and .csv there"
    )
    ap.add_argument("--states", type=int, default=None, help="distinct states for undamped (default 1e5)")
    args, n, repeat = harness.parse_with_sizes(ap, argv, "times per state (default 1e6)")
    rng = np.random.default_rng(1)
    speed = speed_rows(n, repeat, rng)
    many, many_diff = many_state_rows(n, args.states or (20_000 if args.quick else 100_000), repeat, rng)
    acc = accuracy_rows(40 if args.quick else 200)

    speed_cells = [
        (
            name,
            f"{tp:.1f}",
            f"{ts:.1f}" if np.isfinite(ts) else "-",
            f"{ts / tp:.2f}x" if np.isfinite(ts) else "n/a (no answer)",
        )
        for name, tp, ts in speed
    ]
    many_cells = [(name, f"{tp:.1f}", f"{ts:.1f}", rname, f"{tp / ts:.2f}") for name, tp, ts, rname in many]
    target_cells = target_rows(many)
    acc_cells = [
        (f"{delta:.0e}", f"{eo:.2e}", f"{el:.2e}" if np.isfinite(el) else "NaN", f"{nf:.2f}")
        for delta, eo, el, nf in acc
    ]
    text = "\n".join(
        [
            f"pendula.undamped vs the text's listing (scipy {scipy.__version__}), {n} times per state, w0 = sqrt(2)",
            "",
            harness.markdown_table(
                ["case", "pendula ns/pt (theta and Omega)", "listing ns/pt (theta only)", "speed-up"], speed_cells
            ),
            "",
            "Many states, one call (pendula vs SciPy in the same run):",
            "",
            harness.markdown_table(
                ["case", "pendula ns/pt", "reference ns/pt", "reference", "ratio pendula/reference"], many_cells
            ),
            "",
            f"(max |theta_pendula - theta_SciPy| over those states: {many_diff:.1e} rad)",
            "",
            "The targets, as ratios measured in this run:",
            "",
            harness.markdown_table(["target", "goal", "measured", "met"], target_cells),
            "",
            "Max |theta - mpmath| over two periods, Omega0 = 0, theta0 = pi - delta:",
            "",
            harness.markdown_table(["delta", "pendula", "listing", "listing NaN fraction"], acc_cells, align="rrrr"),
        ]
    )
    print(text)
    harness.write_outputs(
        args.out,
        "undamped_bench",
        text,
        [
            (
                ["case", "pendula_ns", "listing_ns", "speedup"],
                [(name, f"{tp:.2f}", f"{ts:.2f}", f"{ts / tp:.3f}") for name, tp, ts in speed],
            ),
            (
                ["case", "pendula_ns", "reference_ns", "reference", "ratio"],
                [(name, f"{tp:.2f}", f"{ts:.2f}", rname, f"{tp / ts:.3f}") for name, tp, ts, rname in many],
            ),
            (
                ["delta", "pendula_max_err", "listing_max_err", "listing_nan_fraction"],
                [(f"{delta:.0e}", f"{eo:.3e}", f"{el:.3e}", f"{nf:.3f}") for delta, eo, el, nf in acc],
            ),
        ],
    )


if __name__ == "__main__":
    main()
