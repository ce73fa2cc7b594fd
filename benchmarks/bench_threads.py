"""Speed-up from releasing the GIL in the f2py layer.

For each long-running entry point, the same total work (two equal chunks) is
done twice: serially on one thread, then by a pool of 2 threads (one chunk
each).  Since every f2py routine is declared ``!f2py threadsafe``, the Fortran
calls run truly in parallel and the speed-up approaches the number of cores
(2 here); a routine holding the GIL would show ~1.0.  Best of several repeats.

    python benchmarks/bench_threads.py [--quick] [--out DIR] [--threads N]

Prints a table (ns/point serial and threaded, speed-up, and the process CPU
time per wall time of the threaded run -- about 2 when both threads compute at
once, at most 1 if the GIL were held; and how fast a pure-Python thread keeps
counting while the Fortran calls run, relative to its free rate -- near 0 if
the GIL were held, whatever the machine's load) and, with --out,
writes bench_threads.md and bench_threads.csv there.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
import platform
import time

import harness
import numpy as np

import pendula


def _workloads(n):
    """name -> (points per chunk, mk) where mk(i) returns the i-th chunk as a
    zero-argument callable."""
    rng = np.random.default_rng(7)
    out = {}

    def have(name):
        return callable(getattr(pendula, name, None))

    # Elementwise closed forms: n points per chunk.
    if have("small_angle_period"):

        def mk(i):
            w0 = 0.5 + rng.random(n)
            return lambda: pendula.small_angle_period(w0)

        out["small_angle_period"] = (n, mk)
    if have("ellipk"):

        def mk(i):
            m = rng.random(n) * 0.999
            return lambda: pendula.ellipk(m)

        out["ellipk"] = (n, mk)
    if have("ellipj"):

        def mk(i):
            u = rng.random(n) * 4
            m = rng.random(n) * 0.999
            return lambda: pendula.ellipj(u, m)

        out["ellipj"] = (n, mk)
    if have("ellipf"):

        def mk(i):
            phi = rng.random(n) * 10
            return lambda: pendula.ellipf(phi, 0.7)

        out["ellipf"] = (n, mk)
    if have("undamped"):

        def mk(i):
            t = np.linspace(0.0, 100.0, n)
            return lambda: pendula.undamped(t, 1.0 + 0.1 * i, 0.0, 1.4)

        out["undamped"] = (n, mk)
    if have("period"):

        def mk(i):
            th = rng.random(max(n // 50, 10)) * 3
            return lambda: pendula.period(th, 0.0, 1.4)

        out["period"] = (max(n // 50, 10), mk)
    if have("linear_damped"):

        def mk(i):
            t = np.linspace(0.0, 100.0, n)
            return lambda: pendula.linear_damped(t, 0.1, 0.5 + 0.1 * i, 1.4, 0.3)

        out["linear_damped"] = (n, mk)
    # Integrators: a long window sampled at n // 10 points (the stepping dominates).
    if have("rk4"):

        def mk(i):
            t = np.linspace(0.0, 2000.0, max(n // 10, 10))
            return lambda: pendula.rk4(t, 0.0, 2.0 + 0.1 * i, 1.4, 0.1, 0.005)

        out["rk4"] = (max(n // 10, 10), mk)
    if have("cvode") and pendula.build_info()["cvode"]:

        def mk(i):
            t = np.linspace(0.0, 2000.0, max(n // 10, 10))
            return lambda: pendula.cvode(t, 0.0, 2.0 + 0.1 * i, 1.4, 0.1, rtol=1e-10, atol=1e-12)

        out["cvode"] = (max(n // 10, 10), mk)
    return out


def _python_progress(call):
    """Fraction of its free-running rate that a pure-Python counter thread keeps
    while `call` runs on another thread: ~1 when the GIL is released (given a
    free core), ~0 when it is held.  Independent of how fast the call is."""
    import sys
    import threading

    stop = threading.Event()
    count = [0]

    def counter():
        while not stop.is_set():
            count[0] += 1

    old = sys.getswitchinterval()
    sys.setswitchinterval(0.001)
    th = threading.Thread(target=counter)
    th.start()
    try:
        time.sleep(0.02)
        c0, t0 = count[0], time.perf_counter()
        time.sleep(0.1)
        free = (count[0] - c0) / (time.perf_counter() - t0)
        c0, t0 = count[0], time.perf_counter()
        call()
        while time.perf_counter() - t0 < 0.1:  # at least 0.1 s of calls
            call()
        dt = time.perf_counter() - t0
        ran = (count[0] - c0) / dt
    finally:
        stop.set()
        th.join()
        sys.setswitchinterval(old)
    return ran / free if free > 0 else float("nan")


def main(argv=None):
    ap = harness.parser(
        __doc__, "small sizes, few repeats (a few seconds)", "also write bench_threads.md/.csv into this folder"
    )
    ap.add_argument("--threads", type=int, default=2, help="threads (and chunks); default 2")
    args = ap.parse_args(argv)
    n = 100_000 if args.quick else 1_000_000
    repeats = 2 if args.quick else 5
    k = args.threads

    rows = []
    with cf.ThreadPoolExecutor(max_workers=k) as pool:
        for name, (points, mk) in _workloads(n).items():
            chunks = [mk(i) for i in range(k)]
            try:
                for c in chunks:
                    c()  # warm up; also proves the call works in this build
            except Exception as exc:  # noqa: BLE001 - report, do not hide
                rows.append(
                    dict(
                        entry=name,
                        points=points * k,
                        serial_ns=float("nan"),
                        threaded_ns=float("nan"),
                        speedup=float("nan"),
                        cpu_per_wall=float("nan"),
                        python_progress=float("nan"),
                        note=f"failed: {exc}",
                    )
                )
                continue

            def serial():
                for c in chunks:
                    c()

            def threaded():
                list(pool.map(lambda c: c(), chunks))

            # CPU/wall of the fastest threaded run: above 1 only if two threads computed at
            # the same moment, which a routine holding the GIL cannot do (load-independent)
            ts, _, _, _ = harness.best_run(serial, repeats)
            tt, _, par, _ = harness.best_run(threaded, repeats)
            prog = _python_progress(serial)
            total = points * k
            rows.append(
                dict(
                    entry=name,
                    points=total,
                    serial_ns=ts / total * 1e9,
                    threaded_ns=tt / total * 1e9,
                    speedup=ts / tt,
                    cpu_per_wall=par,
                    python_progress=prog,
                    note="",
                )
            )

    cores = os.cpu_count()
    head = (
        f"GIL release: {k} threads vs 1 on {cores} logical cores "
        f"({platform.processor() or platform.machine()}), best of {repeats} "
        f"(speed-ups need idle cores)"
    )
    table = harness.markdown_table(
        [
            "entry point",
            "points",
            "serial ns/point",
            "threaded ns/point",
            "speed-up",
            "CPU/wall (threaded)",
            "Python thread progress during the call",
        ],
        [
            (
                r["entry"],
                r["points"],
                f"{r['serial_ns']:.1f}",
                f"{r['threaded_ns']:.1f}",
                f"{r['speedup']:.2f}",
                f"{r['cpu_per_wall']:.2f}",
                f"{r['python_progress']:.0%}",
            )
            for r in rows
        ],
    )
    notes = [f"{r['entry']}: {r['note']}" for r in rows if r["note"]]
    text = "\n".join([head, "", table] + ([""] + notes if notes else []))
    print(text)
    fields = list(rows[0]) if rows else ["entry"]
    harness.write_outputs(args.out, "bench_threads", text, [(fields, [list(r.values()) for r in rows])])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
