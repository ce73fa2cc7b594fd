"""Runtime CPU dispatch: every compiled variant of the batch RK4 kernel that
this machine can run (build_info()["kernel"]["available"]) is forced with
PENDULA_KERNEL in a fresh interpreter, reports itself in build_info(), and
returns the same bits as the baseline path and as pendula.rk4 state by state
(the variants differ in vector width only: -ffp-contract=off, no fast-math).
Likewise the block kernel of the K and E array forms, the compensated AGM of K
in double-double for a block and the core of the Jacobi array forms (Maclaurin
start and duplications): the same bits on every path (also through
pendula.undamped over many distinct states and the Jacobi array forms), and on
every path the bits of the scalar Fortran functions (the Fortran test program
test_elliptic, run with each path when the meson build is there).  And the block
kernel of the elliptic parameter of undamped states, through elliptic_parameter,
amplitude, regime and period.
"""

import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import pendula

_SCRIPT = r"""
import sys
import numpy as np
import pendula
from pendula._many import kernels as _batch
sys.path.insert(0, sys.argv[2])
from test_kernel_paths import scenes
out = {"path": pendula.build_info()["kernel"]["path"]}
for name, (t, th0, om0, w0, gam, h) in scenes().items():
    r = _batch.rk4_batch(t, th0, om0, w0, gam, h, threads=1)
    out.update({f"{name}_theta": r.theta, f"{name}_omega": r.omega, f"{name}_steps": r.steps})
np.savez(sys.argv[1], **out)
"""


def scenes():
    """The batches every path runs: (t, theta0, omega0, w0, gamma, h) by name.

    mixed: each state its own w0, gamma and (some) h, one block, with states
    beyond the table path's range; shared: one w0, gamma and h for 300 states
    (several blocks, the block-wide constants); sweep: one h, w0 and gamma per
    state (constants per lane, equal substeps).
    """
    n = 61
    k = np.arange(1, n + 1)
    th0 = -3.1 + 6.2 * ((k * 7) % n) / n
    om0 = -4.0 + 8.0 * ((k * 13) % n) / n
    w0 = 0.5 + 2.5 * ((k * 5) % n) / n
    gam = 0.4 * ((k * 11) % n) / n
    h = np.full(n, 0.05)
    gam[:5] = 0.0
    th0[8] = 3.0e6  # beyond the table path's range: libm steps
    om0[9] = 40.0  # fast rotation: libm steps
    h[19:30] = [0.01, 0.02, 0.03, 0.07, 0.1, 0.125, 0.3, 0.25, 0.0333, 0.2, 0.06]
    t = np.linspace(0.0, 30.0, 121)
    m = 300
    j = np.arange(1, m + 1)
    th0s = -3.1 + 6.2 * ((j * 7) % m) / m
    om0s = -4.0 + 8.0 * ((j * 13) % m) / m
    th0s[17], om0s[200] = 3.0e6, 40.0
    ts = np.linspace(0.0, 10.0, 41)
    return {
        "mixed": (t, th0, om0, w0, gam, h),
        "shared": (ts, th0s, om0s, np.array([1.3]), np.array([0.2]), np.array([0.04])),
        "sweep": (ts, th0s, om0s, 0.5 + 2.5 * ((j * 5) % m) / m, 0.4 * ((j * 11) % m) / m, np.array([0.04])),
    }


def _run(tmp_path, path, script=None):
    """The npz that `script` (default _SCRIPT) writes in a fresh interpreter on kernel path `path`."""
    script = _SCRIPT if script is None else script
    out = tmp_path / f"{path}.npz"  # tmp_path is the test's own
    env = dict(os.environ, PENDULA_KERNEL=path)
    here = os.path.dirname(os.path.abspath(__file__))
    subprocess.run([sys.executable, "-c", script, str(out), here], env=env, check=True, timeout=120)
    return np.load(out)


def _other_paths_equal(tmp_path, base, script=None, equal_nan=False):
    """Every array of `base` (the baseline path's run) bit for bit on every other path."""
    for path in pendula.build_info()["kernel"]["available"][1:]:
        got = _run(tmp_path, path, script)
        assert str(got["path"]) == path
        for key in base.files:
            if key != "path":
                assert np.array_equal(got[key], base[key], equal_nan=equal_nan), (path, key)


def test_build_info_reports_a_path():
    info = pendula.build_info()["kernel"]
    assert info["path"] in info["available"]
    assert info["available"][0] == "baseline"
    assert set(info["available"]) <= {"baseline", "v3", "v4"}


def test_every_path_gives_the_same_bits(tmp_path):
    base = _run(tmp_path, "baseline")
    assert str(base["path"]) == "baseline"
    # the baseline path against single-state pendula.rk4, every state bit for bit
    for name, (t, th0, om0, w0, gam, h) in scenes().items():
        for i in range(th0.size):
            one = pendula.rk4(t, th0[i], om0[i], w0[i % w0.size], gamma=gam[i % gam.size], h=h[i % h.size])
            assert np.array_equal(one.theta, base[f"{name}_theta"][i]), (name, i)
            assert np.array_equal(one.omega, base[f"{name}_omega"][i]), (name, i)
    _other_paths_equal(tmp_path, base)


@pytest.mark.parametrize("value", ["v9", "AVX2", ""])
def test_unknown_request_runs_the_best_path(tmp_path, value):
    env = dict(os.environ, PENDULA_KERNEL=value)
    code = "import pendula; i = pendula.build_info()['kernel']; print(i['path'] == i['available'][-1])"
    out = subprocess.run([sys.executable, "-c", code], env=env, check=True, capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "True"


@pytest.mark.skipif(not pendula._many.kernels.openmp(), reason="no OpenMP in this build")
@pytest.mark.parametrize("user, want", [(None, "PASSIVE"), ("active", "ACTIVE")])
def test_openmp_threads_sleep_unless_the_user_chose(user, want):
    """libgomp (OMP_DISPLAY_ENV shows what it read at load) gets the passive wait
    policy when the user set none, the user's otherwise; os.environ is restored."""
    env = {k: v for k, v in os.environ.items() if k not in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT")}
    env["OMP_DISPLAY_ENV"] = "true"
    if user is not None:
        env["OMP_WAIT_POLICY"] = user
    code = "import os, pendula; print(os.environ.get('OMP_WAIT_POLICY'))"
    out = subprocess.run([sys.executable, "-c", code], env=env, check=True, capture_output=True, text=True, timeout=120)
    assert f"OMP_WAIT_POLICY = '{want}'" in out.stderr
    assert out.stdout.strip() == str(user)


_KE_SCRIPT = r"""
import sys
import numpy as np
import pendula
sys.path.insert(0, sys.argv[2])
from test_kernel_paths import ke_inputs
m, p = ke_inputs()
out = {"path": pendula.build_info()["kernel"]["path"]}
out.update(k=pendula.ellipk(m), e=pendula.ellipe(m), km1=pendula.ellipkm1(p), em1=pendula.ellipem1(p))
out.update(period=pendula.period(np.arccos(1 - 2 * p[(p > 0) & (p <= 1)]), 0.0, 1.0))
np.savez(sys.argv[1], **out)
"""


def ke_inputs():
    """m and p = 1 - m for the K and E block kernel: uniform m, blocks of mostly one
    kind (interval polynomial, logarithmic form) with a few of the other, subnormal
    complements, and the values outside the unit interval (0, 1, m < 0, NaN)."""
    rng = np.random.default_rng(7)
    m = rng.uniform(0.0, 1.0, 3000)
    m[::9] = 1 - 10.0 ** rng.uniform(-15, -1.5, m[::9].size)
    p = 10.0 ** rng.uniform(-320, 0, 3000)
    p[5::11] = rng.uniform(0.03, 1.0, p[5::11].size)
    p[[10, 20, 30]] = [5e-324, 1e-310, 2.2250738585072014e-308]
    m[[40, 41, 42, 43]] = [0.0, 1.0, -3.5, np.nan]
    p[[40, 41, 42, 43]] = [0.0, 1.0, 4.5, np.nan]
    return m, p


def test_elliptic_blocks_give_the_same_bits_on_every_path(tmp_path):
    base = _run(tmp_path, "baseline", _KE_SCRIPT)
    assert str(base["path"]) == "baseline"
    _other_paths_equal(tmp_path, base, _KE_SCRIPT, equal_nan=True)


_UNDAMPED_SCRIPT = r"""
import sys
import numpy as np
import pendula
sys.path.insert(0, sys.argv[2])
from test_kernel_paths import undamped_inputs
(t, th, om, w0), (u, p) = undamped_inputs()
out = {"path": pendula.build_info()["kernel"]["path"]}
out["theta"], out["omega"] = pendula.undamped(t, th, om, w0)
out["sn"], out["cn"], out["dn"], out["am"] = pendula.ellipjm1(u, p)
out["sn_m"], out["cn_m"], out["dn_m"], out["am_m"] = pendula.ellipj(u, 1 - p)
np.savez(sys.argv[1], **out)
"""


def undamped_inputs():
    """Distinct undamped states, one time each, and Jacobi arguments for the dispatched
    AGM and Jacobi core: librations (t in 0..100 s: most reductions need K in
    double-double), near the separatrix on both sides (1 - m down to ~1e-12), rotations,
    |theta0| > pi, negative and zero times, long times (1e4 s); u up to 1e5 with
    1 - m from 1e-300 to 1."""
    rng = np.random.default_rng(11)
    n = 2000
    th = rng.uniform(-3.1, 3.1, n)
    w0 = rng.uniform(0.5, 3.0, n)
    ratio = rng.uniform(-0.99, 0.99, n)
    ratio[::7] = np.sign(ratio[::7]) * (1 - 10.0 ** rng.uniform(-12, -1, ratio[::7].size))
    ratio[3::7] = np.sign(ratio[3::7]) * (1 + 10.0 ** rng.uniform(-12, 0.5, ratio[3::7].size))
    om = 2 * w0 * np.cos(th / 2) * ratio
    th[5::13] += rng.choice([-1, 1], th[5::13].size) * 2 * np.pi * rng.integers(1, 5, th[5::13].size)
    t = rng.uniform(0.0, 100.0, n)
    t[1::11] = -t[1::11]
    t[2::17] = rng.uniform(0, 1e4, t[2::17].size)
    t[::97] = 0.0
    u = rng.uniform(-1e5, 1e5, 1500)
    u[::3] = rng.uniform(-10, 10, u[::3].size)
    p = 10.0 ** rng.uniform(-300, 0, 1500)
    p[1::4] = rng.uniform(0.0, 1.0, p[1::4].size)
    return (t, th, om, w0), (u, p)


def test_undamped_states_and_jacobi_arrays_give_the_same_bits_on_every_path(tmp_path):
    base = _run(tmp_path, "baseline", _UNDAMPED_SCRIPT)
    assert str(base["path"]) == "baseline"
    assert np.isfinite(base["theta"]).all() and np.isfinite(base["sn"]).all()
    _other_paths_equal(tmp_path, base, _UNDAMPED_SCRIPT)


_PROPERTIES_SCRIPT = r"""
import sys
import numpy as np
import pendula
sys.path.insert(0, sys.argv[2])
from test_kernel_paths import properties_inputs
th, om, w0 = properties_inputs()
out = {"path": pendula.build_info()["kernel"]["path"]}
out["m"], out["mc"] = pendula.elliptic_parameter(th, om, w0)
out["amplitude"] = pendula.amplitude(th, om, w0)
out["regime"] = pendula.regime(th, om, w0)
out["period"] = pendula.period(th, om, w0)
np.savez(sys.argv[1], **out)
"""


def properties_inputs():
    """Undamped states for the dispatched elliptic-parameter block (half-angle sine and
    cosine, the double-double cosine near the separatrix, 1 - m): librations and
    rotations, near the separatrix on both sides (|q|/cos(theta0/2) within 1e-15 of 1,
    the double-double band 7/8..8/7 and its edges), Omega0 = 0, theta0 = +-0, |theta0| >=
    pi (the scalar path beside the block), huge and tiny w0 and Omega0 (free rotors, q
    beyond 1e150, w0 Omega0 beyond 1e290)."""
    rng = np.random.default_rng(13)
    n = 3000
    th = rng.uniform(-3.14, 3.14, n)
    w0 = rng.uniform(0.2, 5.0, n)
    ratio = rng.uniform(-1.5, 1.5, n)
    ratio[::5] = rng.choice([-1, 1], ratio[::5].size) * (
        1 + rng.choice([-1, 1], ratio[::5].size) * 10.0 ** rng.uniform(-15, -1, ratio[::5].size)
    )
    ratio[1::9] = rng.choice([0.875, 8 / 7, 0.8749999999, 1.1428572], ratio[1::9].size)
    ratio[2::11] = 0.0
    om = 2 * w0 * np.cos(th / 2) * ratio
    th[3::13] = rng.choice([-1, 1], th[3::13].size) * (np.pi + rng.uniform(0, 20, th[3::13].size))
    th[4::29] = np.pi * rng.choice([-1, 1], th[4::29].size)
    th[[0, 1]] = [0.0, -0.0]
    om[[0, 1]] = [0.0, 0.0]
    th[9::43] = 0.0
    om[9::43] = 2 * w0[9::43]  # on the separatrix exactly: q = 1 = cos(0)
    w0[6::31] = 10.0 ** rng.uniform(-300, -100, w0[6::31].size)
    w0[7::37] = 10.0 ** rng.uniform(100, 300, w0[7::37].size)
    om[8::41] = rng.choice([-1, 1], om[8::41].size) * 10.0 ** rng.uniform(140, 300, om[8::41].size)
    return th, om, w0


@pytest.mark.filterwarnings("ignore::pendula.AngleWarning")
def test_undamped_properties_give_the_same_bits_on_every_path(tmp_path):
    """elliptic_parameter, amplitude, regime and period (Omega0 != 0: the block kernel of
    the parameter) bit for bit on every path, and on the baseline path equal to the
    one-state functions (state_parameter's scalar set-up) state by state."""
    base = _run(tmp_path, "baseline", _PROPERTIES_SCRIPT)
    assert str(base["path"]) == "baseline"
    th, om, w0 = properties_inputs()
    for i in range(0, th.size, 7):
        m1, mc1 = pendula.elliptic_parameter(th[i], om[i], w0[i])
        assert (m1, mc1) == (base["m"][i], base["mc"][i]), i
        assert pendula.period(th[i], om[i], w0[i]) == base["period"][i], i
    regimes = set(base["regime"].tolist())
    assert len(regimes) == 3, regimes  # libration, separatrix and rotation all reached
    _other_paths_equal(tmp_path, base, _PROPERTIES_SCRIPT)


def _fortran_test(name):
    root = pathlib.Path(__file__).resolve().parents[2]
    for cand in (os.environ.get("PENDULA_BUILD_DIR"), root / "build" / "test", root / "build" / "dev"):
        if cand and (pathlib.Path(cand) / "tests" / name).is_file():
            return pathlib.Path(cand) / "tests" / name
    return None


def test_elliptic_arrays_equal_the_scalars_on_every_path():
    """test_elliptic checks the array forms against the scalar (baseline-compiled)
    K and E bit for bit, in mixed blocks too: run it on every path."""
    exe = _fortran_test("test_elliptic")
    if exe is None:
        pytest.skip("needs the meson build's Fortran tests (PENDULA_BUILD_DIR)")
    for path in pendula.build_info()["kernel"]["available"]:
        env = dict(os.environ, PENDULA_KERNEL=path)
        r = subprocess.run([str(exe)], env=env, capture_output=True, text=True, timeout=120)
        assert r.returncode == 0, (path, r.stdout[-2000:], r.stderr[-2000:])
