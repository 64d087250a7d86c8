// glint — glTF meshes and their primitives: attributes, morph targets, and the primitive
// extensions glint implements (KHR_materials_variants, KHR_draco_mesh_compression).
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "scenes/gltf_document_parts.h"

namespace glint::gltf {

namespace {

// KHR_materials_variants on a primitive: its (material, variants) mappings.
void readVariantMappings(JsonReader& kv, const Document& doc, Primitive* p) {
  kv.require("mappings");
  for (JsonReader* mo : kv.objects("mappings")) {
    const int material = mo->index("material", doc.materials.size(), "material");
    std::vector<int> variants;
    for (const JsonItem& v : mo->array("variants"))
      variants.push_back(v.asIndex(doc.variants.size(), "variant"));
    if (variants.empty()) throw SceneError(mo->where("variants"), "must not be empty");
    p->variantMappings.emplace_back(material, std::move(variants));
  }
}

// KHR_draco_mesh_compression on a primitive whose (decoded) attributes are `attributes`.
Primitive::Draco readDraco(JsonReader& dr, JsonReader& attributes, const Primitive& p,
                           const Document& doc) {
  Primitive::Draco d;
  d.where = dr.where();
  d.bufferView = dr.index("bufferView", doc.bufferViews.size(), "bufferView");
  JsonReader& da = dr.object("attributes");
  for (const auto& entry : da.json().items()) {
    const std::string& name = entry.key();
    if (!attributes.has(name))
      throw SceneError(da.where(name),
                       "names attribute " + name + " that the primitive's attributes do not have");
    d.attributes.emplace_back(name, int(da.getSize(name)));
  }
  if (p.indices < 0)
    throw SceneError(dr.where(), "a Draco-compressed primitive needs an indices accessor");
  return d;
}

Primitive readPrimitive(JsonReader& po, const Mesh& mesh, const Document& doc) {
  Primitive p;
  p.where = po.where();
  JsonReader& attributes = po.object("attributes");
  const size_t accessors = doc.accessors.size();
  p.position = attributes.index("POSITION", accessors, "accessor", -1);
  p.normal = attributes.index("NORMAL", accessors, "accessor", -1);
  p.tangent = attributes.index("TANGENT", accessors, "accessor", -1);
  p.texcoord0 = attributes.index("TEXCOORD_0", accessors, "accessor", -1);
  p.texcoord1 = attributes.index("TEXCOORD_1", accessors, "accessor", -1);
  p.color0 = attributes.index("COLOR_0", accessors, "accessor", -1);
  p.joints0 = attributes.index("JOINTS_0", accessors, "accessor", -1);
  p.weights0 = attributes.index("WEIGHTS_0", accessors, "accessor", -1);
  if ((p.joints0 >= 0) != (p.weights0 >= 0))
    throw SceneError(attributes.where(),
                     p.joints0 >= 0 ? "JOINTS_0 without WEIGHTS_0" : "WEIGHTS_0 without JOINTS_0");
  p.moreJoints = attributes.has("JOINTS_1") || attributes.has("WEIGHTS_1");
  for (JsonReader* to : po.objects("targets")) {
    MorphTarget t;
    t.where = to->where();
    t.position = to->index("POSITION", accessors, "accessor", -1);
    t.normal = to->index("NORMAL", accessors, "accessor", -1);
    t.tangent = to->index("TANGENT", accessors, "accessor", -1);
    p.targets.push_back(t);
  }
  // glTF: every primitive of a mesh has the same number of morph targets.
  if (!mesh.primitives.empty() && p.targets.size() != mesh.primitives[0].targets.size())
    throw SceneError(po.has("targets") ? po.where("targets") : po.where(),
                     "has " + plural(p.targets.size(), "morph target") + " but primitive 0 has " +
                         std::to_string(mesh.primitives[0].targets.size()) +
                         " (every primitive of a mesh must have the same number)");
  p.indices = po.index("indices", accessors, "accessor", -1);
  p.material = po.index("material", doc.materials.size(), "material", -1);
  if (JsonReader* ext = po.optionalObject("extensions")) {
    if (JsonReader* kv = ext->optionalObject("KHR_materials_variants"))
      readVariantMappings(*kv, doc, &p);
    if (JsonReader* dr = ext->optionalObject("KHR_draco_mesh_compression"))
      p.draco = readDraco(*dr, attributes, p, doc);
  }
  size_t mode = po.getSize("mode", kTriangles);
  if (mode > kTriangleFan)
    throw SceneError(po.where("mode"), "unknown mode " + std::to_string(mode));
  p.mode = int(mode);
  if (p.position < 0) throw SceneError(attributes.where(), "missing POSITION");
  return p;
}

}  // namespace

std::vector<float> morphWeights(JsonReader& o, std::string_view key, size_t targets,
                                const std::string& owner) {
  std::vector<float> w;
  if (!o.has(key)) return w;
  const std::vector<JsonItem> items = o.array(key);
  if (items.size() != targets)
    throw SceneError(o.where(key), "has " + plural(items.size(), "weight") + " but " + owner + " " +
                                       plural(targets, "morph target"));
  for (const JsonItem& item : items) w.push_back(float(item.as<double>()));
  return w;
}

void readVariants(JsonReader& root, Document* doc) {
  JsonReader* ext = root.optionalObject("extensions");
  JsonReader* kv = ext ? ext->optionalObject("KHR_materials_variants") : nullptr;
  if (!kv) return;
  kv->require("variants");
  for (JsonReader* v : kv->objects("variants")) {
    const std::string name = v->get<std::string>("name");
    if (std::find(doc->variants.begin(), doc->variants.end(), name) != doc->variants.end())
      throw SceneError(v->where("name"), "variant '" + name + "' is named twice");
    doc->variants.push_back(name);
  }
}

void readMeshes(JsonReader& root, Document* doc) {
  size_t meshIndex = 0;
  for (const JsonItem& item : root.optionalArray("meshes")) {
    JsonReader o(item);
    Mesh mesh;
    mesh.where = o.where();
    mesh.name = o.get<std::string>("name", "mesh " + std::to_string(meshIndex++));
    o.require("primitives");
    for (JsonReader* po : o.objects("primitives"))
      mesh.primitives.push_back(readPrimitive(*po, mesh, *doc));
    if (mesh.primitives.empty()) throw SceneError(o.where("primitives"), "must not be empty");
    mesh.targetCount = mesh.primitives[0].targets.size();
    mesh.weights = morphWeights(o, "weights", mesh.targetCount, "the mesh's primitives have");
    doc->meshes.push_back(mesh);
  }
}

}  // namespace glint::gltf
