"""The default thread count of a batch against one thread and every core.

``threads=None`` (the default of rk4, cvode, sweep, solve) chooses the thread
count from the predicted work (states x steps against
``pendula._defaults.SERIAL_WORK``): one thread for a small batch, where waking
an OpenMP team costs more than it gives, every core for a large one.  For RK4
batches of the text's damped pendulum over growing work, this prints the best
wall time of threads=None, threads=1 and threads=0 (every core) and the ratios
default / threads=1 (the goal: about 1 or below on a small batch, never the
10-20x of waking a team on a busy machine) and default / threads=0.

    python benchmarks/bench_default_threads.py [--quick] [--out DIR]
"""

import os
import time

import harness
import numpy as np

import pendula
from pendula import _defaults


def best_interleaved(fns, repeat):
    """Best wall time of each callable, the runs interleaved (a loaded machine drifts)."""
    out = {k: float("inf") for k in fns}
    for _ in range(repeat):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            out[k] = min(out[k], time.perf_counter() - t0)
    return out


def main(argv=None):
    ap = harness.parser(__doc__, "fewer repeats and sizes", "also write bench_default_threads.md here")
    args = ap.parse_args(argv)
    cases = [(200, 1.0), (200, 10.0), (2000, 10.0)] + ([] if args.quick else [(20000, 10.0)])
    h = 0.01
    lines = [
        f"pendula {pendula.__version__}, {os.cpu_count()} cores; SERIAL_WORK = {_defaults.SERIAL_WORK:g} RK4 steps",
        "",
        "| states | t_end [s] | work [steps] | default [ms] | threads=1 [ms] | threads=0 [ms] | default / 1 "
        "| default / 0 |",
        "|---|---|---|---|---|---|---|---|",
    ]
    print("\n".join(lines), flush=True)
    for n, t_end in cases:
        th0 = np.linspace(0.1, 3.0, n)
        t = np.array([0.0, t_end])
        # small batches are cheap and noisy: many rounds; large ones: few
        rep = 30 if n <= 200 else 5 if args.quick or n > 2000 else 15
        times = best_interleaved(
            {thr: (lambda thr=thr: pendula.rk4(t, th0, 0.0, np.sqrt(2), 0.1, h, threads=thr)) for thr in (None, 1, 0)},
            rep,
        )
        work = n * (t_end / h + t.size)
        lines.append(
            f"| {n} | {t_end:g} | {work:.1e} | {times[None] * 1e3:.3f} | {times[1] * 1e3:.3f} | "
            f"{times[0] * 1e3:.3f} | {times[None] / times[1]:.2f} | {times[None] / times[0]:.2f} |"
        )
        print(lines[-1], flush=True)
    harness.write_outputs(args.out, "bench_default_threads", "\n".join(lines))


if __name__ == "__main__":
    main()
