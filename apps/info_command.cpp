// glint — `glint info`: what a scene holds and which effects it calls for.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/frames.h"
#include "scenes/build.h"
#include "scenes/load.h"
#include "scenes/scene_info.h"

namespace glint::app {

namespace {

struct InfoArgs {
  std::string scene;
  std::optional<std::string> sidecar;
  std::optional<std::string> frames;  // --frames A-B[:STEP]
  SceneOverrides overrides;
};

// "a, b, c" of up to `limit` names, then "... (N more)".
template <class T, class F>
std::string listNames(const std::vector<T>& items, F name, size_t limit = 8) {
  std::string s;
  for (size_t i = 0; i < items.size() && i < limit; ++i) s += (i ? ", " : "") + name(items[i]);
  if (items.size() > limit) s += ", ... (" + std::to_string(items.size() - limit) + " more)";
  return s;
}

// "ball (sphere)", "dice (csg, 7 leaves)", "mountain (terrain, 32768 triangles)".
std::string objectSummary(const SceneInfo::Object& o) {
  const std::string name = o.name.empty() ? std::string("(unnamed)") : o.name;
  if (o.type == "csg") return name + " (csg, " + std::to_string(o.leaves) + " leaves)";
  if (o.type == "terrain")
    return name + " (terrain, " + std::to_string(o.triangles) + " triangles)";
  return name + " (" + o.type + ")";
}

// The nodes with a mesh, as a sidecar material's "nodes" list names them: "'CubeLeft' (mesh
// 'Cube')".
std::string nodeSummary(const std::vector<SceneInfo::Node>& nodes) {
  return std::to_string(nodes.size()) +
         " with a mesh (names for a sidecar material's "
         "\"nodes\"): " +
         listNames(
             nodes,
             [](const SceneInfo::Node& n) {
               return "'" + n.name + "' (mesh" + (n.meshes.size() == 1 ? " " : "es ") +
                      quotedNames(n.meshes) + ")";
             },
             32);
}

// "Name (type)", "(unnamed) (type)".
std::string namedSummary(const SceneInfo::Named& n) {
  return (n.name.empty() ? std::string("(unnamed)") : n.name) + " (" + n.type + ")";
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

// The media, and each grid of every VDB file they read.
void printMedia(const SceneInfo& info) {
  if (info.media.empty()) return;
  std::printf("media:      %zu: %s\n", info.media.size(),
              listNames(info.media, [](const SceneInfo::Medium& m) {
                return (m.name.empty() ? std::string("(unnamed)") : m.name) + " (" + m.type + ")";
              }).c_str());
  for (const SceneInfo::Medium& m : info.media) {
    if (m.vdbFile.empty()) continue;
    std::printf("  vdb %s: %.2f MiB in memory (NanoVDB grids and majorant grid)\n",
                m.vdbFile.c_str(), double(m.vdbBytes) / (1024.0 * 1024.0));
    for (const VdbGridInfo& g : m.grids)
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
  SceneInfo info;
  namingFile(args.scene, "cannot build the scene", [&] {
    SceneDescription desc = loadScene(args.scene, args.sidecar);
    args.overrides.apply(&desc);
    // Nothing here reads a texel: image textures stay undecoded.
    const RenderScene scene = buildRenderScene(desc, nullptr, {.decodeImages = false});
    info = describeScene(desc, scene);
  });
  for (const std::string& w : info.warnings) std::printf("warning: %s\n", w.c_str());

  std::printf("scene:      %s\n", info.file.c_str());
  std::printf("meshes:     %zu (%zu triangles stored, %zu placed in the world)%s%s\n",
              info.meshes.size(), info.trianglesStored, info.trianglesPlaced,
              info.meshes.empty() ? "" : ": ", listNames(info.meshes, [](const std::string& m) {
                                                 return m.empty() ? std::string("(unnamed)") : m;
                                               }).c_str());
  std::printf("instances:  %zu\n", info.instances);
  if (info.instances > 0) std::printf("nodes:      %s\n", nodeSummary(info.nodes).c_str());
  if (!info.objects.empty())
    std::printf("objects:    %zu: %s\n", info.objects.size(),
                listNames(info.objects, objectSummary).c_str());
  std::printf("materials:  %zu%s%s\n", info.materials.size(), info.materials.empty() ? "" : ": ",
              listNames(info.materials, namedSummary).c_str());
  std::printf("textures:   %zu (%zu images)\n", info.textures, info.images);
  // Where each image the textures read lives: in memory (a MIP pyramid glint looks up itself)
  // or in OpenImageIO's texture cache (tiled, MIP-mapped files, and images too big to hold).
  if (info.imagesListed) {
    for (const std::string& image : info.imageDescriptions)
      std::printf("  image %s\n", image.c_str());
    std::printf("  images in memory: %.1f MiB once decoded\n",
                double(info.imageBytes) / (1024.0 * 1024.0));
  }
  if (!info.variants.empty()) {
    std::string names;
    for (const std::string& v : info.variants) names += (names.empty() ? "" : ", ") + v;
    std::printf("variants:   %zu: %s%s\n", info.variants.size(), names.c_str(),
                info.variant.empty() ? "" : ("; showing '" + info.variant + "'").c_str());
  }
  std::printf("cameras:    %zu%s%s; rendering with '%s'\n", info.cameras.size(),
              info.cameras.empty() ? "" : ": ",
              listNames(info.cameras,
                        [](const SceneInfo::Named& c) { return c.name + " (" + c.type + ")"; })
                  .c_str(),
              info.camera.c_str());
  std::printf("lights:     %zu%s%s\n", info.lights.size(), info.lights.empty() ? "" : ": ",
              listNames(info.lights, namedSummary).c_str());
  printMedia(info);
  // Emitting surfaces that are not lights: next-event estimation never samples them.
  for (const UnsampledEmitter& e : info.unsampledEmitters)
    std::printf("unsampled emitter: instance %u (%s): %s\n", e.instance, e.shape.c_str(),
                e.reason.c_str());
  const Bounds3f& b = info.bounds;
  if (b.empty())
    std::printf("bounds:     empty\n");
  else
    std::printf("bounds:     (%g, %g, %g) to (%g, %g, %g)\n", b.lower.x, b.lower.y, b.lower.z,
                b.upper.x, b.upper.y, b.upper.z);
  std::printf("image:      %dx%d, %d spp, seed %llu, accel %s, integrator %s%s\n", info.width,
              info.height, info.spp, (unsigned long long)info.seed, info.accel.c_str(),
              info.integrator.c_str(), info.integratorAuto ? " (auto)" : "");
  if (info.animatedNodes > 0)
    std::printf(
        "animation:  %zu animated node%s, keys from %g s to %g s (frames %lld-%lld at %g fps)\n",
        info.animatedNodes, info.animatedNodes == 1 ? "" : "s", info.animationStart,
        info.animationEnd, info.firstFrame, info.lastFrame, info.fps);
  // What motion blur costs: how many placements move and meshes deform over the shutter, and
  // with how many time steps (each a pose Embree stores and blends).
  std::string motion;
  if (info.moving > 0)
    motion = std::to_string(info.moving) + " moving placement" + (info.moving == 1 ? "" : "s") +
             " (up to " + std::to_string(info.movingKeys) + " keys)";
  if (info.deforming > 0)
    motion += (motion.empty() ? "" : ", ") + std::to_string(info.deforming) + " deforming mesh" +
              (info.deforming == 1 ? "" : "es") + " (up to " + std::to_string(info.deformSteps) +
              " time steps)";
  if (!motion.empty()) std::printf("motion:     %s over the shutter\n", motion.c_str());
  std::printf("effects:    %s\n",
              info.effects.empty() ? "none"
                                   : listNames(
                                         info.effects, [](const std::string& s) { return s; }, 64)
                                         .c_str());
  if (args.frames) printEffectsOverFrames(args, info.fps);
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
