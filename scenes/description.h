// glint — SceneDescription: plain structs holding what the scene files say.
//
// Loaders (glTF, sidecar JSON) fill these and record where every item came from; they never
// touch Embree or the renderer. scenes/build turns a validated description into render-time
// objects. Indices between items are plain ints into the vectors below (-1 = none).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "geometry/math.h"
#include "geometry/shape.h"
#include "renderer/settings.h"
#include "scenes/animation.h"
#include "scenes/errors.h"

namespace glint {

// Decoded image pixels, as stored in the file (not yet linearized): `channels` floats per
// pixel in [0, 1], rows top to bottom.
struct ImageDesc {
  std::string name;                         // the URI, or "image N" for embedded images
  int width = 0, height = 0, channels = 0;  // from the file's header
  int bits = 8;                             // per channel as stored: 8, or 16
  // The encoded file (PNG, JPEG, WebP, ...), shared by every copy of the description: it is
  // decoded only when a render scene is built (in parallel, materials/image_texture.h), never
  // by loading, copying or `glint info`.
  std::shared_ptr<const std::string> encoded;
  SourceLocation where;
};

enum class WrapMode { Repeat, ClampToEdge, MirroredRepeat, Black };

// Where a texture reads its coordinates (materials/texture.h, TextureMapping).
struct MappingDesc {
  enum class Space { Uv, Object, World } space = Space::Uv;
  enum class Plane { Xy, Xz, Yz } plane = Plane::Xy;  // 2D lookups in object/world space
  Vec3f scale{1, 1, 1}, offset{0, 0, 0};
  // UV space only: a rotation (radians) between the scale and the offset, glTF's
  // KHR_texture_transform (see TextureMapping).
  float uvRotation = 0;
  int uvSet = 0;  // UV space: which texture coordinate set (glTF texCoord 0 or 1)
};

enum class TextureKind {
  Image,      // a glTF texture: `image` with the glTF sampler's wrap and filter
  ImageFile,  // an image file named in the sidecar
  Checker,
  Noise,   // Perlin patterns (materials/procedural.h)
  Random,  // random colour per object / primitive / hit
};

enum class NoiseKind { Noise, Fbm, Turbulence, Marble, Wood, Clouds };

struct TextureDesc {
  std::string name;  // sidecar textures are referenced by name
  TextureKind kind = TextureKind::Image;
  int image = -1;                                                        // Image
  std::string file;                                                      // ImageFile: absolute path
  enum class Encoding { Auto, Srgb, Linear } encoding = Encoding::Auto;  // ImageFile
  WrapMode wrapS = WrapMode::Repeat, wrapT = WrapMode::Repeat;
  bool nearest = false;  // glTF magFilter NEAREST; otherwise filtered
  bool mipmap = true;    // MIP-mapped filtering (otherwise bilinear)
  MappingDesc mapping;
  // Checker and Noise: lerp(colorA, colorB, pattern weight).
  Rgb colorA{0, 0, 0}, colorB{1, 1, 1};
  bool solid = false;  // Checker: 3D cubes instead of 2D squares
  NoiseKind noise = NoiseKind::Noise;
  uint64_t seed = 0;  // Noise, Random
  int octaves = 5;
  float lacunarity = 2, gain = 0.5f, frequency = 4, distortion = 6, ringFrequency = 8,
        jitter = 0.6f;
  enum class RandomMode { Object, Primitive, Hit } randomMode = RandomMode::Object;
  SourceLocation where;
};

enum class MaterialType {
  Pbr,       // glTF pbrMetallicRoughness: GGX microfacet metal/dielectric (materials/pbr.h)
  Eyelight,  // colour x |cos(normal, view)|, no lights: the course's first shader
  Unlit,     // colour as radiance towards every ray, no lights (glTF KHR_materials_unlit)
  Lambert,
  Phong,       // energy-normalized Phong: diffuse + specular lobe
  BlinnPhong,  // the same with Blinn's half-vector lobe
  Mirror,      // perfect specular reflection, tinted by baseColor
  Glass,       // dielectric: Snell refraction + Fresnel, transmission tinted by baseColor
  Random,      // a deterministic random colour (eyelight- or Lambert-shaded)
};

enum class AlphaModeDesc { Opaque, Mask, Blend };

// glTF's material extensions on a metallic-roughness material (MaterialType::Pbr; pbr.h has
// the model). Textures are indices into SceneDescription::textures (-1: none), read in the
// channels the extensions name. The defaults leave every layer out.
struct MaterialLayersDesc {
  float specular = 1;  // KHR_materials_specular: strength (texture A)
  int specularTexture = -1;
  Rgb specularColor{1, 1, 1};  // colour of F0 (sRGB texture)
  int specularColorTexture = -1;
  float clearcoat = 0;  // KHR_materials_clearcoat (texture R)
  int clearcoatTexture = -1;
  float clearcoatRoughness = 0;  // (texture G)
  int clearcoatRoughnessTexture = -1;
  int clearcoatNormalTexture = -1;
  float clearcoatNormalScale = 1;
  Rgb sheenColor{0, 0, 0};  // KHR_materials_sheen (sRGB texture)
  int sheenColorTexture = -1;
  float sheenRoughness = 0;  // (texture A)
  int sheenRoughnessTexture = -1;
  float diffuseTransmission = 0;  // KHR_materials_diffuse_transmission (texture A)
  int diffuseTransmissionTexture = -1;
  Rgb diffuseTransmissionColor{1, 1, 1};  // (sRGB texture)
  int diffuseTransmissionColorTexture = -1;
  // KHR_materials_volume: a thickness above 0 makes transmission refract into a volume that
  // absorbs attenuationColor over attenuationDistance (infinite: clear); 0 is a thin sheet.
  float thickness = 0;
  Rgb attenuationColor{1, 1, 1};
  float attenuationDistance = kInfinity;
  float iridescence = 0;  // KHR_materials_iridescence (texture R)
  int iridescenceTexture = -1;
  float iridescenceIor = 1.3f;
  float iridescenceThicknessMin = 100, iridescenceThicknessMax = 400;  // nm
  int iridescenceThicknessTexture = -1;                                // G
  float anisotropy = 0, anisotropyRotation = 0;  // KHR_materials_anisotropy (radians)
  int anisotropyTexture = -1;                    // RG direction, B strength
  float dispersion = 0;                          // KHR_materials_dispersion: 20 / Abbe number
};

struct MaterialDesc {
  std::string name;
  MaterialType type = MaterialType::Pbr;
  Rgb baseColor{1, 1, 1};  // diffuse colour / glTF baseColorFactor.rgb (linear)
  float opacity = 1;       // glTF baseColorFactor.a; 1 - transparency (eyelight)
  AlphaModeDesc alphaMode = AlphaModeDesc::Opaque;
  float alphaCutoff = 0.5f;
  int baseColorTexture = -1;          // multiplied with baseColor (glTF: sRGB-encoded)
  float metallic = 1, roughness = 1;  // roughness also for glass (0: smooth)
  int metallicRoughnessTexture = -1;  // glTF: roughness in G, metallic in B (linear)
  Rgb emissive{0, 0, 0};              // emitted radiance (linear), multiplied by emissiveTexture
  int emissiveTexture = -1;           // sRGB-encoded
  int normalTexture = -1;             // tangent-space normal map (linear)
  float normalScale = 1;
  float ior = 1.5f;        // glass, pbr (KHR_materials_ior)
  float transmission = 0;  // pbr (KHR_materials_transmission), x its texture's R
  int transmissionTexture = -1;
  // pbr: transmission through a thin sheet instead of refraction into a volume (glTF
  // transmission without KHR_materials_volume; the sidecar's pbr materials refract).
  bool thinWalled = false;
  MaterialLayersDesc layers;  // pbr: glTF's material extensions
  Rgb specular{0, 0, 0};      // Phong specular colour
  float shininess = 0;        // Phong exponent
  int bumpTexture = -1;       // height map (scalar: luminance)
  float bumpStrength = 1;
  float snowAmount = 0;  // > 0: random normal jitter ("snow")
  float snowGrain = 0.01f;
  uint64_t snowSeed = 0;
  TextureDesc::RandomMode randomMode = TextureDesc::RandomMode::Object;  // Random
  uint64_t randomSeed = 0;
  bool randomLit = false;  // Random: Lambert instead of eyelight shading
  // Both sides of its meshes are seen (sidecar default). glTF materials are single-sided
  // unless the file says otherwise (the loader sets it); see TriangleMesh::singleSided.
  bool doubleSided = true;
  SourceLocation where;
};

// A morph target: displacements added, times its weight, to a mesh's attributes (glTF
// morph targets; tangent displacements move xyz only).
struct MorphTargetDesc {
  std::vector<Vec3f> positions, normals, tangents;  // each empty, or one per vertex
};

// One triangle primitive. A glTF mesh with several primitives becomes several MeshDescs.
// Skinned and morphed meshes are posed per instance by scenes/deform.h.
struct MeshDesc {
  std::string name;
  std::vector<Vec3f> positions;
  std::vector<Vec3f> normals;     // empty, or one unit normal per position
  std::vector<Vec4f> tangents;    // TANGENT: empty, or unit xyz + handedness w = +-1
  std::vector<Vec2f> uvs;         // TEXCOORD_0: empty or one per position
  std::vector<Vec2f> uvs1;        // TEXCOORD_1: empty or one per position
  std::vector<Vec4f> colors;      // COLOR_0 (linear RGBA): empty or one per position
  std::vector<uint32_t> indices;  // 3 per triangle; generated 0..n-1 when the file has none
  int material = -1;              // -1 = the default material (white Lambert)
  std::vector<MorphTargetDesc> targets;
  std::vector<float> weights;  // default morph weights (empty: all 0)
  // Skinning (JOINTS_0, WEIGHTS_0): four joints of the instance's skin per vertex and their
  // weights (empty when the mesh is not skinned).
  std::vector<std::array<uint16_t, 4>> joints;
  std::vector<Vec4f> jointWeights;
  // KHR_materials_variants: the material of each variant that changes it, by variant name.
  std::vector<std::pair<std::string, int>> variantMaterials;
  SourceLocation where;
};

// A glTF skin: joints whose world transforms, each after its inverse bind matrix, blend the
// vertices of the meshes it binds (linear blend skinning).
struct SkinDesc {
  struct Joint {
    int node = -1;    // animated placement (index into SceneDescription::nodes); -1 = static
    Transform world;  // the placement when static (at time 0 otherwise)
  };
  std::string name;
  std::vector<Joint> joints;
  std::vector<Transform> inverseBind;  // one per joint
  SourceLocation where;
};

enum class CameraType { Perspective, Orthographic };

struct CameraDesc {
  std::string name;
  CameraType type = CameraType::Perspective;
  float yfov = 0.8f;      // radians (perspective)
  float aspectRatio = 0;  // width / height; 0 = not given (use the image's)
  float znear = 0, zfar = kInfinity;
  float xmag = 1, ymag = 1;   // half extents (orthographic)
  Transform worldFromCamera;  // camera at the origin looking down -Z, +Y up (glTF)
  // Animated placement: worldFromNode(nodes, transformNode, t) · nodeFromCamera; -1 = static
  // (worldFromCamera). When set, worldFromCamera holds the placement at the load time.
  int transformNode = -1;
  Transform nodeFromCamera;
  // Thin lens (sidecar): aperture radius and focus distance in camera-space units (world
  // units unless the camera's transform scales); 0 = pinhole.
  float apertureRadius = 0;
  float focusDistance = 0;     // along the view axis; 0 = not given (required with an aperture)
  int apertureBlades = 0;      // 0 = round; >= 3: a regular polygon (bokeh shape)
  float apertureRotation = 0;  // radians, polygon orientation
  // Shutter interval in seconds relative to the frame's time; open == close = no motion blur.
  float shutterOpen = 0, shutterClose = 0;
  SourceLocation where;
};

enum class LightType { Point, Spot, Directional, Quad, Disk, Sphere, Projective };

// Units follow KHR_lights_punctual: point and spot intensity in candela (W/sr here),
// directional in lux (W/m^2 here). glint is RGB, so photometric units are used as radiometric.
struct LightDesc {
  std::string name;
  LightType type = LightType::Point;
  Rgb color{1, 1, 1};
  float intensity = 1;
  float range = 0;                                     // 0 = infinite
  float innerConeAngle = 0, outerConeAngle = kPi / 4;  // spot, radians
  Transform worldFromLight;                            // light at the origin, shining down -Z
  int transformNode = -1;  // animated placement (see CameraDesc); -1 = static
  Transform nodeFromLight;
  bool castsShadows = true;
  // Area lights (sidecar; color * intensity is their radiance), in the light's frame, which
  // worldFromLight places: quad corner + [0,1] edgeU + [0,1] edgeV, emitting towards
  // cross(edgeU, edgeV); disk of `radius` in the frame's XY plane facing -Z; sphere of
  // `radius` at the origin. One-sided unless twoSided.
  Vec3f corner, edgeU, edgeV;
  float radius = 1;
  bool twoSided = false;
  // Projective (sidecar): the slide's full field of view (radians), its texture (index into
  // SceneDescription::textures, -1 = none) and how much it attenuates, in [0, 1].
  float fov = kPi / 4;
  int texture = -1;
  float attenuation = 1;
  SourceLocation where;
};

// The environment at infinity (sidecar "environment", or --env): a constant colour, an
// equirectangular image (OpenEXR or Radiance .hdr) or the built-in studio
// (renderer/environment_light.h, also the default light of a scene without lights), times
// intensity, turned by `rotation` (radians) about +Y.
struct EnvironmentDesc {
  Rgb color{1, 1, 1};
  std::string image;    // path of the image (resolved against the sidecar's folder)
  bool studio = false;  // the built-in studio (then `image` is empty)
  float intensity = 1;
  float rotation = 0;
  SourceLocation where;
};

// A placement of a mesh in the world. A mesh used by several nodes appears in several
// instances and is built once.
struct InstanceDesc {
  int mesh = -1;
  Transform worldFromObject;
  std::string node;  // name of the glTF node, for messages
  SourceLocation where;
  int material = -1;       // a sidecar material assigned to the node; -1 = the mesh's own
  int transformNode = -1;  // animated placement (see CameraDesc); -1 = static
  Transform nodeFromObject;
  // A skinned instance (index into SceneDescription::skins): its skin places the vertices in
  // the world, and worldFromObject is the identity (glTF ignores the skinned node's transform).
  int skin = -1;
  std::vector<float> morphWeights;         // the node's weights (empty: the mesh's)
  std::vector<Track<float>> weightTracks;  // animated weights, one track per target (or none)
};

// ---------------------------------------------------------------------------------------------
// Analytic objects (sidecar "objects"): primitives, CSG trees, fractal terrain
// ---------------------------------------------------------------------------------------------

// An analytic primitive in its own object space. The loader makes and checks it through the
// shape registry (geometry/shapes/registry.h), so a description holds only valid shapes; each
// build of a render scene takes its own copy (Shape::clone).
using ShapeRef = std::shared_ptr<const Shape>;

enum class CsgOp { Leaf, Union, Intersection, Difference };

// A node of a CSG tree: a leaf primitive, or an operator over children. Union and
// intersection take two or more children; difference takes two or more and subtracts every
// child after the first from the first.
struct CsgNodeDesc {
  CsgOp op = CsgOp::Leaf;
  std::vector<int> children;  // indices into CsgTreeDesc::nodes
  ShapeRef shape;             // leaves: a solid (Shape::isSolid)
  int material = -1;          // leaves: index into SceneDescription::materials, -1 = the object's
  std::string materialName;   // as written in a .csg file; resolved to `material` by the loader
  Transform parentFromNode;   // this node's transform within its parent (identity by default)
  MeantTransform parentFromNodeMeant;  // the same, as meant (CsgShape's tie rule)
  SourceLocation where;
};

struct CsgTreeDesc {
  std::vector<CsgNodeDesc> nodes;
  int root = -1;
};

// The deepest CSG tree the loaders accept, in levels (a lone leaf is 1). Building and
// intersecting a tree recurse once per level; a deeper tree is a generated mistake, and it would
// overflow the stack instead of rendering.
inline constexpr int kMaxCsgDepth = 1000;

// Fractal terrain (geometry/terrain.h): a square of `size` in the XZ plane, centred on the
// origin, subdivided `depth` times with midpoint displacement (2 * 4^depth triangles).
struct TerrainDesc {
  float size = 100;
  int depth = 7;
  float roughness = 0.5f;  // ratio of displacement amplitude between successive levels
  Vec2f peak{0, 0};        // (x, z) of the highest point
  float height = 25;       // peak height
  uint64_t seed = 1;
};

enum class ObjectKind { Shape, Csg, Terrain };

struct ObjectDesc {
  std::string name;
  ObjectKind kind = ObjectKind::Shape;
  ShapeRef shape;  // ObjectKind::Shape
  CsgTreeDesc csg;
  TerrainDesc terrain;
  int material = -1;  // index into materials, -1 = the default material
  Transform worldFromObject;
  int transformNode = -1;  // animated placement (see CameraDesc); -1 = static
  Transform nodeFromObject;
  SourceLocation where;
};

// ---------------------------------------------------------------------------------------------
// Participating media (sidecar "media"; materials/medium.h, renderer/volume.h)
// ---------------------------------------------------------------------------------------------

enum class DensityType { Constant, Grid, Noise, Exponential, Vdb };

struct VdbVolume;  // materials/vdb_volume.h (read by scenes/vdb_file.h)

// A medium filling a region: a convex solid (`shape` placed by worldFromRegion), the solid of
// the analytic object `object`, or (neither) the whole scene.
struct MediumDesc {
  std::string name;
  enum class Region { Scene, Shape, Object } region = Region::Scene;
  ShapeRef shape;  // Region::Shape: a bounded solid (sphere, box, capped cylinder or cone)
  Transform worldFromRegion;  // Region::Shape
  int object = -1;            // Region::Object: index into SceneDescription::objects
  Rgb sigmaA{0, 0, 0}, sigmaS{0, 0, 0}, emission{0, 0, 0};
  float g = 0;
  bool heroTracking = true;  // "chromatic_tracking": "spectral_mis" (else "max_channel")
  DensityType density = DensityType::Constant;
  float value = 1;             // constant
  int gridRes[3] = {0, 0, 0};  // grid (x fastest in gridValues)
  std::vector<float> gridValues;
  float noiseScale = 1, noiseThreshold = 0;  // noise
  int noiseOctaves = 4;
  uint64_t noiseSeed = 0;
  Vec3f noiseOffset{0, 0, 0};  // noise: the pattern moves by this
  Vec3f up{0, 1, 0};           // exponential
  float falloff = 1, h0 = 0;
  // vdb: the grids read from the file (the region is the box of their active voxels, in the
  // file's world space placed by worldFromRegion), the density scale and the fire's emission
  std::shared_ptr<const VdbVolume> vdb;
  float vdbScale = 1;
  float blackbodyIntensity = 0;  // the temperature map is in the file's request
  float flameStrength = 0;
  Rgb flameColor{1, 1, 1};
  bool colorTintsAlbedo = false;  // "color_mode": "albedo" (else "scattering"); Medium's
  SourceLocation where;
};

struct SceneDescription {
  std::string file;  // the scene file the user named
  std::vector<ImageDesc> images;
  std::vector<TextureDesc> textures;
  std::vector<MaterialDesc> materials;
  std::vector<MeshDesc> meshes;
  std::vector<InstanceDesc> instances;
  std::vector<CameraDesc> cameras;
  std::vector<LightDesc> lights;
  std::optional<EnvironmentDesc> environment;
  std::vector<ObjectDesc> objects;  // analytic objects from the sidecar
  std::vector<MediumDesc> media;    // participating media from the sidecar
  // The transform hierarchy of everything animated (glTF nodes with animated ancestry,
  // sidecar objects with keyframes); items refer to it by transformNode.
  std::vector<NodeDesc> nodes;
  std::vector<SkinDesc> skins;
  std::vector<std::string> variants;  // KHR_materials_variants names, in file order
  RenderSettings render;
  // Things loaders accepted but did not use (e.g. glTF point or line primitives), one line
  // each with its location; `glint render` and `glint info` print them.
  std::vector<std::string> warnings;
};

// The sidecar's name of a material type ("blinn_phong").
const char* materialTypeName(MaterialType type);

// World-space bounds of all instances (skinned and morphed meshes at rest).
Bounds3f sceneBounds(const SceneDescription& scene);

// The first and last key time of every animation in the scene (node transforms and morph
// weights); {0, 0} when nothing is animated.
std::pair<double, double> animationRange(const SceneDescription& scene);

// Sets the static transform (worldFromObject, worldFromCamera, worldFromLight) of every item
// with a transformNode to its placement at `time`: worldFromNode(nodes, transformNode, time) ·
// nodeFrom*.
void evaluatePlacements(SceneDescription* scene, double time);

}  // namespace glint
