"""The one contract (docs/robustness.md) on the driven pendulum's surfaces.

pendula.driven and the chaos tools (poincare, bifurcation, lyapunov,
periodic_orbits, find_periodic_orbit, basins): the text's default pendulum
and the g/length, b/mass convention; a state that fails is NaN (integer
fields FAILED) with its code, the others keep their answers bit for bit; the
call raises only when every state failed; argument errors are ValueError
naming the argument and the state; results carry their inputs; a Dask basin
map, bifurcation diagram, Lyapunov batch and periodic-orbit search are bit
for bit the local ones.
"""

import math

import numpy as np
import pytest

import pendula
from pendula._errors import OK

W0_TEXT = math.sqrt(9.8 / 4.9)
D = pendula.Drive("torque", 1.07, 2 / 3)
FAST = dict(transient=20, steps_per_period=32)
# w0 = 1e4 needs ~63,000 steps per period at Omega = 2/3: with 128 that state fails (unstable)
W0_BAD = np.array([1.0, 1e4, 1.0])


def _no_numpy_repr(msg):
    assert "np." not in msg and "float64(" not in msg and "int64(" not in msg, msg


def test_the_text_pendulum_is_the_default():
    th = [0.1, 0.3]
    by_default = pendula.poincare(th, 0.0, drive=D, gamma=0.5, points=3, **FAST)
    explicit = pendula.poincare(th, 0.0, drive=D, w0=W0_TEXT, gamma=0.5, points=3, **FAST)
    by_g_l = pendula.poincare(th, 0.0, drive=D, g=9.8, length=4.9, b=0.05, mass=0.1, points=3, **FAST)
    assert np.array_equal(by_default.theta, explicit.theta) and np.array_equal(by_default.theta, by_g_l.theta)
    assert (by_default.inputs["w0"] == W0_TEXT).all() and by_default.inputs["frequency"] == D.frequency
    t = [0.0, 5.0]
    assert np.array_equal(
        pendula.driven(t, 0.2, 0.0, drive=D).theta, pendula.driven(t, 0.2, 0.0, drive=D, w0=W0_TEXT, gamma=0.0).theta
    )
    assert pendula.resonance_curve(1.0) == pendula.resonance_curve(1.0, w0=W0_TEXT)
    assert pendula.resonance_curve(1.0, length=9.8) == pendula.resonance_curve(1.0, w0=1.0)
    with pytest.raises(ValueError, match="mass"):
        pendula.lyapunov(0.2, 0.0, drive=D, b=0.1, periods=16)


@pytest.mark.parametrize(
    "call, real",
    [
        (lambda w0: pendula.driven([0.0, 5.0], 0.2, 0.0, drive=D, w0=w0, gamma=0.5), ("theta", "omega")),
        (
            lambda w0: pendula.poincare(0.2, 0.0, drive=D, w0=w0, gamma=0.5, points=2, **FAST),
            ("theta", "omega", "mean_omega", "rotation_number"),
        ),
        (lambda w0: pendula.lyapunov(0.2, 0.0, drive=D, w0=w0, gamma=0.5, periods=16, **FAST), ("exponents", "errors")),
        (
            lambda w0: pendula.periodic_orbits(0.2, 0.0, drive=D, w0=w0, gamma=0.5, **FAST),
            ("theta", "omega", "floquet_exponents", "residual"),
        ),
        (lambda w0: pendula.basins(0.2, 0.0, drive=D, w0=w0, gamma=0.5, **FAST), ()),
    ],
)
def test_a_failed_state_is_nan_and_the_others_keep_their_answers(call, real):
    r = call(W0_BAD)
    assert r.codes.tolist()[0] == OK and r.codes[1] != OK and r.ok.tolist() == [True, False, True]
    assert r.message.startswith("1 of 3 states failed") and "[1]" in r.message
    _no_numpy_repr(r.message)
    good = call(1.0)
    for name in real:
        a, b = getattr(r, name), getattr(good, name)
        assert np.isnan(a[1]).all(), name  # never zero, never a plausible number
        assert np.array_equal(a[0], b) and np.array_equal(a[2], b), name
    for name in ("labels", "period", "winding"):  # integer fields: the sentinel
        if hasattr(r, name):
            assert getattr(r, name)[1] == pendula.FAILED
    with pytest.raises(ValueError, match="^every state failed"):  # unstable: as rk4 and sweep say it
        call(np.array([1e4, 1e4]))
    with pytest.raises(ValueError, match="too few"):  # a scalar call: the state's own error
        call(1e4)


def test_a_failed_bifurcation_value_is_nan():
    b = pendula.bifurcation("w0", [1.0, 1e4], drive=D, gamma=0.5, points=2, **FAST)
    assert b.codes.tolist()[0] == OK and b.codes[1] != OK and np.isnan(b.theta[1]).all()
    assert np.isfinite(b.theta[0]).all() and b.inputs["w0"].tolist() == [1.0, 1e4]


@pytest.mark.parametrize(
    "call, pattern",
    [
        (
            lambda: pendula.driven([0, 1], [0.1, 0.2], 0.0, drive=D, w0=np.array([1.0, -1.0])),
            r"^w0\[1\] = -1\.0 is out of range",
        ),
        (
            lambda: pendula.basins(np.zeros((2, 2)), 0.0, drive=D, gamma=np.array([[0.5, 0.5], [0.5, -2.0]])),
            r"^gamma\[1, 1\] = -2\.0 is out of range",
        ),
        (lambda: pendula.lyapunov([0.0, math.nan], 0.0, drive=D), r"^theta0\[1\] = nan"),
        (lambda: pendula.poincare(0.0, 0.0, drive=D, w0=-1.0), r"^w0 = -1\.0 is out of range"),
        (lambda: pendula.bifurcation("frequency", [1.0, -0.5], drive=D), r"^values\[1\] = -0\.5 is out of range"),
        (lambda: pendula.periodic_orbits(0.0, 0.0, drive=D, g=-9.8), "g"),
    ],
)
def test_argument_errors_name_the_argument_and_the_state(call, pattern):
    with pytest.raises(ValueError, match=pattern) as exc:
        call()
    _no_numpy_repr(str(exc.value))


def test_results_carry_their_inputs():
    r = pendula.lyapunov([0.2, 0.3], 0.0, drive=D, w0=1.0, gamma=0.5, periods=16, **FAST)
    df = r.to_pandas()
    assert df["theta0"].tolist() == [0.2, 0.3] and (df["w0"] == 1.0).all() and (df["code"] == 0).all()
    assert r.inputs["kind"] == "torque" and r.inputs["amplitude"] == D.amplitude


def test_dask_matches_local_bit_for_bit():
    distributed = pytest.importorskip("distributed")
    # in-process workers (no spawn, no sockets): the chunking and the join are what is tested
    # (test_sweep.py runs chunks in worker processes); several chunks, attractors across them
    with (
        distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as lc,
        distributed.Client(lc) as client,
    ):
        grid = (np.linspace(-3, 3, 9)[:, None], np.linspace(-2, 2, 5)[None, :])
        kw = dict(
            drive=pendula.Drive("torque", 1.07, 2 / 3),
            w0=1.0,
            gamma=0.5,
            transient=60,
            nmax=4,
            tol=1e-4,
            steps_per_period=64,
        )
        local = pendula.basins(*grid, **kw)
        seen = []
        remote = pendula.basins(*grid, **kw, client=client, chunk_states=7, progress=lambda d, n: seen.append((d, n)))
        assert len(local.attractors["period"]) >= 2
        assert np.array_equal(remote.labels, local.labels) and np.array_equal(remote.codes, local.codes)
        for k, v in local.attractors.items():
            assert np.array_equal(remote.attractors[k], v), k
        assert seen[-1] == (45, 45)
        # a failed state on Dask: the same codes, NaN/sentinel and message as locally
        bad = dict(kw, w0=np.array([1.0, 1e4, 1.0]))
        lb, rb = pendula.basins(0.2, 0.0, **bad), pendula.basins(0.2, 0.0, **bad, client=client, chunk_states=1)
        assert np.array_equal(lb.labels, rb.labels) and lb.message == rb.message and rb.labels[1] == pendula.FAILED
        amps = np.linspace(0.9, 1.2, 11)
        b_loc = pendula.bifurcation("amplitude", amps, drive=D, w0=1.0, gamma=0.5, points=3, **FAST)
        b_rem = pendula.bifurcation(
            "amplitude", amps, drive=D, w0=1.0, gamma=0.5, points=3, **FAST, client=client, chunk_states=4
        )
        assert np.array_equal(b_loc.theta, b_rem.theta) and np.array_equal(b_loc.rotation_number, b_rem.rotation_number)
        ly_loc = pendula.lyapunov([0.2, 0.4, 0.6], 0.0, drive=D, w0=1.0, gamma=0.5, periods=16, **FAST)
        ly_rem = pendula.lyapunov(
            [0.2, 0.4, 0.6], 0.0, drive=D, w0=1.0, gamma=0.5, periods=16, **FAST, client=client, chunk_states=2
        )
        assert np.array_equal(ly_loc.exponents, ly_rem.exponents) and np.array_equal(ly_loc.errors, ly_rem.errors)
        starts = (np.linspace(-2, 2, 5), np.array([0.0, 1.0])[:, None])
        kw = dict(drive=D, w0=1.0, gamma=0.5, transient=60, nmax=4, steps_per_period=64)
        po_loc = pendula.periodic_orbits(*starts, **kw)
        po_rem = pendula.periodic_orbits(*starts, **kw, client=client, chunk_states=3)
        assert (po_loc.period > 0).any()
        for k in (
            "period",
            "winding",
            "theta",
            "omega",
            "multipliers",
            "stable",
            "floquet_exponents",
            "residual",
            "codes",
        ):
            a, b = getattr(po_loc, k), getattr(po_rem, k)
            assert np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"), k
        with pytest.raises(TypeError, match="client"):
            pendula.basins(0.2, 0.0, **kw, client="tcp://x")


def test_the_commands_take_the_pendulum_as_every_command_does(tmp_path):
    import io

    from pendula.cli import main

    def run(*flags):
        folder = tmp_path / f"o{len(list(tmp_path.iterdir()))}"
        code = main(
            [
                "lyapunov",
                "--theta0",
                "0.2",
                "--periods",
                "16",
                "--transient",
                "5",
                "--no-png",
                *flags,
                "--out",
                str(folder),
            ],
            out=io.StringIO(),
        )
        return code, (dict(np.load(folder / "lyapunov.npz")) if code == 0 else None)

    code, text = run()
    assert code == 0
    _, one = run("--w0", "1")
    _, g_l = run("--g", "9.8", "--length", "9.8")
    _, direct = run("--w0", str(W0_TEXT))
    for k in one:
        assert np.array_equal(one[k], g_l[k]) and np.array_equal(text[k], direct[k]), k
    assert not all(np.array_equal(one[k], text[k]) for k in one)  # the default is the text's, not w0 = 1
    assert run("--w0", "1", "--g", "9.8")[0] == 2
