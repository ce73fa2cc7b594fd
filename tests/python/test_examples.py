"""The Python examples and the main job (examples/python/run_all.py), in --quick mode.

run_all.py runs once (module fixture, benchmarks skipped: they are exercised by
their own tests and by the main job) and every example's outputs are checked
from that run: exit status, the files it must write, PNG signatures and
non-empty CSV tables, and that missing library parts are reported, not faked.
"""

import csv
import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import load_file

import pendula

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "python"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"

HAVE_MPL = importlib.util.find_spec("matplotlib") is not None
HAVE_SCENES = hasattr(pendula, "Scene") and hasattr(pendula, "solve") and hasattr(pendula, "tradeoff")
HAVE_TEXTBOOK = importlib.util.find_spec("pendula.textbook") is not None

TEXT_FIGURES = [
    "fig03_complete_elliptic_K_vs_k.png",
    "fig04_period_exact_vs_small_angle_vs_sin_half_theta0.png",
    "fig05_theta_exact_vs_small_angle_small_theta0.png",
    "fig06_theta_exact_vs_small_angle_medium_theta0.png",
    "fig07_theta_exact_vs_small_angle_large_theta0.png",
    "fig08_theta_exact_vs_small_angle_all_theta0.png",
    "fig09_theta_launch_speed_v0_series.png",
    "fig10_overdamped_gamma_3w0_theta_omega.png",
    "fig11_overdamped_gamma_5w0_theta_omega.png",
    "fig12_overdamped_gamma_3w0_theta_and_phase_plane.png",
    "fig13_critical_damping_gamma_2w0_theta_omega.png",
]
LISTING_FIGURES = [
    "fig14_nonlinear_damped_theta_omega_correct_vs_text_listing.png",
    "fig15_nonlinear_damped_b0.05_theta_and_phase_plane_vs_text_listing.png",
]
EXTRA_FIGURES = [
    "figA1_underdamped_linear_theta_with_envelope.png",
    "figA2_phase_portrait_librations_separatrix_rotations.png",
    "figA3_period_and_revolution_time_vs_energy_through_separatrix.png",
]
LISTING_EXTRA = "figA5_text_listing_error_vs_time_vs_correct_rk4.png"
WORK_PRECISION = "figA4_work_precision_text_scene_b0.01.png"

TABLES = {
    "period_table.py": "period_table.csv",
    "exact_motion.py": "exact_motion.csv",
    "linear_damping.py": "linear_damping.csv",
    "integrators.py": "integrators_comparison.csv",
    "scene_solver.py": "scene_solver.csv",
    "fit_lab.py": "periods.csv",
}


def _run_all_module():
    return load_file(EXAMPLES / "run_all.py")


@pytest.fixture(scope="module")
def main_job(tmp_path_factory):
    out = tmp_path_factory.mktemp("main_job")
    env = dict(os.environ, MPLBACKEND="Agg")
    proc = subprocess.run(
        [sys.executable, str(EXAMPLES / "run_all.py"), "--out", str(out), "--quick", "--skip-benchmarks"],
        capture_output=True,
        text=True,
        timeout=600,
        env=env,
        cwd=str(out),
    )
    return out, proc


def _log(out, script):
    return (out / "logs" / (Path(script).stem + ".txt")).read_text()


def _check_png(path):
    assert path.is_file(), f"missing {path.name}"
    data = path.read_bytes()
    assert data[:8] == PNG_MAGIC, f"{path.name} is not a PNG"
    assert len(data) > 10_000, f"{path.name} is suspiciously small ({len(data)} bytes)"


def _check_csv(path, min_rows=3):
    assert path.is_file(), f"missing {path.name}"
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    assert len(rows) >= min_rows + 1, f"{path.name} has {len(rows) - 1} data rows"
    assert all(len(r) == len(rows[0]) for r in rows), f"{path.name}: ragged rows"
    return rows


def test_main_job_succeeds_and_prints_where_and_summary(main_job):
    out, proc = main_job
    if not HAVE_MPL:
        pytest.skip("matplotlib is not installed: the figure steps cannot run")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert f"Everything is in {out.resolve()}" in proc.stdout
    assert "| step | status | time (s) | files written | notes |" in proc.stdout
    assert (out / "summary.md").read_text().startswith("# pendula main job")
    assert "FAILED" not in proc.stdout
    assert "| highlight | value | compared with |" in proc.stdout
    assert "printed listing" in proc.stdout and "period at θ0 = 179°" in proc.stdout


@pytest.mark.parametrize("script", sorted(TABLES))
def test_table_examples(main_job, script):
    out, _ = main_job
    log = _log(out, script)
    assert "Traceback" not in log, log
    if script == "scene_solver.py" and not HAVE_SCENES:
        assert "not run: pendula.Scene" in log
        assert not (out / "tables" / TABLES[script]).exists()
        return
    _check_csv(out / "tables" / TABLES[script])
    assert "wrote" in log


def test_period_table_values(main_job):
    out, _ = main_job
    rows = _check_csv(out / "tables" / "period_table.csv", min_rows=10)
    import numpy as np

    th = np.array([float(r[1]) for r in rows[1:]])
    t_exact = np.array([float(r[2]) for r in rows[1:]])
    np.testing.assert_allclose(t_exact, pendula.period(th, 0.0, np.sqrt(2.0)), rtol=1e-14)


def test_integrators_example_shows_the_listing_drift(main_job):
    out, _ = main_job
    rows = _check_csv(out / "tables" / "integrators_comparison.csv", min_rows=5)
    by = {(r[0], r[1], r[3]): r for r in rows[1:]}
    rk4 = float(by[("text scene", "0.01", "rk4 h=0.05")][4])
    listing = float(by[("text scene", "0.01", "text listing as printed h=0.05")][4])
    assert rk4 < 1e-5  # the correct RK4 at the text's step
    assert listing > 1.0  # the printed listing is off by more than a radian


@pytest.mark.skipif(not HAVE_MPL, reason="matplotlib is not installed")
def test_text_figures(main_job):
    out, _ = main_job
    for name in TEXT_FIGURES:
        _check_png(out / "figures" / name)
    log = _log(out, "figures_text.py")
    for name in LISTING_FIGURES:
        if HAVE_TEXTBOOK:
            _check_png(out / "figures" / name)
        else:
            assert not (out / "figures" / name).exists()
            assert f"not drawn: {name[:5]}: pendula.textbook" in log


@pytest.mark.skipif(not HAVE_MPL, reason="matplotlib is not installed")
def test_extra_figures(main_job):
    out, _ = main_job
    for name in EXTRA_FIGURES:
        _check_png(out / "figures" / name)
    if HAVE_TEXTBOOK:
        _check_png(out / "figures" / LISTING_EXTRA)
    if HAVE_SCENES:
        _check_png(out / "figures" / WORK_PRECISION)
    else:
        assert not (out / "figures" / WORK_PRECISION).exists()
        assert "not drawn: figA4" in _log(out, "figures_extra.py")


def test_every_example_script_is_run_by_the_main_job():
    mod = _run_all_module()
    steps = mod._steps(quick=True, full_benchmarks=False, skip_benchmarks=False)
    labels = {label for label, *_ in steps}
    for path in EXAMPLES.glob("*.py"):
        if path.name != "run_all.py" and not path.name.startswith("_"):
            assert f"examples/python/{path.name}" in labels
    for path in (ROOT / "benchmarks").glob("bench_*.py"):
        step = [s for s in steps if s[0] == f"benchmarks/{path.name}"]
        assert step and step[0][2] == "benchmarks"
    for label, path, _, args in steps:  # --quick wherever the script accepts it
        assert args == (["--quick"] if "--quick" in path.read_text() else []), label


def test_run_all_reports_a_failing_step(tmp_path, monkeypatch):
    """A step that fails is reported (FAILED, exit 1) and the others still run."""
    mod = _run_all_module()
    bad = tmp_path / "bad_example.py"
    bad.write_text("import sys\nsys.exit('boom: bad example')\n")
    good = EXAMPLES / "period_table.py"
    monkeypatch.setattr(
        mod,
        "_steps",
        lambda *a: [("bad_example.py", bad, "tables", []), ("examples/python/period_table.py", good, "tables", [])],
    )
    out = tmp_path / "out"
    assert mod.main(["--out", str(out)]) == 1
    summary = (out / "summary.md").read_text()
    assert "| bad_example.py | FAILED |" in summary and "boom: bad example" in summary
    assert "| examples/python/period_table.py | ok |" in summary
    assert (out / "tables" / "period_table.csv").is_file()
