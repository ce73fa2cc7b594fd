"""Scenes: honesty and economy of pendula.solve on a seeded grid, against references without pendula code.

For each scene of the grid (benchmarks/scene_grid_draw.py: 432 scenes; --quick:
24 short ones) this script
- builds a reference that shares no code with pendula (benchmarks/scene_reference.py):
  undamped states, periods and events from mpmath elliptic functions at 40 digits,
  damped states and events from a fixed-point Taylor integrator of order 30 (~60
  digits), both once from the data exactly as given (w0 = sqrt(g/l) in mpmath)
  and once with pendula's rounded w0 = fl(sqrt(g/l)) (for Taylor references only
  where the energy parameter is within 1e-3 of the separatrix; elsewhere the
  rounded grade is the exact one); a scene whose Taylor reference needs more
  than --max-steps steps (predicted from its first 100) or --ref-seconds of wall
  time is left out and counted; references are cached on disk (--cache, default
  out/scene-refs) keyed by the scene, with the seconds their build took;
- grades solve(scene): the true error in the Scene error measure (sup over the
  output times of max(|d theta|, |d Omega|/w0); energy: |dE|/w0^2; period:
  w0 |dT|; events: the largest event-time error [s], infinite when the number
  or kinds of events differ), against tol and against the reported estimate;
- economy: runs every applicable model with pendula.run_model over a ladder
  of settings (RK4 step from just inside its stability limit halving, CVODE
  rtol 1e-2 ... 1e-13, the Taylor series at the scene's tol, the closed forms once) and keeps the cheapest whose true
  error over the whole window is <= tol; the wall-time ratio solve / cheapest
  adequate is the best of 3 calls each.
Prints the runtime and the slowest scenes (reference build and grading), the
table, the worst scenes with reproducers (--scene ID re-runs one verbosely;
--ids A:B grades a slice of the grid); --out DIR writes scenes-benchmark.md and .csv (the
table) and scenes-benchmark-scenes.csv (one row per graded scene: its data, model, tol,
estimate, true errors, tol_met, wall time, cheapest adequate model, its time, the ratio,
the reference's build time).
"""

import csv
import hashlib
import json
import math
import pathlib
import sys
import time

import harness
import mpmath as mp
import numpy as np
import scene_grid_draw
import scene_reference as ref

import pendula
from pendula.integrate import TURNING_POINT, ZERO_CROSSING, rk4_max_stable_step

REF_VERSION = 4  # 2: zero crossings are theta = 0 mod 2 pi; 3: settled events in closed form;
#                   4: undamped events from the elliptic solution
HAVE_CVODE = pendula.scene.HAVE_CVODE


def _key(sc):
    blob = json.dumps(
        [
            REF_VERSION,
            sc["theta0"].hex(),
            sc["omega0"].hex(),
            float(sc["g"]).hex(),
            float(sc["length"]).hex(),
            float(sc["gamma"]).hex(),
            np.atleast_1d(sc["t"]).astype(float).tobytes().hex(),
            sc["want"] == "events",
        ]
    )
    return hashlib.sha1(blob.encode()).hexdigest()


def _reference_for(sc, w0, max_steps, max_seconds):
    t = [float(x) for x in np.atleast_1d(sc["t"])]
    events = sc["want"] == "events"
    out = {}
    closed_events = ref.undamped_events(t[-1], sc["theta0"], sc["omega0"], w0) if sc["gamma"] == 0 and events else None
    if sc["gamma"] == 0 and (not events or closed_events is not None):
        th, om, period = ref.undamped(t, sc["theta0"], sc["omega0"], w0)
        out["period"] = str(period)
        if events:
            out["ev_t"] = [mp.nstr(x, 40) for x in closed_events[0]]
            out["ev_k"] = closed_events[1]
    else:
        tay = ref.Taylor(w0, sc["gamma"], max_steps=max_steps, relative=events, max_seconds=max_seconds)
        res = tay.solve(t, sc["theta0"], sc["omega0"], events=events)
        th, om = res[:2]
        if events:
            out["ev_t"] = [mp.nstr(x, 40) for x in res[2]]
            out["ev_k"] = res[3]
        out["taylor_steps"] = tay.steps
    out["theta"] = [mp.nstr(x, 40) for x in th]
    out["omega"] = [mp.nstr(x, 40) for x in om]
    return out


def reference(sc, cache, max_steps, max_seconds=math.inf):
    """{'exact': ..., 'rounded': ..., 'seconds': build time} for scene sc (cached), or None
    beyond the Taylor budget (steps, or seconds per reference run)."""
    path = pathlib.Path(cache) / f"{_key(sc)}.json"
    if path.exists():
        return json.loads(path.read_text())
    w_exact = ref.exact_w0(sc["g"], sc["length"])
    w_round = float(np.sqrt(sc["g"] / sc["length"]))
    t0 = time.perf_counter()
    try:
        data = {"exact": _reference_for(sc, w_exact, max_steps, max_seconds)}
        # the rounding of w0 (relative 1e-16) matters where the energy parameter is near 1;
        # elsewhere a damped (Taylor) reference is graded with the exact data only
        near = abs(ref.energy_parameter(sc["theta0"], sc["omega0"], w_exact) - 1) < 1e-3
        if sc["gamma"] == 0 and sc["want"] != "events" or near:
            data["rounded"] = _reference_for(sc, mp.mpf(w_round), max_steps, max_seconds)
        else:
            data["rounded"] = data["exact"]
    except ref.BudgetExceeded:
        return None
    data["seconds"] = time.perf_counter() - t0
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data))
    return data


def make_scene(sc):
    return pendula.Scene(
        theta0=sc["theta0"],
        omega0=sc["omega0"],
        t=sc["t"],
        g=sc["g"],
        length=sc["length"],
        gamma=sc["gamma"],
        tol=sc["tol"],
        want=sc["want"],
    )


def true_error(sc, res, r, w0):
    """The Scene error measure of result res against reference r (one of the two)."""
    want = sc["want"]
    with mp.workdps(40):
        w0 = mp.mpf(w0)
        if want == "events":
            ev = res.events
            kinds = [TURNING_POINT if k == 1 else ZERO_CROSSING for k in r["ev_k"]]  # the reference's 1 / 2
            if ev is None or len(ev.t) != len(kinds) or list(ev.kind) != kinds:
                return math.inf
            return max((float(abs(mp.mpf(a) - mp.mpf(b))) for a, b in zip(ev.t, r["ev_t"])), default=0.0)
        if want == "period":
            p, q = res.period, mp.mpf(r["period"])
            if p is None or not math.isfinite(p) or q == mp.inf:
                return 0.0 if (p == math.inf and q == mp.inf) else math.inf
            return float(w0 * abs(mp.mpf(p) - q))
        th = [mp.mpf(x) for x in r["theta"]]
        om = [mp.mpf(x) for x in r["omega"]]
        if want == "final":
            return float(max(abs(mp.mpf(res.theta[-1]) - th[-1]), abs(mp.mpf(res.omega[-1]) - om[-1]) / w0))
        if want == "energy":
            e = np.atleast_1d(res.energy)
            if len(e) == 1 and len(th) > 1:
                e = np.repeat(e, len(th))
            return float(
                max(abs(mp.mpf(a) - (o**2 / 2 + w0**2 * (1 - mp.cos(x)))) / w0**2 for a, x, o in zip(e, th, om))
            )
        a = np.atleast_1d(res.theta)
        err = max(abs(mp.mpf(x) - y) for x, y in zip(a, th))
        if want == "state":
            b = np.atleast_1d(res.omega)
            err = max(err, max(abs(mp.mpf(x) - y) / w0 for x, y in zip(b, om)))
        return float(err)


def estimate_of(res, want):
    return res.event_time_error if want == "events" else res.error_estimate


def _ladder(sc, scene):
    """(model, setting) pairs, coarse to fine, for the economy search."""
    t_end = float(np.atleast_1d(sc["t"])[-1])
    closed = ["small_angle", "exact"] if sc["gamma"] == 0 else ["linear"]
    out = [(m, None) for m in closed]
    h = 0.9 * rk4_max_stable_step(scene.w0, scene.gamma)
    rk4 = []
    while t_end / h <= 2e6 and len(rk4) < 22:
        rk4.append(("rk4", h))
        h /= 2
    cv = [("cvode", 10.0**-k) for k in range(2, 14)] if HAVE_CVODE else []
    return out, rk4, cv + [("taylor", 0.0)]  # the Taylor series runs once, at the scene's tol


def _timed(fn, t_first, repeat):
    """Best of the first call's time t_first and `repeat` more calls, but no more
    calls after a first one over a second (long calls vary little; the grid has
    solves of up to ~1 min)."""
    return min(t_first, harness.best_time(fn, repeat if t_first < 1 else 0, warm_up=False))


def cheapest_adequate(sc, scene, r, w0, repeat):
    """(model, setting, wall time, cost) of the cheapest run_model whose true error <= tol."""
    closed, rk4, cv = _ladder(sc, scene)
    tay = [ms for ms in cv if ms[0] == "taylor"]
    cv = [ms for ms in cv if ms[0] != "taylor"]
    found = []
    for group in ([(m, s)] for m, s in closed), [rk4], [cv], [tay]:
        for ladder in group:
            for model, setting in ladder:
                try:
                    t0 = time.perf_counter()
                    res = pendula.run_model(scene, model, setting, max_steps=2_000_000)
                    t_first = time.perf_counter() - t0
                    err = true_error(sc, res, r, w0)
                except Exception:  # noqa: BLE001 -- a model that refuses or fails is not adequate
                    continue
                if err <= sc["tol"]:
                    wall = _timed(
                        lambda: pendula.run_model(scene, model, setting, max_steps=2_000_000), t_first, repeat
                    )
                    found.append((wall, model, setting, res.cost["rhs_evals"] + res.cost["closed_form_evals"]))
                    break
    if not found:
        return None
    wall, model, setting, cost = min(found, key=lambda f: f[0])
    return model, setting, wall, cost


def grade(sc, cache, max_steps, repeat=3, economy=True, max_seconds=math.inf):
    """One row of results for scene sc (a dict), or None without a reference."""
    r = reference(sc, cache, max_steps, max_seconds)
    if r is None:
        return None
    scene = make_scene(sc)
    w_exact = float(ref.exact_w0(sc["g"], sc["length"]))
    row = dict(
        id=sc["id"],
        want=sc["want"],
        damping=sc["damping"],
        start=sc["start"],
        grid=sc["grid"],
        periods=sc["periods"],
        tol=sc["tol"],
        t_ref=r.get("seconds", math.nan),
    )
    try:
        t0 = time.perf_counter()
        res = pendula.solve(scene)
        t_first = time.perf_counter() - t0
    except Exception as exc:  # noqa: BLE001 -- a crash is a result to report
        row.update(
            model="CRASH",
            reason=f"{type(exc).__name__}: {exc}",
            err=math.inf,
            err_r=math.inf,
            estimate=math.nan,
            tol_met=False,
            t_solve=math.nan,
            cheapest="",
            t_cheapest=math.nan,
        )
        return row
    est = estimate_of(res, sc["want"])
    row.update(
        model=res.model,
        reason=res.reason,
        estimate=est,
        tol_met=res.tol_met,
        err=true_error(sc, res, r["exact"], w_exact),
        err_r=true_error(sc, res, r["rounded"], scene.w0),
    )
    row["t_solve"] = _timed(lambda: pendula.solve(scene), t_first, repeat) if economy else math.nan
    best = cheapest_adequate(sc, scene, r["exact"], w_exact, repeat) if economy else None
    row["cheapest"] = "" if best is None else f"{best[0]}" + ("" if best[1] is None else f"@{best[1]:.3g}")
    row["t_cheapest"] = math.nan if best is None else best[2]
    return row


def describe(sc):
    """The scene's data in one line (the output times as grid kind, count and end)."""
    t = np.atleast_1d(sc["t"])
    return (
        f"Scene(theta0={sc['theta0']!r}, omega0={sc['omega0']!r}, g={sc['g']!r}, length={sc['length']!r}, "
        f"gamma={sc['gamma']!r}, t={sc['grid']}[{t.size}] to {float(t[-1])!r}, tol={sc['tol']:.3g}, "
        f"want={sc['want']!r})"
    )


def reproducer(sc):
    return f"python benchmarks/bench_scenes.py --scene {sc['id']}  # {describe(sc)}"


SCENE_COLUMNS = [
    "id",
    "scene",
    "want",
    "model",
    "reason",
    "tol",
    "estimate",
    "err",
    "err_r",
    "tol_met",
    "t_solve",
    "cheapest",
    "t_cheapest",
    "ratio",
    "t_ref",
]


def scene_rows(rows, by_id):
    """Per-scene CSV rows (SCENE_COLUMNS): every number behind the summary table, floats
    in full (repr) so a claim can be re-checked; err / err_r are the true errors graded
    with the exact and the rounded w0, ratio = t_solve / t_cheapest (times in s)."""
    out = []
    for r in rows:
        d = dict(r, scene=describe(by_id[r["id"]]), ratio=r["t_solve"] / r["t_cheapest"])
        out.append([repr(float(d[c])) if isinstance(d[c], float) else d[c] for c in SCENE_COLUMNS])
    return out


def _pct(x):
    return f"{100 * x:.1f} %"


def summary(rows, skipped, total):
    n = len(rows)
    ok = sum(r["err"] <= r["tol"] for r in rows)
    ok_r = sum(r["err_r"] <= r["tol"] for r in rows)
    honest = sum(r["err"] <= r["estimate"] for r in rows)
    liars = sum(bool(r["tol_met"]) and r["err"] > 10 * r["tol"] for r in rows)
    crashes = sum(r["model"] == "CRASH" for r in rows)
    ratio = np.array(
        [r["t_solve"] / r["t_cheapest"] for r in rows if math.isfinite(r["t_cheapest"]) and math.isfinite(r["t_solve"])]
    )
    none = sum(not math.isfinite(r["t_cheapest"]) for r in rows)
    if ratio.size:
        q = np.percentile(ratio, [50, 90])
        econ = f"{q[0]:.2g}x / {q[1]:.2g}x / {ratio.max():.3g}x ({ratio.size} scenes)"
    else:
        econ = "n/a"
    table = [
        ["true error <= tol (data exactly as given: w0 = sqrt(g/l))", _pct(ok / n), ">= 99.5 %"],
        ["true error <= tol, graded with pendula's rounded w0 = fl(sqrt(g/l))", _pct(ok_r / n), ">= 99.5 %"],
        ["true error <= reported estimate", _pct(honest / n), ">= 99 %"],
        ["scenes claiming tol met while > 10x tol", str(liars), "0"],
        ["wall time / cheapest adequate model: median / p90 / worst", econ, "<= 1.5x / 3x / 10x"],
        [
            "scenes graded / without reference (Taylor budget) / crashes",
            f"{n} / {skipped} / {crashes} (of {total})",
            "",
        ],
        ["scenes where no model run met tol (no economy ratio)", str(none), ""],
    ]
    return ["measure", "now", "target"], table


def rounding_note(rows):
    """Why the rounded-w0 grading differs: near the separatrix solve answers for the data
    as given (issue finding 2), which a reference built on fl(sqrt(g/l)) counts against it."""
    only = [r for r in rows if r["err"] <= r["tol"] < r["err_r"]]
    return (
        f"{len(only)} scene(s) meet tol against the data as given but not against the rounded "
        "w0: near the separatrix the rounding of w0 moves 1 - m by up to ~0.25 %, and solve "
        "answers for the data the user gave (g, length), not for fl(sqrt(g/l))."
    )


def economy_by_model(rows):
    """Wall-time ratio solve / cheapest adequate run_model, by the model solve chose."""
    table = []
    for model in ("small_angle", "exact", "linear", "rk4", "cvode", "taylor"):
        x = np.array(
            [
                r["t_solve"] / r["t_cheapest"]
                for r in rows
                if r["model"] == model and math.isfinite(r["t_cheapest"]) and math.isfinite(r["t_solve"])
            ]
        )
        if x.size:
            q = np.percentile(x, [50, 90])
            table.append([model, str(x.size), f"{q[0]:.2g}x", f"{q[1]:.2g}x", f"{x.max():.3g}x"])
    return ["model chosen", "scenes", "median", "p90", "worst"], table


def main():
    ap = harness.parser(
        __doc__, "24 short scenes (about a minute)", "write scenes-benchmark.md, .csv and -scenes.csv here"
    )
    ap.add_argument(
        "--cache",
        type=pathlib.Path,
        default=harness.ROOT / "out" / "scene-refs",
        help="reference cache directory (never committed)",
    )
    ap.add_argument(
        "--max-steps",
        type=int,
        default=None,
        help="Taylor-step budget of one reference (default 3000 quick, 4000 full)",
    )
    ap.add_argument("--scene", type=int, default=None, help="grade only this scene id, verbosely")
    ap.add_argument("--ids", default=None, metavar="A:B", help="grade only scenes A .. B-1 of the grid (a slice)")
    ap.add_argument(
        "--ref-seconds",
        type=float,
        default=120.0,
        help="wall-time budget [s] of one Taylor reference run (beyond it the scene is left out)",
    )
    ap.add_argument("--no-economy", action="store_true", help="honesty only (no timing, no model ladder)")
    args = ap.parse_args()
    grid = scene_grid_draw.draw()
    max_steps = args.max_steps or (3000 if args.quick else 4000)
    if args.scene is not None:
        grid = [grid[args.scene]]
    elif args.ids is not None:
        a, b = (int(x) if x else None for x in args.ids.split(":"))
        grid = grid[a:b]
    elif args.quick:
        grid = [s for s in grid if s["periods"] <= 20][:24]
    rows, skipped = [], []
    start = time.perf_counter()
    for k, sc in enumerate(grid):
        t0 = time.perf_counter()
        row = grade(sc, args.cache, max_steps, economy=not args.no_economy, max_seconds=args.ref_seconds)
        if row is None:
            skipped.append(sc)
        else:
            row["t_scene"] = time.perf_counter() - t0
            rows.append(row)
            if row["t_scene"] > 10:
                print(
                    f"  scene {sc['id']}: {row['t_scene']:.0f} s (reference {row['t_ref']:.1f} s, solve "
                    f"{row['t_solve']:.2g} s, {row['model']})",
                    file=sys.stderr,
                )
        if args.scene is not None or (k + 1) % 20 == 0:
            print(f"[{k + 1}/{len(grid)} scenes, {time.perf_counter() - start:.0f} s]", file=sys.stderr)
    runtime = time.perf_counter() - start
    if args.scene is not None:
        print(reproducer(grid[0]))
        print(json.dumps(rows[0] if rows else "no reference within the Taylor budget", indent=1, default=str))
        return
    header, table = summary(rows, len(skipped), len(grid))
    by_id = {s["id"]: s for s in grid}
    worst = sorted(rows, key=lambda r: -(r["err"] / r["tol"]))[:10]
    costly = sorted(
        (r for r in rows if math.isfinite(r["t_cheapest"])), key=lambda r: -(r["t_solve"] / r["t_cheapest"])
    )[:5]
    which = "--quick subset" if args.quick else (f"scenes {args.ids}" if args.ids else "full grid")
    t_ref = [r["t_ref"] for r in rows if math.isfinite(r["t_ref"])]
    slow = sorted(rows, key=lambda r: -r["t_scene"])[:5]
    lines = [
        "# Scenes benchmark: honesty and economy",
        "",
        f"{len(grid)} seeded scenes ({which}), "
        f"references without pendula code; generated by benchmarks/bench_scenes.py.",
        "",
        f"Runtime {runtime:.0f} s ({len(grid)} scenes; building their references took (when not "
        f"cached) {sum(t_ref):.0f} s in all, at most {max(t_ref, default=0):.1f} s for one scene; cached ones cost "
        f"nothing here). Slowest scenes (reference build + grading): "
        + ", ".join(f"{r['id']} ({r['t_scene']:.1f} s, reference {r['t_ref']:.1f} s)" for r in slow)
        + ".",
        "",
        harness.markdown_table(header, table, "lrr"),
        "",
        rounding_note(rows),
        "",
        "## Economy by the model solve chose",
        "",
        harness.markdown_table(*economy_by_model(rows), "lrrrr"),
        "",
        "## Worst scenes (true error / tol)",
        "",
    ]
    for r in worst:
        lines.append(
            f"- {r['err'] / r['tol']:.3g}x tol, estimate {r['estimate']:.2g}, model {r['model']}, "
            f"tol_met {r['tol_met']}: `{reproducer(by_id[r['id']])}`"
        )
    lines += ["", "## Costliest scenes (wall time / cheapest adequate)", ""]
    for r in costly:
        lines.append(
            f"- {r['t_solve'] / r['t_cheapest']:.3g}x ({r['model']} {r['t_solve'] * 1e3:.3g} ms vs "
            f"{r['cheapest']} {r['t_cheapest'] * 1e3:.3g} ms): `{reproducer(by_id[r['id']])}`"
        )
    if skipped:
        lines += [
            "",
            f"Without reference (more than {max_steps} Taylor steps or {args.ref_seconds:g} s): scenes "
            + ", ".join(str(s["id"]) for s in skipped),
        ]
    text = "\n".join(lines)
    print(text)
    cols = [
        "id",
        "want",
        "damping",
        "start",
        "grid",
        "periods",
        "tol",
        "model",
        "estimate",
        "tol_met",
        "err",
        "err_r",
        "t_solve",
        "cheapest",
        "t_cheapest",
        "t_ref",
        "t_scene",
    ]
    csv_rows = [[f"{r[c]:.3g}" if isinstance(r[c], float) else r[c] for c in cols] for r in rows]
    harness.write_outputs(args.out, "scenes-benchmark", text, [(header, table), (cols, csv_rows)])
    if args.out is not None:
        with open(pathlib.Path(args.out) / "scenes-benchmark-scenes.csv", "w", newline="") as fh:
            w = csv.writer(fh, lineterminator="\n")
            w.writerow(SCENE_COLUMNS)
            w.writerows(scene_rows(rows, by_id))


if __name__ == "__main__":
    main()
