"""Shared pieces of the Python module's tests: where the test data and the glint executable are
(ctest sets them: tests/CMakeLists.txt), and running the command line to compare with it."""

import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("GLINT_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
DATA = pathlib.Path(os.environ.get("GLINT_TEST_DATA", SOURCE / "tests" / "data"))
# The five spheres under the default studio (path tracer); a Lambert plane under a point light
# (Whitted); a .json scene of two triangles.
FIRST_IMAGE = SOURCE / "scenes" / "first_image" / "first_image.gltf"
LAMBERT_PLANE = DATA / "scenes" / "lambert_plane.gltf"
TRIANGLE = DATA / "sidecar" / "triangle.gltf"
JSON_SCENE = DATA / "sidecar" / "scene.json"


def glint_executable():
    path = os.environ.get("GLINT_EXECUTABLE")
    if not path:
        raise RuntimeError("GLINT_EXECUTABLE is not set: run these tests through ctest "
                           "(tests/CMakeLists.txt sets it), or set it to build-tests/glint")
    return path


def run_glint(*args):
    """Runs the glint command line; returns the CompletedProcess (text output)."""
    return subprocess.run([glint_executable(), *map(str, args)], capture_output=True, text=True,
                          check=False)


@pytest.fixture
def out(tmp_path):
    return tmp_path
