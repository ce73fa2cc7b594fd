"""Subcommands of the driven pendulum: ``pendula poincare``, ``bifurcation``,
``lyapunov`` and ``basins``.  Each writes NAME.npz and NAME.csv (every number
to full precision) and NAME.png (unless --no-png) into --out.  Registered by
pendula.cli (add_parsers and COMMANDS)."""

import contextlib
import csv
import math
from pathlib import Path

import numpy as np

from ._cli_values import angle, angular_velocity, count, data, finite, nonnegative, positive
from ._codes import DRIVEN_DEFAULT_STEPS, LYAPUNOV_DEFAULT_PERIODS, LYAPUNOV_DEFAULT_STEPS, LYAPUNOV_ORBITS


def _grid(spec, kind, name):
    lo, hi, n = spec
    try:
        n = int(n)
    except ValueError:
        raise ValueError(f"{name}: N = {n!r} is not an integer") from None
    if n < 1:
        raise ValueError(f"{name}: N = {n} must be >= 1")
    return np.linspace(kind(lo), kind(hi), n)


def _common(p, name, png_what, add_physics, steps=DRIVEN_DEFAULT_STEPS):
    g = p.add_argument_group(
        "the driven pendulum: theta'' + gamma theta' + w0^2 sin theta = F cos(Omega t + phi) "
        "(torque), or a pivot a cos(Omega t + phi) (pivot: (a/l) Omega^2 cos(...) added to w0^2)"
    )
    g.add_argument("--kind", choices=("torque", "pivot"), default="torque", help="drive kind (default torque)")
    g.add_argument(
        "--amplitude",
        "-F",
        type=finite,
        default=1.15,
        metavar="F",
        help="F in rad/s^2 (torque) or a/l (pivot) (default 1.15)",
    )
    g.add_argument(
        "--frequency",
        type=positive,
        default=2 / 3,
        metavar="RAD/S",
        help="drive frequency Omega in rad/s (default 2/3)",
    )
    g.add_argument("--phase", type=finite, default=0.0, metavar="RAD", help="drive phase phi in rad (default 0)")
    g.add_argument("--gamma", type=nonnegative, default=0.5, metavar="1/S", help="damping rate (default 0.5)")
    g.add_argument(
        "--steps", type=count, default=steps, metavar="N", help=f"RK4 steps per drive period (default {steps})"
    )
    add_physics(p, damping=False, w0=True)  # the pendulum: --w0, or --g/--length (the text's by default)
    p.add_argument(
        "--out",
        required=True,
        metavar="DIR",
        help="output folder (created if missing, but its parent must exist unless --mkdir)",
    )
    p.add_argument("--mkdir", action="store_true", help="also create the missing parent folders of --out")
    p.add_argument("--no-png", action="store_true", help=f"skip {png_what} (no matplotlib needed)")


def _transient(p, default, what="periods discarded"):
    """--transient: drive periods before the measurement."""
    p.add_argument("--transient", type=int, default=default, metavar="P", help=f"{what} (default {default})")


def _start(p):
    """The one start (--theta0, --omega0) of a section command, and its transient."""
    p.add_argument("--theta0", type=angle, default=0.2, metavar="ANGLE", help="initial angle (default 0.2 rad)")
    p.add_argument("--omega0", type=angular_velocity, default=0.0, metavar="RAD/S", help="initial Omega (default 0)")
    _transient(p, 300)


def add_parsers(sub, add_physics):
    """Add the four subcommands to the subparsers ``sub`` of pendula.cli;
    ``add_physics(parser, damping, w0)`` is pendula.cli's --g/--length/--w0
    group, so that every command takes the pendulum one way."""
    p = sub.add_parser(
        "poincare",
        help="Poincare section of the driven pendulum: NPZ, CSV and PNG",
        description="Stroboscopic (Poincare) section at t = k T after a transient: theta wrapped "
        "to (-pi, pi] [rad] and Omega [rad/s]; poincare.npz, poincare.csv, poincare.png.",
    )
    _start(p)
    p.add_argument("--points", type=count, default=5000, metavar="K", help="section points (default 5000)")
    _common(p, "poincare", "the section plot", add_physics)
    b = sub.add_parser(
        "bifurcation",
        help="bifurcation diagram of the driven pendulum: NPZ, CSV and PNG",
        description="Section points over values of one parameter (every value from the same "
        "start): bifurcation.npz, bifurcation.csv, bifurcation.png.",
    )
    b.add_argument("--parameter", choices=("amplitude", "frequency", "phase", "gamma", "w0"), default="amplitude")
    b.add_argument(
        "--values",
        nargs=3,
        default=["0.9", "1.5", "400"],
        metavar=("LO", "HI", "N"),
        help="N values from LO to HI (default 0.9 1.5 400)",
    )
    _start(b)
    b.add_argument("--points", type=count, default=200, metavar="K", help="section points per value (default 200)")
    _common(b, "bifurcation", "the diagram", add_physics)
    lp = sub.add_parser(
        "lyapunov",
        help="Lyapunov exponents of the driven pendulum: NPZ, CSV and PNG",
        description="Both Lyapunov exponents [1/s] with 95 % error bounds, per initial state "
        "(an ensemble of copies in the SIMD lanes): "
        "lyapunov.npz, lyapunov.csv, lyapunov.png.",
    )
    lp.add_argument("--theta0", type=angle, nargs="+", default=[0.2], metavar="ANGLE", help="initial angles")
    lp.add_argument("--omega0", type=angular_velocity, default=0.0, metavar="RAD/S", help="initial Omega (default 0)")
    _transient(lp, 100, "periods before measuring")
    lp.add_argument(
        "--periods",
        type=count,
        default=LYAPUNOV_DEFAULT_PERIODS,
        metavar="P",
        help=f"periods measured by each copy (default {LYAPUNOV_DEFAULT_PERIODS})",
    )
    lp.add_argument(
        "--orbits",
        type=count,
        default=LYAPUNOV_ORBITS,
        metavar="K",
        help=f"copies of each start averaged, 1 to {LYAPUNOV_ORBITS} (default {LYAPUNOV_ORBITS})",
    )
    _common(lp, "lyapunov", "the plot", add_physics, steps=LYAPUNOV_DEFAULT_STEPS)
    g = sub.add_parser(
        "basins",
        help="basins of attraction of the driven pendulum: NPZ, CSV and PNG",
        description="For each start of a theta0 x Omega0 grid, the periodic attractor it settles on "
        "(label 0: none of period <= nmax, chaotic or unsettled): basins.npz, "
        "basins.csv, basins.png.",
    )
    g.add_argument(
        "--theta0",
        nargs=3,
        default=["-3.14159", "3.14159", "101"],
        metavar=("LO", "HI", "N"),
        help="theta0 grid (default -pi pi 101)",
    )
    g.add_argument(
        "--omega0",
        nargs=3,
        default=["-3", "3", "101"],
        metavar=("LO", "HI", "N"),
        help="Omega0 grid (default -3 3 101)",
    )
    _transient(g, 200, "periods before classifying")
    g.add_argument("--nmax", type=count, default=8, metavar="N", help="largest period recognised (default 8)")
    _common(g, "basins", "the basin map", add_physics)


def _w0(args):
    """--w0, or sqrt(g/l) of --g and --length (pendula.cli set the text's values for those not given)."""
    import pendula

    return args.w0 if args.w0 is not None else float(pendula.natural_frequency(args.g, args.length))


def _setup(args):
    import pendula

    drive = pendula.Drive(args.kind, args.amplitude, args.frequency, args.phase)
    if getattr(args, "mkdir", False):
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    folder = Path(args.out)
    folder.mkdir(exist_ok=True)
    return pendula, drive, folder


def _shared(args, drive):
    """The keyword arguments every command passes to its pendula call."""
    return dict(drive=drive, w0=_w0(args), gamma=args.gamma, transient=args.transient, steps_per_period=args.steps)


def _save(folder, name, arrays, header, rows):
    """NAME.npz (the arrays) and NAME.csv (header and rows) in folder."""
    np.savez(folder / f"{name}.npz", **arrays)
    _csv(folder / f"{name}.csv", header, rows)


def _wrote(out, folder, name):
    out.write(f"wrote {folder / (name + '.npz')}\nwrote {folder / (name + '.csv')}\n")


@contextlib.contextmanager
def _png(folder, out, name, figsize):
    """A figure (fig, ax) of figsize, saved as NAME.png in folder (dpi 120) and
    reported on out when the block ends."""
    plt = _fig()
    fig, ax = plt.subplots(figsize=figsize)
    yield fig, ax
    fig.savefig(folder / f"{name}.png", dpi=120)
    plt.close(fig)
    out.write(f"wrote {folder / (name + '.png')}\n")


def _csv(path, header, rows):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(rows)
    return path


def _fig():
    import matplotlib
    import matplotlib.pyplot as plt

    matplotlib.use(matplotlib.get_backend())
    return plt


def cmd_poincare(args, out):
    pendula, drive, folder = _setup(args)
    s = pendula.poincare(args.theta0, args.omega0, points=args.points, **_shared(args, drive))
    _save(
        folder,
        "poincare",
        dict(theta=s.theta, omega=s.omega, mean_omega=s.mean_omega),
        ["k", "theta_rad", "omega_rad_per_s"],
        [[k, data(a), data(b)] for k, (a, b) in enumerate(zip(s.theta, s.omega))],
    )
    out.write(f"{args.points} section points, rotation number {float(s.rotation_number):.6g}\n")
    _wrote(out, folder, "poincare")
    if not args.no_png:
        with _png(folder, out, "poincare", (6, 5)) as (fig, ax):
            ax.plot(s.theta, s.omega, ",k" if args.points > 2000 else ".k", ms=2)
            ax.set(
                xlabel="theta [rad]",
                ylabel="Omega [rad/s]",
                xlim=(-math.pi, math.pi),
                title=f"Poincare section: {args.kind} {args.amplitude:g}, Omega {args.frequency:.4g}, "
                f"gamma {args.gamma:g}",
            )
    return 0


def cmd_bifurcation(args, out):
    pendula, drive, folder = _setup(args)
    vals = _grid(args.values, finite, "--values")
    b = pendula.bifurcation(
        args.parameter, vals, theta0=args.theta0, omega0=args.omega0, points=args.points, **_shared(args, drive)
    )
    _save(
        folder,
        "bifurcation",
        dict(values=vals, theta=b.theta, omega=b.omega, mean_omega=b.mean_omega, parameter=args.parameter),
        [args.parameter, "k", "theta_rad", "omega_rad_per_s"],
        [
            [data(v), k, data(a), data(c)]
            for v, ta, oa in zip(vals, b.theta, b.omega)
            for k, (a, c) in enumerate(zip(ta, oa))
        ],
    )
    out.write(f"{vals.size} values x {args.points} points\n")
    _wrote(out, folder, "bifurcation")
    if not args.no_png:
        with _png(folder, out, "bifurcation", (8, 5)) as (fig, ax):
            ax.plot(np.repeat(vals, args.points), b.theta.ravel(), ",k")
            ax.set(
                xlabel=args.parameter,
                ylabel="theta at t = k T [rad]",
                ylim=(-math.pi, math.pi),
                title="bifurcation diagram of the driven pendulum",
            )
    return 0


def cmd_lyapunov(args, out):
    pendula, drive, folder = _setup(args)
    th0 = np.asarray(args.theta0, dtype=float)
    r = pendula.lyapunov(th0, args.omega0, periods=args.periods, orbits=args.orbits, **_shared(args, drive))
    _save(
        folder,
        "lyapunov",
        dict(theta0=th0, exponents=r.exponents, errors=r.errors),
        ["theta0_rad", "lambda1", "lambda1_err", "lambda2", "lambda2_err"],
        [[data(t), data(e[0]), data(s[0]), data(e[1]), data(s[1])] for t, e, s in zip(th0, r.exponents, r.errors)],
    )
    for t, e, s in zip(th0, r.exponents, r.errors):
        out.write(f"theta0 = {t:.6g}: lambda1 = {e[0]:.4g} +- {s[0]:.2g} 1/s, lambda2 = {e[1]:.4g} +- {s[1]:.2g} 1/s\n")
    _wrote(out, folder, "lyapunov")
    if not args.no_png:
        with _png(folder, out, "lyapunov", (6, 4)) as (fig, ax):
            ax.errorbar(th0, r.exponents[:, 0], yerr=r.errors[:, 0], fmt="o", label="lambda1")
            ax.errorbar(th0, r.exponents[:, 1], yerr=r.errors[:, 1], fmt="s", label="lambda2")
            ax.axhline(0, color="0.7", lw=0.8)
            ax.set(xlabel="theta0 [rad]", ylabel="exponent [1/s]", title="Lyapunov exponents")
            ax.legend()
    return 0


def cmd_basins(args, out):
    pendula, drive, folder = _setup(args)
    th = _grid(args.theta0, angle, "--theta0")
    om = _grid(args.omega0, angular_velocity, "--omega0")
    g = pendula.basins(th[:, None], om[None, :], nmax=args.nmax, **_shared(args, drive))
    tt, oo = np.meshgrid(th, om, indexing="ij")
    _save(
        folder,
        "basins",
        dict(
            theta0=th,
            omega0=om,
            labels=g.labels,
            period=g.period,
            winding=g.winding,
            **{"attractor_" + k: v for k, v in g.attractors.items()},
        ),
        ["theta0_rad", "omega0_rad_per_s", "label", "period", "winding"],
        [
            [data(a), data(b), int(c), int(d), int(e)]
            for a, b, c, d, e in zip(tt.ravel(), oo.ravel(), g.labels.ravel(), g.period.ravel(), g.winding.ravel())
        ],
    )
    out.write(
        f"{g.labels.size} starts, {len(g.attractors['period'])} attractors, "
        f"{int((g.labels == 0).sum())} unsettled (label 0)\n"
    )
    _wrote(out, folder, "basins")
    if not args.no_png:
        with _png(folder, out, "basins", (6, 5)) as (fig, ax):
            im = ax.pcolormesh(th, om, g.labels.T, shading="nearest", cmap="tab20")
            fig.colorbar(im, ax=ax, label="attractor label (0: unsettled)")
            ax.set(xlabel="theta0 [rad]", ylabel="Omega0 [rad/s]", title="basins of attraction")
    return 0


COMMANDS = {"poincare": cmd_poincare, "bifurcation": cmd_bifurcation, "lyapunov": cmd_lyapunov, "basins": cmd_basins}
