"""The batch RK4 kernel on every CPU dispatch path, side by side with its peers.

The scene of bench_ensembles.py (N states of the text's damped pendulum,
1200 RK4 steps each, every state within 1e-6 rad).  Contenders, all in the
same run:

  pendula batch, 1 thread      pendula._many.kernels.rk4_batch on each kernel path this
                               machine has (baseline x86-64, x86-64-v3 = AVX2,
                               x86-64-v4 = AVX-512), forced by PENDULA_KERNEL
                               in a fresh interpreter; and 2 threads on the
                               path pendula picks by itself.  Each twice: into
                               fresh outputs (theta and omega, new pages every
                               call: the kernel pays for the OS zeroing them),
                               and into outputs reused by out= (as the C loop
                               and numba reuse theirs in the "reused" rows)
  C loop, -march=native        benchmarks/rk4_peer.c, compiled here with
                               cc -O3 -march=native -ffast-math: a plain RK4
                               loop vectorised across states over glibc's
                               vector sin (libmvec); skipped without cc
  numba njit, 1 thread         bench_ensembles' numba RK4 (optional: the
                               `bench` extra), into fresh and reused outputs
  heyoka.py batch, tol 1e-7    taylor_adaptive_batch (this machine's SIMD
                               width of doubles) over the same states and
                               outputs, block by block (optional, when heyoka
                               is installed; its own steps, so its time is
                               given per state and per state-step of the RK4)
  200 states, default threads  rk4_batch with threads=None against threads=1
                               (wall time, interleaved: the default must not
                               be slower on a batch this small)

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
    keep = (np.empty((n, ens.T.size)), np.empty((n, ens.T.size)))
    for threads in (1, 2):
        wall, cpu, _, theta = harness.best_run(lambda: ens.run_batch(th0, om0, threads), repeat)
        out[f"wall{threads}"], out[f"cpu{threads}"] = wall, cpu
        wall, _, _, _ = harness.best_run(lambda: ens.run_batch(th0, om0, threads, keep), repeat)
        out[f"wall{threads}_out"] = wall
    # One thread computes on the calling thread: its CPU time is the cost,
    # without the CPU of idle library threads in the process (BLAS pools).
    out["cpu1"] = _thread_cpu(lambda: ens.run_batch(th0, om0, 1), repeat)
    out["cpu1_out"] = _thread_cpu(lambda: ens.run_batch(th0, om0, 1, keep), repeat)
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
    """CPU s of the C loop: (its first run, into a fresh output array; the best
    of the next runs, into the same array again)."""
    out = subprocess.run([str(exe), str(n), "1"], check=True, capture_output=True, text=True).stdout
    fresh = float(out.split()[0])
    out = subprocess.run([str(exe), str(n), "3"], check=True, capture_output=True, text=True).stdout
    return fresh, min(fresh, float(out.split()[0]))


def _heyoka_batch(th0, om0, tol=1e-7):
    """(run(), SIMD width) for heyoka.py's batch integrator on the scene, or
    (None, why not).  run() returns theta, shape (n, n_t)."""
    try:
        import heyoka as hy
    except ImportError:
        return None, "heyoka.py not installed"
    import bench_ensembles as ens

    x, v = hy.make_vars("x", "v")
    width = hy.recommended_simd_size()
    n = th0.size
    nb = -(-n // width)
    pad = nb * width - n
    th_p = np.concatenate([th0, th0[:pad]]).reshape(nb, width)
    om_p = np.concatenate([om0, om0[:pad]]).reshape(nb, width)
    ta = hy.taylor_adaptive_batch([(x, v), (v, -ens.GAMMA * v - ens.W0SQ * hy.sin(x))], np.zeros((2, width)), tol=tol)
    grid = np.repeat(ens.T[:, None], width, axis=1)

    def run():
        out = np.empty((nb * width, ens.T.size))
        for b in range(nb):
            ta.set_time(0.0)
            ta.state[0, :] = th_p[b]
            ta.state[1, :] = om_p[b]
            out[b * width : (b + 1) * width] = ta.propagate_grid(grid)[-1][:, 0, :].T
        return out[:n]

    return run, width


def _rounds(n, repeat, paths, exe, nb, th0, om0, hy_run=None):
    """Best times of every contender, measured in `repeat` interleaved rounds
    (each path in a fresh interpreter, the C loop, numba, heyoka): load from
    other processes then hits all alike.  Returns ({path: child result}, [C s,
    numba s] each as [into fresh outputs, into reused ones], heyoka s)."""
    res, peer, nb_cpu, hy_cpu = {}, [np.inf, np.inf], [np.inf, np.inf], np.inf
    import bench_ensembles as ens

    keep = np.empty((th0.size, ens.T.size))
    for _ in range(repeat):
        for path in paths:
            r = _path_run(path, n, 2)
            if path not in res:
                res[path] = r
            else:
                for k in r:
                    if k != "path" and k != "err":
                        res[path][k] = min(res[path][k], r[k])
        if exe is not None:
            peer = [min(a, b) for a, b in zip(peer, _c_peer(exe, n))]
        if nb is not None:
            nb_cpu[0] = min(nb_cpu[0], _thread_cpu(lambda: nb(th0, om0), 1))
            nb_cpu[1] = min(nb_cpu[1], _thread_cpu(lambda: nb(th0, om0, keep), 1))
        if hy_run is not None:
            hy_cpu = min(hy_cpu, _thread_cpu(hy_run, 1))
    return res, peer, nb_cpu, hy_cpu


def _small_batch(repeat, m=200):
    """Best wall times (default threads, threads=1) of rk4_batch on m states, interleaved."""
    import bench_ensembles as ens

    th0, om0 = ens.scene(m)
    return harness.best_times_interleaved(
        [lambda: ens.run_batch(th0, om0, None), lambda: ens.run_batch(th0, om0, 1)], max(repeat * 4, 20)
    )


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
    from pendula._many import kernels as _batch

    hy_run, hy_width = _heyoka_batch(th0, om0)
    hy_err = float("nan")
    if hy_run is not None:
        ref = _batch.rk4_batch(ens.T, th0, om0, np.sqrt(ens.W0SQ), ens.GAMMA, ens.H / 16).theta
        hy_err = float(np.abs(hy_run() - ref).max())  # also compiles outside the timing
    with tempfile.TemporaryDirectory() as tmp:
        exe, peer_how = _build_c_peer(tmp)
        paths, peer_cpu, nb_cpu, hy_cpu = _rounds(n, repeat, info["available"], exe, nb1, th0, om0, hy_run)
    if exe is None:
        peer_cpu = None
    rows = []
    for path, r in paths.items():
        name = f"pendula batch, 1 thread, path {path}" + (" (default)" if path == info["path"] else "")
        rows.append((name, r["cpu1"], r["err"]))
        rows.append((name + ", outputs reused (out=)", r["cpu1_out"], r["err"]))
    if peer_cpu is not None:
        rows.append((f"C loop, {peer_how}", peer_cpu[0], float("nan")))
        rows.append((f"C loop, {peer_how}, outputs reused", peer_cpu[1], float("nan")))
    if nb1 is not None:
        rows.append(("numba njit, 1 thread", nb_cpu[0], float("nan")))
        rows.append(("numba njit, 1 thread, outputs reused", nb_cpu[1], float("nan")))
    nb = nb1
    if hy_run is not None:
        rows.append((f"heyoka.py batch (SIMD width {hy_width}), tol 1e-7, 1 thread", hy_cpu, hy_err))

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
        ratios.append(
            f"default path / C loop, 1 thread: {peer_cpu[0] / best['cpu1']:.2f}x into fresh outputs, "
            f"{peer_cpu[1] / best['cpu1_out']:.2f}x both into reused ones (target >= 1)"
        )
    if nb is not None:
        ratios.append(
            f"default path / numba, 1 thread: {nb_cpu[0] / best['cpu1']:.2f}x into fresh outputs, "
            f"{nb_cpu[1] / best['cpu1_out']:.2f}x both into reused ones (target >= 7x)"
        )
    if hy_run is not None:
        ratios.append(
            f"default path / heyoka.py batch, 1 thread: {hy_cpu / best['cpu1']:.2f}x "
            f"(heyoka {n / hy_cpu:,.0f} states/s, pendula {n / best['cpu1']:,.0f} states/s)"
        )
    else:
        ratios.append(str(hy_width))  # why heyoka.py was not timed
    for path, r in paths.items():
        ratios.append(
            f"path {path}, 2 threads / 1 thread, wall: {r['wall1'] / r['wall2']:.2f}x into fresh outputs, "
            f"{r['wall1_out'] / r['wall2_out']:.2f}x into reused ones (target >= 1.8x; only meaningful on "
            f"an idle machine)"
        )
    t_def, t_one = _small_batch(repeat)
    ratios.append(
        f"200 states, default threads / threads=1, wall: {t_def / t_one:.2f} "
        f"({t_def * 1e3:.2f} ms against {t_one * 1e3:.2f} ms; target <= 1)"
    )
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
