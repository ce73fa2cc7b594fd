"""What every benchmarks/bench_*.py shares: the command line (--quick, --out,
and --n/--repeat sizes), best-of-N timing (wall or CPU, optionally filling a
time budget; or wall and CPU together), interleaved timing of two contenders,
Markdown tables and the CSV/Markdown files written with --out, and loading the
mpmath reference generators of tools/gen without editing sys.path.

A script in this folder imports it as ``import harness`` (Python puts the
script's folder first on sys.path when it runs a script).
"""

import argparse
import csv
import importlib.util
import pathlib
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]


def parser(doc, quick_help, out_help):
    """An ArgumentParser with the options every benchmark takes: --quick and --out DIR."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help=quick_help)
    ap.add_argument("--out", type=pathlib.Path, default=None, help=out_help)
    return ap


def parse_with_sizes(ap, argv, n_help, n=(100_000, 1_000_000), repeat=(3, 7)):
    """Add --n (points or states: n_help) and --repeat to ap and parse argv.
    Returns (args, n, repeat), each size the given one or its (quick, full) default."""
    ap.add_argument("--n", type=int, default=None, help=n_help)
    ap.add_argument(
        "--repeat", type=int, default=None, help=f"best of this many runs (default {repeat[1]}; --quick {repeat[0]})"
    )
    args = ap.parse_args(argv)
    pick = 0 if args.quick else 1
    return args, args.n or n[pick], args.repeat or repeat[pick]


def best_time(fn, repeat, clock=time.perf_counter, warm_up=True, budget=0.0, max_repeat=200):
    """Best of the timed calls of fn() in s (after one untimed call when warm_up):
    `repeat` calls, more while their total is below `budget` s (at most max_repeat)."""
    if warm_up:
        fn()
    best, spent, runs = np.inf, 0.0, 0
    while runs < repeat or (spent < budget and runs < max_repeat):
        t0 = clock()
        fn()
        dt = clock() - t0
        best, spent, runs = min(best, dt), spent + dt, runs + 1
    return best


def best_run(fn, repeat):
    """Run fn() `repeat` times (no warm-up) and return (best wall time s, best
    process CPU time s, CPU/wall of the fastest run, the last result).  CPU/wall
    above 1 means threads computed at once; CPU time is the per-core cost when
    other processes share the machine."""
    best_wall = best_cpu = np.inf
    cpu_per_wall, out = 0.0, None
    for _ in range(repeat):
        c0, t0 = time.process_time(), time.perf_counter()
        out = fn()
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        if wall < best_wall:
            best_wall, cpu_per_wall = wall, cpu / wall
        best_cpu = min(best_cpu, cpu)
    return best_wall, best_cpu, cpu_per_wall, out


def best_times_interleaved(fns, repeat, clock=time.perf_counter, warm_up=True):
    """Best-of-repeat for each of fns, alternating them so that load from other
    processes hits all alike; a list of times in s."""
    if warm_up:
        for fn in fns:
            fn()
    best = [np.inf] * len(fns)
    for _ in range(repeat):
        for i, fn in enumerate(fns):
            best[i] = min(best[i], best_time(fn, 1, clock, warm_up=False))
    return best


def markdown_table(header, rows, align=None):
    """Rows of already formatted cells as a Markdown table; align: one of
    'l'/'r' per column (default: first left, the others right)."""
    align = align or "l" + "r" * (len(header) - 1)
    rule = ["---" if a == "l" else "---:" for a in align]
    return "\n".join("| " + " | ".join(map(str, r)) + " |" for r in [header, rule, *rows])


def write_outputs(out, stem, markdown, tables=()):
    """With --out: write stem.md (the printed text) and, when tables are given,
    stem.csv (each table a header row and rows, tables separated by a blank line)."""
    if out is None:
        return
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{stem}.md").write_text(markdown + "\n")
    if tables:
        with open(out / f"{stem}.csv", "w", newline="") as fh:
            w = csv.writer(fh, lineterminator="\n")
            for i, (header, rows) in enumerate(tables):
                if i:
                    fh.write("\n")
                w.writerow(header)
                w.writerows(rows)


def _load_file(name, folder):
    """<folder>/<name>.py as a module, loaded from its file: no sys.path edit."""
    spec = importlib.util.spec_from_file_location(name, folder / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_generator(name):
    """tools/gen/<name>.py as a module (the mpmath references the tests use too)."""
    return _load_file(name, ROOT / "tools" / "gen")


def load_test_module(name):
    """tests/python/<name>.py as a module (the mpmath references and error measures the tests use)."""
    return _load_file(name, ROOT / "tests" / "python")
