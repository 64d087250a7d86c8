// glint — reading analytic objects, CSG trees and terrain from the sidecar JSON.
#include "scenes/sidecar_objects.h"

#include <filesystem>

#include "scenes/csg_rpn.h"
#include "scenes/paths.h"

namespace glint {

namespace fs = std::filesystem;

namespace {

// The index of the material called `name`, or a SceneError at `where`.
int materialByName(const SceneDescription& scene, const std::string& name,
                   const SourceLocation& where) {
  for (size_t i = 0; i < scene.materials.size(); ++i)
    if (scene.materials[i].name == name) return int(i);
  std::vector<std::string> names;
  for (const MaterialDesc& m : scene.materials) names.push_back(m.name);
  std::string message = "no material named '" + name + "'";
  if (std::string guess = closestMatch(name, names); !guess.empty())
    message += "; did you mean '" + guess + "'?";
  throw SceneError(where, message);
}

int readMaterialRef(JsonReader& r, const SceneDescription& scene) {
  if (!r.has("material")) return -1;
  return materialByName(scene, r.get<std::string>("material"), r.where("material"));
}

}  // namespace

namespace {

// A shape's parameters from its JSON object; errors at the key's JSON pointer.
class JsonShapeParameters final : public ShapeParameters {
 public:
  explicit JsonShapeParameters(JsonReader& r) : r_(r) {}
  float positive(const char* key, std::optional<float> fallback) override {
    return fallback ? r_.get<float>(key, *fallback, kPositive) : r_.get<float>(key, kPositive);
  }
  Vec3f vector(const char* key, std::optional<Vec3f> fallback) override {
    return fallback ? r_.get<Vec3f>(key, *fallback) : r_.get<Vec3f>(key);
  }
  bool flag(const char* key, bool fallback) override { return r_.get<bool>(key, fallback); }
  [[noreturn]] void invalid(const char* key, const std::string& message) override {
    throw SceneError(r_.where(key), message);
  }

 private:
  JsonReader& r_;
};

}  // namespace

std::vector<std::string> shapeNames() {
  std::vector<std::string> names;
  for (const ShapeKind& kind : shapeKinds()) names.push_back(kind.name);
  return names;
}

ShapeRef readShape(JsonReader& r, const ShapeKind& kind) {
  JsonShapeParameters params(r);
  return kind.create(params);
}

namespace {

const std::vector<std::pair<std::string, CsgOp>> kCsgOps = {
    {"union", CsgOp::Union},
    {"intersection", CsgOp::Intersection},
    {"difference", CsgOp::Difference},
};

// One node of a nested JSON tree: {"op": ..., "children": [...]} or a primitive with "type";
// `depth` is its level (the root is 1).
int readCsgNode(JsonReader& r, const SceneDescription& scene, CsgTreeDesc* tree, int depth = 1) {
  CsgNodeDesc node;
  node.where = r.where();
  // Checked before reading on: the recursion below must not get deeper than this.
  if (depth > kMaxCsgDepth)
    throw SceneError(r.where(), "CSG tree nested more than " + std::to_string(kMaxCsgDepth) +
                                    " levels deep (glint's limit)");
  if (const nlohmann::json* t = r.take("transform"))
    node.parentFromNode = readTransform(*t, r.where("transform"), &node.parentFromNodeMeant);
  if (r.has("op") == r.has("type"))
    throw SceneError(r.where(), "a CSG node has either 'op' (an operation) or 'type' (a leaf)");
  if (r.has("type")) {
    node.shape = readShape(r, *findShapeKind(r.oneOf("type", shapeNames())));
    if (!node.shape->isSolid())
      throw SceneError(r.where("type"),
                       "CSG leaves must be solids (sphere, box, capped cylinder or cone, plane)");
    node.material = readMaterialRef(r, scene);
    tree->nodes.push_back(node);
    return int(tree->nodes.size() - 1);
  }
  node.op = r.oneOf<CsgOp>("op", kCsgOps);
  std::vector<JsonItem> children = r.array("children");
  if (children.size() < 2)
    throw SceneError(r.where("children"), "an operation needs at least two children, got " +
                                              std::to_string(children.size()));
  for (const JsonItem& child : children)
    node.children.push_back(readCsgNode(r.item(child), scene, tree, depth + 1));
  tree->nodes.push_back(node);
  return int(tree->nodes.size() - 1);
}

TerrainDesc readTerrain(JsonReader& r) {
  TerrainDesc t;
  t.size = r.get<float>("size", t.size, kPositive);
  // Depth 10 is 2 million triangles: beyond that a terrain is a mistake, not a wish.
  t.depth = r.get<int>("depth", t.depth, {.ge = 0, .le = 10});
  t.roughness = r.get<float>("roughness", t.roughness, kUnit);
  t.peak = r.get<Vec2f>("peak", t.peak);
  t.height = r.get<float>("height", t.height, kNonNegative);
  t.seed = r.get<uint64_t>("seed", t.seed);
  return t;
}

ObjectDesc readObject(JsonReader& r, const std::string& file, SceneDescription* sceneOut) {
  const SceneDescription& scene = *sceneOut;
  ObjectDesc obj;
  obj.where = r.where();
  obj.name = r.get<std::string>("name", "");
  obj.worldFromObject = r.get<Transform>("transform", Transform());
  if (std::optional<NodeDesc> node = readAnimation(r, obj.name)) {
    sceneOut->nodes.push_back(*node);
    obj.transformNode = int(sceneOut->nodes.size()) - 1;
    obj.nodeFromObject = obj.worldFromObject;
    // The placement at the scene time; scenes/sidecar.cpp sets it again once all is read.
    obj.worldFromObject =
        worldFromNode(sceneOut->nodes, obj.transformNode, r.time().value_or(0.0)) *
        obj.nodeFromObject;
  }
  obj.material = readMaterialRef(r, scene);
  std::string type = r.get<std::string>("type");
  if (type == "csg") {
    obj.kind = ObjectKind::Csg;
    if (r.has("tree") == r.has("file"))
      throw SceneError(r.where(), "a csg object has either 'tree' (nested JSON) or 'file' (.csg)");
    if (r.has("tree")) {
      obj.csg.root = readCsgNode(r.object("tree"), scene, &obj.csg);
      if (obj.csg.nodes[size_t(obj.csg.root)].op == CsgOp::Leaf)
        throw SceneError(r.where("tree"), "a CSG tree needs an operation at its root");
    } else {
      std::string relative = r.get<std::string>("file");
      const fs::path path = existingScenePath(relative, file, r.where("file"));
      obj.csg = loadCsgRpn(path.string());
      resolveCsgMaterials(&obj.csg, scene);
    }
  } else if (type == "terrain") {
    obj.kind = ObjectKind::Terrain;
    obj.terrain = readTerrain(r);
  } else {
    obj.kind = ObjectKind::Shape;
    const ShapeKind* kind = findShapeKind(type);
    if (!kind) {
      std::vector<std::string> names = {"csg", "terrain"};
      for (const std::string& name : shapeNames()) names.push_back(name);
      std::string message = "unknown object type '" + type + "'";
      if (std::string guess = closestMatch(type, names); !guess.empty())
        message += "; did you mean '" + guess + "'?";
      throw SceneError(r.where("type"), message);
    }
    obj.shape = readShape(r, *kind);
  }
  return obj;
}

}  // namespace

void resolveCsgMaterials(CsgTreeDesc* tree, const SceneDescription& scene) {
  for (CsgNodeDesc& node : tree->nodes)
    if (!node.materialName.empty())
      node.material = materialByName(scene, node.materialName, node.where);
}

void readObjects(JsonReader& root, const std::string& file, SceneDescription* scene) {
  for (JsonReader* r : root.objects("objects")) {
    ObjectDesc obj = readObject(*r, file, scene);
    scene->objects.push_back(std::move(obj));
  }
}

std::optional<NodeDesc> readAnimation(JsonReader& item, const std::string& name) {
  JsonReader* r = item.optionalObject("animation");
  if (!r) return std::nullopt;
  NodeDesc node;
  node.name = name.empty() ? "animation at " + r->where().pointer : name;
  node.where = r->where();
  if (JsonReader* t = r->optionalObject("translation"))
    node.translationTrack = readTrack<Vec3f>(
        *t,
        [](const nlohmann::json& v, const SourceLocation& w) { return readValue<Vec3f>(v, w); });
  if (JsonReader* q = r->optionalObject("rotation")) {
    if (q->has("axis")) {
      // Angles rather than quaternions: two keys can then turn by any amount (a wheel
      // spinning 720 degrees), where slerp would take the shortest way.
      Vec3f axis = q->get<Vec3f>("axis");
      if (axis == Vec3f{}) throw SceneError(q->where("axis"), "must not be zero");
      node.rotationAxis = normalize(axis);
      node.angleTrack = readTrack<float>(*q, [](const nlohmann::json& v, const SourceLocation& w) {
        return readValue<float>(v, w);
      });
    } else {
      node.rotationTrack =
          readTrack<Quaternion>(*q, [](const nlohmann::json& v, const SourceLocation& w) {
            return readValue<Quaternion>(v, w);
          });
    }
  }
  if (JsonReader* s = r->optionalObject("scale"))
    node.scaleTrack = readTrack<Vec3f>(*s, [](const nlohmann::json& v, const SourceLocation& w) {
      Vec3f x = v.is_number() ? Vec3f{1, 1, 1} * readValue<float>(v, w) : readValue<Vec3f>(v, w);
      if (x.x == 0 || x.y == 0 || x.z == 0)
        throw SceneError(w, "scale must not be zero (the transform would not be invertible)");
      return x;
    });
  r->finish();  // a misspelt track is reported as such, not as a missing one
  if (!node.hasTracks())
    throw SceneError(r->where(), "an animation needs 'translation', 'rotation' or 'scale'");
  return node;
}

}  // namespace glint
