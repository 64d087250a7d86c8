// glint — EXT_meshopt_compression: decoding a compressed buffer view (gltfpack's output) with
// Debian's libmeshoptimizer into the bytes the view would hold uncompressed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "scenes/gltf_document.h"

namespace glint::gltf {

// The view's `count` x `byteStride` bytes, decoded from `bytes` (the extension's source range)
// by its mode (vertex attributes, triangle or sequence indices) and filter (octahedral unit
// vectors, quaternions, exponents). Bytes that do not decode to that size are a SceneError at
// the extension.
std::vector<uint8_t> decodeMeshoptView(const BufferView& view, const uint8_t* bytes, size_t size);

}  // namespace glint::gltf
