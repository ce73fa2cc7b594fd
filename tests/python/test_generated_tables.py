"""The elliptic tables in src/special are written by tools/gen/gen_elliptic_tables.py,
their one home: the files in the tree must be exactly what it writes now (a hand
edit, a lint reformat or a changed generator shows up here)."""

import subprocess
import sys

from helpers import ROOT


def test_elliptic_tables_match_their_generator():
    run = subprocess.run(
        [sys.executable, str(ROOT / "tools" / "gen" / "gen_elliptic_tables.py"), "--check"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert run.stdout.count("identical") == 3, run.stdout
