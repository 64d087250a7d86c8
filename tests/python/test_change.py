"""Change and render again: a material parameter, a light's intensity, a camera's placement,
without reading the scene's files again; the image is the one a fresh load of the changed scene
gives, to the last bit."""

import copy
import json

import numpy as np
import pytest

import glint
from conftest import DATA, FIRST_IMAGE, LAMBERT_PLANE

SIDECAR = json.loads((DATA / "scenes" / "lambert_plane.glint.json").read_text())


def fresh(change, spp=4):
    sidecar = copy.deepcopy(SIDECAR)
    change(sidecar)
    return glint.load(LAMBERT_PLANE, sidecar=sidecar).render(spp=spp)


def test_a_material_parameter_changes_as_a_fresh_load_of_it_renders():
    scene = glint.load(LAMBERT_PLANE)
    before = scene.render(spp=4)
    scene.update({"materials": [{"name": "Plane", "diffuse": [0.8, 0.2, 0.2]}]})
    after = scene.render(spp=4)
    expected = fresh(lambda s: s["materials"][0].update(diffuse=[0.8, 0.2, 0.2]))
    assert np.array_equal(after.beauty, expected.beauty)
    assert not np.array_equal(after.beauty, before.beauty)


def test_a_lights_intensity_changes_as_a_fresh_load_of_it_renders():
    scene = glint.load(LAMBERT_PLANE)
    before = scene.render(spp=4)
    scene.set_light("Bulb", intensity=25)
    after = scene.render(spp=4)
    expected = fresh(lambda s: s["lights"][0].update(intensity=25))
    assert np.array_equal(after.beauty, expected.beauty)
    assert after.beauty.mean() > 2 * before.beauty.mean()


def test_a_cameras_placement_changes_as_a_fresh_load_of_it_renders():
    scene = glint.load(LAMBERT_PLANE)
    top = {"name": "Top", "type": "perspective", "position": [1, 3, 1], "look_at": [0, 0, 0]}
    scene.update({"cameras": [top]})
    after = scene.render(spp=4)
    expected = fresh(lambda s: s.setdefault("cameras", []).append(top))
    assert np.array_equal(after.beauty, expected.beauty)


def test_changes_last_for_a_render_at_another_time():
    scene = glint.load(LAMBERT_PLANE)
    scene.set_light("Bulb", intensity=25)
    assert np.array_equal(scene.render(spp=2, time=0.5).beauty, scene.render(spp=2).beauty)


def loaded_then_deleted(tmp_path):
    """The plane loaded and rendered from a copy whose files are then deleted: a render after a
    change can only work if nothing is read again."""
    folder = tmp_path / "scene"
    folder.mkdir()
    names = ("lambert_plane.gltf", "lambert_plane.glint.json")
    for name in names:
        (folder / name).write_bytes((DATA / "scenes" / name).read_bytes())
    scene = glint.load(folder / "lambert_plane.gltf")
    scene.render(spp=1)
    for name in names:
        (folder / name).unlink()
    return scene


def test_a_light_or_camera_change_rebuilds_only_them_and_reads_no_file(tmp_path):
    scene = loaded_then_deleted(tmp_path)
    assert (scene.builds, scene.refreshes) == (1, 0)
    scene.set_light("Bulb", intensity=5)
    lit = scene.render(spp=2)
    # Only the lights were made again: no build (geometry, accelerator, materials, textures).
    assert (scene.builds, scene.refreshes) == (1, 1)
    assert np.array_equal(lit.beauty,
                          fresh(lambda s: s["lights"][0].update(intensity=5), spp=2).beauty)
    scene.update({"cameras": [{"name": "Top", "type": "perspective", "position": [1, 3, 1],
                               "look_at": [0, 0, 0]}]})
    scene.render(spp=1)
    assert (scene.builds, scene.refreshes) == (1, 2)
    scene.render(spp=1, seed=3)
    assert (scene.builds, scene.refreshes) == (1, 2)


def test_a_refreshed_scene_renders_as_a_fresh_load_of_the_change():
    scene = glint.load(LAMBERT_PLANE)
    scene.render(spp=1)
    scene.set_light("Bulb", intensity=25, color=[1, 0.5, 0.25])
    top = {"name": "Top", "type": "perspective", "position": [1, 3, 1], "look_at": [0, 0, 0]}
    scene.update({"cameras": [top]})
    after = scene.render(spp=4)
    assert scene.refreshes == 1 and scene.builds == 1

    def change(s):
        s["lights"][0].update(intensity=25, color=[1, 0.5, 0.25])
        s.setdefault("cameras", []).append(top)
    assert np.array_equal(after.beauty, fresh(change).beauty)


def test_a_material_change_replaces_the_material_alone_and_reads_no_file(tmp_path):
    scene = loaded_then_deleted(tmp_path)
    build = scene.timings["build_seconds"]
    scene.update({"materials": [{"name": "Plane", "diffuse": [0.8, 0.2, 0.2]}]})
    changed = scene.render(spp=2)
    # The material was made again inside the kept render scene (refreshMaterials): no build,
    # so neither the geometry nor its accelerator was made again.
    assert (scene.builds, scene.refreshes) == (1, 1)
    assert scene.timings["build_seconds"] == build > 0
    assert np.array_equal(changed.beauty,
                          fresh(lambda s: s["materials"][0].update(diffuse=[0.8, 0.2, 0.2]),
                                spp=2).beauty)


def first_image_fresh(sidecar, spp):
    return glint.load(FIRST_IMAGE, sidecar=sidecar).render(spp=spp, width=96, height=72)


@pytest.mark.parametrize("change", [
    # A sphere made to glow: its surface lights are made again (the path tracer samples them).
    {"name": "WhiteDiffuse", "emissive": [4, 3, 2]},
    # Another type altogether, and two materials at once.
    [{"name": "Gold", "type": "lambert", "diffuse": [0.2, 0.7, 0.3]},
     {"name": "RedPlastic", "roughness": 0.05}],
], ids=["emission", "type_and_two_materials"])
def test_material_changes_in_a_kept_scene_render_as_a_fresh_load(change):
    changes = change if isinstance(change, list) else [change]
    scene = glint.load(FIRST_IMAGE)
    before = scene.render(spp=4, width=96, height=72)
    scene.update({"materials": changes})
    after = scene.render(spp=4, width=96, height=72)
    assert (scene.builds, scene.refreshes) == (1, 1)
    assert np.array_equal(after.beauty, first_image_fresh({"materials": changes}, 4).beauty)
    assert not np.array_equal(after.beauty, before.beauty)
    # The emitting sphere lights the rest: the path tracer's surface lights were remade.
    if "emissive" in changes[0]:
        assert after.beauty.mean() > before.beauty.mean()


def test_a_textured_materials_parameter_changes_with_the_scenes_own_texture():
    checks = {"textures": [{"name": "Checks", "type": "checker"}],
              "materials": [{"name": "Floor", "base_color": "Checks", "roughness": 0.9}]}
    scene = glint.load(FIRST_IMAGE, sidecar=checks)
    scene.render(spp=1, width=96, height=72)
    change = {"name": "Floor", "roughness": 0.2, "metallic": 0.5}
    scene.update({"materials": [change]})
    after = scene.render(spp=2, width=96, height=72)
    assert (scene.builds, scene.refreshes) == (1, 1)
    both = dict(checks, materials=[dict(checks["materials"][0], **change)])
    assert np.array_equal(after.beauty, first_image_fresh(both, 2).beauty)


@pytest.mark.parametrize("change", [
    {"name": "Floor", "double_sided": True},  # the accelerator culls by it
    {"name": "Fresh", "type": "lambert", "diffuse": [1, 0, 0], "nodes": ["Floor"]},
    {"name": "Floor", "base_color": "Checks"},  # a texture lives with the scene's
], ids=["sidedness", "new_material_on_a_node", "texture"])
def test_material_changes_a_refresh_cannot_make_build_again(change):
    extra = {"textures": [{"name": "Checks", "type": "checker"}]}
    scene = glint.load(FIRST_IMAGE, sidecar=extra)
    scene.render(spp=1, width=96, height=72)
    scene.update({"materials": [change]})
    after = scene.render(spp=2, width=96, height=72)
    assert (scene.builds, scene.refreshes) == (2, 0)
    assert np.array_equal(after.beauty,
                          first_image_fresh(dict(extra, materials=[change]), 2).beauty)


def test_bad_changes_are_input_errors_and_change_nothing():
    scene = glint.load(LAMBERT_PLANE)
    before = scene.render(spp=2)
    with pytest.raises(glint.InputError) as e:
        scene.update({"materials": [{"name": "Plane", "difuse": [1, 0, 0]}]})
    assert e.value.file == "update()" and e.value.pointer == "/materials/0/difuse"
    with pytest.raises(glint.InputError) as e:
        scene.set_light("Lamp", intensity=3)
    assert "'Bulb'" in str(e.value)
    with pytest.raises(glint.InputError):
        scene.set_light("Bulb", intensity=-1)
    with pytest.raises(TypeError):
        scene.set_light("Bulb", intensity="bright")
    assert np.array_equal(scene.render(spp=2).beauty, before.beauty)
