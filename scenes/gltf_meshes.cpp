// glint — glTF mesh primitives into MeshDescs (see gltf_meshes.h).
#include "scenes/gltf_meshes.h"

#include <algorithm>
#include <cmath>

#include "scenes/errors.h"
#include "scenes/gltf_draco.h"

namespace glint::gltf {

namespace {

const char* modeName(int mode) {
  static const char* names[] = {"POINTS",    "LINES",          "LINE_LOOP",   "LINE_STRIP",
                                "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};
  return names[mode];
}

}  // namespace

MeshConverter::MeshConverter(const Document& doc, AccessorReader& reader, int materialBase,
                             SceneDescription* scene)
    : doc_(doc), reader_(reader), materialBase_(materialBase), scene_(scene) {
  for (const std::string& e : doc.extensionsUsed) quantized_ |= e == "KHR_mesh_quantization";
}

const std::vector<int>& MeshConverter::meshDescs(int m) {
  auto it = converted_.find(m);
  if (it != converted_.end()) return it->second;
  const Mesh& mesh = doc_.meshes[size_t(m)];
  std::vector<int> ids;
  for (size_t p = 0; p < mesh.primitives.size(); ++p) {
    std::string name = mesh.name;
    if (mesh.primitives.size() > 1) name += " (primitive " + std::to_string(p) + ")";
    ids.push_back(convertPrimitive(mesh.primitives[p], name, mesh.weights));
  }
  return converted_[m] = ids;
}

// ---------------------------------------------------------------------------------------------
// A primitive
// ---------------------------------------------------------------------------------------------

int MeshConverter::convertPrimitive(const Primitive& p, const std::string& name,
                                    const std::vector<float>& weights) {
  if (p.mode < kTriangles) {
    scene_->warnings.push_back(p.where.str() + ": " + modeName(p.mode) +
                               " primitive skipped (only triangles are rendered)");
    return -1;
  }
  MeshDesc mesh;
  mesh.name = name;
  mesh.where = p.where;
  // A Draco-compressed primitive: its accessors read the decoded values (only while this
  // primitive is converted).
  struct ClearDecoded {
    AccessorReader& reader;
    ~ClearDecoded() { reader.setDecoded({}); }
  } clearDecoded{reader_};
  if (p.draco) {
    size_t size = 0;
    const uint8_t* bytes = reader_.view(p.draco->bufferView, &size, p.draco->where);
    reader_.setDecoded(decodeDracoPrimitive(bytes, size, p, doc_));
  }
  readPositions(p, &mesh);
  readNormals(p, &mesh);
  readTangents(p, &mesh);
  readUvs(p, p.texcoord0, "TEXCOORD_0", mesh.positions.size(), &mesh.uvs);
  readUvs(p, p.texcoord1, "TEXCOORD_1", mesh.positions.size(), &mesh.uvs1);
  readColors(p, &mesh);
  if (p.joints0 >= 0) readSkinning(p, &mesh);
  readMorphTargets(p, &mesh);
  mesh.weights = weights;
  mesh.indices = readTriangles(p, mesh.positions.size());
  if (mesh.indices.empty()) {
    scene_->warnings.push_back(p.where.str() + ": " + modeName(p.mode) +
                               " primitive with fewer than 3 vertices skipped");
    return -1;
  }
  if (p.material >= 0) mesh.material = materialBase_ + p.material;
  for (const auto& [material, variants] : p.variantMappings)
    for (int v : variants)
      mesh.variantMaterials.emplace_back(doc_.variants[size_t(v)], materialBase_ + material);
  scene_->meshes.push_back(std::move(mesh));
  return int(scene_->meshes.size()) - 1;
}

// ---------------------------------------------------------------------------------------------
// Vertex attributes
// ---------------------------------------------------------------------------------------------

void MeshConverter::readPositions(const Primitive& p, MeshDesc* mesh) {
  const Accessor& pa = attribute(p.position, p, "POSITION", {"VEC3"}, Kind::Position);
  std::vector<double> pos = reader_.read(p.position);
  const size_t n = pa.count;
  mesh->positions.resize(n);
  for (size_t i = 0; i < n; ++i) {
    Vec3f v{float(pos[3 * i]), float(pos[3 * i + 1]), float(pos[3 * i + 2])};
    if (!isFinite(v))
      throw SceneError(pa.where, "position " + std::to_string(i) + " is not finite");
    mesh->positions[i] = v;
  }
}

void MeshConverter::readNormals(const Primitive& p, MeshDesc* mesh) {
  if (p.normal < 0) return;
  const Accessor& na = attribute(p.normal, p, "NORMAL", {"VEC3"}, Kind::Direction);
  const size_t n = mesh->positions.size();
  checkCount(p.normal, p.where.child("attributes").child("NORMAL"), n);
  std::vector<double> v = reader_.read(p.normal);
  mesh->normals.resize(n);
  for (size_t i = 0; i < n; ++i) {
    Vec3f nv{float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2])};
    if (!isFinite(nv)) throw SceneError(na.where, "normal " + std::to_string(i) + " is not finite");
    float len = length(nv);
    if (!(len > 0) || !std::isfinite(len))
      throw SceneError(na.where, "normal " + std::to_string(i) + " has zero length");
    mesh->normals[i] = nv / len;
  }
}

// xyz: the tangent (normalised), w: +-1, the handedness of the bitangent.
void MeshConverter::readTangents(const Primitive& p, MeshDesc* mesh) {
  if (p.tangent < 0) return;
  const Accessor& ta = attribute(p.tangent, p, "TANGENT", {"VEC4"}, Kind::Direction);
  const size_t n = mesh->positions.size();
  checkCount(p.tangent, p.where.child("attributes").child("TANGENT"), n);
  std::vector<double> v = reader_.read(p.tangent);
  mesh->tangents.resize(n);
  for (size_t i = 0; i < n; ++i) {
    Vec3f t{float(v[4 * i]), float(v[4 * i + 1]), float(v[4 * i + 2])};
    float w = float(v[4 * i + 3]);
    float len = length(t);
    if (!isFinite(t) || !std::isfinite(w) || !(len > 0) || !std::isfinite(len))
      throw SceneError(ta.where,
                       "tangent " + std::to_string(i) + " is not a finite, non-zero vector");
    t = t / len;
    mesh->tangents[i] = {t.x, t.y, t.z, w < 0 ? -1.0f : 1.0f};
  }
}

void MeshConverter::readUvs(const Primitive& p, int accessor, const char* set, size_t n,
                            std::vector<Vec2f>* uvs) {
  if (accessor < 0) return;
  const Accessor& ta = attribute(accessor, p, set, {"VEC2"}, Kind::TexCoord);
  checkCount(accessor, p.where.child("attributes").child(set), n);
  std::vector<double> v = reader_.read(accessor);
  uvs->resize(n);
  for (size_t i = 0; i < n; ++i) {
    Vec2f uv{float(v[2 * i]), float(v[2 * i + 1])};
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
      throw SceneError(ta.where, "texture coordinate " + std::to_string(i) + " is not finite");
    (*uvs)[i] = uv;
  }
}

void MeshConverter::readColors(const Primitive& p, MeshDesc* mesh) {
  if (p.color0 < 0) return;
  const Accessor& ca = attribute(p.color0, p, "COLOR_0", {"VEC3", "VEC4"}, Kind::Color);
  const size_t n = mesh->positions.size();
  checkCount(p.color0, p.where.child("attributes").child("COLOR_0"), n);
  std::vector<double> v = reader_.read(p.color0);
  size_t c = size_t(ca.components);
  mesh->colors.resize(n);
  for (size_t i = 0; i < n; ++i) {
    Vec4f col{float(v[c * i]), float(v[c * i + 1]), float(v[c * i + 2]),
              c == 4 ? float(v[c * i + 3]) : 1.0f};
    if (!std::isfinite(col.x) || !std::isfinite(col.y) || !std::isfinite(col.z) ||
        !std::isfinite(col.w))
      throw SceneError(ca.where, "color " + std::to_string(i) + " is not finite");
    mesh->colors[i] = col;
  }
}

// JOINTS_0 (VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT) and WEIGHTS_0 (VEC4 of FLOAT or
// normalized UNSIGNED_BYTE/SHORT): finite, non-negative weights; joint indices are checked
// against the skin of each node that uses the mesh.
void MeshConverter::readSkinning(const Primitive& p, MeshDesc* mesh) {
  const SourceLocation attrs = p.where.child("attributes");
  const Accessor& ja = doc_.accessors[size_t(p.joints0)];
  if (ja.type != "VEC4" || ja.normalized ||
      (ja.componentType != kUnsignedByte && ja.componentType != kUnsignedShort))
    throw SceneError(attrs.child("JOINTS_0"),
                     "accessor " + std::to_string(p.joints0) + " is " + ja.type + " of " +
                         componentTypeName(ja.componentType) +
                         "; JOINTS_0 must be VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT");
  const Accessor& wa = attribute(p.weights0, p, "WEIGHTS_0", {"VEC4"}, Kind::Color);
  const size_t n = mesh->positions.size();
  checkCount(p.joints0, attrs.child("JOINTS_0"), n);
  checkCount(p.weights0, attrs.child("WEIGHTS_0"), n);
  std::vector<double> j = reader_.read(p.joints0), w = reader_.read(p.weights0);
  mesh->joints.resize(n);
  mesh->jointWeights.resize(n);
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 4; ++k) {
      mesh->joints[i][size_t(k)] = uint16_t(j[4 * i + size_t(k)]);
      const double wk = w[4 * i + size_t(k)];
      if (!std::isfinite(wk) || wk < 0)
        throw SceneError(wa.where, "weight " + std::to_string(k) + " of vertex " +
                                       std::to_string(i) + " is " + std::to_string(wk) +
                                       "; skin weights must be finite and >= 0");
    }
    mesh->jointWeights[i] = {float(w[4 * i]), float(w[4 * i + 1]), float(w[4 * i + 2]),
                             float(w[4 * i + 3])};
  }
  if (p.moreJoints)
    scene_->warnings.push_back(attrs.str() +
                               ": JOINTS_1/WEIGHTS_1 ignored (glint blends the first four "
                               "joints of each vertex)");
}

void MeshConverter::readMorphTargets(const Primitive& p, MeshDesc* mesh) {
  const size_t n = mesh->positions.size();
  for (const MorphTarget& target : p.targets) {
    MorphTargetDesc d;
    auto displacements = [&](int index, const char* what, std::vector<Vec3f>* out) {
      if (index < 0) return;
      SourceLocation at = target.where.child(what);
      attribute(index, at, std::string("a morph target's ") + what, {"VEC3"}, Kind::Position);
      checkCount(index, at, n);
      std::vector<double> v = reader_.read(index);
      out->resize(n);
      for (size_t i = 0; i < n; ++i) {
        (*out)[i] = {float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2])};
        if (!isFinite((*out)[i]))
          throw SceneError(at, "displacement " + std::to_string(i) + " is not finite");
      }
    };
    displacements(target.position, "POSITION", &d.positions);
    displacements(target.normal, "NORMAL", &d.normals);
    displacements(target.tangent, "TANGENT", &d.tangents);
    mesh->targets.push_back(std::move(d));
  }
}

// ---------------------------------------------------------------------------------------------
// Topology
// ---------------------------------------------------------------------------------------------

std::vector<uint32_t> MeshConverter::readTriangles(const Primitive& p, size_t vertices) {
  // Vertex order: the index accessor, or 0..n-1 when there is none.
  std::vector<uint32_t> order;
  if (p.indices >= 0) {
    const Accessor& ia = doc_.accessors[size_t(p.indices)];
    if (ia.type != "SCALAR" || ia.normalized ||
        (ia.componentType != kUnsignedByte && ia.componentType != kUnsignedShort &&
         ia.componentType != kUnsignedInt))
      throw SceneError(
          p.where.child("indices"),
          "accessor " + std::to_string(p.indices) + " is " + ia.type + " of " +
              componentTypeName(ia.componentType) +
              "; indices must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
    std::vector<double> v = reader_.read(p.indices);
    order.resize(v.size());
    for (size_t i = 0; i < v.size(); ++i) {
      if (v[i] >= double(vertices))
        throw SceneError(p.where.child("indices"), "index " + std::to_string(uint64_t(v[i])) +
                                                       " out of range (" +
                                                       std::to_string(vertices) + " vertices)");
      order[i] = uint32_t(v[i]);
    }
  } else {
    order.resize(vertices);
    for (size_t i = 0; i < vertices; ++i) order[i] = uint32_t(i);
  }

  const size_t m = order.size();
  if (p.mode == kTriangles) {
    if (m % 3)
      throw SceneError(p.where, "TRIANGLES primitive has " + std::to_string(m) +
                                    " vertices, not a multiple of 3");
    return order;
  }
  std::vector<uint32_t> triangles;
  if (p.mode == kTriangleStrip) {
    // glTF 2.0 §3.7.2.1: triangle i is (i, i+1+i%2, i+2-i%2), keeping the winding.
    for (size_t i = 0; i + 2 < m; ++i)
      triangles.insert(triangles.end(), {order[i], order[i + 1 + i % 2], order[i + 2 - i % 2]});
  } else {  // TRIANGLE_FAN: triangle i is (i+1, i+2, 0).
    for (size_t i = 0; i + 2 < m; ++i)
      triangles.insert(triangles.end(), {order[i + 1], order[i + 2], order[0]});
  }
  return triangles;
}

// ---------------------------------------------------------------------------------------------
// Attribute layouts
// ---------------------------------------------------------------------------------------------

// Core glTF allows FLOAT (and normalized UNSIGNED_BYTE/SHORT for texture coordinates, colours
// and weights); KHR_mesh_quantization adds integer positions and displacements, normalized
// BYTE/SHORT directions, and any 8- or 16-bit texture coordinates.
bool MeshConverter::componentAllowed(const Accessor& a, Kind kind) const {
  const int c = a.componentType;
  if (c == kFloat) return true;
  const bool unsigned8or16 = c == kUnsignedByte || c == kUnsignedShort;
  const bool signed8or16 = c == kByte || c == kShort;
  if ((kind == Kind::TexCoord || kind == Kind::Color) && a.normalized && unsigned8or16) return true;
  if (!quantized_) return false;
  switch (kind) {
    case Kind::Position:
      return unsigned8or16 || signed8or16;
    case Kind::Direction:
      return a.normalized && signed8or16;
    case Kind::TexCoord:
      return unsigned8or16 || signed8or16;
    case Kind::Color:
      return false;
  }
  return false;
}

std::string MeshConverter::allowedComponents(Kind kind) const {
  std::string core = kind == Kind::TexCoord || kind == Kind::Color
                         ? "FLOAT or normalized UNSIGNED_BYTE/UNSIGNED_SHORT"
                         : "FLOAT";
  if (kind == Kind::Color) return core;
  if (!quantized_) return core + " (other types need KHR_mesh_quantization)";
  switch (kind) {
    case Kind::Position:
      return "FLOAT, BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT";
    case Kind::Direction:
      return "FLOAT or normalized BYTE/SHORT";
    default:
      return "FLOAT, BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT";
  }
}

const Accessor& MeshConverter::attribute(int index, const SourceLocation& where,
                                         const std::string& attribute,
                                         std::initializer_list<const char*> types,
                                         Kind kind) const {
  const Accessor& a = doc_.accessors[size_t(index)];
  bool typeOk = false;
  for (const char* t : types) typeOk |= a.type == t;
  if (!typeOk || !componentAllowed(a, kind)) {
    std::string want;
    for (const char* t : types) want += std::string(want.empty() ? "" : " or ") + t;
    throw SceneError(where, "accessor " + std::to_string(index) + " is " + a.type + " of " +
                                (a.normalized ? "normalized " : "") +
                                componentTypeName(a.componentType) + "; " + attribute +
                                " must be " + want + " of " + allowedComponents(kind));
  }
  return a;
}

const Accessor& MeshConverter::attribute(int index, const Primitive& p, const std::string& name,
                                         std::initializer_list<const char*> types,
                                         Kind kind) const {
  return attribute(index, p.where.child("attributes").child(name), name, types, kind);
}

void MeshConverter::checkCount(int index, const SourceLocation& where, size_t vertices) const {
  const Accessor& a = doc_.accessors[size_t(index)];
  if (a.count != vertices)
    throw SceneError(where, "accessor " + std::to_string(index) + " has " +
                                std::to_string(a.count) + " elements but POSITION has " +
                                std::to_string(vertices));
}

}  // namespace glint::gltf
