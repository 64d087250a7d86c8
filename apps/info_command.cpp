// glint — `glint info`: what a scene holds and which effects it calls for.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/frames.h"
#include "materials/image_texture.h"
#include "renderer/integrator.h"
#include "scenes/build.h"
#include "scenes/load.h"
#include "scenes/vdb_file.h"

namespace glint::app {

namespace {

struct InfoArgs {
  std::string scene;
  std::optional<std::string> sidecar;
  std::optional<std::string> frames;  // --frames A-B[:STEP]
  SceneOverrides overrides;
};

const char* lightTypeName(LightType t) {
  switch (t) {
    case LightType::Point:
      return "point";
    case LightType::Spot:
      return "spot";
    case LightType::Directional:
      return "directional";
    case LightType::Quad:
      return "quad";
    case LightType::Disk:
      return "disk";
    case LightType::Sphere:
      return "sphere";
    case LightType::Projective:
      return "projective";
  }
  return "?";
}

// "a, b, c" of up to `limit` names, then "... (N more)".
template <class T, class F>
std::string listNames(const std::vector<T>& items, F name, size_t limit = 8) {
  std::string s;
  for (size_t i = 0; i < items.size() && i < limit; ++i) s += (i ? ", " : "") + name(items[i]);
  if (items.size() > limit) s += ", ... (" + std::to_string(items.size() - limit) + " more)";
  return s;
}

// "ball (sphere)", "dice (csg, 7 leaves)", "mountain (terrain, 32768 triangles)".
std::string objectSummary(const ObjectDesc& o) {
  std::string name = o.name.empty() ? std::string("(unnamed)") : o.name;
  switch (o.kind) {
    case ObjectKind::Shape:
      return name + " (" + o.shape->typeName() + ")";
    case ObjectKind::Csg: {
      size_t leaves = 0;
      for (const CsgNodeDesc& n : o.csg.nodes) leaves += n.op == CsgOp::Leaf;
      return name + " (csg, " + std::to_string(leaves) + " leaves)";
    }
    case ObjectKind::Terrain:
      return name + " (terrain, " + std::to_string(2ull << (2 * o.terrain.depth)) + " triangles)";
  }
  return name;
}

// The glTF nodes that place a mesh, each with its meshes, as a sidecar material's "nodes" list
// names them (scenes/sidecar_materials.cpp matches InstanceDesc::node): "'CubeLeft' (mesh
// 'Cube')". A node placed several times (EXT_mesh_gpu_instancing) or holding a mesh of several
// primitives (one MeshDesc each, "Name (primitive 1)") is listed once, in file order.
std::string nodeSummary(const SceneDescription& desc) {
  std::vector<std::pair<std::string, std::vector<std::string>>> nodes;
  for (const InstanceDesc& inst : desc.instances) {
    auto it = std::find_if(nodes.begin(), nodes.end(),
                           [&](const auto& n) { return n.first == inst.node; });
    if (it == nodes.end()) it = nodes.insert(nodes.end(), {inst.node, {}});
    const std::string& mesh = desc.meshes[size_t(inst.mesh)].name;
    const std::string name = mesh.empty() ? "mesh " + std::to_string(inst.mesh) : mesh;
    if (std::find(it->second.begin(), it->second.end(), name) == it->second.end())
      it->second.push_back(name);
  }
  return std::to_string(nodes.size()) +
         " with a mesh (names for a sidecar material's "
         "\"nodes\"): " +
         listNames(
             nodes,
             [](const auto& n) {
               return "'" + n.first + "' (mesh" + (n.second.size() == 1 ? " " : "es ") +
                      quotedNames(n.second) + ")";
             },
             32);
}

// The whole frames that cover the animation's keys from `start` to `end` seconds at `fps`: the
// last frame at or before the first key to the first at or after the last, as --frames takes
// them (never below 0). A tolerance keeps a key stored as the float 1/24 s on frame 1.
std::pair<long long, long long> framesCovering(double start, double end, double fps) {
  const double eps = 1e-3;  // of a frame
  const long long first = std::max(0LL, (long long)std::floor(start * fps + eps));
  const long long last = std::max(first, (long long)std::ceil(end * fps - eps));
  return {first, last};
}

// The effects of every frame of `args.frames` (each built as `glint render --frames` would
// build it), with the first and last frame each one appears in: an animation's effects come
// and go (a lens only in the closing shot, motion blur while something moves).
void printEffectsOverFrames(const InfoArgs& args, double fps) {
  struct Seen {
    int first = 0, last = 0, frames = 0;
  };
  std::map<std::string, Seen> seen;
  const FrameRange range = parseFrameRange(*args.frames);
  int checked = 0;
  namingFile(args.scene, "cannot build the scene", [&] {
    const SceneLoader loader(args.scene, args.sidecar);
    for (int frame : range.frames()) {
      SceneDescription d = loader.at(double(frame) / fps);
      args.overrides.apply(&d);
      const RenderScene s = buildRenderScene(d, nullptr, {.decodeImages = false});
      ++checked;
      for (const std::string& name : s.features().names()) {
        auto it = seen.try_emplace(name, Seen{frame, frame, 0}).first;
        it->second.last = frame;
        ++it->second.frames;
      }
    }
  });
  // Sorted by feature, as the single-frame line is.
  std::vector<std::string> names;
  for (uint32_t i = 0; i < uint32_t(Feature::Count); ++i)
    if (seen.count(featureName(Feature(i)))) names.push_back(featureName(Feature(i)));
  std::printf("effects over frames %d-%d (every %d, %d frames at %g fps):\n", range.first,
              range.last, range.step, checked, fps);
  for (const std::string& name : names) {
    const Seen& s = seen[name];
    std::printf("  %-22s frames %d-%d (%d of %d checked)\n", name.c_str(), s.first, s.last,
                s.frames, checked);
  }
  if (names.empty()) std::printf("  none\n");
}

// The media, and each grid of every VDB file they read: what a user needs to name grids in
// the sidecar and to judge the memory a volume takes.
void printMedia(const SceneDescription& desc) {
  if (desc.media.empty()) return;
  static const char* kTypes[] = {"constant", "grid", "noise", "exponential", "vdb"};
  std::printf("media:      %zu: %s\n", desc.media.size(),
              listNames(desc.media, [](const MediumDesc& m) {
                return (m.name.empty() ? std::string("(unnamed)") : m.name) + " (" +
                       kTypes[int(m.density)] + ")";
              }).c_str());
  for (const MediumDesc& m : desc.media) {
    if (!m.vdb) continue;
    const VdbVolume& v = *m.vdb;
    std::printf("  vdb %s: %.2f MiB in memory (NanoVDB grids and majorant grid)\n", v.file.c_str(),
                double(v.bytes()) / (1024.0 * 1024.0));
    for (const VdbGridInfo& g : listVdbGrids(v.file))
      std::printf(
          "    grid '%s': %s, voxel %g x %g x %g, %llu active voxels, bounds (%g, %g, %g) to "
          "(%g, %g, %g), %.2f MiB\n",
          g.name.c_str(), g.type.c_str(), g.voxelSize.x, g.voxelSize.y, g.voxelSize.z,
          (unsigned long long)g.activeVoxels, g.worldBounds.lower.x, g.worldBounds.lower.y,
          g.worldBounds.lower.z, g.worldBounds.upper.x, g.worldBounds.upper.y,
          g.worldBounds.upper.z, double(g.memoryBytes) / (1024.0 * 1024.0));
  }
}

void runInfo(const InfoArgs& args) {
  SceneDescription desc;
  RenderScene scene;
  namingFile(args.scene, "cannot build the scene", [&] {
    desc = loadScene(args.scene, args.sidecar);
    args.overrides.apply(&desc);
    // Nothing here reads a texel: image textures stay undecoded.
    scene = buildRenderScene(desc, nullptr, {.decodeImages = false});
  });
  for (const std::string& w : desc.warnings) std::printf("warning: %s\n", w.c_str());

  size_t triangles = 0;
  for (const MeshDesc& m : desc.meshes) triangles += m.indices.size() / 3;
  Bounds3f b = scene.geometry().bounds();
  std::printf("scene:      %s\n", desc.file.c_str());
  std::printf("meshes:     %zu (%zu triangles stored, %zu placed in the world)%s%s\n",
              desc.meshes.size(), triangles, scene.geometry().instancedTriangleCount(),
              desc.meshes.empty() ? "" : ": ", listNames(desc.meshes, [](const MeshDesc& m) {
                                                 return m.name.empty() ? std::string("(unnamed)")
                                                                       : m.name;
                                               }).c_str());
  std::printf("instances:  %zu\n", desc.instances.size());
  if (!desc.instances.empty()) std::printf("nodes:      %s\n", nodeSummary(desc).c_str());
  if (!desc.objects.empty())
    std::printf(
        "objects:    %zu: %s\n", desc.objects.size(),
        listNames(desc.objects, [](const ObjectDesc& o) { return objectSummary(o); }).c_str());
  std::printf("materials:  %zu%s%s\n", desc.materials.size(), desc.materials.empty() ? "" : ": ",
              listNames(desc.materials, [](const MaterialDesc& m) {
                return (m.name.empty() ? std::string("(unnamed)") : m.name) + " (" +
                       materialTypeName(m.type) + ")";
              }).c_str());
  std::printf("textures:   %zu (%zu images)\n", desc.textures.size(), desc.images.size());
  // Where each image the textures read lives: in memory (a MIP pyramid glint looks up itself)
  // or in OpenImageIO's texture cache (tiled, MIP-mapped files, and images too big to hold).
  if (scene.images()) {
    size_t resident = 0;
    for (TextureImages::Handle h : scene.images()->handles()) {
      std::printf("  image %s\n", scene.images()->describe(h).c_str());
      resident += scene.images()->residentBytes(h);
    }
    std::printf("  images in memory: %.1f MiB once decoded\n",
                double(resident) / (1024.0 * 1024.0));
  }
  if (!desc.variants.empty()) {
    std::string names;
    for (const std::string& v : desc.variants) names += (names.empty() ? "" : ", ") + v;
    std::printf(
        "variants:   %zu: %s%s\n", desc.variants.size(), names.c_str(),
        desc.render.variant.empty() ? "" : ("; showing '" + desc.render.variant + "'").c_str());
  }
  std::printf("cameras:    %zu%s%s; rendering with '%s'\n", desc.cameras.size(),
              desc.cameras.empty() ? "" : ": ",
              listNames(desc.cameras,
                        [](const CameraDesc& c) {
                          return c.name + (c.type == CameraType::Perspective ? " (perspective)"
                                                                             : " (orthographic)");
                        })
                  .c_str(),
              scene.cameraName().c_str());
  std::printf("lights:     %zu%s%s\n", desc.lights.size(), desc.lights.empty() ? "" : ": ",
              listNames(desc.lights, [](const LightDesc& l) {
                return (l.name.empty() ? std::string("(unnamed)") : l.name) + " (" +
                       lightTypeName(l.type) + ")";
              }).c_str());
  printMedia(desc);
  // Emitting surfaces that are not lights: next-event estimation never samples them.
  for (const UnsampledEmitter& e : scene.unsampledEmitters())
    std::printf("unsampled emitter: instance %u (%s): %s\n", e.instance, e.shape.c_str(),
                e.reason.c_str());
  if (b.empty())
    std::printf("bounds:     empty\n");
  else
    std::printf("bounds:     (%g, %g, %g) to (%g, %g, %g)\n", b.lower.x, b.lower.y, b.lower.z,
                b.upper.x, b.upper.y, b.upper.z);
  std::string integratorLabel = integratorName(resolveIntegrator(scene, desc.render.integrator));
  if (desc.render.integrator.type == "auto") integratorLabel += " (auto)";
  std::printf("image:      %dx%d, %d spp, seed %llu, accel %s, integrator %s\n",
              scene.camera().width(), scene.camera().height(), desc.render.spp,
              (unsigned long long)desc.render.seed, desc.render.accel.c_str(),
              integratorLabel.c_str());
  auto [animStart, animEnd] = animationRange(desc);
  size_t animatedNodes = 0;
  for (const NodeDesc& n : desc.nodes) animatedNodes += n.hasTracks();
  if (animatedNodes > 0) {
    const auto [firstFrame, lastFrame] = framesCovering(animStart, animEnd, desc.render.fps);
    std::printf(
        "animation:  %zu animated node%s, keys from %g s to %g s (frames %lld-%lld at %g fps)\n",
        animatedNodes, animatedNodes == 1 ? "" : "s", animStart, animEnd, firstFrame, lastFrame,
        desc.render.fps);
  }
  // What motion blur costs: how many placements move and meshes deform over the shutter, and
  // with how many time steps (each a pose Embree stores and blends).
  size_t moving = 0, movingKeys = 0, deforming = 0, deformSteps = 0;
  for (const Instance& inst : scene.geometry().instances)
    if (inst.moves()) ++moving, movingKeys = std::max(movingKeys, inst.motion.keyCount());
  for (const TriangleMesh& m : scene.geometry().meshes)
    if (m.deforms()) ++deforming, deformSteps = std::max(deformSteps, m.positionSteps.size());
  std::string motion;
  if (moving > 0)
    motion = std::to_string(moving) + " moving placement" + (moving == 1 ? "" : "s") + " (up to " +
             std::to_string(movingKeys) + " keys)";
  if (deforming > 0)
    motion += (motion.empty() ? "" : ", ") + std::to_string(deforming) + " deforming mesh" +
              (deforming == 1 ? "" : "es") + " (up to " + std::to_string(deformSteps) +
              " time steps)";
  if (!motion.empty()) std::printf("motion:     %s over the shutter\n", motion.c_str());
  std::vector<std::string> effects = scene.features().names();
  std::printf("effects:    %s\n", effects.empty()
                                      ? "none"
                                      : listNames(
                                            effects, [](const std::string& s) { return s; }, 64)
                                            .c_str());
  if (args.frames) printEffectsOverFrames(args, desc.render.fps);
}

}  // namespace

void addInfoCommand(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd =
      app.add_subcommand("info", "print what a scene holds and the effects it calls for");
  cmd->add_option("scene", args->scene, "a .gltf/.glb scene or a glint .json scene")->required();
  cmd->add_option("--sidecar", args->sidecar,
                  "sidecar JSON (default: NAME.glint.json beside the glTF)");
  cmd->add_option("--frames", args->frames,
                  "also list the effects of frames A-B[:STEP] of the animation (at render.fps), "
                  "each with the first and last frame it appears in");
  args->overrides.addOptions(cmd);
  cmd->callback([args] { runInfo(*args); });
}

}  // namespace glint::app
