#!/usr/bin/env python3
"""Work-precision of every pendula model on standard scenes, with SciPy on the same axes.

Scenes (w0 = sqrt(2): the text's g = 9.8, l = 4.9):
  text_fig14_b0.01   text §2.2 / fig 14: theta0 = 0, Omega0 = 2 rad/s, m = 0.1 kg, b = 0.01 kg/s, t <= 30 s
  text_fig14_b0.05   the same with b = 0.05 kg/s
  text_fig08_0.9pi   text figs 5-8: theta0 = 0.9 pi from rest, undamped, 10 periods of T0
  text_fig10_over    text fig 10: gamma = 3 w0, theta0 = 0.1, Omega0 = 0.5, t <= 10 s
  near_separatrix    theta0 = pi - 1e-3 from rest, undamped, 10 (exact) periods
  long_1000_periods  theta0 = 1, Omega0 = 0, gamma = 1e-4 w0, 1000 periods of T0 (100 with --quick)
  stiff_damping      theta0 = 1, gamma = 1e3 w0, t <= 100 s (the slow creep back)

For each scene: pendula.tradeoff (closed forms that apply; RK4 at halving
steps; CVODE at rtol 1e-3 ... 1e-12 with atol = rtol * scale / 100) and
scipy.integrate.solve_ivp (RK45, DOP853, LSODA, and Radau/BDF for the stiff
scene) at rtol 1e-3 ... 1e-12 (atol = rtol * 1e-3), each against the same
reference, on the scene's output grid.  Error = sup over the grid of
max(|d theta|, |d Omega|/w0); time = best wall time of the repeats, whole
Python call.  Also what pendula.solve picks at tol = 1e-6 and 1e-10, with its
estimate, true error and cost.

Writes (to --out DIR, default bench_tradeoff_out/): <scene>.csv, <scene>.png,
tradeoff_summary.md; prints the summary.

    python3 benchmarks/bench_tradeoff.py [--quick] [--out DIR]
"""

import csv
import math
import pathlib
import time

import harness
import numpy as np
from scipy.integrate import solve_ivp

import pendula
from pendula._scipy_rows import rhs_and_jacobian

W0 = math.sqrt(9.8 / 4.9)
T0 = 2 * math.pi / W0


def scenes(quick):
    long_p = 100 if quick else 1000
    n = 201 if quick else 601
    return [
        ("text_fig14_b0.01", dict(theta0=0.0, omega0=2.0, mass=0.1, b=0.01), np.linspace(0, 30, n)),
        ("text_fig14_b0.05", dict(theta0=0.0, omega0=2.0, mass=0.1, b=0.05), np.linspace(0, 30, n)),
        ("text_fig08_0.9pi", dict(theta0=0.9 * math.pi, omega0=0.0), np.linspace(0, 10 * T0, n)),
        ("text_fig10_over", dict(theta0=0.1, omega0=0.5, gamma=3 * W0), np.linspace(0, 10, n)),
        (
            "near_separatrix",
            dict(theta0=math.pi - 1e-3, omega0=0.0),
            np.linspace(0, 10 * pendula.period(math.pi - 1e-3, 0.0, W0), n),
        ),
        ("long_1000_periods", dict(theta0=1.0, omega0=0.0, gamma=1e-4 * W0), np.linspace(0, long_p * T0, n)),
        ("stiff_damping", dict(theta0=1.0, omega0=0.0, gamma=1e3 * W0), np.linspace(0, 100, n)),
    ]


def scipy_rows(scene, ref, quick, repeat):
    gamma, w0 = scene.gamma, scene.w0
    stiff = gamma > 20 * w0
    methods = ["Radau", "BDF", "LSODA"] if stiff else ["RK45", "DOP853", "LSODA"]
    rtols = [10.0**-k for k in range(3, 13, 3 if quick else 1)]
    budget = 0.5 if quick else 8.0  # seconds per run before tighter settings are skipped
    t = scene.t
    rhs, jac = rhs_and_jacobian(w0, gamma)  # the same right-hand side as pendula.tradeoff's SciPy rows
    rows = []
    for m in methods:
        for r in rtols:
            kw = {"jac": jac} if m in ("Radau", "BDF", "LSODA") else {}
            # best wall time of the same repeats as pendula.tradeoff's rows
            wall, _, _, sol = harness.best_run(
                lambda m=m, r=r, kw=kw: solve_ivp(
                    rhs, (0.0, t[-1]), [scene.theta0, scene.omega0], method=m, t_eval=t, rtol=r, atol=r * 1e-3, **kw
                ),
                repeat,
            )
            if sol.status != 0:
                break
            err = max(np.max(np.abs(sol.y[0] - ref.theta)), np.max(np.abs(sol.y[1] - ref.omega)) / w0)
            rows.append(
                {
                    "model": f"scipy {m}",
                    "setting": f"rtol={r:.0e}",
                    "sup_error": float(err),
                    "wall_time": wall,
                    "rhs_evals": int(sol.nfev),
                    "closed_form_evals": 0,
                    "error_estimate": 0.0,
                }
            )
            if wall > budget:
                break
    return rows


def auto_rows(name, scene_kw, t, ref, w0):
    out = []
    for tol in (1e-6, 1e-10):
        s = pendula.Scene(t=t, tol=tol, **scene_kw)
        wall, _, _, r = harness.best_run(lambda s=s: pendula.solve(s), 1)
        err = max(np.max(np.abs(r.theta - ref.theta)), np.max(np.abs(r.omega - ref.omega)) / w0)
        out.append(
            dict(
                scene=name,
                tol=tol,
                model=r.model,
                estimate=r.error_estimate,
                true_error=float(err),
                tol_met=r.tol_met,
                wall_time=wall,
                rhs_evals=r.cost["rhs_evals"],
                closed_form_evals=r.cost["closed_form_evals"],
                reason=r.reason,
            )
        )
    return out


def cheapest(rows, target):
    """Per model family: the fastest row with sup error <= target."""
    best = {}
    for r in rows:
        if r["sup_error"] <= target:
            k = r["model"]
            if k not in best or r["wall_time"] < best[k]["wall_time"]:
                best[k] = r
    return best


def main(argv=None):
    ap = harness.parser(
        __doc__,
        "fewer settings and shorter long run (a few s)",
        "output folder (CSV, PNG, markdown; default bench_tradeoff_out)",
    )
    ap.set_defaults(out=pathlib.Path("bench_tradeoff_out"))
    args = ap.parse_args(argv)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        plt = None
    repeat = 1 if args.quick else 3
    md = [
        "# Work-precision of pendula's models (bench_tradeoff.py)",
        "",
        f"Mode: {'quick' if args.quick else 'full'}; CVODE built: {pendula.build_info()['cvode']}. "
        "Error: sup over the output grid of max(|dθ|, |dΩ|/w0) in rad against the reference; "
        "time: best wall time of a whole Python call.",
        "",
    ]
    autos = []
    for name, kw, t in scenes(args.quick):
        scene = pendula.Scene(t=t, tol=1e-6, **kw)
        tstart = time.perf_counter()
        table = pendula.tradeoff(
            scene,
            repeat=repeat,
            max_steps=200_000 if args.quick else 2_000_000,
            scipy=False,
            cvode_rtols=[10.0**-k for k in range(3, 13, 3 if args.quick else 1)],
        )
        ref = table.reference_result
        rows = list(table.rows) + scipy_rows(table.scene, ref, args.quick, repeat)
        with open(out / f"{name}.csv", "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(table.COLUMNS), extrasaction="ignore")
            w.writeheader()
            w.writerows(rows)
        if plt is not None:
            fig, ax = plt.subplots(figsize=(7.5, 5.0))
            desc = ", ".join(f"{k}={v:.4g}" for k, v in kw.items())
            table.plot(None, ax=ax, title=f"{name}: {desc}, t <= {t[-1]:.4g} s")
            fams = []
            for r in rows:
                if r["model"].startswith("scipy") and r["model"] not in fams:
                    fams.append(r["model"])
            for i, f in enumerate(fams):
                rs = [r for r in rows if r["model"] == f]
                ax.loglog(
                    [r["wall_time"] for r in rs],
                    [max(r["sup_error"], 1e-17) for r in rs],
                    linestyle="--",
                    marker="x+1234"[i % 5],
                    label=f,
                )
            ax.legend(fontsize=7)
            fig.tight_layout()
            fig.savefig(out / f"{name}.png", dpi=110)
            plt.close(fig)
        autos += auto_rows(name, kw, t, ref, table.scene.w0)
        md += [f"## {name}", "", f"`{scene!r}`", "", f"Reference: {table.reference}.", ""]
        for target in (1e-6, 1e-10):
            best = cheapest(rows, target)
            if not best:
                md += [f"No method reached {target:g} rad.", ""]
                continue
            md += [
                f"Cheapest run of each method with sup error <= {target:g} rad:",
                "",
                "| method | setting | sup error [rad] | wall time [s] | rhs evals |",
                "|---|---|---|---|---|",
            ]
            for k, r in sorted(best.items(), key=lambda kv: kv[1]["wall_time"]):
                md.append(f"| {k} | {r['setting']} | {r['sup_error']:.2e} | {r['wall_time']:.2e} | {r['rhs_evals']} |")
            md.append("")
        md += [f"(scene measured in {time.perf_counter() - tstart:.1f} s; CSV {name}.csv, plot {name}.png)", ""]
        print(f"{name}: {len(rows)} runs, {time.perf_counter() - tstart:.1f} s", flush=True)
    md += [
        "## What pendula.solve picks",
        "",
        "| scene | tol | model | estimate | true error | tol met | wall time [s] | rhs evals |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for a in autos:
        md.append(
            f"| {a['scene']} | {a['tol']:g} | {a['model']} | {a['estimate']:.1e} | {a['true_error']:.1e} | "
            f"{a['tol_met']} | {a['wall_time']:.2e} | {a['rhs_evals']} |"
        )
    text = "\n".join(md)
    harness.write_outputs(out, "tradeoff_summary", text)
    print()
    print(text)
    print(f"wrote {out.resolve()}/ (CSV, PNG, tradeoff_summary.md)")


if __name__ == "__main__":
    main()
