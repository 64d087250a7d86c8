// glint — glTF JSON → validated structs (the loader's first pass): the document as a whole
// (asset, extensions, the order of the parts) and what the parts share. The parts are
// scenes/gltf_document_*.cpp (scenes/gltf_document_parts.h lists them).
#include <algorithm>
#include <cstdio>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "scenes/gltf_document_parts.h"

namespace glint::gltf {

namespace {

// Extensions glint implements; any other extension in extensionsRequired is an error, and one
// in extensionsUsed a warning.
const char* const kSupportedExtensions[] = {
    "KHR_lights_punctual",        "KHR_materials_emissive_strength",
    "KHR_materials_transmission", "KHR_materials_ior",
    "KHR_texture_transform",      "KHR_materials_unlit",
    "KHR_mesh_quantization",      "EXT_mesh_gpu_instancing",
    "EXT_texture_webp",           "KHR_materials_variants",
    "KHR_materials_specular",     "KHR_materials_clearcoat",
    "KHR_materials_sheen",        "KHR_materials_volume",
    "KHR_materials_iridescence",  "KHR_materials_anisotropy",
    "KHR_materials_dispersion",   "KHR_materials_diffuse_transmission",
    "KHR_draco_mesh_compression", "EXT_meshopt_compression"};

bool isSupportedExtension(const std::string& name) {
  return std::find(std::begin(kSupportedExtensions), std::end(kSupportedExtensions), name) !=
         std::end(kSupportedExtensions);
}

// What glint does without an extension it does not implement, for the warning.
std::string whatIsIgnored(const std::string& name) {
  static const std::pair<const char*, const char*> kKnown[] = {
      {"KHR_materials_pbrSpecularGlossiness", "the metallic-roughness parameters, if any"},
      {"KHR_xmp_json_ld", "metadata only"},
      {"KHR_texture_basisu",
       "textures use their fallback 'source' image (Debian has no Basis "
       "Universal decoder)"},
      {"KHR_animation_pointer", "animated material and camera properties stay at rest"},
  };
  for (const auto& [known, ignored] : kKnown)
    if (name == known) return ignored;
  return "whatever it adds";
}

std::string supportedExtensionList() {
  std::string list;
  for (const char* e : kSupportedExtensions) list += (list.empty() ? "" : ", ") + std::string(e);
  return list;
}

void checkExtensions(JsonReader& root, std::vector<std::string>* warnings,
                     std::vector<std::string>* used) {
  for (const JsonItem& item : root.optionalArray("extensionsRequired")) {
    std::string name = item.as<std::string>();
    if (!isSupportedExtension(name))
      throw SceneError(item.where, "unsupported extension '" + name +
                                       "' is required (glint supports " + supportedExtensionList() +
                                       ")");
  }
  for (const JsonItem& item : root.optionalArray("extensionsUsed")) {
    std::string name = item.as<std::string>();
    used->push_back(name);
    if (!isSupportedExtension(name))
      warnings->push_back(item.where.str() + ": extension '" + name +
                          "' is not supported; ignored: " + whatIsIgnored(name));
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Shared by the parts
// ---------------------------------------------------------------------------------------------

std::string plural(size_t n, const std::string& word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

float nonNegative(JsonReader& o, std::string_view key, double fallback, double upper) {
  double v = o.get<double>(key, fallback);
  if (v < 0) throw SceneError(o.where(key), "must not be negative");
  if (v > upper) {
    char bound[32];
    std::snprintf(bound, sizeof bound, "%.15g", upper);
    throw SceneError(o.where(key), "must be between 0 and " + std::string(bound));
  }
  return float(v);
}

// ---------------------------------------------------------------------------------------------
// Public
// ---------------------------------------------------------------------------------------------

size_t componentSize(int componentType) {
  switch (componentType) {
    case kByte:
    case kUnsignedByte:
      return 1;
    case kShort:
    case kUnsignedShort:
      return 2;
    default:
      return 4;
  }
}

std::string componentTypeName(int componentType) {
  switch (componentType) {
    case kByte:
      return "BYTE";
    case kUnsignedByte:
      return "UNSIGNED_BYTE";
    case kShort:
      return "SHORT";
    case kUnsignedShort:
      return "UNSIGNED_SHORT";
    case kUnsignedInt:
      return "UNSIGNED_INT";
    case kFloat:
      return "FLOAT";
    default:
      return "componentType " + std::to_string(componentType);
  }
}

size_t elementSize(const Accessor& accessor) {
  size_t c = componentSize(accessor.componentType);
  // Matrix columns start on 4-byte boundaries (glTF 2.0, "Data Alignment").
  if (accessor.type == "MAT2" && c == 1) return 8;
  if (accessor.type == "MAT3" && c <= 2) return 3 * ((3 * c + 3) / 4 * 4);
  return c * size_t(accessor.components);
}

Document readDocument(const nlohmann::json& rootValue, const std::string& file) {
  // Lenient: glTF allows keys glint does not read (see JsonMode).
  JsonReader root(rootValue, SourceLocation{file, ""}, JsonMode::Lenient);
  Document doc;
  doc.file = file;
  JsonReader& asset = root.object("asset");
  std::string version = asset.get<std::string>("version");
  if (version.rfind("2.", 0) != 0)
    throw SceneError(asset.where("version"),
                     "unsupported glTF version '" + version + "' (glint reads 2.x)");
  checkExtensions(root, &doc.warnings, &doc.extensionsUsed);
  readBuffers(root, &doc);
  readBufferViews(root, &doc);
  readAccessors(root, &doc);
  readImages(root, &doc);
  readSamplers(root, &doc);
  readTextures(root, &doc);
  readMaterials(root, &doc);
  readVariants(root, &doc);
  readMeshes(root, &doc);
  readCameras(root, &doc);
  readLights(root, &doc);
  readNodes(root, &doc);
  readSkins(root, &doc);
  readAnimations(root, &doc);
  return doc;
}

}  // namespace glint::gltf