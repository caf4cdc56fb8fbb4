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
from ..engine.contact import ContactParameters
from .scene import Block, Scene
from .text_files import did_you_mean, file_errors


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


MISMATCH = object()


def _as_number(value):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return MISMATCH
    return float(value)


def _as_integer(value):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return MISMATCH
    if isinstance(value, float) and not value.is_integer():
        return MISMATCH
    return int(value)


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
PAIR = ValueType("a pair of numbers [a, b]", _as_pair)
POINTS = ValueType("a list of [x, y] points (numbers, m)", _as_points)
RECORD_SOURCE = ValueType("a bundled record name, a file path or a list of accelerations", _as_record_source)
VERTICAL = ValueType("true, false, a component number, or a record name or path", _as_vertical)

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
}
EXPLICIT_BLOCKS_KEYS = {"builder", "interface_friction", "slenderness", "allow_free_blocks"}
CONTACT_TYPES = {**{f.name: NUMBER for f in fields(ContactParameters)}, "law": STRING}
EXCITATION_TYPES = {
    "kind": STRING, "source": RECORD_SOURCE, "vertical": VERTICAL, "units": STRING, "component": INTEGER,
    "baseline": BOOLEAN, "resample": BOOLEAN, "dt": NUMBER, "scale": NUMBER, "pga": NUMBER, "amplitude": NUMBER,
    "frequency": NUMBER, "vertical_amplitude": NUMBER, "duration": NUMBER, "rate": NUMBER, "peak": NUMBER,
}
SIMULATION_TYPES = {"duration": NUMBER, "dt": NUMBER, "output_dt": NUMBER, "ground_motion": STRING,
                    "safety": NUMBER, "stop_at_overturn": BOOLEAN, "integrator": STRING, "theta": NUMBER}
OUTPUT_TYPES = {"format": STRING, "plots": BOOLEAN}
BLOCK_TYPES = {"name": STRING, "vertices": POINTS, "density": NUMBER, "friction": NUMBER, "depth": NUMBER,
               "angle": NUMBER}
BASE_TYPES = {"vertices": POINTS, "friction": NUMBER, "depth": NUMBER}
SIMULATION_KEYS = set(SIMULATION_TYPES)
OUTPUT_KEYS = set(OUTPUT_TYPES)
TABLES = ("scene", "contact", "excitation", "simulation", "output", "base")
TOP_LEVEL = {*TABLES, "block"}


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
        with file_errors(path, error, what), open(path, "rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML: {exc}") from None


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
    scene = _scene(tables, path, contact)
    motion = _excitation(tables["excitation"], path)
    _refuse_extreme(tables["excitation"], motion, tables["simulation"], path)
    if tables["output"].get("format", "csv") not in ("csv", "parquet"):
        raise SceneFileError(f"{path}: [output] format must be 'csv' or 'parquet', got {tables['output']['format']!r}")
    return SceneFile(path, scene, motion, tables["simulation"], tables["output"])


def check(data: dict, path=Path("<scene>")) -> dict:
    """The tables of a scene file with every key checked for its name and type and converted (integers
    to int, numbers to float, pairs to tuples); raises :class:`SceneFileError` naming the file, the
    table, the key, the type expected and the value given.  Values are not judged here (a negative
    width is the builder's to refuse)."""
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
                      *(set(inspect.signature(BUILDERS[builder]).parameters) - {"contact", "interface_friction"})}
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
    if converted is MISMATCH:
        raise SceneFileError(f"{path}: {where} {key}: expected {expected.description}, got {_given(value)}"
                             f"{_quoting_hint(value, expected)}")
    return converted


def _quoting_hint(value, expected: ValueType) -> str:
    if not isinstance(value, str):
        return ""
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
    text = repr(value)
    kind = {list: "the array", dict: "the table"}.get(type(value), type(value).__name__)
    return f"{kind} {text if len(text) <= 60 else text[:57] + '...'}"


def _short(value) -> str:
    """``repr(value)``, cut to 60 characters."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


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
    allowed = set(inspect.signature(function).parameters)
    unknown = set(table) - allowed - {"kind"}
    if unknown:
        raise SceneFileError(f"{path}: [excitation] kind {kind!r} has no parameter(s) {sorted(unknown)}"
                             f"{did_you_mean(unknown, allowed)}; its parameters: {sorted(allowed)}", keys=unknown)
    _required(function, table, f"[excitation] kind {kind!r}", path)
    return _checked(table, "[excitation]", path, EXCITATION_TYPES, allowed | {"kind"})


def _scene(tables, path, contact) -> Scene:
    spec = dict(tables["scene"])
    builder_name = spec.pop("builder")
    friction = spec.pop("interface_friction")
    if builder_name == "blocks":
        return _explicit_blocks(tables, spec, path, contact, friction)
    try:
        return BUILDERS[builder_name](**spec, contact=contact, interface_friction=friction)
    except ValueError as exc:
        raise SceneFileError(f"{path}: [scene]: {exc}") from None


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
    if kind == "record":
        for key in ("source", "vertical"):
            value = spec.get(key)
            if isinstance(value, str) and value not in excitation_module.records.BUNDLED:
                spec[key] = str((path.parent / value).resolve())
    try:
        return EXCITATIONS[kind](**spec)
    except ValueError as exc:
        raise SceneFileError(f"{path}: [excitation]: {exc}", keys=getattr(exc, "keys", ())) from None


#: [excitation] keys that set the size of a ground motion, as an extreme one names them
SIZE_KEYS = ("pga", "scale", "amplitude", "frequency", "vertical_amplitude", "peak", "rate", "units")


def _refuse_extreme(spec: dict, motion, simulation: dict, path) -> None:
    """Refuse a ground motion that would peak above ``EXTREME_PGA_G`` (:func:`~.excitation.refuse_extreme`; a ramp
    without a peak by ``[simulation] duration``, when given), naming the keys that set its size."""
    try:
        excitation_module.refuse_extreme(motion, simulation.get("duration"))
    except excitation_module.ExcitationError as exc:
        keys = [key for key in SIZE_KEYS if key in spec] or [key for key in ("source",) if key in spec]
        given = ", ".join(f"{key} = {_short(spec[key])}" for key in keys)
        raise SceneFileError(f"{path}: [excitation] {given}: {exc} (pga, peak and a pulse's amplitude are in m/s^2, "
                             f"a harmonic's amplitude in m, a ramp's rate in m/s^2 per s)", keys=keys) from None
