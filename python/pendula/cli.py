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

import os
import sys

from . import _cli_driven, _cli_fit
from ._cli_commands import cmd_figures, cmd_period, cmd_solve, cmd_sweep, cmd_tradeoff
from ._cli_common import MODELS, PROG, WANTS, CliError, physics_defaults
from ._cli_parser import build_parser
from ._cli_values import data

__all__ = ["CliError", "MODELS", "WANTS", "build_parser", "main"]


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
        physics_defaults(args)
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
