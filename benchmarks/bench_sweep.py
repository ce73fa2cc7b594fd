"""Sweeps on Dask: per-chunk cost, scheduler overhead, and projected throughput.

Measured on a dask.distributed LocalCluster of 2 worker processes on
127.0.0.1 (one thread each), for the text's damped scene (w0^2 = 2,
gamma = 0.1, t in [0, 30] s, 601 outputs, RK4 h = 0.025 s) over a grid of
starts (theta0, Omega0):

- chunk cost c: the wall time of one chunk (`chunk_states` states) through the
  batch kernel in this process, one thread (what a worker does per task);
- per-task overhead on a worker o_w: a sweep of many tiny chunks (1 state,
  negligible compute) on the 2 workers, wall time x 2 / chunks: scheduling,
  serialisation, pendula's chunk handling and the round trip of one task;
- scheduler rate s: no-op tasks (client.map) completed per second on the same
  cluster -- a LOWER bound of what the scheduler sustains, since 2 workers
  also limit it, so the cap below is conservative;
- the cluster run itself: states/s for the whole sweep on the 2 workers.

Projection for W workers (one chunk at a time each): W * chunk_states /
(c + o_w) states/s, capped by the scheduler at s * chunk_states.  The model
ignores network transfer of the results (final states: 16 bytes per state)
and stragglers; the measured 2-worker row shows how close it is at W = 2.

Usage: python3 benchmarks/bench_sweep.py [--quick] [--out DIR]
"""

import time

import harness
import numpy as np

import pendula
from pendula._many import kernels as _batch

W0 = np.sqrt(2.0)


def grid(n_side):
    return np.linspace(-3.1, 3.1, n_side)[:, None], np.linspace(-4.0, 4.0, n_side)[None, :]


def main(argv=None):
    ap = harness.parser(
        __doc__,
        "a 40x40 grid and fewer overhead tasks (about half a minute)",
        "also write sweep_bench.md and .csv there",
    )
    args = ap.parse_args(argv)
    try:
        import distributed
    except ImportError:
        print("bench_sweep: dask.distributed is not installed (pip install 'pendula[cluster]'); skipped")
        return
    n_side = 40 if args.quick else 100
    chunk = 200 if args.quick else 500
    n_tiny = 100 if args.quick else 400
    t = np.linspace(0.0, 30.0, 601)
    th, om = grid(n_side)
    n_states = th.size * om.size

    # chunk cost: one chunk through the batch kernel here, one thread, best of 3
    th0 = np.broadcast_to(th, (n_side, n_side)).reshape(-1)[:chunk].copy()
    om0 = np.broadcast_to(om, (n_side, n_side)).reshape(-1)[:chunk].copy()
    c = harness.best_time(lambda: _batch.rk4_batch(t, th0, om0, W0, 0.1, 0.025, threads=1), 3)

    with (
        distributed.LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
            worker_dashboard_address=None,
        ) as lc,
        distributed.Client(lc) as client,
    ):
        tiny_t = np.array([0.0, 1e-3])
        tiny = np.zeros(n_tiny)
        pendula.sweep(tiny_t, tiny[:4], 0.0, W0, 0.1, h=1e-3, chunk_states=1, client=client)  # warm up
        t0 = time.perf_counter()
        pendula.sweep(tiny_t, tiny, 0.0, W0, 0.1, h=1e-3, chunk_states=1, client=client)
        o = (time.perf_counter() - t0) * 2 / n_tiny
        client.gather(client.map(abs, range(-20, 0)))  # warm up
        t0 = time.perf_counter()
        client.gather(client.map(abs, range(-5 * n_tiny, 0)))
        s_rate = 5 * n_tiny / (time.perf_counter() - t0)
        t0 = time.perf_counter()
        r = pendula.sweep(t, th, om, W0, 0.1, h=0.025, chunk_states=chunk, client=client)
        wall = time.perf_counter() - t0
    measured = n_states / wall
    local = pendula.sweep(t, th, om, W0, 0.1, h=0.025, chunk_states=chunk, threads=1)
    identical = np.array_equal(local.theta, r.theta) and np.array_equal(local.omega, r.omega)

    sched_cap = s_rate * chunk
    rows = []
    for workers in (2, 10, 100, 1000):
        rate = workers * chunk / (c + o)
        proj = min(rate, sched_cap)
        rows.append((str(workers), f"{proj:,.0f}", "scheduler" if rate > sched_cap else "workers"))
    text = "\n".join(
        [
            f"pendula.sweep on a 2-process LocalCluster: {n_states} states x 601 outputs (RK4, h = 0.025 s), "
            f"chunks of {chunk} states",
            "",
            harness.markdown_table(
                ["quantity", "value"],
                [
                    ("chunk cost c (one thread)", f"{c * 1e3:.1f} ms ({c / chunk * 1e6:.0f} us/state)"),
                    ("per-task overhead on a worker o_w", f"{o * 1e3:.2f} ms"),
                    ("scheduler rate s (no-op tasks, lower bound)", f"{s_rate:,.0f} tasks/s"),
                    ("measured, 2 workers", f"{measured:,.0f} states/s"),
                    ("cluster result == local result", "bit-identical" if identical else "DIFFERENT"),
                ],
            ),
            "",
            "Projected throughput, W * chunk / (c + o_w), capped by the scheduler at s * chunk:",
            "",
            harness.markdown_table(["workers", "states/s", "limited by"], rows),
        ]
    )
    print(text)
    harness.write_outputs(args.out, "sweep_bench", text, [(["workers", "states_per_s", "limited_by"], rows)])


if __name__ == "__main__":
    main()
