"""What every benchmarks/bench_*.py shares: the command line (--quick, --out),
best-of-N timing, interleaved timing of two contenders, Markdown tables and
the CSV/Markdown files written with --out, and loading the mpmath reference
generators of tools/gen without editing sys.path.

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


def best_time(fn, repeat, clock=time.perf_counter, warm_up=True):
    """Best of `repeat` timed calls of fn() in s (after one untimed call when warm_up)."""
    if warm_up:
        fn()
    best = np.inf
    for _ in range(repeat):
        t0 = clock()
        fn()
        best = min(best, clock() - t0)
    return best


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


def load_generator(name):
    """tools/gen/<name>.py as a module (the mpmath references the tests use too),
    loaded from its file: no sys.path edit."""
    spec = importlib.util.spec_from_file_location(name, ROOT / "tools" / "gen" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
