"""Ensembles: many pendulums per call, side by side with the usual ways.

The scene: N states of the text's damped pendulum (w0**2 = 2, gamma = 0.1,
theta0 ~ U(-0.1, 0.1) rad, Omega0 ~ U(1.9, 2.1) rad/s), t in [0, 30] s with
601 outputs, RK4 with h = 0.025 s (two steps per output: the largest step
meeting 1e-6 rad for every state).  Contenders, all doing the same 1200 RK4
steps per state except solve_ivp:

  batch 1 thread / all cores  pendula._many.kernels.rk4_batch (SIMD blocks, OpenMP)
  pendula.rk4 loop            one pendula.rk4 call per state from Python
  numba njit / prange         a plain RK4 over states (libm sin), optional
  numpy vectorised            the RK4 stages as array operations across states
  solve_ivp stacked           one DOP853 system of 2N equations (rtol 1e-10)
  batch CVODE 1 thread / all  pendula._many.kernels.cvode_batch (Adams, rtol 1e-8,
                              atol 1e-10: one solver per thread, CVodeReInit)
  pendula.cvode loop          one pendula.cvode call per state, same settings

Columns: states/s (wall), states/s per core (states per CPU-second of the
process: the honest per-core rate when the machine is shared), ns per RK4
step per core against the ~3.3 ns flop floor (136 flops at 16 double
flops/cycle, 2.6 GHz), and the largest error of any state against a fine
reference (batch RK4 at h/16, itself checked against DOP853 at rtol 1e-13).
Slow contenders run on fewer states and are scaled (the N column says how many).
The batch rows include the first-touch page faults of their fresh outputs
(2 x N x 601 doubles per call, ~15% of their time here); the loop recycles
small arrays.  benchmarks/bench_kernels.py times the batch kernel on every
dispatch path against a vectorised C loop (docs/performance.md).

    python benchmarks/bench_ensembles.py [--quick] [--n N] [--out DIR]

numba is optional (pip install numba, or the `bench` extra); without it its
rows say so.  Times are best of --repeat runs.
"""

from __future__ import annotations

import os
import platform

import harness
import numpy as np
from scipy.integrate import solve_ivp

import pendula
from pendula._many import kernels as _batch

W0SQ, GAMMA, H = 2.0, 0.1, 0.025
T = np.linspace(0.0, 30.0, 601)
STEPS = 1200  # per state: 600 outputs x 2 substeps of 0.025 s
FLOOR_NS = 3.3


def scene(n, seed=2024):
    rng = np.random.default_rng(seed)
    return rng.uniform(-0.1, 0.1, n), rng.uniform(1.9, 2.1, n)


# ---- contenders -----------------------------------------------------------


def run_batch(th0, om0, threads, out=None):
    """out: None, or (theta, omega) arrays the batch fills in place (reused pages)."""
    r = _batch.rk4_batch(T, th0, om0, np.sqrt(W0SQ), GAMMA, H, threads=threads, out=out)
    assert r.code == 0, r.message
    return r.theta


RTOL, ATOL = 1e-8, 1e-10  # CVODE rows: pendula.cvode's defaults, every state within 1e-6 rad


def run_cvode_batch(th0, om0, threads):
    r = _batch.cvode_batch(T, th0, om0, np.sqrt(W0SQ), GAMMA, rtol=RTOL, atol=ATOL, threads=threads)
    assert r.code == 0, r.message
    return r.theta


def run_cvode_loop(th0, om0):
    w0 = float(np.sqrt(W0SQ))
    return np.array(
        [pendula.cvode(T, float(a), float(b), w0, GAMMA, rtol=RTOL, atol=ATOL).theta for a, b in zip(th0, om0)]
    )


def run_loop(th0, om0):
    w0 = float(np.sqrt(W0SQ))
    return np.array([pendula.rk4(T, float(a), float(b), w0, GAMMA, H).theta for a, b in zip(th0, om0)])


def run_numpy(th0, om0):
    y, u = th0.copy(), om0.copy()
    out = np.empty((th0.size, T.size))
    out[:, 0] = y
    h, half = H, H / 2

    def f(yy, uu):
        return -GAMMA * uu - W0SQ * np.sin(yy)

    for j in range(1, T.size):
        for _ in range(2):
            k1 = f(y, u)
            k2 = f(y + half * u, u + half * k1)
            m2 = u + half * k1
            k3 = f(y + half * m2, u + half * k2)
            m3 = u + half * k2
            k4 = f(y + h * m3, u + h * k3)
            y = y + h * u + (h * h / 6) * (k1 + k2 + k3)
            u = u + (h / 6) * (k1 + 2 * (k2 + k3) + k4)
        out[:, j] = y
    return out


def run_solve_ivp(th0, om0):
    n = th0.size

    def rhs(_, z):
        y, u = z[:n], z[n:]
        return np.concatenate([u, -GAMMA * u - W0SQ * np.sin(y)])

    sol = solve_ivp(rhs, (T[0], T[-1]), np.concatenate([th0, om0]), method="DOP853", t_eval=T, rtol=1e-10, atol=1e-12)
    return sol.y[:n]


def numba_kernels():
    try:
        import numba
    except ImportError:
        return None

    def rk4_states(th0, om0, nout, h, w0sq, gamma, out):
        for s in numba.prange(th0.size):
            y, u = th0[s], om0[s]
            out[s, 0] = y
            half = h / 2
            for j in range(1, nout):
                for _ in range(2):
                    k1 = -gamma * u - w0sq * np.sin(y)
                    m2 = u + half * k1
                    k2 = -gamma * m2 - w0sq * np.sin(y + half * u)
                    m3 = u + half * k2
                    k3 = -gamma * m3 - w0sq * np.sin(y + half * m2)
                    k4 = -gamma * (u + h * k3) - w0sq * np.sin(y + h * m3)
                    y = y + h * u + (h * h / 6) * (k1 + k2 + k3)
                    u = u + (h / 6) * (k1 + 2 * (k2 + k3) + k4)
                out[s, j] = y

    serial = numba.njit(cache=False)(rk4_states)
    parallel = numba.njit(parallel=True, cache=False)(rk4_states)

    def mk(fn, threads):
        def run(th0, om0, out=None):
            numba.set_num_threads(threads)
            out = np.empty((th0.size, T.size)) if out is None else out
            fn(th0, om0, T.size, H, W0SQ, GAMMA, out)
            return out

        return run

    return mk(serial, 1), mk(parallel, numba.config.NUMBA_NUM_THREADS), numba.config.NUMBA_NUM_THREADS


# ---- main -------------------------------------------------------------------


def main(argv=None):
    ap = harness.parser(
        __doc__, "2,000 states, slow contenders on fewer (a few seconds)", "also write bench_ensembles.md here"
    )
    args, n, repeat = harness.parse_with_sizes(
        ap, argv, "states (default 10,000; --quick 2,000)", n=(2_000, 10_000), repeat=(2, 3)
    )
    ncores = os.cpu_count() or 1
    th0, om0 = scene(n)

    # Reference: batch RK4 at h/16 (error ~ 1e-7 / 16**4), checked on a few
    # states against DOP853 at rtol 1e-13.
    ref = _batch.rk4_batch(T, th0, om0, np.sqrt(W0SQ), GAMMA, H / 16).theta
    ref_check = 0.0
    for i in range(0, n, max(1, n // 5)):
        d = solve_ivp(
            lambda _, z: [z[1], -GAMMA * z[1] - W0SQ * np.sin(z[0])],
            (0, 30),
            [th0[i], om0[i]],
            method="DOP853",
            t_eval=T,
            rtol=1e-13,
            atol=1e-14,
        ).y[0]
        ref_check = max(ref_check, float(np.abs(d - ref[i]).max()))

    sub = {"loop": min(n, 1000 if args.quick else 3000), "numpy": n, "solve_ivp": min(n, 100 if args.quick else 500)}
    rows = []

    def add(name, fn, m, steps=STEPS, threads=1, rep=repeat):
        w, c, _, theta = harness.best_run(lambda: fn(th0[:m], om0[:m]), rep)
        err = float(np.abs(theta - ref[:m]).max())
        rows.append(
            dict(
                name=name,
                n=m,
                threads=threads,
                wall=w,
                cpu=c,
                sps=m / w,
                sps_core=m / c,
                ns_step=(c / (m * steps) * 1e9) if steps else float("nan"),
                err=err,
            )
        )
        print(f"  {name:<24s} {m:>6d} states  wall {w:8.3f} s  cpu {c:8.3f} s  max err {err:.2e}", flush=True)

    print(
        f"pendula {pendula.__version__}, {platform.machine()}, {ncores} cores, load average "
        f"{os.getloadavg()[0]:.1f}; OpenMP in this build: {_batch.openmp()}; "
        f"OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', '(unset)')}"
    )
    print(f"reference (batch RK4, h/16) vs DOP853 rtol 1e-13: {ref_check:.1e} rad")
    add("batch, 1 thread", lambda a, b: run_batch(a, b, 1), n)
    add(f"batch, {ncores} threads", lambda a, b: run_batch(a, b, ncores), n, threads=ncores)
    add("pendula.rk4 loop", run_loop, sub["loop"])
    nb = numba_kernels()
    if nb is not None:
        nb1, nbp, nthr = nb
        nb1(th0[:8], om0[:8])  # compile outside the timing
        nbp(th0[:8], om0[:8])
        add("numba njit, 1 thread", nb1, n)
        add(f"numba prange, {nthr} threads", nbp, n, threads=nthr)
    add("numpy vectorised", run_numpy, sub["numpy"], rep=1 if args.quick else repeat)
    add("solve_ivp stacked DOP853", run_solve_ivp, sub["solve_ivp"], steps=0, rep=1)
    if pendula.have_cvode():
        add("batch CVODE, 1 thread", lambda a, b: run_cvode_batch(a, b, 1), n, steps=0)
        add(f"batch CVODE, {ncores} threads", lambda a, b: run_cvode_batch(a, b, ncores), n, steps=0, threads=ncores)
        add("pendula.cvode loop", run_cvode_loop, sub["loop"], steps=0)

    by = {r["name"]: r for r in rows}
    b1 = by["batch, 1 thread"]
    lines = [
        "| contender | N | threads | states/s | states/s per core | ns/step/core (floor 3.3) | max error [rad] |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        ns = "-" if np.isnan(r["ns_step"]) else f"{r['ns_step']:.1f} ({r['ns_step'] / FLOOR_NS:.1f}x)"
        lines.append(
            f"| {r['name']} | {r['n']} | {r['threads']} | {r['sps']:,.0f} | {r['sps_core']:,.0f} | {ns} "
            f"| {r['err']:.1e} |"
        )
    ratios = [
        f"batch 1 thread / pendula.rk4 loop, per core: {b1['sps_core'] / by['pendula.rk4 loop']['sps_core']:.2f}x"
        " (target >= 4x)"
    ]
    if nb is not None:
        ratios.append(
            f"batch 1 thread / numba 1 thread, per core: "
            f"{b1['sps_core'] / by['numba njit, 1 thread']['sps_core']:.2f}x (target >= 7x)"
        )
    if "pendula.cvode loop" in by:
        ratios.append(
            f"batch CVODE 1 thread / pendula.cvode loop, per core: "
            f"{by['batch CVODE, 1 thread']['sps_core'] / by['pendula.cvode loop']['sps_core']:.2f}x "
            "(target >= 3x)"
        )
    bn = by[f"batch, {ncores} threads"]
    ratios.append(
        f"batch {ncores} threads / 1 thread, wall: {b1['wall'] / bn['wall']:.2f}x (target >= 1.8x; "
        f"only meaningful on an idle machine)"
    )
    ratios.append(
        "every state within 1e-6 rad: " + ", ".join(f"{r['name']} {'yes' if r['err'] < 1e-6 else 'NO'}" for r in rows)
    )
    text = "\n".join(lines + [""] + ["- " + r for r in ratios])
    print()
    print(text)
    harness.write_outputs(args.out, "bench_ensembles", text)


if __name__ == "__main__":
    main()
