"""What the example scripts share: the command line (--out DIR, --quick), writing
their CSV table, and the text's section 2.2 scene with its tight reference.

A script in this folder imports it as ``import _example_support`` (Python puts
the script's folder first on sys.path when it runs a script); the leading
underscore keeps run_all.py and the docs gallery from running it as an example.
"""

import argparse
import csv
from pathlib import Path

import pendula


def parse_args(doc, csv_name, argv=None, default_out="."):
    """--out DIR (where csv_name goes; default_out None: no CSV unless given) and
    --quick (accepted so that every example takes the same options)."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    where = f"default: {default_out}" if default_out else "not written without --out"
    ap.add_argument("--out", type=Path, default=default_out, help=f"folder for {csv_name} ({where})")
    ap.add_argument("--quick", action="store_true", help="accepted for symmetry with the other examples")
    return ap.parse_args(argv)


def write_csv(folder, name, header, rows):
    """Write folder/name (folder created if missing): one header row, then rows; print its path."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(rows)
    print(f"\nwrote {path}")


def text_damping():
    """The text's two damping coefficients: (b [kg/s], gamma = b/m [1/s]) for m = 0.1 kg."""
    return [(b, pendula.damping_rate(b, 0.1)) for b in (0.01, 0.05)]


def tight_reference(t, theta0, omega0, w0, gamma, method="adams"):
    """(theta [rad] at t, its name): pendula.cvode at rtol 1e-12 (atol 1e-14) with
    `method`, or pendula.rk4 at h = 1e-4 s in a build without SUNDIALS."""
    if pendula.build_info()["cvode"]:
        r = pendula.cvode(t, theta0, omega0, w0, gamma, rtol=1e-12, atol=1e-14, method=method)
        return r.theta, "CVODE rtol 1e-12"
    return pendula.rk4(t, theta0, omega0, w0, gamma, 1e-4).theta, "RK4 h = 1e-4 s"
