"""Command line of pendula: ``python -m pendula`` or the ``pendula`` console script.

Subcommands (``pendula SUBCOMMAND --help`` for each):

  figures   draw every figure of the text (and the ones it lacks) into a folder
  period    exact period (or time per revolution) against small-angle and series
  solve     solve a scene (the library picks the cheapest model meeting --tol)
  tradeoff  speed/accuracy table of every model on a scene (CSV, work-precision PNG)
  sweep     a theta0 x Omega0 grid integrated to t-end: NPZ, CSV and the basin map (PNG)
  poincare, bifurcation, lyapunov, basins   the driven pendulum's chaos tools (NPZ, CSV, PNG)

Units: angles rad, angular velocities rad/s, times s, g m/s^2, length m,
mass kg, b kg/s, gamma and w0 1/s; angles may be given in degrees (--theta0 90deg,
--omega0 30deg/s) and the initial state by the text's launch speed (--v0 in m/s,
Omega0 = v0/l).  Exit status 0 on success, 2 on a bad flag or value (with a
message saying what is wrong), 1 when a solver fails.

Output: tables printed for people show the times of the output grid without
binary noise (0.45, not 0.44999999999999996); CSV and NPZ files are data files
and keep every number to full precision (the shortest decimal that reads back as
the same double).
"""
import argparse
import csv
import math
import sys
from pathlib import Path

import numpy as np

from . import _cli_driven
from ._cli_values import accept_negative_values, angle, angular_velocity, count as _count, data, grid_times
from ._cli_values import finite as _finite
from ._cli_values import nonnegative as _nonnegative, positive as _positive
from ._codes import EVENT_TURNING, EVENT_ZERO, G_DEFAULT, LENGTH_DEFAULT, MODEL_CODES, WANT_CODES

PROG = "pendula"
MODELS = tuple(name for name in MODEL_CODES if name != "auto")
WANTS = tuple(WANT_CODES)


class CliError(Exception):
    """A bad value the parser could not see (e.g. inconsistent flags)."""


# ---------------------------------------------------------------- parser

_PHYS_HELP = (f"physical parameters (the text's defaults: g = {G_DEFAULT:g} m/s^2, l = {LENGTH_DEFAULT:g} m, "
              "so w0 = sqrt(2) 1/s)")


def _add_physics(p, damping=True):
    g = p.add_argument_group(_PHYS_HELP)
    g.add_argument("--g", type=_positive, default=G_DEFAULT, metavar="M/S2",
                   help=f"gravitational acceleration g in m/s^2 (default {G_DEFAULT:g})")
    g.add_argument("--length", "-l", type=_positive, default=LENGTH_DEFAULT, metavar="M",
                   help=f"pendulum length l in m (default {LENGTH_DEFAULT:g}); w0 = sqrt(g/l) in 1/s")
    if damping:
        g.add_argument("--gamma", type=_nonnegative, default=None, metavar="1/S",
                       help="damping rate gamma in 1/s (eq. 2.3); or give --mass and --b "
                            "(all three only when gamma = b/m)")
        g.add_argument("--mass", "-m", type=_positive, default=None, metavar="KG",
                       help="bob mass m in kg (with --b: gamma = b/m, eq. 2.2)")
        g.add_argument("--b", type=_nonnegative, default=None, metavar="KG/S",
                       help="damping constant b in kg/s (with --mass)")


_ANGLE_HELP = "in rad, or in degrees with the unit: 90deg"
_RATE_HELP = "in rad/s, or in degrees per second with the unit: 30deg/s"


def _add_launch(group, what="initial angular velocity Omega0"):
    """--omega0 and its alternative --v0 (the bob's launch speed of the text's §1.3)."""
    one = group.add_mutually_exclusive_group()
    one.add_argument("--omega0", type=angular_velocity, default=0.0, metavar="RAD/S",
                     help=f"{what} {_RATE_HELP} (default 0)")
    one.add_argument("--v0", type=_finite, default=None, metavar="M/S",
                     help="instead of --omega0: the bob's launch speed v0 in m/s (text §1.3), "
                          "Omega0 = v0/l; signed, > 0 towards increasing theta")


def _add_scene(p):
    s = p.add_argument_group("initial state and window")
    s.add_argument("--theta0", type=angle, required=True, metavar="ANGLE",
                   help=f"initial angle theta0 {_ANGLE_HELP} (any real; 0 = hanging down)")
    _add_launch(s)
    s.add_argument("--t-end", type=_positive, required=True, metavar="S",
                   help="end of the time window in s (the window starts at t = 0)")
    s.add_argument("--n", type=_count, default=201, metavar="N",
                   help="number of equally spaced output times in [0, t-end] (default 201)")
    s.add_argument("--tol", type=_positive, default=1e-6, metavar="RAD",
                   help="absolute tolerance on theta in rad over the whole window "
                        "(Omega scaled by w0); default 1e-6")
    _add_physics(p)


def build_parser():
    """The argparse parser of the command line (exposed for tests and docs)."""
    p = argparse.ArgumentParser(
        prog=PROG,
        description="The simple pendulum, exact where mathematics allows. "
                    "Units: angles rad (or degrees with the unit: 90deg), angular velocities rad/s "
                    "(or 30deg/s), times s, g m/s^2, "
                    "length m, mass kg, b kg/s, gamma and w0 1/s.",
        epilog="Run `pendula SUBCOMMAND --help` for the flags of each subcommand.")
    p.add_argument("--version", action="store_true", help="print the version and build information")
    sub = p.add_subparsers(dest="command", metavar="SUBCOMMAND")

    f = sub.add_parser("figures", help="draw every figure of the text (and those it lacks) into a folder",
                       description="Draw the text's figures 3-15 from the library (correct where the "
                                   "text's listings were wrong) and the figures it lacks (underdamped "
                                   "case, phase portrait, period vs energy, work-precision), as PNG "
                                   "files into --out. Needs matplotlib; needs no display.")
    f.add_argument("--out", metavar="DIR", help="output folder (created if missing, but its parent must "
                   "exist unless --mkdir); required unless --list")
    f.add_argument("--quick", action="store_true", help="fewer points per curve (fast, for tests)")
    f.add_argument("--only", default=None, metavar="KEYS",
                   help="comma-separated figure keys to draw, e.g. fig03,fig14 (default: all)")
    f.add_argument("--list", action="store_true", help="list the figure keys and exit")
    f.add_argument("--mkdir", action="store_true", help="also create the missing parent folders of --out")

    q = sub.add_parser("period", help="exact period or revolution time vs small-angle and series",
                       description="Exact period T = 4K(m)/w0 of the libration (eq. 1.53, any Omega0) or "
                                   "the time per revolution 2K(1/m)/(sqrt(m) w0) of a rotation, against "
                                   "the small-angle period T0 = 2 pi/w0 (eq. 1.8) and the series "
                                   "T0 (1 + m/4 + 9 m^2/64), where m = sin^2(theta0/2) + (Omega0/2w0)^2 "
                                   "is the energy over the separatrix energy. Times in s.")
    q.add_argument("--theta0", type=angle, nargs="+", required=True, metavar="ANGLE",
                   help=f"one or more initial angles {_ANGLE_HELP}")
    _add_launch(q, "initial angular velocity")
    q.add_argument("--csv", default=None, metavar="FILE", help="also write the table as CSV")
    q.add_argument("--mkdir", action="store_true", help="create the missing folders of --csv")
    _add_physics(q, damping=False)

    s = sub.add_parser("solve", help="solve a scene with the cheapest model that meets --tol",
                       description="Describe a scene (parameters, initial state, window, tolerance); the "
                                   "library picks the cheapest model whose error estimate fits the "
                                   "tolerance (small-angle, exact elliptic, linear damped closed form, "
                                   "RK4, CVODE), says which and why, and returns theta (rad) and "
                                   "Omega (rad/s) at the output times (s).")
    _add_scene(s)
    s.add_argument("--model", default=None, choices=MODELS,
                   help="force a model instead of letting the library choose")
    s.add_argument("--want", default="state", choices=WANTS,
                   help="what to compute: state (theta [rad] and Omega [rad/s] at the output times, "
                        "default), theta, final (the state at t-end only, no history), energy "
                        "(per unit m l^2, 1/s^2), period (period or time per revolution [s], "
                        "undamped only), events (turning points and zero crossings [s])")
    s.add_argument("--csv", default=None, metavar="FILE",
                   help="write t [s], theta [rad], omega [rad/s] as CSV, a data file: every number to full "
                        "precision, the times as computed (default: print a summary table, its times "
                        "rounded to the grid's resolution: 0.45, not 0.44999999999999996)")
    s.add_argument("--png", default=None, metavar="FILE",
                   help="also draw theta(t), Omega(t) and the phase plane as PNG (pendula.plot_motion; "
                        "theta(t) alone for --want theta); needs matplotlib")
    s.add_argument("--mkdir", action="store_true", help="create the missing folders of --csv and --png")

    t = sub.add_parser("tradeoff", help="speed/accuracy table of every applicable model on a scene",
                       description="Run every applicable model over a range of settings (RK4 steps, "
                                   "CVODE tolerances, closed forms) on a scene, against a reference, "
                                   "and print model, setting, sup error of the state over the output "
                                   "grid (rad), wall time (s) and right-hand-side evaluations.")
    _add_scene(t)
    t.add_argument("--csv", default=None, metavar="FILE", help="also write the table as CSV")
    t.add_argument("--png", default=None, metavar="FILE", help="also draw the work-precision diagram (PNG)")
    t.add_argument("--mkdir", action="store_true", help="create the missing folders of --csv and --png")
    t.add_argument("--models", default=None, metavar="NAMES",
                   help="comma-separated subset of " + ", ".join(MODELS) + " (default: every applicable one)")
    t.add_argument("--repeat", type=_count, default=3, metavar="N",
                   help="wall time is the best of N >= 2 calls (default 3)")
    w = sub.add_parser("sweep", help="a theta0 x Omega0 grid integrated to t-end: NPZ, CSV and basin map",
                       description="Integrate every start of a theta0 x Omega0 grid (RK4 batch kernel, in "
                                   "chunks; Ctrl-C stops it) to --t-end and write into --out: sweep.npz "
                                   "(theta0 [rad], omega0 [rad/s], final theta [rad], final Omega [rad/s], "
                                   "well, status codes), sweep.csv (one row per start) and basin.png: the "
                                   "basin map, each start coloured by the well 2 pi k it ends in (the turns "
                                   "made before the damping caught it).")
    w.add_argument("--theta0", nargs=3, default=[-math.pi, math.pi, 101], metavar=("LO", "HI", "N"),
                   help=f"theta0 grid: LO HI {_ANGLE_HELP} (-180deg 180deg 101), N points "
                        "(default -pi pi 101)")
    w.add_argument("--omega0", nargs=3, default=[-6.0, 6.0, 101], metavar=("LO", "HI", "N"),
                   help=f"Omega0 grid: LO HI {_RATE_HELP}, N points (default -6 6 101)")
    w.add_argument("--t-end", type=_positive, default=30.0, metavar="S", help="end time in s (default 30)")
    w.add_argument("--h", type=_positive, default=0.01, metavar="S", help="RK4 step in s (default 0.01)")
    w.add_argument("--out", required=True, metavar="DIR",
                   help="output folder (created if missing, but its parent must exist unless --mkdir)")
    w.add_argument("--mkdir", action="store_true", help="also create the missing parent folders of --out")
    w.add_argument("--no-png", action="store_true", help="skip the figure (no matplotlib needed)")
    _add_physics(w)
    _cli_driven.add_parsers(sub)   # poincare, bifurcation, lyapunov, basins
    for parser in (p, *sub.choices.values()):
        accept_negative_values(parser)
    return p


# ---------------------------------------------------------------- helpers

def _scene(args, want="state"):
    """The scene of the flags; --gamma, --mass and --b go through to the library,
    which checks them (mass and b together; gamma too only when it equals b/mass)."""
    import pendula
    scene_cls = getattr(pendula, "Scene", None)
    if scene_cls is None:
        raise NotImplementedError("pendula.Scene (the scenes module) is not available in this build")
    t = np.linspace(0.0, args.t_end, args.n)
    return scene_cls(theta0=args.theta0, omega0=args.omega0, t=t, g=args.g, length=args.length,
                     gamma=args.gamma, mass=args.mass, b=args.b, tol=args.tol, want=want)


def _fmt_table(header, rows):
    cols = [[str(h)] + [str(r[i]) for r in rows] for i, h in enumerate(header)]
    widths = [max(len(c) for c in col) for col in cols]
    lines = ["  ".join(h.rjust(w) for h, w in zip(header, widths)),
             "  ".join("-" * w for w in widths)]
    lines += ["  ".join(str(v).rjust(w) for v, w in zip(r, widths)) for r in rows]
    return "\n".join(lines)


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
        raise CliError(f"{option} {path}: directory {parent} does not exist "
                       f"(create it, or give --mkdir to let {PROG} create it)")


def _need_matplotlib(what):
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        from .motion_plots import EXTRA
        raise CliError(f"{what} needs matplotlib: pip install 'pendula[{EXTRA}]' (or pip install matplotlib)") \
            from None


def _make_parent(path, args):
    if getattr(args, "mkdir", False):
        Path(path).parent.mkdir(parents=True, exist_ok=True)


def _write_csv(path, header, rows):
    path = Path(path)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(rows)
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
        _check_output(args.csv, "--csv", args)
    w0 = pendula.natural_frequency(args.g, args.length)
    t0 = float(pendula.small_angle_period(w0))
    theta0 = np.asarray(args.theta0, dtype=float)
    exact = np.atleast_1d(np.asarray(pendula.period(theta0, args.omega0, w0), dtype=float))
    header = ["theta0_rad", "omega0_rad_per_s", "E_over_Esep", "1_minus_E_over_Esep", "motion", "T_exact_s",
              "T0_small_angle_s", "T_series_s", "T_exact_over_T0"]
    m_all, mc_all = (np.atleast_1d(x) for x in pendula.elliptic_parameter(theta0, args.omega0, w0))
    regimes = np.atleast_1d(pendula.regime(theta0, args.omega0, w0))
    rows = []
    for th, te, m, mc, reg in zip(theta0, exact, m_all, mc_all, regimes):
        motion = "rotation (per turn)" if reg == "rotation" else str(reg)
        series = t0 * (1 + m / 4 + 9 * m * m / 64) if reg == "libration" else float("nan")
        rows.append([f"{th:.10g}", f"{args.omega0:.10g}", f"{m:.10g}", f"{mc:.6g}", motion, f"{te:.12g}",
                     f"{t0:.12g}", f"{series:.8g}", f"{te / t0:.8g}"])
    out.write(f"g = {args.g} m/s^2, l = {args.length} m, w0 = {w0:.12g} 1/s\n")
    out.write(_fmt_table(header, rows) + "\n")
    if args.csv:
        _make_parent(args.csv, args)
        out.write(f"wrote {_write_csv(args.csv, header, rows)}\n")
    return 0


_SERIES = ("state", "theta", "energy")   # the wants that give theta at every output time


def cmd_solve(args, out):
    import pendula
    for opt, path in (("--csv", args.csv), ("--png", args.png)):
        if path:
            _check_output(path, opt, args)
    if args.png:
        if args.want not in _SERIES:
            raise CliError(f"--png draws a time series: give --want {', '.join(_SERIES)}, not {args.want}")
        _need_matplotlib("--png")
    scene = _scene(args, want=args.want)
    kw = {"model": args.model} if args.model else {}
    res = pendula.solve(scene, **kw)
    out.write(f"model: {_get(res, 'model')}\n")
    out.write(f"reason: {_get(res, 'reason')}\n")
    out.write(f"error estimate: {_get(res, 'error_estimate')} rad (tolerance {args.tol:g} rad)\n")
    cost = _get(res, "cost")
    if cost is not None:
        out.write(f"cost: {cost}\n")
    if args.want == "period":
        out.write(f"period or time per revolution: {data(res.period)} s\n")
        header, rows = ["period_s"], [[data(res.period)]]
    elif args.want == "final":
        theta, omega = float(res.theta[-1]), float(res.omega[-1])
        out.write(f"final state at t = {args.t_end:g} s: theta = {data(theta)} rad, "
                  f"Omega = {data(omega)} rad/s\n")
        header = ["t_s", "theta_rad", "omega_rad_per_s"]
        rows = [[data(args.t_end), data(theta), data(omega)]]
    elif args.want == "events":   # event times are found, not grid points: full precision everywhere
        ev = res.events
        kinds = {EVENT_TURNING: "turning point (Omega = 0)", EVENT_ZERO: "zero crossing (theta = 0 mod 2 pi)"}
        header = ["t_s", "kind", "theta_rad", "omega_rad_per_s"]
        rows = [[data(a), kinds.get(int(k), str(k)), data(b), data(c)]
                for a, k, b, c in zip(ev.t, ev.kind, ev.theta, ev.omega)]
        out.write(f"{len(rows)} event(s) in (0, {args.t_end:g}] s, time error ~ {res.event_time_error} s\n")
    else:
        t = np.asarray(res.t, dtype=float)
        cols = [("theta_rad", res.theta), ("omega_rad_per_s", res.omega), ("energy_per_ml2_1_per_s2", res.energy)]
        cols = [(n, np.asarray(v, dtype=float)) for n, v in cols if v is not None]
        header = ["t_s"] + [n for n, _ in cols]
        rows = [[data(x) for x in vals] for vals in zip(t, *(v for _, v in cols))]
        if not args.csv:   # the printed table is for people: the grid's times without binary noise
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
    for opt, path in (("--csv", args.csv), ("--png", args.png)):
        if path:
            _check_output(path, opt, args)
    scene = _scene(args)
    kw = {"repeat": args.repeat}
    if args.models:
        kw["models"] = [m.strip() for m in args.models.split(",") if m.strip()]
        bad = [m for m in kw["models"] if m not in MODELS]
        if bad:
            raise CliError(f"--models: unknown model(s) {', '.join(bad)}; known: {', '.join(MODELS)}")
    table = fn(scene, **kw)
    rows = _tradeoff_rows(table)
    header = ["model", "setting", "sup_error_rad", "wall_time_s", "rhs_evaluations"]
    out.write(_fmt_table(header, [[r[0], r[1], f"{r[2]:.3g}", f"{r[3]:.3g}", r[4]] for r in rows]) + "\n")
    if args.csv:
        _make_parent(args.csv, args)
        out.write(f"wrote {_write_csv(args.csv, header, rows)}\n")
    if args.png:
        _make_parent(args.png, args)
        from .figures import work_precision_plot
        note = str(getattr(table, "reference", "") or "")
        out.write(f"wrote {work_precision_plot(rows, args.png, title='Work-precision', tol=args.tol, note=note or None)}\n")
    return 0


def _tradeoff_rows(table):
    """Normalise pendula.tradeoff's table into rows (model, setting, error, time, evaluations)."""
    from .figures import tradeoff_rows
    return tradeoff_rows(table)


def _grid_axis(spec, option, kind):
    try:
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
    w0 = pendula.natural_frequency(args.g, args.length)
    gamma = args.gamma if args.gamma is not None else (
        pendula.damping_rate(args.b, args.mass) if args.mass is not None and args.b is not None else 0.0)
    t = np.array([0.0, args.t_end])
    r = pendula.sweep(t, th[:, None], om[None, :], w0, gamma, h=args.h)
    _make_parent(Path(args.out) / "x", args)
    folder = Path(args.out)
    folder.mkdir(exist_ok=True)
    well = r.well
    np.savez(folder / "sweep.npz", theta0=th, omega0=om, theta=r.theta, omega=r.omega, well=well, codes=r.codes,
             t_end=args.t_end, w0=w0, gamma=gamma, h=args.h)
    tt, oo = np.meshgrid(th, om, indexing="ij")
    rows = [[data(a), data(b), data(c), data(d), int(k), int(code)] for a, b, c, d, k, code in
            zip(tt.ravel(), oo.ravel(), r.theta.ravel(), r.omega.ravel(), well.ravel(), r.codes.ravel())]
    _write_csv(folder / "sweep.csv", ["theta0_rad", "omega0_rad_per_s", "theta_end_rad", "omega_end_rad_per_s",
                                      "well", "code"], rows)
    out.write(f"{r.codes.size} starts, w0 = {w0:.12g} 1/s, gamma = {gamma:g} 1/s, t-end = {args.t_end:g} s; "
              f"{int((~r.ok).sum())} failed; wells {int(well.min())}..{int(well.max())}\n")
    out.write(f"wrote {folder / 'sweep.npz'}\nwrote {folder / 'sweep.csv'}\n")
    if not args.no_png:
        from .figures import basin_map_plot
        out.write(f"wrote {basin_map_plot(th, om, well, folder / 'basin.png', w0=w0, gamma=gamma)}\n")
    if r.code:
        sys.stderr.write(f"{PROG} sweep: {r.message}\n")
        return 1
    return 0


COMMANDS = {"sweep": cmd_sweep, "figures": cmd_figures, "period": cmd_period, "solve": cmd_solve, "tradeoff": cmd_tradeoff,
            **_cli_driven.COMMANDS}


def main(argv=None, out=None):
    """Entry point of the ``pendula`` console script and ``python -m pendula``; returns the exit code."""
    out = out or sys.stdout
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
    if getattr(args, "v0", None) is not None:   # the text's §1.3 launch speed: Omega0 = v0 / l
        args.omega0 = args.v0 / args.length
        out.write(f"Omega0 = v0/l = {data(args.omega0)} rad/s (v0 = {data(args.v0)} m/s, "
                  f"l = {data(args.length)} m)\n")
    try:
        return COMMANDS[args.command](args, out)
    except (CliError, ValueError, TypeError) as exc:
        sys.stderr.write(f"{sub}: error: {exc}\n")
        return 2
    except NotImplementedError as exc:
        sys.stderr.write(f"{sub}: not available: {exc}\n")
        return 2
    except RuntimeError as exc:  # PendulaSolverError and friends
        sys.stderr.write(f"{sub}: solver failed: {exc}\n")
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
