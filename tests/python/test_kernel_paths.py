"""Runtime CPU dispatch: every compiled variant of the batch RK4 kernel that
this machine can run (build_info()["kernel"]["available"]) is forced with
PENDULA_KERNEL in a fresh interpreter, reports itself in build_info(), and
returns the same bits as the baseline path and as pendula.rk4 state by state
(the variants differ in vector width only: -ffp-contract=off, no fast-math).
"""

import os
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
n = 61
k = np.arange(1, n + 1)
th0 = -3.1 + 6.2 * ((k * 7) % n) / n
om0 = -4.0 + 8.0 * ((k * 13) % n) / n
w0 = 0.5 + 2.5 * ((k * 5) % n) / n
gam = 0.4 * ((k * 11) % n) / n
h = np.full(n, 0.05)
gam[:5] = 0.0
th0[8] = 3.0e6          # beyond the table path's range: libm steps
om0[9] = 40.0           # fast rotation: libm steps
h[19:30] = [0.01, 0.02, 0.03, 0.07, 0.1, 0.125, 0.3, 0.25, 0.0333, 0.2, 0.06]
t = np.linspace(0.0, 30.0, 121)
r = _batch.rk4_batch(t, th0, om0, w0, gam, h, threads=1)
np.savez(sys.argv[1], theta=r.theta, omega=r.omega, steps=r.steps,
         path=pendula.build_info()["kernel"]["path"])
"""


def _run(tmp_path, path):
    out = tmp_path / f"{path}.npz"
    env = dict(os.environ, PENDULA_KERNEL=path)
    subprocess.run([sys.executable, "-c", _SCRIPT, str(out)], env=env, check=True, timeout=120)
    return np.load(out)


def test_build_info_reports_a_path():
    info = pendula.build_info()["kernel"]
    assert info["path"] in info["available"]
    assert info["available"][0] == "baseline"
    assert set(info["available"]) <= {"baseline", "v3", "v4"}


def test_every_path_gives_the_same_bits(tmp_path):
    available = pendula.build_info()["kernel"]["available"]
    base = _run(tmp_path, "baseline")
    assert str(base["path"]) == "baseline"
    # the baseline path against single-state pendula.rk4, bit for bit
    n = base["theta"].shape[0]
    k = np.arange(1, n + 1)
    th0 = -3.1 + 6.2 * ((k * 7) % n) / n
    om0 = -4.0 + 8.0 * ((k * 13) % n) / n
    w0 = 0.5 + 2.5 * ((k * 5) % n) / n
    gam = 0.4 * ((k * 11) % n) / n
    h = np.full(n, 0.05)
    gam[:5] = 0.0
    th0[8] = 3.0e6
    om0[9] = 40.0
    h[19:30] = [0.01, 0.02, 0.03, 0.07, 0.1, 0.125, 0.3, 0.25, 0.0333, 0.2, 0.06]
    t = np.linspace(0.0, 30.0, 121)
    for i in (0, 8, 9, 20, 26, 60):
        one = pendula.rk4(t, th0[i], om0[i], w0[i], gamma=gam[i], h=h[i])
        assert np.array_equal(one.theta, base["theta"][i])
        assert np.array_equal(one.omega, base["omega"][i])
    for path in available[1:]:
        got = _run(tmp_path, path)
        assert str(got["path"]) == path
        for key in ("theta", "omega", "steps"):
            assert np.array_equal(got[key], base[key]), (path, key)


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
