"""The result of a fit (``fit_period``, ``fit_motion``): estimates, standard
errors, covariance, intervals, goodness of fit, a table and a figure.

The numbers are computed by the fit functions (pendula.fit); this module only
holds and shows them.  pandas and matplotlib are imported when a conversion
or a figure is asked for.
"""

import math

import numpy as np

_UNITS = {
    "w0": "1/s",
    "g": "m/s^2",
    "length": "m",
    "gamma": "1/s",
    "theta0": "rad",
    "omega0": "rad/s",
    "theta_offset": "rad",
    "omega_offset": "rad/s",
}


def _optional(module, extra, what):
    """Import an optional module or raise ImportError naming the extra."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise ImportError(
            f"FitResult.{what} needs {module.split('.')[0]}, an optional dependency: pip install 'pendula[{extra}]'"
        ) from None


class FitResult:
    """Estimates of a pendulum fit with their uncertainties.

    Built by :func:`pendula.fit_period` and :func:`pendula.fit_motion`; not
    meant to be constructed by hand.

    Parameters
    ----------
    values : ndarray
        The estimates, in the order of ``names``.
    model : callable
        The fitted model as a function of amplitudes (period fits) or times
        (motion fits); called by :meth:`model`.
    kind, names, covariance, sigma_known, dof, chi2, confidence, residuals, data, residuals_omega, small_angle, info
        The attributes of the same names.

    Attributes
    ----------
    kind : str
        ``"period"`` or ``"motion"``.
    names : tuple of str
        Parameter names, fitted first (e.g. ``w0``, ``gamma``, ``theta0``),
        then derived ones (``g`` or ``length``).
    estimates, stderr : dict
        Name -> estimate and its standard error (units: ``units``).
    units : dict
        Name -> unit.
    covariance, correlation : ndarray
        Over ``names`` (derived parameters by the delta method).
    confidence : float
        Level of ``intervals`` (0.95 by default).
    interval_kind : str
        ``"normal"`` when the uncertainties of the data were given (the
        covariance is then known), ``"t"`` (Student's t with ``dof`` degrees
        of freedom) when they were estimated from the scatter of the residuals.
    intervals : dict
        Name -> (low, high) confidence interval.
    chi2, dof, reduced_chi2, pvalue : float, int, float, float
        Chi-square of the weighted residuals, degrees of freedom (data minus
        fitted parameters), chi2/dof and the probability of a chi-square at
        least as large (goodness of fit; NaN when the uncertainties were not
        given: the scatter then defines them, chi2 is the plain sum of squared
        residuals and reduced_chi2 the estimated noise variance).
    sigma_known : bool
        The data's uncertainties were given.
    residuals : ndarray
        Data minus model (periods in s, or angles in rad).
    residuals_omega : ndarray or None
        Angular-velocity data minus model (rad/s) for a motion fit with omega.
    small_angle : dict
        Period fits: what the small-angle formula T = 2 pi sqrt(l/g) gives
        (``w0`` overall and per point, and ``g`` or ``length`` when those
        apply). Motion fits: empty.
    data : dict
        The data fitted (arrays), for the figure and ``to_pandas("data")``.
    info : dict
        Engine details (iterations, evaluations, loss, integrator, message).

    Examples
    --------
    >>> import numpy as np, pendula
    >>> th = np.radians([10.0, 60.0, 120.0])
    >>> r = pendula.fit_period(th, pendula.period(th, w0=2.0), sigma_period=1e-3, g=9.81)
    >>> r.names, round(r["length"], 6), r.interval_kind
    (('w0', 'length'), 2.4525, 'normal')
    """

    def __init__(
        self,
        *,
        kind,
        names,
        values,
        covariance,
        sigma_known,
        dof,
        chi2,
        confidence,
        residuals,
        data,
        model,
        residuals_omega=None,
        small_angle=None,
        info=None,
    ):
        from scipy import stats

        self.kind = kind
        self.names = tuple(names)
        values = np.asarray(values, dtype=float)
        cov = np.asarray(covariance, dtype=float)
        self.covariance = cov
        se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
        scale = np.outer(se, se)
        with np.errstate(invalid="ignore", divide="ignore"):
            # a parameter with a zero standard error (exact data) is uncorrelated
            self.correlation = np.where(scale > 0, cov / np.where(scale > 0, scale, 1.0), np.eye(se.size))
        self.estimates = dict(zip(self.names, values.tolist()))
        self.stderr = dict(zip(self.names, se.tolist()))
        self.units = {n: _UNITS.get(n, "") for n in self.names}
        self.sigma_known = bool(sigma_known)
        self.dof = int(dof)
        self.chi2 = float(chi2)
        self.reduced_chi2 = self.chi2 / self.dof if self.dof > 0 else math.nan
        self.pvalue = float(stats.chi2.sf(self.chi2, self.dof)) if self.sigma_known and self.dof > 0 else math.nan
        self.confidence = float(confidence)
        q = 0.5 + 0.5 * self.confidence
        if self.sigma_known:
            self.interval_kind, z = "normal", float(stats.norm.ppf(q))
        else:
            self.interval_kind, z = "t", float(stats.t.ppf(q, max(self.dof, 1)))
        self.intervals = {n: (v - z * s, v + z * s) for n, v, s in zip(self.names, values, se)}
        self.residuals = np.asarray(residuals, dtype=float)
        self.residuals_omega = None if residuals_omega is None else np.asarray(residuals_omega, dtype=float)
        self.small_angle = dict(small_angle or {})
        self.data = data
        self.info = dict(info or {})
        self._model = model

    def model(self, x):
        """The fitted model at x.

        Parameters
        ----------
        x : array_like
            Amplitudes [rad] (period fits) or times [s] (motion fits; not
            before the fit's ``t_ref`` when damped).

        Returns
        -------
        ndarray
            The period [s] at each amplitude, or the angle theta [rad] at
            each time (with the sensor offset when one was fitted).

        Examples
        --------
        >>> import numpy as np, pendula
        >>> th = np.radians([10.0, 60.0, 120.0])
        >>> r = pendula.fit_period(th, pendula.period(th, w0=2.0), sigma_period=1e-3)
        >>> np.round(r.model([0.0, np.pi / 2]), 6)     # 2 pi/w0 and 4 K(1/2)/w0
        array([3.141593, 3.708149])
        """
        return self._model(np.asarray(x, dtype=float))

    def __getitem__(self, name):
        return self.estimates[name]

    def __repr__(self):
        head = (
            f"FitResult({self.kind} fit: {np.size(self.residuals)} points, chi2 = {self.chi2:.4g}, "
            f"dof = {self.dof}, chi2/dof = {self.reduced_chi2:.4g}"
            + (f", p = {self.pvalue:.3g}" if self.sigma_known else ", uncertainties from the scatter")
            + ")"
        )
        pct = f"{100 * self.confidence:g}%"
        rows = [
            f"  {'parameter':<13}{'estimate':>16}{'std error':>12}   {pct + ' interval (' + self.interval_kind + ')':<34}unit"
        ]
        for n in self.names:
            lo, hi = self.intervals[n]
            rows.append(
                f"  {n:<13}{self.estimates[n]:>16.10g}{self.stderr[n]:>12.3g}   [{lo:.8g}, {hi:.8g}]".ljust(33 + 44)
                + f" {self.units[n]}"
            )
        sa = self.small_angle
        if sa:
            key = "g" if "g" in sa else ("length" if "length" in sa else "w0")
            rows.append(f"  small-angle formula T = 2 pi/w0 would give {key} = {sa[key]:.6g} {_UNITS[key]}")
        return "\n".join([head] + rows)

    def to_pandas(self, what="parameters"):
        """The estimates (or the data with model and residuals) as a DataFrame.

        Parameters
        ----------
        what : {"parameters", "data"}
            ``"parameters"``: one row per parameter, columns estimate, stderr,
            ci_low, ci_high, unit; ``attrs`` hold chi2, dof, reduced_chi2,
            pvalue, confidence and interval_kind.  ``"data"``: the data
            (theta0 and period, or t and theta [and omega]) with the model and
            the residuals.

        Returns
        -------
        pandas.DataFrame
            The table asked for (see ``what``).

        Raises
        ------
        ValueError
            For another ``what``.
        ImportError
            When pandas (the optional extra ``tables``) is not installed.

        Examples
        --------
        >>> import numpy as np, pendula
        >>> th = np.radians([10.0, 40.0, 80.0, 120.0])
        >>> T = pendula.period(th, w0=3.6)
        >>> r = pendula.fit_period(th, T, sigma_period=1e-3, length=0.75)
        >>> df = r.to_pandas()
        >>> list(df.index), list(df.columns)
        (['w0', 'g'], ['estimate', 'stderr', 'ci_low', 'ci_high', 'unit'])
        """
        pd = _optional("pandas", "tables", "to_pandas")
        if what == "parameters":
            df = pd.DataFrame(
                {
                    "estimate": [self.estimates[n] for n in self.names],
                    "stderr": [self.stderr[n] for n in self.names],
                    "ci_low": [self.intervals[n][0] for n in self.names],
                    "ci_high": [self.intervals[n][1] for n in self.names],
                    "unit": [self.units[n] for n in self.names],
                },
                index=pd.Index(self.names, name="parameter"),
            )
            df.attrs.update(
                kind=self.kind,
                chi2=self.chi2,
                dof=self.dof,
                reduced_chi2=self.reduced_chi2,
                pvalue=self.pvalue,
                confidence=self.confidence,
                interval_kind=self.interval_kind,
            )
            return df
        if what == "data":
            cols = {k: np.asarray(v) for k, v in self.data.items() if v is not None and k != "sigma_effective"}
            x = cols["theta0"] if self.kind == "period" else cols["t"]
            name = "period" if self.kind == "period" else "theta"
            cols[name + "_model"] = self.model(x)
            cols["residual"] = self.residuals
            if self.residuals_omega is not None:
                cols["residual_omega"] = self.residuals_omega
            return pd.DataFrame(cols)
        raise ValueError(f"what must be 'parameters' or 'data', not {what!r}")

    def plot(self, path=None, *, figsize=(7.0, 5.5)):
        """One figure of the fit: data with error bars and the model above, the
        residuals below; period fits add the small-angle line T = 2 pi/w0.

        Parameters
        ----------
        path : str or path-like, optional
            Also save the figure there (PNG by its suffix).
        figsize : tuple, optional
            Inches.

        Returns
        -------
        matplotlib.figure.Figure
            Two Axes: the data and model above, the residuals below.

        Raises
        ------
        ImportError
            When matplotlib is not installed.

        Examples
        --------
        >>> import numpy as np, pendula
        >>> th = np.radians([10.0, 40.0, 80.0, 120.0])
        >>> r = pendula.fit_period(th, pendula.period(th, w0=3.6), sigma_period=1e-3)
        >>> len(r.plot().axes)
        2
        """
        figure_cls = _optional("matplotlib.figure", "examples", "plot").Figure
        fig = figure_cls(figsize=figsize)
        top, bottom = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 1]})
        if self.kind == "period":
            self._plot_period(top, bottom)
        else:
            self._plot_motion(top, bottom)
        bottom.axhline(0.0, color="0.5", lw=0.8)
        fig.tight_layout()
        if path is not None:
            fig.savefig(path, dpi=120)
        return fig

    def _plot_period(self, top, bottom):
        th, per = np.asarray(self.data["theta0"]), np.asarray(self.data["period"])
        sp, st = self.data.get("sigma_period"), self.data.get("sigma_theta0")
        deg = np.degrees
        top.errorbar(
            deg(th), per, yerr=sp, xerr=None if st is None else deg(st), fmt="o", ms=4, color="k", label="measured"
        )
        grid = np.linspace(0.0, max(float(np.max(np.abs(th))), 0.1), 400)
        top.plot(deg(grid), self.model(grid), color="C0", label=f"exact, w0 = {self.estimates['w0']:.6g} 1/s")
        top.axhline(
            2 * np.pi / self.estimates["w0"], color="0.4", ls=":", label="this pendulum's small-angle period 2π/w0"
        )
        w_sa = self.small_angle["w0"]
        top.axhline(2 * np.pi / w_sa, color="C3", ls="--", label=f"small-angle fit, T = 2π/w0 with w0 = {w_sa:.5g} 1/s")
        top.set_ylabel("period T  (s)")
        top.legend(loc="upper left", fontsize=8)
        # residual error bars: the effective sigma (period and amplitude errors together)
        bottom.errorbar(deg(th), self.residuals, yerr=self.data.get("sigma_effective"), fmt="o", ms=4, color="k")
        bottom.set_xlabel("amplitude θ0  (deg)")
        bottom.set_ylabel("residual (s)")

    def _plot_motion(self, top, bottom):
        t, th = np.asarray(self.data["t"]), np.asarray(self.data["theta"])
        top.plot(t, th, ".", ms=3, color="k", label="measured θ")
        dense = np.linspace(t[0], t[-1], max(2000, 4 * t.size))
        top.plot(dense, self.model(dense), color="C0", lw=1, label="fit")
        top.set_ylabel("θ  (rad)")
        top.legend(loc="upper right", fontsize=8)
        bottom.plot(t, self.residuals, ".", ms=3, color="k")
        bottom.set_xlabel("time t  (s)")
        bottom.set_ylabel("residual (rad)")
