"""Where a report comes from: the commit it was made from and the versions of what ran it."""

import os
import platform
import subprocess
from importlib import metadata
from pathlib import Path

#: the packages whose versions change the numbers of the report
PACKAGES = ("numpy", "numba", "scipy", "pandas", "matplotlib", "pymunk", "pybullet", "mujoco")
REPOSITORY = Path(__file__).resolve().parents[2]  # comparisons/report/provenance.py -> the checkout


def _git(*args) -> str:
    try:
        done = subprocess.run(["git", *args], cwd=REPOSITORY, capture_output=True, text=True, timeout=10,
                              check=False)
    except (OSError, subprocess.SubprocessError):
        return ""
    return done.stdout.rstrip() if done.returncode == 0 else ""


def provenance() -> dict:
    """``commit`` (full hash, "unknown" outside a git checkout), ``branch``, ``modified`` (files under
    dem_core/, adapters/ and comparisons/, which the numbers depend on, changed or added since the commit),
    ``python``, ``machine``, ``cores`` and ``versions`` (package: version)."""
    changed = _git("status", "--porcelain", "--", "dem_core", "adapters", "comparisons")
    versions = {}
    for name in PACKAGES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = "not installed"
    return {"commit": _git("rev-parse", "HEAD").strip() or "unknown",
            "branch": _git("rev-parse", "--abbrev-ref", "HEAD").strip(),
            "modified": [line[3:] for line in changed.splitlines()], "python": platform.python_version(),
            "machine": f"{platform.system()} {platform.machine()}", "cores": os.cpu_count(), "versions": versions}
