"""The driven pendulum: the three speed targets, each printed with what it is compared to.

1. The largest Lyapunov exponent of the Baker-Gollub chaotic orbit (w0 = 1,
   gamma = 0.5, torque F = 1.15, Omega = 2/3), one core, by pendula.lyapunov's
   defaults (an ensemble of 8 copies in the SIMD lanes, 64 RK4 steps per
   period, 100 transient + 50,000 measured periods each): the exponent with
   its 95 % error bound and the CPU time, against the long reference below
   (inside the bound?), and against the single-orbit run it replaces (1 copy,
   128 steps, 20,000 periods) in the same process: the error bound per CPU
   second.  The reference: REFERENCE[N] is the mean over 128 orbits (starts
   0.2 + k 1e-3 rad, 200 transient periods) x 125,000 periods with N steps
   per period, with its standard error (`--reference` recomputes them, ~2
   min of CPU); N = 32, 64 and 128 show the step's bias falling like h^4.
2. A bifurcation diagram of 1,000 drive amplitudes F in [0.9, 1.5] x (300
   transient + 200 recorded periods), 2 threads: the time.
3. Per core: the driven batch kernel (pendula.driven, 1 thread) against a
   numba implementation of the same fixed-step RK4 (N = 128 steps per
   period, the drive cos evaluated at each stage time, reused across steps,
   libm sin), written as a competent user would, on the same states (F = 0.9,
   a regular drive, so that the final states can be compared); the ratio of
   CPU times and the largest difference of the final states.

Times are CPU seconds of this process (time.process_time) where one thread
runs, so a loaded machine slows both sides alike; wall seconds for the
2-thread bifurcation.  numba is a benchmark requirement (the `bench` extra).

    python benchmarks/bench_driven.py [--quick] [--out FILE.md]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import pendula
import pendula._codes

W0, GAMMA, OMEGA = 1.0, 0.5, 2.0 / 3.0
N_STEPS = 128
# the long reference runs (`--reference`): steps per period -> (largest exponent, standard error) [1/s]
REFERENCE = {32: (0.099919, 0.000035), 64: (0.099387, 0.000037), 128: (0.099359, 0.000044)}
REF_STARTS, REF_PERIODS = 128, 125000


def best(fn, repeat, clock=time.process_time):
    out, t_best = None, math.inf
    for _ in range(repeat):
        t0 = clock()
        out = fn()
        t_best = min(t_best, clock() - t0)
    return out, t_best


def numba_kernel():
    import numba

    @numba.njit(cache=False)
    def run(theta0, omega0, w0, gamma, F, Om, phi, nsteps, periods):
        n = theta0.size
        out = np.empty((2, n))
        h = 2 * math.pi / Om / nsteps
        for i in range(n):
            y = theta0[i]
            u = omega0[i]
            wsq = w0 * w0
            f1 = F * math.cos(phi)
            for k in range(periods * nsteps):
                t = k * h
                f2 = F * math.cos(Om * (t + 0.5 * h) + phi)
                f3 = F * math.cos(Om * (t + h) + phi)
                k1 = f1 - gamma * u - wsq * math.sin(y)
                y2 = y + 0.5 * h * u
                u2 = u + 0.5 * h * k1
                k2 = f2 - gamma * u2 - wsq * math.sin(y2)
                y3 = y + 0.5 * h * u2
                u3 = u + 0.5 * h * k2
                k3 = f2 - gamma * u3 - wsq * math.sin(y3)
                y4 = y + h * u3
                u4 = u + h * k3
                k4 = f3 - gamma * u4 - wsq * math.sin(y4)
                y = y + h / 6 * (u + 2 * (u2 + u3) + u4)
                u = u + h / 6 * (k1 + 2 * (k2 + k3) + k4)
                f1 = f3
            out[0, i] = y
            out[1, i] = u
        return out

    return run


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller sizes (a smoke run)")
    ap.add_argument("--out", default=None, help="also write the table as Markdown")
    ap.add_argument("--reference", action="store_true", help="recompute the long Lyapunov references (slow)")
    ap.add_argument("--reference-threads", type=int, default=2, help="threads for --reference (default 2)")
    args = ap.parse_args(argv)
    rows = []
    drive = pendula.Drive("torque", 1.15, OMEGA)

    # 1. Lyapunov exponent, one core
    if args.reference:
        for n_steps in sorted(REFERENCE):
            starts = 0.2 + 1e-3 * np.arange(REF_STARTS)
            r = pendula.lyapunov(
                starts,
                0.0,
                drive=drive,
                w0=W0,
                gamma=GAMMA,
                transient=200,
                periods=REF_PERIODS,
                steps_per_period=n_steps,
                orbits=1,
                threads=args.reference_threads,
            )
            e = r.exponents[..., 0]
            REFERENCE[n_steps] = (float(e.mean()), float(e.std(ddof=1) / math.sqrt(e.size)))
            print(f"reference N = {n_steps}: {REFERENCE[n_steps][0]:.6f} +- {REFERENCE[n_steps][1]:.6f} (1 sigma)")
    ref, ref_se = REFERENCE[pendula._codes.LYAPUNOV_DEFAULT_STEPS]
    pendula.lyapunov(0.2, 0.0, drive=drive, w0=W0, gamma=GAMMA, periods=16, threads=1)  # warm-up
    repeat = 1 if args.quick else 3
    scale = 10 if args.quick else 1
    defaults = dict(periods=pendula._codes.LYAPUNOV_DEFAULT_PERIODS // scale)
    single = dict(orbits=1, steps_per_period=N_STEPS, periods=20000 // scale)
    runs = {}
    for label, kw in (("ensemble (the defaults)", defaults), ("one orbit, the former defaults", single)):
        r, t_ly = best(lambda: pendula.lyapunov(0.2, 0.0, drive=drive, w0=W0, gamma=GAMMA, threads=1, **kw), repeat)
        runs[label] = (float(r.exponents[0]), float(r.errors[0]), float(r.exponents.sum()), t_ly, kw)
    # CPU time for a given error bound goes like bound**2 * time: the speed-up of the ensemble per digit
    (_, e_ens, _, t_ens, _), (_, e_one, _, t_one, _) = runs.values()
    gain = (e_one**2 * t_one) / (e_ens**2 * t_ens)
    for label, (lam, err, total, t_ly, kw) in runs.items():
        inside = "inside" if abs(lam - ref) <= err else "OUTSIDE"
        kw_text = ", ".join(f"{k} {v}" for k, v in kw.items())
        rows.append(
            (
                f"largest Lyapunov exponent, Baker-Gollub F = 1.15, {label} (1 core)",
                f"{lam:.5f} +- {err:.5f} 1/s (95 %; {kw_text}; sum {total:+.6f} = -gamma)",
                f"{t_ly:.2f} s CPU",
                f"reference {ref:.5f} +- {ref_se:.5f}: {inside}; "
                + ("target +-0.0005 in < 1 s" if kw is defaults else f"the ensemble is {gain:.0f}x faster per digit"),
            )
        )
    bias = REFERENCE[64][0] - REFERENCE[128][0]
    rows.append(
        (
            "step bias of the exponent, N = 64 vs 128 steps per period (long runs)",
            f"{bias:+.6f} +- {math.hypot(REFERENCE[64][1], REFERENCE[128][1]):.6f} 1/s "
            f"(N = 32: {REFERENCE[32][0] - REFERENCE[128][0]:+.6f})",
            f"{REF_STARTS} orbits x {REF_PERIODS} periods each",
            "well below the +-0.0005 bound",
        )
    )

    # 2. Bifurcation diagram, 2 threads
    nval = 100 if args.quick else 1000
    amps = np.linspace(0.9, 1.5, nval)
    _, t_bif = best(
        lambda: pendula.bifurcation(
            "amplitude", amps, drive=drive, w0=W0, gamma=GAMMA, transient=300, points=200, threads=2
        ),
        1,
        clock=time.perf_counter,
    )
    rows.append(
        (
            f"bifurcation diagram, {nval} amplitudes x (300 + 200) periods (2 threads)",
            f"{nval * 500 * N_STEPS / 1e6:.0f} M RK4 steps",
            f"{t_bif:.2f} s wall",
            "target < 5 s",
        )
    )

    # 3. batch kernel vs numba, per core; a regular drive (F = 0.9), so that the
    # two answers can be compared (on a chaotic orbit rounding differences grow)
    regular = pendula.Drive("torque", 0.9, OMEGA)
    n = 64 if args.quick else 512
    per = 20 if args.quick else 100
    rng = np.random.default_rng(1)
    th0 = rng.uniform(-1, 1, n)
    om0 = rng.uniform(-1, 1, n)
    t_end = per * drive.period
    try:
        run = numba_kernel()
        run(th0[:2], om0[:2], W0, GAMMA, regular.amplitude, OMEGA, 0.0, N_STEPS, 1)  # compile
        nb, t_nb = best(lambda: run(th0, om0, W0, GAMMA, regular.amplitude, OMEGA, 0.0, N_STEPS, per), 3)
    except ImportError:
        nb, t_nb = None, math.nan
    pr, t_pd = best(lambda: pendula.driven([0.0, t_end], th0, om0, drive=regular, w0=W0, gamma=GAMMA, threads=1), 3)
    steps = n * per * N_STEPS
    diff = (
        max(np.abs(pr.theta[:, -1] - nb[0]).max(), np.abs(pr.omega[:, -1] - nb[1]).max())
        if nb is not None
        else math.nan
    )
    rows.append(
        (
            f"driven batch kernel, {n} states x {per} periods (1 core)",
            f"{t_pd / steps * 1e9:.1f} ns/state-step",
            f"{t_pd:.3f} s CPU",
            "",
        )
    )
    rows.append(
        (
            "numba, same RK4 and states (1 core)",
            f"{t_nb / steps * 1e9:.1f} ns/state-step",
            f"{t_nb:.3f} s CPU",
            f"ratio {t_nb / t_pd:.1f}x (target >= 3x); largest difference {diff:.1e}",
        )
    )

    head = ("case", "result", "time", "vs target / peer")
    width = [max(len(str(r[i])) for r in rows + [head]) for i in range(4)]
    line = "  ".join
    print(line(h.ljust(w) for h, w in zip(head, width)))
    for r in rows:
        print(line(str(c).ljust(w) for c, w in zip(r, width)))
    if args.out:
        with open(args.out, "w") as f:
            f.write("<!-- written by benchmarks/bench_driven.py: do not edit -->\n\n")
            f.write("| " + " | ".join(head) + " |\n|" + "---|" * 4 + "\n")
            for r in rows:
                f.write("| " + " | ".join(str(c) for c in r) + " |\n")


if __name__ == "__main__":
    main()
