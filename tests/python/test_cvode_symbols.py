"""The CVODE callbacks and N_Vector kernels have no global C names.

pendula_cvode hands SUNDIALS C function pointers (c_funloc) to its callbacks
and to the length-2 vector kernels of pendula_cvode_vector.  With default
bind(C) names (`div`, `scale`, `rhs`, ...) they were exported from every
extension module, and inside Python (extensions are dlopen'ed after libc)
c_funloc(div) resolved to libc's div(): CVODE's N_VDiv ran libc code and the
Python results differed from the Fortran build's.  They are bind(C, name='')
now; this checks that none of those names is defined by a pendula extension
(a name found through ctypes must be the process-wide one, e.g. libc's div).
"""

import ctypes
import importlib.machinery
import pathlib

from helpers import needs_cvode

import pendula

NAMES = [
    "div",
    "scale",
    "prod",
    "inv",
    "const",
    "abs_",
    "min_",
    "add_const",
    "dot_prod",
    "max_norm",
    "wrms_norm",
    "wsqr_sum",
    "linear_sum",
    "linear_combination",
    "scale_add_multi",
    "scale_vector_array",
    "linear_sum_vector_array",
    "rhs",
    "jacobian",
    "root_functions",
    "capture_error",
]


def _address(fn):
    return ctypes.cast(fn, ctypes.c_void_p).value


@needs_cvode
def test_extensions_define_no_callback_names():
    process = ctypes.CDLL(None)
    folder = pathlib.Path(pendula.__file__).parent
    found = [p for s in importlib.machinery.EXTENSION_SUFFIXES for p in folder.glob("_*" + s)]
    assert found, f"no extension modules in {folder}"
    for path in found:
        lib = ctypes.CDLL(str(path))
        for name in NAMES:
            fn = getattr(lib, name, None)
            if fn is None:
                continue
            outside = getattr(process, name, None)
            assert outside is not None and _address(outside) == _address(fn), (
                f"{path.name} defines the C symbol {name!r} (use bind(C, name=''))"
            )
