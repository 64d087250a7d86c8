"""glint.load: scene files, dicts in the scene and sidecar schemas, and bad input raised as
glint.InputError with the file and the JSON pointer, as the command line reports it."""

import numpy as np
import pytest

import glint
from conftest import JSON_SCENE, LAMBERT_PLANE, TRIANGLE, run_glint, DATA


def test_loads_a_gltf_with_its_sidecar():
    scene = glint.load(LAMBERT_PLANE)
    assert "Top" in scene.cameras
    assert scene.file == str(LAMBERT_PLANE)


def test_loads_a_json_scene_file():
    scene = glint.load(JSON_SCENE)
    assert scene.render(spp=1).shape == scene.render(spp=2).shape


def test_a_scene_dict_renders_as_the_same_json_file_does():
    import json
    doc = json.loads(JSON_SCENE.read_text())
    from_dict = glint.load(doc, base_dir=JSON_SCENE.parent).render(spp=2)
    from_file = glint.load(JSON_SCENE).render(spp=2)
    assert np.array_equal(from_dict.beauty, from_file.beauty)
    assert np.array_equal(from_dict.alpha, from_file.alpha)


def test_a_scene_dict_listing_a_gltf_renders_as_the_gltf_with_its_sidecar():
    import json
    doc = json.loads((DATA / "scenes" / "lambert_plane.glint.json").read_text())
    doc["gltf"] = ["lambert_plane.gltf"]
    from_dict = glint.load(doc, base_dir=LAMBERT_PLANE.parent).render(spp=2)
    from_files = glint.load(LAMBERT_PLANE).render(spp=2)
    assert np.array_equal(from_dict.beauty, from_files.beauty)
    assert from_dict.beauty.max() > 0


def test_a_sidecar_dict_applies_as_the_sidecar_file_does():
    import json
    sidecar = json.loads((DATA / "scenes" / "lambert_plane.glint.json").read_text())
    sidecar["render"]["spp"] = 2
    from_dict = glint.load(LAMBERT_PLANE, sidecar=sidecar).render()
    from_file = glint.load(LAMBERT_PLANE).render(spp=2)
    assert from_dict.spp == 2
    assert (from_dict.beauty == from_file.beauty).all()


def test_an_unknown_key_names_the_dict_and_the_pointer():
    with pytest.raises(glint.InputError) as e:
        glint.load(TRIANGLE, sidecar={"render": {"spq": 4}})
    assert e.value.pointer == "/render/spq"
    assert e.value.file.endswith("<dict>")
    assert "did you mean 'spp'?" in str(e.value)


def test_a_missing_file_is_an_input_error_naming_it():
    with pytest.raises(glint.InputError) as e:
        glint.load("no_such_scene.glb")
    assert e.value.file == "no_such_scene.glb"
    assert e.value.pointer is None
    assert "not found" in str(e.value)


def test_a_bad_sidecar_file_reads_as_the_command_line_says_it(out):
    sidecar = DATA / "sidecar" / "bad_intensity.glint.json"
    with pytest.raises(glint.InputError) as e:
        glint.load(TRIANGLE, sidecar=sidecar)
    cli = run_glint("render", TRIANGLE, "--sidecar", sidecar, "-o", out / "x.exr")
    assert cli.returncode == 2
    assert cli.stderr.strip() == f"glint: {e.value}"
    assert e.value.file == str(sidecar)
    assert e.value.pointer == "/lights/1/intensity"
    assert isinstance(e.value, ValueError)  # an InputError is a ValueError too


@pytest.mark.parametrize("value, pointer, words", [
    ({1, 2}, "/render/spp", "got set"),
    (float("nan"), "/render/spp", "must be finite"),
    ("many", "/render/spp", "expected"),
    (-3, "/render/spp", "must be"),
])
def test_a_wrong_python_value_is_an_input_error_at_its_pointer(value, pointer, words):
    with pytest.raises(glint.InputError) as e:
        glint.load(TRIANGLE, sidecar={"render": {"spp": value}})
    assert e.value.pointer == pointer
    assert words in str(e.value)


def test_a_key_that_is_not_a_string_is_an_input_error():
    with pytest.raises(glint.InputError) as e:
        glint.load(TRIANGLE, sidecar={"render": {1: 2}})
    assert e.value.pointer == "/render"


def test_numpy_numbers_and_tuples_are_json_values():
    import numpy as np
    scene = glint.load(TRIANGLE, sidecar={"render": {"spp": np.int64(2), "width": 16,
                                                     "background": (np.float32(0.5), 0.5, 0.5)}})
    assert scene.render().spp == 2


def test_wrong_argument_types_raise_type_errors():
    with pytest.raises(TypeError):
        glint.load(42)
    with pytest.raises(TypeError):
        glint.load(TRIANGLE, time="noon")
