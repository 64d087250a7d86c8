// glint — the bytes of a glTF: the GLB container, and the data its buffers and images point at.
//
// A .gltf file is JSON; a .glb is a 12-byte header, a JSON chunk and an optional BIN chunk.
// Buffers and images are read from the BIN chunk, from base64 data URIs, or from files beside
// the glTF. Every file read stays inside the scene's folder: a URI that leaves it, or that
// names a scheme (http:, file:), is an error at its JSON pointer, never a read.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "scenes/gltf_document.h"

namespace glint::gltf {

// A .gltf or .glb file's contents, split into its JSON text and its BIN chunk (both views into
// the bytes given to readContainer, which must outlive them).
struct Container {
  bool binary = false;    // a GLB
  std::string_view json;  // the JSON text (a GLB's chunk, without its padding)
  bool hasBin = false;    // a GLB with a BIN chunk
  std::string_view bin;   // the BIN chunk's data (may be longer than buffer 0: padding)
};

// Splits `bytes` (the contents of `file`). A ".glb" extension or the GLB magic at the start
// selects the binary container, whose header and chunk headers are checked: truncation,
// trailing data, a version other than 2, a first chunk that is not JSON, and a BIN chunk
// that does not follow it are SceneErrors naming the file.
Container readContainer(const std::string& bytes, const std::string& file);

// What the JSON points at: each buffer's bytes and each image's encoded file.
struct Payload {
  // One per Document::buffers, exactly its byteLength bytes; empty for an
  // EXT_meshopt_compression fallback buffer without data (only its decompressed views are read).
  std::vector<std::string_view> buffers;
  // One per Document::images: the encoded file (PNG, JPEG, WebP, ...), shared with the
  // ImageDescs made from it.
  std::vector<std::shared_ptr<const std::string>> images;
  // The buffers read from data URIs and files (the others view the container's BIN chunk).
  std::vector<std::unique_ptr<const std::string>> owned;
};

// Reads every buffer and image of `doc` from `file`'s BIN chunk, data URIs, or files inside the
// folder of `path` (the glTF's own path, relative URIs resolve there). A URI that leaves the folder
// or names a scheme, a file that cannot be read, a data URI that is not base64, a byte length that
// disagrees with the data, and an image in a buffer view outside its buffer are SceneErrors at the
// offending pointer.
Payload readPayload(const Document& doc, const Container& file, const std::string& path);

// The bytes of data URI `uri` ("data:[<media type>][;base64],<data>"), or false when it is not
// one glint reads: only base64 data is, since glTF's buffers and images are binary.
bool decodeDataUri(std::string_view uri, std::string* bytes);

}  // namespace glint::gltf
