#!/usr/bin/env python3
"""Scenes: describe the problem and a tolerance, the library picks the cheapest model that meets it.

Mirrors examples/fortran/example_scene.f90.  Six scenes from small swings to the
text's nonlinear damped run and a near-separatrix rotation (g = 9.8 m/s^2,
l = 4.9 m); for each, the model pendula.solve chose, why, its error estimate,
its cost, and the true error against an independent answer (the exact solution
when undamped, CVODE BDF at rtol 1e-12 otherwise).  Writes scene_solver.csv into --out.
"""

import argparse
import csv
import sys
from pathlib import Path

import numpy as np

import pendula

W0 = np.sqrt(2.0)
T0 = 2 * np.pi / W0

# name, keyword arguments of pendula.Scene (besides g, length, t), window in s, tol in rad
SCENES = [
    ("small swing, undamped", dict(theta0=0.05, omega0=0.0), 10 * T0, 1e-3),
    ("large swing, undamped (text fig 7)", dict(theta0=0.9 * np.pi, omega0=0.0), 10 * T0, 1e-8),
    ("small swing, lightly damped", dict(theta0=0.01, omega0=0.0, gamma=0.1), 10 * T0, 1e-6),
    ("text §2.2 scene, b = 0.01 kg/s", dict(theta0=0.0, omega0=2.0, mass=0.1, b=0.01), 30.0, 1e-6),
    ("near-separatrix rotation", dict(theta0=0.0, omega0=2.0001 * W0), 5 * T0, 1e-9),
    ("strongly damped, large angle", dict(theta0=2.0, omega0=0.0, gamma=50.0), 20.0, 1e-6),
]


def true_theta(kw, t):
    gamma = kw.get("gamma")
    if gamma is None and "b" in kw:
        gamma = pendula.damping_rate(kw["b"], kw["mass"])
    if not gamma:
        return pendula.undamped(t, kw["theta0"], kw["omega0"], W0)[0]
    if pendula.build_info()["cvode"]:
        return pendula.cvode(t, kw["theta0"], kw["omega0"], W0, gamma, rtol=1e-12, atol=1e-14, method="bdf").theta
    return pendula.rk4(t, kw["theta0"], kw["omega0"], W0, gamma, 1e-4).theta


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=".", help="folder for scene_solver.csv (default: .)")
    ap.add_argument("--quick", action="store_true", help="fewer output times per scene")
    args = ap.parse_args(argv)
    if not hasattr(pendula, "Scene") or not hasattr(pendula, "solve"):
        print("not run: pendula.Scene / pendula.solve (the scenes module) are not available in this build")
        return 0

    n = 101 if args.quick else 1001
    print(f"{'scene':36} {'tol [rad]':>9} {'model':>14} {'estimate':>10} {'true error':>10}  reason")
    rows = []
    for name, kw, window, tol in SCENES:
        t = np.linspace(0.0, window, n)
        scene = pendula.Scene(t=t, g=9.8, length=4.9, tol=tol, **kw)
        res = pendula.solve(scene)
        err = float(np.max(np.abs(np.asarray(res.theta) - true_theta(kw, t))))
        print(f"{name:36} {tol:9.0e} {res.model!s:>14} {float(res.error_estimate):10.2e} {err:10.2e}  {res.reason}")
        rows.append([name, tol, res.model, float(res.error_estimate), err, res.reason, res.cost])

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "scene_solver.csv"
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["scene", "tol_rad", "model", "error_estimate_rad", "true_error_rad", "reason", "cost"])
        w.writerows(rows)
    print(f"\nwrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
