// glint — the glTF JSON read into small validated structs, every item with its JSON pointer.
//
// This is the loader's first pass (scenes/gltf_loader.cpp): it runs before any byte a buffer
// or image holds is read, so that type errors, dangling indices and out-of-range byte ranges
// are reported with the exact pointer. It reads only what glint uses (plus what it must check
// for safety); unknown keys, extras and optional extensions are ignored, as glTF allows.
//
// The JSON is read with JsonReader (scenes/json_reader.h), the reader of every sidecar and
// scene schema, in its lenient mode: the same typed getters, located errors, size and index
// readers, with unknown keys allowed and glTF's wording of errors ("missing required property
// 'x'"). glTF thus has no JSON reader of its own.
//
// The reading is split by concept, one file per group of top-level glTF arrays, in the order
// readDocument reads them (each part checks its indices against the parts read before it):
//   gltf_document.cpp             the document: asset, extensionsRequired/Used, the order
//   gltf_document_buffers.cpp     buffers, buffer views (EXT_meshopt_compression), accessors
//   gltf_document_materials.cpp   images, samplers, textures, materials and their extensions
//   gltf_document_meshes.cpp      meshes, primitives, morph targets, variants, Draco
//   gltf_document_nodes.cpp       cameras, lights, nodes and the node graph, scenes, skins
//   gltf_document_animations.cpp  animations
// Why split: the single file had grown to 1,350 lines across six unrelated concerns; a
// material extension, say, is now read, reviewed and changed beside the other materials
// alone. scenes/gltf_document_parts.h declares the parts and their few shared helpers.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scenes/description.h"

namespace glint::gltf {

// glTF componentType values.
inline constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122, kUnsignedShort = 5123,
                     kUnsignedInt = 5125, kFloat = 5126;

struct Buffer {
  size_t byteLength = 0;
  std::string uri;  // empty: the GLB BIN chunk (or, for a fallback, no data at all)
  // EXT_meshopt_compression's placeholder for decompressed views: it may have no data.
  bool fallback = false;
  SourceLocation where;
};

struct BufferView {
  int buffer = -1;
  size_t byteOffset = 0, byteLength = 0;
  size_t byteStride = 0;  // 0 = not given (tightly packed)
  // EXT_meshopt_compression: the view's data is `count` elements of `byteStride` bytes decoded
  // from bytes [byteOffset, byteOffset + byteLength) of `buffer` (scenes/gltf_meshopt.h).
  struct Meshopt {
    int buffer = -1;
    size_t byteOffset = 0, byteLength = 0, byteStride = 0, count = 0;
    std::string mode;             // ATTRIBUTES | TRIANGLES | INDICES
    std::string filter = "NONE";  // NONE | OCTAHEDRAL | QUATERNION | EXPONENTIAL
    SourceLocation where;
  };
  std::optional<Meshopt> meshopt;
  SourceLocation where;
};

struct Sparse {
  size_t count = 0;
  int indicesView = -1;
  size_t indicesOffset = 0;
  int indicesComponentType = 0;
  int valuesView = -1;
  size_t valuesOffset = 0;
  SourceLocation where;  // .../sparse
};

struct Accessor {
  int bufferView = -1;  // -1: all zeros (then usually sparse)
  size_t byteOffset = 0;
  int componentType = 0;
  bool normalized = false;
  size_t count = 0;
  std::string type;    // "SCALAR", "VEC2", ...
  int components = 1;  // 1, 2, 3, 4, 4 (MAT2), 9, 16
  std::optional<Sparse> sparse;
  SourceLocation where;
};

struct Image {
  std::string uri;  // empty when stored in a bufferView
  int bufferView = -1;
  SourceLocation where;
};

struct Sampler {
  int magFilter = -1;
  WrapMode wrapS = WrapMode::Repeat, wrapT = WrapMode::Repeat;
};

struct Texture {
  int sampler = -1;
  int source = -1;
  SourceLocation where;
};

struct TextureRef {
  int index = -1;
  int texCoord = 0;  // KHR_texture_transform's texCoord when it gives one
  // KHR_texture_transform: uv' = offset + R(rotation) (scale * uv), R as in the extension's
  // GLSL (a column-major mat3 with columns (cos, sin) and (-sin, cos)).
  bool transformed = false;
  Vec2f offset{0, 0}, scale{1, 1};
  float rotation = 0;  // radians
  SourceLocation where;
};

struct Material {
  std::string name;
  Vec4f baseColorFactor{1, 1, 1, 1};
  TextureRef baseColorTexture;
  float metallic = 1, roughness = 1;
  TextureRef metallicRoughnessTexture;
  TextureRef normalTexture;
  float normalScale = 1;
  std::string alphaMode = "OPAQUE";  // OPAQUE | MASK | BLEND
  float alphaCutoff = 0.5f;
  float transmission = 0;  // KHR_materials_transmission
  TextureRef transmissionTexture;
  float ior = 1.5f;  // KHR_materials_ior
  Rgb emissiveFactor{0, 0, 0};
  float emissiveStrength = 1;  // KHR_materials_emissive_strength
  TextureRef emissiveTexture;
  bool doubleSided = false;
  bool unlit = false;  // KHR_materials_unlit
  // The other KHR_materials_* extensions: their numbers (texture indices there unused) and
  // their textures.
  MaterialLayersDesc layers;
  struct LayerTextures {
    TextureRef specular, specularColor, clearcoat, clearcoatRoughness, clearcoatNormal, sheenColor,
        sheenRoughness, diffuseTransmission, diffuseTransmissionColor, iridescence,
        iridescenceThickness, anisotropy;
  } layerTextures;
  SourceLocation where;
};

enum Mode { kPoints = 0, kLines, kLineLoop, kLineStrip, kTriangles, kTriangleStrip, kTriangleFan };

// One morph target of a primitive: accessors of its displacements (-1 = absent).
struct MorphTarget {
  int position = -1, normal = -1, tangent = -1;
  SourceLocation where;
};

struct Primitive {
  // Accessor indices of the attributes glint reads (-1 = absent).
  int position = -1, normal = -1, tangent = -1, texcoord0 = -1, texcoord1 = -1, color0 = -1;
  int joints0 = -1, weights0 = -1;  // skinning: four joint influences per vertex
  bool moreJoints = false;          // JOINTS_1 / WEIGHTS_1 given (ignored, with a warning)
  std::vector<MorphTarget> targets;
  // KHR_materials_variants: (material, variant indices) mappings.
  std::vector<std::pair<int, std::vector<int>>> variantMappings;
  // KHR_draco_mesh_compression: the compressed data's buffer view and the Draco attribute id of
  // each glTF attribute it holds; the primitive's accessors then describe the decoded data.
  struct Draco {
    int bufferView = -1;
    std::vector<std::pair<std::string, int>> attributes;  // glTF name, Draco unique id
    SourceLocation where;
  };
  std::optional<Draco> draco;
  int indices = -1;
  int material = -1;
  int mode = kTriangles;
  SourceLocation where;
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
  std::vector<float> weights;  // default morph weights, one per target (empty: all 0)
  size_t targetCount = 0;      // every primitive has this many morph targets
  SourceLocation where;
};

struct Node {
  std::string name;
  Transform local;
  // The rest values `local` was made from: a matrix, or translation, rotation (unit) and scale.
  bool hasMatrix = false;
  Vec3f translation{0, 0, 0};
  Quaternion rotation;
  Vec3f scale{1, 1, 1};
  std::vector<int> children;
  int mesh = -1, camera = -1, light = -1;
  int skin = -1;
  // EXT_mesh_gpu_instancing: accessors of per-instance TRS (-1 = absent) and their count (0:
  // the node is drawn once, as usual).
  int instanceTranslation = -1, instanceRotation = -1, instanceScale = -1;
  size_t instanceCount = 0;
  std::vector<float> weights;  // morph weights replacing the mesh's (empty: the mesh's)
  SourceLocation where;
};

// A skin: the joint nodes and the inverse bind matrices that take the mesh into each joint's
// space at rest.
struct Skin {
  std::vector<int> joints;             // node indices
  std::vector<Transform> inverseBind;  // one per joint (identity when the file gives none)
  int inverseBindMatrices = -1;        // accessor, read by the loader (-1: identities)
  SourceLocation where;
};

// An animation sampler: keyframe times (input) and values (output). Accessor layouts are
// checked against the channels that use the sampler; the data (strictly increasing finite
// times, finite values) is checked by the loader, which decodes it.
struct AnimationSampler {
  int input = -1, output = -1;
  Interpolation interpolation = Interpolation::Linear;
  SourceLocation where;
};

enum class AnimationPath { Translation, Rotation, Scale, Weights };

struct AnimationChannel {
  int sampler = -1;  // index into Animation::samplers
  int node = -1;     // -1: no target node (the channel is ignored, as glTF allows)
  AnimationPath path = AnimationPath::Translation;
  SourceLocation where;
};

struct Animation {
  std::string name;  // "animation N" when the file gives none
  std::vector<AnimationSampler> samplers;
  std::vector<AnimationChannel> channels;
  SourceLocation where;
};

struct Scene {
  std::vector<int> nodes;
  SourceLocation where;
};

struct Document {
  std::string file;
  std::vector<Buffer> buffers;
  std::vector<BufferView> bufferViews;
  std::vector<Accessor> accessors;
  std::vector<Image> images;
  std::vector<Sampler> samplers;
  std::vector<Texture> textures;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Node> nodes;
  std::vector<Skin> skins;
  std::vector<Scene> scenes;
  std::vector<Animation> animations;
  std::vector<CameraDesc> cameras;  // everything but worldFromCamera
  std::vector<LightDesc> lights;    // KHR_lights_punctual, everything but worldFromLight
  int scene = -1;                   // the "scene" property
  std::vector<std::string> extensionsUsed;
  std::vector<std::string> variants;  // KHR_materials_variants names
  std::vector<std::string> warnings;
};

// Reads and validates `root` (the parsed JSON of `file`): types, required fields, index
// ranges, byte ranges of buffer views and accessors against the declared byte lengths, the
// node graph (trees, no cycles), camera and light parameters, animations (targets, paths,
// interpolation names, accessor types and counts) and extensionsRequired.
// Throws SceneError at the offending pointer.
Document readDocument(const nlohmann::json& root, const std::string& file);

// Bytes one element of `accessor` occupies, including the column padding glTF requires for
// byte and short matrices.
size_t elementSize(const Accessor& accessor);
size_t componentSize(int componentType);
std::string componentTypeName(int componentType);

}  // namespace glint::gltf
