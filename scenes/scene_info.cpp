// glint — what a scene holds (see scene_info.h).
#include "scenes/scene_info.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "materials/image_texture.h"
#include "materials/vdb_volume.h"
#include "renderer/integrator.h"
#include "scenes/sidecar_media.h"

namespace glint {

namespace {

SceneInfo::Object objectInfo(const ObjectDesc& o) {
  SceneInfo::Object info{o.name, ""};
  switch (o.kind) {
    case ObjectKind::Shape:
      info.type = o.shape->typeName();
      break;
    case ObjectKind::Csg:
      info.type = "csg";
      for (const CsgNodeDesc& n : o.csg.nodes) info.leaves += n.op == CsgOp::Leaf;
      break;
    case ObjectKind::Terrain:
      info.type = "terrain";
      info.triangles = size_t(2ull << (2 * o.terrain.depth));
      break;
  }
  return info;
}

// The glTF nodes that place a mesh, each with its meshes, as a sidecar material's "nodes" list
// names them (scenes/sidecar_materials.cpp matches InstanceDesc::node). A node placed several
// times (EXT_mesh_gpu_instancing) or holding a mesh of several primitives (one MeshDesc each,
// "Name (primitive 1)") is listed once, in file order.
std::vector<SceneInfo::Node> nodesOf(const SceneDescription& desc) {
  std::vector<SceneInfo::Node> nodes;
  for (const InstanceDesc& inst : desc.instances) {
    auto it = std::find_if(nodes.begin(), nodes.end(),
                           [&](const SceneInfo::Node& n) { return n.name == inst.node; });
    if (it == nodes.end()) it = nodes.insert(nodes.end(), {inst.node, {}});
    const std::string& mesh = desc.meshes[size_t(inst.mesh)].name;
    const std::string name = mesh.empty() ? "mesh " + std::to_string(inst.mesh) : mesh;
    if (std::find(it->meshes.begin(), it->meshes.end(), name) == it->meshes.end())
      it->meshes.push_back(name);
  }
  return nodes;
}

}  // namespace

const char* lightTypeName(LightType type) {
  switch (type) {
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

std::pair<long long, long long> framesCovering(double start, double end, double fps) {
  const double eps = 1e-3;  // of a frame: a key stored as the float 1/24 s stays on frame 1
  const long long first = std::max(0LL, (long long)std::floor(start * fps + eps));
  const long long last = std::max(first, (long long)std::ceil(end * fps - eps));
  return {first, last};
}

SceneInfo describeScene(const SceneDescription& desc, const RenderScene& scene) {
  SceneInfo info;
  info.file = desc.file;
  info.warnings = desc.warnings;
  for (const MeshDesc& m : desc.meshes) {
    info.meshes.push_back(m.name);
    info.trianglesStored += m.indices.size() / 3;
  }
  info.trianglesPlaced = scene.geometry().instancedTriangleCount();
  info.instances = desc.instances.size();
  info.nodes = nodesOf(desc);
  for (const ObjectDesc& o : desc.objects) info.objects.push_back(objectInfo(o));
  for (const MaterialDesc& m : desc.materials)
    info.materials.push_back({m.name, materialTypeName(m.type)});
  info.textures = desc.textures.size();
  info.images = desc.images.size();
  if (scene.images()) {
    info.imagesListed = true;
    for (TextureImages::Handle h : scene.images()->handles()) {
      info.imageDescriptions.push_back(scene.images()->describe(h));
      info.imageBytes += scene.images()->residentBytes(h);
    }
  }
  info.variants = desc.variants;
  info.variant = desc.render.variant;
  for (const CameraDesc& c : desc.cameras)
    info.cameras.push_back(
        {c.name, c.type == CameraType::Perspective ? "perspective" : "orthographic"});
  info.camera = scene.cameraName();
  for (const LightDesc& l : desc.lights) info.lights.push_back({l.name, lightTypeName(l.type)});
  for (const MediumDesc& m : desc.media) {
    SceneInfo::Medium medium{m.name, densityTypeName(m.density)};
    if (m.vdb) {
      medium.vdbFile = m.vdb->file;
      medium.vdbBytes = m.vdb->bytes();
      medium.grids = listVdbGrids(m.vdb->file);
    }
    info.media.push_back(std::move(medium));
  }
  info.unsampledEmitters = scene.unsampledEmitters();
  info.bounds = scene.geometry().bounds();
  info.width = scene.camera().width();
  info.height = scene.camera().height();
  info.spp = desc.render.spp;
  info.seed = desc.render.seed;
  info.accel = desc.render.accel;
  info.integrator = integratorName(resolveIntegrator(scene, desc.render.integrator));
  info.integratorAuto = desc.render.integrator.type == "auto";
  std::tie(info.animationStart, info.animationEnd) = animationRange(desc);
  for (const NodeDesc& n : desc.nodes) info.animatedNodes += n.hasTracks();
  info.fps = desc.render.fps;
  std::tie(info.firstFrame, info.lastFrame) =
      framesCovering(info.animationStart, info.animationEnd, info.fps);
  for (const Instance& inst : scene.geometry().instances)
    if (inst.moves())
      ++info.moving, info.movingKeys = std::max(info.movingKeys, inst.motion.keyCount());
  for (const TriangleMesh& m : scene.geometry().meshes)
    if (m.deforms())
      ++info.deforming, info.deformSteps = std::max(info.deformSteps, m.positionSteps.size());
  info.effects = scene.features().names();
  return info;
}

}  // namespace glint
