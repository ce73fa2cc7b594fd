"""Property-based tests (issue 9, hypothesis).

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
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import pendula

EPS = np.finfo(float).eps
SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
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
    for cand in (os.environ.get("PENDULA_BUILD_DIR"), ROOT / "build" / "robust", ROOT / "build" / "test"):
        if cand and (pathlib.Path(cand) / "src" / "libpendula_core.a").is_file():
            return pathlib.Path(cand)
    return None


def _sundials_libs():
    names = ["sundials_fcvode_mod", "sundials_cvode", "sundials_fnvecserial_mod", "sundials_nvecserial",
             "sundials_fsunmatrixdense_mod", "sundials_sunmatrixdense", "sundials_fsunlinsoldense_mod",
             "sundials_sunlinsoldense"]
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


@pytest.fixture(scope="module")
def fortran_linear(tmp_path_factory):
    return _fortran_program(tmp_path_factory, "fortran_linear", FORTRAN_LINEAR)


def test_fortran_and_python_paths_agree_linear(fortran_linear):
    rng = np.random.default_rng(2024)
    n = 300
    t = rng.uniform(0, 30, n)
    theta0 = rng.uniform(-3, 3, n)
    omega0 = rng.uniform(-5, 5, n)
    w0 = rng.uniform(0.1, 10, n)
    gamma = np.where(rng.random(n) < 0.2, 2 * w0, rng.uniform(0, 25, n))
    gamma[:10] = 0.0
    lines = "\n".join(" ".join(repr(float(v)) for v in row) for row in zip(t, theta0, omega0, w0, gamma))
    out = subprocess.run([str(fortran_linear)], input=lines + "\n", capture_output=True, text=True,
                         check=True).stdout.split("\n")
    f = np.array([[float(x) for x in line.split()] for line in out if line.strip()])
    th, om = pendula.linear_damped(t, theta0, omega0, w0, gamma)
    # Same archive, same compiler: only the 17-digit decimal round trip
    # separates the paths, which is exact; allow 2 ulps for a different -O.
    np.testing.assert_allclose(f[:, 0], th, rtol=4 * EPS, atol=4 * EPS * np.max(np.abs(th)))
    np.testing.assert_allclose(f[:, 1], om, rtol=4 * EPS, atol=4 * EPS * np.max(np.abs(om)))
