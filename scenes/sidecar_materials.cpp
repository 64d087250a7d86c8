// glint — the sidecar's textures and materials.
#include "scenes/sidecar_materials.h"

#include <filesystem>

#include "scenes/paths.h"

namespace glint {

namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------------------------------------
// textures
// ---------------------------------------------------------------------------------------------

const std::vector<std::pair<std::string, NoiseKind>> kNoiseTypes = {
    {"noise", NoiseKind::Noise},   {"fbm", NoiseKind::Fbm},   {"turbulence", NoiseKind::Turbulence},
    {"marble", NoiseKind::Marble}, {"wood", NoiseKind::Wood}, {"clouds", NoiseKind::Clouds},
};

const std::vector<std::pair<std::string, WrapMode>> kWrapModes = {
    {"repeat", WrapMode::Repeat},
    {"clamp", WrapMode::ClampToEdge},
    {"mirror", WrapMode::MirroredRepeat},
    {"black", WrapMode::Black},
};

// "mapping": {"space": "uv" | "object" | "world", "plane": "xy" | "xz" | "yz",
//             "scale": s or [x, y, z], "offset": [x, y, z]}
MappingDesc readMapping(JsonReader& r, MappingDesc::Space fallback) {
  MappingDesc m;
  m.space = fallback;
  JsonReader* j = r.optionalObject("mapping");
  if (!j) return m;
  m.space = j->oneOf<MappingDesc::Space>("space",
                                         {{"uv", MappingDesc::Space::Uv},
                                          {"object", MappingDesc::Space::Object},
                                          {"world", MappingDesc::Space::World}},
                                         fallback);
  m.plane = j->oneOf<MappingDesc::Plane>("plane",
                                         {{"xy", MappingDesc::Plane::Xy},
                                          {"xz", MappingDesc::Plane::Xz},
                                          {"yz", MappingDesc::Plane::Yz}},
                                         MappingDesc::Plane::Xy);
  if (const nlohmann::json* s = j->take("scale")) {
    m.scale = s->is_number() ? Vec3f{1, 1, 1} * j->value<float>(*s, j->where("scale"), kPositive)
                             : j->value<Vec3f>(*s, j->where("scale"), kPositive);
  }
  m.offset = j->get<Vec3f>("offset", m.offset);
  return m;
}

// "colors": [[r, g, b], [r, g, b]]: the pattern's colours at weight 0 and 1.
void readColors(JsonReader& r, TextureDesc* t) {
  std::vector<JsonItem> colors = r.optionalArray("colors");
  if (colors.empty()) {
    if (r.has("colors")) throw SceneError(r.where("colors"), "expected two colours");
    return;
  }
  if (colors.size() != 2) throw SceneError(r.where("colors"), "expected two colours");
  t->colorA = colors[0].as<Rgb>(kNonNegative);
  t->colorB = colors[1].as<Rgb>(kNonNegative);
}

TextureDesc readTexture(JsonReader& r, const std::string& file) {
  TextureDesc t;
  t.where = r.where();
  t.name = r.get<std::string>("name");
  if (t.name.empty()) throw SceneError(r.where("name"), "must not be empty");
  std::vector<std::string> types = {"image", "checker", "random"};
  for (const auto& n : kNoiseTypes) types.push_back(n.first);
  const std::string type = r.oneOf("type", types);

  if (type == "image") {
    t.kind = TextureKind::ImageFile;
    const std::string relative = r.get<std::string>("file");
    t.file = existingScenePath(relative, file, r.where("file")).string();
    t.encoding = r.oneOf<TextureDesc::Encoding>("colorspace",
                                                {{"auto", TextureDesc::Encoding::Auto},
                                                 {"srgb", TextureDesc::Encoding::Srgb},
                                                 {"linear", TextureDesc::Encoding::Linear}},
                                                TextureDesc::Encoding::Auto);
    if (const nlohmann::json* w = r.take("wrap")) {
      // One mode for both axes, or [s, t].
      auto mode = [&](const nlohmann::json& v, const SourceLocation& at) {
        std::string name = readValue<std::string>(v, at);
        for (const auto& [n, m] : kWrapModes)
          if (n == name) return m;
        throw SceneError(at, "must be one of repeat, clamp, mirror, black (got '" + name + "')");
      };
      if (w->is_array() && w->size() == 2) {
        t.wrapS = mode((*w)[0], r.where("wrap").child(size_t(0)));
        t.wrapT = mode((*w)[1], r.where("wrap").child(size_t(1)));
      } else {
        t.wrapS = t.wrapT = mode(*w, r.where("wrap"));
      }
    }
    const std::string filter = r.oneOf("filter", {"mipmap", "linear", "nearest"}, "mipmap");
    t.nearest = filter == "nearest";
    t.mipmap = filter == "mipmap";
    t.mapping = readMapping(r, MappingDesc::Space::Uv);
  } else if (type == "checker") {
    t.kind = TextureKind::Checker;
    readColors(r, &t);
    t.solid = r.get<bool>("solid", false);
    t.mapping = readMapping(r, t.solid ? MappingDesc::Space::Object : MappingDesc::Space::Uv);
  } else if (type == "random") {
    t.kind = TextureKind::Random;
    t.randomMode =
        r.oneOf<TextureDesc::RandomMode>("mode",
                                         {{"object", TextureDesc::RandomMode::Object},
                                          {"primitive", TextureDesc::RandomMode::Primitive},
                                          {"hit", TextureDesc::RandomMode::Hit}},
                                         TextureDesc::RandomMode::Object);
    t.seed = r.get<uint64_t>("seed", 0);
  } else {
    t.kind = TextureKind::Noise;
    for (const auto& [n, k] : kNoiseTypes)
      if (n == type) t.noise = k;
    t.seed = r.get<uint64_t>("seed", t.seed);
    t.octaves = r.get<int>("octaves", t.octaves, {.ge = 1, .le = 16});
    t.lacunarity = r.get<float>("lacunarity", t.lacunarity, kPositive);
    t.gain = r.get<float>("gain", t.gain, kPositive);
    if (t.noise == NoiseKind::Marble) {
      t.frequency = r.get<float>("frequency", t.frequency, kNonNegative);
      t.distortion = r.get<float>("distortion", t.distortion, kNonNegative);
    }
    if (t.noise == NoiseKind::Wood) {
      t.ringFrequency = r.get<float>("ring_frequency", t.ringFrequency, kPositive);
      t.jitter = r.get<float>("jitter", t.jitter, kNonNegative);
    }
    readColors(r, &t);
    t.mapping = readMapping(r, MappingDesc::Space::Object);
  }
  return t;
}

// The index of the sidecar texture called `name`, or a SceneError at `where`.
int textureByName(const SceneDescription& scene, const std::string& name,
                  const SourceLocation& where) {
  std::vector<std::string> names;
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    if (scene.textures[i].name.empty()) continue;
    if (scene.textures[i].name == name) return int(i);
    names.push_back(scene.textures[i].name);
  }
  std::string message = "no texture named '" + name + "'";
  std::string guess = closestMatch(name, names);
  if (!guess.empty())
    message += "; did you mean '" + guess + "'?";
  else if (names.empty())
    message += " (the scene defines no textures)";
  throw SceneError(where, message);
}

// ---------------------------------------------------------------------------------------------
// materials
// ---------------------------------------------------------------------------------------------

const std::vector<std::pair<std::string, MaterialType>> kMaterialTypes = {
    {"pbr", MaterialType::Pbr},       {"eyelight", MaterialType::Eyelight},
    {"unlit", MaterialType::Unlit},   {"lambert", MaterialType::Lambert},
    {"phong", MaterialType::Phong},   {"blinn_phong", MaterialType::BlinnPhong},
    {"mirror", MaterialType::Mirror}, {"glass", MaterialType::Glass},
    {"random", MaterialType::Random},
};

// A colour parameter: [r, g, b], or the name of a texture (which then replaces the material's
// texture, with the factor reset to white).
void readColorParam(JsonReader& r, const char* key, const SceneDescription& scene, Rgb* factor,
                    int* texture) {
  const nlohmann::json* v = r.take(key);
  if (!v) return;
  if (v->is_string()) {
    *texture = textureByName(scene, v->get<std::string>(), r.where(key));
    *factor = {1, 1, 1};
    return;
  }
  *factor = r.value<Rgb>(*v, r.where(key), kNonNegative);
}

// "bump", "normal_map" or "snow": at most one per material.
void readNormalModifier(JsonReader& r, const SceneDescription& scene, MaterialDesc* m) {
  int given = int(r.has("bump")) + int(r.has("normal_map")) + int(r.has("snow"));
  if (given > 1) throw SceneError(r.where(), "give at most one of 'bump', 'normal_map' and 'snow'");
  if (JsonReader* b = r.optionalObject("bump")) {
    m->bumpTexture = textureByName(scene, b->get<std::string>("texture"), b->where("texture"));
    m->bumpStrength = b->get<float>("strength", 1.0f);
    m->normalTexture = -1;  // replaces a glTF normal map
    m->snowAmount = 0;
  }
  if (JsonReader* n = r.optionalObject("normal_map")) {
    m->normalTexture = textureByName(scene, n->get<std::string>("texture"), n->where("texture"));
    m->normalScale = n->get<float>("scale", 1.0f);
    m->bumpTexture = -1;
    m->snowAmount = 0;
  }
  if (JsonReader* s = r.optionalObject("snow")) {
    m->snowAmount = s->get<float>("amount", 0.3f, {.gt = 0, .le = 10});
    m->snowGrain = s->get<float>("grain", m->snowGrain, kPositive);
    m->snowSeed = s->get<uint64_t>("seed", 0);
    m->bumpTexture = m->normalTexture = -1;
  }
}

// The `pbr` type's layers, glTF's material extensions by their sidecar names (scenes/README):
// each object sets the factors it gives and keeps the rest (a glTF material overridden by name
// keeps its extension textures).
void readPbrLayers(JsonReader& r, const SceneDescription& scene, MaterialLayersDesc* l) {
  if (JsonReader* o = r.optionalObject("specular")) {
    l->specular = o->get<float>("strength", l->specular, kUnit);
    readColorParam(*o, "color", scene, &l->specularColor, &l->specularColorTexture);
  }
  if (JsonReader* o = r.optionalObject("clearcoat")) {
    l->clearcoat = o->get<float>("factor", 1.0f, kUnit);
    l->clearcoatRoughness = o->get<float>("roughness", l->clearcoatRoughness, kUnit);
  }
  if (JsonReader* o = r.optionalObject("sheen")) {
    readColorParam(*o, "color", scene, &l->sheenColor, &l->sheenColorTexture);
    l->sheenRoughness = o->get<float>("roughness", l->sheenRoughness, kUnit);
  }
  if (JsonReader* o = r.optionalObject("volume")) {
    l->thickness = o->get<float>("thickness", 1.0f, kNonNegative);
    l->attenuationColor = o->get<Rgb>("attenuation_color", l->attenuationColor, kUnit);
    l->attenuationDistance =
        o->get<float>("attenuation_distance", l->attenuationDistance, kPositive);
  }
  if (JsonReader* o = r.optionalObject("iridescence")) {
    l->iridescence = o->get<float>("factor", 1.0f, kUnit);
    l->iridescenceIor = o->get<float>("ior", l->iridescenceIor, {.ge = 1});
    const float nm = o->get<float>("thickness_nm", l->iridescenceThicknessMax, kNonNegative);
    l->iridescenceThicknessMin = l->iridescenceThicknessMax = nm;
    l->iridescenceThicknessTexture = -1;  // one thickness, as given
  }
  if (JsonReader* o = r.optionalObject("anisotropy")) {
    l->anisotropy = o->get<float>("strength", l->anisotropy, kUnit);
    l->anisotropyRotation = o->get<float>("rotation", l->anisotropyRotation);
  }
  l->dispersion = r.get<float>("dispersion", l->dispersion, kNonNegative);
  if (JsonReader* o = r.optionalObject("diffuse_transmission")) {
    l->diffuseTransmission = o->get<float>("factor", 1.0f, kUnit);
    readColorParam(*o, "color", scene, &l->diffuseTransmissionColor,
                   &l->diffuseTransmissionColorTexture);
  }
}

// Sets the given parameters of `m` (type already decided); others keep their values, so an
// override keeps the glTF material's textures and unmentioned factors.
void readMaterialParameters(JsonReader& r, const SceneDescription& scene, MaterialDesc* m) {
  switch (m->type) {
    case MaterialType::Pbr:
      readColorParam(r, "base_color", scene, &m->baseColor, &m->baseColorTexture);
      m->metallic = r.get<float>("metallic", m->metallic, kUnit);
      m->roughness = r.get<float>("roughness", m->roughness, kUnit);
      m->ior = r.get<float>("ior", m->ior, kPositive);
      m->transmission = r.get<float>("transmission", m->transmission, kUnit);
      readPbrLayers(r, scene, &m->layers);
      break;
    case MaterialType::Eyelight:
    case MaterialType::Unlit:
      readColorParam(r, "color", scene, &m->baseColor, &m->baseColorTexture);
      if (r.has("transparency")) {
        m->opacity = 1 - r.get<float>("transparency", kUnit);
        m->alphaMode = AlphaModeDesc::Blend;
      }
      break;
    case MaterialType::Lambert:
      readColorParam(r, "diffuse", scene, &m->baseColor, &m->baseColorTexture);
      break;
    case MaterialType::Phong:
    case MaterialType::BlinnPhong:
      readColorParam(r, "diffuse", scene, &m->baseColor, &m->baseColorTexture);
      m->specular = r.get<Rgb>("specular", m->specular, kNonNegative);
      m->shininess = r.get<float>("shininess", m->shininess, kNonNegative);
      break;
    case MaterialType::Mirror:
      readColorParam(r, "color", scene, &m->baseColor, &m->baseColorTexture);
      break;
    case MaterialType::Glass:
      readColorParam(r, "color", scene, &m->baseColor, &m->baseColorTexture);
      m->ior = r.get<float>("ior", m->ior, kPositive);
      m->roughness = r.get<float>("roughness", m->roughness, kUnit);
      break;
    case MaterialType::Random:
      m->randomMode =
          r.oneOf<TextureDesc::RandomMode>("mode",
                                           {{"object", TextureDesc::RandomMode::Object},
                                            {"primitive", TextureDesc::RandomMode::Primitive},
                                            {"hit", TextureDesc::RandomMode::Hit}},
                                           m->randomMode);
      m->randomSeed = r.get<uint64_t>("seed", m->randomSeed);
      m->randomLit = r.oneOf("shading", {"eyelight", "lambert"},
                             m->randomLit ? "lambert" : "eyelight") == "lambert";
      break;
  }
  readColorParam(r, "emissive", scene, &m->emissive, &m->emissiveTexture);
  m->doubleSided = r.get<bool>("double_sided", m->doubleSided);
  m->alphaMode = r.oneOf<AlphaModeDesc>("alpha_mode",
                                        {{"opaque", AlphaModeDesc::Opaque},
                                         {"mask", AlphaModeDesc::Mask},
                                         {"blend", AlphaModeDesc::Blend}},
                                        m->alphaMode);
  m->alphaCutoff = r.get<float>("alpha_cutoff", m->alphaCutoff, kUnit);
  readNormalModifier(r, scene, m);
}

// "nodes": glTF node names whose meshes take this material.
void assignToNodes(JsonReader& r, int material, SceneDescription* scene) {
  for (const JsonItem& item : r.optionalArray("nodes")) {
    const std::string node = item.as<std::string>();
    bool found = false;
    std::vector<std::string> names;
    for (InstanceDesc& inst : scene->instances) {
      if (inst.node == node) inst.material = material, found = true;
      names.push_back(inst.node);
    }
    if (found) continue;
    std::string message = "no glTF node named '" + node + "' with a mesh";
    std::string guess = closestMatch(node, names);
    if (!guess.empty()) message += "; did you mean '" + guess + "'?";
    throw SceneError(item.where, message);
  }
}

}  // namespace

const char* materialTypeName(MaterialType type) {
  for (const auto& [name, t] : kMaterialTypes)
    if (t == type) return name.c_str();
  return "?";
}

void readTextures(JsonReader& root, const std::string& file, SceneDescription* scene) {
  for (JsonReader* r : root.objects("textures")) {
    TextureDesc t = readTexture(*r, file);
    for (const TextureDesc& other : scene->textures)
      if (other.name == t.name)
        throw SceneError(r->where("name"), "duplicate texture name '" + t.name + "' (also at " +
                                               other.where.pointer + ")");
    scene->textures.push_back(std::move(t));
  }
}

// A material named like an existing one overrides it (every one of that name); others are
// added as new materials, which need a type.
void readMaterials(JsonReader& root, SceneDescription* scene) {
  std::vector<std::pair<std::string, std::string>> seen;  // name, pointer
  for (JsonReader* r : root.objects("materials")) {
    std::string name = r->get<std::string>("name");
    if (name.empty()) throw SceneError(r->where("name"), "must not be empty");
    for (const auto& [other, pointer] : seen)
      if (other == name)
        throw SceneError(r->where("name"),
                         "duplicate material name '" + name + "' (also at " + pointer + ")");
    seen.emplace_back(name, r->where().pointer);

    std::vector<int> targets;
    for (size_t i = 0; i < scene->materials.size(); ++i)
      if (scene->materials[i].name == name) targets.push_back(int(i));
    if (targets.empty()) {
      if (!r->has("type"))
        throw SceneError(r->where(), "a new material needs a 'type' (no material named '" + name +
                                         "' to override)");
      MaterialDesc m;
      m.name = name;
      m.where = r->where();
      m.type = r->oneOf<MaterialType>("type", kMaterialTypes);
      if (m.type == MaterialType::Glass) m.roughness = 0;  // smooth unless given
      readMaterialParameters(*r, *scene, &m);
      scene->materials.push_back(m);
      assignToNodes(*r, int(scene->materials.size() - 1), scene);
      continue;
    }
    std::optional<MaterialType> type;
    if (r->has("type")) type = r->oneOf<MaterialType>("type", kMaterialTypes);
    // Reading the same keys again for each match is fine: the reader only records them.
    for (int i : targets) {
      MaterialDesc& m = scene->materials[size_t(i)];
      if (type && *type == MaterialType::Glass && m.type != MaterialType::Glass) m.roughness = 0;
      if (type) m.type = *type;
      readMaterialParameters(*r, *scene, &m);
      // Errors found later (when the material is built) belong to the override that set its
      // final parameters, not to the glTF it came from.
      m.where = r->where();
    }
    assignToNodes(*r, targets.front(), scene);
  }
}

}  // namespace glint
