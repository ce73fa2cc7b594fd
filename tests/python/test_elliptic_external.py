"""External reference leg: other libraries' published elliptic test data.

Boost.Math and GSL test data (plus SciPy's own local.npz cases) for K, E, F and
sn, cn, dn in both the m and the complement (p = 1 - m) forms, converted with the
references moved to the exact double inputs (README beside the file).  The file is
test data from other projects: it is read from ``<repo>/../shared/reference-data/``
(or the folder named by PENDULA_REFERENCE_DATA) and never copied into this
repository; without it the leg skips with the reason shown.

Every row runs, with no exceptions list: |computed - ref| <= 16 eps * cond, where
cond = |f| + sum |x_i df/dx_i| at the double inputs (the file's ``cond`` column) and
ref = ref_hi + ref_lo.  The Jacobi rows run twice: elementwise (arrays u, m) and
through the one-parameter plan path (grouped by parameter).
"""

import importlib
import os
import pathlib

import numpy as np
import pytest

import pendula

_elliptic = importlib.import_module("pendula._fortran")  # the f2py extension (plan routines)
_codes = importlib.import_module("pendula._codes")  # its selector codes

EPS = 2.0**-52
TOL = 16.0
ROOT = pathlib.Path(__file__).resolve().parents[2]


def _data_file():
    folder = os.environ.get("PENDULA_REFERENCE_DATA") or str(ROOT.parent / "shared" / "reference-data")
    return pathlib.Path(folder) / "elliptic_external.npz"


_FILE = _data_file()
pytestmark = pytest.mark.skipif(
    not _FILE.is_file(),
    reason=f"external elliptic reference data not found at {_FILE} "
    "(set PENDULA_REFERENCE_DATA to the folder holding elliptic_external.npz)",
)


@pytest.fixture(scope="module")
def data():
    with np.load(_FILE, allow_pickle=False) as d:
        return {k: d[k] for k in ("func", "x", "ref_hi", "ref_lo", "cond", "source")}


JACOBI = {"sn": 0, "cn": 1, "dn": 2}
FUNCS = [
    "ellipk",
    "ellipkm1",
    "ellipe",
    "ellipem1",
    "ellipf",
    "ellipfm1",
    "ellipj.sn",
    "ellipj.cn",
    "ellipj.dn",
    "ellipjm1.sn",
    "ellipjm1.cn",
    "ellipjm1.dn",
]


def _evaluate(name, x, path="elementwise"):
    base, _, comp = name.partition(".")
    fn = getattr(pendula, base)
    if base in ("ellipk", "ellipkm1", "ellipe", "ellipem1"):
        return fn(x[:, 0])
    if base in ("ellipf", "ellipfm1"):
        return fn(x[:, 0], x[:, 1])
    if path == "elementwise":
        return fn(x[:, 0], x[:, 1])[JACOBI[comp]]
    # plan path: the one-parameter routine (table of Taylor polynomials) that pendula
    # picks for many u at one m, called directly so that every row goes through it
    which = _codes.GLUE_PARAM_P if base == "ellipjm1" else _codes.GLUE_PARAM_M
    out = np.empty(len(x))
    for p in np.unique(x[:, 1]):
        sel = np.flatnonzero(x[:, 1] == p)
        u = np.ascontiguousarray(x[sel, 0])
        res = tuple(np.empty(len(sel)) for _ in range(4))
        _elliptic.ellipj_one_into_f2py(which, _codes.GLUE_JACOBI_PLAN, u, p, *res)
        out[sel] = res[JACOBI[comp]]
    return out


def _check(data, name, path="elementwise"):
    sel = data["func"] == name
    assert sel.sum() > 0, f"no rows for {name}"
    x = data["x"][sel]
    ref = data["ref_hi"][sel] + data["ref_lo"][sel]
    cond = data["cond"][sel]
    got = _evaluate(name, x, path)
    err = np.abs(got - ref)
    ok = err <= TOL * EPS * cond
    ratio = np.where(cond > 0, err / (EPS * np.where(cond > 0, cond, 1)), np.where(err == 0, 0, np.inf))
    worst = float(np.max(ratio))
    bad = np.flatnonzero(~ok)
    detail = "\n".join(
        f"  {data['source'][sel][i]}: x = {x[i][~np.isnan(x[i])].tolist()} got {got[i]!r} "
        f"ref {ref[i]!r} err/(eps cond) = {ratio[i]:.3g}"
        for i in bad[:10]
    )
    assert not bad.size, f"{name} ({path}): {bad.size} of {sel.sum()} rows beyond {TOL} eps*cond:\n{detail}"
    print(f"{name} ({path}): {sel.sum()} rows, worst |err|/(eps cond) = {worst:.2f}")
    return worst


@pytest.mark.parametrize("name", FUNCS)
def test_external_reference_elementwise(data, name):
    _check(data, name)


@pytest.mark.parametrize("name", [f for f in FUNCS if f.startswith("ellipj")])
def test_external_reference_plan_path(data, name):
    _check(data, name, path="plan")


def test_external_reference_covers_every_function(data):
    # every function of the file is tested above (a new function in the data must be added)
    assert set(np.unique(data["func"]).tolist()) == set(FUNCS)
    assert len(data["func"]) >= 20000
