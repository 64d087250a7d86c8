// glint — the parts of gltf::readDocument, one per concept (scenes/gltf_document.h says why
// they are split), and the few helpers they share. Internal to scenes/gltf_document*.cpp.
//
// Each part reads its top-level arrays from the lenient root reader into `doc`, in the order
// readDocument calls them: a part may rely on everything read before it (indices into earlier
// arrays are checked against their sizes; later ones, such as a node's skin, are checked by the
// later part).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "scenes/gltf_document.h"
#include "scenes/json_reader.h"

namespace glint::gltf {

// --- gltf_document_buffers.cpp ---
void readBuffers(JsonReader& root, Document* doc);
void readBufferViews(JsonReader& root, Document* doc);
void readAccessors(JsonReader& root, Document* doc);

// --- gltf_document_materials.cpp ---
void readImages(JsonReader& root, Document* doc);
void readSamplers(JsonReader& root, Document* doc);
void readTextures(JsonReader& root, Document* doc);
void readMaterials(JsonReader& root, Document* doc);

// --- gltf_document_meshes.cpp ---
void readVariants(JsonReader& root, Document* doc);
void readMeshes(JsonReader& root, Document* doc);
// Morph weights at `key` (absent: empty): numbers, one per morph target. `owner` says whose
// target count it is, for the message ("the mesh's primitives have", "mesh 2 has").
std::vector<float> morphWeights(JsonReader& o, std::string_view key, size_t targets,
                                const std::string& owner);

// --- gltf_document_nodes.cpp ---
void readCameras(JsonReader& root, Document* doc);
void readLights(JsonReader& root, Document* doc);
void readNodes(JsonReader& root, Document* doc);  // and the scenes
void readSkins(JsonReader& root, Document* doc);

// --- gltf_document_animations.cpp ---
void readAnimations(JsonReader& root, Document* doc);

// --- shared (gltf_document.cpp) ---
// "1 byte", "3 bytes".
std::string plural(size_t n, const std::string& word);
// A factor at `key` (fallback when absent) between 0 and `upper`: "must not be negative",
// "must be between 0 and 1" (the message glTF's factors in [0, 1] need; larger uppers are
// practical limits that files stay far below).
float nonNegative(JsonReader& o, std::string_view key, double fallback, double upper);

}  // namespace glint::gltf
