"""One home per fact: the codes, names and limits Python uses come from the
Fortran modules (pendula/_codes.py is generated from them at build time by
tools/gen/gen_codes.f90), and no Python source types a second copy.  Also the
scene facts that travel through _codes: the result's number array by name, the
event bound that caps the event slots (one solve up to 65536 events), and the
step/rtol fields of a result."""

import pathlib
import re

import numpy as np
import pytest

import pendula
from pendula import _codes
from pendula import scene as scene_mod

ROOT = pathlib.Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "python" / "pendula"
W0 = float(np.sqrt(2.0))


# ---------------------------------------------------------------- _codes == the Fortran sources


def _fortran_int_parameters(*files):
    """NAME -> value of every `integer, parameter :: A = 1, B = 2` in the files."""
    out = {}
    for f in files:
        text = re.sub(r"&\s*\n\s*", " ", (ROOT / f).read_text())
        for decl in re.findall(r"^\s*integer, parameter :: (.*)$", text, re.M):
            for name, value in re.findall(r"(\w+)\s*=\s*(-?\d+)\b(?!\s*[(\[])", decl):
                out[name] = int(value)
    return out


def _fortran_names(file, array):
    """The strings of a `character(...), parameter :: ARRAY(...) = [...]` list."""
    text = re.sub(r"&\s*\n\s*", " ", (ROOT / file).read_text())
    m = re.search(array + r"\([^)]*\)\s*=\s*\[character\(len=\d+\) ::(.*?)\]", text)
    assert m, array
    return re.findall(r"'(\w+)'", m.group(1))


def _fortran_real(file, name):
    m = re.search(name + r"\s*=\s*([0-9.e+-]+)(?:_wp)?", (ROOT / file).read_text())
    assert m, name
    return float(m.group(1))


CODES_F90 = "src/scene/pendula_scene_codes.f90"


def test_glue_selector_codes_match_the_fortran_include():
    glue = _fortran_int_parameters("python/f2py/pendula_glue_codes.inc")
    assert len(glue) >= 14
    for name, value in glue.items():
        assert getattr(_codes, name) == value, name
    # the selectors of one glue routine are distinct (the routine tells them apart)
    for group in (
        ("GLUE_ELLIPK", "GLUE_ELLIPKM1", "GLUE_ELLIPE", "GLUE_ELLIPEM1"),
        ("GLUE_PARAM_M", "GLUE_PARAM_P"),
        ("GLUE_JACOBI_AUTO", "GLUE_JACOBI_PLAN"),
        ("GLUE_SMALL_ANGLE_MOTION", "GLUE_SMALL_ANGLE_BOUND"),
        ("GLUE_PERIOD", "GLUE_AMPLITUDE"),
        ("GLUE_W0", "GLUE_GAMMA"),
    ):
        assert len({glue[n] for n in group}) == len(group), group


def test_status_event_and_method_codes_match_the_fortran():
    status = _fortran_int_parameters("src/core/pendula_status.f90")
    ode = _fortran_int_parameters("src/integrators/pendula_ode.f90")
    names = [n for n in status if n.startswith("PENDULA_ERR_")] + ["PENDULA_OK"]
    assert len(names) >= 10
    for n in names:
        assert getattr(_codes, n.replace("PENDULA_", "")) == status[n], n
    inc = (ROOT / "src" / "core" / "pendula_msg_len.inc").read_text()
    assert _codes.MSG_LEN == int(re.search(r"PENDULA_MSG_LEN\s*=\s*(\d+)", inc).group(1))
    assert (_codes.EVENT_TURNING, _codes.EVENT_ZERO) == (ode["PENDULA_EVENT_TURNING"], ode["PENDULA_EVENT_ZERO"])
    assert (_codes.CVODE_ADAMS, _codes.CVODE_BDF) == (ode["PENDULA_CVODE_ADAMS"], ode["PENDULA_CVODE_BDF"])


def test_scene_tables_match_the_fortran():
    ints = _fortran_int_parameters(CODES_F90)
    models = _fortran_names(CODES_F90, "SCENE_MODEL_NAMES")
    assert list(_codes.MODEL_CODES) == models
    for name, code in _codes.MODEL_CODES.items():
        assert ints["SCENE_MODEL_" + name.upper()] == code
    assert (
        _codes.MODEL_ALIASES
        == {"linear_damped": "linear"}
        == dict(zip(_fortran_names(CODES_F90, "SCENE_MODEL_ALIAS_NAMES"), ["linear"]))
    )
    wants = _fortran_names(CODES_F90, "SCENE_WANT_NAMES")
    assert list(_codes.WANT_CODES) == wants
    for name, code in _codes.WANT_CODES.items():
        assert ints["SCENE_WANT_" + name.upper()] == code
    info = _fortran_names(CODES_F90, "SCENE_INFO_NAMES")
    assert list(_codes.INFO) == info and len(info) == _codes.INFO_SIZE == ints["SCENE_INFO_SIZE"]
    for name, pos in _codes.INFO.items():
        assert ints["SCENE_INFO_" + name.upper()] == pos + 1
    for py, f in (
        ("RK4_STEP_LIMIT", "SCENE_RK4_STEP_LIMIT"),
        ("STEP_CAP", "SCENE_STEP_CAP"),
        ("CVODE_STEP_COST", "SCENE_CVODE_STEP_COST"),
        ("STIFF_RATIO", "SCENE_STIFF_RATIO"),
        ("TAYLOR_STEP_COST", "SCENE_TAYLOR_STEP_COST"),
        ("STIFF_RK4_STEPS", "SCENE_STIFF_RK4_STEPS"),
        ("LINEAR_SAFETY", "SCENE_LINEAR_SAFETY"),
    ):
        assert getattr(_codes, py) == _fortran_real(CODES_F90, f), py


def test_public_python_names_come_from_codes():
    from pendula import cli, integrate

    assert scene_mod.MODELS == cli.MODELS == tuple(n for n in _codes.MODEL_CODES if n != "auto")
    assert scene_mod.WANTS == cli.WANTS == tuple(_codes.WANT_CODES)
    assert (integrate.TURNING_POINT, integrate.ZERO_CROSSING) == (_codes.EVENT_TURNING, _codes.EVENT_ZERO)
    assert pendula.solve.__defaults__[1] == _codes.STEP_CAP


# ---------------------------------------------------------------- no second copy in python/pendula

_NAMES = "|".join(list(_codes.MODEL_CODES) + list(_codes.WANT_CODES) + ["adams", "bdf"])
SECOND_COPY = [
    # a name -> integer table ({"rk4": 4, ...})
    (re.compile(r"""["'](%s)["']\s*:\s*\d""" % _NAMES), "name -> code table"),
    # a status code or event kind typed as a number
    (re.compile(r"^\s*(OK|ERR_\w+|TURNING_POINT|ZERO_CROSSING|EVENT_\w+)\s*=\s*\d", re.M), "code constant"),
    # a model/want code tested by its number: code in (1, 2), model_code == 4
    (re.compile(r"\b\w*code\w*\s*(?:==|!=|in|not in)\s*\(?\s*\d"), "bare code test"),
    # the scene limits written out (they drift: 2e6 vs 2e8)
    (re.compile(r"\b(?:2e[689]|2\.0e[689]|2_000_000_000|200_000_000)\b"), "scene limit"),
]
# the limit pattern applies to the scene layer; integrate.py's rk4/cvode budgets are their own
LIMIT_FILES = ("scene.py", "_scene_types.py", "_scene_call.py", "cli.py")


def second_copies(files):
    found = []
    for f in files:
        text = f.read_text()
        for pattern, what in SECOND_COPY:
            if what == "scene limit" and f.name not in LIMIT_FILES:
                continue
            for m in pattern.finditer(text):
                line = text.count("\n", 0, m.start()) + 1
                found.append((f.name, line, what, m.group(0).strip()))
    return found


def test_no_second_copy_of_the_codes_in_python():
    files = sorted(p for p in PACKAGE.glob("*.py") if p.name != "_codes.py")
    assert {"scene.py", "cli.py", "integrate.py", "_errors.py"} <= {p.name for p in files}
    assert not (PACKAGE / "_codes.py").exists(), "_codes.py is generated in the build, not kept in the source"
    assert second_copies(files) == []


def test_the_second_copy_scan_is_not_blind(tmp_path):
    bad = tmp_path / "scene.py"
    bad.write_text(
        '_M = {"auto": 0, "rk4": 4}\nERR_DOMAIN = 2\nif code in (1, 2):\n    pass\n"""CVODE above 2e6 steps"""\n'
    )
    kinds = {what for _, _, what, _ in second_copies([bad])}
    assert kinds == {"name -> code table", "code constant", "bare code test", "scene limit"}


# ---------------------------------------------------------------- the event bound, one solve


def test_event_bound_holds_and_is_tight():
    """Sturm: turning points are >= pi/w0 apart, passes through the bottom at most one more
    plus one per full turn: 2 floor(w0 T/pi) + 3 + floor(Omega_max T/(2 pi)).  An undamped small
    swing reaches the swinging part up to the rounding of floor."""
    for theta0, omega0, gamma, periods in [
        (0.1, 0.0, 0.0, 10.25),
        (1.0, 0.5, 0.0, 7.0),
        (3.0, 0.0, 0.0, 3.0),
        (0.5, 0.0, 0.2, 20.0),
        (0.3, 2.0, 3.5, 5.0),
        (0.0, 4.0, 0.0, 6.0),
    ]:
        t_end = periods * 2 * np.pi / W0
        s = pendula.Scene(theta0=theta0, omega0=omega0, t=[t_end], gamma=gamma, tol=1e-8, want="events")
        res = pendula.solve(s)
        bound = int(pendula.scene._scene.scene_event_bound_f2py(s.w0, t_end, theta0, omega0))
        turns = np.hypot(omega0, 2 * s.w0 * np.sin(theta0 / 2)) * t_end / (2 * np.pi)
        assert bound == 2 * int(s.w0 * t_end / np.pi) + 3 + int(turns)
        assert len(res.events.t) <= bound, (theta0, omega0, gamma)
    s = pendula.Scene(theta0=0.1, t=[10.25 * 2 * np.pi / W0], tol=1e-8, want="events")
    n = len(pendula.solve(s).events.t)
    bound = int(pendula.scene._scene.scene_event_bound_f2py(s.w0, s.t[-1], s.theta0, s.omega0))
    assert n >= bound - 3 - int(np.hypot(0, 2 * s.w0 * np.sin(0.05)) * s.t[-1] / (2 * np.pi))


@pytest.mark.parametrize("gamma, model", [(0.0, None), (0.01, "rk4"), (0.01, None)])
def test_events_come_from_one_solve(monkeypatch, gamma, model):
    """The first event slots hold every event of such a window: the solve runs once."""
    calls = []
    real = scene_mod._scene.scene_solve_f2py

    def counted(*args):
        calls.append(args[11])  # m, the event slots
        return real(*args)

    monkeypatch.setattr(scene_mod._scene, "scene_solve_f2py", counted)
    s = pendula.Scene(theta0=0.2, t=[60 * 2 * np.pi / W0], gamma=gamma, tol=1e-6, want="events")
    res = pendula.solve(s, model=model)
    assert len(calls) == 1 and len(res.events.t) > 200 and calls[0] >= len(res.events.t)


def test_solve_checks_the_scene_in_fortran_only(monkeypatch):
    """solve() adds no check of its own: the rule (small_angle/exact need gamma = 0) is Fortran's."""
    calls = []
    real = scene_mod._scene.scene_check_f2py
    monkeypatch.setattr(scene_mod._scene, "scene_check_f2py", lambda *a: calls.append(a) or real(*a))
    damped = pendula.Scene(theta0=0.5, t=[1.0], gamma=0.1)
    assert len(calls) == 1  # the construction
    with pytest.raises(ValueError, match=r"model = exact needs gamma = 0 \(gamma = 1\.0+E-01\)"):
        pendula.solve(damped, model="exact")
    with pytest.raises(ValueError, match="model = small_angle needs gamma = 0"):
        pendula.run_model(damped, "small_angle")
    pendula.solve(damped)
    assert len(calls) == 1


def test_step_and_rtol_say_what_setting_is():
    s = pendula.Scene(theta0=0.5, t=np.linspace(0, 5, 11), gamma=0.1, tol=1e-8)
    rk = pendula.solve(s, model="rk4")
    assert rk.step == rk.setting > 0 and rk.rtol is None
    fixed = pendula.run_model(s, "rk4", 0.01)
    assert fixed.step == fixed.setting == 0.01 and fixed.rtol is None
    closed = pendula.solve(s, model="linear")
    assert closed.setting is None and closed.step is None and closed.rtol is None
    if pendula.have_cvode():
        cv = pendula.solve(s, model="cvode")
        assert cv.rtol == cv.setting > 0 and cv.step is None
        fixed = pendula.run_model(s, "cvode", 1e-7)
        assert fixed.rtol == fixed.setting == 1e-7 and fixed.step is None
