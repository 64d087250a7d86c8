"""Scene.info(): what `glint info` prints, as a dict (the same library code computes both)."""

import re

import pytest

import glint
from conftest import DATA, FIRST_IMAGE, JSON_SCENE, LAMBERT_PLANE, run_glint


def cli_info(scene):
    result = run_glint("info", scene)
    assert result.returncode == 0, result.stderr
    return {line[:11].strip().rstrip(":"): line[12:] for line in result.stdout.splitlines()
            if re.match(r"^[a-z]+: ", line)}


@pytest.mark.parametrize("scene", [LAMBERT_PLANE, FIRST_IMAGE, JSON_SCENE,
                                   DATA / "gltf" / "features.gltf"])
def test_info_holds_what_glint_info_prints(scene):
    info = glint.load(scene).info()
    cli = cli_info(scene)
    image = info["image"]
    auto = " (auto)" if image["integrator_auto"] else ""
    assert cli["image"] == (f"{image['width']}x{image['height']}, {image['spp']} spp, seed "
                            f"{image['seed']}, accel {image['accel']}, integrator "
                            f"{image['integrator']}{auto}")
    assert cli["effects"] == (", ".join(info["effects"]) if info["effects"] else "none")
    assert cli["meshes"].startswith(f"{len(info['meshes'])} ({info['triangles_stored']} "
                                    f"triangles stored, {info['triangles_placed']} placed")
    assert cli["instances"] == str(info["instances"])
    assert cli["cameras"].endswith(f"rendering with '{info['camera']}'")
    assert cli["cameras"].startswith(str(len(info["cameras"])))
    assert cli["lights"].startswith(str(len(info["lights"])))
    assert cli["materials"].startswith(str(len(info["materials"])))
    for light in info["lights"]:
        assert f"({light['type']})" in cli["lights"]


def test_info_names_cameras_lights_and_materials():
    info = glint.load(LAMBERT_PLANE).info()
    assert {"name": "Top", "type": "orthographic"} in info["cameras"]
    assert info["lights"] == [{"name": "Bulb", "type": "point"}]
    assert {"name": "Plane", "type": "lambert"} in info["materials"]
    assert info["image"]["integrator"] == "whitted"
    lower, upper = info["bounds"]
    assert all(lo <= hi for lo, hi in zip(lower, upper))


def test_info_builds_what_the_next_render_uses():
    scene = glint.load(LAMBERT_PLANE)
    scene.info()
    scene.render(spp=1)
    assert scene.builds == 1
