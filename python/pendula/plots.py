"""Plot helpers shared by the figures, the scenes and the command line: the
work-precision diagram of a tradeoff table and the basin map of a damped sweep.

They draw with matplotlib's object API on an Agg canvas (no pyplot state), like
:mod:`pendula.figures`, which re-exports them.
"""

from pathlib import Path

import numpy as np

DPI = 110


def _figure(nrows=1, ncols=1, size=(7.0, 4.6), **kw):
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, dpi=DPI, layout="constrained")
    axs = fig.subplots(nrows, ncols, squeeze=False, **kw)
    return fig, axs


_TRADEOFF_KEYS = {
    "model": ("model", "method", "name"),
    "setting": ("setting", "settings", "parameter", "param"),
    "error": ("sup_error", "error", "err", "max_error"),
    "time": ("wall_time", "time", "seconds", "wall", "wall_s"),
    "evals": ("rhs_evals", "evaluations", "nfev", "rhs_evaluations", "evals"),
}


def tradeoff_rows(table):
    """Rows (model, setting, sup error [rad], wall time [s], rhs evaluations) from pendula.tradeoff's table.

    Accepts a list of dicts or objects, a dict of columns, or an object with
    ``rows``/``records``; the column names are matched loosely.
    """
    for attr in ("rows", "records", "table"):
        if not isinstance(table, (list, tuple, dict)) and hasattr(table, attr):
            table = getattr(table, attr)
            break
    if isinstance(table, dict):  # dict of columns
        n = len(next(iter(table.values())))
        table = [{k: v[i] for k, v in table.items()} for i in range(n)]

    def pick(rec, key):
        for name in _TRADEOFF_KEYS[key]:
            if isinstance(rec, dict) and name in rec:
                return rec[name]
            if not isinstance(rec, dict) and hasattr(rec, name):
                return getattr(rec, name)
        if isinstance(rec, (list, tuple)):
            return rec[list(_TRADEOFF_KEYS).index(key)]
        return None

    rows = []
    for rec in table:
        evals = pick(rec, "evals")
        rows.append(
            (
                str(pick(rec, "model")),
                str(pick(rec, "setting")),
                float(pick(rec, "error")),
                float(pick(rec, "time")),
                "" if evals is None else int(evals),
            )
        )
    return rows


def work_precision_plot(rows, path, title="Work-precision", tol=None, note=None, ax=None):
    """Log-log sup error (rad) against wall time (s), one line per model; returns the path.

    ``rows`` as from :func:`tradeoff_rows`; ``tol`` draws the tolerance line,
    ``note`` (e.g. how the reference was made) goes under the title.  ``ax``:
    draw into these matplotlib axes instead of a new figure (then ``path``
    may be None: nothing is saved, the caller owns the figure).
    """
    fig = None
    if ax is None:
        fig, axs = _figure(size=(8.0, 5.4))
        ax = axs[0, 0]
    models = []
    for r in rows:
        if r[0] not in models:
            models.append(r[0])
    markers = "osD^v<>ph*"
    floor = 1e-17
    for i, m in enumerate(models):
        pts = [(r[3], max(r[2], floor)) for r in rows if r[0] == m]  # in setting order
        x, y = zip(*pts)
        ax.loglog(
            x,
            y,
            marker=markers[i % len(markers)],
            lw=1.3,
            ls="-" if len(pts) > 1 else "none",
            label=m if len(pts) > 1 else f"{m} (closed form)",
        )
    if tol is not None:
        ax.axhline(tol, color="grey", ls=":", label=f"tol = {tol:g} rad")
    ax.set_title(title, fontsize=10.5)
    if note:
        import textwrap

        ax.text(
            0.01,
            0.01,
            "\n".join(textwrap.wrap(note, 95)),
            transform=ax.transAxes,
            fontsize=7.5,
            va="bottom",
            ha="left",
            color="0.3",
        )
    ax.set(xlabel="wall time per solve  (s)", ylabel="sup over the grid of max(|Δθ|, |ΔΩ|/w0)  (rad)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    if path is None:
        return None
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    (fig if fig is not None else ax.figure).savefig(path, dpi=DPI)
    return path


def basin_map_plot(theta0, omega0, well, path, w0=None, gamma=None):
    """The basin map of a damped sweep: each start (theta0 [rad], omega0 [rad/s])
    coloured by the well 2 pi k its motion ends in (``SweepResult.well``,
    shape (len(theta0), len(omega0))); returns the path of the PNG.  Starts
    without a well (``WELL_NONE``: failed, or not settled at t[-1]) are left
    blank, never coloured as a well."""
    from matplotlib.colors import BoundaryNorm

    from ._defaults import WELL_NONE

    fig, axs = _figure(size=(7.0, 5.4))
    ax = axs[0, 0]
    well = np.ma.masked_equal(np.asarray(well), WELL_NONE)
    lo, hi = (int(well.min()), int(well.max())) if well.count() else (0, 0)
    ks = np.arange(lo, hi + 2) - 0.5
    mesh = ax.pcolormesh(theta0, omega0, well.T, shading="nearest", cmap="coolwarm", norm=BoundaryNorm(ks, 256))
    fig.colorbar(mesh, ax=ax, ticks=np.arange(lo, hi + 1), label="well k: ends near θ = 2πk (full turns made)")
    sub = "" if w0 is None else f"  (w0 = {w0:.4g} 1/s, γ = {gamma:.4g} 1/s)"
    ax.set(xlabel="θ0  (rad)", ylabel="Ω0  (rad/s)", title="Basin map: where each start comes to rest" + sub)
    path = Path(path)
    fig.savefig(path, dpi=DPI)
    return path


__all__ = ["tradeoff_rows", "work_precision_plot", "basin_map_plot"]
