"""Property-based tests (hypothesis).

Invariants that must hold for every input in the domain, not only at the
points the concern tests pick:
  * linear damped: gamma = 0 is the small-angle solution; the energy
    E = Omega^2/2 + w0^2 theta^2/2 never increases for gamma > 0; the flow
    property (evolving t1 then t2 equals evolving t1 + t2); continuity across
    critical damping gamma = 2 w0;
  * Fortran and Python paths agree: the Python API and a Fortran program
    calling the library directly (compiled here against the meson build in
    $PENDULA_BUILD_DIR, or build/robust) give the same numbers.
Further sections (exact undamped solution, elliptic functions, integrators)
follow below.

Tolerances are relative to the natural scale of the state,
|theta| + |Omega|/w0, in units of eps = 2.2e-16 unless said otherwise.
Each test draws a modest number of examples (settings below); the file runs in
well under a minute.
"""

from __future__ import annotations

import math
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest
from helpers import HAVE_CVODE, needs_cvode
from hypothesis import HealthCheck, Phase, assume, given, settings
from hypothesis import strategies as st

import pendula

EPS = np.finfo(float).eps
SETTINGS = settings(
    max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow], report_multiple_bugs=False
)
# For tests whose failures are cheap to read as drawn: no shrinking (keeps a
# failing run within the file's time budget).
NO_SHRINK = settings(SETTINGS, phases=[Phase.explicit, Phase.reuse, Phase.generate])
ROOT = pathlib.Path(__file__).resolve().parents[2]


def fin(lo, hi):
    return st.floats(min_value=lo, max_value=hi, allow_nan=False, allow_infinity=False)


angles = fin(-3.0, 3.0)
rates = fin(-5.0, 5.0)
w0s = fin(0.05, 20.0)
gammas = fin(0.0, 40.0)


def scale(theta0, omega0, w0):
    return abs(theta0) + abs(omega0) / w0 + 1e-300


# ---- linear damped --------------------------------------------------------------------------------------
@SETTINGS
@given(theta0=angles, omega0=rates, w0=w0s, t=st.lists(fin(0.0, 50.0), min_size=1, max_size=20))
def test_linear_gamma_zero_is_small_angle_solution(theta0, omega0, w0, t):
    t = np.array(t)
    th, om = pendula.linear_damped(t, theta0, omega0, w0, 0.0)
    ref_th = theta0 * np.cos(w0 * t) + omega0 / w0 * np.sin(w0 * t)
    ref_om = omega0 * np.cos(w0 * t) - w0 * theta0 * np.sin(w0 * t)
    s = scale(theta0, omega0, w0)
    assert np.all(np.abs(th - ref_th) <= 8 * EPS * s)
    assert np.all(np.abs(om - ref_om) <= 8 * EPS * s * w0)


@SETTINGS
@given(theta0=angles, omega0=rates, w0=w0s, gamma=fin(1e-3, 40.0))
def test_linear_energy_never_increases(theta0, omega0, w0, gamma):
    # dE/dt = -gamma Omega^2 <= 0 (text eq. 2.4 times Omega).
    t = np.linspace(0.0, 20.0 / max(min(gamma, w0), 0.05), 400)
    th, om = pendula.linear_damped(t, theta0, omega0, w0, gamma)
    e = 0.5 * om**2 + 0.5 * w0**2 * th**2
    e0 = 0.5 * omega0**2 + 0.5 * w0**2 * theta0**2
    assert abs(e[0] - e0) <= 16 * EPS * e0 + 1e-300
    tol = 32 * EPS * e0 + 1e-300
    assert np.all(np.diff(e) <= tol), f"energy rose by {np.max(np.diff(e)) / e0:.3g} relative"


@SETTINGS
@given(theta0=angles, omega0=rates, w0=w0s, gamma=gammas, t1=fin(0.0, 5.0), t2=fin(0.0, 5.0))
def test_linear_flow_property(theta0, omega0, w0, gamma, t1, t2):
    # The solution operator is a semigroup: Phi(t1 + t2) = Phi(t2) Phi(t1).
    th1, om1 = pendula.linear_damped(t1, theta0, omega0, w0, gamma)
    th2, om2 = pendula.linear_damped(t2, th1, om1, w0, gamma)
    th12, om12 = pendula.linear_damped(t1 + t2, theta0, omega0, w0, gamma)
    # Error amplification of the composed map ~ (1 + w0 t + gamma t) for
    # non-normal (near-critical) dynamics; 1e3 eps is far below any defect.
    s = scale(theta0, omega0, w0) * (1 + (w0 + gamma) * (t1 + t2))
    assert abs(th2 - th12) <= 1e3 * EPS * s
    assert abs(om2 - om12) <= 1e3 * EPS * s * max(w0, gamma)


@SETTINGS
@given(theta0=angles, omega0=rates, w0=w0s, t=fin(0.0, 30.0), k=st.integers(4, 14))
def test_linear_continuous_across_critical_damping(theta0, omega0, w0, t, k):
    # gamma = 2 w0 (1 +- delta): the three regimes must join continuously, with
    # |d theta/d gamma| <= t * scale * (1 + w0 t) bounding the jump.
    gc = 2 * w0
    delta = 10.0**-k
    th_c, om_c = pendula.linear_damped(t, theta0, omega0, w0, gc)
    s = scale(theta0, omega0, w0)
    for g in (gc * (1 - delta), gc * (1 + delta)):
        th, om = pendula.linear_damped(t, theta0, omega0, w0, g)
        bound = (gc * delta) * t * s * (1 + w0 * t) + 64 * EPS * s * (1 + w0 * t)
        assert abs(th - th_c) <= bound, (g, th, th_c)
        assert abs(om - om_c) <= bound * max(w0, 1.0) * 2


@SETTINGS
@given(w0=w0s, gamma=gammas)
def test_linear_regime_matches_gamma_vs_2w0(w0, gamma):
    r = pendula.damping_regime(w0, gamma)
    want = "critical" if gamma == 2 * w0 else ("underdamped" if gamma < 2 * w0 else "overdamped")
    assert r.regime == want


# ---- Fortran and Python paths agree -----------------------------------------------------------------------
def _build_dir():
    for cand in (os.environ.get("PENDULA_BUILD_DIR"), ROOT / "build" / "test", ROOT / "build" / "dev"):
        if cand and (pathlib.Path(cand) / "src" / "libpendula_core.a").is_file():
            return pathlib.Path(cand)
    return None


def _sundials_libs():
    names = [
        "sundials_fcvode_mod",
        "sundials_cvode",
        "sundials_fnvecserial_mod",
        "sundials_nvecserial",
        "sundials_fsunmatrixdense_mod",
        "sundials_sunmatrixdense",
        "sundials_fsunlinsoldense_mod",
        "sundials_sunlinsoldense",
    ]
    return [f"-l{n}" for n in names]


FORTRAN_LINEAR = r"""
program fortran_path
  use pendula
  implicit none
  real(wp) :: theta0, omega0, w0, gamma, t, th, om
  type(linear_damped_t) :: sol
  type(status_t) :: st
  integer :: ios
  do
    read (*, *, iostat=ios) t, theta0, omega0, w0, gamma
    if (ios /= 0) exit
    call linear_damped_init(sol, theta0, omega0, w0, gamma, st)
    if (st%code /= PENDULA_OK) then
      write (*, '(a)') 'error'
      cycle
    end if
    call linear_damped_state(sol, t, th, om)
    write (*, '(2(es25.17e3,1x))') th, om
  end do
end program fortran_path
"""


def _fortran_program(tmp_path_factory, name, source):
    bdir = _build_dir()
    if bdir is None or shutil.which("gfortran") is None:
        pytest.skip("needs a meson build of the Fortran library (PENDULA_BUILD_DIR) and gfortran")
    d = tmp_path_factory.mktemp(name)
    src = d / f"{name}.f90"
    src.write_text(source)
    exe = d / name
    mods = bdir / "src" / "libpendula_core.a.p"
    cmd = ["gfortran", str(src), f"-I{mods}", "-o", str(exe), str(bdir / "src" / "libpendula_core.a")]
    proc = subprocess.run(cmd + _sundials_libs(), capture_output=True, text=True)
    if proc.returncode != 0:
        proc = subprocess.run(cmd, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return exe


def _program_fixture(name, source):
    """A module-scoped fixture: the Fortran program `source` built once as `name`."""

    @pytest.fixture(scope="module", name=name)
    def fixture(tmp_path_factory):
        return _fortran_program(tmp_path_factory, name, source)

    return fixture


def _run_program(exe, rows):
    """Feed exe one line of numbers (repr, exact) per row; its output lines as a float array."""
    lines = "\n".join(" ".join(repr(float(v)) for v in row) for row in rows)
    out = subprocess.run([str(exe)], input=lines + "\n", capture_output=True, text=True, check=True).stdout
    return np.array([[float(x) for x in line.split()] for line in out.split("\n") if line.strip()])


fortran_linear = _program_fixture("fortran_linear", FORTRAN_LINEAR)


def test_fortran_and_python_paths_agree_linear(fortran_linear):
    rng = np.random.default_rng(2024)
    n = 300
    t = rng.uniform(0, 30, n)
    theta0 = rng.uniform(-3, 3, n)
    omega0 = rng.uniform(-5, 5, n)
    w0 = rng.uniform(0.1, 10, n)
    gamma = np.where(rng.random(n) < 0.2, 2 * w0, rng.uniform(0, 25, n))
    gamma[:10] = 0.0
    f = _run_program(fortran_linear, zip(t, theta0, omega0, w0, gamma))
    th, om = pendula.linear_damped(t, theta0, omega0, w0, gamma)
    # Same archive, same compiler: only the 17-digit decimal round trip
    # separates the paths, which is exact; allow 2 ulps for a different -O.
    np.testing.assert_allclose(f[:, 0], th, rtol=4 * EPS, atol=4 * EPS * np.max(np.abs(th)))
    np.testing.assert_allclose(f[:, 1], om, rtol=4 * EPS, atol=4 * EPS * np.max(np.abs(om)))


# ---- elliptic functions -----------------------------------------------------------------------------------
ms = fin(-5.0, 0.999)
us = fin(-20.0, 20.0)


@SETTINGS
@given(u=us, m=fin(-10.0, 10.0))
def test_jacobi_identities(u, m):
    # sn^2 + cn^2 = 1 and dn^2 + m sn^2 = 1 for every real m (DLMF 22.6.1).
    sn, cn, dn, ph = pendula.ellipj(u, m)
    assert abs(sn * sn + cn * cn - 1) <= 16 * EPS
    assert abs(dn * dn + m * sn * sn - 1) <= 16 * EPS * (1 + abs(m))


@SETTINGS
@given(u=fin(-8.0, 8.0), k=st.integers(3, 12))
def test_jacobi_continuous_across_m_equal_1(u, k):
    # At m = 1: sn = tanh u, cn = dn = sech u (DLMF 22.5.iv); both sides of
    # m = 1 must approach them linearly in delta = |1 - m|, with
    # |d(sn, cn, dn)/dm| <= cosh(u)^2 while delta cosh(u)^2 << 1 (beyond, u
    # nears the quarter period K ~ ln(16/delta)/2 and the limit is not uniform).
    delta = 10.0**-k
    bound = 2 * delta * math.cosh(u) ** 2
    assume(bound < 1e-2)
    ref = (math.tanh(u), 1 / math.cosh(u), 1 / math.cosh(u))
    for p in (delta, -delta):
        got = pendula.ellipjm1(u, p)[:3]
        got_m = pendula.ellipj(u, 1 - p)[:3]
        for g, gm, r in zip(got, got_m, ref):
            assert abs(g - r) <= bound + 64 * EPS
            assert abs(gm - r) <= bound + 64 * EPS
    at1 = pendula.ellipj(u, 1.0)[:3]
    for g, r in zip(at1, ref):
        assert abs(g - r) <= 16 * EPS


@SETTINGS
@given(phi=fin(-1.5, 1.5), k=st.integers(3, 12))
def test_incomplete_integral_continuous_across_m_equal_1(phi, k):
    # F(phi | 1) = atanh(sin phi) for |phi| < pi/2; dF/dm is bounded there.
    delta = 10.0**-k
    ref = math.atanh(math.sin(phi))
    bound = delta * (1 + abs(ref)) * 1e2 / math.cos(phi) ** 2
    for p in (delta, -delta):
        assert abs(pendula.ellipfm1(phi, p) - ref) <= bound + 64 * EPS * (1 + abs(ref))
    assert abs(pendula.ellipf(phi, 1.0) - ref) <= 64 * EPS * (1 + abs(ref))


@SETTINGS
@given(m=ms)
def test_complete_integrals_and_complement_forms_agree(m):
    p = 1 - m  # exact for m in [-5, 1) up to one rounding of 1 - m
    assert abs(pendula.ellipk(m) - pendula.ellipkm1(p)) <= 8 * EPS * pendula.ellipk(m) * (1 + 1 / p)
    assert abs(pendula.ellipe(m) - pendula.ellipem1(p)) <= 8 * EPS * pendula.ellipe(m) * (1 + 1 / p)
    # F(pi/2 | m) = K(m) and F is odd in phi.
    assert abs(pendula.ellipf(math.pi / 2, m) - pendula.ellipk(m)) <= 16 * EPS * pendula.ellipk(m)
    assert pendula.ellipf(-0.7, m) == -pendula.ellipf(0.7, m)


@SETTINGS
@given(u=fin(-5.0, 5.0), m=fin(0.0, 0.99), n=st.integers(-3, 3))
def test_jacobi_periodicity(u, m, n):
    # sn and cn have period 4K, dn period 2K; sn(u + 2K) = -sn(u).
    K = pendula.ellipk(m)
    sn, cn, dn, _ = pendula.ellipj(u, m)
    sn4, cn4, dn4, _ = pendula.ellipj(u + 4 * n * K, m)
    sn2, cn2, dn2, _ = pendula.ellipj(u + 2 * K, m)
    tol = 64 * EPS * (1 + abs(u) + 4 * abs(n) * K) / (1 - m) ** 0.5
    assert abs(sn4 - sn) <= tol and abs(cn4 - cn) <= tol and abs(dn4 - dn) <= tol
    assert abs(sn2 + sn) <= tol and abs(cn2 + cn) <= tol and abs(dn2 - dn) <= tol


@SETTINGS
@given(u=us, m=fin(-10.0, 10.0))
def test_jacobi_time_reversal(u, m):
    # sn and am are odd in u, cn and dn even (DLMF 22.6.ii).
    a = pendula.ellipj(u, m)
    b = pendula.ellipj(-u, m)
    assert b[0] == -a[0] and b[1] == a[1] and b[2] == a[2] and b[3] == -a[3]


# ---- integrators -------------------------------------------------------------------------------------------
def _energy(theta, omega, w0):
    # Mechanical energy per m l^2 of the nonlinear pendulum, minimum 0 at rest.
    return 0.5 * omega**2 + 2 * w0**2 * np.sin(theta / 2) ** 2


@SETTINGS
@given(theta0=fin(-3.0, 3.0), omega0=fin(-3.0, 3.0), w0=fin(0.3, 3.0), gamma=fin(0.01, 3.0))
def test_rk4_energy_never_increases_with_damping(theta0, omega0, w0, gamma):
    # dE/dt = -gamma Omega^2 <= 0; RK4's local error at h = 0.01/max(w0, gamma)
    # (~1e-10 relative per step) must not make it rise.
    h = 0.01 / max(w0, gamma)
    t = np.linspace(0.0, 10.0 / w0, 201)
    r = pendula.rk4(t, theta0, omega0, w0, gamma, h)
    e = _energy(r.theta, r.omega, w0)
    e0 = _energy(theta0, omega0, w0)
    assert np.all(np.diff(e) <= 1e-9 * e0 + 1e-300), f"energy rose by {np.max(np.diff(e)) / e0:.3g}"


@needs_cvode
@SETTINGS
@given(theta0=fin(-3.0, 3.0), omega0=fin(-3.0, 3.0), w0=fin(0.3, 3.0), gamma=fin(0.01, 3.0))
def test_cvode_energy_never_increases_with_damping(theta0, omega0, w0, gamma):
    t = np.linspace(0.0, 10.0 / w0, 201)
    # atol scaled to the motion: an absolute 1e-13 would swamp a 1e-11 swing.
    # (At rest, or with energies that underflow, there is nothing to test.)
    s = scale(theta0, omega0, w0)
    assume(s > 1e-150)
    r = pendula.cvode(t, theta0, omega0, w0, gamma, rtol=1e-11, atol=1e-13 * s)
    e = _energy(r.theta, r.omega, w0)
    e0 = _energy(theta0, omega0, w0)
    assert np.all(np.diff(e) <= 1e-8 * e0 + 1e-300), f"energy rose by {np.max(np.diff(e)) / e0:.3g}"


@SETTINGS
@given(a=fin(-1.0, 1.0), b=fin(-1.0, 1.0), w0=fin(0.3, 3.0), gamma=fin(0.0, 8.0))
def test_integrators_agree_with_linear_closed_form_at_small_amplitude(a, b, w0, gamma):
    # theta0 = 1e-5 a: sin(theta) = theta (1 - theta^2/6), so the nonlinear
    # solution is the linear closed form up to ~ theta^3/6 ~ 2e-16 relative to
    # the amplitude; what remains is the integrator's own error.
    theta0, omega0 = 1e-5 * a, 1e-5 * b * w0
    assume(abs(a) + abs(b) > 1e-3)
    t = np.linspace(0.0, 8.0 / w0, 41)
    th, om = pendula.linear_damped(t, theta0, omega0, w0, gamma)
    s = scale(theta0, omega0, w0)
    h = 0.002 / max(w0, gamma)
    r = pendula.rk4(t, theta0, omega0, w0, gamma, h)
    # RK4 global error ~ (h max(w0, gamma))^4 * rate * T ~ 1e-10 here.
    np.testing.assert_allclose(r.theta, th, rtol=0, atol=1e-8 * s)
    np.testing.assert_allclose(r.omega, om, rtol=0, atol=1e-8 * s * max(w0, gamma))
    if HAVE_CVODE:
        c = pendula.cvode(t, theta0, omega0, w0, gamma, rtol=1e-11, atol=1e-13 * s, method="bdf")
        np.testing.assert_allclose(c.theta, th, rtol=0, atol=2e-7 * s)
        np.testing.assert_allclose(c.omega, om, rtol=0, atol=2e-7 * s * max(w0, gamma))


@SETTINGS
@given(theta0=fin(-2.5, 2.5), omega0=fin(-1.0, 1.0), w0=fin(0.3, 3.0), gamma=fin(0.0, 2.0))
def test_rk4_and_cvode_agree(theta0, omega0, w0, gamma):
    if not HAVE_CVODE:
        pytest.skip("CVODE not built")
    t = np.linspace(0.0, 10.0 / w0, 21)
    r = pendula.rk4(t, theta0, omega0, w0, gamma, 0.002 / w0)
    c = pendula.cvode(t, theta0, omega0, w0, gamma, rtol=1e-11, atol=1e-13 * max(scale(theta0, omega0, w0), 1e-100))
    np.testing.assert_allclose(r.theta, c.theta, rtol=0, atol=1e-7 * (1 + abs(theta0)))
    np.testing.assert_allclose(r.omega, c.omega, rtol=0, atol=1e-7 * w0 * (1 + abs(theta0)))


@SETTINGS
@given(theta0=fin(-2.0, 2.0), omega0=fin(-1.0, 1.0), w0=fin(0.3, 3.0), gamma=fin(0.0, 2.0), split=st.integers(1, 19))
def test_rk4_restart_is_consistent(theta0, omega0, w0, gamma, split):
    # Integrating [0, T] in one go or restarting from the state at t_k on the
    # same grid is the same sequence of steps (to rounding of the restart).
    t = np.linspace(0.0, 10.0 / w0, 21)
    h = 0.01 / w0
    full = pendula.rk4(t, theta0, omega0, w0, gamma, h)
    part = pendula.rk4(t[split:], full.theta[split], full.omega[split], w0, gamma, h)
    np.testing.assert_allclose(part.theta, full.theta[split:], rtol=0, atol=1e-12 * (1 + abs(theta0)))


# ---- exact undamped solution ----------------------------------------------------------------------------------
def _cond_scale(theta0, omega0, w0, t):
    # The exact solution's own sensitivity grows with the number of periods
    # (a phase error ~ eps w0 t) and near the separatrix; bound it generously.
    m = math.sin(theta0 / 2) ** 2 + (omega0 / (2 * w0)) ** 2
    return (1 + w0 * abs(t)) / max(abs(1 - m), 1e-6) ** 0.5


@SETTINGS
@given(
    theta0=fin(-6.0, 6.0),
    omega0=fin(-6.0, 6.0),
    w0=fin(0.2, 5.0),
    t=st.lists(fin(-50.0, 50.0), min_size=1, max_size=16),
)
def test_undamped_energy_is_constant(theta0, omega0, w0, t):
    t = np.array(t)
    th, om = pendula.undamped(t, theta0, omega0, w0)
    e0 = pendula.energy(theta0, omega0, w0)
    e = pendula.energy(th, om, w0)
    cond = max(_cond_scale(theta0, omega0, w0, x) for x in t)
    assert np.all(np.abs(e - e0) <= 64 * EPS * cond * (e0 + w0 * w0)), (e - e0) / e0


@SETTINGS
@given(theta0=fin(-3.1, 3.1), omega0=fin(-6.0, 6.0), w0=fin(0.2, 5.0), t=fin(0.0, 30.0))
def test_undamped_time_reversal(theta0, omega0, w0, t):
    # theta(-t; theta0, omega0) = theta(t; theta0, -omega0), omega flips sign.
    a_th, a_om = pendula.undamped(-t, theta0, omega0, w0)
    b_th, b_om = pendula.undamped(t, theta0, -omega0, w0)
    c = 64 * EPS * _cond_scale(theta0, omega0, w0, t)
    assert abs(a_th - b_th) <= c * (1 + abs(a_th))
    assert abs(a_om + b_om) <= c * (w0 + abs(a_om))


@SETTINGS
@given(theta0=fin(-3.0, 3.0), omega0=fin(-1.0, 1.0), w0=fin(0.2, 5.0), t=fin(0.0, 20.0), n=st.integers(1, 4))
def test_undamped_periodicity(theta0, omega0, w0, t, n):
    assume(pendula.regime(theta0, omega0, w0) == "libration")
    T = pendula.period(theta0, omega0, w0)
    assume(T < 1e3)
    th, om = pendula.undamped(t, theta0, omega0, w0)
    thn, omn = pendula.undamped(t + n * T, theta0, omega0, w0)
    c = 64 * EPS * _cond_scale(theta0, omega0, w0, t + n * T) * (1 + w0 * T)
    assert abs(thn - th) <= c * (1 + abs(th))
    assert abs(omn - om) <= c * (w0 + abs(om))


@SETTINGS
@given(w0=fin(0.2, 5.0), t=fin(0.0, 3.0), k=st.integers(4, 12))
def test_undamped_continuous_across_separatrix(w0, t, k):
    # theta0 = 0, omega0 = 2 w0 (1 -+ delta): libration just below, rotation
    # just above m = 1; at finite t both approach the separatrix motion
    # theta = 4 atan(tanh(w0 t / 2)) (the gudermannian, eq. 1.66's limit).
    delta = 10.0**-k
    ref = 4 * math.atan(math.tanh(w0 * t / 2))
    bound = 8 * delta * math.cosh(w0 * t) ** 2 + 1e-13
    for om0 in (2 * w0 * (1 - delta), 2 * w0 * (1 + delta)):
        th, _ = pendula.undamped(t, 0.0, om0, w0)
        assert abs(th - ref) <= bound, (om0, th, ref)
    th1, _ = pendula.undamped(t, 0.0, 2 * w0, w0)
    assert abs(th1 - ref) <= 1e-13


@SETTINGS
@given(theta0=fin(-3.0, 3.0), omega0=fin(-2.0, 2.0), w0=fin(0.3, 3.0))
def test_integrators_agree_with_exact_undamped(theta0, omega0, w0):
    t = np.linspace(0.0, 10.0 / w0, 21)
    th, om = pendula.undamped(t, theta0, omega0, w0)
    m = pendula.elliptic_parameter(theta0, omega0, w0)[1]
    assume(abs(m) > 1e-3)  # keep away from the separatrix (unbounded sensitivity)
    r = pendula.rk4(t, theta0, omega0, w0, 0.0, 0.002 / w0)
    tol = 1e-7 * (1 + abs(theta0) + abs(omega0) / w0) / abs(m)
    np.testing.assert_allclose(r.theta, th, rtol=0, atol=tol)
    np.testing.assert_allclose(r.omega, om, rtol=0, atol=tol * w0)
    if HAVE_CVODE:
        c = pendula.cvode(t, theta0, omega0, w0, 0.0, rtol=1e-11, atol=1e-13)
        np.testing.assert_allclose(c.theta, th, rtol=0, atol=10 * tol)
        np.testing.assert_allclose(c.omega, om, rtol=0, atol=10 * tol * w0)


@NO_SHRINK
@given(theta0=st.one_of(fin(-10.0, 10.0), fin(-1e300, 1e300)), omega0=fin(-10.0, 10.0), w0=fin(0.2, 5.0))
def test_elliptic_parameter_and_its_complement_add_to_one(theta0, omega0, w0):
    # m = sin^2(theta0/2) + (omega0/(2 w0))^2 depends on theta0 only modulo
    # 2 pi, which is exact for every double; (m, 1 - m) must stay consistent
    # (a complement that is not 1 - m is a garbage number, whatever theta0).
    m, mc = pendula.elliptic_parameter(theta0, omega0, w0)
    q = (omega0 / (2 * w0)) ** 2
    ref = math.sin(theta0 / 2) ** 2 + q
    assert abs(m - ref) <= 8 * EPS * max(1.0, ref), (m, ref)
    assert abs(m + mc - 1) <= 8 * EPS * max(1.0, m), (m, mc)


def test_small_angle_limit_of_undamped():
    # theta0 -> 0: the exact solution tends to the harmonic one, error ~ theta0^3.
    t = np.linspace(0.0, 20.0, 50)
    for a in (1e-2, 1e-4, 1e-6):
        th, _ = pendula.undamped(t, a, 0.0, 1.4)
        sa, _ = pendula.small_angle(t, a, 0.0, 1.4)
        assert np.max(np.abs(th - sa)) <= a**3 * (1 + 1.4 * 20.0) / 8 + 64 * EPS * a


FORTRAN_EXACT = r"""
program fortran_exact
  use pendula
  implicit none
  real(wp) :: u, m, sn, cn, dn, am, t, theta0, omega0, w0, th, om
  type(undamped_motion_t) :: mo
  type(status_t) :: st
  integer :: ios
  do
    read (*, *, iostat=ios) u, m, t, theta0, omega0, w0
    if (ios /= 0) exit
    call ellipj(u, m, sn, cn, dn, am)
    call undamped_init(mo, theta0, omega0, w0, st)
    th = -999; om = -999
    if (st%code == PENDULA_OK) call undamped_eval(mo, t, th, om)
    write (*, '(6(es25.17e3,1x))') sn, cn, dn, am, th, om
  end do
end program fortran_exact
"""


fortran_exact = _program_fixture("fortran_exact", FORTRAN_EXACT)


def test_fortran_and_python_paths_agree_elliptic_and_undamped(fortran_exact):
    rng = np.random.default_rng(99)
    n = 300
    u = rng.uniform(-30, 30, n)
    m = np.concatenate([rng.uniform(-3, 0.999, n - 40), 1 - 10.0 ** -rng.uniform(3, 15, 20), rng.uniform(1.0, 4.0, 20)])
    t = rng.uniform(-40, 40, n)
    theta0 = rng.uniform(-7, 7, n)
    omega0 = rng.uniform(-6, 6, n)
    w0 = rng.uniform(0.2, 5, n)
    f = _run_program(fortran_exact, zip(u, m, t, theta0, omega0, w0))
    py = np.array(pendula.ellipj(u, m)).T
    th, om = pendula.undamped(t, theta0, omega0, w0)
    # The Python API may take a different (vectorised) kernel than the
    # elemental Fortran procedure, so agreement is within the documented
    # accuracy, a few eps times the condition number (~ |u| for the Jacobi
    # functions, ~ w0 |t| for the motion); a conversion error in the Python
    # layer would be O(1).
    ju = 16 * EPS * (1 + np.abs(u))[:, None]
    assert np.all(np.abs(f[:, :4] - py) <= ju * (1 + np.abs(py))), np.max(np.abs(f[:, :4] - py) / ju)
    c = 64 * EPS * (1 + w0 * np.abs(t))
    assert np.all(np.abs(f[:, 4] - th) <= c * (1 + np.abs(th))), np.max(np.abs(f[:, 4] - th) / c)
    assert np.all(np.abs(f[:, 5] - om) <= c * (w0 + np.abs(om))), np.max(np.abs(f[:, 5] - om) / c)


FORTRAN_RK4 = r"""
program fortran_rk4
  use pendula
  implicit none
  real(wp) :: theta0, omega0, w0, gamma, h, t(5), th(5), om(5)
  type(ode_stats_t) :: stats
  type(status_t) :: st
  integer :: ios, i
  do
    read (*, *, iostat=ios) theta0, omega0, w0, gamma, h, t
    if (ios /= 0) exit
    call rk4_solve(t, theta0, omega0, w0, gamma, h, th, om, stats, st)
    if (st%code /= PENDULA_OK) then
      write (*, '(a)') 'error'
      cycle
    end if
    write (*, '(10(es25.17e3,1x))') (th(i), i = 1, 5), (om(i), i = 1, 5)
  end do
end program fortran_rk4
"""


fortran_rk4 = _program_fixture("fortran_rk4", FORTRAN_RK4)


def test_fortran_and_python_paths_agree_rk4(fortran_rk4):
    # Same steps in the same order on both paths: the results must be identical.
    rng = np.random.default_rng(5)
    rows, pys = [], []
    for _ in range(40):
        theta0, omega0 = rng.uniform(-3, 3), rng.uniform(-3, 3)
        w0, gamma = rng.uniform(0.3, 3), rng.uniform(0, 2)
        h = 0.3 / max(w0, gamma) * rng.uniform(0.1, 1)
        t = np.sort(rng.uniform(0, 20, 5))
        t[0] = 0.0
        rows.append([theta0, omega0, w0, gamma, h, *t])
        r = pendula.rk4(t, theta0, omega0, w0, gamma, h)
        pys.append(np.concatenate([r.theta, r.omega]))
    f = _run_program(fortran_rk4, rows)
    np.testing.assert_array_equal(f, np.array(pys))
