"""The wheel route: python -m build --wheel, installed into a fresh venv outside
the tree (tests/consumer/run_wheel_consumer.sh does it and checks a call)."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _have(module):
    try:
        return importlib.util.find_spec(module) is not None
    except ImportError:  # a missing parent package
        return False


@pytest.mark.slow
@pytest.mark.skipif(
    not (_have("build.__main__") and _have("mesonpy")),
    reason="needs the build and meson-python packages (requirements-dev.txt)",
)
def test_wheel_installs_into_a_fresh_venv():
    proc = subprocess.run(
        ["bash", str(ROOT / "tests" / "consumer" / "run_wheel_consumer.sh"), str(ROOT), sys.executable],
        capture_output=True,
        text=True,
        timeout=1200,
    )
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-4000:]
    assert "wheel: pendula" in proc.stdout
