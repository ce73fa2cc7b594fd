"""rk4, cvode, their batch forms and sweep with ``drive=`` (pendula.Drive).

References: mpmath.odefun (Taylor series at 30 digits) on a short window for
a torque and a pivot drive; the linearised driven oscillator in closed form
(pendula.driven_linear) for a small drive; the stroboscopic map's own
periodicity after 1e6 drive periods (no phase lost); the scalar call for
every batch state and the local sweep for the Dask one, bit for bit.
"""

import importlib.util
import math

import numpy as np
import pytest

import pendula
from pendula import _defaults

mpmath = pytest.importorskip("mpmath")

W0, GAMMA, TH0, OM0 = 1.0, 0.5, 0.2, 0.1
TORQUE = pendula.Drive("torque", 1.15, 2 / 3, 0.3)
PIVOT = pendula.Drive("pivot", 0.1, 20.0, 0.7)  # Kapitza: a/l = 0.1, Omega = 20 w0
T_END = 2.0


def _mp_reference(drive, t_end):
    """theta, omega at t_end from mpmath's Taylor-series odefun at 30 digits."""
    mp = mpmath.mp
    with mpmath.workdps(30):
        amp, freq, ph = mp.mpf(drive.amplitude), mp.mpf(drive.frequency), mp.mpf(drive.phase)
        w0sq, gam = mp.mpf(W0) ** 2, mp.mpf(GAMMA)

        def f(t, y):
            c = mp.cos(freq * t + ph)
            p = w0sq + (amp * freq**2 * c if drive.kind == "pivot" else 0)
            q = 0 if drive.kind == "pivot" else amp * c
            return [y[1], q - gam * y[1] - p * mp.sin(y[0])]

        sol = mpmath.odefun(f, 0, [mp.mpf(TH0), mp.mpf(OM0)])
        y = sol(mp.mpf(t_end))
        return float(y[0]), float(y[1])


# _mp_reference(d, T_END) for TORQUE and PIVOT, rounded to double (odefun
# takes ~20 s for the two: stored here, recomputed by the slow test below)
REFERENCES = {
    "torque": (0.848590238759373, -0.04003679342864841),
    "pivot": (-0.1357200135234296, -0.149027288825657),
}


@pytest.mark.slow
def test_stored_references_are_mpmath_at_30_digits():
    for d in (TORQUE, PIVOT):
        assert _mp_reference(d, T_END) == REFERENCES[d.kind]


@pytest.fixture(scope="module")
def references():
    return REFERENCES


@pytest.mark.parametrize("drive", [TORQUE, PIVOT], ids=["torque", "pivot"])
def test_rk4_with_a_drive_against_mpmath(drive, references):
    ref = np.array(references[drive.kind])
    errs = []
    for n in (1000, 2000):
        h = drive.period / n
        r = pendula.rk4([0.0, T_END], TH0, OM0, W0, GAMMA, h, drive=drive)
        errs.append(np.abs(np.array([r.theta[-1], r.omega[-1]]) - ref).max())
    # RK4's global error O(h^4): below 1e-8 and falling ~16x when h halves
    assert errs[0] < 1e-8, errs
    assert 10 < errs[0] / errs[1] < 22, errs


@pytest.mark.skipif(not pendula.build_info()["cvode"], reason="no CVODE in this build")
@pytest.mark.parametrize("drive", [TORQUE, PIVOT], ids=["torque", "pivot"])
@pytest.mark.parametrize("method", ["adams", "bdf"])
def test_cvode_with_a_drive_against_mpmath(drive, method, references):
    ref = np.array(references[drive.kind])
    r = pendula.cvode([0.0, T_END], TH0, OM0, W0, GAMMA, rtol=1e-12, atol=1e-14, method=method, drive=drive)
    err = np.abs(np.array([r.theta[-1], r.omega[-1]]) - ref).max()
    assert err < 2e-9, err  # local tolerance 1e-12: a global error within 2000x of it


def test_small_drive_matches_the_linear_closed_form():
    # F = 1e-6 rad/s^2: the nonlinearity (theta^3/6 ~ 1e-18) is far below the tolerance
    d = pendula.Drive("torque", 1e-6, 0.8, 0.4)
    t = np.linspace(0.0, 40.0, 9)
    lin_theta, lin_omega = pendula.driven_linear(t, 0.0, 0.0, drive=d, w0=W0, gamma=GAMMA)
    scale = np.abs(lin_theta).max()
    r = pendula.rk4(t, 0.0, 0.0, W0, GAMMA, h=d.period / 2000, drive=d)
    assert np.abs(r.theta - lin_theta).max() < 1e-8 * scale
    assert np.abs(r.omega - lin_omega).max() < 1e-8 * scale
    if pendula.build_info()["cvode"]:
        c = pendula.cvode(t, 0.0, 0.0, W0, GAMMA, rtol=1e-12, atol=1e-20, drive=d)
        assert np.abs(c.theta - lin_theta).max() < 1e-8 * scale


def test_a_million_drive_periods_lose_no_phase():
    # gamma = 1: the transient is gone after 20 periods (e^-63); the steady
    # state of the RK4 map is periodic, so theta after 1e6 periods equals
    # theta after 20 to rounding -- a drift of the drive phase by Omega dt
    # would show as dt times the velocity (~1e-3 rad/s).
    d = pendula.Drive("torque", 1e-3, 1.0, 0.25)
    h = d.period / 8
    t = [0.0, 20 * d.period, 1e6 * d.period]
    r = pendula.rk4(t, 0.5, 0.0, 1.0, 1.0, h=h, drive=d)
    amp = abs(r.theta[1]) + abs(r.omega[1])
    assert abs(r.theta[2] - r.theta[1]) < 4e-9 * amp
    assert abs(r.omega[2] - r.omega[1]) < 4e-9 * amp
    # 8 steps a period (plus a partial step at an output that falls between grid times)
    assert 8_000_000 <= r.stats["steps"] <= 8_000_002


@pytest.mark.parametrize("method", ["rk4", "cvode"])
def test_a_late_start_keeps_the_drive_phase(method):
    # the same motion started at t = 0 and at t = 1e6 periods (the phase at
    # t[0] is reduced once): equal to the rounding of t[0] itself (Omega ulp(t0) ~ 1e-9)
    if method == "cvode" and not pendula.build_info()["cvode"]:
        pytest.skip("no CVODE in this build")
    d = TORQUE
    t0 = 1e6 * d.period
    k = np.linspace(0.0, 3 * d.period, 4)
    kw = dict(h=d.period / 200) if method == "rk4" else dict(rtol=1e-11, atol=1e-13)
    f = getattr(pendula, method)
    a = f(k, TH0, OM0, W0, GAMMA, drive=d, **kw)
    b = f(t0 + k, TH0, OM0, W0, GAMMA, drive=d, **kw)
    assert np.abs(a.theta - b.theta).max() < 1e-7


def _drives():
    return np.array(
        [
            pendula.Drive("torque", 1.15, 2 / 3, 0.3),
            pendula.Drive("pivot", 0.1, 20.0, 0.7),
            pendula.Drive("torque", 0.5, 1.3),
            pendula.Drive("torque", 1.15, 2 / 3, 0.3),
        ],
        dtype=object,
    )


def test_rk4_batch_is_the_scalar_call_bit_for_bit():
    t = np.linspace(0.0, 12.0, 7)
    ds = _drives()
    saved = [(d.kind, d.amplitude, d.frequency, d.phase) for d in ds]
    th0 = np.array([0.2, -1.0, 3.0, 0.2])
    b = pendula.rk4(t, th0, 0.1, 1.0, 0.4, h=0.02, drive=ds, threads=2)
    assert b.ok.all() and b.method == "rk4"
    for i, d in enumerate(ds):
        s = pendula.rk4(t, float(th0[i]), 0.1, 1.0, 0.4, h=0.02, drive=d)
        assert np.array_equal(s.theta, b.theta[i]) and np.array_equal(s.omega, b.omega[i])
        assert s.stats["steps"] == b.stats["steps"][i]
    # the same drive broadcast over states: one kernel call, the same bits
    one = pendula.rk4(t, th0, 0.1, 1.0, 0.4, h=0.02, drive=ds[0])
    assert np.array_equal(one.theta[0], b.theta[0]) and np.array_equal(one.theta[3], b.theta[3])
    assert one.inputs["drive_amplitude"].tolist() == [1.15] * 4
    # nothing the user passed changed
    assert [(d.kind, d.amplitude, d.frequency, d.phase) for d in ds] == saved
    assert th0.tolist() == [0.2, -1.0, 3.0, 0.2]


@pytest.mark.skipif(not pendula.build_info()["cvode"], reason="no CVODE in this build")
def test_cvode_batch_is_the_scalar_call_bit_for_bit():
    t = np.linspace(0.0, 6.0, 4)
    ds = _drives()
    b = pendula.cvode(t, 0.2, 0.1, 1.0, 0.4, rtol=1e-9, atol=1e-12, drive=ds, threads=2)
    e = pendula.cvode(t, 0.2, 0.1, 1.0, 0.4, rtol=1e-9, atol=1e-12, drive=ds, events=True)
    for i, d in enumerate(ds):
        s = pendula.cvode(t, 0.2, 0.1, 1.0, 0.4, rtol=1e-9, atol=1e-12, drive=d)
        assert np.array_equal(s.theta, b.theta[i]) and np.array_equal(s.omega, b.omega[i])
        assert np.array_equal(s.theta, e.theta[i])
        assert s.stats["steps"] == b.stats["steps"][i]


def test_failures_follow_the_contract():
    d = TORQUE
    # a scalar step too large for the drive: ValueError naming h and the largest h
    with pytest.raises(ValueError, match=r"h = .* too large for RK4 with this drive"):
        pendula.rk4([0.0, 10.0], 0.2, 0.0, 10.0, 0.0, h=1.0, drive=d)
    with pytest.raises(TypeError, match="drive"):
        pendula.rk4([0.0, 1.0], 0.2, 0.0, 1.0, 0.0, h=0.01, drive="torque")
    with pytest.raises(TypeError, match=r"drive\[1\]"):
        pendula.rk4([0.0, 1.0], 0.2, 0.0, 1.0, 0.0, h=0.01, drive=[d, 1.0])
    with pytest.raises(ValueError, match="broadcast"):
        pendula.rk4([0.0, 1.0], [0.1, 0.2, 0.3], 0.0, 1.0, 0.0, h=0.01, drive=[d, d])
    # in a batch an unstable state is its own code, NaN, and the others keep their answers
    b = pendula.rk4([0.0, 10.0], 0.2, 0.0, [1.0, 10.0], 0.0, h=1.0, drive=d)
    assert b.ok.tolist() == [True, False] and np.isnan(b.theta[1]).all()
    assert "w0[1]" in b.message or "state 1" in b.message or "[1]" in b.message
    # one output time takes no step (as without a drive)
    r = pendula.rk4([5.0], 0.2, 0.3, 10.0, 0.0, h=1.0, drive=d)
    assert r.theta.tolist() == [0.2] and r.stats["steps"] == 0


def test_sweep_takes_a_drive_axis_and_matches_the_batch():
    ds = np.array([pendula.Drive("torque", f, 2 / 3) for f in (0.5, 1.07, 1.15)], dtype=object)
    th0 = np.array([0.0, 1.0])[:, None]
    r = pendula.sweep([0.0, 30.0], th0, w0=1.0, gamma=0.5, h=0.05, drive=ds[None, :], chunk_states=4)
    b = pendula.rk4([0.0, 30.0], th0, 0.0, 1.0, 0.5, h=0.05, drive=ds[None, :])
    assert r.n_chunks == 2 and np.array_equal(r.theta, b.theta[..., -1])
    assert r.inputs["drive_amplitude"].tolist() == [[0.5, 1.07, 1.15]] * 2
    with pytest.raises(ValueError, match="period"):
        pendula.sweep(None, 0.1, drive=ds[0], want="period")


def test_driven_sweep_refuses_settled_and_well():
    # the energy rule (below the separatrix energy: trapped for ever) is false with a
    # drive: Baker-Gollub's chaotic torque pendulum goes over the top again after
    # resting low in its well, so settled/well refuse instead of answering wrongly
    d = pendula.Drive("torque", 1.15, 2 / 3)
    t = np.linspace(0.0, 200.0, 4001)
    r = pendula.sweep(t, 0.2, w0=1.0, gamma=0.5, h=d.period / 128, drive=d, want="trajectory")
    e = 0.5 * r.omega**2 + (1 - np.cos(r.theta))
    low = np.flatnonzero(e < 2 * (1 - _defaults.SETTLE_MARGIN))
    assert low.size and (e[low[0] :] > 2).any()  # low energy at some time, over the top later
    for name in ("settled", "well"):
        with pytest.raises(ValueError, match=f"{name} is not defined for a driven sweep.*pendula.basins"):
            getattr(r, name)
    assert r.rotating().shape == ()  # the energy at t[-1] is still a fact
    if importlib.util.find_spec("pandas") is not None:
        assert not {"well", "settled"} & set(r.to_pandas().columns)
    # a drive of zero amplitude is the undriven pendulum: the undriven rule
    th0 = np.array([0.5, 3.0])
    z = pendula.sweep([0.0, 40.0], th0, 2.0, w0=1.0, gamma=0.2, h=0.01, drive=pendula.Drive("torque", 0.0, 1.0))
    u = pendula.sweep([0.0, 40.0], th0, 2.0, w0=1.0, gamma=0.2, h=0.01)
    assert z.settled.tolist() == u.settled.tolist() == [True, True]
    assert z.well.tolist() == u.well.tolist()


def test_dask_sweep_with_a_drive_is_the_local_one():
    distributed = pytest.importorskip("distributed")
    ds = np.array([pendula.Drive("torque", f, 2 / 3, 0.1) for f in np.linspace(0.9, 1.2, 6)], dtype=object)
    args = ([0.0, 5.0, 20.0], np.linspace(-1, 1, 4)[:, None])
    kw = dict(w0=1.0, gamma=0.5, h=0.05, drive=ds[None, :], want="trajectory", chunk_states=5)
    local = pendula.sweep(*args, **kw)
    with (
        distributed.LocalCluster(
            n_workers=1,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
            worker_dashboard_address=None,
        ) as lc,
        distributed.Client(lc) as client,
    ):
        r = pendula.sweep(*args, client=client, **kw)
    assert r.n_chunks == math.ceil(24 / 5)
    assert np.array_equal(r.theta, local.theta) and np.array_equal(r.omega, local.omega)
    assert np.array_equal(r.codes, local.codes)


def test_drive_tables_the_core_cannot_allocate_are_a_memory_error():
    # N = 1e6 steps a period: a block's drive tables need 2 x 8 lanes x (2N + 1) doubles
    # (244 MiB); in a child whose address space is capped 100 MiB above its use, the
    # kernel's checked allocation reports it (PENDULA_ERR_MEMORY -> MemoryError), no crash
    resource = pytest.importorskip("resource")
    import subprocess
    import sys
    import textwrap

    del resource
    try:
        open("/proc/self/status").close()
    except OSError:
        pytest.skip("reads /proc/self/status")
    code = textwrap.dedent(
        """
        import re, resource
        import numpy as np, pendula
        pendula.rk4([0.0, 1.0], np.zeros(2), 0.0, 1.0, 0.0, h=0.1, threads=2)
        vm = int(re.search(r"VmSize:\\s+(\\d+) kB", open("/proc/self/status").read()).group(1)) * 1024
        resource.setrlimit(resource.RLIMIT_AS, (vm + 100 * 2**20, vm + 100 * 2**20))
        d = pendula.Drive("torque", 0.1, 1.0)
        for call in (
            lambda: pendula.rk4([0.0, 0.001], 0.2, 0.0, 1.0, 0.1, h=d.period / 1e6, drive=d),
            lambda: pendula.rk4([0.0, 0.001], [0.2, 0.3], 0.0, 1.0, 0.1, h=d.period / 1e6, drive=d),
            lambda: pendula.driven([0.0, 0.001], 0.2, 0.0, drive=d, w0=1.0, gamma=0.1, steps_per_period=10**6),
        ):
            try:
                call()
                print("no error")
            except MemoryError as exc:
                print("MemoryError:", exc)
        """
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr[-3000:]
    lines = r.stdout.splitlines()
    assert len(lines) == 3, r.stdout
    for line in lines:
        assert line.startswith("MemoryError:") and "the drive tables of a block of lanes need 244 MiB" in line, line
    assert lines[0].startswith("MemoryError: out of memory:"), lines[0]
