"""Where a report comes from: the commit it was made from, the versions of what ran it, and the digest of the
sources that decide its numbers (:func:`source_digest`), which ``tests/test_report.py`` compares with the one the
committed report records (``reports/digest.json``) to tell whether that report is current."""

import hashlib
import json
import os
import platform
import subprocess
from importlib import metadata
from pathlib import Path

#: the packages whose versions change the numbers of the report
PACKAGES = ("numpy", "numba", "scipy", "pandas", "matplotlib", "pymunk", "pybullet", "mujoco")
REPOSITORY = Path(__file__).resolve().parents[2]  # comparisons/report/provenance.py -> the checkout
#: the sources that decide the report's numbers (glob patterns relative to the checkout): the engine and the run
#: around it, the scene builders, motions and record readers and the bundled records, the threshold tools the
#: catalogue calls, the other engines' adapters, and the cases, references and harness; documentation (``*.md``),
#: compiled files and the report's own layout code (``comparisons/report/``) are left out, so editing them leaves a
#: report current
DIGEST_SOURCES = (
    "dem_core/engine/**/*.py",
    "dem_core/simulation.py",
    "dem_core/inputs/**/*.py",
    "dem_core/analyses/thresholds.py",
    "dem_core/data/records/*",
    "adapters/**/*.py",
    "comparisons/cases/**/*",
    "comparisons/references/**/*",
    "comparisons/harness/**/*",
)
#: the file beside index.html that records the digest it was made from
DIGEST_FILE = "digest.json"


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
    ``python``, ``machine``, ``cores``, ``versions`` (package: version), ``digest`` and ``digest_files``
    (:func:`source_digest`)."""
    changed = _git("status", "--porcelain", "--", "dem_core", "adapters", "comparisons")
    versions = {}
    for name in PACKAGES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = "not installed"
    digest, files = source_digest()
    return {"commit": _git("rev-parse", "HEAD").strip() or "unknown", "digest": digest, "digest_files": files,
            "branch": _git("rev-parse", "--abbrev-ref", "HEAD").strip(),
            "modified": [line[3:] for line in changed.splitlines()], "python": platform.python_version(),
            "machine": f"{platform.system()} {platform.machine()}", "cores": os.cpu_count(), "versions": versions}


def _covered(path: Path, root: Path) -> bool:
    """Whether a file matched by :data:`DIGEST_SOURCES` is a source: not compiled, hidden or documentation."""
    parts = path.relative_to(root).parts
    return (path.is_file() and "__pycache__" not in parts and not any(p.startswith(".") for p in parts)
            and path.suffix not in (".pyc", ".pyo", ".md"))


def source_files(root: Path = REPOSITORY) -> list:
    """The files :func:`source_digest` covers, as sorted paths relative to ``root`` (POSIX)."""
    found = {p for pattern in DIGEST_SOURCES for p in root.glob(pattern)}
    return sorted(p.relative_to(root).as_posix() for p in found if _covered(p, root))


def source_digest(root: Path = REPOSITORY) -> tuple[str, list]:
    """``(sha256 hex, files)``: a digest over the sorted relative paths and bytes of :func:`source_files` (the
    idea of ``examples/studies/_study.py:core_fingerprint``)."""
    files = source_files(root)
    digest = hashlib.sha256()
    for name in files:
        digest.update(name.encode())
        digest.update((root / name).read_bytes())
    return digest.hexdigest(), files


def write_digest(out: Path, made: dict) -> Path:
    """Write ``digest.json`` into ``out``: the digest of the sources, the files it covers and the commit."""
    path = Path(out) / DIGEST_FILE
    record = {"digest": made["digest"], "commit": made["commit"], "modified": made["modified"],
              "sources": list(DIGEST_SOURCES), "files": made["digest_files"]}
    path.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
    return path


def recorded_digest(out: Path) -> str | None:
    """The digest ``digest.json`` in ``out`` records (None if there is none)."""
    path = Path(out) / DIGEST_FILE
    return json.loads(path.read_text(encoding="utf-8")).get("digest") if path.is_file() else None
