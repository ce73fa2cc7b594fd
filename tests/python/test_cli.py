"""The command line: python -m pendula {figures, period, solve, tradeoff}, help and errors."""

import csv
import math
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import pendula
from pendula import cli

W0 = np.sqrt(2.0)


def run(argv, capsys):
    """Run the CLI in-process; returns (exit code, stdout, stderr)."""
    try:
        code = cli.main(argv)
    except SystemExit as exc:  # argparse: --help (0) and bad flags (2)
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


# ---------------------------------------------------------------- help


def test_help_lists_subcommands_and_units(capsys):
    code, out, _ = run(["--help"], capsys)
    assert code == 0
    for word in ("figures", "period", "solve", "tradeoff", "sweep", "rad/s", "m/s^2", "kg/s"):
        assert word in out


@pytest.mark.parametrize(
    "sub, words",
    [
        ("figures", ["--out", "--quick", "PNG"]),
        ("period", ["--theta0", "rad", "rad/s", "m/s^2", "Times in s"]),
        ("solve", ["--theta0", "--t-end", "--tol", "--gamma", "kg/s", "--csv", "1/s"]),
        ("tradeoff", ["--theta0", "--csv", "--png", "wall time"]),
    ],
)
def test_subcommand_help_explains_flags_with_units(capsys, sub, words):
    code, out, _ = run([sub, "--help"], capsys)
    assert code == 0
    for w in words:
        assert w in out, f"{sub} --help lacks {w!r}"


def test_no_subcommand_prints_help_and_fails(capsys):
    code, out, _ = run([], capsys)
    assert code == 2 and "SUBCOMMAND" in out


def test_version(capsys):
    code, out, _ = run(["--version"], capsys)
    assert code == 0 and pendula.__version__ in out


# ---------------------------------------------------------------- period


def test_period_matches_library_and_writes_csv(capsys, tmp_path):
    path = tmp_path / "p.csv"
    code, out, _ = run(["period", "--theta0", "0.1", "1.0", "3.0", "--csv", str(path)], capsys)
    assert code == 0
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    assert [float(r["theta0_rad"]) for r in rows] == [0.1, 1.0, 3.0]
    exact = pendula.period(np.array([0.1, 1.0, 3.0]), 0.0, W0)
    got = np.array([float(r["T_exact_s"]) for r in rows])
    np.testing.assert_allclose(got, exact, rtol=1e-11)
    assert all(float(r["T0_small_angle_s"]) == pytest.approx(2 * np.pi / W0, rel=1e-12) for r in rows)
    assert "libration" in out


def test_period_rotation_and_custom_length(capsys):
    code, out, _ = run(["period", "--theta0", "0", "--omega0", "8", "--length", "1.0", "--g", "9.81"], capsys)
    assert code == 0
    w0 = np.sqrt(9.81)
    assert "rotation" in out
    assert f"{float(pendula.period(0.0, 8.0, w0)):.12g}" in out


# ---------------------------------------------------------------- errors


@pytest.mark.parametrize(
    "argv, expect",
    [
        (["period", "--theta0", "nan"], "--theta0: 'nan' is not a finite number"),
        (["period", "--theta0", "abc"], "--theta0: 'abc' is not an angle: give radians (1.57 or 1.57rad) or degrees"),
        (["period", "--theta0", "1", "--g", "-9.8"], "--g: '-9.8' must be > 0"),
        (["period", "--theta0", "1", "--length", "0"], "--length/-l: '0' must be > 0"),
        (["period"], "the following arguments are required: --theta0"),
        (["solve", "--theta0", "1"], "--t-end"),
        (["solve", "--theta0", "1", "--t-end", "5", "--n", "1"], "--n: '1' must be an integer in [2, 10000000]"),
        (["solve", "--theta0", "1", "--t-end", "5", "--tol", "0"], "--tol: '0' must be > 0"),
        (["solve", "--theta0", "1", "--t-end", "5", "--gamma", "-1"], "--gamma: '-1' must be >= 0"),
        (["solve", "--theta0", "1", "--t-end", "inf"], "--t-end: 'inf' is not a finite number"),
        (["bogus"], "invalid choice: 'bogus'"),
        (["period", "--theta0", "1", "--frobnicate"], "unrecognized arguments: --frobnicate"),
    ],
)
def test_bad_flags_exit_2_with_message(capsys, argv, expect):
    code, _, err = run(argv, capsys)
    assert code == 2
    assert expect in err


# The damping rule is the library's (scene_physics): mass and b together, and
# gamma with them only when it equals b/mass; the CLI passes the flags through.
@pytest.mark.parametrize(
    "extra, expect",
    [
        (["--gamma", "1", "--mass", "0.1", "--b", "0.01"], "disagree: give gamma, or mass and b, not both"),
        (["--b", "0.01"], "b is given without mass"),
        (["--mass", "0.1"], "mass is given without b"),
    ],
)
def test_inconsistent_damping_flags(capsys, extra, expect):
    code, _, err = run(["solve", "--theta0", "1", "--t-end", "5"] + extra, capsys)
    assert code == 2
    assert expect in err and err.startswith("pendula solve: error:")


def test_consistent_damping_flags_pass_through(capsys):
    """gamma with mass and b that agree is what the library allows: same answer as mass and b
    alone (the library then uses b/mass)."""
    base = ["solve", "--theta0", "0.1", "--t-end", "5", "--want", "final"]
    code, both, _ = run(base + ["--gamma", "0.1", "--mass", "0.1", "--b", "0.01"], capsys)
    assert code == 0
    code, alone, _ = run(base + ["--mass", "0.1", "--b", "0.01"], capsys)
    assert code == 0
    pick = [ln for ln in both.splitlines() if ln.startswith("final state")]
    assert pick and pick == [ln for ln in alone.splitlines() if ln.startswith("final state")]


def test_figures_errors(capsys, tmp_path):
    code, _, err = run(["figures"], capsys)
    assert code == 2 and "--out DIR is required" in err
    code, _, err = run(["figures", "--out", str(tmp_path), "--only", "fig03,fig99"], capsys)
    assert code == 2 and "unknown figure key(s) fig99" in err
    assert not any(tmp_path.iterdir())


def test_figures_list(capsys):
    code, out, _ = run(["figures", "--list"], capsys)
    assert code == 0
    for key in ["fig03", "fig09", "fig14", "fig15", "figA2", "figA4"]:
        assert key in out


# ---------------------------------------------------------------- figures


def test_figures_writes_pngs(capsys, tmp_path):
    pytest.importorskip("matplotlib")
    code, out, _ = run(["figures", "--out", str(tmp_path), "--quick", "--only", "fig03,fig10,figA3"], capsys)
    assert code == 0
    pngs = sorted(p.name for p in tmp_path.glob("*.png"))
    assert pngs == [
        "fig03_complete_elliptic_K_vs_k.png",
        "fig10_overdamped_gamma_3w0_theta_omega.png",
        "figA3_period_and_revolution_time_vs_energy_through_separatrix.png",
    ]
    for p in tmp_path.glob("*.png"):
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and p.stat().st_size > 10_000
    assert f"wrote 3 figure(s) to {tmp_path.resolve()}" in out


# ---------------------------------------------------------------- solve / tradeoff

needs_scenes = pytest.mark.skipif(
    not (hasattr(pendula, "Scene") and hasattr(pendula, "solve")), reason="the scenes module is not in this build"
)


@needs_scenes
def test_solve_undamped_csv_matches_exact(capsys, tmp_path):
    path = tmp_path / "s.csv"
    code, out, err = run(
        ["solve", "--theta0", "2.0", "--t-end", "10", "--n", "51", "--tol", "1e-8", "--csv", str(path)], capsys
    )
    assert code == 0, err
    assert "model:" in out and "reason:" in out
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    assert data.shape == (51, 3)
    np.testing.assert_allclose(data[:, 0], np.linspace(0, 10, 51), rtol=0, atol=1e-14)
    theta, omega = pendula.undamped(data[:, 0], 2.0, 0.0, W0)
    assert np.max(np.abs(data[:, 1] - theta)) <= 1e-7  # within 10 x tol
    assert np.max(np.abs(data[:, 2] - omega)) <= 1e-7 * W0 * 10


@needs_scenes
def test_solve_prints_table_with_mass_and_b(capsys):
    code, out, err = run(
        ["solve", "--theta0", "0", "--omega0", "2", "--t-end", "30", "--mass", "0.1", "--b", "0.01", "--n", "31"],
        capsys,
    )
    assert code == 0, err
    assert "t_s" in out and "theta_rad" in out and "..." in out


@needs_scenes
def test_tradeoff_writes_csv(capsys, tmp_path):
    path = tmp_path / "t.csv"
    code, out, err = run(["tradeoff", "--theta0", "1.0", "--t-end", "5", "--n", "11", "--csv", str(path)], capsys)
    assert code == 0, err
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    assert rows and all(float(r["sup_error_rad"]) >= 0 and float(r["wall_time_s"]) > 0 for r in rows)


# ---------------------------------------------------------------- python -m pendula


def test_python_dash_m_entry_point():
    proc = subprocess.run(
        [sys.executable, "-m", "pendula", "period", "--theta0", "1.0"], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    assert f"{float(pendula.period(1.0, 0.0, W0)):.12g}" in proc.stdout
    proc = subprocess.run(
        [sys.executable, "-m", "pendula", "period", "--theta0", "x"], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 2 and "'x' is not an angle" in proc.stderr


@needs_scenes
def test_solve_want_period_final_events(capsys, tmp_path):
    code, out, err = run(["solve", "--theta0", "2.0", "--t-end", "10", "--want", "period"], capsys)
    assert code == 0, err
    assert f"{float(pendula.period(2.0, 0.0, W0)):.12g}"[:12] in out
    code, out, err = run(["solve", "--theta0", "2.0", "--t-end", "10", "--want", "final", "--tol", "1e-9"], capsys)
    assert code == 0, err
    th, om = pendula.undamped(10.0, 2.0, 0.0, W0)
    line = [ln for ln in out.splitlines() if ln.startswith("final state")][0]
    assert abs(float(line.split("theta = ")[1].split(" rad")[0]) - th) < 1e-8
    path = tmp_path / "ev.csv"
    code, out, err = run(
        [
            "solve",
            "--theta0",
            "0",
            "--omega0",
            "2",
            "--t-end",
            "30",
            "--mass",
            "0.1",
            "--b",
            "0.01",
            "--want",
            "events",
            "--csv",
            str(path),
        ],
        capsys,
    )
    assert code == 0, err
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) > 10 and {r["kind"] for r in rows} == {
        "turning point (Omega = 0)",
        "zero crossing (theta = 0 mod 2 pi)",
    }
    assert all(float(a["t_s"]) < float(b["t_s"]) for a, b in zip(rows, rows[1:]))


def test_solve_rejects_unknown_model_and_want(capsys):
    code, _, err = run(["solve", "--theta0", "1", "--t-end", "5", "--model", "euler"], capsys)
    assert code == 2 and "--model: invalid choice: 'euler'" in err
    code, _, err = run(["solve", "--theta0", "1", "--t-end", "5", "--want", "everything"], capsys)
    assert code == 2 and "--want: invalid choice: 'everything'" in err


@needs_scenes
def test_solve_library_error_is_reported_not_raised(capsys):
    # the period of a damped motion is not defined: the library's ValueError becomes exit 2
    code, _, err = run(["solve", "--theta0", "1", "--t-end", "5", "--gamma", "0.5", "--want", "period"], capsys)
    assert code == 2 and err.startswith("pendula solve: error:")


def test_a_failing_figure_is_reported_and_the_others_drawn(capsys, tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    from pendula import figures

    def broken(out_dir, quick=False):
        raise ZeroDivisionError("deliberately broken")

    monkeypatch.setattr(figures, "FIGURES", [("fig03", figures.fig03_complete_elliptic_K), ("figXX", broken)])
    code, out, err = run(["figures", "--out", str(tmp_path), "--quick"], capsys)
    assert code == 1
    assert "not drawn: figXX: FAILED: ZeroDivisionError: deliberately broken" in out
    assert "1 figure(s) failed: figXX" in err
    assert (tmp_path / "fig03_complete_elliptic_K_vs_k.png").is_file()


@needs_scenes
def test_tradeoff_models_subset_and_errors(capsys, tmp_path):
    code, out, err = run(
        ["tradeoff", "--theta0", "0.5", "--t-end", "5", "--n", "11", "--models", "exact,rk4", "--repeat", "2"], capsys
    )
    assert code == 0, err
    lines = [ln.split()[0] for ln in out.splitlines()[2:] if ln.strip()]
    assert set(lines) == {"exact", "rk4"}
    code, _, err = run(["tradeoff", "--theta0", "0.5", "--t-end", "5", "--models", "euler"], capsys)
    assert code == 2 and "--models: unknown model(s) euler" in err
    code, _, err = run(["tradeoff", "--theta0", "0.5", "--t-end", "5", "--gamma", "1", "--models", "exact"], capsys)
    assert code == 2 and "do not apply" in err  # the library's ValueError, reported


# ---------------------------------------------------------------- output paths

_SOLVE = ["solve", "--theta0", "0.5", "--t-end", "2", "--n", "5"]
# a sweep of 3 x 2 starts over 1 s without its figure (add --out)
_SWEEP_3X2 = ["sweep", "--theta0", "0", "1", "3", "--omega0", "0", "1", "2", "--t-end", "1", "--no-png"]
_TRADEOFF = ["tradeoff", "--theta0", "0.5", "--t-end", "2", "--n", "5", "--models", "exact", "--repeat", "2"]


@pytest.mark.parametrize(
    "argv, option",
    [
        (["period", "--theta0", "0.1", "--csv"], "--csv"),
        (_SOLVE + ["--csv"], "--csv"),
        (_SOLVE + ["--png"], "--png"),
        (_TRADEOFF + ["--csv"], "--csv"),
        (_TRADEOFF + ["--png"], "--png"),
    ],
)
def test_output_into_a_missing_directory_is_refused_and_nothing_created(capsys, tmp_path, argv, option):
    # `solve --csv /nonexistent/dir/x.csv` created /nonexistent/dir: every option that
    # writes a file refuses a missing directory, naming the option, and creates nothing
    missing = tmp_path / "no" / "such"
    code, out, err = run(argv + [str(missing / "x.out")], capsys)
    assert code == 2
    assert option in err and "does not exist" in err and "--mkdir" in err
    assert not (tmp_path / "no").exists()
    assert out == ""  # refused before any work is printed


def test_mkdir_creates_the_directories_asked_for(capsys, tmp_path):
    path = tmp_path / "a" / "b" / "s.csv"
    code, out, err = run(_SOLVE + ["--csv", str(path), "--mkdir"], capsys)
    assert code == 0, err
    assert path.is_file()


@pytest.mark.parametrize(
    "argv, option, name",
    [
        (["period", "--theta0", "0.1"], "--csv", "period.csv"),
        (_SOLVE, "--csv", "solve.csv"),
        (_TRADEOFF, "--csv", "tradeoff.csv"),
    ],
)
def test_output_path_naming_a_folder_writes_inside_it(capsys, tmp_path, argv, option, name):
    # `--csv dir/ --mkdir` wrote a file named dir: a folder (existing, or a path ending
    # in /) gets the command's file inside it, never a file named like the folder
    code, out, err = run(argv + [option, str(tmp_path)], capsys)
    assert code == 0, err
    assert (tmp_path / name).is_file()
    code, out, err = run(argv + [option, str(tmp_path / "new") + "/", "--mkdir"], capsys)
    assert code == 0, err
    assert (tmp_path / "new").is_dir() and (tmp_path / "new" / name).is_file()
    code, out, err = run(argv + [option, str(tmp_path / "absent") + "/"], capsys)
    assert code == 2 and "--mkdir" in err and not (tmp_path / "absent").exists()


# ---------------------------------------------------------------- I/O errors, Ctrl-C: one line


def _one_line(err):
    lines = err.strip().splitlines()
    return len(lines) == 1 and "Traceback" not in err


@pytest.mark.parametrize(
    "argv",
    [
        ["period", "--theta0", "0.1", "--csv", "/proc/pendula-no-such.csv"],
        ["period", "--theta0", "0.1", "--csv", "/dev/full"],
        _SOLVE + ["--csv", "/dev/full"],
        _SWEEP_3X2 + ["--out", "/proc/pendula-basin"],
    ],
)
def test_io_errors_are_one_line_and_exit_1(argv):
    # a subprocess: the exit status and stderr exactly as a shell sees them
    if not pathlib.Path("/dev/full").exists() or not pathlib.Path("/proc").is_dir():
        pytest.skip("needs Linux's /dev/full and /proc")
    r = subprocess.run([sys.executable, "-m", "pendula", *argv], capture_output=True, text=True, timeout=120)
    assert r.returncode == 1, r.stderr
    assert _one_line(r.stderr) and "cannot write" in r.stderr
    assert argv[-1] in r.stderr  # names the file
    assert r.stderr.startswith(f"pendula {argv[0]}: error:")


@pytest.mark.parametrize("sub, target", [("sweep", "sweep"), ("period", "period"), ("solve", "solve")])
def test_ctrl_c_is_one_line_and_exit_130(capsys, tmp_path, monkeypatch, sub, target):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(pendula, target, interrupted)
    argv = {
        "sweep": _SWEEP_3X2 + ["--out", str(tmp_path / "sw")],
        "period": ["period", "--theta0", "0.1"],
        "solve": _SOLVE,
    }[sub]
    code, _, err = run(argv, capsys)
    assert code == 130 and _one_line(err) and "interrupted" in err


def test_ctrl_c_before_the_subcommand_runs_is_one_line_too(capsys, monkeypatch):
    def interrupted():
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "build_parser", interrupted)
    code, _, err = run(["period", "--theta0", "0.1"], capsys)
    assert code == 130 and _one_line(err) and err.startswith("pendula: interrupted")


def test_out_of_memory_is_one_line(capsys, tmp_path, monkeypatch):
    def refused(*args, **kwargs):
        raise MemoryError("out of memory: the outputs need 7.45 GiB (8000000000 bytes), which could not be allocated")

    monkeypatch.setattr(pendula, "sweep", refused)
    code, _, err = run(["sweep", "--out", str(tmp_path / "sw"), "--no-png"], capsys)
    assert code == 1 and _one_line(err) and "7.45 GiB" in err


# ---------------------------------------------------------------- exact decimals


def _numbers(text):
    return [tok for tok in text.replace(",", " ").split() if tok[:1].isdigit() or tok[:1] == "-"]


def test_period_writes_shortest_exact_decimals(capsys, tmp_path):
    # `period --csv` rounded to 10-12 digits: every number is now repr(float), so it reads back exactly
    path = tmp_path / "p.csv"
    code, out, err = run(["period", "--theta0", "0.1", "1.0", "3.0", "--omega0", "0.3", "--csv", str(path)], capsys)
    assert code == 0, err
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    w0 = pendula.natural_frequency(9.8, 4.9)
    exact = pendula.period(np.array([0.1, 1.0, 3.0]), 0.3, w0)
    assert [float(r["T_exact_s"]) for r in rows] == exact.tolist()  # bit for bit
    for r in rows:
        for key, text in r.items():
            if key != "motion":
                assert text == repr(float(text)), (key, text)  # shortest round trip
    table = [ln.split() for ln in out.splitlines() if ln.strip()[:1].isdigit()]
    assert [float(ln[-4]) for ln in table] == exact.tolist()  # the printed table too
    assert f"w0 = {w0!r} 1/s" in out


def test_tradeoff_table_prints_exact_decimals(capsys, tmp_path):
    code, out, err = run(_TRADEOFF + ["--models", "exact", "--csv", str(tmp_path / "t.csv")], capsys)
    assert code == 0, err
    with open(tmp_path / "t.csv") as fh:
        rows = list(csv.DictReader(fh))
    printed = [ln.split() for ln in out.splitlines() if ln.split()[:1] == ["exact"]]
    assert printed and rows
    assert [ln[-3] for ln in printed] == [r["sup_error_rad"] for r in rows]
    for r in rows:
        for key in ("sup_error_rad", "wall_time_s"):
            assert r[key] == repr(float(r[key])), (key, r[key])


# ---------------------------------------------------------------- sweep options

_SWEEP = ["sweep", "--t-end", "6", "--gamma", "0.3", "--no-png"]


def test_sweep_w0_threads_and_method_reach_the_library(capsys, tmp_path):
    th, om = np.linspace(-2, 2, 3), np.linspace(-3, 3, 4)
    code, out, err = run(
        _SWEEP
        + [
            "--theta0",
            "-2",
            "2",
            "3",
            "--omega0",
            "-3",
            "3",
            "4",
            "--w0",
            "2.5",
            "--threads",
            "1",
            "--method",
            "cvode",
            "--rtol",
            "1e-9",
            "--atol",
            "1e-12",
            "--out",
            str(tmp_path / "a"),
        ],
        capsys,
    )
    assert code == 0, err
    z = np.load(tmp_path / "a" / "sweep.npz")
    lib = pendula.sweep([0.0, 6.0], th[:, None], om[None, :], 2.5, 0.3, method="cvode", rtol=1e-9, atol=1e-12)
    assert np.array_equal(z["theta"], lib.theta) and float(z["w0"]) == 2.5 and str(z["method"]) == "cvode"
    assert "w0 = 2.5 1/s" in out and "cvode" in out
    code, _, err = run(_SWEEP + ["--w0", "2", "--g", "9.8", "--out", str(tmp_path / "b")], capsys)
    assert code == 2 and "--w0" in err and not (tmp_path / "b").exists()
    code, _, err = run(_SWEEP + ["--rtol", "1e-9", "--out", str(tmp_path / "c")], capsys)
    assert code == 2 and "--method cvode" in err
    code, _, err = run(_SWEEP + ["--threads", "-1", "--out", str(tmp_path / "d")], capsys)
    assert code == 2 and "--threads" in err


@pytest.mark.parametrize("fixed, axis", [("--theta0", 1), ("--omega0", 0)])
def test_sweep_over_one_axis(capsys, tmp_path, fixed, axis):
    grid = {"--theta0": ["-2", "2", "5"], "--omega0": ["-3", "3", "5"]}
    grid[fixed] = ["0.5"]
    code, out, err = run(
        [
            "sweep",
            "--t-end",
            "4",
            "--gamma",
            "0.3",
            "--theta0",
            *grid["--theta0"],
            "--omega0",
            *grid["--omega0"],
            "--out",
            str(tmp_path / "s"),
        ],
        capsys,
    )
    assert code == 0, err
    assert "5 starts" in out
    z = np.load(tmp_path / "s" / "sweep.npz")
    assert z["theta"].shape[axis] == 5 and z["theta"].size == 5
    th, om = np.asarray(z["theta0"]), np.asarray(z["omega0"])
    lib = pendula.sweep([0.0, 4.0], th[:, None], om[None, :], W0, 0.3, h=0.01)
    assert np.array_equal(z["theta"], lib.theta)
    assert (tmp_path / "s" / "basin.png").stat().st_size > 1000
    code, _, err = run(["sweep", "--theta0", "0", "1", "--out", str(tmp_path / "x")], capsys)
    assert code == 2 and "--theta0" in err and "LO HI N" in err


def test_figures_out_creates_the_folder_but_not_its_parents(capsys, tmp_path):
    code, _, err = run(["figures", "--out", str(tmp_path / "x" / "figs"), "--quick", "--only", "fig03"], capsys)
    assert code == 2 and "--out" in err and "--mkdir" in err
    assert not (tmp_path / "x").exists()
    code, _, err = run(["figures", "--out", str(tmp_path / "figs"), "--quick", "--only", "fig03"], capsys)
    assert code == 0, err
    assert (tmp_path / "figs").is_dir()


# ---------------------------------------------------------------- sweep


def test_sweep_writes_npz_csv_png_equal_to_the_library(capsys, tmp_path):
    out_dir = tmp_path / "sw"
    code, out, _ = run(
        [
            "sweep",
            "--theta0",
            "-3",
            "3",
            "7",
            "--omega0",
            "-5",
            "5",
            "5",
            "--t-end",
            "12",
            "--gamma",
            "0.2",
            "--h",
            "0.02",
            "--out",
            str(out_dir),
        ],
        capsys,
    )
    assert code == 0 and "35 starts" in out
    z = np.load(out_dir / "sweep.npz")
    th, om = np.linspace(-3, 3, 7), np.linspace(-5, 5, 5)
    lib = pendula.sweep([0.0, 12.0], th[:, None], om[None, :], W0, 0.2, h=0.02)
    assert np.array_equal(z["theta"], lib.theta) and np.array_equal(z["well"], lib.well)
    with open(out_dir / "sweep.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 35 and float(rows[-1]["theta_end_rad"]) == lib.theta[-1, -1]
    assert (out_dir / "basin.png").stat().st_size > 1000


def test_sweep_refuses_missing_parent_and_bad_grid(capsys, tmp_path):
    code, _, err = run(["sweep", "--out", str(tmp_path / "a" / "b")], capsys)
    assert code == 2 and "--mkdir" in err and not (tmp_path / "a").exists()
    code, _, err = run(["sweep", "--theta0", "1", "0", "5", "--out", str(tmp_path / "c")], capsys)
    assert code == 2 and "--theta0" in err
    code, _, _ = run(_SWEEP_3X2 + ["--mkdir", "--out", str(tmp_path / "d" / "e")], capsys)
    assert code == 0 and (tmp_path / "d" / "e" / "sweep.npz").exists()


# ---------------------------------------------------------------- degrees, v0, times for people


def _final_line(out):
    return [ln for ln in out.splitlines() if ln.startswith("final state")]


@pytest.mark.parametrize(
    "deg, rad",
    [
        ("90deg", "1.5707963267948966"),
        ("90°", "1.5707963267948966"),
        ("-45DEG", "-0.7853981633974483"),
        ("1.2rad", "1.2"),
        ("-1e-3", "-0.001"),
        ("-1e-1deg", repr(math.radians(-0.1))),
    ],
)
def test_theta0_in_degrees_is_the_same_scene(capsys, deg, rad):
    base = ["solve", "--t-end", "3", "--want", "final", "--theta0"]
    code, out_deg, err = run(base + [deg], capsys)
    assert code == 0, err
    code, out_rad, _ = run(base + [rad], capsys)
    assert _final_line(out_deg) and _final_line(out_deg) == _final_line(out_rad)


def test_degrees_everywhere(capsys, tmp_path):
    # period: one parser for every option
    code, out, err = run(
        ["period", "--theta0", "90deg", "2", "--omega0", "30deg/s", "--csv", str(tmp_path / "p.csv")], capsys
    )
    assert code == 0, err
    with open(tmp_path / "p.csv") as fh:
        rows = list(csv.DictReader(fh))
    expect = pendula.period(np.array([np.pi / 2, 2.0]), np.pi / 6, W0)
    np.testing.assert_allclose([float(r["T_exact_s"]) for r in rows], expect, rtol=1e-11)
    assert float(rows[0]["omega0_rad_per_s"]) == pytest.approx(np.pi / 6, rel=1e-10)
    # sweep: LO and HI in degrees, N a count; the grid is exactly the one in radians
    code, _, err = run(
        [
            "sweep",
            "--theta0",
            "-180deg",
            "180deg",
            "5",
            "--omega0",
            "-90deg/s",
            "90deg/s",
            "3",
            "--t-end",
            "1",
            "--no-png",
            "--out",
            str(tmp_path / "d"),
        ],
        capsys,
    )
    assert code == 0, err
    z = np.load(tmp_path / "d" / "sweep.npz")
    assert np.array_equal(z["theta0"], np.linspace(-np.pi, np.pi, 5))
    assert np.array_equal(z["omega0"], np.linspace(-np.pi / 2, np.pi / 2, 3))


@pytest.mark.parametrize(
    "argv, expect",
    [
        (["solve", "--theta0", "90degs"], "argument --theta0: '90degs' is not an angle: give radians"),
        (["solve", "--theta0", "deg"], "argument --theta0: 'deg' is not an angle"),
        (["solve", "--theta0", "1.2.3deg"], "argument --theta0: '1.2.3deg' is not an angle"),
        (["solve", "--theta0", "30deg/s"], "argument --theta0: '30deg/s' is not an angle"),
        (["solve", "--theta0", "-90dg"], "argument --theta0: '-90dg' is not an angle"),
        (["solve", "--theta0", "infdeg"], "argument --theta0: 'infdeg' is not a finite angle"),
        (
            ["solve", "--theta0", "1", "--omega0", "2deg"],
            "argument --omega0: '2deg' is not an angular velocity: give rad/s (0.5 or 0.5rad/s) or degrees per second",
        ),
        (["solve", "--theta0", "1", "--omega0", "nan"], "argument --omega0: 'nan' is not a finite number"),
        (["period", "--theta0", "1", "90grad"], "argument --theta0: '90grad' is not an angle"),
        (["sweep", "--theta0", "-180dg", "180deg", "3", "--out", "x"], "--theta0: '-180dg' is not an angle"),
        (["sweep", "--omega0", "0", "1deg", "3", "--out", "x"], "--omega0: '1deg' is not an angular velocity"),
    ],
)
def test_bad_angle_text_names_the_option(capsys, argv, expect):
    code, out, err = run(argv + ([] if argv[0] != "solve" else ["--t-end", "1"]), capsys)
    assert code == 2 and expect in err, err


@pytest.mark.parametrize("length", [4.9, 2.0])
def test_v0_is_the_launch_speed_of_the_text(capsys, length):
    """§1.3: Omega0 = v0 / l; E/E_sep = (v0 / (2 sqrt(g l)))^2 from the bottom."""
    v0 = 1.5 * float(W0) * 4.9  # the text's fig 9: v0 = 1.5 w0 l (l = 4.9 m)
    code, out, err = run(["period", "--theta0", "0", "--v0", repr(v0), "--length", repr(length)], capsys)
    assert code == 0, err
    assert f"Omega0 = v0/l = {v0 / length!r} rad/s" in out
    row = out.splitlines()[-1].split()
    assert float(row[1]) == pytest.approx(v0 / length, rel=1e-9)
    assert float(row[2]) == pytest.approx((v0 / (2 * math.sqrt(9.8 * length))) ** 2, rel=1e-9)
    base = ["solve", "--theta0", "0.2", "--t-end", "4", "--want", "final", "--length", repr(length)]
    code, out_v0, err = run(base + ["--v0", repr(v0)], capsys)
    assert code == 0, err
    code, out_om, _ = run(base + ["--omega0", repr(v0 / length)], capsys)
    assert _final_line(out_v0) and _final_line(out_v0) == _final_line(out_om)


@pytest.mark.parametrize("sub", ["solve", "tradeoff", "period"])
def test_v0_and_omega0_are_exclusive(capsys, sub):
    argv = [sub, "--theta0", "0", "--omega0", "1", "--v0", "2"] + ([] if sub == "period" else ["--t-end", "1"])
    code, out, err = run(argv, capsys)
    assert code == 2 and "argument --v0: not allowed with argument --omega0" in err and out == ""
    code, _, err = run([sub, "--theta0", "0", "--v0", "fast"] + ([] if sub == "period" else ["--t-end", "1"]), capsys)
    assert code == 2 and "argument --v0: 'fast' is not a number" in err


def test_printed_times_have_no_binary_noise_and_csv_keeps_full_precision(capsys, tmp_path):
    t = np.linspace(0.0, 30.0, 201)
    assert repr(float(t[3])) == "0.44999999999999996"  # the noise the table must not show
    argv = ["solve", "--theta0", "0.5", "--t-end", "30", "--n", "201"]
    code, out, err = run(argv, capsys)
    assert code == 0, err
    first = [ln.split()[0] for ln in out.splitlines() if ln.strip()[:1].isdigit()]
    assert first[:4] == ["0.00", "0.15", "0.30", "0.45"] and first[-1] == "30.00"
    assert "0.44999999999999996" not in out
    code, _, err = run(argv + ["--csv", str(tmp_path / "s.csv")], capsys)
    assert code == 0, err
    with open(tmp_path / "s.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert rows[3]["t_s"] == "0.44999999999999996"  # a data file: the times as computed
    assert np.array_equal([float(r["t_s"]) for r in rows], t)
    theta, _ = pendula.undamped(t, 0.5, 0.0, W0)
    assert np.max(np.abs(np.array([float(r["theta_rad"]) for r in rows]) - theta)) <= 1e-6


@pytest.mark.parametrize(
    "t_end, n, expect",
    [
        (30.0, 201, ["0.00", "0.15", "0.30"]),
        (0.3, 4, ["0.0", "0.1", "0.2", "0.3"]),
        (7.0, 8, ["0", "1", "2"]),
        (1e6, 3, ["0", "500000", "1000000"]),
        (1e5, 1_000_001, ["0.0", "0.1", "0.2"]),
        (1.0, 4, ["0.0", "0.3333333333333333", "0.6666666666666666", "1.0"]),  # not a decimal grid
    ],
)
def test_grid_times(t_end, n, expect):
    from pendula._cli_values import grid_times

    t = np.linspace(0.0, t_end, n)
    got = grid_times(t)
    assert got[: len(expect)] == expect
    # every string names its grid point: within 4 ulps of it and all distinct
    vals = np.array([float(x) for x in got])
    assert np.all(np.abs(vals - t) <= 4 * np.spacing(t_end)) and len(set(got)) == n


def test_solve_png_draws_the_motion(capsys, tmp_path):
    pytest.importorskip("matplotlib")
    path = tmp_path / "m.png"
    code, out, err = run(["solve", "--theta0", "0", "--v0", "10.4", "--t-end", "20", "--png", str(path)], capsys)
    assert code == 0, err
    assert f"wrote {path}" in out and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    code, _, err = run(["solve", "--theta0", "1", "--t-end", "5", "--want", "theta", "--png", str(path)], capsys)
    assert code == 0, err
    code, out, err = run(["solve", "--theta0", "1", "--t-end", "5", "--want", "period", "--png", str(path)], capsys)
    assert code == 2 and "--png draws a time series: give --want state, theta, energy, not period" in err
    assert out == ""


def test_png_without_matplotlib_names_the_extra(capsys, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    code, out, err = run(["solve", "--theta0", "1", "--t-end", "5", "--png", str(tmp_path / "m.png")], capsys)
    assert code == 2 and "--png needs matplotlib: pip install 'pendula[examples]'" in err and out == ""
    code, _, err = run(["figures", "--out", str(tmp_path / "f"), "--only", "fig03"], capsys)
    assert code == 2 and "drawing the figures needs matplotlib" in err
