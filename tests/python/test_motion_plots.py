"""pendula.plot_motion and pendula.plot_phase_portrait: the plotted line data are the
result's arrays (bit for bit) and exact level curves of the energy; axis labels carry
units; ax= draws into given Axes; bad input is refused by name; matplotlib stays optional."""

import doctest
import math
import subprocess
import sys

import numpy as np
import pytest

import pendula

mpl = pytest.importorskip("matplotlib")
from matplotlib.figure import Figure  # noqa: E402

W0 = math.sqrt(2.0)


@pytest.fixture(scope="module")
def damped():
    """The text's §2.2 scene, b = 0.01 kg/s, solved by the library."""
    scene = pendula.Scene(theta0=0.0, omega0=2.0, t=np.linspace(0.0, 30.0, 301), mass=0.1, b=0.01)
    return pendula.solve(scene)


def _data_lines(ax):
    """The curves drawn from data (the start marker's label starts with '_')."""
    return [ln for ln in ax.get_lines() if not ln.get_label().startswith("_start")]


def test_time_panels_are_the_result_arrays(damped):
    fig = pendula.plot_motion(damped)
    assert isinstance(fig, Figure) and len(fig.axes) == 2
    (th_line,), (om_line,) = (_data_lines(a) for a in fig.axes)
    assert np.array_equal(th_line.get_xdata(), damped.t) and np.array_equal(th_line.get_ydata(), damped.theta)
    assert np.array_equal(om_line.get_xdata(), damped.t) and np.array_equal(om_line.get_ydata(), damped.omega)
    assert [a.get_ylabel() for a in fig.axes] == ["θ(t)  (rad)", "Ω(t)  (rad/s)"]
    assert all(a.get_xlabel() == "time t  (s)" for a in fig.axes)
    assert th_line.get_label() == damped.model  # default legend: the model used


def test_phase_and_both(damped):
    fig = pendula.plot_motion(damped, kind="phase")
    (ax,) = fig.axes
    (line,) = _data_lines(ax)
    assert np.array_equal(line.get_xdata(), damped.theta) and np.array_equal(line.get_ydata(), damped.omega)
    start = [ln for ln in ax.get_lines() if ln is not line][0]
    assert (start.get_xdata()[0], start.get_ydata()[0]) == (0.0, 2.0)  # the initial state
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("θ  (rad)", "Ω  (rad/s)")
    fig = pendula.plot_motion(damped, kind="both")
    assert [a.get_ylabel() for a in fig.axes] == ["θ(t)  (rad)", "Ω(t)  (rad/s)", "Ω  (rad/s)"]
    assert np.array_equal(_data_lines(fig.axes[2])[0].get_xdata(), damped.theta)


def test_integration_result_and_arrays():
    t = np.linspace(0.0, 10.0, 101)
    r = pendula.rk4(t, 1.0, 0.0, W0, 0.3, 0.01)
    fig = pendula.plot_motion(r, kind="both")
    assert np.array_equal(_data_lines(fig.axes[1])[0].get_ydata(), r.omega)
    assert _data_lines(fig.axes[0])[0].get_label() == "rk4"
    th, om = pendula.undamped(t, 2.0, 0.0, W0)
    t_in, th_in = t.copy(), th.copy()
    fig = pendula.plot_motion(t=t, theta=th, omega=om, label="exact")
    assert np.array_equal(_data_lines(fig.axes[0])[0].get_ydata(), th)
    assert fig.axes[0].get_legend().get_texts()[0].get_text() == "exact"
    assert np.array_equal(t, t_in) and np.array_equal(th, th_in)  # inputs untouched
    fig = pendula.plot_motion(t=t, theta=th)  # theta alone: one panel
    assert len(fig.axes) == 1 and fig.axes[0].get_legend() is None


def test_a_scene_is_solved(damped):
    scene = pendula.Scene(theta0=0.0, omega0=2.0, t=np.linspace(0.0, 30.0, 301), mass=0.1, b=0.01)
    fig = pendula.plot_motion(scene)
    assert np.array_equal(_data_lines(fig.axes[0])[0].get_ydata(), damped.theta)


def test_theta_only_result():
    r = pendula.solve(pendula.Scene(theta0=0.5, t=np.linspace(0, 5, 51), want="theta"))
    fig = pendula.plot_motion(r)
    assert len(fig.axes) == 1 and np.array_equal(_data_lines(fig.axes[0])[0].get_ydata(), r.theta)
    with pytest.raises(ValueError, match="omega"):
        pendula.plot_motion(r, kind="phase")


def test_draws_into_given_axes(damped):
    fig = Figure()
    axs = fig.subplots(1, 3)
    assert pendula.plot_motion(damped, kind="both", ax=axs) is fig
    assert [a.get_ylabel() for a in axs] == ["θ(t)  (rad)", "Ω(t)  (rad/s)", "Ω  (rad/s)"]
    fig2 = Figure()
    ax = fig2.subplots()
    assert pendula.plot_motion(damped, kind="phase", ax=ax) is fig2
    # a motion drawn over the portrait: both curves in one Axes
    assert pendula.plot_phase_portrait(w0=W0, ax=ax) is fig2
    assert any(np.array_equal(ln.get_xdata(), damped.theta) for ln in ax.get_lines())


@pytest.mark.parametrize(
    "kwargs, exc, words",
    [
        (dict(kind="phasee"), ValueError, "kind"),
        (dict(kind=1), TypeError, "kind"),
        (dict(label=3), TypeError, "label"),
        (dict(ax="ax"), TypeError, "ax"),
        (dict(t=[0.0, 1.0]), ValueError, "not both"),
        (dict(kind="time", ax=[]), ValueError, "ax: kind='time' draws 2 panel"),
    ],
)
def test_bad_options(damped, kwargs, exc, words):
    with pytest.raises(exc, match=words):
        pendula.plot_motion(damped, **kwargs)


@pytest.mark.parametrize(
    "kwargs, exc, words",
    [
        (dict(t=[0.0, 1.0]), TypeError, "theta missing"),
        (dict(t=[0.0, 1.0], theta=[0.0, 1.0, 2.0]), ValueError, "theta has 3 values but t has 2"),
        (dict(t=[0.0, 1.0], theta=[0.0, 1.0], omega=[1.0]), ValueError, "omega has 1 values"),
        (dict(t=[0.0, np.nan], theta=[0.0, 1.0]), ValueError, "t contains NaN"),
        (dict(t=[0.0, 1.0], theta=[0.0, np.inf]), ValueError, "theta contains NaN or Inf"),
        (dict(t=[], theta=[]), ValueError, "t must be a non-empty 1-D array"),
        (dict(t=[[0.0, 1.0]], theta=[0.0, 1.0]), ValueError, "t must be a non-empty 1-D"),
        (dict(t=["a", "b"], theta=[0.0, 1.0]), TypeError, "t must be a real"),
        (dict(t=[0.0, 1.0], theta=[1 + 1j, 0.0]), TypeError, "theta must be a real"),
        (dict(t=[0.0, 1.0], theta=[True, False]), TypeError, "theta"),
    ],
)
def test_bad_arrays(kwargs, exc, words):
    with pytest.raises(exc, match=words):
        pendula.plot_motion(**kwargs)


def test_bad_results():
    with pytest.raises(TypeError, match="result must be a SceneResult"):
        pendula.plot_motion((np.zeros(3), np.zeros(3)))
    r = pendula.solve(pendula.Scene(theta0=0.5, t=np.linspace(0, 5, 51), want="period"))
    with pytest.raises(ValueError, match="no single time series"):
        pendula.plot_motion(r)
    batch = pendula.rk4(np.linspace(0, 1, 11), np.array([0.1, 0.2]), 0.0, W0, 0.0, 0.01)
    with pytest.raises(ValueError, match=r"theta=r.theta\[i\]"):
        pendula.plot_motion(batch)


# ---------------------------------------------------------------- phase portrait


def _energy_ratio(line, w0):
    return pendula.energy(line.get_xdata(), line.get_ydata(), w0) / (2.0 * w0**2)


@pytest.mark.parametrize("w0", [W0, 0.01, 1e3])
def test_portrait_curves_are_exact_levels_of_the_energy(w0):
    levels = [0.05, 0.5, 0.999, 1.001, 2.0]
    fig = pendula.plot_phase_portrait(w0=w0, levels=levels, theta_range=(-2 * np.pi, 3 * np.pi))
    ax = fig.axes[0]
    by_gid = {}
    for ln in ax.get_lines():
        by_gid.setdefault(ln.get_gid(), []).append(ln)
    assert set(by_gid) == {
        "libration 0.05",
        "libration 0.5",
        "libration 0.999",
        "rotation 1.001",
        "rotation 2",
        "separatrix 1",
        "centres",
        "saddles",
    }
    for e in levels + [1.0]:
        family = "libration" if e < 1 else "rotation" if e > 1 else "separatrix"
        for ln in by_gid[f"{family} {e:g}"]:
            # against the library's energy: a few ulps of the level (librations circle
            # every centre in the window, so the angle reaches 4 pi: a few ulps of that)
            err = np.max(np.abs(_energy_ratio(ln, w0) - e))
            assert err <= 8e-15 * max(e, 1.0), (family, e, err)
    # the islands that show in [-2 pi, 3 pi]: around -2 pi, 0, 2 pi (the one at 4 pi starts beyond 3 pi)
    assert len(by_gid["libration 0.5"]) == 3 and len(by_gid["libration 0.999"]) == 3
    np.testing.assert_array_equal(by_gid["centres"][0].get_xdata(), [-2 * np.pi, 0.0, 2 * np.pi])
    np.testing.assert_array_equal(by_gid["saddles"][0].get_xdata(), [-np.pi, np.pi, 3 * np.pi])
    assert ax.get_xlim() == (-2 * np.pi, 3 * np.pi)
    assert ax.get_ylim()[1] == pytest.approx(1.1 * 2 * w0 * math.sqrt(2.0), rel=1e-15)
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("θ  (rad)", "Ω  (rad/s)")


@pytest.mark.parametrize(
    "levels, title",
    [
        (1.0, "the separatrix"),
        ([2.0, 0.5], "levels E/E_sep = 0.5, 2"),
        (np.linspace(0.05, 3.0, 40), "40 levels E/E_sep from 0.05 to 3"),
    ],
)
def test_portrait_title_says_which_levels(levels, title):
    fig = pendula.plot_phase_portrait(w0=W0, levels=levels, n=16)
    assert fig.axes[0].get_title().endswith(title)
    assert sum(ln.get_gid() == "separatrix 1" for ln in fig.axes[0].get_lines()) == 2


def test_portrait_libration_closes_on_its_amplitude():
    fig = pendula.plot_phase_portrait(w0=W0, levels=0.5, theta_range=(-1.0, 1.0))
    (ln,) = [x for x in fig.axes[0].get_lines() if x.get_gid() == "libration 0.5"]  # only the centre 0 shows
    x = ln.get_xdata()
    # E/E_sep = sin^2(theta_max/2) for a release from rest: theta_max = pi/2 at e = 0.5
    assert np.max(x) == pytest.approx(float(pendula.amplitude(np.pi / 2, 0.0, W0)), rel=1e-15)
    assert np.min(x) == pytest.approx(-np.pi / 2, rel=1e-15)
    assert (x[0], ln.get_ydata()[0]) == (x[-1], ln.get_ydata()[-1])  # a closed curve


@pytest.mark.parametrize(
    "kwargs, exc, words",
    [
        (dict(w0=0.0), ValueError, "w0 must be finite and > 0"),
        (dict(w0=-1.0), ValueError, "w0"),
        (dict(w0=np.nan), ValueError, "w0"),
        (dict(w0="1"), TypeError, "w0"),
        (dict(w0=np.array([1.0, 2.0])), TypeError, "w0"),
        (dict(w0=True), TypeError, "w0"),
        (dict(w0=1.0, levels=[0.5, -1.0]), ValueError, "levels"),
        (dict(w0=1.0, levels=[0.5, np.inf]), ValueError, "levels"),
        (dict(w0=1.0, levels=np.ones((2, 2))), ValueError, "levels"),
        (dict(w0=1.0, levels="0.5"), TypeError, "levels"),
        (dict(w0=1.0, theta_range=(1.0, 0.0)), ValueError, "theta_range"),
        (dict(w0=1.0, theta_range=(0.0, np.inf)), ValueError, "theta_range"),
        (dict(w0=1.0, theta_range=(0.0, 1e4)), ValueError, "theta_range spans"),
        (dict(w0=1.0, theta_range=1.0), TypeError, "theta_range"),
        (dict(w0=1.0, theta_range=("a", 1.0)), TypeError, "theta_range"),
        (dict(w0=1.0, omega_max=0.0), ValueError, "omega_max"),
        (dict(w0=1.0, n=15), ValueError, r"n = 15 is out of range"),
        (dict(w0=1.0, n=100.0), TypeError, "n must be an integer"),
        (dict(w0=1.0, ax=[1, 2]), TypeError, "ax"),
        (dict(g=-9.8), ValueError, "g"),
        (dict(length=0.0), ValueError, "length"),
        (dict(w0=1.0, g=9.8, length=4.9), ValueError, "w0"),
    ],
)
def test_portrait_bad_input(kwargs, exc, words):
    with pytest.raises(exc, match=words):
        pendula.plot_phase_portrait(**kwargs)


def _curve_data(fig):
    return [(ln.get_gid(), ln.get_xdata().tolist(), ln.get_ydata().tolist()) for ln in fig.axes[0].get_lines()]


def test_portrait_takes_the_pendulum_as_everywhere():
    """No w0: the text's pendulum (w0 = sqrt(g/length) with g = 9.8, length = 4.9), as every
    function of pendula; g and length give the same curves as the w0 they make."""
    ref = _curve_data(pendula.plot_phase_portrait(w0=pendula.natural_frequency(), levels=[0.5, 2.0], n=16))
    assert _curve_data(pendula.plot_phase_portrait(levels=[0.5, 2.0], n=16)) == ref
    assert _curve_data(pendula.plot_phase_portrait(g=9.8, length=4.9, levels=[0.5, 2.0], n=16)) == ref
    other = _curve_data(pendula.plot_phase_portrait(g=1.0, length=1.0, levels=[0.5, 2.0], n=16))
    assert other == _curve_data(pendula.plot_phase_portrait(w0=1.0, levels=[0.5, 2.0], n=16))


def test_portrait_options_are_keyword_only():
    with pytest.raises(TypeError):
        pendula.plot_phase_portrait(W0)  # noqa: the signature is keyword-only
    with pytest.raises(TypeError):
        pendula.plot_motion(None, None)


# ---------------------------------------------------------------- docstrings, optional matplotlib


@pytest.mark.parametrize("name", ["plot_motion", "plot_phase_portrait"])
def test_docstring_examples_run(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    fn = getattr(pendula, name)
    tests = doctest.DocTestFinder().find(fn, name, globs={})
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    for t in tests:
        runner.run(t)
    result = runner.summarize(verbose=False)
    assert result.attempted >= 4 and result.failed == 0


def test_importing_pendula_does_not_import_matplotlib():
    code = "import sys, pendula; print('matplotlib' in sys.modules)"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "False"


@pytest.mark.parametrize(
    "call", [lambda: pendula.plot_motion(t=[0.0, 1.0], theta=[0.0, 1.0]), lambda: pendula.plot_phase_portrait(w0=1.0)]
)
def test_without_matplotlib_import_error_names_the_extra(monkeypatch, call):
    for mod in ("matplotlib", "matplotlib.figure", "matplotlib.axes"):
        monkeypatch.setitem(sys.modules, mod, None)  # `import matplotlib...` now raises ImportError
    with pytest.raises(ImportError, match=r"needs matplotlib.*pip install 'pendula\[examples\]'"):
        call()
