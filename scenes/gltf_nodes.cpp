// glint — the glTF node tree placed in the scene description (see gltf_nodes.h).
#include "scenes/gltf_nodes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scenes/errors.h"

namespace glint::gltf {

namespace {

class NodeWalk {
 public:
  NodeWalk(const Document& doc, const AccessorReader& reader, const AnimationTracks& tracks,
           MeshConverter& meshes, const Transform& rootTransform, SceneDescription* scene)
      : doc_(doc),
        reader_(reader),
        tracks_(tracks),
        meshes_(meshes),
        rootTransform_(rootTransform),
        scene_(scene) {}

  void run() {
    subtreeAnimated_.assign(doc_.nodes.size(), -1);
    nodeDesc_.assign(doc_.nodes.size(), -1);
    nodeWorld_.assign(doc_.nodes.size(), std::nullopt);
    for (int r : roots()) visit(r, rootTransform_, -1, false);
    resolveSkins();
  }

 private:
  // The default scene's nodes, or scene 0's, or every node without a parent.
  std::vector<int> roots() const {
    if (doc_.scene >= 0) return doc_.scenes[size_t(doc_.scene)].nodes;
    if (!doc_.scenes.empty()) return doc_.scenes[0].nodes;
    std::vector<bool> isChild(doc_.nodes.size(), false);
    for (const Node& n : doc_.nodes)
      for (int c : n.children) isChild[size_t(c)] = true;
    std::vector<int> roots;
    for (size_t i = 0; i < doc_.nodes.size(); ++i)
      if (!isChild[i]) roots.push_back(int(i));
    return roots;
  }

  // Whether node `index` or a node below it has tracks (memoised; the graph is a forest).
  bool subtreeAnimated(int index) {
    int& memo = subtreeAnimated_[size_t(index)];
    if (memo >= 0) return memo;
    bool any = tracks_.nodes.count(index) > 0;
    for (int c : doc_.nodes[size_t(index)].children) any = subtreeAnimated(c) || any;
    memo = any;
    return any;
  }

  // The NodeDesc of the glTF root transform, made on first use (-1 when it is the identity).
  int rootNode() {
    if (rootTransform_.isIdentity()) return -1;
    if (rootNode_ < 0) {
      NodeDesc root;
      root.name = "glTF root transform";
      root.hasMatrix = true;
      root.matrix = rootTransform_;
      root.where = SourceLocation{doc_.file, ""};
      scene_->nodes.push_back(root);
      rootNode_ = int(scene_->nodes.size()) - 1;
    }
    return rootNode_;
  }

  // The node graph was checked to be a forest, so recursion terminates. Nodes whose world
  // transform can change (animated, below an animated node, or above one) are kept as
  // NodeDescs; `parentDesc` is the parent's (-1 when it has none) and `moving` says whether
  // the parent moves.
  void visit(int index, const Transform& parent, int parentDesc, bool moving) {
    const Node& node = doc_.nodes[size_t(index)];
    std::string nodeName = node.name.empty() ? "node " + std::to_string(index) : node.name;
    Transform world = parent * node.local;
    int desc = -1;
    if (moving || subtreeAnimated(index)) {
      NodeDesc d;
      d.name = nodeName;
      d.parent = parentDesc >= 0 ? parentDesc : rootNode();
      d.hasMatrix = node.hasMatrix;
      d.matrix = node.local;
      d.translation = node.translation;
      d.rotation = node.rotation;
      d.scale = node.scale;
      if (auto it = tracks_.nodes.find(index); it != tracks_.nodes.end()) {
        d.translationTrack = it->second.translation;
        d.rotationTrack = it->second.rotation;
        d.scaleTrack = it->second.scale;
      }
      d.where = node.where;
      scene_->nodes.push_back(d);
      desc = int(scene_->nodes.size()) - 1;
      moving = isAnimated(scene_->nodes, desc);
      // The placement at time 0: a channel's first value, else the rest value.
      world = worldFromNode(scene_->nodes, desc, 0.0);
    }
    int transformNode = moving ? desc : -1;
    nodeDesc_[size_t(index)] = transformNode;
    nodeWorld_[size_t(index)] = world;
    if (node.mesh >= 0) placeMesh(index, nodeName, world, transformNode);
    if (node.camera >= 0) {
      CameraDesc c = doc_.cameras[size_t(node.camera)];
      if (c.name.empty())
        c.name = node.name.empty() ? "camera " + std::to_string(node.camera) : node.name;
      c.worldFromCamera = world;
      c.transformNode = transformNode;
      scene_->cameras.push_back(c);
    }
    if (node.light >= 0) {
      LightDesc l = doc_.lights[size_t(node.light)];
      if (l.name.empty())
        l.name = node.name.empty() ? "light " + std::to_string(node.light) : node.name;
      l.worldFromLight = world;
      l.transformNode = transformNode;
      scene_->lights.push_back(l);
    }
    for (int c : node.children) visit(c, world, desc, moving);
  }

  // The instances of node `index`'s mesh: one per primitive, and per GPU instance
  // (EXT_mesh_gpu_instancing). A skinned one is placed by its skin, resolved after the walk.
  void placeMesh(int index, const std::string& nodeName, const Transform& world,
                 int transformNode) {
    const Node& node = doc_.nodes[size_t(index)];
    const std::vector<int>& meshes = meshes_.meshDescs(node.mesh);
    const Mesh& gm = doc_.meshes[size_t(node.mesh)];
    // EXT_mesh_gpu_instancing: one placement per instance, in the node's frame.
    const std::vector<Transform> copies = instancePlacements(node);
    for (size_t copy = 0; copy < std::max<size_t>(copies.size(), 1); ++copy) {
      for (size_t p = 0; p < meshes.size(); ++p) {
        const int m = meshes[p];
        if (m < 0) continue;
        InstanceDesc inst;
        inst.mesh = m;
        inst.worldFromObject = world;
        inst.transformNode = transformNode;
        if (!copies.empty() && node.skin < 0) {
          inst.worldFromObject = world * copies[copy];
          inst.nodeFromObject = copies[copy];
        }
        inst.node = nodeName;
        inst.where = node.where;
        inst.morphWeights = node.weights;
        if (auto it = tracks_.weights.find(index); it != tracks_.weights.end())
          inst.weightTracks = it->second;
        const MeshDesc& md = scene_->meshes[size_t(m)];
        if (node.skin >= 0 && !md.joints.empty()) {
          // glTF: the skin places the vertices; the skinned node's own transform is ignored.
          const Skin& skin = doc_.skins[size_t(node.skin)];
          for (size_t v = 0; v < md.joints.size(); ++v)
            for (int k = 0; k < 4; ++k)
              if (md.jointWeights[v][k] > 0 && md.joints[v][size_t(k)] >= skin.joints.size())
                throw SceneError(gm.primitives[p].where.child("attributes").child("JOINTS_0"),
                                 "vertex " + std::to_string(v) + " names joint " +
                                     std::to_string(md.joints[v][size_t(k)]) + " but skin " +
                                     std::to_string(node.skin) + " (" +
                                     node.where.child("skin").pointer + ") has " +
                                     std::to_string(skin.joints.size()) + " joints");
          inst.worldFromObject = Transform();
          inst.transformNode = -1;
          pendingSkins_.emplace_back(scene_->instances.size(), node.skin);
        } else if (node.skin < 0 && !md.joints.empty()) {
          scene_->warnings.push_back(gm.primitives[p].where.str() +
                                     ": JOINTS_0/WEIGHTS_0 without a skin on node " +
                                     std::to_string(index) + "; drawn unskinned");
        }
        scene_->instances.push_back(inst);
      }
    }
  }

  // The per-instance placements of an EXT_mesh_gpu_instancing node (T · R · S of each), or
  // none. Rotations are normalised; non-finite values and zero scales are errors.
  std::vector<Transform> instancePlacements(const Node& node) {
    std::vector<Transform> out;
    if (node.instanceCount == 0) return out;
    const SourceLocation attrs =
        node.where.child("extensions").child("EXT_mesh_gpu_instancing").child("attributes");
    if (node.skin >= 0) {
      scene_->warnings.push_back(attrs.str() +
                                 ": EXT_mesh_gpu_instancing on a skinned node is ignored (the "
                                 "skin places the mesh once)");
      return out;
    }
    std::vector<double> t, r, sc;
    if (node.instanceTranslation >= 0) t = reader_.read(node.instanceTranslation);
    if (node.instanceRotation >= 0) r = reader_.read(node.instanceRotation);
    if (node.instanceScale >= 0) sc = reader_.read(node.instanceScale);
    out.reserve(node.instanceCount);
    for (size_t i = 0; i < node.instanceCount; ++i) {
      Vec3f translation{0, 0, 0}, scale{1, 1, 1};
      Quaternion rotation;
      if (!t.empty()) translation = {float(t[3 * i]), float(t[3 * i + 1]), float(t[3 * i + 2])};
      if (!sc.empty()) scale = {float(sc[3 * i]), float(sc[3 * i + 1]), float(sc[3 * i + 2])};
      if (!r.empty()) {
        rotation = {float(r[4 * i]), float(r[4 * i + 1]), float(r[4 * i + 2]), float(r[4 * i + 3])};
        if (!(dot(rotation, rotation) > 1e-12f) || !std::isfinite(dot(rotation, rotation)))
          throw SceneError(attrs.child("ROTATION"),
                           "instance " + std::to_string(i) + " has a zero or non-finite rotation");
        rotation = normalize(rotation);
      }
      if (!isFinite(translation))
        throw SceneError(attrs.child("TRANSLATION"),
                         "instance " + std::to_string(i) + " has a non-finite translation");
      if (!isFinite(scale) || scale.x == 0 || scale.y == 0 || scale.z == 0)
        throw SceneError(attrs.child("SCALE"),
                         "instance " + std::to_string(i) + " has a zero or non-finite scale");
      out.push_back(Transform::translate(translation) * toTransform(rotation) *
                    Transform::scale(scale));
    }
    return out;
  }

  // The world placement of glTF node `index` at rest, for joints outside the scene walked.
  Transform restWorld(int index) {
    if (nodeWorld_[size_t(index)]) return *nodeWorld_[size_t(index)];
    if (parent_.empty()) {
      parent_.assign(doc_.nodes.size(), -1);
      for (size_t i = 0; i < doc_.nodes.size(); ++i)
        for (int c : doc_.nodes[i].children) parent_[size_t(c)] = int(i);
    }
    const int p = parent_[size_t(index)];
    return (p >= 0 ? restWorld(p) : rootTransform_) * doc_.nodes[size_t(index)].local;
  }

  // SkinDescs for the skins skinned instances use (one per glTF skin), their joints placed by
  // the nodes the walk made (animated) or at rest.
  void resolveSkins() {
    std::map<int, int> skinDesc;  // glTF skin -> SceneDescription::skins index
    for (auto [instance, skin] : pendingSkins_) {
      auto it = skinDesc.find(skin);
      if (it == skinDesc.end()) {
        const Skin& gs = doc_.skins[size_t(skin)];
        SkinDesc d;
        d.name = "skin " + std::to_string(skin);
        d.where = gs.where;
        std::vector<double> ibm;
        if (gs.inverseBindMatrices >= 0) ibm = reader_.read(gs.inverseBindMatrices);
        for (size_t j = 0; j < gs.joints.size(); ++j) {
          const int node = gs.joints[j];
          d.joints.push_back({nodeDesc_[size_t(node)], restWorld(node)});
          Transform inverseBind;
          if (!ibm.empty()) {
            float f[16];
            for (int k = 0; k < 16; ++k) f[k] = float(ibm[16 * j + size_t(k)]);
            Mat4 m = Mat4::fromColumnMajor(f), inv;
            if (!invert(m, &inv))
              throw SceneError(gs.where.child("inverseBindMatrices"),
                               "matrix " + std::to_string(j) + " of accessor " +
                                   std::to_string(gs.inverseBindMatrices) +
                                   " is not finite and invertible");
            inverseBind = Transform(m, inv);
          }
          d.inverseBind.push_back(inverseBind);
        }
        scene_->skins.push_back(std::move(d));
        it = skinDesc.emplace(skin, int(scene_->skins.size()) - 1).first;
      }
      scene_->instances[instance].skin = it->second;
    }
  }

  const Document& doc_;
  const AccessorReader& reader_;
  const AnimationTracks& tracks_;
  MeshConverter& meshes_;
  Transform rootTransform_;
  SceneDescription* scene_;
  // Per glTF node, from the walk: its animated placement (-1: static) and its world at time 0.
  std::vector<int> nodeDesc_;
  std::vector<std::optional<Transform>> nodeWorld_;
  std::vector<int> parent_;                           // made on first use by restWorld
  std::vector<std::pair<size_t, int>> pendingSkins_;  // (instance, glTF skin)
  std::vector<int> subtreeAnimated_;                  // -1 = not yet known
  int rootNode_ = -1;
};

}  // namespace

void placeNodes(const Document& doc, const AccessorReader& reader, const AnimationTracks& tracks,
                MeshConverter& meshes, const Transform& rootTransform, SceneDescription* scene) {
  NodeWalk(doc, reader, tracks, meshes, rootTransform, scene).run();
}

}  // namespace glint::gltf
