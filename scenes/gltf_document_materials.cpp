// glint — glTF images, samplers, textures and materials, with the material and texture
// extensions glint implements (KHR_materials_*, KHR_texture_transform, EXT_texture_webp).
#include <algorithm>
#include <initializer_list>
#include <string>

#include "scenes/gltf_document_parts.h"

namespace glint::gltf {

namespace {

WrapMode wrapMode(JsonReader& o, std::string_view key) {
  size_t v = o.getSize(key, 10497);
  switch (v) {
    case 10497:
      return WrapMode::Repeat;
    case 33071:
      return WrapMode::ClampToEdge;
    case 33648:
      return WrapMode::MirroredRepeat;
    default:
      throw SceneError(o.where(key), "unknown wrap mode " + std::to_string(v));
  }
}

TextureRef textureRef(JsonReader& parent, std::string_view key, const Document& doc) {
  TextureRef r;
  JsonReader* o = parent.optionalObject(key);
  if (!o) return r;
  r.where = o->where();
  r.index = o->index("index", doc.textures.size(), "texture");
  r.texCoord = int(std::min<size_t>(o->getSize("texCoord", 0), 1000));
  JsonReader* ext = o->optionalObject("extensions");
  if (JsonReader* t = ext ? ext->optionalObject("KHR_texture_transform") : nullptr) {
    r.transformed = true;
    if (t->has("offset")) {
      auto v = t->numbers<2>("offset");
      r.offset = {float(v[0]), float(v[1])};
    }
    if (t->has("scale")) {
      auto v = t->numbers<2>("scale");
      r.scale = {float(v[0]), float(v[1])};
    }
    r.rotation = float(t->get<double>("rotation", 0));
    if (t->has("texCoord")) r.texCoord = int(std::min<size_t>(t->getSize("texCoord"), 1000));
  }
  return r;
}

// A colour factor at `key`: three numbers, each >= 0 and, with `upToOne`, <= 1.
Rgb colorFactor(JsonReader& o, std::string_view key, Rgb fallback, bool upToOne) {
  if (!o.has(key)) return fallback;
  auto f = o.numbers<3>(key);
  for (size_t i = 0; i < 3; ++i) {
    if (f[i] < 0) throw SceneError(o.where(key).child(i), "must not be negative");
    if (upToOne && f[i] > 1) throw SceneError(o.where(key).child(i), "must be between 0 and 1");
  }
  return {float(f[0]), float(f[1]), float(f[2])};
}

// The KHR_materials_* extensions beyond the metallic-roughness core (pbr.h has the model).
void readMaterialLayers(JsonReader& ext, const Document& doc, Material* m) {
  MaterialLayersDesc& l = m->layers;
  Material::LayerTextures& t = m->layerTextures;
  if (JsonReader* o = ext.optionalObject("KHR_materials_specular")) {
    l.specular = nonNegative(*o, "specularFactor", 1, 1);
    t.specular = textureRef(*o, "specularTexture", doc);
    l.specularColor = colorFactor(*o, "specularColorFactor", {1, 1, 1}, false);
    t.specularColor = textureRef(*o, "specularColorTexture", doc);
  }
  if (JsonReader* o = ext.optionalObject("KHR_materials_clearcoat")) {
    l.clearcoat = nonNegative(*o, "clearcoatFactor", 0, 1);
    t.clearcoat = textureRef(*o, "clearcoatTexture", doc);
    l.clearcoatRoughness = nonNegative(*o, "clearcoatRoughnessFactor", 0, 1);
    t.clearcoatRoughness = textureRef(*o, "clearcoatRoughnessTexture", doc);
    t.clearcoatNormal = textureRef(*o, "clearcoatNormalTexture", doc);
    if (o->has("clearcoatNormalTexture"))
      l.clearcoatNormalScale = float(o->object("clearcoatNormalTexture").get<double>("scale", 1.0));
  }
  if (JsonReader* o = ext.optionalObject("KHR_materials_sheen")) {
    l.sheenColor = colorFactor(*o, "sheenColorFactor", {0, 0, 0}, true);
    t.sheenColor = textureRef(*o, "sheenColorTexture", doc);
    l.sheenRoughness = nonNegative(*o, "sheenRoughnessFactor", 0, 1);
    t.sheenRoughness = textureRef(*o, "sheenRoughnessTexture", doc);
  }
  if (JsonReader* o = ext.optionalObject("KHR_materials_diffuse_transmission")) {
    l.diffuseTransmission = nonNegative(*o, "diffuseTransmissionFactor", 0, 1);
    t.diffuseTransmission = textureRef(*o, "diffuseTransmissionTexture", doc);
    l.diffuseTransmissionColor = colorFactor(*o, "diffuseTransmissionColorFactor", {1, 1, 1}, true);
    t.diffuseTransmissionColor = textureRef(*o, "diffuseTransmissionColorTexture", doc);
  }
  if (JsonReader* o = ext.optionalObject("KHR_materials_volume")) {
    l.thickness = nonNegative(*o, "thicknessFactor", 0, kInfinity);
    // thicknessTexture serves rasterisers, which cannot trace the inside; a ray tracer measures
    // the real distance. It is validated, not read.
    textureRef(*o, "thicknessTexture", doc);
    const double distance = o->get<double>("attenuationDistance", kInfinity);
    if (!(distance > 0)) throw SceneError(o->where("attenuationDistance"), "must be > 0");
    l.attenuationDistance = float(distance);
    l.attenuationColor = colorFactor(*o, "attenuationColor", {1, 1, 1}, true);
  }
  if (JsonReader* o = ext.optionalObject("KHR_materials_iridescence")) {
    l.iridescence = nonNegative(*o, "iridescenceFactor", 0, 1);
    t.iridescence = textureRef(*o, "iridescenceTexture", doc);
    const double ior = o->get<double>("iridescenceIor", 1.3);
    if (!(ior >= 1)) throw SceneError(o->where("iridescenceIor"), "must be >= 1");
    l.iridescenceIor = float(ior);
    l.iridescenceThicknessMin = nonNegative(*o, "iridescenceThicknessMinimum", 100, 1e6);
    l.iridescenceThicknessMax = nonNegative(*o, "iridescenceThicknessMaximum", 400, 1e6);
    t.iridescenceThickness = textureRef(*o, "iridescenceThicknessTexture", doc);
  }
  if (JsonReader* o = ext.optionalObject("KHR_materials_anisotropy")) {
    l.anisotropy = nonNegative(*o, "anisotropyStrength", 0, 1);
    l.anisotropyRotation = float(o->get<double>("anisotropyRotation", 0));
    t.anisotropy = textureRef(*o, "anisotropyTexture", doc);
  }
  if (JsonReader* o = ext.optionalObject("KHR_materials_dispersion"))
    l.dispersion = nonNegative(*o, "dispersion", 0, 1e3);
}

}  // namespace

void readImages(JsonReader& root, Document* doc) {
  for (const JsonItem& item : root.optionalArray("images")) {
    JsonReader o(item);
    Image im;
    im.where = o.where();
    im.uri = o.get<std::string>("uri", "");
    im.bufferView = o.index("bufferView", doc->bufferViews.size(), "bufferView", -1);
    if (o.has("uri") && im.uri.empty()) throw SceneError(o.where("uri"), "empty URI");
    if (im.uri.empty() == (im.bufferView < 0))
      throw SceneError(im.where, "needs exactly one of 'uri' and 'bufferView'");
    // Type check only: the bytes say what they are.
    if (im.bufferView >= 0) o.get<std::string>("mimeType", "");
    doc->images.push_back(im);
  }
}

void readSamplers(JsonReader& root, Document* doc) {
  for (const JsonItem& item : root.optionalArray("samplers")) {
    JsonReader o(item);
    Sampler s;
    size_t mag = o.getSize("magFilter", 9729);
    if (mag != 9728 && mag != 9729)
      throw SceneError(o.where("magFilter"), "unknown magFilter " + std::to_string(mag));
    s.magFilter = int(mag);
    o.getSize("minFilter", 0);  // type check only
    s.wrapS = wrapMode(o, "wrapS");
    s.wrapT = wrapMode(o, "wrapT");
    doc->samplers.push_back(s);
  }
}

void readTextures(JsonReader& root, Document* doc) {
  for (const JsonItem& item : root.optionalArray("textures")) {
    JsonReader o(item);
    Texture t;
    t.where = o.where();
    t.sampler = o.index("sampler", doc->samplers.size(), "sampler", -1);
    t.source = o.index("source", doc->images.size(), "image", -1);
    if (JsonReader* ext = o.optionalObject("extensions")) {
      // EXT_texture_webp: the WebP image (OpenImageIO decodes it) wins over the fallback.
      if (JsonReader* webp = ext->optionalObject("EXT_texture_webp"))
        t.source = webp->index("source", doc->images.size(), "image");
      if (t.source < 0 && ext->has("KHR_texture_basisu"))
        throw SceneError(ext->where("KHR_texture_basisu"),
                         "KTX2/Basis Universal textures cannot be decoded (Debian has no Basis "
                         "Universal decoder) and the texture has no fallback 'source'");
    }
    if (t.source < 0)
      throw SceneError(t.where,
                       "no 'source' image (textures that only an extension defines are "
                       "not supported)");
    doc->textures.push_back(t);
  }
}

void readMaterials(JsonReader& root, Document* doc) {
  size_t index = 0;
  for (const JsonItem& item : root.optionalArray("materials")) {
    JsonReader o(item);
    Material m;
    m.where = o.where();
    m.name = o.get<std::string>("name", "material " + std::to_string(index++));
    if (JsonReader* pbr = o.optionalObject("pbrMetallicRoughness")) {
      if (pbr->has("baseColorFactor")) {
        auto f = pbr->numbers<4>("baseColorFactor");
        for (size_t i = 0; i < 4; ++i)
          if (f[i] < 0 || f[i] > 1)
            throw SceneError(pbr->where("baseColorFactor").child(i), "must be between 0 and 1");
        m.baseColorFactor = {float(f[0]), float(f[1]), float(f[2]), float(f[3])};
      }
      m.baseColorTexture = textureRef(*pbr, "baseColorTexture", *doc);
      m.metallicRoughnessTexture = textureRef(*pbr, "metallicRoughnessTexture", *doc);
      m.metallic = nonNegative(*pbr, "metallicFactor", 1, 1);
      m.roughness = nonNegative(*pbr, "roughnessFactor", 1, 1);
    }
    m.normalTexture = textureRef(o, "normalTexture", *doc);
    if (o.has("normalTexture"))
      m.normalScale = float(o.object("normalTexture").get<double>("scale", 1.0));
    textureRef(o, "occlusionTexture", *doc);  // ambient occlusion: not used by a ray tracer
    m.alphaMode = o.get<std::string>("alphaMode", "OPAQUE");
    if (m.alphaMode != "OPAQUE" && m.alphaMode != "MASK" && m.alphaMode != "BLEND")
      throw SceneError(o.where("alphaMode"),
                       "must be OPAQUE, MASK or BLEND (got '" + m.alphaMode + "')");
    m.alphaCutoff = nonNegative(o, "alphaCutoff", 0.5, kInfinity);
    m.emissiveTexture = textureRef(o, "emissiveTexture", *doc);
    if (o.has("emissiveFactor")) {
      auto f = o.numbers<3>("emissiveFactor");
      for (size_t i = 0; i < 3; ++i)
        if (f[i] < 0 || f[i] > 1)
          throw SceneError(o.where("emissiveFactor").child(i), "must be between 0 and 1");
      m.emissiveFactor = {float(f[0]), float(f[1]), float(f[2])};
    }
    m.doubleSided = o.get<bool>("doubleSided", false);
    if (JsonReader* ext = o.optionalObject("extensions")) {
      if (JsonReader* es = ext->optionalObject("KHR_materials_emissive_strength"))
        m.emissiveStrength = nonNegative(*es, "emissiveStrength", 1, kInfinity);
      if (ext->has("KHR_materials_unlit")) m.unlit = true;
      if (JsonReader* t = ext->optionalObject("KHR_materials_transmission")) {
        m.transmission = nonNegative(*t, "transmissionFactor", 0, 1);
        m.transmissionTexture = textureRef(*t, "transmissionTexture", *doc);
      }
      if (JsonReader* i = ext->optionalObject("KHR_materials_ior")) {
        double ior = i->get<double>("ior", 1.5);
        // The extension allows 0 as "infinite" only for historical exporters; glint needs a
        // real index.
        if (!(ior >= 1)) throw SceneError(i->where("ior"), "must be >= 1");
        m.ior = float(ior);
      }
      readMaterialLayers(*ext, *doc, &m);
    }
    const Material::LayerTextures& lt = m.layerTextures;
    for (const TextureRef* r : std::initializer_list<const TextureRef*>{
             &m.baseColorTexture, &m.emissiveTexture, &m.metallicRoughnessTexture, &m.normalTexture,
             &m.transmissionTexture, &lt.specular, &lt.specularColor, &lt.clearcoat,
             &lt.clearcoatRoughness, &lt.clearcoatNormal, &lt.sheenColor, &lt.sheenRoughness,
             &lt.diffuseTransmission, &lt.diffuseTransmissionColor, &lt.iridescence,
             &lt.iridescenceThickness, &lt.anisotropy})
      if (r->index >= 0 && r->texCoord > 1)
        doc->warnings.push_back(r->where.child("texCoord").str() + ": texCoord " +
                                std::to_string(r->texCoord) +
                                " is not supported (glint reads TEXCOORD_0 and TEXCOORD_1); "
                                "TEXCOORD_0 is used instead");
    doc->materials.push_back(m);
  }
}

}  // namespace glint::gltf
