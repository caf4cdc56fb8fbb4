"""A scene as plain JSON, for other tools and for the record of a run: every block's outline as built (tilts,
offsets and chipped outlines included), the contact law's parameters, the friction overrides and the connectors.

No well-kept interchange format describes rigid blocks with a contact law (OpenSees' own describes frames and
springs, not blocks in contact), so the format is this project's, written down as a JSON Schema in
``dem_core/data/scene.schema.json``.  :func:`scene_to_json` and :func:`scene_from_json` are each other's inverse: a
scene read back runs bit for bit as the scene written (tests/test_scene_json.py).  An unbounded rupture slip is
written as ``null``, since JSON has no infinity.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np

from .engine.contact import ContactParameters
from .inputs.connectors import Connector, ConnectorKind
from .inputs.errors import SceneError
from .inputs.number_types import is_real
from .inputs.scene import Block, Scene
from .output_files import replacing

#: the format's version, written as ``"format"``
FORMAT = "dem-colonnade scene 1"
#: the JSON Schema of the format
SCHEMA = Path(__file__).resolve().parent / "data" / "scene.schema.json"
_BLOCK_KEYS = ("name", "vertices", "density", "depth", "friction", "angle")


def _block(block: Block) -> dict:
    return {"name": block.name, "vertices": np.asarray(block.vertices, float).tolist(), "density": block.density,
            "depth": block.depth, "friction": block.friction, "angle": block.angle}


def _finite_or_none(value):
    return None if isinstance(value, float) and math.isinf(value) else value


def scene_to_json(scene: Scene) -> dict:
    """The JSON description of ``scene`` (a dict of JSON types; ``json.dumps`` writes it)."""
    return {
        "format": FORMAT,
        "units": {"length": "m", "mass": "kg", "time": "s", "angle": "rad", "force": "N"},
        "gravity": scene.gravity,
        "base": _block(scene.base),
        "blocks": [_block(block) for block in scene.blocks],
        "contact": dataclasses.asdict(scene.contact),
        "interface_friction": [{"between": list(pair), "friction": mu}
                               for pair, mu in sorted(scene.interface_friction.items())],
        "connectors": [{"between": list(c.between), "position": c.position,
                        "kind": {k: _finite_or_none(v) for k, v in dataclasses.asdict(c.kind).items()}}
                       for c in scene.connectors],
        "overlap_tolerance": scene.overlap_tolerance,
        "slenderness": scene.slenderness,
        "allow_free_blocks": scene.allow_free_blocks,
    }


def _read_block(data: dict, where: str) -> Block:
    if not isinstance(data, dict):
        raise SceneError(f"{where}: a block is an object with {', '.join(_BLOCK_KEYS)}")
    unknown = sorted(set(data) - set(_BLOCK_KEYS))
    if unknown:
        raise SceneError(f"{where}: unknown keys {unknown}")
    return Block(**{**data, "vertices": np.asarray(data.get("vertices"), dtype=float)})


def _read_connector(data, where: str) -> Connector:
    if not isinstance(data, dict) or not isinstance(data.get("kind"), dict):
        raise SceneError(f"{where}: a connector is an object with 'between', 'kind' (an object of its kind's "
                         f"parameters) and 'position'")
    try:
        kind = ConnectorKind(**{k: math.inf if k == "rupture_slip" and v is None else v
                                for k, v in data["kind"].items()})
        return Connector(tuple(data["between"]), kind, data["position"])
    except KeyError as missing:
        raise SceneError(f"{where}: has no {missing}") from None
    except (TypeError, ValueError) as error:
        raise SceneError(f"{where}: {error}") from None


def _number(data: dict, key: str, none: bool = False):
    value = data[key]
    if (value is None and none) or is_real(value):
        return value
    raise SceneError(f"the scene's JSON: {key!r} is {value!r}, not a number")


def scene_from_json(data: dict) -> Scene:
    """The :class:`Scene` that ``data`` (as :func:`scene_to_json` writes it) describes; :class:`SceneError` naming
    the key at fault."""
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise SceneError(f"not a scene in the format {FORMAT!r} (its 'format' is "
                         f"{data.get('format') if isinstance(data, dict) else None!r})")
    try:
        contact = ContactParameters(**data["contact"])
        connectors = tuple(_read_connector(c, f"connectors[{k}]") for k, c in enumerate(data.get("connectors", [])))
        friction = {tuple(f["between"]): f["friction"] for f in data.get("interface_friction", [])}
        return Scene(tuple(_read_block(b, f"blocks[{k}]") for k, b in enumerate(data["blocks"])),
                     _read_block(data["base"], "base"), contact, friction, _number(data, "gravity"),
                     _number(data, "overlap_tolerance"), _number(data, "slenderness", none=True),
                     data["allow_free_blocks"], connectors)
    except KeyError as missing:
        raise SceneError(f"the scene's JSON has no {missing}") from None
    except TypeError as error:
        raise SceneError(f"the scene's JSON: {error}") from None


def write_scene_json(scene: Scene, path) -> None:
    """Write ``scene`` to ``path`` as indented JSON, whole or not at all."""
    with replacing(path) as tmp:
        Path(tmp).write_text(json.dumps(scene_to_json(scene), indent=1) + "\n", encoding="utf-8")


def read_scene_json(path) -> Scene:
    """The scene in the JSON file ``path``."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except json.JSONDecodeError as error:
        raise SceneError(f"{path}: not JSON ({error})") from None
    return scene_from_json(data)
