// glint — EXT_meshopt_compression through libmeshoptimizer (see gltf_meshopt.h).
#include "scenes/gltf_meshopt.h"

#include <meshoptimizer.h>

#include <string>

#include "scenes/errors.h"

namespace glint::gltf {

std::vector<uint8_t> decodeMeshoptView(const BufferView& view, const uint8_t* bytes, size_t size) {
  const BufferView::Meshopt& m = *view.meshopt;
  // The view may be longer than the elements (padding); the rest stays zero.
  std::vector<uint8_t> out(std::max(view.byteLength, m.count * m.byteStride), 0);
  int status = 0;
  if (m.mode == "ATTRIBUTES")
    status = meshopt_decodeVertexBuffer(out.data(), m.count, m.byteStride, bytes, size);
  else if (m.mode == "TRIANGLES")
    status = meshopt_decodeIndexBuffer(out.data(), m.count, m.byteStride, bytes, size);
  else
    status = meshopt_decodeIndexSequence(out.data(), m.count, m.byteStride, bytes, size);
  if (status != 0)
    throw SceneError(m.where, "cannot decode the compressed " + m.mode + " (" +
                                  std::to_string(m.byteLength) + " bytes for " +
                                  std::to_string(m.count) + " elements of " +
                                  std::to_string(m.byteStride) + " bytes; meshoptimizer error " +
                                  std::to_string(status) + ")");
  if (m.filter == "OCTAHEDRAL")
    meshopt_decodeFilterOct(out.data(), m.count, m.byteStride);
  else if (m.filter == "QUATERNION")
    meshopt_decodeFilterQuat(out.data(), m.count, m.byteStride);
  else if (m.filter == "EXPONENTIAL")
    meshopt_decodeFilterExp(out.data(), m.count, m.byteStride);
  return out;
}

}  // namespace glint::gltf
