"""glint.diff: the figures `glint diff --json` prints, for files and for images in memory."""

import json

import numpy as np
import pytest

import glint
from conftest import FIRST_IMAGE, LAMBERT_PLANE, run_glint


@pytest.fixture(scope="module")
def renders(tmp_path_factory):
    folder = tmp_path_factory.mktemp("compare")
    scene = glint.load(FIRST_IMAGE)
    images = {"low": scene.render(spp=8, seed=1, width=64),
              "other": scene.render(spp=8, seed=2, width=64),
              "reference": scene.render(spp=64, seed=3, width=64)}
    for name, image in images.items():
        image.save(folder / f"{name}.exr")
    return folder, images


def cli_diff(*args):
    result = run_glint("diff", *args, "--json")
    assert result.returncode in (0, 1), result.stderr
    return json.loads(result.stdout)


@pytest.mark.parametrize("options, flags", [
    ({}, []),
    ({"fail": 0.05, "fail_percent": 5}, ["--fail", "0.05", "--failpercent", "5"]),
    ({"statistical": True}, ["--statistical"]),
    ({"flip": True}, ["--flip"]),
])
def test_diff_of_files_returns_what_glint_diff_prints(renders, options, flags):
    folder, _ = renders
    a, b = folder / "low.exr", folder / "reference.exr"
    assert glint.diff(a, b, **options) == cli_diff(a, b, *flags)


def test_diff_of_images_in_memory_gives_the_files_figures(renders):
    folder, images = renders
    mine = glint.diff(images["low"], images["reference"], statistical=True)
    theirs = cli_diff(folder / "low.exr", folder / "reference.exr", "--statistical")
    for key in ("verdict", "pass_percent", "global_z", "mean_z2", "spp"):
        assert mine[key] == theirs[key], key
    assert mine["pass"] and mine["spp"] == [8, 64]


def test_statistical_diff_finds_a_darkened_image(renders):
    _, images = renders
    low = images["low"]
    darker = glint.Image(beauty=low.beauty * 0.95, variance=low.variance)
    result = glint.diff(darker, images["reference"], statistical=True, spp_a=8)
    assert not result["pass"] and result["biased"]
    assert glint.diff(glint.Image(beauty=low.beauty, variance=low.variance), images["reference"],
                      statistical=True, spp_a=8)["pass"]


def test_identical_renders_diff_to_zero():
    scene = glint.load(LAMBERT_PLANE)
    result = glint.diff(scene.render(spp=2), scene.render(spp=2))
    assert result["verdict"] == "pass" and result["rmse"] == 0 and result["max_error"] == 0


def test_bad_diff_options_and_files_are_input_errors(renders):
    folder, _ = renders
    with pytest.raises(glint.InputError) as e:
        glint.diff(folder / "low.exr", folder / "reference.exr", fial=1)
    assert e.value.file == "diff()" and e.value.pointer == "/fial"
    with pytest.raises(glint.InputError) as e:
        glint.diff(folder / "low.exr", folder / "reference.exr", min_pass=150)
    assert e.value.pointer == "/min_pass"
    with pytest.raises(glint.InputError) as e:
        glint.diff(folder / "missing.exr", folder / "reference.exr")
    assert "missing.exr" in str(e.value)


def test_an_image_of_arrays_checks_their_shapes():
    with pytest.raises(glint.InputError):
        glint.Image(beauty=np.zeros((4, 4)))
    with pytest.raises(glint.InputError):
        glint.Image(beauty=np.zeros((4, 4, 3)), variance=np.zeros((2, 4, 3)))
