"""The environment CI tests in is the one constraints.txt pins (checked when .ci/run sets DEM_CHECK_CONSTRAINTS)."""

import os
import re
from importlib import metadata
from pathlib import Path

import pytest

CONSTRAINTS = Path(__file__).resolve().parents[1] / "constraints.txt"


def _pins() -> dict:
    pins = {}
    for line in CONSTRAINTS.read_text().splitlines():
        match = re.fullmatch(r"\s*([A-Za-z0-9_.\-]+)==([^\s;#]+)\s*", line)
        if match:
            pins[match.group(1)] = match.group(2)
    return pins


def test_constraints_pin_every_direct_dependency():
    pins = {name.lower().replace("_", "-") for name in _pins()}
    for requirement in metadata.requires("dem-colonnade") or []:
        if "extra ==" in requirement:
            continue
        name = re.match(r"[A-Za-z0-9_.\-]+", requirement).group(0).lower().replace("_", "-")
        assert name in pins, f"constraints.txt does not pin {name}, a dependency in pyproject.toml"


@pytest.mark.skipif(not os.environ.get("DEM_CHECK_CONSTRAINTS"), reason="only where .ci/run installed the pins")
def test_installed_versions_are_the_pinned_ones():
    wrong = {}
    for name, version in _pins().items():
        try:
            installed = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue  # pinned for an optional path this environment does not install
        if installed != version:
            wrong[name] = (version, installed)
    assert not wrong, f"installed versions differ from constraints.txt (pinned, installed): {wrong}"
