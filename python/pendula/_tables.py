"""Compact reprs and pandas/xarray conversion for the result classes.

Why one module: every result (``IntegrationResult``, ``SceneResult``, the
batch results, ``SweepResult``, ``TradeoffTable``) holds the same kinds of
data -- series over the output times t, optionally with a batch shape in
front, plus per-state values -- so their reprs and their frames are built by
the same few functions here.

pandas and xarray are optional: they are imported only when a conversion is
asked for, and a missing one raises ImportError naming the package.

Frames: a single series is indexed by t; a batch is a long frame with a
MultiIndex (batch dimensions, t); per-state values (codes, model, ...) are
repeated along t.  Datasets: dims ``batch`` (one batch dimension) or
``batch_0``, ``batch_1``, ... (several), then ``t``; units in each
variable's ``attrs``.
"""

import importlib

import numpy as np

from ._codes import OK

UNITS = {
    "t": "s",
    "theta": "rad",
    "omega": "rad/s",
    "energy": "1/s^2",
    "period": "s",
    "error_estimate": "rad",
    "event_time_error": "s",
}
INPUT_UNITS = {
    "theta0": "rad",
    "omega0": "rad/s",
    "w0": "1/s",
    "gamma": "1/s",
    "h": "s",
    "tol": "rad",
    "rtol": "1",
    "atol": "1",
}
_REASON_CHARS = 100


def optional(name):
    """Import the optional package ``name`` or raise ImportError naming it."""
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        raise ImportError(
            f"this conversion needs the optional package {name!r}, which is not installed: pip install {name}"
        ) from exc


# ------------------------------------------------------------------ reprs


def span(a, unit=""):
    """'[lo, hi] unit' of the finite values of a (or 'empty' / 'no finite values')."""
    if a is None:
        return "None"
    a = np.asarray(a, dtype=float)
    fin = a[np.isfinite(a)]
    if a.size == 0:
        return "empty"
    text = f"[{fin.min():.4g}, {fin.max():.4g}]" if fin.size else "no finite values"
    if fin.size < a.size:
        text += f" ({a.size - fin.size} non-finite)"
    return f"{text} {unit}".rstrip()


def series(t, fields):
    """One line: 't[n] in [..] s, theta in [..] rad, ...' for the fields present (name -> array)."""
    parts = [] if t is None else [f"t[{np.size(t)}] in {span(t, UNITS['t'])}"]
    parts += [f"{name} in {span(v, UNITS.get(name, ''))}" for name, v in fields.items() if v is not None]
    return ", ".join(parts)


def codes_line(codes, message=""):
    """'codes: n ok, m failed (first: message)'."""
    codes = np.asarray(codes)
    bad = int(np.count_nonzero(codes != OK))
    line = f"codes: {codes.size - bad} ok, {bad} failed"
    if bad and message:
        line += f" ({clip(message)})"
    return line


def clip(text, n=_REASON_CHARS):
    """text cut to n characters (an ellipsis says it was cut)."""
    text = str(text)
    return text if len(text) <= n else text[: n - 3] + "..."


def block(name, lines):
    """'Name(first line\\n  more lines)': the repr layout of every result."""
    lines = [ln for ln in lines if ln]
    return f"{name}(" + "\n  ".join(lines) + ")"


def counts(names):
    """'rk4: 2, exact: 1' for an array of names ('' = failed, left out)."""
    vals, n = np.unique(np.asarray(names, dtype=str).reshape(-1), return_counts=True)
    return ", ".join(f"{v}: {k}" for v, k in zip(vals, n) if v) or "none"


# ------------------------------------------------------------ conversions


def batch_dims(shape):
    """Dimension names of a batch shape: ('batch',) or ('batch_0', 'batch_1', ...)."""
    if len(shape) == 1:
        return ("batch",)
    return tuple(f"batch_{i}" for i in range(len(shape)))


def frame(t, fields, shape=(), per_state=None, attrs=None, coords=None):
    """pandas DataFrame of ``fields`` (name -> array of shape shape + (n_t,), or
    shape alone when t is None), indexed by t, or by (batch dims..., t) for a
    batch; ``per_state`` and ``coords`` (the per-state inputs: name -> array
    of shape ``shape``) repeated along t."""
    pd = optional("pandas")
    fields = {k: np.asarray(v) for k, v in fields.items() if v is not None}
    per_state = {k: np.asarray(v) for k, v in (per_state or {}).items() if v is not None}
    per_state.update({k: np.broadcast_to(np.asarray(v), shape) for k, v in (coords or {}).items()})
    n_t = 1 if t is None else np.size(t)
    levels = [np.arange(n) for n in shape] + ([] if t is None else [np.asarray(t, dtype=float)])
    names = list(batch_dims(shape)) + ([] if t is None else ["t"])
    if len(levels) == 1:
        index = pd.Index(levels[0], name=names[0])
    elif levels:
        index = pd.MultiIndex.from_product(levels, names=names)
    else:
        index = pd.RangeIndex(1)
    data = {k: v.reshape(-1) for k, v in fields.items()}
    data.update({k: np.repeat(v.reshape(-1), n_t) for k, v in per_state.items()})
    out = pd.DataFrame(data, index=index)
    units = dict(UNITS, **INPUT_UNITS)
    out.attrs.update(attrs or {}, units={k: units[k] for k in data if k in units})
    return out


def dataset(t, fields, shape=(), per_state=None, attrs=None, coords=None):
    """xarray Dataset of ``fields`` with dims (batch dims..., t) and ``per_state``
    with the batch dims; t is a coordinate [s], and so is each per-state input
    of ``coords`` (theta0, w0, ...: non-index coordinates over the batch dims)."""
    xr = optional("xarray")
    dims = batch_dims(shape)
    series_dims = dims + (() if t is None else ("t",))
    data = {}
    for k, v in fields.items():
        if v is not None:
            data[k] = (series_dims, np.asarray(v), {"units": UNITS[k]} if k in UNITS else {})
    for k, v in (per_state or {}).items():
        if v is not None:
            data[k] = (dims, np.asarray(v), {"units": UNITS[k]} if k in UNITS else {})
    inputs = coords or {}
    coords = {} if t is None else {"t": ("t", np.asarray(t, dtype=float), {"units": "s"})}
    coords.update({d: np.arange(n) for d, n in zip(dims, shape)})
    for k, v in inputs.items():
        coords[k] = (dims, np.broadcast_to(np.asarray(v), shape), {"units": INPUT_UNITS[k]} if k in INPUT_UNITS else {})
    return xr.Dataset(data, coords=coords, attrs=dict(attrs or {}))


class Tabular:
    """Mixin of the result classes: ``to_pandas`` and ``to_xarray`` from one
    description of the data, ``_table()`` -> dict(t, fields, shape, per_state, attrs)."""

    def to_pandas(self):
        """The result as a pandas DataFrame.

        Returns
        -------
        pandas.DataFrame
            One series: indexed by t [s], one column per quantity (theta [rad],
            omega [rad/s], energy [1/s^2], period [s], as the result holds
            them).  A batch: a long frame with a MultiIndex (``batch`` -- or
            ``batch_0``, ``batch_1``, ... for several batch dimensions -- then
            t; no t level when there is one value per state), and the
            per-state values (``code``; for scenes also model, error_estimate,
            tol_met) and inputs (theta0, omega0, w0, gamma, h or rtol, atol
            or tol) repeated along t.  ``attrs``: units and the result's
            summary values (method or model, ...).

        Raises
        ------
        ValueError
            For a result without a table (a scene's want "events": use
            ``events.to_pandas()``).
        ImportError
            When pandas (an optional dependency) is not installed.

        Examples
        --------
        >>> import pendula
        >>> r = pendula.rk4([0.0, 0.5, 1.0], 0.1, 0.0, 1.0, 0.0, h=0.01)
        >>> df = r.to_pandas()
        >>> df.index.name, list(df.columns), len(df)
        ('t', ['theta', 'omega'], 3)
        >>> b = pendula.rk4([0.0, 1.0], [0.1, 0.2, 0.3], 0.0, 1.0, 0.0, h=0.01).to_pandas()
        >>> list(b.index.names), list(b.columns)
        (['batch', 't'], ['theta', 'omega', 'code', 'theta0', 'omega0', 'w0', 'gamma', 'h'])
        """
        return frame(**self._table())

    def to_xarray(self):
        """The result as an xarray Dataset.

        Returns
        -------
        xarray.Dataset
            The quantities over dims (batch dims..., ``t``) -- ``batch`` or
            ``batch_0``, ``batch_1``, ...; no ``t`` when there is one value
            per state -- with units in each variable's ``attrs``; per-state
            values (``code``, ...) over the batch dims; coordinate t [s],
            and a batch's inputs (theta0, omega0, w0, gamma, h or rtol,
            atol or tol) as coordinates over the batch dims.

        Raises
        ------
        ValueError
            For a result without a table (a scene's want "events").
        ImportError
            When xarray (an optional dependency) is not installed.

        Examples
        --------
        >>> import pendula
        >>> r = pendula.rk4([0.0, 1.0], [0.1, 0.2, 0.3], 0.0, 1.0, 0.0, h=0.01)
        >>> ds = r.to_xarray()
        >>> dict(ds.sizes), ds["theta"].dims, ds["theta"].attrs["units"]
        ({'batch': 3, 't': 2}, ('batch', 't'), 'rad')
        >>> ds["theta0"].values.tolist()
        [0.1, 0.2, 0.3]
        """
        return dataset(**self._table())
