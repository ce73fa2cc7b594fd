"""The commands of the text's pendulum: figures, period, solve, tradeoff and sweep."""

import argparse
import sys
from pathlib import Path

import numpy as np

from ._cli_common import (
    MODELS,
    PROG,
    CliError,
    check_output,
    field,
    fmt_table,
    make_parent,
    need_matplotlib,
    output_file,
    scene_of,
    w0_of,
    write_csv,
)
from ._cli_values import angle, angular_velocity, data, grid_times
from ._cli_values import finite as _finite
from ._codes import EVENT_TURNING, EVENT_ZERO

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
    check_output(args.out, "--out", args, folder=True)
    need_matplotlib("drawing the figures")
    make_parent(Path(args.out) / "x", args)
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
        args.csv = output_file(args.csv, "--csv", args, "period.csv")
    w0 = w0_of(args)
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
    out.write(fmt_table(header, rows) + "\n")
    if args.csv:
        make_parent(args.csv, args)
        out.write(f"wrote {write_csv(args.csv, header, rows)}\n")
    return 0


_SERIES = ("state", "theta", "energy")  # the wants that give theta at every output time


def cmd_solve(args, out):
    import pendula

    if args.csv:
        args.csv = output_file(args.csv, "--csv", args, "solve.csv")
    if args.png:
        args.png = output_file(args.png, "--png", args, "solve.png")
    if args.png:
        if args.want not in _SERIES:
            raise CliError(f"--png draws a time series: give --want {', '.join(_SERIES)}, not {args.want}")
        need_matplotlib("--png")
    scene = scene_of(args, want=args.want)
    kw = {"model": args.model} if args.model else {}
    res = pendula.solve(scene, **kw)
    out.write(f"model: {field(res, 'model')}\n")
    out.write(f"reason: {field(res, 'reason')}\n")
    out.write(f"error estimate: {data(field(res, 'error_estimate'))} rad (tolerance {data(args.tol)} rad)\n")
    cost = field(res, "cost")
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
        make_parent(args.csv, args)
        out.write(f"wrote {len(rows)} rows to {write_csv(args.csv, header, rows)}\n")
    elif len(rows) > 1 or args.want in ("events",):
        show = rows if len(rows) <= 12 else rows[:6] + [["..."] * len(header)] + rows[-5:]
        out.write(fmt_table(header, show) + "\n")
    if args.png:
        from .motion_plots import plot_motion
        from .plots import DPI

        make_parent(args.png, args)
        plot_motion(res, kind="time" if res.omega is None else "both").savefig(args.png, dpi=DPI)
        out.write(f"wrote {args.png}\n")
    return 0


def cmd_tradeoff(args, out):
    import pendula

    fn = getattr(pendula, "tradeoff", None)
    if fn is None:
        raise NotImplementedError("pendula.tradeoff (the scenes module) is not available in this build")
    if args.csv:
        args.csv = output_file(args.csv, "--csv", args, "tradeoff.csv")
    if args.png:
        args.png = output_file(args.png, "--png", args, "tradeoff.png")
    scene = scene_of(args)
    kw = {"repeat": args.repeat}
    if args.models:
        kw["models"] = [m.strip() for m in args.models.split(",") if m.strip()]
        bad = [m for m in kw["models"] if m not in MODELS]
        if bad:
            raise CliError(f"--models: unknown model(s) {', '.join(bad)}; known: {', '.join(MODELS)}")
    table = fn(scene, **kw)
    rows = [[r[0], _exact(r[1]), _exact(r[2]), _exact(r[3]), _exact(r[4])] for r in _tradeoff_rows(table)]
    header = ["model", "setting", "sup_error_rad", "wall_time_s", "rhs_evaluations"]
    out.write(fmt_table(header, rows) + "\n")
    if args.csv:
        make_parent(args.csv, args)
        out.write(f"wrote {write_csv(args.csv, header, rows)}\n")
    if args.png:
        make_parent(args.png, args)
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
    check_output(args.out, "--out", args, folder=True)
    w0 = w0_of(args)
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
    make_parent(Path(args.out) / "x", args)
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
    write_csv(
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
