#!/usr/bin/env python3
"""RK4 vs CVODE vs exact solutions on the text's scenarios (§2.2, figs 14-15).

Mirrors examples/fortran/example_integrators.f90.
1. The text's nonlinear damped scene (g = 9.8 m/s^2, l = 4.9 m, m = 0.1 kg,
   b = 0.01 and 0.05 kg/s, theta0 = 0, Omega0 = 2 rad/s, t <= 30 s): max |theta error|
   [rad] on t = 0, 1, ..., 30 s of pendula.rk4 at the text's h = 0.05 s, of
   pendula.cvode (Adams, rtol 1e-8), and of the text's listing AS PRINTED (line 67
   reads m2 = m1 * h * k1 / 2.0 for m1 + h * k1 / 2.0), against CVODE BDF at
   rtol 1e-12 (RK4 at h = 1e-4 s when SUNDIALS is not built).
2. gamma = 0: both integrators against the exact elliptic solution.
3. Small amplitude with damping: both against the linear closed form.
Writes integrators_comparison.csv into --out.
"""

import time

import _example_support
import numpy as np

import pendula
from pendula.textbook import text_listing_rk4

COLUMNS = ["scenario", "b_kg_per_s", "gamma_per_s", "method", "max_theta_error_rad", "rhs_evals", "wall_time_s"]


def text_listing(theta0, omega0, w0, gamma, h, t_out):
    """theta [rad] of the text's §2.2 listing as printed (with its line-67 typo) at
    t_out (a uniform grid from 0 whose spacing is a multiple of h).

    Kept here only to show how far it drifts; pendula.rk4 is the correct method.
    """
    per_output = int(round((t_out[1] - t_out[0]) / h))
    _, theta, _ = text_listing_rk4(t_out[-1], h, theta0, omega0, w0, gamma, typo=True)
    return theta[::per_output][: len(t_out)]


def timed(fn, *args, **kw):
    t0 = time.perf_counter()
    res = fn(*args, **kw)
    return res, time.perf_counter() - t0


def main(argv=None):
    args = _example_support.parse_args(__doc__, "integrators_comparison.csv", argv)

    w0 = pendula.natural_frequency(9.8, 4.9)
    t = np.arange(31.0)
    cv = pendula.build_info()["cvode"]
    print(f"CVODE (SUNDIALS) built: {cv}")
    rows = []

    print("\n1. The text's scene, theta0 = 0, Omega0 = 2 rad/s, t in [0, 30] s: max |theta - reference| [rad]")
    print(
        f"{'b [kg/s]':>9} {'gamma [1/s]':>12} {'RK4 h=0.05':>12} {'CVODE Adams 1e-8':>17} "
        f"{'text listing':>13} {'RK4 rhs evals':>14} {'CVODE rhs evals':>16}"
    )
    for b, gamma in _example_support.text_damping():
        ref, _ = _example_support.tight_reference(t, 0.0, 2.0, w0, gamma, method="bdf")
        rk, rk_s = timed(pendula.rk4, t, 0.0, 2.0, w0, gamma, 0.05)
        txt = text_listing(0.0, 2.0, w0, gamma, 0.05, t)
        e_rk = np.max(np.abs(rk.theta - ref))
        e_txt = np.max(np.abs(txt - ref))
        if cv:
            cvr, cv_s = timed(pendula.cvode, t, 0.0, 2.0, w0, gamma, rtol=1e-8, atol=1e-10)
            e_cv, cv_evals = np.max(np.abs(cvr.theta - ref)), cvr.stats["rhs_evals"]
        else:
            e_cv, cv_evals, cv_s = float("nan"), 0, float("nan")
        print(
            f"{b:9.2f} {gamma:12.3f} {e_rk:12.3e} {e_cv:17.3e} {e_txt:13.3e} {rk.stats['rhs_evals']:14d} {cv_evals:16d}"
        )
        rows += [
            ["text scene", b, gamma, "rk4 h=0.05", e_rk, rk.stats["rhs_evals"], rk_s],
            ["text scene", b, gamma, "cvode adams rtol=1e-8", e_cv, cv_evals, cv_s],
            ["text scene", b, gamma, "text listing as printed h=0.05", e_txt, 4 * 600, float("nan")],
        ]

    print("\n2. Undamped (gamma = 0), theta0 = 0.9 pi, Omega0 = 0: max |theta - exact elliptic| [rad]")
    exact, _ = pendula.undamped(t, 0.9 * np.pi, 0.0, w0)
    e_rk = np.max(np.abs(pendula.rk4(t, 0.9 * np.pi, 0.0, w0, 0.0, 0.01).theta - exact))
    e_cv = np.max(np.abs(pendula.cvode(t, 0.9 * np.pi, 0.0, w0, 0.0).theta - exact)) if cv else float("nan")
    print(f"   RK4 h = 0.01 s: {e_rk:.3e}   CVODE Adams 1e-8: {e_cv:.3e}")
    rows += [
        ["undamped 0.9 pi", 0.0, 0.0, "rk4 h=0.01", e_rk, "", ""],
        ["undamped 0.9 pi", 0.0, 0.0, "cvode adams rtol=1e-8", e_cv, "", ""],
    ]

    print("\n3. Small amplitude, theta0 = 1e-3 rad, gamma = 0.5 1/s: max |theta - linear closed form| [rad]")
    print("   (the nonlinearity itself is ~theta0^3/16 ~ 6e-11 rad)")
    lin, _ = pendula.linear_damped(t, 1e-3, 0.0, w0, 0.5)
    e_rk = np.max(np.abs(pendula.rk4(t, 1e-3, 0.0, w0, 0.5, 0.01).theta - lin))
    e_cv = np.max(np.abs(pendula.cvode(t, 1e-3, 0.0, w0, 0.5).theta - lin)) if cv else float("nan")
    print(f"   RK4 h = 0.01 s: {e_rk:.3e}   CVODE Adams 1e-8: {e_cv:.3e}")
    rows += [
        ["linear small amplitude", "", 0.5, "rk4 h=0.01", e_rk, "", ""],
        ["linear small amplitude", "", 0.5, "cvode adams rtol=1e-8", e_cv, "", ""],
    ]

    _example_support.write_csv(args.out, "integrators_comparison.csv", COLUMNS, rows)


if __name__ == "__main__":
    main()
