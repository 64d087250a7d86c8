// glint — glTF mesh primitives into MeshDescs: attributes with their allowed layouts
// (KHR_mesh_quantization), skin weights, morph targets, and strips and fans as triangles.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "scenes/description.h"
#include "scenes/gltf_accessors.h"
#include "scenes/gltf_document.h"

namespace glint::gltf {

class MeshConverter {
 public:
  // Appends to `scene`; a primitive's material index `i` becomes `materialBase + i`. `doc` and
  // `reader` must outlive the converter.
  MeshConverter(const Document& doc, AccessorReader& reader, int materialBase,
                SceneDescription* scene);

  // The MeshDesc indices of glTF mesh `m`'s primitives (-1 for skipped ones: points, lines,
  // fewer than three vertices), converted on first use so that every node using the mesh
  // shares them.
  const std::vector<int>& meshDescs(int m);

 private:
  // How an attribute's values are used, which decides the component types it may have.
  enum class Kind { Position, Direction, TexCoord, Color };

  int convertPrimitive(const Primitive& p, const std::string& name,
                       const std::vector<float>& weights);
  void readPositions(const Primitive& p, MeshDesc* mesh);
  void readNormals(const Primitive& p, MeshDesc* mesh);
  void readTangents(const Primitive& p, MeshDesc* mesh);
  void readUvs(const Primitive& p, int accessor, const char* set, size_t n,
               std::vector<Vec2f>* uvs);
  void readColors(const Primitive& p, MeshDesc* mesh);
  void readSkinning(const Primitive& p, MeshDesc* mesh);
  void readMorphTargets(const Primitive& p, MeshDesc* mesh);
  // The primitive's vertex order as triangles (strips and fans unrolled); empty when it has
  // fewer than three vertices.
  std::vector<uint32_t> readTriangles(const Primitive& p, size_t vertices);

  bool componentAllowed(const Accessor& a, Kind kind) const;
  std::string allowedComponents(Kind kind) const;
  // Checks that accessor `index`, used as `attribute` at `where`, has one of `types` and a
  // component type `kind` allows.
  const Accessor& attribute(int index, const SourceLocation& where, const std::string& attribute,
                            std::initializer_list<const char*> types, Kind kind) const;
  const Accessor& attribute(int index, const Primitive& p, const std::string& name,
                            std::initializer_list<const char*> types, Kind kind) const;
  // Checks that accessor `index`, the primitive's attribute `what`, has `vertices` elements.
  void checkCount(int index, const SourceLocation& where, size_t vertices) const;

  const Document& doc_;
  AccessorReader& reader_;
  int materialBase_;
  SceneDescription* scene_;
  bool quantized_ = false;  // KHR_mesh_quantization is used: integer attributes allowed
  std::map<int, std::vector<int>> converted_;
};

}  // namespace glint::gltf
