"""Bad input, everywhere: every public function of ``pendula``.

The table ``API`` below has one entry per public callable in ``pendula.__all__``.
Each entry gives a call that must succeed (finite results) and, per argument,
a *kind* (finite real, > 0, >= 0, increasing times, ...).  From the kinds the
test generates the bad inputs: NaN and +-Inf, wrong signs, strings, None,
complex numbers, object and string arrays, arrays with one NaN element, empty
arrays, 2-D arrays where 1-D times are wanted, non-increasing and repeated
times, incompatible shapes, out-of-range choices and counts.  Each must raise
ValueError or TypeError whose message names the argument (or the name the
Fortran core uses for it) -- never a silent NaN, garbage, a crash.  Array
arguments are passed as numpy arrays and compared with copies afterwards: the
library must never modify its input.

Elliptic special functions follow their own documented rule (NaN in -> NaN
out, finite out-of-domain -> ValueError); their entries say so with
``nan="propagate"``.

A new public function without an entry here, or an entry that declares no
checked argument, FAILS ``test_every_public_callable_has_an_entry``: add it to
the table (that is the point).
"""

from __future__ import annotations

import dataclasses
import inspect
import numbers
import re

import numpy as np
import pytest
from api_table import (
    ALL_CASES,
    API,
    NONNEG,
    NOT_ENTRY_POINTS,
    POS,
    REAL,
    _as_array_arg,
    _call,
    _materialise,
    _walk_numbers,
)
from helpers import HAVE_CVODE, ROOT, fortran_statements

import pendula

# ---- helpers --------------------------------------------------------------------


def _public_callables():
    out = {}
    for name in pendula.__all__:
        obj = getattr(pendula, name)
        # Result records (dataclasses) carry no checks of their own.
        if inspect.isclass(obj) and dataclasses.is_dataclass(obj):
            continue
        if callable(obj) and name not in NOT_ENTRY_POINTS:
            out[name] = obj
    return out


def _all_nan(result):
    vals = list(_walk_numbers(result))
    return bool(vals) and all(isinstance(v, numbers.Number) and v != v for v in vals)


def _snapshot(kwargs):
    # zero-stride views of 2**31 elements are read-only and never copied
    return {k: np.array(v, copy=True) for k, v in kwargs.items() if isinstance(v, np.ndarray) and v.size < 10**6}


def _assert_unmodified(kwargs, snap):
    for k, before in snap.items():
        after = kwargs[k]
        assert after.shape == before.shape and after.dtype == before.dtype, (
            f"argument {k} changed shape/dtype in the call"
        )
        if before.dtype.kind in "fc":
            assert np.array_equal(after, before, equal_nan=True), f"argument {k} was modified in place"
        else:
            assert all(a is b or a == b for a, b in zip(after.ravel(), before.ravel())), (
                f"argument {k} was modified in place"
            )


def _skip_if_unavailable(entry):
    if entry.needs_cvode and not HAVE_CVODE:
        pytest.skip("CVODE not built")


# ---- the tests -------------------------------------------------------------------------
def test_every_public_callable_has_an_entry():
    public = _public_callables()
    missing = sorted(set(public) - set(API))
    assert not missing, f"public functions without a bad-input entry in tests/python/test_bad_input.py: {missing}"
    stale = sorted(set(API) - set(public))
    assert not stale, f"table entries that are not public callables: {stale}"
    for name, entry in API.items():
        assert entry.args, f"{name}: an entry must declare at least one checked argument"
        sig = inspect.signature(public[name])
        params = {p.name for p in sig.parameters.values() if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)}
        unknown = set(entry.args) - params
        assert not unknown, f"{name}: table names arguments it does not have: {unknown}"
        # Every real-valued or array parameter must be checked (or excused).
        for p in sig.parameters.values():
            if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
                continue
            if p.name in entry.args or p.name in entry.unchecked:
                continue
            d = p.default
            assert d is None or isinstance(d, (bool, str)), (
                f"{name}({p.name}=...) has no entry in the bad-input table "
                "(add it to args, or to unchecked with a reason)"
            )


@pytest.mark.parametrize("fname", sorted(API))
def test_valid_call_gives_finite_results_and_keeps_inputs(fname):
    entry = API[fname]
    _skip_if_unavailable(entry)
    kwargs = {k: _materialise(v) for k, v in entry.valid.items()}
    snap = _snapshot(kwargs)
    result = _call(fname, kwargs)
    _assert_unmodified(kwargs, snap)
    vals = list(_walk_numbers(result))
    is_text = isinstance(result, str) or (isinstance(result, np.ndarray) and result.dtype.kind in "UO")
    assert vals or is_text, f"{fname}: the valid call returned no numbers"
    assert all(np.isfinite(v) for v in vals), f"{fname}: the valid call returned non-finite values"
    # Array variants of array arguments: broadcasting keeps them untouched too.
    for aname, spec in entry.args.items():
        if spec.array and aname in entry.valid:  # (an optional one left out stays out)
            kw = dict(kwargs)
            kw[aname] = _as_array_arg(entry.valid[aname])
            snap = _snapshot(kw)
            res = _call(fname, kw)
            _assert_unmodified(kw, snap)
            assert all(np.isfinite(v) for v in _walk_numbers(res))


def _names_argument(msg, aname, spec):
    low = msg.lower()
    names = (aname,) + tuple(spec.aliases)
    for n in names:
        if re.search(r"(?<![A-Za-z0-9_])" + re.escape(n.lower()) + r"(?![A-Za-z0-9_])", low):
            return True
    return False


_RAISED = object()


def _result_or_named_error(case, kwargs, spec):
    """The call's result, or _RAISED when it raised a ValueError that names case.arg."""
    try:
        return _call(case.func, kwargs)
    except ValueError as exc:
        assert _names_argument(str(exc), case.arg, spec), f"{case.id}: message does not name {case.arg!r}: {exc}"
    return _RAISED


@pytest.mark.parametrize("case", ALL_CASES, ids=[c.id for c in ALL_CASES])
def test_bad_input(case):
    entry = API[case.func]
    _skip_if_unavailable(entry)
    spec = entry.args[case.arg]
    kwargs = {k: _materialise(v) for k, v in entry.valid.items()}
    kwargs.update(case.others)
    kwargs[case.arg] = case.value
    snap = _snapshot(kwargs)
    expect = case.expect
    if expect == "nan":
        result = _call(case.func, kwargs)
        assert _all_nan(result), f"{case.id}: NaN in must give NaN out, got {result!r}"
    elif expect == "nan-element":
        result = _call(case.func, kwargs)
        arr = np.asarray(result, dtype=float)
        assert np.isnan(arr[..., 1]).all() and np.isfinite(arr[..., 0]).all(), (
            f"{case.id}: NaN element must give NaN only there, got {result!r}"
        )
    elif expect == "error-or-empty":
        result = _result_or_named_error(case, kwargs, spec)
        if result is not _RAISED:
            vals = list(_walk_numbers(result))
            assert not vals or all(np.isfinite(v) for v in vals)
            parts = result if isinstance(result, tuple) else (result,)
            if dataclasses.is_dataclass(result):  # a result object: its arrays
                parts = [v for v in vars(result).values() if isinstance(v, np.ndarray)]
            arrs = [np.asarray(r) for r in parts]
            for attr in ("codes", "scenes"):  # a batch (result): its status or scene array is the batch
                if hasattr(result, attr):
                    arrs.append(np.asarray(getattr(result, attr)))
            assert any(a.size == 0 for a in arrs), (
                f"{case.id}: empty input must give an empty result or ValueError, got {result!r}"
            )
    elif expect == "error-or-defined":
        result = _result_or_named_error(case, kwargs, spec)
        if result is not _RAISED:
            vals = list(_walk_numbers(result))
            assert vals and not any(v != v for v in vals), (
                f"{case.id}: must raise ValueError or give a defined (non-NaN) value, got {result!r}"
            )
    else:
        exc_types = expect
        with pytest.raises(exc_types) as info:
            result = _call(case.func, kwargs)
            pytest.fail(f"{case.id}: no exception, returned {result!r}")  # pragma: no cover
        msg = str(info.value)
        if case.arg in case.others or case.label.startswith("shape-mismatch"):
            assert _names_argument(msg, case.arg, spec) or "shape" in msg.lower() or "broadcast" in msg.lower()
        else:
            assert _names_argument(msg, case.arg, spec), f"{case.id}: message does not name {case.arg!r}: {msg!r}"
    _assert_unmodified(kwargs, snap)


# ---- extreme but valid values -------------------------------------------------------------------
EXTREMES = {
    REAL: (1e300, -1e300, 1e-300, -5e-324, 1e20),
    POS: (1e-300, 5e-324, 1e300, 1e154, 1e-10, 1e10),
    NONNEG: (0.0, 5e-324, 1e300, 1e10),
}
EXTREME_CASES = [
    (f, a, x)
    for f, e in API.items()
    for a, spec in e.args.items()
    for x in (spec.extremes if spec.extremes is not None else EXTREMES.get(spec.kind, ()))
    if x not in spec.out_of_domain
]
# A number printed without its exponent letter ("1.00000+300", Fortran's Ew.d
# for 3-digit exponents) is garbage in a message.
_MANGLED = re.compile(r"\d[+-]\d{3}(?![\d.])")


@pytest.mark.parametrize("fname, arg, value", EXTREME_CASES, ids=[f"{f}-{a}-{x!r}" for f, a, x in EXTREME_CASES])
def test_extreme_valid_values(fname, arg, value):
    """Huge, tiny and subnormal values inside the domain: a result without NaN,
    or a clear error (ValueError naming the argument, or PendulaSolverError
    when an integrator cannot do it) -- never a silent NaN."""
    entry = API[fname]
    _skip_if_unavailable(entry)
    kwargs = {k: _materialise(v) for k, v in entry.valid.items()}
    kwargs.update(entry.args[arg].others)
    kwargs[arg] = value
    try:
        result = _call(fname, kwargs)
    except ValueError as exc:
        msg = str(exc)
        assert not _MANGLED.search(msg), f"{fname}({arg}={value!r}): mangled number in message: {msg}"
        # Scene(g=5e-324) said "w0 = 0 is out of range": a refusal names what was given
        assert _names_argument(msg, arg, entry.args[arg]), f"{fname}({arg}={value!r}): {msg}"
    except pendula.PendulaSolverError as exc:
        msg = str(exc)
        assert not _MANGLED.search(msg), f"{fname}({arg}={value!r}): mangled number in message: {msg}"
    else:
        vals = list(_walk_numbers(result))
        nan = [v for v in vals if v != v]
        assert not nan, f"{fname}({arg}={value!r}): silent NaN in the result {result!r}"


def test_case_count_report():
    """Not a check of the library: records how much this file tries."""
    n_entry = len(API)
    n_cases = len(ALL_CASES)
    print(f"\nbad-input table: {n_entry} entry points, {n_cases} bad inputs, {len(EXTREME_CASES)} extreme valid values")
    assert n_cases >= 10 * n_entry


# ---- the Fortran API (`use pendula`): every non-elemental procedure reports a status -----------------------------
# House rule: non-elemental Fortran procedures take a type(status_t) argument
# (message naming the argument and its range).  Elemental procedures cannot
# carry one and follow their documented value rule (NaN in -> NaN out, or a
# documented limit), which the concern tests check.  Exemptions, with reasons:
FORTRAN_NO_STATUS = {
    # total functions of integer codes / no arguments
    "cancel_requested": "total: reads the cancel flag of a control array",
    "add_progress": "total: adds to the progress counter of a control array",
    "rk4_batch_openmp": "no arguments (build constant)",
    "code_name": "total function of a status code",
    "regime_name": "total function of a regime code",
    "equilibrium_type_name": "total function of a type code",
    "undamped_regime_name": "total function of a regime code",
    "scene_model_code": "total function of a name",
    "scene_model_name": "total function of a code",
    "scene_want_code": "total function of a name",
    "scene_want_name": "total function of a code",
    "cvode_available": "no arguments",
    "kernel_path": "no arguments (chosen once at load time)",
    "kernel_path_available": "total function of a kernel path code",
    # the batch RK4 block kernel of the running path: rk4_batch_solve checks the states first
    "rk4_lanes": "unchecked kernel behind rk4_batch_solve (pendula_dispatch)",
    "rk4_lanes_width": "no arguments (the running kernel path's block width)",
    "taylor_series_lanes": "unchecked series kernel behind taylor_batch_solve (pendula_dispatch)",
    "ke_block_lanes": "unchecked block kernel behind the K and E array forms (pendula_dispatch)",
    "k_dd_block_lanes": "unchecked AGM kernel behind k_double_double_block (pendula_dispatch)",
    "core_block_lanes": "unchecked block kernel behind the Jacobi array forms (pendula_dispatch)",
    "libration_block_lanes": "unchecked block kernel behind undamped_states (pendula_dispatch)",
    "parameter_block_lanes": "unchecked block kernel behind parameter_lanes (pendula_dispatch)",
    # the elliptic functions' own rule (NaN in -> NaN out, out of domain -> NaN; Python raises)
    "ellipj_plan": "elliptic rule",
    "ellipj_planm1": "elliptic rule",
    # whether a Jacobi plan pays off: a total decision on (m, n) for any m and n
    "ellipj_plan_pays": "total decision",
    "ellipjm1_plan_pays": "total decision",
    # the same for a motion built (and checked) by undamped_init, and adding that plan to it
    "undamped_plan_pays": "total decision on a checked motion",
    "undamped_add_plan": "acts on a motion undamped_init built and checked",
    # documented unchecked kernels with a checked entry point (reported to their concerns)
    "linear_eigenvalues": "helper of rk4_max_stable_step on checked inputs",
}


def _fortran_public_procedures():
    """(file, name, info) for every procedure that `use pendula` exports: the
    union of the public lists of the modules the umbrella uses (facades such as
    pendula_integrators re-export their modules' names)."""
    files = sorted(p for p in (ROOT / "src").rglob("*") if p.suffix in (".f90", ".F90"))
    parsed = {f: fortran_statements(f.read_text()) for f in files}
    module_file, public_of = {}, {}
    for f, lines in parsed.items():
        mod = None
        for _, st in lines:
            m = re.match(r"module\s+(?!procedure)(\w+)\s*$", st, re.I)
            if m:
                mod = m.group(1).lower()
                module_file.setdefault(mod, set()).add(f)  # pendula_cvode has a stub twin
                public_of.setdefault(mod, set())
            m = re.match(r"public\s*::\s*(.*)", st, re.I)
            if m and mod:
                public_of[mod] |= {x.strip().lower() for x in m.group(1).split(",")}
    umbrella = [
        re.match(r"use\s+(\w+)", st, re.I).group(1).lower()
        for _, st in parsed[ROOT / "src" / "pendula.f90"]
        if re.match(r"use\s+\w+", st, re.I)
    ]
    exported = set().union(*(public_of.get(m, set()) for m in umbrella))
    out = []
    for f, lines in parsed.items():
        cur = None
        procs = {}
        for _, st in lines:
            low = st.lower()
            m = re.match(
                r"((?:(?:pure|elemental|impure|recursive|module)\s+)*)"
                r"(?:(?:real|integer|logical|character|type|class|complex)\b[^:]*?\s+)?"
                r"(subroutine|function)\s+(\w+)\s*\(",
                low,
            )
            if m and not low.startswith("end"):
                cur = m.group(3)
                procs[cur] = {"elemental": "elemental" in m.group(1), "status": False}
                continue
            if cur and re.match(r"(type|class)\s*\(\s*status_t\s*\)", low):
                procs[cur]["status"] = True
            if re.match(r"end\s*(subroutine|function)\b", low):
                cur = None
        mods_here = {m for m, fs in module_file.items() if f in fs}
        for name in sorted(exported & set(procs)):
            if any(name in public_of[m] for m in mods_here):
                out.append((f.relative_to(ROOT), name, procs[name]))
    return out


@pytest.mark.skipif(not (ROOT / "src").is_dir(), reason="needs the source tree")
def test_fortran_public_procedures_report_a_status():
    procs = _fortran_public_procedures()
    assert len(procs) > 20, "the scan of src/ found too few public procedures"
    bad = [
        f"{path}: {name}"
        for path, name, p in procs
        if not p["elemental"]
        and not p["status"]
        and name not in FORTRAN_NO_STATUS
        and not str(path).endswith("pendula_status.f90")
    ]
    assert not bad, (
        "public non-elemental Fortran procedures without a type(status_t) argument "
        "(add one, or an exemption with its reason to FORTRAN_NO_STATUS):\n" + "\n".join(bad)
    )
    uniq = {name: p for _, name, p in procs}  # the CVODE stub twin defines the same names
    print(
        f"\nFortran API (use pendula): {len(uniq)} procedures, "
        f"{sum(1 for p in uniq.values() if p['status'])} with a status, "
        f"{sum(1 for p in uniq.values() if p['elemental'])} elemental"
    )
