// glint — glTF cameras, KHR_lights_punctual lights, nodes (transforms, EXT_mesh_gpu_instancing,
// the node graph's shape), scenes and skins.
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "scenes/gltf_document_parts.h"

namespace glint::gltf {

namespace {

// Fills node->local and the rest values it is made of.
void nodeTransform(JsonReader& o, Node* node) {
  bool trs = o.has("translation") || o.has("rotation") || o.has("scale");
  if (o.has("matrix")) {
    if (trs) throw SceneError(o.where(), "has both 'matrix' and translation/rotation/scale");
    auto v = o.numbers<16>("matrix");
    float f[16];
    for (int i = 0; i < 16; ++i) f[i] = float(v[size_t(i)]);
    Mat4 m = Mat4::fromColumnMajor(f), inv;
    if (!invert(m, &inv)) throw SceneError(o.where("matrix"), "matrix is not invertible");
    node->hasMatrix = true;
    node->local = Transform(m, inv);
    return;
  }
  if (o.has("translation")) {
    auto t = o.numbers<3>("translation");
    node->translation = {float(t[0]), float(t[1]), float(t[2])};
  }
  if (o.has("rotation")) {
    auto q = o.numbers<4>("rotation");
    if (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] < 1e-12)
      throw SceneError(o.where("rotation"), "quaternion has zero length");
    node->rotation = normalize(Quaternion{float(q[0]), float(q[1]), float(q[2]), float(q[3])});
  }
  if (o.has("scale")) {
    auto s = o.numbers<3>("scale");
    if (s[0] == 0 || s[1] == 0 || s[2] == 0)
      throw SceneError(o.where("scale"), "a zero scale makes the node matrix not invertible");
    node->scale = {float(s[0]), float(s[1]), float(s[2])};
  }
  node->local = Transform::translate(node->translation) * toTransform(node->rotation) *
                Transform::scale(node->scale);
}

// EXT_mesh_gpu_instancing: TRANSLATION and SCALE as VEC3 of FLOAT, ROTATION as VEC4 of FLOAT
// or normalized BYTE/SHORT, all with one element per instance.
void readInstancing(JsonReader& o, const Document& doc, Node* node) {
  JsonReader& attributes = o.object("attributes");
  const size_t accessors = doc.accessors.size();
  node->instanceTranslation = attributes.index("TRANSLATION", accessors, "accessor", -1);
  node->instanceRotation = attributes.index("ROTATION", accessors, "accessor", -1);
  node->instanceScale = attributes.index("SCALE", accessors, "accessor", -1);
  bool first = true;
  for (auto [index, name] : {std::pair{node->instanceTranslation, "TRANSLATION"},
                             {node->instanceRotation, "ROTATION"},
                             {node->instanceScale, "SCALE"}}) {
    if (index < 0) continue;
    const Accessor& a = doc.accessors[size_t(index)];
    const bool rotation = std::string(name) == "ROTATION";
    const bool ok =
        rotation ? a.type == "VEC4" &&
                       (a.componentType == kFloat ||
                        (a.normalized && (a.componentType == kByte || a.componentType == kShort)))
                 : a.type == "VEC3" && a.componentType == kFloat;
    if (!ok)
      throw SceneError(attributes.where(name),
                       "accessor " + std::to_string(index) + " is " + a.type + " of " +
                           (a.normalized ? "normalized " : "") +
                           componentTypeName(a.componentType) + "; " + name + " must be " +
                           (rotation ? "VEC4 of FLOAT or normalized BYTE/SHORT" : "VEC3 of FLOAT"));
    if (!first && a.count != node->instanceCount)
      throw SceneError(attributes.where(name), "accessor " + std::to_string(index) + " has " +
                                                   plural(a.count, "element") + " but the other " +
                                                   "instancing attributes have " +
                                                   std::to_string(node->instanceCount));
    node->instanceCount = a.count;
    first = false;
  }
  if (first) throw SceneError(attributes.where(), "needs TRANSLATION, ROTATION or SCALE");
}

// The deepest node hierarchy glint reads (roots are level 0). glTF sets no limit, but the
// loader walks the tree recursively, and real rigs stay far below this.
constexpr int kMaxNodeDepth = 1000;

}  // namespace

void readCameras(JsonReader& root, Document* doc) {
  for (const JsonItem& item : root.optionalArray("cameras")) {
    JsonReader o(item);
    CameraDesc c;
    c.where = o.where();
    c.name = o.get<std::string>("name", "");
    std::string type = o.get<std::string>("type");
    if (type == "perspective") {
      JsonReader& p = o.object("perspective");
      c.type = CameraType::Perspective;
      c.yfov = float(p.get<double>("yfov"));
      if (c.yfov <= 0 || c.yfov >= kPi)
        throw SceneError(p.where("yfov"), "must be between 0 and pi");
      c.aspectRatio = float(p.get<double>("aspectRatio", 0.0));
      if (p.has("aspectRatio") && c.aspectRatio <= 0)
        throw SceneError(p.where("aspectRatio"), "must be greater than 0");
      c.znear = float(p.get<double>("znear"));
      if (c.znear <= 0) throw SceneError(p.where("znear"), "must be greater than 0");
      c.zfar = float(p.get<double>("zfar", kInfinity));
      if (p.has("zfar") && c.zfar <= c.znear)
        throw SceneError(p.where("zfar"), "must be greater than znear");
    } else if (type == "orthographic") {
      JsonReader& p = o.object("orthographic");
      c.type = CameraType::Orthographic;
      c.xmag = float(p.get<double>("xmag"));
      if (c.xmag == 0) throw SceneError(p.where("xmag"), "must not be zero");
      c.ymag = float(p.get<double>("ymag"));
      if (c.ymag == 0) throw SceneError(p.where("ymag"), "must not be zero");
      c.znear = float(p.get<double>("znear"));
      if (c.znear < 0) throw SceneError(p.where("znear"), "must not be negative");
      c.zfar = float(p.get<double>("zfar"));
      if (c.zfar <= c.znear) throw SceneError(p.where("zfar"), "must be greater than znear");
    } else {
      throw SceneError(o.where("type"), "unknown camera type '" + type +
                                            "' (expected 'perspective' or 'orthographic')");
    }
    doc->cameras.push_back(c);
  }
}

void readLights(JsonReader& root, Document* doc) {
  JsonReader* ext = root.optionalObject("extensions");
  JsonReader* punctual = ext ? ext->optionalObject("KHR_lights_punctual") : nullptr;
  if (!punctual) return;
  for (const JsonItem& item : punctual->optionalArray("lights")) {
    JsonReader o(item);
    LightDesc l;
    l.where = o.where();
    l.name = o.get<std::string>("name", "");
    std::string type = o.get<std::string>("type");
    if (type == "point") {
      l.type = LightType::Point;
    } else if (type == "spot") {
      l.type = LightType::Spot;
    } else if (type == "directional") {
      l.type = LightType::Directional;
    } else {
      throw SceneError(o.where("type"), "unknown light type '" + type +
                                            "' (expected 'point', 'spot' or 'directional')");
    }
    if (o.has("color")) {
      auto c = o.numbers<3>("color");
      for (size_t i = 0; i < 3; ++i)
        if (c[i] < 0) throw SceneError(o.where("color").child(i), "must not be negative");
      l.color = {float(c[0]), float(c[1]), float(c[2])};
    }
    l.intensity = nonNegative(o, "intensity", 1, kInfinity);
    l.range = float(o.get<double>("range", 0.0));
    if (o.has("range") && l.range <= 0)
      throw SceneError(o.where("range"), "must be greater than 0");
    if (l.type == LightType::Spot) {
      JsonReader& s = o.object("spot");
      l.innerConeAngle = float(s.get<double>("innerConeAngle", 0.0));
      l.outerConeAngle = float(s.get<double>("outerConeAngle", kPi / 4));
      if (l.outerConeAngle <= 0 || l.outerConeAngle > kPi / 2)
        throw SceneError(s.where("outerConeAngle"), "must be in (0, pi/2]");
      if (l.innerConeAngle < 0 || l.innerConeAngle >= l.outerConeAngle)
        throw SceneError(s.where("innerConeAngle"),
                         "must be at least 0 and less than outerConeAngle");
    }
    doc->lights.push_back(l);
  }
}

namespace {

// One node of the "nodes" array (`n` nodes in all); its children are checked to be nodes, not
// yet to form trees.
Node readNode(const JsonItem& item, size_t n, const Document& doc) {
  JsonReader o(item);
  Node node;
  node.where = o.where();
  node.name = o.get<std::string>("name", "");
  node.mesh = o.index("mesh", doc.meshes.size(), "mesh", -1);
  node.camera = o.index("camera", doc.cameras.size(), "camera", -1);
  if (JsonReader* ext = o.optionalObject("extensions")) {
    if (JsonReader* light = ext->optionalObject("KHR_lights_punctual"))
      node.light = light->index("light", doc.lights.size(), "light");
    if (JsonReader* instancing = ext->optionalObject("EXT_mesh_gpu_instancing"))
      readInstancing(*instancing, doc, &node);
  }
  for (const JsonItem& child : o.optionalArray("children"))
    node.children.push_back(child.asIndex(n, "node"));
  nodeTransform(o, &node);
  // Skins are read after the nodes (their joints are nodes): the index is checked there.
  if (o.has("skin")) {
    node.skin = int(std::min<size_t>(o.getSize("skin"), size_t(1) << 30));
    if (node.mesh < 0) throw SceneError(o.where("skin"), "a skin needs a mesh on the same node");
  }
  if (o.has("weights")) {
    if (node.mesh < 0)
      throw SceneError(o.where("weights"), "morph weights need a mesh on the same node");
    const Mesh& mesh = doc.meshes[size_t(node.mesh)];
    node.weights =
        morphWeights(o, "weights", mesh.targetCount, "mesh " + std::to_string(node.mesh) + " has");
  }
  return node;
}

// Each node's parent (-1 for roots). glTF node graphs are disjoint trees: one parent per
// node, and no node its own child.
std::vector<int> nodeParents(const std::vector<Node>& nodes) {
  std::vector<int> parent(nodes.size(), -1);
  for (size_t i = 0; i < nodes.size(); ++i)
    for (size_t k = 0; k < nodes[i].children.size(); ++k) {
      int c = nodes[i].children[k];
      SourceLocation loc = nodes[i].where.child("children").child(k);
      if (size_t(c) == i)
        throw SceneError(
            loc, "node " + std::to_string(c) + " is its own child (cycle in the node graph)");
      if (parent[size_t(c)] >= 0)
        throw SceneError(loc, "node " + std::to_string(c) + " already has parent node " +
                                  std::to_string(parent[size_t(c)]) +
                                  " (the node graph must be a set of trees)");
      parent[size_t(c)] = int(i);
    }
  return parent;
}

// With one parent each, a cycle is a parent chain that comes back to where it started. Each
// node's depth is found once, walking up until a root or a node whose depth is known, so a
// long chain costs linear time; the loader recurses once per level, hence the depth limit.
void checkNodeDepths(const std::vector<Node>& nodes, const std::vector<int>& parent) {
  const size_t n = nodes.size();
  auto childEntry = [&](size_t node) {  // the pointer of `node` in its parent's children
    const Node& parentNode = nodes[size_t(parent[node])];
    size_t k = size_t(std::find(parentNode.children.begin(), parentNode.children.end(), int(node)) -
                      parentNode.children.begin());
    return parentNode.where.child("children").child(k);
  };
  std::vector<int> depth(n, -1);  // 0 for roots; -1 = not known yet
  std::vector<bool> walked(n, false);
  std::vector<size_t> walk;
  for (size_t i = 0; i < n; ++i) {
    walk.clear();
    int p = int(i);
    while (p >= 0 && depth[size_t(p)] < 0) {
      if (walked[size_t(p)]) {
        // Back at a node of this walk: p is on a cycle. Name its lowest node, as a reader
        // scanning the file would meet it first.
        size_t first = size_t(p);
        for (int q = parent[size_t(p)]; q != p; q = parent[size_t(q)])
          first = std::min(first, size_t(q));
        throw SceneError(childEntry(first),
                         "node " + std::to_string(first) + " is an ancestor of node " +
                             std::to_string(parent[first]) + " (cycle in the node graph)");
      }
      walked[size_t(p)] = true;
      walk.push_back(size_t(p));
      p = parent[size_t(p)];
    }
    int d = p < 0 ? -1 : depth[size_t(p)];
    for (auto it = walk.rbegin(); it != walk.rend(); ++it) {
      depth[*it] = ++d;
      if (d > kMaxNodeDepth)
        throw SceneError(childEntry(*it), "node " + std::to_string(*it) + " is nested " +
                                              std::to_string(d) +
                                              " levels below its root node; glint reads node "
                                              "hierarchies at most " +
                                              std::to_string(kMaxNodeDepth) + " levels deep");
    }
  }
}

// The "scenes" array, whose nodes must be roots, and the default "scene".
void readScenes(JsonReader& root, const std::vector<int>& parent, Document* doc) {
  for (const JsonItem& item : root.optionalArray("scenes")) {
    JsonReader o(item);
    Scene s;
    s.where = o.where();
    for (const JsonItem& entry : o.optionalArray("nodes")) {
      int node = entry.asIndex(parent.size(), "node");
      if (parent[size_t(node)] >= 0)
        throw SceneError(entry.where, "node " + std::to_string(node) +
                                          " is not a root node (its parent is node " +
                                          std::to_string(parent[size_t(node)]) + ")");
      s.nodes.push_back(node);
    }
    doc->scenes.push_back(s);
  }
  doc->scene = root.index("scene", doc->scenes.size(), "scene", -1);
}

}  // namespace

void readNodes(JsonReader& root, Document* doc) {
  const std::vector<JsonItem> nodes = root.optionalArray("nodes");
  for (const JsonItem& item : nodes) doc->nodes.push_back(readNode(item, nodes.size(), *doc));
  const std::vector<int> parent = nodeParents(doc->nodes);
  checkNodeDepths(doc->nodes, parent);
  readScenes(root, parent, doc);
}

void readSkins(JsonReader& root, Document* doc) {
  for (const JsonItem& item : root.optionalArray("skins")) {
    JsonReader o(item);
    Skin skin;
    skin.where = o.where();
    for (const JsonItem& joint : o.array("joints"))
      skin.joints.push_back(joint.asIndex(doc->nodes.size(), "node"));
    if (skin.joints.empty()) throw SceneError(o.where("joints"), "must not be empty");
    skin.inverseBindMatrices =
        o.index("inverseBindMatrices", doc->accessors.size(), "accessor", -1);
    if (skin.inverseBindMatrices >= 0) {
      const Accessor& a = doc->accessors[size_t(skin.inverseBindMatrices)];
      if (a.type != "MAT4" || a.componentType != kFloat)
        throw SceneError(o.where("inverseBindMatrices"),
                         "accessor " + std::to_string(skin.inverseBindMatrices) + " is " + a.type +
                             " of " + componentTypeName(a.componentType) +
                             "; inverse bind matrices must be MAT4 of FLOAT");
      if (a.count < skin.joints.size())
        throw SceneError(o.where("inverseBindMatrices"),
                         "accessor " + std::to_string(skin.inverseBindMatrices) + " has " +
                             std::to_string(a.count) + " matrices for " +
                             plural(skin.joints.size(), "joint"));
    }
    doc->skins.push_back(skin);
  }
  for (Node& node : doc->nodes)
    if (node.skin >= 0 && size_t(node.skin) >= doc->skins.size())
      throw SceneError(node.where.child("skin"),
                       "skin " + std::to_string(node.skin) + " does not exist (" +
                           plural(doc->skins.size(), "skin") + " in the file)");
}

}  // namespace glint::gltf
