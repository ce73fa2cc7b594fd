#!/usr/bin/env python3
"""Speed and accuracy of pendula.taylor against heyoka.py, measured in the same run.

Problem: the damped pendulum theta'' + gamma theta' + w0**2 sin(theta) = 0,
theta0 = 2.5 rad, Omega0 = 0, w0 = sqrt(2) 1/s; over 30 s (gamma = 0.1, 31
outputs) and over 1000 s (gamma = 0.001, 101 outputs), at tol 1e-8, 1e-12 and
1e-15.  Both integrators get the same tol (heyoka's is its per-step
tolerance; pendula's is the accuracy asked at the outputs).  Error = max over
the outputs of max(|theta - ref|, |Omega - ref|/w0), ref = heyoka in 80-bit
extended precision at tol 1e-19 (it agrees with mpmath at 30 digits to ~1e-17
on the 30 s window).  Times: CPU time of the process (time.process_time:
on a machine shared with other work the wall time mostly measures the
waiting), best of interleaved repeats of one whole call (pendula: the Python
call; heyoka: reset the state and time, propagate_grid; its JIT compilation
is done once before timing and not counted).  Both run on one thread.

Batch: 2,000 states (theta0 uniform in [0.1, 3], Omega0 in [-1, 1]), gamma =
0.1, 30 s, 601 outputs, tol 1e-10, one thread for pendula, heyoka's batch
integrator (SIMD width of this machine's doubles) state by batch; states/s.

Scenes: pendula.solve (the model it picks, its verification included) on
damped scenes at tol 1e-12 and 1e-14 relative to the motion's size (|theta0| +
|Omega0|/w0, as solve's floor is stated): the true error against the
extended-precision reference, whether tol is met, and the CPU time against
heyoka's propagate_grid at the same tol over the same window and outputs; and
the 1000 s window at tol 1e-8 (theta0 = 2.5, gamma = 0.001, 1001 outputs)
against solve forced to RK4 (the model it took before the Taylor series) and
heyoka.  Targets: tol met at <= 3x heyoka's time; the 1000 s window >= 20x
faster than RK4.

heyoka.py is a benchmark requirement (the `bench` extra), never a runtime
dependency: without it the script prints pendula's rows alone.

    python3 benchmarks/bench_taylor.py [--quick] [--out DIR]
"""

import math
import sys
import time

import harness
import numpy as np

import pendula

W0 = math.sqrt(2.0)
TOLS = (1e-8, 1e-12, 1e-15)
WINDOWS = ((30.0, 0.1, 31), (1000.0, 0.001, 101))

try:
    import heyoka as hy
except ImportError:  # optional peer
    hy = None


def _system():
    x, v = hy.make_vars("x", "v")
    return [(x, v), (v, -hy.par[1] * v - hy.par[0] * hy.sin(x))]


def reference(t, gamma, theta0=2.5):
    """heyoka in long double at tol 1e-19 (the problem's extended-precision reference)."""
    return reference_state(t, gamma, theta0, 0.0)


def reference_state(t, gamma, theta0, omega0):
    """The same from any start (theta0, omega0) at t[0]."""
    ld = np.longdouble
    ta = hy.taylor_adaptive(
        _system(), [ld(theta0), ld(omega0)], tol=ld(1e-19), pars=[ld(2), ld(gamma)], fp_type=ld, time=ld(t[0])
    )
    states = ta.propagate_grid(np.asarray(t, dtype=ld))[-1]
    return states[:, 0], states[:, 1]


def error(theta, omega, ref):
    return float(np.max(np.maximum(abs(theta - ref[0]), abs(omega - ref[1]) / W0)))


def single_rows(repeat):
    rows = []
    for t_end, gamma, n_out in WINDOWS:
        t = np.linspace(0.0, t_end, n_out)
        ref = reference(t, gamma) if hy else None
        for tol in TOLS:
            r = pendula.taylor(t, 2.5, 0.0, W0, gamma, tol=tol)
            fns = [lambda: pendula.taylor(t, 2.5, 0.0, W0, gamma, tol=tol)]
            if hy:
                ta = hy.taylor_adaptive(_system(), [2.5, 0.0], tol=tol, pars=[2.0, gamma])

                def run_heyoka(ta=ta):
                    ta.time = 0.0
                    ta.state[:] = (2.5, 0.0)
                    return ta.propagate_grid(t)

                fns.append(run_heyoka)
            times = harness.best_times_interleaved(fns, repeat, clock=time.process_time)
            row = [
                f"{t_end:g}",
                f"{gamma:g}",
                f"{tol:.0e}",
                f"{times[0] * 1e6:.1f}",
                str(r.stats["steps"]),
                str(r.stats["order"]),
                f"{r.error.max():.1e}",
            ]
            if hy:
                out = run_heyoka()
                row[4:4] = []
                row += [
                    f"{error(r.theta, r.omega, ref):.1e}",
                    f"{times[1] * 1e6:.1f}",
                    str(out[3]),
                    str(ta.order),
                    f"{error(out[-1][:, 0], out[-1][:, 1], ref):.1e}",
                    f"{times[0] / times[1]:.2f}",
                ]
            rows.append(row)
    header = ["window [s]", "gamma", "tol", "pendula [us]", "steps", "order", "estimate"]
    if hy:
        header += [
            "pendula error",
            "heyoka [us]",
            "heyoka steps",
            "heyoka order",
            "heyoka error",
            "time ratio pendula/heyoka",
        ]
    return header, rows


def batch_rows(n_states, repeat):
    rng = np.random.default_rng(7)
    th0 = rng.uniform(0.1, 3.0, n_states)
    om0 = rng.uniform(-1.0, 1.0, n_states)
    t = np.linspace(0.0, 30.0, 601)
    tol, gamma = 1e-10, 0.1
    fns = [lambda: pendula.taylor(t, th0, om0, W0, gamma, tol=tol, threads=1)]
    if hy:
        width = hy.recommended_simd_size()
        nb = -(-n_states // width)
        pad = nb * width - n_states
        th_p = np.concatenate([th0, th0[:pad]]).reshape(nb, width)
        om_p = np.concatenate([om0, om0[:pad]]).reshape(nb, width)
        ta = hy.taylor_adaptive_batch(
            _system(), np.zeros((2, width)), tol=tol, pars=np.array([[2.0] * width, [gamma] * width])
        )
        grid = np.repeat(t[:, None], width, axis=1)

        def run_heyoka():
            out = []
            for b in range(nb):
                ta.set_time(0.0)
                ta.state[0, :] = th_p[b]
                ta.state[1, :] = om_p[b]
                out.append(ta.propagate_grid(grid)[-1])
            return out

        fns.append(run_heyoka)
    times = harness.best_times_interleaved(fns, repeat, clock=time.process_time)
    r = fns[0]()
    row = [str(n_states), f"{tol:.0e}", f"{n_states / times[0]:,.0f}", f"{r.error.max():.1e}"]
    header = ["states", "tol", "pendula states/s (1 thread)", "pendula max estimate"]
    if hy:
        out = fns[1]()
        ref_err = 0.0
        for i in (0, n_states // 2, n_states - 1):  # three states checked against each other
            b, lane = divmod(i, width)
            ref_err = max(ref_err, float(np.max(abs(out[b][:, 0, lane] - r.theta[i]))))
        row += [f"{n_states / times[1]:,.0f}", str(width), f"{ref_err:.1e}", f"{times[0] / times[1]:.2f}"]
        header += [
            "heyoka states/s (batch)",
            "heyoka SIMD width",
            "max |pendula - heyoka| theta",
            "time ratio pendula/heyoka",
        ]
    return header, [row]


# (theta0, Omega0, gamma, t): the scene and two more damped ones (as tests/python/test_scene_taylor.py)
SCENES = (
    (2.5, 0.0, 0.1, np.linspace(0.0, 30.0, 31)),
    (1.0, 0.5, 0.3, np.linspace(0.0, 20.0, 11)),
    (0.2, -1.0, 0.05, np.linspace(0.0, 25.0, 6)),
)


def _heyoka_runner(theta0, omega0, gamma, t, tol):
    ta = hy.taylor_adaptive(_system(), [theta0, omega0], tol=tol, pars=[2.0, gamma])

    def run():
        ta.time = float(t[0])
        ta.state[:] = (theta0, omega0)
        return ta.propagate_grid(t)

    return run


def scene_rows(repeat):
    rows = []
    for theta0, omega0, gamma, t in SCENES:
        ref = reference_state(t, gamma, theta0, omega0) if hy else None
        size = abs(theta0) + abs(omega0) / W0
        for rel in (1e-12, 1e-14):
            sc = pendula.Scene(theta0=theta0, omega0=omega0, t=t, gamma=gamma, tol=rel * size)
            r = pendula.solve(sc)
            fns = [lambda sc=sc: pendula.solve(sc)]
            if hy:
                fns.append(_heyoka_runner(theta0, omega0, gamma, t, rel * size))
            times = harness.best_times_interleaved(fns, repeat, clock=time.process_time)
            row = [
                f"{theta0:g}, {omega0:g}",
                f"{gamma:g}",
                f"{t[-1]:g}",
                f"{rel:.0e} ({rel * size:.1e})",
                r.model,
                "yes" if r.tol_met else "NO",
                f"{r.error_estimate:.1e}",
                f"{times[0] * 1e6:.1f}",
            ]
            if hy:
                row += [
                    f"{error(r.theta, r.omega, ref):.1e}",
                    f"{times[1] * 1e6:.1f}",
                    f"{times[0] / times[1]:.2f}",
                ]
            rows.append(row)
    header = ["theta0, Omega0", "gamma", "window [s]", "tol rel (abs)", "model", "tol met", "estimate", "solve [us]"]
    if hy:
        header += ["true error", "heyoka [us]", "time ratio solve/heyoka"]
    return header, rows


def long_window_rows(repeat):
    t = np.linspace(0.0, 1000.0, 1001)
    sc = pendula.Scene(theta0=2.5, t=t, gamma=0.001, tol=1e-8)
    r = pendula.solve(sc)
    old = pendula.solve(sc, model="rk4")
    fns = [lambda: pendula.solve(sc), lambda: pendula.solve(sc, model="rk4")]
    if hy:
        fns.append(_heyoka_runner(2.5, 0.0, 0.001, t, 1e-8))
    times = harness.best_times_interleaved(fns, repeat, clock=time.process_time)
    ref = reference_state(t, 0.001, 2.5, 0.0) if hy else None
    rows = []
    for name, res, tm in ((f"solve ({r.model})", r, times[0]), ("solve(model='rk4')", old, times[1])):
        row = [name, "yes" if res.tol_met else "NO", f"{res.error_estimate:.1e}", f"{tm * 1e3:.2f}"]
        row.append(f"{times[1] / tm:.1f}")
        if hy:
            row += [f"{error(res.theta, res.omega, ref):.1e}", f"{tm / times[2]:.2f}"]
        rows.append(row)
    header = ["run", "tol met", "estimate", "CPU [ms]", "speed-up over RK4"]
    if hy:
        header += ["true error", "time ratio / heyoka"]
    return header, rows


def main(argv=None):
    ap = harness.parser(__doc__, "fewer repeats and states", "write bench_taylor.md there")
    args = ap.parse_args(argv)
    repeat = 5 if args.quick else 25
    n_states = 500 if args.quick else 2000
    parts = [
        "Single state: damped pendulum, theta0 = 2.5 rad, w0 = sqrt(2) 1/s"
        + ("" if hy else " (heyoka.py not installed: pendula only)"),
        "",
    ]
    h1, r1 = single_rows(repeat)
    parts += [harness.markdown_table(h1, r1), "", f"Batch: {n_states} states, 30 s, 601 outputs", ""]
    h2, r2 = batch_rows(n_states, max(3, repeat // 5))
    parts += [harness.markdown_table(h2, r2), "", "Scenes: solve at tol relative to the motion's size", ""]
    h3, r3 = scene_rows(repeat)
    parts += [harness.markdown_table(h3, r3), "", "Scene: 1000 s window, theta0 = 2.5, gamma = 0.001, tol 1e-8", ""]
    h4, r4 = long_window_rows(max(3, repeat // 5))
    parts.append(harness.markdown_table(h4, r4))
    text = "\n".join(parts)
    print(text)
    harness.write_outputs(args.out, "bench_taylor", text, tables=[(h1, r1), (h2, r2), (h3, r3), (h4, r4)])


if __name__ == "__main__":
    sys.exit(main())
