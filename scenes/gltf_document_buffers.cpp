// glint — glTF buffers, buffer views (with EXT_meshopt_compression) and accessors: every byte
// range checked against the declared lengths before the loader reads a byte.
#include <algorithm>
#include <string>

#include "scenes/gltf_document_parts.h"

namespace glint::gltf {

namespace {

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

// EXT_meshopt_compression on buffer view `v`: where the compressed bytes are and what they
// decode to, checked against the extension's rules (strides per mode and filter, sizes).
BufferView::Meshopt readMeshopt(JsonReader& o, const BufferView& v, const Document& doc) {
  BufferView::Meshopt m;
  m.where = o.where();
  m.buffer = o.index("buffer", doc.buffers.size(), "buffer");
  m.byteOffset = o.getSize("byteOffset", 0);
  m.byteLength = o.getSize("byteLength");
  m.byteStride = o.getSize("byteStride");
  m.count = o.getSize("count");
  m.mode = o.get<std::string>("mode");
  m.filter = o.get<std::string>("filter", "NONE");
  const size_t source = doc.buffers[size_t(m.buffer)].byteLength;
  if (m.byteOffset > source || m.byteLength > source - m.byteOffset)
    throw SceneError(m.where, "compressed bytes " + std::to_string(m.byteOffset) + ".." +
                                  std::to_string(m.byteOffset + m.byteLength) +
                                  " lie outside buffer " + std::to_string(m.buffer) + " (" +
                                  plural(source, "byte") + ")");
  const size_t s = m.byteStride;
  if (m.mode == "ATTRIBUTES") {
    if (s == 0 || s % 4 || s > 256)
      throw SceneError(o.where("byteStride"), "must be a multiple of 4 up to 256 for ATTRIBUTES");
  } else if (m.mode == "TRIANGLES" || m.mode == "INDICES") {
    if (s != 2 && s != 4) throw SceneError(o.where("byteStride"), "must be 2 or 4 for " + m.mode);
    if (m.mode == "TRIANGLES" && m.count % 3)
      throw SceneError(o.where("count"), "must be a multiple of 3 for TRIANGLES");
  } else {
    throw SceneError(o.where("mode"),
                     "must be ATTRIBUTES, TRIANGLES or INDICES (got '" + m.mode + "')");
  }
  if (m.filter != "NONE") {
    if (m.mode != "ATTRIBUTES")
      throw SceneError(o.where("filter"), "a filter needs mode ATTRIBUTES");
    const bool ok = m.filter == "OCTAHEDRAL"    ? s == 4 || s == 8
                    : m.filter == "QUATERNION"  ? s == 8
                    : m.filter == "EXPONENTIAL" ? s % 4 == 0
                                                : false;
    if (!ok)
      throw SceneError(o.where("filter"), "filter '" + m.filter + "' with byteStride " +
                                              std::to_string(s) +
                                              " (OCTAHEDRAL: 4 or 8, QUATERNION: 8, EXPONENTIAL: "
                                              "a multiple of 4)");
  }
  constexpr size_t kLimit = size_t(1) << 40;
  if (m.count > kLimit / std::max<size_t>(s, 1) || m.count * s > v.byteLength)
    throw SceneError(o.where("count"),
                     std::to_string(m.count) + " elements of " + plural(s, "byte") +
                         " do not fit the view's byteLength " + std::to_string(v.byteLength));
  return m;
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

// A componentType: any non-negative integer reads (capped, to stay an int), then is checked
// by the caller against the types it allows.
int componentTypeOf(JsonReader& o) {
  return int(std::min<size_t>(o.getSize("componentType"), 1u << 30));
}

Sparse readSparse(JsonReader& so, const Accessor& a, const Document& doc) {
  Sparse s;
  s.where = so.where();
  s.count = so.getSize("count");
  if (s.count == 0 || s.count > a.count)
    throw SceneError(so.where("count"), "must be between 1 and the accessor's count (" +
                                            std::to_string(a.count) + ")");
  JsonReader& io = so.object("indices");
  s.indicesView = io.index("bufferView", doc.bufferViews.size(), "bufferView");
  s.indicesOffset = io.getSize("byteOffset", 0);
  s.indicesComponentType = componentTypeOf(io);
  if (s.indicesComponentType != kUnsignedByte && s.indicesComponentType != kUnsignedShort &&
      s.indicesComponentType != kUnsignedInt)
    throw SceneError(io.where("componentType"),
                     "sparse indices must be UNSIGNED_BYTE, "
                     "UNSIGNED_SHORT or UNSIGNED_INT");
  size_t indexSize = componentSize(s.indicesComponentType);
  checkRange(doc, s.indicesView, s.indicesOffset, indexSize, s.count, indexSize, io.where(),
             "sparse indices");
  JsonReader& vo = so.object("values");
  s.valuesView = vo.index("bufferView", doc.bufferViews.size(), "bufferView");
  s.valuesOffset = vo.getSize("byteOffset", 0);
  size_t elem = elementSize(a);
  checkRange(doc, s.valuesView, s.valuesOffset, elem, s.count, elem, vo.where(), "sparse values");
  return s;
}

}  // namespace

void readBuffers(JsonReader& root, Document* doc) {
  for (const JsonItem& item : root.optionalArray("buffers")) {
    JsonReader o(item);
    Buffer b;
    b.where = o.where();
    b.byteLength = o.getSize("byteLength");
    b.uri = o.get<std::string>("uri", "");
    if (o.has("uri") && b.uri.empty()) throw SceneError(o.where("uri"), "empty URI");
    if (JsonReader* ext = o.optionalObject("extensions"))
      if (JsonReader* meshopt = ext->optionalObject("EXT_meshopt_compression"))
        b.fallback = meshopt->get<bool>("fallback", false);
    doc->buffers.push_back(b);
  }
}

void readBufferViews(JsonReader& root, Document* doc) {
  for (const JsonItem& item : root.optionalArray("bufferViews")) {
    JsonReader o(item);
    BufferView v;
    v.where = o.where();
    v.buffer = o.index("buffer", doc->buffers.size(), "buffer");
    v.byteOffset = o.getSize("byteOffset", 0);
    v.byteLength = o.getSize("byteLength");
    v.byteStride = o.getSize("byteStride", 0);
    if (o.has("byteStride") && (v.byteStride < 4 || v.byteStride > 252 || v.byteStride % 4))
      throw SceneError(o.where("byteStride"), "must be a multiple of 4 between 4 and 252 (got " +
                                                  std::to_string(v.byteStride) + ")");
    size_t bufferLength = doc->buffers[size_t(v.buffer)].byteLength;
    if (v.byteOffset > bufferLength || v.byteLength > bufferLength - v.byteOffset)
      throw SceneError(v.where, "bytes " + std::to_string(v.byteOffset) + ".." +
                                    std::to_string(v.byteOffset + v.byteLength) +
                                    " lie outside buffer " + std::to_string(v.buffer) + " (" +
                                    plural(bufferLength, "byte") + ")");
    if (JsonReader* ext = o.optionalObject("extensions"))
      if (JsonReader* meshopt = ext->optionalObject("EXT_meshopt_compression"))
        v.meshopt = readMeshopt(*meshopt, v, *doc);
    doc->bufferViews.push_back(v);
  }
}

void readAccessors(JsonReader& root, Document* doc) {
  size_t index = 0;
  for (const JsonItem& item : root.optionalArray("accessors")) {
    JsonReader o(item);
    Accessor a;
    a.where = o.where();
    a.bufferView = o.index("bufferView", doc->bufferViews.size(), "bufferView", -1);
    a.byteOffset = o.getSize("byteOffset", 0);
    a.componentType = componentTypeOf(o);
    if (!isComponentType(a.componentType))
      throw SceneError(o.where("componentType"),
                       "unknown componentType " + std::to_string(a.componentType));
    a.normalized = o.get<bool>("normalized", false);
    a.count = o.getSize("count");
    if (a.count == 0) throw SceneError(o.where("count"), "must be at least 1");
    // Without a bufferView the count is not backed by data; cap it so that a typo cannot ask
    // for gigabytes of zeros.
    constexpr size_t kMaxVirtualCount = size_t(1) << 24;
    if (a.bufferView < 0 && a.count > kMaxVirtualCount)
      throw SceneError(o.where("count"), "count " + std::to_string(a.count) +
                                             " without a bufferView exceeds glint's limit of " +
                                             std::to_string(kMaxVirtualCount));
    a.type = o.get<std::string>("type");
    a.components = componentsOf(a.type);
    if (a.components == 0)
      throw SceneError(o.where("type"), "unknown accessor type '" + a.type + "'");
    if (o.has("bufferView") && o.has("byteOffset") && a.byteOffset % componentSize(a.componentType))
      throw SceneError(o.where("byteOffset"), "must be a multiple of the component size (" +
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
    if (JsonReader* sparse = o.optionalObject("sparse")) a.sparse = readSparse(*sparse, a, *doc);
    doc->accessors.push_back(a);
    ++index;
  }
}

}  // namespace glint::gltf
