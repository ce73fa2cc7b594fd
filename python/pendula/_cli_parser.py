"""The argparse parser of the ``pendula`` command line: every subcommand's flags."""

import argparse
import math

from . import _cli_driven, _cli_fit
from ._cli_common import MODELS, PROG, WANTS
from ._cli_values import accept_negative_values, angle, angular_velocity, threads
from ._cli_values import count as _count
from ._cli_values import finite as _finite
from ._cli_values import nonnegative as _nonnegative
from ._cli_values import positive as _positive
from ._codes import G_DEFAULT, LENGTH_DEFAULT
from ._defaults import SWEEP_H, TOL

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
