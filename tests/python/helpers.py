"""Helpers shared by the Python test modules (imported as `helpers`; pytest
puts this folder on sys.path because tests/python has no __init__.py)."""
import pathlib

import pytest

import pendula

#: The source tree (tests that read sources or data skip without it).
ROOT = pathlib.Path(__file__).resolve().parents[2]

#: Marks a test that reads the source tree.
needs_source = pytest.mark.skipif(not (ROOT / "src").is_dir(), reason="needs the source tree")

#: Whether this build has SUNDIALS CVODE, asked the one way (build_info).
HAVE_CVODE = pendula.build_info()["cvode"]

#: Marks a test that needs CVODE.
needs_cvode = pytest.mark.skipif(not HAVE_CVODE, reason="this pendula build has no SUNDIALS CVODE")
