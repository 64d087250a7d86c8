// glint — glTF JSON → validated structs (the loader's first pass).
#include "scenes/gltf_document.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scenes/json_util.h"

namespace glint::gltf {

using nlohmann::json;

namespace {

// ---------------------------------------------------------------------------------------------
// Typed field access: every failure names the pointer of the bad value
// ---------------------------------------------------------------------------------------------

// A JSON object with its location. Reading a key checks its type; unknown keys are ignored.
class Object {
 public:
  Object(const json& value, SourceLocation where) : value_(value), where_(std::move(where)) {
    if (!value_.is_object())
      throw SceneError(where_, "expected an object, got " + jsonTypeName(value_));
  }

  const SourceLocation& where() const { return where_; }
  SourceLocation at(const std::string& key) const { return where_.child(key); }
  bool has(const std::string& key) const { return value_.contains(key); }
  const json& raw(const std::string& key) const { return value_.at(key); }
  // The object's keys, in the file's order.
  std::vector<std::string> keys() const {
    std::vector<std::string> k;
    for (auto it = value_.begin(); it != value_.end(); ++it) k.push_back(it.key());
    return k;
  }

  void require(const std::string& key) const {
    if (!has(key)) throw SceneError(where_, "missing required property '" + key + "'");
  }

  Object object(const std::string& key) const { return Object(raw(key), at(key)); }

  // A non-negative integer (an integral JSON number such as 3.0 is accepted too).
  size_t size(const std::string& key, size_t fallback) const {
    if (!has(key)) return fallback;
    return sizeValue(raw(key), at(key));
  }
  size_t requiredSize(const std::string& key) const {
    require(key);
    return sizeValue(raw(key), at(key));
  }

  // An index into an array of `count` items called `what` ("accessor"), or -1 when absent.
  int index(const std::string& key, size_t count, const char* what, bool required = false) const {
    if (required) require(key);
    if (!has(key)) return -1;
    return indexValue(raw(key), at(key), count, what);
  }

  double number(const std::string& key, double fallback) const {
    if (!has(key)) return fallback;
    return numberValue(raw(key), at(key));
  }
  double requiredNumber(const std::string& key) const {
    require(key);
    return numberValue(raw(key), at(key));
  }

  std::string string(const std::string& key, const std::string& fallback = "") const {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    if (!v.is_string()) throw SceneError(at(key), "expected a string, got " + jsonTypeName(v));
    return v.get<std::string>();
  }

  bool boolean(const std::string& key, bool fallback) const {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    if (!v.is_boolean()) throw SceneError(at(key), "expected a boolean, got " + jsonTypeName(v));
    return v.get<bool>();
  }

  // An array of exactly `n` finite numbers.
  std::vector<double> numbers(const std::string& key, size_t n) const {
    const json& v = raw(key);
    SourceLocation loc = at(key);
    if (!v.is_array() || v.size() != n)
      throw SceneError(loc, "expected an array of " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (size_t i = 0; i < n; ++i) out.push_back(numberValue(v[i], loc.child(i)));
    return out;
  }

  // The elements of an array property (empty when absent), each with its location.
  std::vector<std::pair<const json*, SourceLocation>> array(const std::string& key) const {
    std::vector<std::pair<const json*, SourceLocation>> out;
    if (!has(key)) return out;
    const json& v = raw(key);
    if (!v.is_array()) throw SceneError(at(key), "expected an array, got " + jsonTypeName(v));
    for (size_t i = 0; i < v.size(); ++i) out.emplace_back(&v[i], at(key).child(i));
    return out;
  }

  static size_t sizeValue(const json& v, const SourceLocation& loc) {
    if (v.is_number_unsigned()) return v.get<size_t>();
    if (v.is_number_integer())
      throw SceneError(loc, "must not be negative (got " + std::to_string(v.get<int64_t>()) + ")");
    if (v.is_number_float()) {
      double d = v.get<double>();
      if (d >= 0 && d == std::floor(d) && d < 9e15) return size_t(d);
    }
    throw SceneError(loc, "expected a non-negative integer, got " + describe(v));
  }

  static int indexValue(const json& v, const SourceLocation& loc, size_t count, const char* what) {
    size_t i = sizeValue(v, loc);
    if (i >= count)
      throw SceneError(loc, std::string(what) + " " + std::to_string(i) + " does not exist (" +
                                std::to_string(count) + " " + what + (count == 1 ? "" : "s") +
                                " in the file)");
    return int(i);
  }

  static double numberValue(const json& v, const SourceLocation& loc) {
    if (!v.is_number()) throw SceneError(loc, "expected a number, got " + jsonTypeName(v));
    double d = v.get<double>();
    // Values beyond float range would become infinities downstream.
    if (!std::isfinite(float(d))) throw SceneError(loc, "number out of range");
    return d;
  }

  static std::string describe(const json& v) {
    if (v.is_number()) return "number " + v.dump();
    if (v.is_string()) return "string " + v.dump();
    return jsonTypeName(v);
  }

 private:
  const json& value_;
  SourceLocation where_;
};

// The elements of a top-level array that must all be objects.
std::vector<Object> objects(const Object& parent, const std::string& key) {
  std::vector<Object> out;
  for (auto& [value, loc] : parent.array(key)) out.emplace_back(*value, loc);
  return out;
}

std::string plural(size_t n, const std::string& word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

// ---------------------------------------------------------------------------------------------
// Buffers, buffer views, accessors
// ---------------------------------------------------------------------------------------------

int componentsOf(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4" || type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  return 0;
}

bool isComponentType(int t) {
  return t == kByte || t == kUnsignedByte || t == kShort || t == kUnsignedShort ||
         t == kUnsignedInt || t == kFloat;
}

void readBuffers(const Object& root, Document* doc) {
  for (const Object& o : objects(root, "buffers")) {
    Buffer b;
    b.where = o.where();
    b.byteLength = o.requiredSize("byteLength");
    b.uri = o.string("uri");
    if (o.has("uri") && b.uri.empty()) throw SceneError(o.at("uri"), "empty URI");
    if (o.has("extensions")) {
      Object ext = o.object("extensions");
      if (ext.has("EXT_meshopt_compression"))
        b.fallback = ext.object("EXT_meshopt_compression").boolean("fallback", false);
    }
    doc->buffers.push_back(b);
  }
}

// EXT_meshopt_compression on buffer view `v`: where the compressed bytes are and what they
// decode to, checked against the extension's rules (strides per mode and filter, sizes).
BufferView::Meshopt readMeshopt(const Object& o, const BufferView& v, const Document& doc) {
  BufferView::Meshopt m;
  m.where = o.where();
  m.buffer = o.index("buffer", doc.buffers.size(), "buffer", true);
  m.byteOffset = o.size("byteOffset", 0);
  m.byteLength = o.requiredSize("byteLength");
  m.byteStride = o.requiredSize("byteStride");
  m.count = o.requiredSize("count");
  o.require("mode");
  m.mode = o.string("mode");
  m.filter = o.string("filter", "NONE");
  const size_t source = doc.buffers[size_t(m.buffer)].byteLength;
  if (m.byteOffset > source || m.byteLength > source - m.byteOffset)
    throw SceneError(m.where, "compressed bytes " + std::to_string(m.byteOffset) + ".." +
                                  std::to_string(m.byteOffset + m.byteLength) +
                                  " lie outside buffer " + std::to_string(m.buffer) + " (" +
                                  plural(source, "byte") + ")");
  const size_t s = m.byteStride;
  if (m.mode == "ATTRIBUTES") {
    if (s == 0 || s % 4 || s > 256)
      throw SceneError(o.at("byteStride"), "must be a multiple of 4 up to 256 for ATTRIBUTES");
  } else if (m.mode == "TRIANGLES" || m.mode == "INDICES") {
    if (s != 2 && s != 4) throw SceneError(o.at("byteStride"), "must be 2 or 4 for " + m.mode);
    if (m.mode == "TRIANGLES" && m.count % 3)
      throw SceneError(o.at("count"), "must be a multiple of 3 for TRIANGLES");
  } else {
    throw SceneError(o.at("mode"),
                     "must be ATTRIBUTES, TRIANGLES or INDICES (got '" + m.mode + "')");
  }
  if (m.filter != "NONE") {
    if (m.mode != "ATTRIBUTES") throw SceneError(o.at("filter"), "a filter needs mode ATTRIBUTES");
    const bool ok = m.filter == "OCTAHEDRAL"    ? s == 4 || s == 8
                    : m.filter == "QUATERNION"  ? s == 8
                    : m.filter == "EXPONENTIAL" ? s % 4 == 0
                                                : false;
    if (!ok)
      throw SceneError(o.at("filter"), "filter '" + m.filter + "' with byteStride " +
                                           std::to_string(s) +
                                           " (OCTAHEDRAL: 4 or 8, QUATERNION: 8, EXPONENTIAL: "
                                           "a multiple of 4)");
  }
  constexpr size_t kLimit = size_t(1) << 40;
  if (m.count > kLimit / std::max<size_t>(s, 1) || m.count * s > v.byteLength)
    throw SceneError(o.at("count"), std::to_string(m.count) + " elements of " + plural(s, "byte") +
                                        " do not fit the view's byteLength " +
                                        std::to_string(v.byteLength));
  return m;
}

void readBufferViews(const Object& root, Document* doc) {
  for (const Object& o : objects(root, "bufferViews")) {
    BufferView v;
    v.where = o.where();
    v.buffer = o.index("buffer", doc->buffers.size(), "buffer", true);
    v.byteOffset = o.size("byteOffset", 0);
    v.byteLength = o.requiredSize("byteLength");
    v.byteStride = o.size("byteStride", 0);
    if (o.has("byteStride") && (v.byteStride < 4 || v.byteStride > 252 || v.byteStride % 4))
      throw SceneError(o.at("byteStride"), "must be a multiple of 4 between 4 and 252 (got " +
                                               std::to_string(v.byteStride) + ")");
    size_t bufferLength = doc->buffers[size_t(v.buffer)].byteLength;
    if (v.byteOffset > bufferLength || v.byteLength > bufferLength - v.byteOffset)
      throw SceneError(v.where, "bytes " + std::to_string(v.byteOffset) + ".." +
                                    std::to_string(v.byteOffset + v.byteLength) +
                                    " lie outside buffer " + std::to_string(v.buffer) + " (" +
                                    plural(bufferLength, "byte") + ")");
    if (o.has("extensions") && o.object("extensions").has("EXT_meshopt_compression"))
      v.meshopt = readMeshopt(o.object("extensions").object("EXT_meshopt_compression"), v, *doc);
    doc->bufferViews.push_back(v);
  }
}

// Checks that `count` elements of `elemSize` bytes, `stride` apart, starting at `offset`, fit
// in buffer view `view`; `what` names the data in the message.
void checkRange(const Document& doc, int view, size_t offset, size_t stride, size_t count,
                size_t elemSize, const SourceLocation& where, const std::string& what) {
  const BufferView& v = doc.bufferViews[size_t(view)];
  // Sizes come from the file: guard the arithmetic against overflow before comparing.
  constexpr size_t kLimit = size_t(1) << 48;
  if (count == 0 || stride > kLimit || count > kLimit / std::max<size_t>(stride, 1)) {
    if (count == 0) return;
    throw SceneError(where, what + " is implausibly large");
  }
  size_t end = offset + stride * (count - 1) + elemSize;
  if (end > v.byteLength)
    throw SceneError(where, what + " needs bytes " + std::to_string(offset) + ".." +
                                std::to_string(end) + " but bufferView " + std::to_string(view) +
                                " has only " + plural(v.byteLength, "byte"));
}

void readAccessors(const Object& root, Document* doc) {
  size_t index = 0;
  for (const Object& o : objects(root, "accessors")) {
    Accessor a;
    a.where = o.where();
    a.bufferView = o.index("bufferView", doc->bufferViews.size(), "bufferView");
    a.byteOffset = o.size("byteOffset", 0);
    o.require("componentType");
    a.componentType = int(std::min<size_t>(
        Object::sizeValue(o.raw("componentType"), o.at("componentType")), 1u << 30));
    if (!isComponentType(a.componentType))
      throw SceneError(o.at("componentType"),
                       "unknown componentType " + std::to_string(a.componentType));
    a.normalized = o.boolean("normalized", false);
    a.count = o.requiredSize("count");
    if (a.count == 0) throw SceneError(o.at("count"), "must be at least 1");
    // Without a bufferView the count is not backed by data; cap it so that a typo cannot ask
    // for gigabytes of zeros.
    constexpr size_t kMaxVirtualCount = size_t(1) << 24;
    if (a.bufferView < 0 && a.count > kMaxVirtualCount)
      throw SceneError(o.at("count"), "count " + std::to_string(a.count) +
                                          " without a bufferView exceeds glint's limit of " +
                                          std::to_string(kMaxVirtualCount));
    o.require("type");
    a.type = o.string("type");
    a.components = componentsOf(a.type);
    if (a.components == 0) throw SceneError(o.at("type"), "unknown accessor type '" + a.type + "'");
    if (o.has("bufferView") && o.has("byteOffset") && a.byteOffset % componentSize(a.componentType))
      throw SceneError(o.at("byteOffset"), "must be a multiple of the component size (" +
                                               std::to_string(componentSize(a.componentType)) +
                                               ")");
    if (a.bufferView >= 0) {
      const BufferView& v = doc->bufferViews[size_t(a.bufferView)];
      size_t elem = elementSize(a);
      size_t stride = v.byteStride ? v.byteStride : elem;
      if (v.byteStride && v.byteStride < elem)
        throw SceneError(a.where, "byteStride " + std::to_string(v.byteStride) + " of bufferView " +
                                      std::to_string(a.bufferView) + " is smaller than one " +
                                      a.type + " element (" + plural(elem, "byte") + ")");
      checkRange(*doc, a.bufferView, a.byteOffset, stride, a.count, elem, a.where,
                 "accessor " + std::to_string(index) + " (" + std::to_string(a.count) + " " +
                     a.type + " elements of " + componentTypeName(a.componentType) + ")");
    }
    if (o.has("sparse")) {
      Object so = o.object("sparse");
      Sparse s;
      s.where = so.where();
      s.count = so.requiredSize("count");
      if (s.count == 0 || s.count > a.count)
        throw SceneError(so.at("count"), "must be between 1 and the accessor's count (" +
                                             std::to_string(a.count) + ")");
      so.require("indices");
      Object io = so.object("indices");
      s.indicesView = io.index("bufferView", doc->bufferViews.size(), "bufferView", true);
      s.indicesOffset = io.size("byteOffset", 0);
      io.require("componentType");
      s.indicesComponentType = int(std::min<size_t>(
          Object::sizeValue(io.raw("componentType"), io.at("componentType")), 1u << 30));
      if (s.indicesComponentType != kUnsignedByte && s.indicesComponentType != kUnsignedShort &&
          s.indicesComponentType != kUnsignedInt)
        throw SceneError(io.at("componentType"),
                         "sparse indices must be UNSIGNED_BYTE, "
                         "UNSIGNED_SHORT or UNSIGNED_INT");
      size_t indexSize = componentSize(s.indicesComponentType);
      checkRange(*doc, s.indicesView, s.indicesOffset, indexSize, s.count, indexSize, io.where(),
                 "sparse indices");
      so.require("values");
      Object vo = so.object("values");
      s.valuesView = vo.index("bufferView", doc->bufferViews.size(), "bufferView", true);
      s.valuesOffset = vo.size("byteOffset", 0);
      size_t elem = elementSize(a);
      checkRange(*doc, s.valuesView, s.valuesOffset, elem, s.count, elem, vo.where(),
                 "sparse values");
      a.sparse = s;
    }
    doc->accessors.push_back(a);
    ++index;
  }
}

// ---------------------------------------------------------------------------------------------
// Images, samplers, textures, materials
// ---------------------------------------------------------------------------------------------

void readImages(const Object& root, Document* doc) {
  for (const Object& o : objects(root, "images")) {
    Image im;
    im.where = o.where();
    im.uri = o.string("uri");
    im.bufferView = o.index("bufferView", doc->bufferViews.size(), "bufferView");
    if (o.has("uri") && im.uri.empty()) throw SceneError(o.at("uri"), "empty URI");
    if (im.uri.empty() == (im.bufferView < 0))
      throw SceneError(im.where, "needs exactly one of 'uri' and 'bufferView'");
    if (im.bufferView >= 0) o.string("mimeType");  // type check only; the bytes say what they are
    doc->images.push_back(im);
  }
}

WrapMode wrapMode(const Object& o, const std::string& key) {
  size_t v = o.size(key, 10497);
  switch (v) {
    case 10497:
      return WrapMode::Repeat;
    case 33071:
      return WrapMode::ClampToEdge;
    case 33648:
      return WrapMode::MirroredRepeat;
    default:
      throw SceneError(o.at(key), "unknown wrap mode " + std::to_string(v));
  }
}

void readSamplers(const Object& root, Document* doc) {
  for (const Object& o : objects(root, "samplers")) {
    Sampler s;
    size_t mag = o.size("magFilter", 9729);
    if (mag != 9728 && mag != 9729)
      throw SceneError(o.at("magFilter"), "unknown magFilter " + std::to_string(mag));
    s.magFilter = int(mag);
    o.size("minFilter", 0);
    s.wrapS = wrapMode(o, "wrapS");
    s.wrapT = wrapMode(o, "wrapT");
    doc->samplers.push_back(s);
  }
}

void readTextures(const Object& root, Document* doc) {
  for (const Object& o : objects(root, "textures")) {
    Texture t;
    t.where = o.where();
    t.sampler = o.index("sampler", doc->samplers.size(), "sampler");
    t.source = o.index("source", doc->images.size(), "image");
    if (o.has("extensions")) {
      Object ext = o.object("extensions");
      // EXT_texture_webp: the WebP image (OpenImageIO decodes it) wins over the fallback.
      if (ext.has("EXT_texture_webp"))
        t.source =
            ext.object("EXT_texture_webp").index("source", doc->images.size(), "image", true);
      if (t.source < 0 && ext.has("KHR_texture_basisu"))
        throw SceneError(ext.at("KHR_texture_basisu"),
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

TextureRef textureRef(const Object& parent, const std::string& key, const Document& doc) {
  TextureRef r;
  if (!parent.has(key)) return r;
  Object o = parent.object(key);
  r.where = o.where();
  r.index = o.index("index", doc.textures.size(), "texture", true);
  r.texCoord = int(std::min<size_t>(o.size("texCoord", 0), 1000));
  if (o.has("extensions")) {
    Object ext = o.object("extensions");
    if (ext.has("KHR_texture_transform")) {
      Object t = ext.object("KHR_texture_transform");
      r.transformed = true;
      if (t.has("offset")) {
        auto v = t.numbers("offset", 2);
        r.offset = {float(v[0]), float(v[1])};
      }
      if (t.has("scale")) {
        auto v = t.numbers("scale", 2);
        r.scale = {float(v[0]), float(v[1])};
      }
      r.rotation = float(t.number("rotation", 0));
      for (float f : {r.offset.x, r.offset.y, r.scale.x, r.scale.y, r.rotation})
        if (!std::isfinite(f))
          throw SceneError(t.where(), "offset, rotation and scale must be finite in float");
      if (t.has("texCoord")) r.texCoord = int(std::min<size_t>(t.size("texCoord", 0), 1000));
    }
  }
  return r;
}

float nonNegative(const Object& o, const std::string& key, double fallback, double upper) {
  double v = o.number(key, fallback);
  if (v < 0) throw SceneError(o.at(key), "must not be negative");
  if (v > upper) throw SceneError(o.at(key), "must be between 0 and 1");
  return float(v);
}

// A colour factor at `key`: three numbers, each >= 0 and, with `upToOne`, <= 1.
Rgb colorFactor(const Object& o, const std::string& key, Rgb fallback, bool upToOne) {
  if (!o.has(key)) return fallback;
  auto f = o.numbers(key, 3);
  for (int i = 0; i < 3; ++i) {
    if (f[size_t(i)] < 0) throw SceneError(o.at(key).child(size_t(i)), "must not be negative");
    if (upToOne && f[size_t(i)] > 1)
      throw SceneError(o.at(key).child(size_t(i)), "must be between 0 and 1");
  }
  return {float(f[0]), float(f[1]), float(f[2])};
}

// The KHR_materials_* extensions beyond the metallic-roughness core (pbr.h has the model).
void readMaterialLayers(const Object& ext, const Document& doc, Material* m) {
  MaterialLayersDesc& l = m->layers;
  Material::LayerTextures& t = m->layerTextures;
  if (ext.has("KHR_materials_specular")) {
    Object o = ext.object("KHR_materials_specular");
    l.specular = nonNegative(o, "specularFactor", 1, 1);
    t.specular = textureRef(o, "specularTexture", doc);
    l.specularColor = colorFactor(o, "specularColorFactor", {1, 1, 1}, false);
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(l.specularColor[c]))
        throw SceneError(o.at("specularColorFactor").child(size_t(c)), "must be finite");
    t.specularColor = textureRef(o, "specularColorTexture", doc);
  }
  if (ext.has("KHR_materials_clearcoat")) {
    Object o = ext.object("KHR_materials_clearcoat");
    l.clearcoat = nonNegative(o, "clearcoatFactor", 0, 1);
    t.clearcoat = textureRef(o, "clearcoatTexture", doc);
    l.clearcoatRoughness = nonNegative(o, "clearcoatRoughnessFactor", 0, 1);
    t.clearcoatRoughness = textureRef(o, "clearcoatRoughnessTexture", doc);
    t.clearcoatNormal = textureRef(o, "clearcoatNormalTexture", doc);
    if (o.has("clearcoatNormalTexture")) {
      Object n = o.object("clearcoatNormalTexture");
      const double scale = n.number("scale", 1);
      if (!std::isfinite(scale)) throw SceneError(n.at("scale"), "must be finite");
      l.clearcoatNormalScale = float(scale);
    }
  }
  if (ext.has("KHR_materials_sheen")) {
    Object o = ext.object("KHR_materials_sheen");
    l.sheenColor = colorFactor(o, "sheenColorFactor", {0, 0, 0}, true);
    t.sheenColor = textureRef(o, "sheenColorTexture", doc);
    l.sheenRoughness = nonNegative(o, "sheenRoughnessFactor", 0, 1);
    t.sheenRoughness = textureRef(o, "sheenRoughnessTexture", doc);
  }
  if (ext.has("KHR_materials_diffuse_transmission")) {
    Object o = ext.object("KHR_materials_diffuse_transmission");
    l.diffuseTransmission = nonNegative(o, "diffuseTransmissionFactor", 0, 1);
    t.diffuseTransmission = textureRef(o, "diffuseTransmissionTexture", doc);
    l.diffuseTransmissionColor = colorFactor(o, "diffuseTransmissionColorFactor", {1, 1, 1}, true);
    t.diffuseTransmissionColor = textureRef(o, "diffuseTransmissionColorTexture", doc);
  }
  if (ext.has("KHR_materials_volume")) {
    Object o = ext.object("KHR_materials_volume");
    l.thickness = nonNegative(o, "thicknessFactor", 0, kInfinity);
    // thicknessTexture serves rasterisers, which cannot trace the inside; a ray tracer measures
    // the real distance. It is validated, not read.
    textureRef(o, "thicknessTexture", doc);
    const double distance = o.number("attenuationDistance", kInfinity);
    if (!(distance > 0)) throw SceneError(o.at("attenuationDistance"), "must be > 0");
    l.attenuationDistance = float(distance);
    l.attenuationColor = colorFactor(o, "attenuationColor", {1, 1, 1}, true);
  }
  if (ext.has("KHR_materials_iridescence")) {
    Object o = ext.object("KHR_materials_iridescence");
    l.iridescence = nonNegative(o, "iridescenceFactor", 0, 1);
    t.iridescence = textureRef(o, "iridescenceTexture", doc);
    const double ior = o.number("iridescenceIor", 1.3);
    if (!(ior >= 1) || !std::isfinite(ior))
      throw SceneError(o.at("iridescenceIor"), "must be >= 1");
    l.iridescenceIor = float(ior);
    l.iridescenceThicknessMin = nonNegative(o, "iridescenceThicknessMinimum", 100, 1e6);
    l.iridescenceThicknessMax = nonNegative(o, "iridescenceThicknessMaximum", 400, 1e6);
    t.iridescenceThickness = textureRef(o, "iridescenceThicknessTexture", doc);
  }
  if (ext.has("KHR_materials_anisotropy")) {
    Object o = ext.object("KHR_materials_anisotropy");
    l.anisotropy = nonNegative(o, "anisotropyStrength", 0, 1);
    const double rotation = o.number("anisotropyRotation", 0);
    if (!std::isfinite(rotation)) throw SceneError(o.at("anisotropyRotation"), "must be finite");
    l.anisotropyRotation = float(rotation);
    t.anisotropy = textureRef(o, "anisotropyTexture", doc);
  }
  if (ext.has("KHR_materials_dispersion")) {
    Object o = ext.object("KHR_materials_dispersion");
    l.dispersion = nonNegative(o, "dispersion", 0, 1e3);
  }
}

void readMaterials(const Object& root, Document* doc) {
  size_t index = 0;
  for (const Object& o : objects(root, "materials")) {
    Material m;
    m.where = o.where();
    m.name = o.string("name", "material " + std::to_string(index++));
    if (o.has("pbrMetallicRoughness")) {
      Object pbr = o.object("pbrMetallicRoughness");
      if (pbr.has("baseColorFactor")) {
        auto f = pbr.numbers("baseColorFactor", 4);
        for (int i = 0; i < 4; ++i)
          if (f[size_t(i)] < 0 || f[size_t(i)] > 1)
            throw SceneError(pbr.at("baseColorFactor").child(size_t(i)), "must be between 0 and 1");
        m.baseColorFactor = {float(f[0]), float(f[1]), float(f[2]), float(f[3])};
      }
      m.baseColorTexture = textureRef(pbr, "baseColorTexture", *doc);
      m.metallicRoughnessTexture = textureRef(pbr, "metallicRoughnessTexture", *doc);
      m.metallic = nonNegative(pbr, "metallicFactor", 1, 1);
      m.roughness = nonNegative(pbr, "roughnessFactor", 1, 1);
    }
    m.normalTexture = textureRef(o, "normalTexture", *doc);
    if (o.has("normalTexture")) m.normalScale = float(o.object("normalTexture").number("scale", 1));
    textureRef(o, "occlusionTexture", *doc);  // ambient occlusion: not used by a ray tracer
    m.alphaMode = o.string("alphaMode", "OPAQUE");
    if (m.alphaMode != "OPAQUE" && m.alphaMode != "MASK" && m.alphaMode != "BLEND")
      throw SceneError(o.at("alphaMode"),
                       "must be OPAQUE, MASK or BLEND (got '" + m.alphaMode + "')");
    m.alphaCutoff = nonNegative(o, "alphaCutoff", 0.5, kInfinity);
    m.emissiveTexture = textureRef(o, "emissiveTexture", *doc);
    if (o.has("emissiveFactor")) {
      auto f = o.numbers("emissiveFactor", 3);
      for (int i = 0; i < 3; ++i)
        if (f[size_t(i)] < 0 || f[size_t(i)] > 1)
          throw SceneError(o.at("emissiveFactor").child(size_t(i)), "must be between 0 and 1");
      m.emissiveFactor = {float(f[0]), float(f[1]), float(f[2])};
    }
    m.doubleSided = o.boolean("doubleSided", false);
    if (o.has("extensions")) {
      Object ext = o.object("extensions");
      if (ext.has("KHR_materials_emissive_strength"))
        m.emissiveStrength = nonNegative(ext.object("KHR_materials_emissive_strength"),
                                         "emissiveStrength", 1, kInfinity);
      if (ext.has("KHR_materials_unlit")) m.unlit = true;
      if (ext.has("KHR_materials_transmission")) {
        Object t = ext.object("KHR_materials_transmission");
        m.transmission = nonNegative(t, "transmissionFactor", 0, 1);
        m.transmissionTexture = textureRef(t, "transmissionTexture", *doc);
      }
      if (ext.has("KHR_materials_ior")) {
        Object i = ext.object("KHR_materials_ior");
        double ior = i.number("ior", 1.5);
        // The extension allows 0 as "infinite" only for historical exporters; glint needs a
        // real index.
        if (!(ior >= 1)) throw SceneError(i.at("ior"), "must be >= 1");
        m.ior = float(ior);
      }
      readMaterialLayers(ext, *doc, &m);
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

// ---------------------------------------------------------------------------------------------
// Meshes
// ---------------------------------------------------------------------------------------------

// Morph weights at `key` (absent: empty): finite numbers, one per morph target. `owner` says
// whose target count it is, for the message.
std::vector<float> morphWeights(const Object& o, const std::string& key, size_t targets,
                                const std::string& owner) {
  std::vector<float> w;
  if (!o.has(key)) return w;
  const auto items = o.array(key);
  if (items.size() != targets)
    throw SceneError(o.at(key), "has " + plural(items.size(), "weight") + " but " + owner + " " +
                                    plural(targets, "morph target"));
  for (auto& [value, loc] : items) w.push_back(float(Object::numberValue(*value, loc)));
  return w;
}

// KHR_materials_variants: the variant names (primitives map them to materials).
void readVariants(const Object& root, Document* doc) {
  if (!root.has("extensions")) return;
  Object ext = root.object("extensions");
  if (!ext.has("KHR_materials_variants")) return;
  Object kv = ext.object("KHR_materials_variants");
  kv.require("variants");
  for (const Object& v : objects(kv, "variants")) {
    v.require("name");
    const std::string name = v.string("name");
    if (std::find(doc->variants.begin(), doc->variants.end(), name) != doc->variants.end())
      throw SceneError(v.at("name"), "variant '" + name + "' is named twice");
    doc->variants.push_back(name);
  }
}

void readMeshes(const Object& root, Document* doc) {
  size_t meshIndex = 0;
  for (const Object& o : objects(root, "meshes")) {
    Mesh mesh;
    mesh.where = o.where();
    mesh.name = o.string("name", "mesh " + std::to_string(meshIndex++));
    o.require("primitives");
    for (const Object& po : objects(o, "primitives")) {
      Primitive p;
      p.where = po.where();
      po.require("attributes");
      Object attributes = po.object("attributes");
      size_t accessors = doc->accessors.size();
      p.position = attributes.index("POSITION", accessors, "accessor");
      p.normal = attributes.index("NORMAL", accessors, "accessor");
      p.tangent = attributes.index("TANGENT", accessors, "accessor");
      p.texcoord0 = attributes.index("TEXCOORD_0", accessors, "accessor");
      p.texcoord1 = attributes.index("TEXCOORD_1", accessors, "accessor");
      p.color0 = attributes.index("COLOR_0", accessors, "accessor");
      p.joints0 = attributes.index("JOINTS_0", accessors, "accessor");
      p.weights0 = attributes.index("WEIGHTS_0", accessors, "accessor");
      if ((p.joints0 >= 0) != (p.weights0 >= 0))
        throw SceneError(attributes.where(), p.joints0 >= 0 ? "JOINTS_0 without WEIGHTS_0"
                                                            : "WEIGHTS_0 without JOINTS_0");
      p.moreJoints = attributes.has("JOINTS_1") || attributes.has("WEIGHTS_1");
      for (const Object& to : objects(po, "targets")) {
        MorphTarget t;
        t.where = to.where();
        t.position = to.index("POSITION", accessors, "accessor");
        t.normal = to.index("NORMAL", accessors, "accessor");
        t.tangent = to.index("TANGENT", accessors, "accessor");
        p.targets.push_back(t);
      }
      // glTF: every primitive of a mesh has the same number of morph targets.
      if (!mesh.primitives.empty() && p.targets.size() != mesh.primitives[0].targets.size())
        throw SceneError(po.has("targets") ? po.at("targets") : po.where(),
                         "has " + plural(p.targets.size(), "morph target") +
                             " but primitive 0 has " +
                             std::to_string(mesh.primitives[0].targets.size()) +
                             " (every primitive of a mesh must have the same number)");
      p.indices = po.index("indices", accessors, "accessor");
      p.material = po.index("material", doc->materials.size(), "material");
      if (po.has("extensions")) {
        Object pext = po.object("extensions");
        if (pext.has("KHR_materials_variants")) {
          Object kv = pext.object("KHR_materials_variants");
          kv.require("mappings");
          for (const Object& mo : objects(kv, "mappings")) {
            const int material = mo.index("material", doc->materials.size(), "material", true);
            mo.require("variants");
            std::vector<int> variants;
            for (auto& [value, loc] : mo.array("variants"))
              variants.push_back(Object::indexValue(*value, loc, doc->variants.size(), "variant"));
            if (variants.empty()) throw SceneError(mo.at("variants"), "must not be empty");
            p.variantMappings.emplace_back(material, std::move(variants));
          }
        }
        if (pext.has("KHR_draco_mesh_compression")) {
          Object dr = pext.object("KHR_draco_mesh_compression");
          Primitive::Draco d;
          d.where = dr.where();
          d.bufferView = dr.index("bufferView", doc->bufferViews.size(), "bufferView", true);
          dr.require("attributes");
          Object da = dr.object("attributes");
          for (const std::string& name : da.keys()) {
            if (!attributes.has(name))
              throw SceneError(da.at(name), "names attribute " + name +
                                                " that the primitive's attributes do not have");
            d.attributes.emplace_back(name, int(da.size(name, 0)));
          }
          if (p.indices < 0)
            throw SceneError(dr.where(), "a Draco-compressed primitive needs an indices accessor");
          p.draco = std::move(d);
        }
      }
      size_t mode = po.size("mode", kTriangles);
      if (mode > kTriangleFan)
        throw SceneError(po.at("mode"), "unknown mode " + std::to_string(mode));
      p.mode = int(mode);
      if (p.position < 0) throw SceneError(attributes.where(), "missing POSITION");
      mesh.primitives.push_back(p);
    }
    if (mesh.primitives.empty()) throw SceneError(o.at("primitives"), "must not be empty");
    mesh.targetCount = mesh.primitives[0].targets.size();
    mesh.weights = morphWeights(o, "weights", mesh.targetCount, "the mesh's primitives have");
    doc->meshes.push_back(mesh);
  }
}

// ---------------------------------------------------------------------------------------------
// Cameras and lights
// ---------------------------------------------------------------------------------------------

void readCameras(const Object& root, Document* doc) {
  for (const Object& o : objects(root, "cameras")) {
    CameraDesc c;
    c.where = o.where();
    c.name = o.string("name");
    o.require("type");
    std::string type = o.string("type");
    if (type == "perspective") {
      o.require("perspective");
      Object p = o.object("perspective");
      c.type = CameraType::Perspective;
      c.yfov = float(p.requiredNumber("yfov"));
      if (c.yfov <= 0 || c.yfov >= kPi) throw SceneError(p.at("yfov"), "must be between 0 and pi");
      c.aspectRatio = float(p.number("aspectRatio", 0));
      if (p.has("aspectRatio") && c.aspectRatio <= 0)
        throw SceneError(p.at("aspectRatio"), "must be greater than 0");
      c.znear = float(p.requiredNumber("znear"));
      if (c.znear <= 0) throw SceneError(p.at("znear"), "must be greater than 0");
      c.zfar = float(p.number("zfar", kInfinity));
      if (p.has("zfar") && c.zfar <= c.znear)
        throw SceneError(p.at("zfar"), "must be greater than znear");
    } else if (type == "orthographic") {
      o.require("orthographic");
      Object p = o.object("orthographic");
      c.type = CameraType::Orthographic;
      c.xmag = float(p.requiredNumber("xmag"));
      if (c.xmag == 0) throw SceneError(p.at("xmag"), "must not be zero");
      c.ymag = float(p.requiredNumber("ymag"));
      if (c.ymag == 0) throw SceneError(p.at("ymag"), "must not be zero");
      c.znear = float(p.requiredNumber("znear"));
      if (c.znear < 0) throw SceneError(p.at("znear"), "must not be negative");
      c.zfar = float(p.requiredNumber("zfar"));
      if (c.zfar <= c.znear) throw SceneError(p.at("zfar"), "must be greater than znear");
    } else {
      throw SceneError(o.at("type"), "unknown camera type '" + type +
                                         "' (expected 'perspective' or 'orthographic')");
    }
    doc->cameras.push_back(c);
  }
}

void readLights(const Object& root, Document* doc) {
  if (!root.has("extensions")) return;
  Object ext = root.object("extensions");
  if (!ext.has("KHR_lights_punctual")) return;
  Object punctual = ext.object("KHR_lights_punctual");
  for (const Object& o : objects(punctual, "lights")) {
    LightDesc l;
    l.where = o.where();
    l.name = o.string("name");
    o.require("type");
    std::string type = o.string("type");
    if (type == "point") {
      l.type = LightType::Point;
    } else if (type == "spot") {
      l.type = LightType::Spot;
    } else if (type == "directional") {
      l.type = LightType::Directional;
    } else {
      throw SceneError(o.at("type"), "unknown light type '" + type +
                                         "' (expected 'point', 'spot' or 'directional')");
    }
    if (o.has("color")) {
      auto c = o.numbers("color", 3);
      for (int i = 0; i < 3; ++i)
        if (c[size_t(i)] < 0)
          throw SceneError(o.at("color").child(size_t(i)), "must not be negative");
      l.color = {float(c[0]), float(c[1]), float(c[2])};
    }
    l.intensity = nonNegative(o, "intensity", 1, kInfinity);
    l.range = float(o.number("range", 0));
    if (o.has("range") && l.range <= 0) throw SceneError(o.at("range"), "must be greater than 0");
    if (l.type == LightType::Spot) {
      o.require("spot");
      Object s = o.object("spot");
      l.innerConeAngle = float(s.number("innerConeAngle", 0));
      l.outerConeAngle = float(s.number("outerConeAngle", kPi / 4));
      if (l.outerConeAngle <= 0 || l.outerConeAngle > kPi / 2)
        throw SceneError(s.at("outerConeAngle"), "must be in (0, pi/2]");
      if (l.innerConeAngle < 0 || l.innerConeAngle >= l.outerConeAngle)
        throw SceneError(s.at("innerConeAngle"), "must be at least 0 and less than outerConeAngle");
    }
    doc->lights.push_back(l);
  }
}

// ---------------------------------------------------------------------------------------------
// Nodes and scenes
// ---------------------------------------------------------------------------------------------

// Fills node->local and the rest values it is made of.
void nodeTransform(const Object& o, Node* node) {
  bool trs = o.has("translation") || o.has("rotation") || o.has("scale");
  if (o.has("matrix")) {
    if (trs) throw SceneError(o.where(), "has both 'matrix' and translation/rotation/scale");
    auto v = o.numbers("matrix", 16);
    float f[16];
    for (int i = 0; i < 16; ++i) f[i] = float(v[size_t(i)]);
    Mat4 m = Mat4::fromColumnMajor(f), inv;
    if (!invert(m, &inv)) throw SceneError(o.at("matrix"), "matrix is not invertible");
    node->hasMatrix = true;
    node->local = Transform(m, inv);
    return;
  }
  if (o.has("translation")) {
    auto t = o.numbers("translation", 3);
    node->translation = {float(t[0]), float(t[1]), float(t[2])};
  }
  if (o.has("rotation")) {
    auto q = o.numbers("rotation", 4);
    if (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] < 1e-12)
      throw SceneError(o.at("rotation"), "quaternion has zero length");
    node->rotation = normalize(Quaternion{float(q[0]), float(q[1]), float(q[2]), float(q[3])});
  }
  if (o.has("scale")) {
    auto s = o.numbers("scale", 3);
    if (s[0] == 0 || s[1] == 0 || s[2] == 0)
      throw SceneError(o.at("scale"), "a zero scale makes the node matrix not invertible");
    node->scale = {float(s[0]), float(s[1]), float(s[2])};
  }
  node->local = Transform::translate(node->translation) * toTransform(node->rotation) *
                Transform::scale(node->scale);
}

// EXT_mesh_gpu_instancing: TRANSLATION and SCALE as VEC3 of FLOAT, ROTATION as VEC4 of FLOAT
// or normalized BYTE/SHORT, all with one element per instance.
void readInstancing(const Object& o, const Document& doc, Node* node) {
  o.require("attributes");
  Object attributes = o.object("attributes");
  const size_t accessors = doc.accessors.size();
  node->instanceTranslation = attributes.index("TRANSLATION", accessors, "accessor");
  node->instanceRotation = attributes.index("ROTATION", accessors, "accessor");
  node->instanceScale = attributes.index("SCALE", accessors, "accessor");
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
      throw SceneError(attributes.at(name),
                       "accessor " + std::to_string(index) + " is " + a.type + " of " +
                           (a.normalized ? "normalized " : "") +
                           componentTypeName(a.componentType) + "; " + name + " must be " +
                           (rotation ? "VEC4 of FLOAT or normalized BYTE/SHORT" : "VEC3 of FLOAT"));
    if (!first && a.count != node->instanceCount)
      throw SceneError(attributes.at(name), "accessor " + std::to_string(index) + " has " +
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

void readNodes(const Object& root, Document* doc) {
  std::vector<Object> nodes = objects(root, "nodes");
  size_t n = nodes.size();
  for (const Object& o : nodes) {
    Node node;
    node.where = o.where();
    node.name = o.string("name");
    node.mesh = o.index("mesh", doc->meshes.size(), "mesh");
    node.camera = o.index("camera", doc->cameras.size(), "camera");
    if (o.has("extensions")) {
      Object ext = o.object("extensions");
      if (ext.has("KHR_lights_punctual"))
        node.light =
            ext.object("KHR_lights_punctual").index("light", doc->lights.size(), "light", true);
      if (ext.has("EXT_mesh_gpu_instancing"))
        readInstancing(ext.object("EXT_mesh_gpu_instancing"), *doc, &node);
    }
    for (auto& [value, loc] : o.array("children"))
      node.children.push_back(Object::indexValue(*value, loc, n, "node"));
    nodeTransform(o, &node);
    // Skins are read after the nodes (their joints are nodes): the index is checked there.
    if (o.has("skin")) {
      node.skin = int(std::min<size_t>(o.size("skin", 0), size_t(1) << 30));
      if (node.mesh < 0) throw SceneError(o.at("skin"), "a skin needs a mesh on the same node");
    }
    if (o.has("weights")) {
      if (node.mesh < 0)
        throw SceneError(o.at("weights"), "morph weights need a mesh on the same node");
      const Mesh& mesh = doc->meshes[size_t(node.mesh)];
      node.weights = morphWeights(o, "weights", mesh.targetCount,
                                  "mesh " + std::to_string(node.mesh) + " has");
    }
    doc->nodes.push_back(node);
  }

  // glTF node graphs are disjoint trees: one parent per node, no cycles.
  std::vector<int> parent(n, -1);
  for (size_t i = 0; i < n; ++i)
    for (size_t k = 0; k < doc->nodes[i].children.size(); ++k) {
      int c = doc->nodes[i].children[k];
      SourceLocation loc = doc->nodes[i].where.child("children").child(k);
      if (size_t(c) == i)
        throw SceneError(
            loc, "node " + std::to_string(c) + " is its own child (cycle in the node graph)");
      if (parent[size_t(c)] >= 0)
        throw SceneError(loc, "node " + std::to_string(c) + " already has parent node " +
                                  std::to_string(parent[size_t(c)]) +
                                  " (the node graph must be a set of trees)");
      parent[size_t(c)] = int(i);
    }
  // With one parent each, a cycle is a parent chain that comes back to where it started. Each
  // node's depth is found once, walking up until a root or a node whose depth is known, so a
  // long chain costs linear time; the loader recurses once per level, hence the depth limit.
  auto childEntry = [&](size_t node) {  // the pointer of `node` in its parent's children
    const Node& parentNode = doc->nodes[size_t(parent[node])];
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

  for (const Object& o : objects(root, "scenes")) {
    Scene s;
    s.where = o.where();
    for (auto& [value, loc] : o.array("nodes")) {
      int node = Object::indexValue(*value, loc, n, "node");
      if (parent[size_t(node)] >= 0)
        throw SceneError(loc, "node " + std::to_string(node) +
                                  " is not a root node (its parent is node " +
                                  std::to_string(parent[size_t(node)]) + ")");
      s.nodes.push_back(node);
    }
    doc->scenes.push_back(s);
  }
  doc->scene = root.index("scene", doc->scenes.size(), "scene");
}

// ---------------------------------------------------------------------------------------------
// Animations
// ---------------------------------------------------------------------------------------------

const char* pathName(AnimationPath path) {
  switch (path) {
    case AnimationPath::Translation:
      return "translation";
    case AnimationPath::Rotation:
      return "rotation";
    case AnimationPath::Scale:
      return "scale";
    case AnimationPath::Weights:
      return "weights";
  }
  return "translation";
}

bool isNormalizedInteger(const Accessor& a) {
  return a.normalized && a.componentType != kFloat && a.componentType != kUnsignedInt;
}

// The output accessor of `sampler` must suit `channel`'s path (glTF 2.0, "Animations"):
// translation and scale VEC3 of FLOAT, rotation VEC4 of FLOAT or normalized (UNSIGNED_)BYTE /
// (UNSIGNED_)SHORT, with one element per key (three for CUBICSPLINE: in-tangent, value,
// out-tangent).
void checkOutput(const Document& doc, const Animation& anim, const AnimationChannel& channel) {
  const AnimationSampler& sampler = anim.samplers[size_t(channel.sampler)];
  const Accessor& out = doc.accessors[size_t(sampler.output)];
  const Accessor& in = doc.accessors[size_t(sampler.input)];
  SourceLocation loc = sampler.where.child("output");
  std::string user =
      "the '" + std::string(pathName(channel.path)) + "' channel at " + channel.where.pointer;
  bool ok = true;
  std::string want;
  switch (channel.path) {
    case AnimationPath::Translation:
    case AnimationPath::Scale:
      ok = out.type == "VEC3" && out.componentType == kFloat;
      want = "VEC3 of FLOAT";
      break;
    case AnimationPath::Rotation:
      ok = out.type == "VEC4" && (out.componentType == kFloat || isNormalizedInteger(out));
      want = "VEC4 of FLOAT or of normalized BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT";
      break;
    case AnimationPath::Weights:
      ok = out.type == "SCALAR" && (out.componentType == kFloat || isNormalizedInteger(out));
      want = "SCALAR of FLOAT or of a normalized integer type";
      break;
  }
  if (!ok)
    throw SceneError(loc, "accessor " + std::to_string(sampler.output) + " is " + out.type +
                              " of " + (out.normalized ? "normalized " : "") +
                              componentTypeName(out.componentType) + "; " + user + " needs " +
                              want);
  size_t perKey = sampler.interpolation == Interpolation::CubicSpline ? 3 : 1;
  if (channel.path == AnimationPath::Weights) {  // one value per morph target and key
    if (channel.node < 0) return;
    const Node& node = doc.nodes[size_t(channel.node)];
    const size_t targets = node.mesh >= 0 ? doc.meshes[size_t(node.mesh)].targetCount : 0;
    if (targets == 0) return;  // nothing to drive: the loader warns and ignores it
    perKey *= targets;
    if (out.count != perKey * in.count)
      throw SceneError(
          loc, "accessor " + std::to_string(sampler.output) + " has " +
                   plural(out.count, "element") + "; " + user + " with " + plural(in.count, "key") +
                   " and " + plural(targets, "morph target") +
                   (sampler.interpolation == Interpolation::CubicSpline ? " (CUBICSPLINE)" : "") +
                   " needs " + std::to_string(perKey * in.count));
    return;
  }
  if (out.count != perKey * in.count)
    throw SceneError(loc, "accessor " + std::to_string(sampler.output) + " has " +
                              plural(out.count, "element") + "; " + user + " with " +
                              plural(in.count, "key") + (perKey == 3 ? " (CUBICSPLINE)" : "") +
                              " needs " + std::to_string(perKey * in.count));
}

void readSkins(const Object& root, Document* doc) {
  for (const Object& o : objects(root, "skins")) {
    Skin skin;
    skin.where = o.where();
    o.require("joints");
    for (auto& [value, loc] : o.array("joints"))
      skin.joints.push_back(Object::indexValue(*value, loc, doc->nodes.size(), "node"));
    if (skin.joints.empty()) throw SceneError(o.at("joints"), "must not be empty");
    skin.inverseBindMatrices = o.index("inverseBindMatrices", doc->accessors.size(), "accessor");
    if (skin.inverseBindMatrices >= 0) {
      const Accessor& a = doc->accessors[size_t(skin.inverseBindMatrices)];
      if (a.type != "MAT4" || a.componentType != kFloat)
        throw SceneError(o.at("inverseBindMatrices"),
                         "accessor " + std::to_string(skin.inverseBindMatrices) + " is " + a.type +
                             " of " + componentTypeName(a.componentType) +
                             "; inverse bind matrices must be MAT4 of FLOAT");
      if (a.count < skin.joints.size())
        throw SceneError(o.at("inverseBindMatrices"),
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

void readAnimations(const Object& root, Document* doc) {
  size_t index = 0;
  for (const Object& o : objects(root, "animations")) {
    Animation anim;
    anim.where = o.where();
    anim.name = o.string("name", "animation " + std::to_string(index++));
    o.require("samplers");
    for (const Object& so : objects(o, "samplers")) {
      AnimationSampler s;
      s.where = so.where();
      s.input = so.index("input", doc->accessors.size(), "accessor", true);
      s.output = so.index("output", doc->accessors.size(), "accessor", true);
      std::string interpolation = so.string("interpolation", "LINEAR");
      if (interpolation == "LINEAR")
        s.interpolation = Interpolation::Linear;
      else if (interpolation == "STEP")
        s.interpolation = Interpolation::Step;
      else if (interpolation == "CUBICSPLINE")
        s.interpolation = Interpolation::CubicSpline;
      else
        throw SceneError(so.at("interpolation"), "unknown interpolation '" + interpolation +
                                                     "' (expected LINEAR, STEP or CUBICSPLINE)");
      const Accessor& in = doc->accessors[size_t(s.input)];
      if (in.type != "SCALAR" || in.componentType != kFloat)
        throw SceneError(so.at("input"), "accessor " + std::to_string(s.input) + " is " + in.type +
                                             " of " + componentTypeName(in.componentType) +
                                             "; keyframe times must be SCALAR of FLOAT");
      if (s.interpolation == Interpolation::CubicSpline && in.count < 2)
        throw SceneError(so.at("input"), "CUBICSPLINE needs at least 2 keys");
      anim.samplers.push_back(s);
    }
    if (anim.samplers.empty()) throw SceneError(o.at("samplers"), "must not be empty");
    o.require("channels");
    for (const Object& co : objects(o, "channels")) {
      AnimationChannel c;
      c.where = co.where();
      c.sampler = co.index("sampler", anim.samplers.size(), "sampler", true);
      co.require("target");
      Object target = co.object("target");
      c.node = target.index("node", doc->nodes.size(), "node");
      target.require("path");
      std::string path = target.string("path");
      if (path == "translation")
        c.path = AnimationPath::Translation;
      else if (path == "rotation")
        c.path = AnimationPath::Rotation;
      else if (path == "scale")
        c.path = AnimationPath::Scale;
      else if (path == "weights")
        c.path = AnimationPath::Weights;
      else
        throw SceneError(
            target.at("path"),
            "unknown path '" + path + "' (expected translation, rotation, scale or weights)");
      if (c.node >= 0 && c.path != AnimationPath::Weights && doc->nodes[size_t(c.node)].hasMatrix)
        throw SceneError(target.at("node"), "node " + std::to_string(c.node) +
                                                " has a matrix; only nodes given by "
                                                "translation/rotation/scale may be animated");
      for (const AnimationChannel& other : anim.channels)
        if (c.node >= 0 && other.node == c.node && other.path == c.path)
          throw SceneError(co.where(), "node " + std::to_string(c.node) + " '" + path +
                                           "' is already animated by " + other.where.pointer);
      checkOutput(*doc, anim, c);
      anim.channels.push_back(c);
    }
    if (anim.channels.empty()) throw SceneError(o.at("channels"), "must not be empty");
    doc->animations.push_back(anim);
  }
}

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

void checkExtensions(const Object& root, std::vector<std::string>* warnings,
                     std::vector<std::string>* used) {
  for (auto& [value, loc] : root.array("extensionsRequired")) {
    if (!value->is_string())
      throw SceneError(loc, "expected a string, got " + jsonTypeName(*value));
    std::string name = value->get<std::string>();
    if (!isSupportedExtension(name))
      throw SceneError(loc, "unsupported extension '" + name + "' is required (glint supports " +
                                supportedExtensionList() + ")");
  }
  for (auto& [value, loc] : root.array("extensionsUsed")) {
    if (!value->is_string())
      throw SceneError(loc, "expected a string, got " + jsonTypeName(*value));
    std::string name = value->get<std::string>();
    used->push_back(name);
    if (!isSupportedExtension(name))
      warnings->push_back(loc.str() + ": extension '" + name +
                          "' is not supported; ignored: " + whatIsIgnored(name));
  }
}

}  // namespace

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

Document readDocument(const json& rootValue, const std::string& file) {
  Object root(rootValue, SourceLocation{file, ""});
  Document doc;
  doc.file = file;
  root.require("asset");
  Object asset = root.object("asset");
  asset.require("version");
  std::string version = asset.string("version");
  if (version.rfind("2.", 0) != 0)
    throw SceneError(asset.at("version"),
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
