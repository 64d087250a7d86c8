// glint — KHR_draco_mesh_compression: decoding a primitive's Draco-compressed geometry (Debian's
// libdraco) into the values of the accessors that describe it.
//
// The glTF primitive keeps its accessors (count, type, component type, normalization) but they
// have no data: the extension's buffer view holds one Draco mesh whose attributes, named by
// unique id, are those accessors' data, and whose faces are the indices. The decoded values
// reach the loader as AccessorReader overrides, so quantized, normalized and morph-free
// attributes go through the same checks as plain ones.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <vector>

#include "scenes/gltf_document.h"

namespace glint::gltf {

// Decodes `bytes` (the extension's buffer view) for primitive `p` of `doc`: accessor index ->
// its elements, components doubles each (integers scaled as the accessor's `normalized` says).
// A buffer Draco cannot decode, an attribute id it does not hold, or a decoded size that
// disagrees with an accessor's count or type is a SceneError at the extension.
std::map<int, std::vector<double>> decodeDracoPrimitive(const uint8_t* bytes, size_t size,
                                                        const Primitive& p, const Document& doc);

}  // namespace glint::gltf
