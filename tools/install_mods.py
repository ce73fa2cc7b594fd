#!/usr/bin/env python3
"""Install the Fortran .mod files of the pendula library (meson install script).

Meson installs libraries but not the module files gfortran writes, and Fortran
users need them for `use pendula`.  Arguments: the build directory that holds
the .mod files, and the install directory relative to the prefix.
"""

import os
import shutil
import sys
from pathlib import Path

src = Path(sys.argv[1])
rel = sys.argv[2]
prefix = os.environ.get("MESON_INSTALL_DESTDIR_PREFIX") or os.environ["MESON_INSTALL_PREFIX"]
dest = Path(prefix) / rel if not os.path.isabs(rel) else Path(os.environ.get("DESTDIR", "") + rel)
dest.mkdir(parents=True, exist_ok=True)
mods = sorted(src.glob("*.mod"))
if not mods:
    sys.exit(f"install_mods: no .mod files in {src}")
for mod in mods:
    shutil.copy2(mod, dest / mod.name)
print(f"install_mods: {len(mods)} module files -> {dest}")
