"""The text's figures, redrawn from the library, and the figures the text lacks.

Every function here takes an output folder (created if missing) and returns
the list of paths it wrote.  They draw with matplotlib's object API on an Agg
canvas (``matplotlib.figure.Figure``), so no display, no pyplot state and no
backend switch are needed: they work on a headless machine and from threads.

Parameters are the text's throughout: g = 9.8 m/s^2, l = 4.9 m, so
w0 = sqrt(g/l) = sqrt(2) 1/s.  The figure numbers follow the text
("Pendulo - Solucoes Gerais"); the text's figures relied on colours named in
captions, ours carry legends, axis units and file names that say what they
show.  Errata of the text's listings are not copied (see each docstring).

``make_figures(out_dir, quick=False)`` draws them all and reports which could
not be drawn because a part of the library is missing from this build (it
never writes a placeholder).  ``quick=True`` uses fewer points, for tests.

The drawing code is split by concern: ``_plotting.text_figures`` (the text's figures
3-15), ``_plotting.extra_figures`` (A1-A5, what the text lacks) and ``_plotting.base``
(the text's parameters and the plumbing they share); this module is the
registry and the entry points, and re-exports every figure function.
"""

from ._plotting.base import _TEXT_H, _TEXT_TEND, LENGTH, MASS, FigureUnavailable, G  # noqa: F401 (re-exported)
from ._plotting.extra_figures import (
    figA1_underdamped_linear,
    figA2_phase_portrait,
    figA3_period_vs_energy,
    figA4_work_precision,
    figA5_text_listing_error,
)
from ._plotting.text_figures import (
    fig03_complete_elliptic_K,
    fig04_period_vs_amplitude,
    fig05_theta_small_theta0,
    fig06_theta_medium_theta0,
    fig07_theta_large_theta0,
    fig08_theta_all_theta0,
    fig09_launch_speed_series,
    fig10_overdamped_gamma3,
    fig11_overdamped_gamma5,
    fig12_overdamped_phase_plane,
    fig13_critical_damping,
    fig14_nonlinear_damped,
    fig15_nonlinear_damped_phase_plane,
)
from .plots import DPI, _figure, basin_map_plot, tradeoff_rows, work_precision_plot  # noqa: F401 (re-exported)

# --------------------------------------------------------------------------

FIGURES = [
    ("fig03", fig03_complete_elliptic_K),
    ("fig04", fig04_period_vs_amplitude),
    ("fig05", fig05_theta_small_theta0),
    ("fig06", fig06_theta_medium_theta0),
    ("fig07", fig07_theta_large_theta0),
    ("fig08", fig08_theta_all_theta0),
    ("fig09", fig09_launch_speed_series),
    ("fig10", fig10_overdamped_gamma3),
    ("fig11", fig11_overdamped_gamma5),
    ("fig12", fig12_overdamped_phase_plane),
    ("fig13", fig13_critical_damping),
    ("fig14", fig14_nonlinear_damped),
    ("fig15", fig15_nonlinear_damped_phase_plane),
    ("figA1", figA1_underdamped_linear),
    ("figA2", figA2_phase_portrait),
    ("figA3", figA3_period_vs_energy),
    ("figA4", figA4_work_precision),
    ("figA5", figA5_text_listing_error),
]


def make_figures(out_dir, quick=False, only=None):
    """Draw every figure (or those whose key is in ``only``) into ``out_dir``.

    Returns ``(written, missing)``: the list of paths written and a dict
    {figure key: reason} for figures this build cannot draw (a part of the
    library missing) or that failed (reason starting with "FAILED:"); no
    placeholder is ever written for those.
    """
    keys = {k for k, _ in FIGURES}
    if only is not None:
        bad = sorted(set(only) - keys)
        if bad:
            raise ValueError(f"unknown figure key(s) {bad}; known: {sorted(keys)}")
    written, missing = [], {}
    for key, fn in FIGURES:
        if only is not None and key not in only:
            continue
        try:
            written.extend(fn(out_dir, quick=quick))
        except FigureUnavailable as exc:
            missing[key] = str(exc)
        except Exception as exc:  # one broken figure must not cost the others
            missing[key] = f"FAILED: {type(exc).__name__}: {exc}"
    return written, missing


def figures_main(argv, only, description, quick_help="fewer points per curve (fast)"):
    """The command line of the figure scripts (examples/python/figures_*.py):
    --out DIR and --quick, draw the figures whose keys are in ``only``, report
    each file written and each figure not drawn; SystemExit if one failed."""
    import argparse

    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--out", default=".", help="folder for the PNG files (default: .)")
    ap.add_argument("--quick", action="store_true", help=quick_help)
    args = ap.parse_args(argv)
    written, missing = make_figures(args.out, quick=args.quick, only=only)
    for path in written:
        print(f"wrote {path}")
    for key, why in missing.items():
        print(f"not drawn: {key}: {why}")
    failed = [key for key, why in missing.items() if why.startswith("FAILED")]
    if failed:
        raise SystemExit(f"figure(s) failed: {', '.join(failed)}")


__all__ = ["make_figures", "figures_main", "FIGURES", "FigureUnavailable", "tradeoff_rows", "work_precision_plot"] + [
    fn.__name__ for _, fn in FIGURES
]
