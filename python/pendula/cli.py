"""Command line of pendula: ``python -m pendula`` or the ``pendula`` console script.

Subcommands (``pendula SUBCOMMAND --help`` for each):

  figures   draw every figure of the text (and the ones it lacks) into a folder
  period    exact period (or time per revolution) against small-angle and series
  solve     solve a scene (the library picks the cheapest model meeting --tol)
  tradeoff  speed/accuracy table of every model on a scene (CSV, work-precision PNG)
  sweep     a theta0 x Omega0 grid integrated to t-end: NPZ, CSV and the basin map (PNG)
  fit       fit g, length, damping and the initial state to measured data (CSV): table and PNG
  poincare, bifurcation, lyapunov, basins   the driven pendulum's chaos tools (NPZ, CSV, PNG)

Units: angles rad, angular velocities rad/s, times s, g m/s^2, length m,
mass kg, b kg/s, gamma and w0 1/s; angles may be given in degrees (--theta0 90deg,
--omega0 30deg/s) and the initial state by the text's launch speed (--v0 in m/s,
Omega0 = v0/l).  Exit status 0 on success, 2 on a bad flag or value (with a
message saying what is wrong), 1 when a solver fails, memory runs out or an
output cannot be written, 130 on Ctrl-C; every error is one line on stderr.

Output: every number written, in CSV and NPZ files and in printed tables, is the
shortest decimal that reads back as the same double (Python's repr), except the
times of the output grid in a table printed for people, shown without binary
noise (0.45, not 0.44999999999999996).  An output path ending in / (or naming an
existing folder) writes a file of the command's name inside that folder.
"""

import argparse
import csv
import math
import os
import sys
from pathlib import Path

import numpy as np

from . import _cli_driven, _cli_fit
from ._cli_values import accept_negative_values, angle, angular_velocity, data, grid_times, threads
from ._cli_values import count as _count
from ._cli_values import finite as _finite
from ._cli_values import nonnegative as _nonnegative
from ._cli_values import positive as _positive
from ._codes import EVENT_TURNING, EVENT_ZERO, G_DEFAULT, LENGTH_DEFAULT, MODEL_CODES, WANT_CODES
from ._defaults import SWEEP_H, TOL

PROG = "pendula"
MODELS = tuple(name for name in MODEL_CODES if name != "auto")
WANTS = tuple(WANT_CODES)


class CliError(Exception):
    """A bad value the parser could not see (e.g. inconsistent flags)."""


# ---------------------------------------------------------------- parser

_PHYS_HELP = (
    f"physical parameters (the text's defaults: g = {G_DEFAULT:g} m/s^2, l = {LENGTH_DEFAULT:g} m, so w0 = sqrt(2) 1/s)"
)


def _add_physics(p, damping=True, w0=False):
    g = p.add_argument_group(_PHYS_HELP)
    # g and length default to None here and to the text's values in main, so that
    # --w0 can refuse them when they are given too
    g.add_argument(
        "--g",
        type=_positive,
        default=None,
        metavar="M/S2",
        help=f"gravitational acceleration g in m/s^2 (default {G_DEFAULT:g})",
    )
    g.add_argument(
        "--length",
        "-l",
        type=_positive,
        default=None,
        metavar="M",
        help=f"pendulum length l in m (default {LENGTH_DEFAULT:g}); w0 = sqrt(g/l) in 1/s",
    )
    if w0:
        g.add_argument(
            "--w0",
            type=_positive,
            default=None,
            metavar="1/S",
            help="natural frequency w0 in 1/s, instead of --g and --length (default sqrt(g/l) = sqrt(2))",
        )
    if damping:
        g.add_argument(
            "--gamma",
            type=_nonnegative,
            default=None,
            metavar="1/S",
            help="damping rate gamma in 1/s (eq. 2.3); or give --mass and --b (all three only when gamma = b/m)",
        )
        g.add_argument(
            "--mass",
            "-m",
            type=_positive,
            default=None,
            metavar="KG",
            help="bob mass m in kg (with --b: gamma = b/m, eq. 2.2)",
        )
        g.add_argument(
            "--b", type=_nonnegative, default=None, metavar="KG/S", help="damping constant b in kg/s (with --mass)"
        )


_ANGLE_HELP = "in rad, or in degrees with the unit: 90deg"
_RATE_HELP = "in rad/s, or in degrees per second with the unit: 30deg/s"


def _add_launch(group, what="initial angular velocity Omega0"):
    """--omega0 and its alternative --v0 (the bob's launch speed of the text's §1.3)."""
    one = group.add_mutually_exclusive_group()
    one.add_argument(
        "--omega0", type=angular_velocity, default=0.0, metavar="RAD/S", help=f"{what} {_RATE_HELP} (default 0)"
    )
    one.add_argument(
        "--v0",
        type=_finite,
        default=None,
        metavar="M/S",
        help="instead of --omega0: the bob's launch speed v0 in m/s (text §1.3), "
        "Omega0 = v0/l; signed, > 0 towards increasing theta",
    )


def _add_scene(p):
    s = p.add_argument_group("initial state and window")
    s.add_argument(
        "--theta0",
        type=angle,
        required=True,
        metavar="ANGLE",
        help=f"initial angle theta0 {_ANGLE_HELP} (any real; 0 = hanging down)",
    )
    _add_launch(s)
    s.add_argument(
        "--t-end",
        type=_positive,
        required=True,
        metavar="S",
        help="end of the time window in s (the window starts at t = 0)",
    )
    s.add_argument(
        "--n",
        type=_count,
        default=201,
        metavar="N",
        help="number of equally spaced output times in [0, t-end] (default 201)",
    )
    s.add_argument(
        "--tol",
        type=_positive,
        default=TOL,
        metavar="RAD",
        help=f"absolute tolerance on theta in rad over the whole window (Omega scaled by w0); default {TOL:g}",
    )
    _add_physics(p)


def build_parser():
    """The argparse parser of the command line (exposed for tests and docs)."""
    p = argparse.ArgumentParser(
        prog=PROG,
        description="The simple pendulum, exact where mathematics allows. "
        "Units: angles rad (or degrees with the unit: 90deg), angular velocities rad/s "
        "(or 30deg/s), times s, g m/s^2, "
        "length m, mass kg, b kg/s, gamma and w0 1/s.",
        epilog="Run `pendula SUBCOMMAND --help` for the flags of each subcommand.",
    )
    p.add_argument("--version", action="store_true", help="print the version and build information")
    sub = p.add_subparsers(dest="command", metavar="SUBCOMMAND")

    f = sub.add_parser(
        "figures",
        help="draw every figure of the text (and those it lacks) into a folder",
        description="Draw the text's figures 3-15 from the library (correct where the "
        "text's listings were wrong) and the figures it lacks (underdamped "
        "case, phase portrait, period vs energy, work-precision), as PNG "
        "files into --out. Needs matplotlib; needs no display.",
    )
    f.add_argument(
        "--out",
        metavar="DIR",
        help="output folder (created if missing, but its parent must exist unless --mkdir); required unless --list",
    )
    f.add_argument("--quick", action="store_true", help="fewer points per curve (fast, for tests)")
    f.add_argument(
        "--only",
        default=None,
        metavar="KEYS",
        help="comma-separated figure keys to draw, e.g. fig03,fig14 (default: all)",
    )
    f.add_argument("--list", action="store_true", help="list the figure keys and exit")
    f.add_argument("--mkdir", action="store_true", help="also create the missing parent folders of --out")

    q = sub.add_parser(
        "period",
        help="exact period or revolution time vs small-angle and series",
        description="Exact period T = 4K(m)/w0 of the libration (eq. 1.53, any Omega0) or "
        "the time per revolution 2K(1/m)/(sqrt(m) w0) of a rotation, against "
        "the small-angle period T0 = 2 pi/w0 (eq. 1.8) and the series "
        "T0 (1 + m/4 + 9 m^2/64), where m = sin^2(theta0/2) + (Omega0/2w0)^2 "
        "is the energy over the separatrix energy. Times in s.",
    )
    q.add_argument(
        "--theta0",
        type=angle,
        nargs="+",
        required=True,
        metavar="ANGLE",
        help=f"one or more initial angles {_ANGLE_HELP}",
    )
    _add_launch(q, "initial angular velocity")
    q.add_argument(
        "--csv",
        default=None,
        metavar="FILE",
        help="also write the table as CSV (FILE ending in / or an existing folder: period.csv in it)",
    )
    q.add_argument("--mkdir", action="store_true", help="create the missing folders of --csv")
    _add_physics(q, damping=False, w0=True)

    s = sub.add_parser(
        "solve",
        help="solve a scene with the cheapest model that meets --tol",
        description="Describe a scene (parameters, initial state, window, tolerance); the "
        "library picks the cheapest model whose error estimate fits the "
        "tolerance (small-angle, exact elliptic, linear damped closed form, "
        "RK4, CVODE), says which and why, and returns theta (rad) and "
        "Omega (rad/s) at the output times (s).",
    )
    _add_scene(s)
    s.add_argument("--model", default=None, choices=MODELS, help="force a model instead of letting the library choose")
    s.add_argument(
        "--want",
        default="state",
        choices=WANTS,
        help="what to compute: state (theta [rad] and Omega [rad/s] at the output times, "
        "default), theta, final (the state at t-end only, no history), energy "
        "(per unit m l^2, 1/s^2), period (period or time per revolution [s], "
        "undamped only), events (turning points and zero crossings [s])",
    )
    s.add_argument(
        "--csv",
        default=None,
        metavar="FILE",
        help="write t [s], theta [rad], omega [rad/s] as CSV, a data file: every number to full "
        "precision, the times as computed (default: print a summary table, its times "
        "rounded to the grid's resolution: 0.45, not 0.44999999999999996)",
    )
    s.add_argument(
        "--png",
        default=None,
        metavar="FILE",
        help="also draw theta(t), Omega(t) and the phase plane as PNG (pendula.plot_motion; "
        "theta(t) alone for --want theta); needs matplotlib",
    )
    s.add_argument("--mkdir", action="store_true", help="create the missing folders of --csv and --png")

    t = sub.add_parser(
        "tradeoff",
        help="speed/accuracy table of every applicable model on a scene",
        description="Run every applicable model over a range of settings (RK4 steps, "
        "CVODE tolerances, closed forms) on a scene, against a reference, "
        "and print model, setting, sup error of the state over the output "
        "grid (rad), wall time (s) and right-hand-side evaluations.",
    )
    _add_scene(t)
    t.add_argument("--csv", default=None, metavar="FILE", help="also write the table as CSV")
    t.add_argument("--png", default=None, metavar="FILE", help="also draw the work-precision diagram (PNG)")
    t.add_argument("--mkdir", action="store_true", help="create the missing folders of --csv and --png")
    t.add_argument(
        "--models",
        default=None,
        metavar="NAMES",
        help="comma-separated subset of " + ", ".join(MODELS) + " (default: every applicable one)",
    )
    t.add_argument(
        "--repeat", type=_count, default=3, metavar="N", help="wall time is the best of N >= 2 calls (default 3)"
    )
    w = sub.add_parser(
        "sweep",
        help="a theta0 x Omega0 grid integrated to t-end: NPZ, CSV and basin map",
        description="Integrate every start of a theta0 x Omega0 grid (or of one axis: give "
        "the other a single value) with pendula.sweep (RK4 or CVODE batch "
        "kernels, in chunks; Ctrl-C stops it) to --t-end and write into --out: "
        "sweep.npz (theta0 [rad], omega0 [rad/s], final theta [rad], final "
        "Omega [rad/s], well, status codes), sweep.csv (one row per start) and "
        "basin.png: the basin map, each start coloured by the well 2 pi k it "
        "ends in (the turns made before the damping caught it).",
    )
    w.add_argument(
        "--theta0",
        nargs="+",
        default=[-math.pi, math.pi, 101],
        metavar="LO HI N",
        help=f"theta0 grid: LO HI {_ANGLE_HELP} (-180deg 180deg 101), N points "
        "(default -pi pi 101); or one value: a 1-D sweep over Omega0 only",
    )
    w.add_argument(
        "--omega0",
        nargs="+",
        default=[-6.0, 6.0, 101],
        metavar="LO HI N",
        help=f"Omega0 grid: LO HI {_RATE_HELP}, N points (default -6 6 101); or one "
        "value: a 1-D sweep over theta0 only",
    )
    w.add_argument("--t-end", type=_positive, default=30.0, metavar="S", help="end time in s (default 30)")
    w.add_argument(
        "--method",
        default="rk4",
        choices=("rk4", "cvode"),
        help="integrator: rk4 (fixed step --h, default) or cvode (tolerances --rtol, --atol)",
    )
    w.add_argument("--h", type=_positive, default=SWEEP_H, metavar="S", help=f"RK4 step in s (default {SWEEP_H:g})")
    w.add_argument(
        "--rtol",
        type=_positive,
        default=None,
        metavar="REL",
        help="CVODE relative tolerance, > 0 (default: pendula.sweep's)",
    )
    w.add_argument(
        "--atol",
        type=_nonnegative,
        default=None,
        metavar="ABS",
        help="CVODE absolute tolerance, >= 0 (default: pendula.sweep's)",
    )
    w.add_argument(
        "--cvode-method",
        default=None,
        choices=("adams", "bdf"),
        help="CVODE's method: adams (non-stiff) or bdf (stiff, gamma >> w0); default pendula.sweep's",
    )
    w.add_argument(
        "--threads",
        type=threads,
        default=None,
        metavar="N",
        help="threads of the batch kernels (0: every core; default: chosen from the predicted work)",
    )
    w.add_argument(
        "--out",
        required=True,
        metavar="DIR",
        help="output folder (created if missing, but its parent must exist unless --mkdir)",
    )
    w.add_argument("--mkdir", action="store_true", help="also create the missing parent folders of --out")
    w.add_argument("--no-png", action="store_true", help="skip the figure (no matplotlib needed)")
    _add_physics(w, w0=True)
    _cli_fit.add_parser(sub, _positive)
    _cli_driven.add_parsers(sub, _add_physics)  # poincare, bifurcation, lyapunov, basins
    for parser in (p, *sub.choices.values()):
        accept_negative_values(parser)
    return p


# ---------------------------------------------------------------- helpers


def _physics_defaults(args):
    """--w0 instead of --g/--length (refused together); then the text's g and l
    (not for ``fit``, where the one given says which is estimated)."""
    if args.command == "fit":
        return
    if not hasattr(args, "g"):  # a command without the physical flags
        return
    if getattr(args, "w0", None) is not None and (args.g is not None or args.length is not None):
        raise CliError("--w0 replaces --g and --length (w0 = sqrt(g/l)): give either --w0 or --g/--length")
    args.g = G_DEFAULT if args.g is None else args.g
    args.length = LENGTH_DEFAULT if args.length is None else args.length


def _w0(args):
    """The natural frequency of the flags: --w0, or sqrt(g/l)."""
    import pendula

    w0 = getattr(args, "w0", None)
    return float(w0) if w0 is not None else float(pendula.natural_frequency(args.g, args.length))


def _scene(args, want="state"):
    """The scene of the flags; --gamma, --mass and --b go through to the library,
    which checks them (mass and b together; gamma too only when it equals b/mass)."""
    import pendula

    scene_cls = getattr(pendula, "Scene", None)
    if scene_cls is None:
        raise NotImplementedError("pendula.Scene (the scenes module) is not available in this build")
    t = np.linspace(0.0, args.t_end, args.n)
    return scene_cls(
        theta0=args.theta0,
        omega0=args.omega0,
        t=t,
        g=args.g,
        length=args.length,
        gamma=args.gamma,
        mass=args.mass,
        b=args.b,
        tol=args.tol,
        want=want,
    )


def _fmt_table(header, rows):
    cols = [[str(h)] + [str(r[i]) for r in rows] for i, h in enumerate(header)]
    widths = [max(len(c) for c in col) for col in cols]
    lines = ["  ".join(h.rjust(w) for h, w in zip(header, widths)), "  ".join("-" * w for w in widths)]
    lines += ["  ".join(str(v).rjust(w) for v, w in zip(r, widths)) for r in rows]
    return "\n".join(lines)


def _output_file(path, option, args, name):
    """The file an output flag names: a path ending in a separator, or naming an
    existing folder, means the file `name` inside that folder (never a file
    named like the folder); checked by _check_output."""
    text = str(path)
    if text.endswith(("/", os.sep)) or Path(text).is_dir():
        path = Path(text) / name
    _check_output(path, option, args)
    return str(path)


def _check_output(path, option, args, folder=False):
    """Refuse an output path whose directory does not exist, before any work,
    unless --mkdir asks to create it; a folder option (--out) may itself be
    missing, it is created, but not its parents.  Never creates anything."""
    path = Path(path)
    if folder and path.exists() and not path.is_dir():
        raise CliError(f"{option} {path}: exists and is not a directory")
    if not folder and path.is_dir():
        raise CliError(f"{option} {path}: is a directory, give a file name")
    parent = path.parent
    if not parent.is_dir() and not getattr(args, "mkdir", False):
        raise CliError(
            f"{option} {path}: directory {parent} does not exist (create it, or give --mkdir to let {PROG} create it)"
        )


def _need_matplotlib(what):
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        from .motion_plots import EXTRA

        raise CliError(f"{what} needs matplotlib: pip install 'pendula[{EXTRA}]' (or pip install matplotlib)") from None


def _make_parent(path, args):
    if getattr(args, "mkdir", False):
        Path(path).parent.mkdir(parents=True, exist_ok=True)


def _write_csv(path, header, rows):
    path = Path(path)
    try:
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(header)
            w.writerows(rows)
    except OSError as exc:  # e.g. a full disk reported when the file is closed: name the file
        raise OSError(exc.errno, exc.strerror, str(path)) from None
    return path


def _get(obj, *names, default=None):
    for n in names:
        if isinstance(obj, dict) and n in obj:
            return obj[n]
        if hasattr(obj, n):
            return getattr(obj, n)
    return default


# ---------------------------------------------------------------- commands


def cmd_figures(args, out):
    from . import figures

    keys = [k for k, _ in figures.FIGURES]
    if args.list:
        for k, fn in figures.FIGURES:
            out.write(f"{k}  {(fn.__doc__ or '').strip().splitlines()[0]}\n")
        return 0
    if not args.out:
        raise CliError("--out DIR is required (the folder to write the PNG files into)")
    only = None
    if args.only:
        only = [k.strip() for k in args.only.split(",") if k.strip()]
        bad = [k for k in only if k not in keys]
        if bad:
            raise CliError(f"--only: unknown figure key(s) {', '.join(bad)}; known: {', '.join(keys)}")
    _check_output(args.out, "--out", args, folder=True)
    _need_matplotlib("drawing the figures")
    _make_parent(Path(args.out) / "x", args)
    written, missing = figures.make_figures(args.out, quick=args.quick, only=only)
    out.write(f"wrote {len(written)} figure(s) to {Path(args.out).resolve()}\n")
    for p in written:
        out.write(f"  {Path(p).name}\n")
    for k, why in missing.items():
        out.write(f"  not drawn: {k}: {why}\n")
    failed = [k for k, why in missing.items() if why.startswith("FAILED")]
    if failed:
        sys.stderr.write(f"{PROG} figures: {len(failed)} figure(s) failed: {', '.join(failed)}\n")
        return 1
    return 0


def cmd_period(args, out):
    import pendula

    if args.csv:
        args.csv = _output_file(args.csv, "--csv", args, "period.csv")
    w0 = _w0(args)
    t0 = float(pendula.small_angle_period(w0))
    theta0 = np.asarray(args.theta0, dtype=float)
    exact = np.atleast_1d(np.asarray(pendula.period(theta0, args.omega0, w0), dtype=float))
    header = [
        "theta0_rad",
        "omega0_rad_per_s",
        "E_over_Esep",
        "1_minus_E_over_Esep",
        "motion",
        "T_exact_s",
        "T0_small_angle_s",
        "T_series_s",
        "T_exact_over_T0",
    ]
    m_all, mc_all = (np.atleast_1d(x) for x in pendula.elliptic_parameter(theta0, args.omega0, w0))
    regimes = np.atleast_1d(pendula.regime(theta0, args.omega0, w0))
    rows = []
    for th, te, m, mc, reg in zip(theta0, exact, m_all, mc_all, regimes):
        motion = "rotation (per turn)" if reg == "rotation" else str(reg)
        series = t0 * (1 + m / 4 + 9 * m * m / 64) if reg == "libration" else float("nan")
        rows.append(
            [data(th), data(args.omega0), data(m), data(mc), motion, data(te), data(t0), data(series), data(te / t0)]
        )
    if args.w0 is not None:
        out.write(f"w0 = {data(w0)} 1/s\n")
    else:
        out.write(f"g = {data(args.g)} m/s^2, l = {data(args.length)} m, w0 = {data(w0)} 1/s\n")
    out.write(_fmt_table(header, rows) + "\n")
    if args.csv:
        _make_parent(args.csv, args)
        out.write(f"wrote {_write_csv(args.csv, header, rows)}\n")
    return 0


_SERIES = ("state", "theta", "energy")  # the wants that give theta at every output time


def cmd_solve(args, out):
    import pendula

    if args.csv:
        args.csv = _output_file(args.csv, "--csv", args, "solve.csv")
    if args.png:
        args.png = _output_file(args.png, "--png", args, "solve.png")
    if args.png:
        if args.want not in _SERIES:
            raise CliError(f"--png draws a time series: give --want {', '.join(_SERIES)}, not {args.want}")
        _need_matplotlib("--png")
    scene = _scene(args, want=args.want)
    kw = {"model": args.model} if args.model else {}
    res = pendula.solve(scene, **kw)
    out.write(f"model: {_get(res, 'model')}\n")
    out.write(f"reason: {_get(res, 'reason')}\n")
    out.write(f"error estimate: {data(_get(res, 'error_estimate'))} rad (tolerance {data(args.tol)} rad)\n")
    cost = _get(res, "cost")
    if cost is not None:
        out.write(f"cost: {cost}\n")
    if args.want == "period":
        out.write(f"period or time per revolution: {data(res.period)} s\n")
        header, rows = ["period_s"], [[data(res.period)]]
    elif args.want == "final":
        theta, omega = float(res.theta[-1]), float(res.omega[-1])
        out.write(f"final state at t = {data(args.t_end)} s: theta = {data(theta)} rad, Omega = {data(omega)} rad/s\n")
        header = ["t_s", "theta_rad", "omega_rad_per_s"]
        rows = [[data(args.t_end), data(theta), data(omega)]]
    elif args.want == "events":  # event times are found, not grid points: full precision everywhere
        ev = res.events
        kinds = {EVENT_TURNING: "turning point (Omega = 0)", EVENT_ZERO: "zero crossing (theta = 0 mod 2 pi)"}
        header = ["t_s", "kind", "theta_rad", "omega_rad_per_s"]
        rows = [
            [data(a), kinds.get(int(k), str(k)), data(b), data(c)]
            for a, k, b, c in zip(ev.t, ev.kind, ev.theta, ev.omega)
        ]
        out.write(f"{len(rows)} event(s) in (0, {data(args.t_end)}] s, time error ~ {data(res.event_time_error)} s\n")
    else:
        t = np.asarray(res.t, dtype=float)
        cols = [("theta_rad", res.theta), ("omega_rad_per_s", res.omega), ("energy_per_ml2_1_per_s2", res.energy)]
        cols = [(n, np.asarray(v, dtype=float)) for n, v in cols if v is not None]
        header = ["t_s"] + [n for n, _ in cols]
        rows = [[data(x) for x in vals] for vals in zip(t, *(v for _, v in cols))]
        if not args.csv:  # the printed table is for people: the grid's times without binary noise
            for row, clean in zip(rows, grid_times(t)):
                row[0] = clean
    if args.csv:
        _make_parent(args.csv, args)
        out.write(f"wrote {len(rows)} rows to {_write_csv(args.csv, header, rows)}\n")
    elif len(rows) > 1 or args.want in ("events",):
        show = rows if len(rows) <= 12 else rows[:6] + [["..."] * len(header)] + rows[-5:]
        out.write(_fmt_table(header, show) + "\n")
    if args.png:
        from .motion_plots import plot_motion
        from .plots import DPI

        _make_parent(args.png, args)
        plot_motion(res, kind="time" if res.omega is None else "both").savefig(args.png, dpi=DPI)
        out.write(f"wrote {args.png}\n")
    return 0


def cmd_tradeoff(args, out):
    import pendula

    fn = getattr(pendula, "tradeoff", None)
    if fn is None:
        raise NotImplementedError("pendula.tradeoff (the scenes module) is not available in this build")
    if args.csv:
        args.csv = _output_file(args.csv, "--csv", args, "tradeoff.csv")
    if args.png:
        args.png = _output_file(args.png, "--png", args, "tradeoff.png")
    scene = _scene(args)
    kw = {"repeat": args.repeat}
    if args.models:
        kw["models"] = [m.strip() for m in args.models.split(",") if m.strip()]
        bad = [m for m in kw["models"] if m not in MODELS]
        if bad:
            raise CliError(f"--models: unknown model(s) {', '.join(bad)}; known: {', '.join(MODELS)}")
    table = fn(scene, **kw)
    rows = [[r[0], _exact(r[1]), _exact(r[2]), _exact(r[3]), _exact(r[4])] for r in _tradeoff_rows(table)]
    header = ["model", "setting", "sup_error_rad", "wall_time_s", "rhs_evaluations"]
    out.write(_fmt_table(header, rows) + "\n")
    if args.csv:
        _make_parent(args.csv, args)
        out.write(f"wrote {_write_csv(args.csv, header, rows)}\n")
    if args.png:
        _make_parent(args.png, args)
        from .figures import work_precision_plot

        note = str(getattr(table, "reference", "") or "")
        out.write(
            f"wrote {work_precision_plot(rows, args.png, title='Work-precision', tol=args.tol, note=note or None)}\n"
        )
    return 0


def _exact(v):
    """A table cell: a real as the shortest decimal that reads back exactly, an
    integer as itself, anything else (a name, an empty setting) as its text."""
    if isinstance(v, (bool, np.bool_)) or v is None or isinstance(v, str):
        return "" if v is None else str(v)
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    try:
        return data(v)
    except (TypeError, ValueError):
        return str(v)


def _tradeoff_rows(table):
    """Normalise pendula.tradeoff's table into rows (model, setting, error, time, evaluations)."""
    from .figures import tradeoff_rows

    return tradeoff_rows(table)


def _grid_axis(spec, option, kind):
    if len(spec) not in (1, 3):
        raise CliError(
            f"{option}: give LO HI N (a grid of N points) or one value (a 1-D sweep over "
            f"the other axis), not {len(spec)} values"
        )
    try:
        if len(spec) == 1:
            return np.array([kind(spec[0])])
        lo, hi, n = kind(spec[0]), kind(spec[1]), _finite(spec[2])
    except argparse.ArgumentTypeError as exc:
        raise CliError(f"{option}: {exc}") from None
    if n != int(n) or not 2 <= n <= 100_000:
        raise CliError(f"{option}: N = {n:g} must be an integer in [2, 100000]")
    if not hi > lo:
        raise CliError(f"{option}: HI = {hi:g} must be > LO = {lo:g}")
    return np.linspace(lo, hi, int(n))


def cmd_sweep(args, out):
    import pendula

    th = _grid_axis(args.theta0, "--theta0", angle)
    om = _grid_axis(args.omega0, "--omega0", angular_velocity)
    _check_output(args.out, "--out", args, folder=True)
    w0 = _w0(args)
    gamma = (
        args.gamma
        if args.gamma is not None
        else (pendula.damping_rate(args.b, args.mass) if args.mass is not None and args.b is not None else 0.0)
    )
    t = np.array([0.0, args.t_end])
    if args.method == "rk4":
        if args.rtol is not None or args.atol is not None or args.cvode_method is not None:
            raise CliError("--rtol, --atol and --cvode-method are CVODE's: give --method cvode (RK4 takes --h)")
        kw = {"h": args.h}
    else:
        kw = {
            k: v
            for k, v in (("rtol", args.rtol), ("atol", args.atol), ("cvode_method", args.cvode_method))
            if v is not None
        }
    r = pendula.sweep(t, th[:, None], om[None, :], w0, gamma, method=args.method, threads=args.threads, **kw)
    _make_parent(Path(args.out) / "x", args)
    folder = Path(args.out)
    folder.mkdir(exist_ok=True)
    well = r.well
    setting = {"h": args.h} if args.method == "rk4" else kw
    np.savez(
        folder / "sweep.npz",
        theta0=th,
        omega0=om,
        theta=r.theta,
        omega=r.omega,
        well=well,
        codes=r.codes,
        t_end=args.t_end,
        w0=w0,
        gamma=gamma,
        method=args.method,
        **setting,
    )
    tt, oo = np.meshgrid(th, om, indexing="ij")
    rows = [
        [data(a), data(b), data(c), data(d), int(k), int(code)]
        for a, b, c, d, k, code in zip(
            tt.ravel(), oo.ravel(), r.theta.ravel(), r.omega.ravel(), well.ravel(), r.codes.ravel()
        )
    ]
    _write_csv(
        folder / "sweep.csv",
        ["theta0_rad", "omega0_rad_per_s", "theta_end_rad", "omega_end_rad_per_s", "well", "code"],
        rows,
    )
    out.write(
        f"{r.codes.size} starts, w0 = {data(w0)} 1/s, gamma = {data(gamma)} 1/s, t-end = {data(args.t_end)} s, "
        f"{args.method}; {int((~r.ok).sum())} failed; " + _wells(r) + "\n"
    )
    out.write(f"wrote {folder / 'sweep.npz'}\nwrote {folder / 'sweep.csv'}\n")
    if not args.no_png:
        from .figures import basin_map_plot

        out.write(f"wrote {basin_map_plot(th, om, well, folder / 'basin.png', w0=w0, gamma=gamma)}\n")
    if r.code:
        sys.stderr.write(f"{PROG} sweep: {r.message}\n")
        return 1
    return 0


def _wells(r):
    # the wells of the settled starts; the others have none (pendula.WELL_NONE in the files)
    k = r.well[r.settled]
    unsettled = int((r.ok & ~r.settled).sum())
    text = f"wells {int(k.min())}..{int(k.max())}" if k.size else "no well reached"
    return text + (f", {unsettled} not settled at t-end" if unsettled else "")


COMMANDS = {
    "sweep": cmd_sweep,
    "figures": cmd_figures,
    "period": cmd_period,
    "solve": cmd_solve,
    "tradeoff": cmd_tradeoff,
    "fit": _cli_fit.cmd_fit,
    **_cli_driven.COMMANDS,
}


def main(argv=None, out=None):
    """Entry point of the ``pendula`` console script and ``python -m pendula``; returns the exit code."""
    try:
        return _main(argv, out or sys.stdout)
    except KeyboardInterrupt:  # before a subcommand runs (parsing, importing): still one line
        sys.stderr.write(f"{PROG}: interrupted (Ctrl-C)\n")
        return 130


def _main(argv, out):
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.version:
        import pendula

        info = pendula.build_info()
        out.write(f"pendula {info['version']} (CVODE: {'yes' if info['cvode'] else 'no'})\n")
        return 0
    if args.command is None:
        parser.print_help(out)
        return 2
    sub = f"{PROG} {args.command}"
    try:
        _physics_defaults(args)
        if getattr(args, "v0", None) is not None:  # the text's §1.3 launch speed: Omega0 = v0 / l
            args.omega0 = args.v0 / args.length
            out.write(
                f"Omega0 = v0/l = {data(args.omega0)} rad/s (v0 = {data(args.v0)} m/s, l = {data(args.length)} m)\n"
            )
        return COMMANDS[args.command](args, out)
    except (CliError, ValueError, TypeError) as exc:
        sys.stderr.write(f"{sub}: error: {exc}\n")
        return 2
    except NotImplementedError as exc:
        sys.stderr.write(f"{sub}: not available: {exc}\n")
        return 2
    except MemoryError as exc:  # refused up front by the library, with the size asked for
        sys.stderr.write(f"{sub}: error: {exc or 'out of memory'}\n")
        return 1
    except KeyboardInterrupt:
        sys.stderr.write(f"{sub}: interrupted (Ctrl-C)\n")
        return 130
    except OSError as exc:  # an output that cannot be written: one line, no traceback
        if isinstance(exc, BrokenPipeError) and out is sys.stdout:
            _quiet_stdout()
            return 1
        where = f" {exc.filename}" if exc.filename else ""
        sys.stderr.write(f"{sub}: error: cannot write{where}: {exc.strerror or exc}\n")
        return 1
    except RuntimeError as exc:  # PendulaSolverError and friends
        sys.stderr.write(f"{sub}: solver failed: {exc}\n")
        return 1


def _quiet_stdout():
    """stdout's reader has gone (``pendula period ... | head``): send the rest,
    and Python's flush at exit, to the null device instead of a traceback."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        pass


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
