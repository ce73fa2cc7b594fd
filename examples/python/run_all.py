#!/usr/bin/env python3
"""Run every Python example, figure script and benchmark, writing everything into one folder.

    python examples/python/run_all.py --out DIR [--quick]

Layout of DIR:
    figures/      PNG figures (the text's figs 3-15 and the ones it lacks)
    tables/       CSV tables written by the example scripts
    benchmarks/   the benchmarks' tables (each benchmarks/bench_*.py runs with --quick)
    logs/         the console output of every step
    summary.md    the summary table printed at the end
Needs no display: every step runs with MPLBACKEND=Agg.  Exit status 0 when every
step succeeded, 1 otherwise (the other steps still run).
"""

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent

# (script, output sub-folder): the example drivers mirror examples/fortran/.
EXAMPLES = [
    ("period_table.py", "tables"),
    ("exact_motion.py", "tables"),
    ("linear_damping.py", "tables"),
    ("integrators.py", "tables"),
    ("scene_solver.py", "tables"),
    ("figures_text.py", "figures"),
    ("figures_extra.py", "figures"),
]


def _quick_flag(path, wanted):
    """["--quick"] when wanted and the script accepts it (scripts added later may not)."""
    return ["--quick"] if wanted and "--quick" in path.read_text(errors="replace") else []


def _steps(quick, full_benchmarks, skip_benchmarks):
    steps = []
    for script, sub in EXAMPLES:
        path = HERE / script
        if path.exists():
            steps.append((f"examples/python/{script}", path, sub, _quick_flag(path, quick)))
    known = {s for s, _ in EXAMPLES} | {"run_all.py"}
    for path in sorted(HERE.glob("*.py")):  # any example added later, not listed above
        if path.name not in known and not path.name.startswith("_"):
            steps.append((f"examples/python/{path.name}", path, "tables", _quick_flag(path, quick)))
    if not skip_benchmarks:
        for path in sorted((ROOT / "benchmarks").glob("bench_*.py")):
            steps.append((f"benchmarks/{path.name}", path, "benchmarks", _quick_flag(path, not full_benchmarks)))
    return steps


def _files(folder):
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.rglob("*") if p.is_file())


def _run(label, path, out_dir, extra, log_dir, timeout):
    out_dir.mkdir(parents=True, exist_ok=True)
    before = {p: p.stat().st_mtime_ns for p in _files(out_dir)}
    cmd = [sys.executable, str(path), "--out", str(out_dir)] + extra
    env = dict(os.environ, MPLBACKEND="Agg")
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, cwd=str(out_dir), env=env, capture_output=True, text=True, timeout=timeout)
        code, stdout, stderr = proc.returncode, proc.stdout, proc.stderr
    except subprocess.TimeoutExpired as exc:
        code = "timeout"
        stdout = exc.stdout.decode() if isinstance(exc.stdout, bytes) else (exc.stdout or "")
        stderr = f"timed out after {timeout} s"
    seconds = time.perf_counter() - t0
    log = log_dir / (Path(label).stem + ".txt")
    log.write_text(f"$ {' '.join(cmd)}\n\n{stdout}\n--- stderr ---\n{stderr}")
    new = [p for p in _files(out_dir) if before.get(p) != p.stat().st_mtime_ns]
    notes = [ln.strip() for ln in stdout.splitlines() if ln.strip().startswith(("not drawn:", "not run:"))]
    if code != 0:
        tail = (stderr.strip().splitlines() or ["(no message)"])[-1]
        notes.append(f"FAILED ({code}): {tail}")
    return {"label": label, "ok": code == 0, "seconds": seconds, "new": new, "notes": notes, "log": log}


def _integrator_highlights(rows):
    by = {(r["scenario"], r["b_kg_per_s"], r["method"]): r for r in rows}
    for b in ("0.01", "0.05"):
        lst = float(by[("text scene", b, "text listing as printed h=0.05")]["max_theta_error_rad"])
        rk4 = float(by[("text scene", b, "rk4 h=0.05")]["max_theta_error_rad"])
        yield (
            f"| text §2.2 scene, b = {b} kg/s: max abs θ error, t = 0, 1, ..., 30 s | "
            f"printed listing {lst:.3g} rad | pendula.rk4 (same h = 0.05 s) {rk4:.2g} rad |"
        )


def _scene_highlights(rows):
    for r in rows:
        yield (
            f"| scene: {r['scene']} (tol {float(r['tol_rad']):g} rad) | model {r['model']} | "
            f"estimate {float(r['error_estimate_rad']):.2g}, true {float(r['true_error_rad']):.2g} rad |"
        )


def _period_highlights(rows):
    for r in rows:
        if r["theta0_deg"] in ("90", "179"):
            t, t0 = float(r["T_exact_s"]), float(r["T0_small_angle_s"])
            yield (
                f"| period at θ0 = {r['theta0_deg']}° | exact {t:.6f} s | "
                f"small-angle {t0:.6f} s ({(t0 - t) / t:+.1%}) |"
            )


def _highlights(out):
    """A few headline numbers read back from the tables (lines for the summary; empty if absent)."""
    import csv

    lines = []
    for table, highlights in (
        ("integrators_comparison.csv", _integrator_highlights),
        ("scene_solver.csv", _scene_highlights),
        ("period_table.csv", _period_highlights),
    ):
        try:  # a missing or malformed table gives fewer lines, never a failure
            with open(out / "tables" / table, newline="") as fh:
                lines.extend(highlights(list(csv.DictReader(fh))))
        except (OSError, KeyError, ValueError):
            pass
    if lines:
        lines = ["| highlight | value | compared with |", "|---|---|---|"] + lines
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True, help="output folder (created if missing)")
    ap.add_argument("--quick", action="store_true", help="quick mode for the examples (fewer points, fewer settings)")
    ap.add_argument(
        "--full-benchmarks", action="store_true", help="run the benchmarks without --quick (minutes instead of seconds)"
    )
    ap.add_argument("--skip-benchmarks", action="store_true", help="do not run benchmarks/bench_*.py")
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds allowed per step (default 900)")
    args = ap.parse_args(argv)

    out = Path(args.out).resolve()
    log_dir = out / "logs"
    log_dir.mkdir(parents=True, exist_ok=True)
    steps = _steps(args.quick, args.full_benchmarks, args.skip_benchmarks)
    print(f"pendula main job: {len(steps)} step(s), writing into {out}", flush=True)
    results = []
    for label, path, sub, extra in steps:
        print(f"  running {label} ...", end="", flush=True)
        res = _run(label, path, out / sub, extra, log_dir, args.timeout)
        results.append(res)
        print(f" {'ok' if res['ok'] else 'FAILED'} ({res['seconds']:.1f} s, {len(res['new'])} file(s))", flush=True)

    lines = ["| step | status | time (s) | files written | notes |", "|---|---|---:|---:|---|"]
    for r in results:
        notes = "; ".join(r["notes"]).replace("|", "/")
        lines.append(
            f"| {r['label']} | {'ok' if r['ok'] else 'FAILED'} | {r['seconds']:.1f} | {len(r['new'])} | {notes} |"
        )
    table = "\n".join(lines)
    listing = []
    for folder in ("figures", "tables", "benchmarks", "fortran"):
        files = _files(out / folder)
        if files:
            listing.append(f"\n{folder}/ ({len(files)} file(s)):")
            listing += [f"  {p.relative_to(out)}  ({p.stat().st_size} bytes)" for p in files]
    highlights = "\n".join(_highlights(out))
    summary = (
        f"# pendula main job\n\nOutput folder: {out}\n\n{table}\n\n"
        + (f"{highlights}\n\n" if highlights else "")
        + f"Logs of every step: {log_dir}\n"
        + "\n".join(listing)
        + "\n"
    )
    (out / "summary.md").write_text(summary)

    print(f"\nEverything is in {out}")
    print(f"  figures:    {out / 'figures'}")
    print(f"  tables:     {out / 'tables'}")
    if not args.skip_benchmarks:
        print(f"  benchmarks: {out / 'benchmarks'}")
    print(f"  logs:       {log_dir}")
    print(f"  summary:    {out / 'summary.md'}\n")
    print(table)
    if highlights:
        print("\n" + highlights)
    print("\n".join(listing))
    failed = [r["label"] for r in results if not r["ok"]]
    if failed:
        print(f"\n{len(failed)} step(s) failed: {', '.join(failed)} (see {log_dir})")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
