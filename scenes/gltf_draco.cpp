// glint — KHR_draco_mesh_compression through libdraco (see gltf_draco.h).
#include "scenes/gltf_draco.h"

#include <draco/compression/decode.h>

#include <memory>
#include <string>

#include "scenes/errors.h"

namespace glint::gltf {

namespace {

// The largest value of an integer component type, for normalized accessors (1: floats).
double normalizer(int componentType) {
  switch (componentType) {
    case kByte:
      return 127;
    case kUnsignedByte:
      return 255;
    case kShort:
      return 32767;
    case kUnsignedShort:
      return 65535;
    default:
      return 1;
  }
}

bool isIntegral(draco::DataType t) {
  return t != draco::DT_FLOAT32 && t != draco::DT_FLOAT64 && t != draco::DT_BOOL &&
         t != draco::DT_INVALID;
}

// The primitive's accessor for glTF attribute `name` (-1: one glint does not read).
int accessorOf(const Primitive& p, const std::string& name) {
  if (name == "POSITION") return p.position;
  if (name == "NORMAL") return p.normal;
  if (name == "TANGENT") return p.tangent;
  if (name == "TEXCOORD_0") return p.texcoord0;
  if (name == "TEXCOORD_1") return p.texcoord1;
  if (name == "COLOR_0") return p.color0;
  if (name == "JOINTS_0") return p.joints0;
  if (name == "WEIGHTS_0") return p.weights0;
  return -1;
}

}  // namespace

std::map<int, std::vector<double>> decodeDracoPrimitive(const uint8_t* bytes, size_t size,
                                                        const Primitive& p, const Document& doc) {
  const Primitive::Draco& d = *p.draco;
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes), size);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok())
    throw SceneError(d.where.child("bufferView"),
                     "cannot decode the Draco mesh: " + decoded.status().error_msg_string());
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  if (!mesh) throw SceneError(d.where.child("bufferView"), "the Draco buffer holds no mesh");

  std::map<int, std::vector<double>> out;
  // Indices: three per face.
  const Accessor& ia = doc.accessors[size_t(p.indices)];
  const size_t faces = mesh->num_faces();
  if (ia.count != faces * 3)
    throw SceneError(d.where, "the Draco mesh has " + std::to_string(faces) + " triangles (" +
                                  std::to_string(faces * 3) + " indices) but accessor " +
                                  std::to_string(p.indices) + " (indices) has count " +
                                  std::to_string(ia.count));
  std::vector<double>& indices = out[p.indices];
  indices.reserve(faces * 3);
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f)
    for (int k = 0; k < 3; ++k) indices.push_back(double(mesh->face(f)[k].value()));

  const size_t points = mesh->num_points();
  for (const auto& [name, id] : d.attributes) {
    const int accessor = accessorOf(p, name);
    if (accessor < 0) continue;
    const SourceLocation where = d.where.child("attributes").child(name);
    const draco::PointAttribute* att = mesh->GetAttributeByUniqueId(uint32_t(id));
    if (!att)
      throw SceneError(where, "the Draco mesh has no attribute with id " + std::to_string(id));
    const Accessor& a = doc.accessors[size_t(accessor)];
    if (a.count != points)
      throw SceneError(where, "the Draco mesh has " + std::to_string(points) +
                                  " points but accessor " + std::to_string(accessor) + " (" + name +
                                  ") has count " + std::to_string(a.count));
    const int components = att->num_components();
    if (components != a.components)
      throw SceneError(where, "the Draco attribute has " + std::to_string(components) +
                                  " components but accessor " + std::to_string(accessor) + " is " +
                                  a.type);
    const double scale = a.normalized && isIntegral(att->data_type()) && !att->normalized()
                             ? 1 / normalizer(a.componentType)
                             : 1;
    std::vector<double>& values = out[accessor];
    values.resize(points * size_t(components));
    for (draco::PointIndex i(0); i < mesh->num_points(); ++i) {
      double* v = &values[size_t(i.value()) * size_t(components)];
      if (!att->ConvertValue<double>(att->mapped_index(i), int8_t(components), v))
        throw SceneError(where, "cannot read Draco attribute " + std::to_string(id));
      for (int c = 0; c < components; ++c) v[c] *= scale;
    }
  }
  return out;
}

}  // namespace glint::gltf
