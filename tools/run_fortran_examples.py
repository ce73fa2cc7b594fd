#!/usr/bin/env python3
"""Run every Fortran example driver of a meson build dir; save each one's output.

Usage: run_fortran_examples.py BUILD_DIR OUT_DIR.  Used by the main job
(quickstart.sh run); exits non-zero if a driver fails.
"""

import json
import subprocess
import sys
from pathlib import Path

build, out = Path(sys.argv[1]), Path(sys.argv[2])
out.mkdir(parents=True, exist_ok=True)
info = json.loads(
    subprocess.run(["meson", "introspect", "--tests", str(build)], capture_output=True, text=True, check=True).stdout
)
examples = [
    t for t in info if "examples" in t.get("suite", []) or any(s.endswith(":examples") for s in t.get("suite", []))
]
failed = 0
for t in examples:
    res = subprocess.run(t["cmd"], capture_output=True, text=True, cwd=out)
    path = out / f"{t['name']}.txt"
    path.write_text(res.stdout + (("\n[stderr]\n" + res.stderr) if res.stderr else ""))
    status = "ok" if res.returncode == 0 else f"FAILED ({res.returncode})"
    failed += res.returncode != 0
    print(f"  fortran example {t['name']:<28} {status:<10} -> {path}")
if not examples:
    print("  (no Fortran example drivers in this build)")
sys.exit(1 if failed else 0)
