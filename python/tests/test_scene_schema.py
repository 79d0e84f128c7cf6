"""The scene files against their JSON Schemas (docs/*.schema.json, written by `cargo xtask
schema` from the types the parsers read; a Rust test keeps them current).

Every scene under validation/scenes/ and every scene in the documentation's ```toml blocks
must validate against the schema its kind uses; scenes with a wrong type, an unknown key, a
value below a field's minimum, a name not among a choice's, or a missing required key must not.
"""

import json
import pathlib
import re
import sys

import pytest

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

jsonschema = pytest.importorskip("jsonschema")

REPO = pathlib.Path(__file__).resolve().parents[2]
DOCS = REPO / "docs"
SCENES = sorted((REPO / "validation" / "scenes").glob("*.toml"))


def validator(name):
    schema = json.loads((DOCS / name).read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


IMPACT = validator("scene.schema.json")
BEAM = validator("beam-scene.schema.json")


def schema_of(text):
    """The validator a scene's kind uses: a beam scene has `analysis`, an impact scene a ball."""
    return BEAM if "analysis" in tomllib.loads(text) else IMPACT


def errors(text, schema=None):
    scene = tomllib.loads(text)
    return [e.message for e in (schema or schema_of(text)).iter_errors(scene)]


@pytest.mark.parametrize("path", SCENES, ids=lambda p: p.name)
def test_every_example_scene_validates_and_names_its_schema(path):
    text = path.read_text()
    first = text.splitlines()[0]
    expected = "beam-scene.schema.json" if path.name.startswith("beam-") else "scene.schema.json"
    assert first == f"#:schema ../../docs/{expected}", f"{path.name}: first line {first!r}"
    assert (path.parent / first.split()[1]).resolve() == (DOCS / expected).resolve()
    assert errors(text) == []


def documented_scenes():
    """The ```toml blocks of the README and docs/ that are whole scenes (they have a name)."""
    for doc in [REPO / "README.md", *sorted(DOCS.glob("*.md"))]:
        for k, block in enumerate(re.findall(r"```toml\n(.*?)```", doc.read_text(), re.S)):
            if re.search(r"^name = ", block, re.M):
                yield pytest.param(block, id=f"{doc.name}[{k}]")


@pytest.mark.parametrize("text", list(documented_scenes()))
def test_the_documentation_s_scenes_validate(text):
    assert errors(text) == []


def test_the_documentation_has_scenes_to_check():
    # The README's scene and the commands guide's: the parametrised test above is not empty.
    assert len(list(documented_scenes())) >= 2


TIP = (REPO / "validation" / "scenes" / "paper-tip.toml").read_text()
BEND = (REPO / "validation" / "scenes" / "beam-bend45.toml").read_text()


@pytest.mark.parametrize(
    "text, message",
    [
        (TIP.replace("length = 1.15", "length = -1.0"), "less than the minimum"),
        (TIP.replace("length = 1.15", 'length = "long"'), "is not of type 'number'"),
        (TIP.replace("drop_height = 0.2", "drop_height = 0.2\ncolour = 1"), "'colour' was unexpected"),
        (TIP.replace('support = "clamped-free"', 'support = "welded"'), "is not one of"),
        (TIP.replace("poisson_ratio = 0.3", "poisson_ratio = 0.5", 1), "greater than or equal to the maximum"),
        (TIP.replace("modes = 128", "modes = 0"), "less than the minimum"),
        (TIP.replace("radius = 0.005\n", "", 1), "'radius' is a required property"),
        (BEND.replace("elements = ", "elements = -", 1), "less than the minimum"),
        (BEND.replace("start = [0.0, 0.0, 0.0]", "start = [0.0, 0.0]", 1), "is too short"),
    ],
    ids=[
        "negative-length",
        "wrong-type",
        "unknown-key",
        "unknown-support",
        "poisson-at-bound",
        "zero-modes",
        "missing-radius",
        "negative-elements",
        "two-component-point",
    ],
)
def test_broken_scenes_fail_validation(text, message):
    found = errors(text)
    assert any(message in e for e in found), found
