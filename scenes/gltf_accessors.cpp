// glint — reading glTF accessors (see gltf_accessors.h).
#include "scenes/gltf_accessors.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "scenes/errors.h"
#include "scenes/gltf_meshopt.h"

namespace glint::gltf {

namespace {

double readComponent(const uint8_t* p, int componentType, bool normalized) {
  switch (componentType) {
    case kByte: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case kUnsignedByte:
      return normalized ? *p / 255.0 : *p;
    case kShort: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case kUnsignedShort: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case kUnsignedInt: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

}  // namespace

std::vector<double> AccessorReader::read(int index) const {
  if (auto it = decoded_.find(index); it != decoded_.end()) return it->second;
  const Accessor& a = doc_.accessors[size_t(index)];
  size_t n = size_t(a.components);
  std::vector<double> out(a.count * n, 0.0);
  size_t elem = elementSize(a);
  if (a.bufferView >= 0) {
    size_t stride = doc_.bufferViews[size_t(a.bufferView)].byteStride;
    if (stride == 0) stride = elem;
    const uint8_t* base =
        viewData(a.bufferView, a.byteOffset, stride * (a.count - 1) + elem, a.where);
    for (size_t i = 0; i < a.count; ++i) readElement(a, base + i * stride, &out[i * n]);
  }
  if (a.sparse) {
    const Sparse& s = *a.sparse;
    size_t indexSize = componentSize(s.indicesComponentType);
    const uint8_t* indices = viewData(s.indicesView, s.indicesOffset, indexSize * s.count, s.where);
    const uint8_t* values = viewData(s.valuesView, s.valuesOffset, elem * s.count, s.where);
    double previous = -1;
    for (size_t k = 0; k < s.count; ++k) {
      double i = readComponent(indices + k * indexSize, s.indicesComponentType, false);
      if (i <= previous || i >= double(a.count))
        throw SceneError(
            s.where.child("indices"),
            "sparse index " + std::to_string(uint64_t(i)) + " at position " + std::to_string(k) +
                (i >= double(a.count) ? " is out of range (count " + std::to_string(a.count) + ")"
                                      : " is not greater than the previous one"));
      previous = i;
      readElement(a, values + k * elem, &out[size_t(i) * n]);
    }
  }
  return out;
}

void AccessorReader::readElement(const Accessor& a, const uint8_t* p, double* out) const {
  size_t c = componentSize(a.componentType);
  int rows = a.type == "MAT2" ? 2 : a.type == "MAT3" ? 3 : a.type == "MAT4" ? 4 : a.components;
  int columns = a.components / rows;
  // Byte and short matrix columns are padded to 4 bytes.
  size_t columnBytes = a.components == rows ? 0 : (rows * c + 3) / 4 * 4;
  for (int col = 0; col < columns; ++col)
    for (int r = 0; r < rows; ++r)
      out[col * rows + r] =
          readComponent(p + col * columnBytes + size_t(r) * c, a.componentType, a.normalized);
}

const uint8_t* AccessorReader::view(int index, size_t* size, const SourceLocation& where) const {
  *size = doc_.bufferViews[size_t(index)].byteLength;
  return viewData(index, 0, *size, where);
}

const uint8_t* AccessorReader::viewData(int view, size_t offset, size_t bytes,
                                        const SourceLocation& where) const {
  const BufferView& v = doc_.bufferViews[size_t(view)];
  if (v.meshopt) {  // EXT_meshopt_compression: decoded once, on first use
    auto it = decodedViews_.find(view);
    if (it == decodedViews_.end()) {
      const BufferView::Meshopt& m = *v.meshopt;
      const std::string_view source = payload_.buffers[size_t(m.buffer)];
      if (m.byteOffset + m.byteLength > source.size())
        throw SceneError(m.where, "compressed bytes lie outside the decoded buffer " +
                                      std::to_string(m.buffer) + " (" +
                                      std::to_string(source.size()) + " bytes)");
      const auto* compressed = reinterpret_cast<const uint8_t*>(source.data()) + m.byteOffset;
      it = decodedViews_.emplace(view, decodeMeshoptView(v, compressed, m.byteLength)).first;
    }
    if (offset + bytes > it->second.size())
      throw SceneError(where, "data of bufferView " + std::to_string(view) +
                                  " lies outside its decompressed " +
                                  std::to_string(it->second.size()) + " bytes");
    return it->second.data() + offset;
  }
  const std::string_view data = payload_.buffers[size_t(v.buffer)];
  if (v.byteOffset + offset + bytes > data.size())
    throw SceneError(where, "data of bufferView " + std::to_string(view) +
                                " lies outside the decoded buffer " + std::to_string(v.buffer) +
                                " (" + std::to_string(data.size()) + " bytes)");
  return reinterpret_cast<const uint8_t*>(data.data()) + v.byteOffset + offset;
}

}  // namespace glint::gltf
