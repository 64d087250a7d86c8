// glint — what a scene holds and which effects it calls for: what `glint info` prints and the
// Python module's Scene.info() returns, worked out once here for both.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "renderer/scene.h"
#include "scenes/description.h"
#include "scenes/vdb_file.h"

namespace glint {

struct SceneInfo {
  struct Named {  // a material, camera or light: its name ("" when unnamed) and its type
    std::string name, type;
  };
  // A glTF node that places meshes, as a sidecar material's "nodes" list names it, with the
  // names of its meshes ("mesh 3" for an unnamed one).
  struct Node {
    std::string name;
    std::vector<std::string> meshes;
  };
  // An analytic object of the sidecar: its shape's type ("sphere"), or "csg" with its leaves,
  // or "terrain" with its triangles.
  struct Object {
    std::string name, type;
    size_t leaves = 0, triangles = 0;
  };

  std::string file;
  std::vector<std::string> warnings;
  std::vector<std::string> meshes;  // names, "" when unnamed
  size_t trianglesStored = 0, trianglesPlaced = 0;
  size_t instances = 0;
  std::vector<Node> nodes;  // in file order, each once
  std::vector<Object> objects;
  std::vector<Named> materials;
  size_t textures = 0, images = 0;
  // Where each image the textures read lives (TextureImages::describe), and the bytes of those
  // held in memory once decoded; `imagesListed` false when the scene has no image set.
  bool imagesListed = false;
  std::vector<std::string> imageDescriptions;
  size_t imageBytes = 0;
  std::vector<std::string> variants;
  std::string variant;  // the one shown ("" for the defaults)
  std::vector<Named> cameras;
  std::string camera;  // the one rendering
  std::vector<Named> lights;
  // Participating media, and every grid of each VDB file they read: what a user needs to name
  // grids in the sidecar and to judge the memory a volume takes.
  struct Medium {
    std::string name, type;          // its density's type: "constant", "grid", "noise", ..., "vdb"
    std::string vdbFile;             // "" unless it reads a VDB file
    size_t vdbBytes = 0;             // held in memory: its NanoVDB grids and majorant grid
    std::vector<VdbGridInfo> grids;  // every grid of the file, in file order
  };
  std::vector<Medium> media;
  std::vector<UnsampledEmitter> unsampledEmitters;
  Bounds3f bounds;
  int width = 0, height = 0, spp = 0;
  uint64_t seed = 0;
  std::string accel, integrator;  // the integrator resolved ("auto" picked it when integratorAuto)
  bool integratorAuto = false;
  // Animation: nodes with keys, the keys' time range and the frames that cover it at fps.
  size_t animatedNodes = 0;
  double animationStart = 0, animationEnd = 0, fps = 24;
  long long firstFrame = 0, lastFrame = 0;
  // Motion blur's cost: placements that move over the shutter (the most keys of one) and meshes
  // that deform (the most time steps of one).
  size_t moving = 0, movingKeys = 0, deforming = 0, deformSteps = 0;
  std::vector<std::string> effects;  // SceneFeatures::names()
};

// What `desc` holds and what `scene`, built from it, calls for.
SceneInfo describeScene(const SceneDescription& desc, const RenderScene& scene);

// "point", "spot", "directional", "quad", "disk", "sphere", "projective".
const char* lightTypeName(LightType type);

// The whole frames that cover the animation's keys from `start` to `end` seconds at `fps`: the
// last frame at or before the first key to the first at or after the last, as --frames takes
// them (never below 0).
std::pair<long long, long long> framesCovering(double start, double end, double fps);

}  // namespace glint
