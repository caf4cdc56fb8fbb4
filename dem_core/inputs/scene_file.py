"""Scene files: TOML that maps one to one onto the scene builders, an excitation and run settings.

::

    [scene]
    builder = "column"            # block | column | colonnade | two_tier_colonnade | blocks
    n_drums = 8                   # every other key is that builder's keyword argument
    width = 1.0
    height = 6.0
    interface_friction = [{between = ["base", "drum1"], mu = 0.05}]

    [contact]                     # optional, fields of dem_core.ContactParameters
    kn = 2e10

    [excitation]                  # optional; kind = record | harmonic | rectangular_pulse |
    kind = "record"               #   sine_pulse | cosine_pulse | ramp | none
    source = "el_centro_1940"     # a bundled record or a path relative to this file
    pga = 3.0                     # every other key is that function's keyword argument

    [simulation]                  # optional: keyword arguments of dem_core.simulate
    duration = 20.0
    output_dt = 0.01

    [output]                      # optional, used by the command line
    format = "csv"                # csv | parquet
    plots = true

With ``builder = "blocks"`` the scene is given block by block: ``[[block]]``
tables with ``name``, ``vertices`` (list of [x, y] in m) and optionally
``density``, ``friction``, ``depth``, ``angle``, and a ``[base]`` table with
``vertices`` and ``friction``.
"""

import inspect
import tomllib
from dataclasses import dataclass, field, fields
from pathlib import Path

from . import excitation as excitation_module
from . import scenes
from ..engine.contact import ContactParameters
from .scene import Block, Scene, SceneError

BUILDERS = {
    "block": scenes.block,
    "column": scenes.column,
    "colonnade": scenes.colonnade,
    "two_tier_colonnade": scenes.two_tier_colonnade,
}
EXCITATIONS = {
    "record": excitation_module.record,
    "harmonic": excitation_module.harmonic,
    "rectangular_pulse": excitation_module.rectangular_pulse,
    "sine_pulse": excitation_module.sine_pulse,
    "cosine_pulse": excitation_module.cosine_pulse,
    "ramp": excitation_module.ramp,
}
SIMULATION_KEYS = {"duration", "dt", "output_dt", "ground_motion", "safety", "stop_at_overturn"}
OUTPUT_KEYS = {"format", "plots"}
TOP_LEVEL = {"scene", "contact", "excitation", "simulation", "output", "block", "base"}


class SceneFileError(ValueError):
    """A scene file that cannot be read; the message names the file and the key or line."""


@dataclass(frozen=True)
class SceneFile:
    """Everything a scene file describes."""

    path: Path
    scene: Scene
    excitation: excitation_module.GroundMotion
    simulation: dict = field(default_factory=dict)
    output: dict = field(default_factory=dict)


def read_toml(path, error=None, what: str = "scene file") -> dict:
    """The tables of a TOML file; a missing or malformed file raises ``error`` (default
    :class:`SceneFileError`) naming the file."""
    error = error or SceneFileError
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise error(f"{path}: no such {what}") from None
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML: {exc}") from None


def load(path) -> SceneFile:
    """Read a scene file; raises :class:`SceneFileError` naming the file and the culprit."""
    return from_dict(read_toml(path), path)


def from_dict(data: dict, path=Path("<scene>")) -> SceneFile:
    """Build a :class:`SceneFile` from the parsed tables of a scene file; ``path`` names it in errors
    and anchors relative record paths."""
    path = Path(path)
    unknown = set(data) - TOP_LEVEL
    if unknown:
        raise SceneFileError(f"{path}: unknown table(s) {sorted(unknown)}; expected some of {sorted(TOP_LEVEL)}")
    try:
        contact = ContactParameters(**_table(data, "contact", path, {f.name for f in fields(ContactParameters)}))
    except (TypeError, ValueError) as exc:
        raise SceneFileError(f"{path}: [contact]: {exc}") from None
    scene = _scene(data, path, contact)
    motion = _excitation(data.get("excitation", {"kind": "none"}), path)
    simulation = _table(data, "simulation", path, SIMULATION_KEYS)
    output = _table(data, "output", path, OUTPUT_KEYS)
    if output.get("format", "csv") not in ("csv", "parquet"):
        raise SceneFileError(f"{path}: [output] format must be 'csv' or 'parquet', got {output['format']!r}")
    return SceneFile(path, scene, motion, simulation, output)


def _table(data, name, path, allowed):
    table = data.get(name, {})
    if not isinstance(table, dict):
        raise SceneFileError(f"{path}: [{name}] must be a table")
    unknown = set(table) - set(allowed)
    if unknown:
        raise SceneFileError(f"{path}: [{name}] has unknown key(s) {sorted(unknown)}; allowed: {sorted(allowed)}")
    return dict(table)


def _scene(data, path, contact) -> Scene:
    spec = dict(data.get("scene", {}))
    builder_name = spec.pop("builder", None)
    if builder_name is None:
        raise SceneFileError(f"{path}: [scene] needs a builder ({', '.join([*BUILDERS, 'blocks'])})")
    friction = {}
    for k, entry in enumerate(spec.pop("interface_friction", [])):
        try:
            a, b = entry["between"]
            friction[(a, b)] = entry["mu"]
        except (KeyError, TypeError, ValueError):
            raise SceneFileError(f"{path}: [scene] interface_friction entry {k + 1} needs "
                                 f"between = [name_a, name_b] and mu") from None
    if builder_name == "blocks":
        return _explicit_blocks(data, spec, path, contact, friction)
    builder = BUILDERS.get(builder_name)
    if builder is None:
        raise SceneFileError(f"{path}: [scene] unknown builder {builder_name!r}; use one of "
                             f"{', '.join([*BUILDERS, 'blocks'])}")
    allowed = set(inspect.signature(builder).parameters) - {"contact", "interface_friction"}
    unknown = set(spec) - allowed
    if unknown:
        raise SceneFileError(f"{path}: [scene] builder {builder_name!r} has no parameter(s) {sorted(unknown)}; "
                             f"its parameters: {sorted(allowed)}")
    for key in ("capital",):
        if key in spec and spec[key] is not None:
            spec[key] = tuple(spec[key])
    try:
        return builder(**spec, contact=contact, interface_friction=friction)
    except (SceneError, TypeError, ValueError) as exc:
        raise SceneFileError(f"{path}: [scene]: {exc}") from None


def _explicit_blocks(data, spec, path, contact, friction) -> Scene:
    if spec:
        raise SceneFileError(f"{path}: [scene] with builder 'blocks' takes only interface_friction, "
                             f"not {sorted(spec)}")
    entries = data.get("block", [])
    if not entries:
        raise SceneFileError(f"{path}: builder 'blocks' needs [[block]] tables")
    block_keys = {"name", "vertices", "density", "friction", "depth", "angle"}
    blocks = []
    for k, entry in enumerate(entries, start=1):
        unknown = set(entry) - block_keys
        if unknown:
            raise SceneFileError(f"{path}: [[block]] number {k} has unknown key(s) {sorted(unknown)}")
        try:
            blocks.append(Block(**entry))
        except (SceneError, TypeError, ValueError) as exc:
            raise SceneFileError(f"{path}: [[block]] number {k} ({entry.get('name', '?')}): {exc}") from None
    base_spec = data.get("base")
    if not base_spec or "vertices" not in base_spec:
        raise SceneFileError(f"{path}: builder 'blocks' needs a [base] table with vertices")
    try:
        base = Block("base", base_spec["vertices"], friction=base_spec.get("friction", 0.7),
                     depth=base_spec.get("depth", 1.0))
        return Scene(tuple(blocks), base, contact=contact, interface_friction=friction,
                     slenderness=data["scene"].get("slenderness"))
    except (SceneError, TypeError, ValueError) as exc:
        raise SceneFileError(f"{path}: {exc}") from None


def _excitation(spec, path) -> excitation_module.GroundMotion:
    spec = dict(spec)
    kind = spec.pop("kind", None)
    if kind in (None, "none"):
        if spec:
            raise SceneFileError(f"{path}: [excitation] without a kind takes no other keys")
        return excitation_module.still()
    function = EXCITATIONS.get(kind)
    if function is None:
        raise SceneFileError(f"{path}: [excitation] unknown kind {kind!r}; use one of {', '.join(EXCITATIONS)} or none")
    allowed = set(inspect.signature(function).parameters)
    unknown = set(spec) - allowed
    if unknown:
        raise SceneFileError(f"{path}: [excitation] kind {kind!r} has no parameter(s) {sorted(unknown)}; "
                             f"its parameters: {sorted(allowed)}")
    if kind == "record":
        for key in ("source", "vertical"):
            value = spec.get(key)
            if isinstance(value, str) and value not in excitation_module.records.BUNDLED:
                spec[key] = str((path.parent / value).resolve())
    try:
        return function(**spec)
    except (TypeError, ValueError) as exc:
        raise SceneFileError(f"{path}: [excitation]: {exc}") from None
