// glint — glTF accessors: typed, bounds-checked reads of buffer data.
//
// An accessor is a view of `count` elements (SCALAR ... MAT4) of one component type in a buffer
// view, possibly strided, normalised, sparse, or compressed (EXT_meshopt_compression decodes
// whole views; KHR_draco_mesh_compression decodes whole primitives, whose values stand in for
// the accessors). Every read is checked against the data actually present, so a file whose
// declared lengths lie is an error at the accessor's pointer, never a read past the end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <vector>

#include "scenes/gltf_container.h"
#include "scenes/gltf_document.h"

namespace glint::gltf {

class AccessorReader {
 public:
  // Reads the accessors of `doc` from `payload`; both must outlive the reader.
  AccessorReader(const Document& doc, const Payload& payload) : doc_(doc), payload_(payload) {}

  // The accessor's elements as `components` doubles each (normalized integers mapped to
  // [0, 1] or [-1, 1], matrices column by column), with sparse substitution applied.
  std::vector<double> read(int index) const;

  // The bytes of buffer view `index` (decompressed, for EXT_meshopt_compression); `where`
  // names the user of the view in messages.
  const uint8_t* view(int index, size_t* size, const SourceLocation& where) const;

  // Values decoded from a compressed primitive (KHR_draco_mesh_compression) stand in for the
  // accessors they describe until the next call.
  void setDecoded(std::map<int, std::vector<double>> decoded) { decoded_ = std::move(decoded); }

 private:
  void readElement(const Accessor& a, const uint8_t* p, double* out) const;
  const uint8_t* viewData(int view, size_t offset, size_t bytes, const SourceLocation& where) const;

  const Document& doc_;
  const Payload& payload_;
  std::map<int, std::vector<double>> decoded_;
  mutable std::map<int, std::vector<uint8_t>> decodedViews_;  // EXT_meshopt_compression
};

}  // namespace glint::gltf
