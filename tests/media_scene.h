// glint tests — the scene the media tests render: an orthographic camera on +z looking down -z
// at [-half, half]^2, a box filter of one pixel (so a pixel's expectation is the mean over its
// own square), and a small far-away triangle out of view so that the geometry is not empty.
// Media and lights are added by the tests.
#pragma once

#include <string>

#include "scenes/description.h"

namespace glint::test {

inline SceneDescription orthographicMediaScene(int size, int spp, float half,
                                               const std::string& integrator, int maxDepth) {
  SceneDescription d;
  d.file = "media test scene (in code)";
  MeshDesc far;
  far.positions = {{100, 100, 100}, {101, 100, 100}, {100, 101, 100}};
  far.indices = {0, 1, 2};
  d.meshes.push_back(far);
  d.instances.push_back({0, Transform(), "far", {}});
  CameraDesc cam;
  cam.name = "c";
  cam.type = CameraType::Orthographic;
  cam.xmag = cam.ymag = half;
  cam.worldFromCamera = Transform::lookAt({0, 0, 6}, {0, 0, 0}, {0, 1, 0});
  d.cameras.push_back(cam);
  d.render.width = d.render.height = size;
  d.render.spp = spp;
  d.render.filter = {"box", 0.5f};
  d.render.integrator.type = integrator;
  d.render.integrator.maxDepth = maxDepth;
  return d;
}

}  // namespace glint::test
