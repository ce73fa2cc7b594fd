"""Result objects: stable field types, compact reprs, pandas/xarray conversion,
and the tradeoff table (used steps, no duplicate runs, SciPy rows, errors
checked against an independent mpmath reference).
"""

import sys

import numpy as np
import pytest
import scene_grid

import pendula

pd = pytest.importorskip("pandas")  # requirements-dev.txt installs both
xr = pytest.importorskip("xarray")

W0 = np.sqrt(2.0)
T30 = np.linspace(0, 30, 601)  # the text's section 2.2 grid
REPR_CHARS = 800  # a few lines, whatever the size of the data


def _text_scene(**kw):
    return pendula.Scene(theta0=0.0, omega0=2.0, t=T30, mass=0.1, b=0.01, **kw)


# ------------------------------------------------------------ stable types


@pytest.mark.parametrize("want", ["state", "theta", "final", "energy"])
@pytest.mark.parametrize("t", [T30, 3.0, [3.0]])
def test_scene_result_series_are_always_1d_arrays(want, t):
    r = pendula.solve(pendula.Scene(theta0=1.0, t=t, gamma=0.1, want=want))
    n = 1 if want == "final" else np.size(t)
    assert isinstance(r.t, np.ndarray) and r.t.shape == (n,)
    for name in ("theta", "omega", "energy"):
        v = getattr(r, name)
        wanted = (name == "theta" or (name == "omega" and want != "theta")) if want != "energy" else True
        if wanted:
            assert isinstance(v, np.ndarray) and v.shape == (n,), (name, v)
        else:
            assert v is None, name
    assert r.t[-1] == np.atleast_1d(t)[-1]


def test_final_equals_the_last_point_of_the_history():
    full = pendula.solve(_text_scene(tol=1e-9))
    final = pendula.solve(_text_scene(tol=1e-9, want="final"))
    assert abs(final.theta[-1] - full.theta[-1]) <= 2e-9
    assert abs(final.omega[-1] - full.omega[-1]) <= 2e-9 * W0


def test_scene_batch_final_has_a_trailing_axis_of_one():
    r = pendula.solve(pendula.Scene([[0.1, 0.2, 0.3]], t=[0.0, 2.0], want="final"))
    assert r.theta.shape == r.omega.shape == r.t.shape == (1, 3, 1)
    one = pendula.solve(pendula.Scene(0.2, t=[0.0, 2.0], want="final"))
    assert r.theta[0, 1, -1] == one.theta[-1]


# ------------------------------------------------------------------- reprs


def _check_repr(obj, *facts):
    text = repr(obj)
    assert len(text) <= REPR_CHARS, (len(text), text)
    assert text.count("\n") <= 6, text
    for fact in facts:
        assert fact in text, (fact, text)
    return text


def test_integration_result_repr_is_compact():
    r = pendula.rk4(T30, 0.0, 2.0, W0, 0.1, 0.05)
    _check_repr(
        r,
        "IntegrationResult",
        "method='rk4'",
        "t[601] in [0, 30] s",
        f"theta in [{r.theta.min():.4g}, {r.theta.max():.4g}] rad",
        "steps=600",
        "rhs_evals=2400",
    )
    big = pendula.rk4(np.linspace(0, 30, 100_001), 0.0, 2.0, W0, 0.1, 0.05)
    assert len(repr(big)) <= REPR_CHARS


@pytest.mark.skipif(not pendula.have_cvode(), reason="events come from CVODE")
def test_events_repr_counts_the_kinds():
    r = pendula.cvode(T30, 0.0, 2.0, W0, 0.1, events=True)
    n_turn = int(np.sum(r.events.kind == pendula.TURNING_POINT))
    _check_repr(r.events, f"{r.events.t.size} events", f"{n_turn} turning points")
    _check_repr(r, "method='adams'", "events:")


def test_batch_repr_reports_codes_and_the_first_failure():
    r = pendula.rk4(T30, [0.1, 0.2], 0.0, [W0, 200.0], 0.0, 0.05)  # the second is unstable at h = 0.05
    _check_repr(
        r, "BatchIntegrationResult", "batch shape (2,)", "codes: 1 ok, 1 failed", "1 of 2 states failed", "h[1] = 0.05"
    )


def test_scene_result_repr_has_model_error_tol_and_cost():
    r = pendula.solve(_text_scene())
    _check_repr(
        r,
        "SceneResult",
        f"model={r.model!r}",
        f"error_estimate={r.error_estimate:.3g} rad",
        f"tol_met={r.tol_met}",
        "reason:",
        "t[601]",
        f"rhs_evals={r.cost['rhs_evals']}",
    )


def test_scene_batch_and_sweep_reprs():
    sb = pendula.solve(pendula.Scene([0.1, 3.0], t=T30))
    _check_repr(
        sb, "SceneBatchResult", "batch shape (2,)", "models: exact: 2", "tol met by 2 of 2", "codes: 2 ok, 0 failed"
    )
    sw = pendula.sweep([0.0, 10.0], np.linspace(0, 3, 4)[:, None], np.zeros(2)[None, :], w0=1.0)
    _check_repr(sw, "SweepResult", "want='final'", "batch shape (4, 2)", "codes: 8 ok")


def test_tradeoff_table_repr_and_str():
    table = pendula.tradeoff(
        pendula.Scene(0.5, t=np.linspace(0, 2, 21)),
        models=["exact", "rk4"],
        rk4_steps=[0.1, 0.05],
        repeat=1,
        scipy=False,
    )
    text = _check_repr(table, "TradeoffTable", "3 rows", "exact elliptic solution", "rk4: 2")
    assert "object at 0x" not in text
    lines = str(table).splitlines()
    assert lines[0].split()[:3] == ["model", "setting", "step_used_s"]
    assert [ln.split()[0] for ln in lines[1:4]] == ["exact", "rk4", "rk4"]


# ------------------------------------------------------------- conversions


def test_integration_result_to_pandas_and_xarray():
    r = pendula.rk4(T30, 0.0, 2.0, W0, 0.1, 0.05)
    df = r.to_pandas()
    assert df.index.name == "t" and list(df.columns) == ["theta", "omega"]
    np.testing.assert_array_equal(df.index.to_numpy(), r.t)
    np.testing.assert_array_equal(df["theta"].to_numpy(), r.theta)
    ds = r.to_xarray()
    np.testing.assert_array_equal(ds["omega"].values, r.omega)
    assert ds["theta"].attrs["units"] == "rad" and ds["t"].attrs["units"] == "s"


def test_batch_to_pandas_is_long_and_to_xarray_has_batch_dims():
    r = pendula.rk4(T30[:11], np.array([[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]]), 0.0, W0, 0.1, 0.05)
    df = r.to_pandas()
    assert df.index.names == ["batch_0", "batch_1", "t"] and len(df) == 6 * 11
    np.testing.assert_array_equal(df.loc[(1, 2)]["theta"].to_numpy(), r.theta[1, 2])
    ds = r.to_xarray()
    assert ds["theta"].dims == ("batch_0", "batch_1", "t") and ds["code"].dims == ("batch_0", "batch_1")
    np.testing.assert_array_equal(ds["theta"].values, r.theta)


def test_scene_results_convert_what_was_wanted():
    r = pendula.solve(_text_scene(want="energy"))
    df = r.to_pandas()
    assert "energy" in df.columns and df.attrs["model"] == r.model
    np.testing.assert_array_equal(df["energy"].to_numpy(), r.energy)
    final = pendula.solve(_text_scene(want="final")).to_xarray()
    assert dict(final.sizes) == {"t": 1} and float(final["t"][0]) == 30.0
    per = pendula.solve(pendula.Scene(1.0, want="period"))
    assert per.to_pandas()["period"].tolist() == [per.period]  # one row, as the batch forms
    assert float(per.to_xarray()["period"]) == per.period
    with pytest.raises(ValueError, match="events"):
        pendula.solve(pendula.Scene(1.0, t=[0.0, 10.0], want="events")).to_pandas()
    sb = pendula.solve(pendula.Scene([0.1, 3.0], t=T30[:5]))
    ds = sb.to_xarray()
    np.testing.assert_array_equal(ds["theta"].values, sb.theta)
    assert list(ds["model"].values) == list(sb.model)
    assert len(sb.to_pandas()) == 10


def test_sweep_and_tradeoff_to_pandas():
    sw = pendula.sweep(T30[:5], np.array([0.1, 0.2]), w0=1.0, h=0.01, want="trajectory")
    ds = sw.to_xarray()
    np.testing.assert_array_equal(ds["theta"].values, sw.theta)
    # the inputs are physical coordinates of the batch
    assert ds["theta0"].values.tolist() == [0.1, 0.2] and ds["w0"].attrs["units"] == "1/s"
    assert ds["h"].values.tolist() == [0.01, 0.01]
    assert sw.to_pandas().index.names == ["batch", "t"]
    per = pendula.sweep(None, np.array([0.1, 0.2]), want="period").to_pandas()
    assert list(per.columns) == ["period", "code", "theta0", "omega0", "w0", "gamma"]
    assert per["w0"].tolist() == [pendula.natural_frequency()] * 2  # the package's one default pendulum
    table = pendula.tradeoff(
        pendula.Scene(0.5, t=[0.0, 1.0]), models=["exact", "rk4"], rk4_steps=[0.1], repeat=1, scipy=False
    )
    df = table.to_pandas()
    assert list(df.columns) == list(pendula.TradeoffTable.COLUMNS) and len(df) == 2
    assert df["sup_error"].tolist() == table.column("sup_error")


@pytest.mark.parametrize("package", ["pandas", "xarray"])
def test_missing_package_names_it(monkeypatch, package):
    monkeypatch.setitem(sys.modules, package, None)  # import now raises ImportError
    r = pendula.rk4([0.0, 1.0], 0.1, 0.0, 1.0, 0.0, 0.1)
    convert = r.to_pandas if package == "pandas" else r.to_xarray
    with pytest.raises(ImportError, match=f"'{package}'"):
        convert()


# ---------------------------------------------------------------- tradeoff


def test_tradeoff_shows_the_step_used_and_drops_repeated_runs():
    # output spacing 0.05 s: every h >= 0.05 runs the same 600 steps
    table = pendula.tradeoff(_text_scene(), models=["rk4"], repeat=1, scipy=False)
    used = table.column("step_used")
    assert used[0] == pytest.approx(0.05, rel=1e-12)
    assert len(used) == len(set(used))
    assert all(a > b for a, b in zip(used, used[1:]))
    assert table[0]["steps"] == 600
    # explicit settings: h = 1.84 ... 0.0575 collapse into one row
    hs = [1.84 / 2**k for k in range(6)]
    table = pendula.tradeoff(_text_scene(), models=["rk4"], rk4_steps=hs, repeat=1, scipy=False)
    assert table.column("setting") == ["h=1.84"] and table.column("steps") == [600]


def test_tradeoff_rows_are_distinct_and_errors_match_an_independent_reference():
    scipy = pytest.importorskip("scipy.integrate")
    t = np.linspace(0, 8, 41)
    theta0, omega0 = 2.0, 0.5
    scene = pendula.Scene(theta0, omega0, t=t)
    table = pendula.tradeoff(
        scene,
        models=["exact", "rk4"],
        rk4_steps=[0.4, 0.2, 0.05, 0.02],
        repeat=1,
        scipy=["RK45", "DOP853", "Radau", "LSODA"],
        scipy_rtols=[1e-4, 1e-8],
    )
    keys = [(r["model"], r["step_used"] if r["model"] == "rk4" else r["setting"]) for r in table]
    assert len(keys) == len(set(keys))
    assert {r["model"] for r in table} == {"exact", "rk4", "scipy RK45", "scipy DOP853", "scipy Radau", "scipy LSODA"}
    th_mp, om_mp = scene_grid.mp_undamped(t, theta0, omega0, W0)  # mpmath, 30 digits
    th_mp, om_mp = np.array(th_mp, dtype=float), np.array(om_mp, dtype=float)

    def err(th, om):
        return max(np.max(np.abs(th - th_mp)), np.max(np.abs(om - om_mp)) / W0)

    scale = max(abs(theta0), abs(omega0) / W0)
    checked = 0
    for row in table:
        if row["model"] == "rk4":
            h = float(row["setting"][2:])
            r = pendula.rk4(t, theta0, omega0, W0, 0.0, h)
            th, om = r.theta, r.omega
        elif row["model"].startswith("scipy"):
            rtol = float(row["setting"][5:])
            method = row["model"].split()[1]
            sol = scipy.solve_ivp(
                lambda _, y: [y[1], -(W0**2) * np.sin(y[0])],
                (0.0, t[-1]),
                [theta0, omega0],
                method=method,
                t_eval=t,
                rtol=rtol,
                atol=[rtol * scale / 100, rtol * W0 * scale / 100],
                **(
                    {"jac": lambda _, y: [[0.0, 1.0], [-(W0**2) * np.cos(y[0]), 0.0]]}
                    if method != "RK45" and method != "DOP853"
                    else {}
                ),
            )
            th, om = sol.y
        else:
            r = pendula.solve(pendula.Scene(theta0, omega0, t=t), model="exact")
            th, om = r.theta, r.omega
        # the table's reference (exact elliptic, ~1e-15) and mpmath agree far below these errors
        assert abs(row["sup_error"] - err(th, om)) <= 1e-13 + 1e-9 * row["sup_error"], row
        checked += 1
    assert checked >= 10


def test_tradeoff_scipy_argument():
    scene = pendula.Scene(0.5, t=[0.0, 1.0])
    plain = pendula.tradeoff(scene, models=["exact"], repeat=1)  # models given: no SciPy by default
    assert plain.column("model") == ["exact"]
    some = pendula.tradeoff(scene, models=["exact"], repeat=1, scipy=["RK45"], scipy_rtols=[1e-3])
    assert some.column("model") == ["exact", "scipy RK45"]
    for bad, exc in (("RK45", ValueError), (["Euler"], ValueError), ([1], TypeError), (1, TypeError)):
        with pytest.raises(exc, match="scipy"):
            pendula.tradeoff(scene, models=["exact"], repeat=1, scipy=bad)
    with pytest.raises(ValueError, match="scipy_rtols"):
        pendula.tradeoff(scene, models=["exact"], repeat=1, scipy=True, scipy_rtols=[0.0])
