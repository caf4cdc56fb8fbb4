"""Scene files: TOML that maps one to one onto the scene builders, an excitation and run settings.

::

    [scene]
    builder = "column"            # block | column | colonnade | two_tier_colonnade | blocks
    n_drums = 8                   # every other key is that builder's keyword argument
    width = 1.0
    height = 6.0
    interface_friction = [{between = ["base", "drum1"], mu = 0.05}]

    [contact]                     # optional, fields of dem_core.ContactParameters
    law = "corner"                # corner (default) | overlap_area (the thesis' law)
    kn = 2e11

    [excitation]                  # optional; kind = record | harmonic | rectangular_pulse |
    kind = "record"               #   sine_pulse | cosine_pulse | ramp | none
    source = "el_centro_1940"     # a bundled record or a path relative to this file
    pga = 3.0                     # every other key is that function's keyword argument
    # resample = true             # a record whose time column is uneven: interpolate onto a uniform step

    [simulation]                  # optional: keyword arguments of dem_core.simulate
    duration = 20.0
    output_dt = 0.01

    [output]                      # optional, used by the command line
    format = "csv"                # csv | parquet
    plots = true

Connectors across joints are ``[[connector]]`` tables: a ``preset`` (``oak_polos``, ``titanium_bar`` with its
``diameter``) or the keys of :class:`~dem_core.inputs.connectors.ConnectorKind` (``name``, ``shear_stiffness``,
...), ``at`` (``"all"``, ``"capital"`` or a list of ``["first", "second"]`` block pairs) and ``position`` (m)::

    [[connector]]
    preset = "titanium_bar"
    diameter = 0.016
    at = "capital"

With ``builder = "blocks"`` the scene is given block by block: ``[[block]]``
tables with ``name``, ``vertices`` (list of [x, y] in m) and optionally
``density``, ``friction``, ``depth``, ``angle``, and a ``[base]`` table with
``vertices`` and ``friction``; ``[scene]`` then takes ``allow_free_blocks = true``
for blocks meant to start out of contact (see :class:`~dem_core.inputs.scene.Scene`).

Every key is checked for its type before it is used (:data:`SCENE_TYPES` and the
other ``*_TYPES`` tables): numbers are numbers, not strings; integers are whole
numbers (``3`` or ``3.0``), not booleans.  Errors name the file, the table, the
key, the type expected and the value given; an unknown key, table, builder or
kind gets the nearest valid name suggested.  A ground motion that would peak
above ``dem_core.inputs.excitation.EXTREME_PGA_G`` (50 g: beyond what a stone
block can meet) is refused naming the keys that set its size.
"""

import inspect
import math
import tomllib
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Callable, NamedTuple

from . import excitation as excitation_module
from . import scenes
from ..engine.contact import LAWS, ContactParameters
from ..engine.settings import INTEGRATORS
from .connectors import PRESETS, ConnectorKind, Placement
from .number_types import is_real, is_whole
from .run_settings import GROUND_MOTION_MODES, check_settings
from .scene import Block, Scene
from .text_files import did_you_mean, file_errors, shown


class SceneFileError(ValueError):
    """A scene file that cannot be read; the message names the file and the key or line.  ``keys`` names
    the ``[excitation]`` keys at fault where the error is about them (a key unknown to the kind, two keys
    that do not go together, a size beyond reason), so that a caller that set one can say so."""

    def __init__(self, message: str, keys=()):
        super().__init__(message)
        self.keys = tuple(keys)


class ValueType(NamedTuple):
    """What a key takes: ``convert(value)`` gives the value as the builders take it, or
    :data:`MISMATCH` when the value is not of this type; ``description`` is how errors say it."""

    description: str
    convert: Callable[[Any], Any]
    choices: tuple = ()


MISMATCH = object()


def _as_number(value):
    if not is_real(value) or not math.isfinite(value):
        return MISMATCH
    return float(value)


def _as_integer(value):
    return int(value) if is_whole(value) else MISMATCH


def _as_pair(value):
    if not isinstance(value, list) or len(value) != 2:
        return MISMATCH
    pair = tuple(_as_number(v) for v in value)
    return MISMATCH if MISMATCH in pair else pair


def _as_points(value):
    if not isinstance(value, list) or not value:
        return MISMATCH
    points = [_as_pair(v) for v in value]
    return MISMATCH if MISMATCH in points else [list(p) for p in points]


def _as_record_source(value):
    if isinstance(value, str):
        return value
    if _lists_records(value):
        return list(value)
    if isinstance(value, list) and value:
        samples = [_as_number(v) for v in value]
        return MISMATCH if MISMATCH in samples else samples
    return MISMATCH


def _as_vertical(value):
    if isinstance(value, (bool, str)):
        return value
    return _as_integer(value)


NUMBER = ValueType("a finite number", _as_number)
INTEGER = ValueType("an integer", _as_integer)
STRING = ValueType("a string", lambda v: v if isinstance(v, str) else MISMATCH)
BOOLEAN = ValueType("true or false", lambda v: v if isinstance(v, bool) else MISMATCH)


def one_of(choices: tuple) -> ValueType:
    """A string that is one of ``choices``; an error suggests the nearest."""
    return ValueType(f"one of {', '.join(map(repr, choices))}", lambda v: v if v in choices else MISMATCH, choices)


PAIR = ValueType("a pair of numbers [a, b]", _as_pair)
POINTS = ValueType("a list of [x, y] points (numbers, m)", _as_points)
RECORD_SOURCE = ValueType("a bundled record name, a file path, a list of accelerations or a list of record names "
                          "and paths (a sequence)", _as_record_source)
VERTICAL = ValueType("true, false, a component number, or a record name or path", _as_vertical)


def _as_table_of(entry: ValueType):
    """How a table of block names to values of ``entry`` converts: a dict of the converted values, or MISMATCH."""
    def convert(value):
        if not isinstance(value, dict):
            return MISMATCH
        table = {name: entry.convert(v) for name, v in value.items()}
        return MISMATCH if any(v is MISMATCH for v in table.values()) else table
    return convert


OFFSETS = ValueType("a table of block names to offsets in m ({drum3 = 0.01})", _as_table_of(NUMBER))
OUTLINES = ValueType("a table of block names to outlines ({drum3 = [[-0.5, 0], [0.5, 0], ...]})",
                     _as_table_of(POINTS))
#: the type of each entry of a table type, for errors that name the entry at fault
TABLE_ENTRIES = {OFFSETS: NUMBER, OUTLINES: POINTS}

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
#: [scene]: the builders' keyword arguments and the keys of ``builder = "blocks"``
SCENE_TYPES = {
    "builder": STRING, "name": STRING, "epistyle": STRING,
    "n_drums": INTEGER, "n_columns": INTEGER, "lower_drums": INTEGER, "upper_drums": INTEGER,
    "width": NUMBER, "height": NUMBER, "tilt": NUMBER, "taper": NUMBER, "spacing": NUMBER,
    "epistyle_density": NUMBER, "epistyle_height": NUMBER, "lower_height": NUMBER, "lower_width": NUMBER,
    "upper_height": NUMBER, "upper_width": NUMBER, "density": NUMBER, "friction": NUMBER, "depth": NUMBER,
    "base_width": NUMBER, "capital": PAIR, "slenderness": NUMBER, "allow_free_blocks": BOOLEAN,
    "foundation_tilt": NUMBER, "offsets": OFFSETS, "outlines": OUTLINES,
}
EXPLICIT_BLOCKS_KEYS = {"builder", "interface_friction", "slenderness", "allow_free_blocks"}
#: the builders' keywords a scene file gives elsewhere than as [scene] keys: [contact], and [[connector]] tables
BUILDER_TABLE_KEYWORDS = {"contact", "interface_friction", "connectors"}
CONTACT_TYPES = {**{f.name: NUMBER for f in fields(ContactParameters)}, "law": one_of(LAWS)}
EXCITATION_TYPES = {
    "kind": STRING, "source": RECORD_SOURCE, "vertical": VERTICAL, "units": STRING, "component": INTEGER,
    "baseline": BOOLEAN, "resample": BOOLEAN, "dt": NUMBER, "scale": NUMBER, "pga": NUMBER, "amplitude": NUMBER,
    "frequency": NUMBER, "vertical_amplitude": NUMBER, "duration": NUMBER, "rate": NUMBER, "peak": NUMBER,
    "rest": NUMBER,
}
#: [excitation] keys of kind "record" beyond record()'s own: the rest after each record, which makes a sequence
SEQUENCE_KEYS = {"rest"}
SIMULATION_TYPES = {"duration": NUMBER, "dt": NUMBER, "output_dt": NUMBER, "ground_motion": one_of(GROUND_MOTION_MODES),
                    "safety": NUMBER, "stop_at_overturn": BOOLEAN, "integrator": one_of(INTEGRATORS),
                    "theta": NUMBER}
OUTPUT_TYPES = {"format": STRING, "plots": BOOLEAN}
CONNECTOR_PLACES = ValueType("\"all\", \"capital\" or a list of [block, block] pairs",
                             lambda v: v if isinstance(v, str) else (
                                 [tuple(p) for p in v] if isinstance(v, list) and all(
                                     isinstance(p, list) and len(p) == 2 and all(isinstance(n, str) for n in p)
                                     for p in v) else MISMATCH))
CONNECTOR_TYPES = {"preset": STRING, "diameter": NUMBER, "at": CONNECTOR_PLACES, "position": NUMBER,
                   **{f.name: (STRING if f.name in ("name", "source") else NUMBER) for f in fields(ConnectorKind)}}
BLOCK_TYPES = {"name": STRING, "vertices": POINTS, "density": NUMBER, "friction": NUMBER, "depth": NUMBER,
               "angle": NUMBER}
BASE_TYPES = {"vertices": POINTS, "friction": NUMBER, "depth": NUMBER}
SIMULATION_KEYS = set(SIMULATION_TYPES)
OUTPUT_KEYS = set(OUTPUT_TYPES)
TABLES = ("scene", "contact", "excitation", "simulation", "output", "base")
TOP_LEVEL = {*TABLES, "block", "connector"}


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
    :class:`SceneFileError`) naming the file, a missing one with the TOML files of its folder whose names are
    close to its."""
    error = error or SceneFileError
    try:
        with file_errors(path, error, what, hint=lambda: _close_toml_files(path)), open(path, "rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML: {exc}") from None


def _close_toml_files(path) -> str:
    """`` (did you mean 'column.toml'?)`` for the ``*.toml`` files beside ``path`` whose names are close to its
    (``""`` for none, or a folder that is not there)."""
    path = Path(path)
    try:
        beside = [p.name for p in path.parent.iterdir() if p.suffix == ".toml"]
    except OSError:
        return ""
    return did_you_mean(path.name, beside)


def load(path) -> SceneFile:
    """Read a scene file; raises :class:`SceneFileError` naming the file and the culprit."""
    return from_dict(read_toml(path), path)


def from_dict(data: dict, path=Path("<scene>")) -> SceneFile:
    """Build a :class:`SceneFile` from the parsed tables of a scene file; ``path`` names it in errors
    and anchors relative record paths."""
    path = Path(path)
    tables = check(data, path)
    try:
        contact = ContactParameters(**tables["contact"])
    except ValueError as exc:
        raise SceneFileError(f"{path}: [contact]: {exc}") from None
    try:
        check_settings(**tables["simulation"])
    except ValueError as exc:
        raise SceneFileError(f"{path}: [simulation]: {exc}") from None
    scene = _scene(tables, path, contact)
    motion = _excitation(tables["excitation"], path)
    _refuse_extreme(tables["excitation"], motion, tables["simulation"], path)
    if tables["output"].get("format", "csv") not in ("csv", "parquet"):
        raise SceneFileError(f"{path}: [output] format must be 'csv' or 'parquet', got {tables['output']['format']!r}")
    return SceneFile(path, scene, motion, tables["simulation"], tables["output"])


def check(data: dict, path=Path("<scene>")) -> dict:
    """The tables of a scene file with every key checked for its name and type and converted (integers
    to int, numbers to float, pairs to tuples); raises :class:`SceneFileError` naming the file, the
    table, the key, the type expected and the value given.  Values are not judged here beyond a choice among
    names (a contact law, an integrator: :func:`one_of`); a negative width is the builder's to refuse."""
    path = Path(path)
    unknown = set(data) - TOP_LEVEL
    if unknown:
        raise SceneFileError(f"{path}: unknown table(s) {sorted(unknown)}{did_you_mean(unknown, TOP_LEVEL)}; "
                             f"expected some of {sorted(TOP_LEVEL)}")
    for name in TABLES:
        if not isinstance(data.get(name, {}), dict):
            raise SceneFileError(f"{path}: {name} must be a table (a [{name}] header with its keys below it), "
                                 f"got {_given(data[name])}")
    blocks = data.get("block", [])
    if not isinstance(blocks, list) or not all(isinstance(b, dict) for b in blocks):
        raise SceneFileError(f"{path}: block must be an array of tables ([[block]] headers), got {_given(blocks)}")
    connectors = data.get("connector", [])
    if not isinstance(connectors, list) or not all(isinstance(c, dict) for c in connectors):
        raise SceneFileError(f"{path}: connector must be an array of tables ([[connector]] headers), got "
                             f"{_given(connectors)}")
    scene = data.get("scene", {})
    builder = _typed(path, "[scene]", "builder", scene["builder"], STRING) if "builder" in scene else None
    if builder is None:
        raise SceneFileError(f"{path}: [scene] needs a builder ({', '.join([*BUILDERS, 'blocks'])})")
    if builder == "blocks":
        scene_keys = EXPLICIT_BLOCKS_KEYS
    elif blocks or "base" in data:
        raise SceneFileError(f"{path}: [[block]] and [base] tables describe a scene block by block, with "
                             f"builder = \"blocks\"; builder {builder!r} makes its own blocks")
    elif builder in BUILDERS:
        scene_keys = {"builder", "interface_friction",
                      *(set(inspect.signature(BUILDERS[builder]).parameters) - BUILDER_TABLE_KEYWORDS)}
    else:
        names = [*BUILDERS, "blocks"]
        raise SceneFileError(f"{path}: [scene] unknown builder {builder!r}{did_you_mean(builder, names)}; "
                             f"use one of {', '.join(names)}")
    unknown = set(scene) - scene_keys
    if unknown:
        raise SceneFileError(f"{path}: [scene] builder {builder!r} has no parameter(s) {sorted(unknown)}"
                             f"{did_you_mean(unknown, scene_keys - {'builder'})}; "
                             f"its parameters: {sorted(scene_keys - {'builder'})}")
    if builder in BUILDERS:
        _required(BUILDERS[builder], scene, f"[scene] builder {builder!r}", path)
    friction = _interface_friction(scene.get("interface_friction", []), path)
    tables = {
        "scene": {**_checked({k: v for k, v in scene.items() if k != "interface_friction"}, "[scene]", path,
                             SCENE_TYPES, scene_keys),
                  "interface_friction": friction},
        "contact": _checked(data.get("contact", {}), "[contact]", path, CONTACT_TYPES),
        "excitation": _checked_excitation(data.get("excitation", {}), path),
        "simulation": _checked(data.get("simulation", {}), "[simulation]", path, SIMULATION_TYPES),
        "output": _checked(data.get("output", {}), "[output]", path, OUTPUT_TYPES),
        "block": [_checked(entry, f"[[block]] number {k} ({entry.get('name', '?')!s})", path, BLOCK_TYPES)
                  for k, entry in enumerate(blocks, start=1)],
        "base": _checked(data["base"], "[base]", path, BASE_TYPES) if "base" in data else None,
        "connector": [_checked(entry, f"[[connector]] number {k}", path, CONNECTOR_TYPES)
                      for k, entry in enumerate(connectors, start=1)],
    }
    return tables


def _checked(table: dict, where: str, path, types: dict, allowed=None) -> dict:
    """``table`` with every key known (in ``allowed``, default all of ``types``) and of its type."""
    allowed = set(types) if allowed is None else set(allowed)
    unknown = set(table) - allowed
    if unknown:
        raise SceneFileError(f"{path}: {where} has unknown key(s) {sorted(unknown)}{did_you_mean(unknown, allowed)}; "
                             f"allowed: {sorted(allowed)}", keys=unknown if where == "[excitation]" else ())
    return {key: _typed(path, where, key, value, types[key]) for key, value in table.items()}


def _typed(path, where: str, key: str, value, expected: ValueType):
    converted = expected.convert(value)
    if converted is MISMATCH and expected in TABLE_ENTRIES and isinstance(value, dict):
        for name, entry in value.items():
            _typed(path, f"{where} {key}", name, entry, TABLE_ENTRIES[expected])
    if converted is MISMATCH:
        raise SceneFileError(f"{path}: {where} {key}: expected {expected.description}, got {_given(value)}"
                             f"{_value_hint(value, expected)}")
    return converted


def _value_hint(value, expected: ValueType) -> str:
    if not isinstance(value, str):
        return ""
    if expected.choices:
        return did_you_mean(value, expected.choices)
    if expected is BOOLEAN and value.strip().lower() in ("true", "false"):
        return " (write true or false without quotes)"
    if expected in (NUMBER, INTEGER):
        try:
            float(value)
        except ValueError:
            return ""
        return " (write numbers without quotes)"
    return ""


def _required(function, table: dict, where: str, path) -> None:
    """Refuse a table that lacks a keyword ``function`` cannot do without."""
    missing = [name for name, parameter in inspect.signature(function).parameters.items()
               if parameter.default is inspect.Parameter.empty and name not in table]
    if missing:
        raise SceneFileError(f"{path}: {where} needs {', '.join(missing)}")


def _given(value) -> str:
    """A TOML value as an error message shows it."""
    if isinstance(value, bool):
        return f"{str(value).lower()} (a boolean)"
    if isinstance(value, str):
        return f"the string {value!r}"
    if isinstance(value, (int, float)):
        return f"the number {value!r}"
    kind = {list: "the array", dict: "the table"}.get(type(value), type(value).__name__)
    return f"{kind} {shown(value)}"


def _interface_friction(entries, path) -> dict:
    if not isinstance(entries, list):
        raise SceneFileError(f"{path}: [scene] interface_friction: expected an array of "
                             f"{{between = [name_a, name_b], mu = number}} tables, got {_given(entries)}")
    friction = {}
    for k, entry in enumerate(entries, start=1):
        where = f"[scene] interface_friction entry {k}"
        if not isinstance(entry, dict) or set(entry) != {"between", "mu"}:
            hint = did_you_mean(set(entry) - {"between", "mu"}, {"between", "mu"}) if isinstance(entry, dict) else ""
            raise SceneFileError(f"{path}: {where}: expected {{between = [name_a, name_b], mu = number}}, "
                                 f"got {_given(entry)}{hint}")
        between = entry["between"]
        if not (isinstance(between, list) and len(between) == 2 and all(isinstance(n, str) for n in between)):
            raise SceneFileError(f"{path}: {where} between: expected two block names [\"a\", \"b\"], "
                                 f"got {_given(between)}")
        friction[tuple(between)] = _typed(path, where, "mu", entry["mu"], NUMBER)
    return friction


def _checked_excitation(table: dict, path) -> dict:
    kind = _typed(path, "[excitation]", "kind", table["kind"], STRING) if "kind" in table else None
    if kind in (None, "none"):
        if set(table) - {"kind"}:
            raise SceneFileError(f"{path}: [excitation] without a kind takes no other keys"
                                 f"{did_you_mean(set(table) - {'kind'}, {'kind'})}; "
                                 f"give kind = {' | '.join(EXCITATIONS)}", keys=set(table) - {"kind"})
        return {"kind": "none"}
    function = EXCITATIONS.get(kind)
    if function is None:
        raise SceneFileError(f"{path}: [excitation] unknown kind {kind!r}{did_you_mean(kind, [*EXCITATIONS, 'none'])}"
                             f"; use one of {', '.join(EXCITATIONS)} or none")
    allowed = set(inspect.signature(function).parameters) | (SEQUENCE_KEYS if kind == "record" else set())
    unknown = set(table) - allowed - {"kind"}
    if unknown:
        raise SceneFileError(f"{path}: [excitation] kind {kind!r} has no parameter(s) {sorted(unknown)}"
                             f"{did_you_mean(unknown, allowed)}; its parameters: {sorted(allowed)}", keys=unknown)
    _required(function, table, f"[excitation] kind {kind!r}", path)
    per_record = {key: value for key, value in table.items() if kind == "record" and _per_record(key, value)}
    checked = _checked({key: value for key, value in table.items() if key not in per_record}, "[excitation]", path,
                       EXCITATION_TYPES, allowed | {"kind"})
    count = len(_record_sources(checked))
    for key, values in per_record.items():
        if len(values) != count:
            raise SceneFileError(f"{path}: [excitation] {key}: {len(values)} value(s) for {count} record(s) in source: "
                                 f"give one value for every record or one per record", keys=(key,))
        checked[key] = [_typed(path, "[excitation]", f"{key} entry {k}", value, EXCITATION_TYPES[key])
                        for k, value in enumerate(values, start=1)]
    return checked


def _per_record(key: str, value) -> bool:
    """Whether ``value`` of [excitation] ``key`` is a list of one value per record of a sequence (a ``source`` list
    is the records themselves)."""
    return key not in ("kind", "source") and isinstance(value, list)


def _lists_records(source) -> bool:
    """Whether an [excitation] ``source`` lists records by name or path (a sequence), not one record or its
    accelerations."""
    return isinstance(source, list) and bool(source) and all(isinstance(v, str) for v in source)


def _record_sources(spec: dict) -> list:
    """The record sources of a checked [excitation]: those ``source`` lists by name or path, else its one source."""
    source = spec.get("source")
    return source if _lists_records(source) else [source]


def _is_sequence(spec: dict) -> bool:
    """Whether a checked [excitation] of kind "record" is a sequence: records listed by name or path in ``source``,
    a ``rest`` after the record, or a key given per record."""
    return (_lists_records(spec.get("source")) or "rest" in spec
            or any(_per_record(key, value) for key, value in spec.items()))


def _scene(tables, path, contact) -> Scene:
    spec = dict(tables["scene"])
    builder_name = spec.pop("builder")
    friction = spec.pop("interface_friction")
    placements = [_placement(entry, k, path) for k, entry in enumerate(tables["connector"], start=1)]
    if builder_name == "blocks":
        scene = _explicit_blocks(tables, spec, path, contact, friction)
        try:
            return scene.replace(connectors=tuple(c for p in placements for c in p.connectors(scene)))
        except ValueError as exc:
            raise SceneFileError(f"{path}: [[connector]]: {exc}") from None
    try:
        return BUILDERS[builder_name](**spec, contact=contact, interface_friction=friction, connectors=placements)
    except ValueError as exc:
        raise SceneFileError(f"{path}: [scene]: {exc}") from None


def _placement(entry: dict, number: int, path) -> Placement:
    """The :class:`~dem_core.inputs.connectors.Placement` of ``[[connector]]`` table ``number``: a preset's kind or
    one of its own keys, at its joints."""
    entry = dict(entry)
    where = f"{path}: [[connector]] number {number}"
    at, position, preset = entry.pop("at", "all"), entry.pop("position", 0.0), entry.pop("preset", None)
    try:
        if preset is None:
            if "diameter" in entry:
                raise SceneFileError(f"{where}: diameter belongs to the titanium_bar preset; give preset = "
                                     f"\"titanium_bar\" or the kind's own keys")
            kind = ConnectorKind(**{"name": "connector", **entry})
        elif preset not in PRESETS:
            raise SceneFileError(f"{where}: unknown preset {preset!r}{did_you_mean(preset, PRESETS)}; use one of "
                                 f"{', '.join(PRESETS)} or give the kind's own keys")
        elif set(entry) - ({"diameter"} if preset == "titanium_bar" else set()):
            extra = sorted(set(entry) - {"diameter"})
            raise SceneFileError(f"{where}: preset {preset!r} takes no {', '.join(extra)}; give the kind's own keys "
                                 f"without a preset to change them")
        else:
            kind = PRESETS[preset](**entry)
        return Placement(kind, at, position)
    except SceneFileError:
        raise
    except ValueError as exc:
        raise SceneFileError(f"{where}: {exc}") from None


def _explicit_blocks(tables, spec, path, contact, friction) -> Scene:
    if not tables["block"]:
        raise SceneFileError(f"{path}: builder 'blocks' needs [[block]] tables")
    blocks = []
    for k, entry in enumerate(tables["block"], start=1):
        if "name" not in entry or "vertices" not in entry:
            raise SceneFileError(f"{path}: [[block]] number {k} needs a name and vertices")
        try:
            blocks.append(Block(**entry))
        except ValueError as exc:
            raise SceneFileError(f"{path}: [[block]] number {k} ({entry['name']}): {exc}") from None
    base_spec = tables["base"]
    if not base_spec or "vertices" not in base_spec:
        raise SceneFileError(f"{path}: builder 'blocks' needs a [base] table with vertices")
    try:
        base = Block("base", base_spec["vertices"], friction=base_spec.get("friction", 0.7),
                     depth=base_spec.get("depth", 1.0))
        return Scene(tuple(blocks), base, contact=contact, interface_friction=friction, **spec)
    except ValueError as exc:
        raise SceneFileError(f"{path}: {exc}") from None


def _excitation(spec, path) -> excitation_module.GroundMotion:
    spec = dict(spec)
    kind = spec.pop("kind")
    if kind == "none":
        return excitation_module.still()
    try:
        if kind == "record" and _is_sequence(spec):
            return _record_sequence(spec, path)
        if kind == "record":
            spec = _sources_found(spec, path)
        return EXCITATIONS[kind](**spec)
    except ValueError as exc:
        raise SceneFileError(f"{path}: [excitation]: {exc}", keys=getattr(exc, "keys", ())) from None


def _sources_found(spec: dict, path) -> dict:
    """A record's [excitation] keys with its ``source`` and ``vertical`` paths (not bundled names) found relative to
    the scene file at ``path``."""
    found = dict(spec)
    for key in ("source", "vertical"):
        value = found.get(key)
        if isinstance(value, str) and value not in excitation_module.records.BUNDLED:
            found[key] = str((path.parent / value).resolve())
    return found


def _record_sequence(spec: dict, path) -> excitation_module.MotionSequence:
    """The sequence of the records of a checked [excitation] (:func:`_is_sequence`), each read with its own values of
    the keys given per record and the one value of the others, followed by its ``rest``."""
    spec = dict(spec)
    rest, sources = spec.pop("rest", 0.0), _record_sources(spec)
    motions = []
    for k, source in enumerate(sources):
        one = {key: (value[k] if _per_record(key, value) else value) for key, value in spec.items()}
        motions.append(excitation_module.record(**_sources_found({**one, "source": source}, path)))
    return excitation_module.sequence(motions, rest=rest, resample=spec.get("resample", False))


#: [excitation] keys that set the size of a ground motion, as an extreme one names them
SIZE_KEYS = ("pga", "scale", "amplitude", "frequency", "vertical_amplitude", "peak", "rate", "units")


def _refuse_extreme(spec: dict, motion, simulation: dict, path) -> None:
    """Refuse a ground motion that would peak above ``EXTREME_PGA_G`` (:func:`~.excitation.refuse_extreme`; a ramp
    without a peak by ``[simulation] duration``, when given), naming the keys that set its size."""
    try:
        excitation_module.refuse_extreme(motion, simulation.get("duration"))
    except excitation_module.ExcitationError as exc:
        keys = [key for key in SIZE_KEYS if key in spec] or [key for key in ("source",) if key in spec]
        given = ", ".join(f"{key} = {shown(spec[key])}" for key in keys)
        raise SceneFileError(f"{path}: [excitation] {given}: {exc} (pga, peak and a pulse's amplitude are in m/s^2, "
                             f"a harmonic's amplitude in m, a ramp's rate in m/s^2 per s)", keys=keys) from None
