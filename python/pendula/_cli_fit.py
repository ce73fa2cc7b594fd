"""``pendula fit DATA.csv``: fit a measured pendulum from the command line.

The CSV's header says what it holds: ``theta0,period`` (optionally
``sigma_period``, ``sigma_theta0``) is a table of periods (fit_period);
``t,theta`` (optionally ``omega``, ``sigma``, ``sigma_omega``) is a recorded
swing (fit_motion).  Angles in rad, or in degrees when the column name ends
in ``_deg`` (``theta0_deg``, ``sigma_theta0_deg``, ``theta_deg``, ``sigma_deg``).
Prints the fit's table and writes its figure as a PNG.
"""

import csv
import math
from pathlib import Path

import numpy as np

PERIOD_COLUMNS = ("theta0", "period", "sigma_period", "sigma_theta0")
MOTION_COLUMNS = ("t", "theta", "omega", "sigma", "sigma_omega")
_ANGLES = {"theta0", "sigma_theta0", "theta", "sigma"}


def add_parser(sub, positive):
    """Add the ``fit`` subcommand to the subparsers ``sub``."""
    f = sub.add_parser(
        "fit",
        help="fit g, length, damping and the initial state to measured data (CSV)",
        description="Fit a measured pendulum. A CSV with columns theta0,period[,sigma_period,"
        "sigma_theta0] is a table of periods at several amplitudes; one with "
        "t,theta[,omega,sigma,sigma_omega] is a recorded swing. Angles in rad, or in "
        "degrees with a _deg column suffix (theta0_deg). Prints the estimates with "
        "standard errors and writes the figure (PNG). Needs SciPy (and matplotlib "
        "for the PNG).",
    )
    f.add_argument("data", metavar="CSV", help="the measurements (see above)")
    one = f.add_mutually_exclusive_group()
    one.add_argument(
        "--length",
        "-l",
        type=positive,
        default=None,
        metavar="M",
        help="pendulum length in m (pivot to the bob's centre): estimate g",
    )
    one.add_argument("--g", type=positive, default=None, metavar="M/S2", help="g in m/s^2: estimate the length")
    f.add_argument(
        "--bob-radius",
        type=positive,
        default=None,
        metavar="M",
        help="periods: radius of a solid spherical bob (finite-bob correction, needs --length or --g)",
    )
    f.add_argument(
        "--damping",
        choices=("linear", "none"),
        default="linear",
        help="swing: linear viscous damping (default) or none",
    )
    f.add_argument("--fit-offsets", action="store_true", help="swing: also fit the sensor's angle offset")
    f.add_argument(
        "--loss",
        choices=("linear", "soft_l1", "huber", "cauchy", "arctan"),
        default="linear",
        help="swing: robust loss against outliers (default linear: plain least squares)",
    )
    f.add_argument(
        "--png", default=None, metavar="PATH", help="the figure's file (default: the CSV's name with _fit.png)"
    )
    f.add_argument("--no-png", action="store_true", help="skip the figure (no matplotlib needed)")
    return f


def read_columns(path):
    """{column: float array} of a CSV with a header row; angles converted to rad."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"no such file: {path}")
    with path.open(newline="") as fh:
        rows = [r for r in csv.reader(fh) if r and not r[0].lstrip().startswith("#")]
    if len(rows) < 2:
        raise ValueError(f"{path}: needs a header row and at least one data row")
    header = [h.strip() for h in rows[0]]
    cols = {}
    for j, name in enumerate(header):
        try:
            vals = np.array([float(r[j]) for r in rows[1:]])
        except (ValueError, IndexError):
            raise ValueError(f"{path}: column {name!r} has a value that is not a number (or a short row)") from None
        if name.endswith("_deg") and name[:-4] in _ANGLES:
            name, vals = name[:-4], np.radians(vals)
        cols[name] = vals
    return cols


def cmd_fit(args, out):
    """Run ``pendula fit``; returns the exit code."""
    import pendula

    cols = read_columns(args.data)
    if {"theta0", "period"} <= set(cols):
        unknown = set(cols) - set(PERIOD_COLUMNS)
        if unknown:
            raise ValueError(
                f"{args.data}: unknown period-table columns {sorted(unknown)} (known: {', '.join(PERIOD_COLUMNS)})"
            )
        r = pendula.fit_period(
            cols["theta0"],
            cols["period"],
            sigma_period=cols.get("sigma_period"),
            sigma_theta0=cols.get("sigma_theta0"),
            length=args.length,
            g=args.g,
            bob_radius=args.bob_radius,
        )
    elif {"t", "theta"} <= set(cols):
        unknown = set(cols) - set(MOTION_COLUMNS)
        if unknown:
            raise ValueError(
                f"{args.data}: unknown swing columns {sorted(unknown)} (known: {', '.join(MOTION_COLUMNS)})"
            )
        if args.bob_radius is not None:
            raise ValueError("--bob-radius applies to period tables only")
        r = pendula.fit_motion(
            cols["t"],
            cols["theta"],
            omega=cols.get("omega"),
            sigma=cols.get("sigma"),
            sigma_omega=cols.get("sigma_omega"),
            damping=None if args.damping == "none" else "linear",
            fit_offsets=args.fit_offsets,
            loss=args.loss,
            length=args.length,
            g=args.g,
        )
    else:
        raise ValueError(
            f"{args.data}: the header must name theta0,period (a table of periods) or t,theta "
            f"(a recorded swing); it names {', '.join(cols)}"
        )
    out.write(f"{r!r}\n")
    if r.small_angle and "g_per_point" in r.small_angle:
        worst = int(np.argmax(np.abs(cols["theta0"])))
        out.write(
            f"  at {math.degrees(abs(cols['theta0'][worst])):.4g} deg the small-angle formula alone "
            f"gives g = {r.small_angle['g_per_point'][worst]:.4g} m/s^2\n"
        )
    if not args.no_png:
        png = Path(args.png) if args.png else Path(args.data).with_name(Path(args.data).stem + "_fit.png")
        r.plot(png)
        out.write(f"wrote {png}\n")
    return 0
