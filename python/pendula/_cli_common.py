"""What every ``pendula`` subcommand shares: the program name, the error a
command raises for a bad value the parser could not see, the physical defaults
of the flags, output paths checked before any work, and tables and CSV files."""

import csv
import os
from pathlib import Path

import numpy as np

from ._codes import G_DEFAULT, LENGTH_DEFAULT, MODEL_CODES, WANT_CODES

PROG = "pendula"
MODELS = tuple(name for name in MODEL_CODES if name != "auto")
WANTS = tuple(WANT_CODES)


class CliError(Exception):
    """A bad value the parser could not see (e.g. inconsistent flags)."""


# ---------------------------------------------------------------- helpers


def physics_defaults(args):
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


def w0_of(args):
    """The natural frequency of the flags: --w0, or sqrt(g/l)."""
    import pendula

    w0 = getattr(args, "w0", None)
    return float(w0) if w0 is not None else float(pendula.natural_frequency(args.g, args.length))


def scene_of(args, want="state"):
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


def fmt_table(header, rows):
    cols = [[str(h)] + [str(r[i]) for r in rows] for i, h in enumerate(header)]
    widths = [max(len(c) for c in col) for col in cols]
    lines = ["  ".join(h.rjust(w) for h, w in zip(header, widths)), "  ".join("-" * w for w in widths)]
    lines += ["  ".join(str(v).rjust(w) for v, w in zip(r, widths)) for r in rows]
    return "\n".join(lines)


def output_file(path, option, args, name):
    """The file an output flag names: a path ending in a separator, or naming an
    existing folder, means the file `name` inside that folder (never a file
    named like the folder); checked by check_output."""
    text = str(path)
    if text.endswith(("/", os.sep)) or Path(text).is_dir():
        path = Path(text) / name
    check_output(path, option, args)
    return str(path)


def check_output(path, option, args, folder=False):
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


def need_matplotlib(what):
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        from .motion_plots import EXTRA

        raise CliError(f"{what} needs matplotlib: pip install 'pendula[{EXTRA}]' (or pip install matplotlib)") from None


def make_parent(path, args):
    if getattr(args, "mkdir", False):
        Path(path).parent.mkdir(parents=True, exist_ok=True)


def write_csv(path, header, rows):
    path = Path(path)
    try:
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(header)
            w.writerows(rows)
    except OSError as exc:  # e.g. a full disk reported when the file is closed: name the file
        raise OSError(exc.errno, exc.strerror, str(path)) from None
    return path


def field(obj, *names, default=None):
    for n in names:
        if isinstance(obj, dict) and n in obj:
            return obj[n]
        if hasattr(obj, n):
            return getattr(obj, n)
    return default
