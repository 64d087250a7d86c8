"""VDB volumes from Python: the gallery's cloud and fire of scenes/volumes/, their .vdb files
written by glint_make_vdb_scenes (ctest gives its path), listed by Scene.info() as by
`glint info`, and rendered to the same bits as the command line renders them."""

import json
import os
import re
import shutil
import subprocess

import numpy as np
import pytest

import glint
from conftest import SOURCE, run_glint


@pytest.fixture(scope="module")
def volumes(tmp_path_factory):
    """A folder with cloud.json, fire.json and their .vdb files."""
    tool = os.environ.get("GLINT_MAKE_VDB_SCENES")
    if not tool:
        raise RuntimeError("GLINT_MAKE_VDB_SCENES is not set: run these tests through ctest "
                           "(tests/CMakeLists.txt sets it)")
    folder = tmp_path_factory.mktemp("volumes")
    subprocess.run([tool, str(folder)], check=True, capture_output=True)
    for name in ("cloud", "fire"):
        shutil.copy(SOURCE / "scenes" / "volumes" / f"{name}.json", folder)
    return folder


def test_info_lists_each_grid_as_glint_info_does(volumes):
    scene = volumes / "fire.json"
    media = glint.load(scene).info()["media"]
    assert len(media) == 1
    fire = media[0]
    assert fire["vdb_file"].endswith("fire.vdb")
    assert fire["vdb_bytes"] > 0
    names = {g["name"]: g for g in fire["grids"]}
    assert {"density", "temperature", "flame"} <= set(names)
    cli = run_glint("info", scene)
    assert cli.returncode == 0, cli.stderr
    for name, grid in names.items():
        assert grid["type"] == "float"
        assert grid["active_voxels"] > 0
        # `glint info`: "grid 'density': float, voxel ..., N active voxels, ..."
        line = re.search(rf"grid '{name}': .*?(\d+) active voxels", cli.stdout)
        assert line, cli.stdout
        assert int(line.group(1)) == grid["active_voxels"]


@pytest.mark.parametrize("name", ["cloud", "fire"])
def test_a_vdb_render_equals_the_command_lines_to_the_last_bit(volumes, name, tmp_path):
    scene = volumes / f"{name}.json"
    exr = tmp_path / f"{name}.exr"
    cli = run_glint("render", scene, "-o", exr, "--quiet", "--spp", "2", "--seed", "5",
                    "--width", "64", "--height", "36")
    assert cli.returncode == 0, cli.stderr
    image = glint.load(scene).render(spp=2, seed=5, width=64, height=36)
    written = glint.read(exr)
    assert np.isfinite(image.beauty).all()
    assert np.array_equal(image.beauty, written.beauty)
    # The volume is in the picture: the image is not the sky and ground alone.
    empty = json.loads(scene.read_text())
    del empty["media"]
    without = glint.load(empty, base_dir=str(volumes)).render(spp=2, seed=5, width=64, height=36)
    assert np.abs(image.beauty - without.beauty).max() > 0.1
