"""The batch RK4 kernel on every CPU dispatch path, side by side with its peers.

The scene of bench_ensembles.py (N states of the text's damped pendulum,
1200 RK4 steps each, every state within 1e-6 rad).  Contenders, all in the
same run:

  pendula batch, 1 thread      pendula._many.kernels.rk4_batch on each kernel path this
                               machine has (baseline x86-64, x86-64-v3 = AVX2,
                               x86-64-v4 = AVX-512), forced by PENDULA_KERNEL
                               in a fresh interpreter; and 2 threads on the
                               path pendula picks by itself
  C loop, -march=native        benchmarks/rk4_peer.c, compiled here with
                               cc -O3 -march=native -ffast-math: a plain RK4
                               loop vectorised across states over glibc's
                               vector sin (libmvec); skipped without cc
  numba njit, 1 thread         bench_ensembles' numba RK4 (optional: the
                               `bench` extra); heyoka.py's batch mode likewise
                               when installed (not timed here otherwise)

and, for the closed forms, pendula.period over many amplitudes against
SciPy's 4 ellipkm1(cos(theta0/2)**2) / w0, and pendula.undamped over many
distinct states against SciPy's closed form (bench_undamped.scipy_undamped).
Times are CPU time of the computing thread (the C loop: of its process), best
of --repeat rounds in which every contender runs once in turn (a path in a
fresh interpreter, the C loop, numba): the per-core cost when other processes
share the
machine.  Ratios > 1 mean pendula is faster.

    python benchmarks/bench_kernels.py [--quick] [--n N] [--repeat R] [--out DIR]
"""

from __future__ import annotations

import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

import harness
import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
STEPS = 1200


def _thread_cpu(fn, repeat):
    """Best CPU time of the calling thread over `repeat` calls of fn."""
    best = np.inf
    for _ in range(repeat):
        c0 = time.thread_time()
        fn()
        best = min(best, time.thread_time() - c0)
    return best


def _child(n, repeat):
    """In a fresh interpreter (PENDULA_KERNEL set by the parent): time the batch."""
    import bench_ensembles as ens

    import pendula
    from pendula._many import kernels as _batch

    th0, om0 = ens.scene(n)
    out = {"path": pendula.build_info()["kernel"]["path"]}
    for threads in (1, 2):
        wall, cpu, _, theta = harness.best_run(lambda: ens.run_batch(th0, om0, threads), repeat)
        out[f"wall{threads}"], out[f"cpu{threads}"] = wall, cpu
    # One thread computes on the calling thread: its CPU time is the cost,
    # without the CPU of idle library threads in the process (BLAS pools).
    out["cpu1"] = _thread_cpu(lambda: ens.run_batch(th0, om0, 1), repeat)
    ref = _batch.rk4_batch(ens.T, th0, om0, np.sqrt(ens.W0SQ), ens.GAMMA, ens.H / 16).theta
    out["err"] = float(np.abs(theta - ref).max())
    print(json.dumps(out))


def _path_run(path, n, repeat):
    """One child result on kernel path `path` (best of `repeat` in that child)."""
    env = dict(os.environ, PENDULA_KERNEL=path)
    run = subprocess.run(
        [sys.executable, __file__, "--child", str(n), str(repeat)],
        env=env,
        check=True,
        capture_output=True,
        text=True,
    )
    return json.loads(run.stdout.strip().splitlines()[-1])


def _build_c_peer(tmp):
    """Path of the compiled C loop (rk4_peer.c) in tmp, or (None, why not)."""
    cc = shutil.which(os.environ.get("CC", "cc"))
    if cc is None:
        return None, "no C compiler"
    exe = pathlib.Path(tmp) / "rk4_peer"
    build = subprocess.run(
        [cc, "-O3", "-march=native", "-ffast-math", str(HERE / "rk4_peer.c"), "-o", str(exe), "-lm"],
        capture_output=True,
        text=True,
    )
    if build.returncode != 0:
        return None, "compile failed: " + build.stderr.strip()[:200]
    return exe, "cc -O3 -march=native -ffast-math (libmvec)"


def _c_peer(exe, n):
    """CPU s of one run of the C loop."""
    out = subprocess.run([str(exe), str(n), "1"], check=True, capture_output=True, text=True).stdout
    return float(out.split()[0])


def _rounds(n, repeat, paths, exe, nb, th0, om0):
    """Best times of every contender, measured in `repeat` interleaved rounds
    (each path in a fresh interpreter, the C loop, numba): load from other
    processes then hits all alike.  Returns ({path: child result}, C s, numba s)."""
    res, peer, nb_cpu = {}, np.inf, np.inf
    for _ in range(repeat):
        for path in paths:
            r = _path_run(path, n, 2)
            if path not in res:
                res[path] = r
            else:
                for k in ("cpu1", "cpu2", "wall1", "wall2"):
                    res[path][k] = min(res[path][k], r[k])
        if exe is not None:
            peer = min(peer, _c_peer(exe, n))
        if nb is not None:
            nb_cpu = min(nb_cpu, _thread_cpu(lambda: nb(th0, om0), 1))
    return res, peer, nb_cpu


def _period(m, repeat):
    """(pendula s, SciPy s) for the period over m amplitudes in (0, pi)."""
    from scipy.special import ellipkm1

    import pendula

    th = np.random.default_rng(5).uniform(1e-3, np.pi - 1e-3, m)
    w0 = 1.4
    tp, ts = harness.best_times_interleaved(
        [lambda: pendula.period(th, 0.0, w0), lambda: 4 * ellipkm1(np.cos(th / 2) ** 2) / w0],
        repeat,
        clock=time.process_time,
    )
    a, b = pendula.period(th, 0.0, w0), 4 * ellipkm1(np.cos(th / 2) ** 2) / w0
    return tp, ts, float(np.max(np.abs(a - b) / b))


def _undamped(m, repeat):
    """(pendula s, SciPy s) for undamped over m distinct libration states, one
    time each in 0..100 s, against bench_undamped's SciPy closed form."""
    from bench_undamped import scipy_undamped

    import pendula

    rng = np.random.default_rng(6)
    w0 = 1.4
    th = rng.uniform(-3.0, 3.0, m)
    om = 2 * w0 * np.cos(th / 2) * rng.uniform(-0.99, 0.99, m)
    t = rng.uniform(0, 100, m)
    return harness.best_times_interleaved(
        [lambda: pendula.undamped(t, th, om, w0), scipy_undamped(t, th, om, w0)], repeat, clock=time.process_time
    )


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["--child"]:
        _child(int(argv[1]), int(argv[2]))
        return
    ap = harness.parser(
        __doc__, "2,000 states, period over 1e5 amplitudes (seconds)", "also write bench_kernels.md here"
    )
    args, n, repeat = harness.parse_with_sizes(
        ap, argv, "states (default 10,000; --quick 2,000)", n=(2_000, 10_000), repeat=(3, 5)
    )
    import bench_ensembles as ens

    import pendula

    info = pendula.build_info()["kernel"]
    print(
        f"pendula {pendula.__version__}; kernel paths {info['available']} (default {info['path']}); "
        f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}",
        flush=True,
    )
    nbk = ens.numba_kernels()
    th0, om0 = ens.scene(n)
    nb1 = None
    if nbk is not None:
        nb1 = nbk[0]
        nb1(th0[:8], om0[:8])  # compile outside the timing
    with tempfile.TemporaryDirectory() as tmp:
        exe, peer_how = _build_c_peer(tmp)
        paths, peer_cpu, nb_cpu = _rounds(n, repeat, info["available"], exe, nb1, th0, om0)
    if exe is None:
        peer_cpu = None
    rows = []
    for path, r in paths.items():
        rows.append(
            (
                f"pendula batch, 1 thread, path {path}" + (" (default)" if path == info["path"] else ""),
                r["cpu1"],
                r["err"],
            )
        )
    if peer_cpu is not None:
        rows.append((f"C loop, {peer_how}", peer_cpu, float("nan")))
    if nb1 is not None:
        rows.append(("numba njit, 1 thread", nb_cpu, float("nan")))
    nb = nb1
    try:
        import heyoka  # noqa: F401

        heyoka_note = "heyoka.py installed: its batch mode is not timed by this script yet"
    except ImportError:
        heyoka_note = "heyoka.py not installed"

    lines = ["| contender | ns per state-step (CPU) | max error [rad] |", "|---|---|---|"]
    for name, cpu, err in rows:
        lines.append(f"| {name} | {cpu / (n * STEPS) * 1e9:.2f} | {'-' if np.isnan(err) else f'{err:.1e}'} |")
    best = paths[info["path"]]
    base = paths["baseline"]
    ratios = []
    for path, r in paths.items():
        if path != "baseline":
            ratios.append(f"path {path} / baseline, 1 thread: {base['cpu1'] / r['cpu1']:.2f}x")
    if peer_cpu is not None:
        ratios.append(f"default path / C loop, 1 thread: {peer_cpu / best['cpu1']:.2f}x (target >= 1)")
    if nb is not None:
        ratios.append(f"default path / numba, 1 thread: {nb_cpu / best['cpu1']:.2f}x (target >= 7x)")
    ratios.append(
        f"default path, 2 threads / 1 thread, wall: {best['wall1'] / best['wall2']:.2f}x (target >= 1.8x; "
        f"only meaningful on an idle machine)"
    )
    ratios.append(heyoka_note)
    m = 100_000 if args.quick else 1_000_000
    tp, ts, dev = _period(m, repeat)
    ratios.append(
        f"period over {m:,} amplitudes: pendula {tp / m * 1e9:.1f} ns, SciPy 4 ellipkm1(cos(theta0/2)**2)/w0 "
        f"{ts / m * 1e9:.1f} ns per point: {ts / tp:.2f}x (target >= 1; largest relative difference "
        f"{dev:.1e})"
    )
    mu = 20_000 if args.quick else 100_000
    tu, tsu = _undamped(mu, repeat)
    ratios.append(
        f"undamped over {mu:,} distinct states: pendula {tu / mu * 1e9:.1f} ns, SciPy closed form "
        f"{tsu / mu * 1e9:.1f} ns per state: {tsu / tu:.2f}x (target >= 3x)"
    )
    text = "\n".join(lines + [""] + ["- " + r for r in ratios])
    print()
    print(text)
    harness.write_outputs(args.out, "bench_kernels", text)


if __name__ == "__main__":
    main()
