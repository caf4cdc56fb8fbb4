"""A scene as JSON: written and read back it runs bit for bit as the scene written (both integrators, connectors,
tilts and friction overrides), it follows its own JSON Schema (dem_core/data/scene.schema.json), every run's
folder holds it, and a broken description is refused naming the key at fault."""

import json

import numpy as np
import pytest

import dem_core
from dem_core import excitation, scenes
from dem_core.cli import main
from dem_core.inputs.connectors import OAK_POLOS, Placement, titanium_bar
from dem_core.inputs.errors import SceneError
from dem_core.scene_json import SCHEMA, read_scene_json, scene_from_json, scene_to_json, write_scene_json

MOTION = excitation.record("el_centro_1940", pga=3.0)


def _conforms(value, schema: dict, root: dict, where: str = "$") -> list:
    """What of ``value`` breaks ``schema``: the part of JSON Schema the format uses (type, const, enum, minLength,
    required, properties, additionalProperties: false, items, minItems, maxItems, $ref)."""
    if "$ref" in schema:
        return _conforms(value, root["$defs"][schema["$ref"].split("/")[-1]], root, where)
    kinds = {"object": dict, "array": list, "string": str, "boolean": bool, "null": type(None),
             "number": (int, float)}
    wanted = schema.get("type")
    if wanted is not None:
        allowed = [wanted] if isinstance(wanted, str) else wanted
        fits = [k for k in allowed if isinstance(value, kinds[k]) and not (k == "number" and isinstance(value, bool))]
        if not fits:
            return [f"{where}: {type(value).__name__}, not {wanted}"]
    wrong = []
    if "const" in schema and value != schema["const"]:
        wrong.append(f"{where}: {value!r}, not {schema['const']!r}")
    if "enum" in schema and value not in schema["enum"]:
        wrong.append(f"{where}: {value!r}, not one of {schema['enum']}")
    if isinstance(value, str) and len(value) < schema.get("minLength", 0):
        wrong.append(f"{where}: {value!r}, shorter than {schema['minLength']}")
    if isinstance(value, dict):
        wrong += [f"{where}: no {key!r}" for key in schema.get("required", []) if key not in value]
        properties = schema.get("properties", {})
        if schema.get("additionalProperties") is False:
            wrong += [f"{where}: {key!r} is not in the schema" for key in value if key not in properties]
        for key, item in value.items():
            if key in properties:
                wrong += _conforms(item, properties[key], root, f"{where}.{key}")
    if isinstance(value, list):
        if not schema.get("minItems", 0) <= len(value) <= schema.get("maxItems", len(value)):
            wrong.append(f"{where}: {len(value)} items")
        wrong += [x for k, item in enumerate(value) for x in _conforms(item, schema.get("items", {}), root,
                                                                      f"{where}[{k}]")]
    return wrong


def restored_colonnade():
    """A colonnade with most of what a scene can hold: a tilted foundation, a dislocated drum, friction overrides,
    titanium bars at every joint and oak poles at the capitals."""
    return scenes.colonnade(n_columns=2, foundation_tilt=0.004, offsets={"c1_drum2": 0.01},
                            interface_friction={("c2_drum1", "c2_drum2"): 0.55},
                            connectors=[Placement(titanium_bar(0.016), "all"), Placement(OAK_POLOS, "capital")])


@pytest.mark.parametrize(("build", "integrator"), [(scenes.column, "moreau"), (scenes.column, "explicit"),
                                                   (restored_colonnade, "moreau")])
def test_a_scene_read_back_from_its_json_runs_bit_for_bit_as_the_scene_written(build, integrator, tmp_path):
    scene = build()
    write_scene_json(scene, tmp_path / "scene.json")
    again = read_scene_json(tmp_path / "scene.json")
    assert scene_to_json(again) == scene_to_json(scene)
    first, second = (dem_core.simulate(s, MOTION, duration=1.5, integrator=integrator) for s in (scene, again))
    assert np.array_equal(first.theta, second.theta) and np.array_equal(first.x, second.x)
    if build is restored_colonnade:
        assert len(scene.connectors) == 6 and scene.interface_friction
        assert np.array_equal(first.connectors.peak_shear_N, second.connectors.peak_shear_N)


def test_the_json_follows_its_schema():
    schema = json.loads(SCHEMA.read_text())
    for scene in (scenes.column(), restored_colonnade(), scenes.block(1.0, 6.0)):
        written = json.loads(json.dumps(scene_to_json(scene)))  # as a file holds it: null for an infinite slip
        assert _conforms(written, schema, schema) == []
    assert _conforms({"format": "x"}, schema, schema)[:2] == ["$: no 'units'", "$: no 'gravity'"]
    unnamed = json.loads(json.dumps(scene_to_json(scenes.block(1.0, 6.0))))
    unnamed["blocks"][0]["name"] = ""
    assert _conforms(unnamed, schema, schema) == ["$.blocks[0].name: '', shorter than 1"]


def test_every_run_folder_holds_its_scene(tmp_path):
    out = tmp_path / "run"
    assert main(["run", "--out", str(out), "--duration", "0.5", "--no-plots"]) == 0
    assert len(read_scene_json(out / "scene.json").blocks) == 8
    assert "scene.json" in json.loads((out / "summary.json").read_text())["files"]


def test_a_broken_description_is_refused_naming_what_is_wrong():
    data = scene_to_json(scenes.column(2))
    with pytest.raises(SceneError, match="has no 'contact'"):
        scene_from_json({k: v for k, v in data.items() if k != "contact"})
    with pytest.raises(SceneError, match="format"):
        scene_from_json({**data, "format": "something else"})
    with pytest.raises(SceneError, match=r"blocks\[1\]: unknown keys \['mass'\]"):
        scene_from_json({**data, "blocks": [data["blocks"][0], {**data["blocks"][1], "mass": 1.0}]})
    with pytest.raises(SceneError, match=r"'gravity' is '9.81', not a number"):
        scene_from_json({**data, "gravity": "9.81"})


def test_a_broken_connector_is_refused_naming_it():
    """A connector's kind written as a name (easily done by hand), or a connector without its position, is refused
    naming the connector."""
    data = scene_to_json(restored_colonnade())
    bars = data["connectors"]
    assert bars
    with pytest.raises(SceneError, match=r"connectors\[0\]: a connector is an object with 'between', 'kind'"):
        scene_from_json({**data, "connectors": [{**bars[0], "kind": "titanium bar"}, *bars[1:]]})
    with pytest.raises(SceneError, match=r"connectors\[1\]: has no 'position'"):
        scene_from_json({**data, "connectors": [bars[0], {k: v for k, v in bars[1].items() if k != "position"}]})
