// glint — SceneDescription -> RenderScene.
#include "scenes/build.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>

#include "geometry/csg.h"
#include "geometry/terrain.h"
#include "image/oiio/plugin.h"
#include "materials/basic_materials.h"
#include "materials/bump.h"
#include "materials/image_texture.h"
#include "materials/pbr.h"
#include "materials/procedural.h"
#include "materials/specular.h"
#include "renderer/integrator.h"
#include "scenes/build_lights.h"
#include "scenes/build_media.h"
#include "scenes/deform.h"

namespace glint {

namespace {

using Clock = std::chrono::steady_clock;

// ---------------------------------------------------------------------------------------------
// Analytic objects
// ---------------------------------------------------------------------------------------------

CsgOperation csgOperation(CsgOp op) {
  switch (op) {
    case CsgOp::Intersection:
      return CsgOperation::Intersection;
    case CsgOp::Difference:
      return CsgOperation::Difference;
    default:
      return CsgOperation::Union;
  }
}

// Adds `node` of `tree` (and its subtree) to `csg`, with transforms composed down to the
// leaves; `leafMaterials` receives each leaf's material (-1 = the object's) in leaf order.
uint32_t addCsgNode(const CsgTreeDesc& tree, int node, const Transform& treeFromParent,
                    const MeantTransform& treeFromParentMeant, CsgShape* csg,
                    std::vector<int>* leafMaterials) {
  const CsgNodeDesc& n = tree.nodes[size_t(node)];
  const Transform treeFromNode = treeFromParent * n.parentFromNode;
  const MeantTransform treeFromNodeMeant = treeFromParentMeant * n.parentFromNodeMeant;
  if (n.op == CsgOp::Leaf) {
    leafMaterials->push_back(n.material);
    return csg->addLeaf(n.shape->clone(), treeFromNode,
                        treeFromNodeMeant.errorOf(treeFromNode.matrix()));
  }
  std::vector<uint32_t> children;
  for (int c : n.children)
    children.push_back(addCsgNode(tree, c, treeFromNode, treeFromNodeMeant, csg, leafMaterials));
  return csg->addOperation(csgOperation(n.op), std::move(children));
}

TerrainParams terrainParams(const TerrainDesc& d) {
  TerrainParams p;
  p.size = d.size;
  p.depth = d.depth;
  p.roughness = d.roughness;
  p.peak = d.peak;
  p.height = d.height;
  p.seed = d.seed;
  return p;
}

SourceLocation commandLineOr(const SceneDescription& desc, const char* pointer) {
  return {desc.file, pointer};
}

// The camera the settings select: by name, else the first one; nullptr when there is none.
const CameraDesc* selectCamera(const SceneDescription& desc) {
  const std::string& name = desc.render.camera;
  if (name.empty()) return desc.cameras.empty() ? nullptr : &desc.cameras.front();
  for (const CameraDesc& c : desc.cameras)
    if (c.name == name) return &c;
  std::vector<std::string> names;
  for (const CameraDesc& c : desc.cameras) names.push_back(c.name);
  const std::string known = quotedNames(names);
  throw SceneError(
      commandLineOr(desc, "/render/camera"),
      "no camera named '" + name + "'" +
          (known.empty() ? " (the scene has no cameras)" : " (cameras: " + known + ")"));
}

// A perspective camera that frames the scene bounds for an image of the given aspect, looking
// from the front and a little above: the eight corners of the bounds fit the view with a 5%
// margin, so the scene fills the frame rather than its bounding sphere.
CameraDesc framingCamera(const Bounds3f& bounds, float aspect) {
  CameraDesc c;
  c.name = "default";
  c.yfov = 40.0f * kPi / 180.0f;
  Vec3f center = bounds.empty() ? Vec3f{} : bounds.center();
  Vec3f back = normalize(Vec3f{0.35f, 0.45f, 1.0f});  // from the target towards the eye
  Transform orient = Transform::lookAt(back, {0, 0, 0}, {0, 1, 0});
  Vec3f right = orient.vector({1, 0, 0}), up = orient.vector({0, 1, 0});
  float tanY = std::tan(c.yfov / 2) / 1.05f, tanX = tanY * aspect;
  float dist = 0;
  if (!bounds.empty())
    for (int i = 0; i < 8; ++i) {
      Vec3f corner{(i & 1) ? bounds.upper.x : bounds.lower.x,
                   (i & 2) ? bounds.upper.y : bounds.lower.y,
                   (i & 4) ? bounds.upper.z : bounds.lower.z};
      Vec3f r = corner - center;
      float z = dot(r, back);  // towards the eye
      dist = std::max({dist, z + std::abs(dot(r, right)) / tanX, z + std::abs(dot(r, up)) / tanY});
    }
  if (!(dist > 0)) dist = 1;
  c.worldFromCamera = Transform::lookAt(center + back * dist, center, {0, 1, 0});
  c.znear = 0;
  return c;
}

TextureWrap toWrap(WrapMode m) {
  switch (m) {
    case WrapMode::ClampToEdge:
      return TextureWrap::Clamp;
    case WrapMode::MirroredRepeat:
      return TextureWrap::Mirror;
    case WrapMode::Black:
      return TextureWrap::Black;
    case WrapMode::Repeat:
    default:
      return TextureWrap::Repeat;
  }
}

TextureMapping toMapping(const MappingDesc& d) {
  TextureMapping m;
  m.space = d.space == MappingDesc::Space::Object  ? TextureMapping::Space::Object
            : d.space == MappingDesc::Space::World ? TextureMapping::Space::World
                                                   : TextureMapping::Space::Uv;
  m.plane = d.plane == MappingDesc::Plane::Xz   ? TextureMapping::Plane::Xz
            : d.plane == MappingDesc::Plane::Yz ? TextureMapping::Plane::Yz
                                                : TextureMapping::Plane::Xy;
  m.scale = d.scale;
  m.offset = d.offset;
  m.setUvRotation(d.uvRotation);
  m.uvSet = d.uvSet;
  return m;
}

NoiseParams toNoiseParams(const TextureDesc& d) {
  NoiseParams p;
  switch (d.noise) {
    case NoiseKind::Noise:
      p.pattern = NoisePattern::Noise;
      break;
    case NoiseKind::Fbm:
      p.pattern = NoisePattern::Fbm;
      break;
    case NoiseKind::Turbulence:
      p.pattern = NoisePattern::Turbulence;
      break;
    case NoiseKind::Marble:
      p.pattern = NoisePattern::Marble;
      break;
    case NoiseKind::Wood:
      p.pattern = NoisePattern::Wood;
      break;
    case NoiseKind::Clouds:
      p.pattern = NoisePattern::Clouds;
      break;
  }
  p.seed = d.seed;
  p.octaves = d.octaves;
  p.lacunarity = d.lacunarity;
  p.gain = d.gain;
  p.frequency = d.frequency;
  p.distortion = d.distortion;
  p.ringFrequency = d.ringFrequency;
  p.jitter = d.jitter;
  p.colorA = d.colorA;
  p.colorB = d.colorB;
  return p;
}

RandomColorTexture::Mode toRandomMode(TextureDesc::RandomMode m) {
  switch (m) {
    case TextureDesc::RandomMode::Primitive:
      return RandomColorTexture::Mode::Primitive;
    case TextureDesc::RandomMode::Hit:
      return RandomColorTexture::Mode::Hit;
    case TextureDesc::RandomMode::Object:
    default:
      return RandomColorTexture::Mode::Object;
  }
}

// Creates textures on demand, one per (texture, encoding), sharing decoded images.
class TextureCache {
 public:
  TextureCache(const SceneDescription& desc, SceneParts* scene,
               std::shared_ptr<TextureImages> reuse)
      : desc_(desc), scene_(scene), reuse_(std::move(reuse)) {}
  // Texture `texture` of the description; `srgb` is how a glTF image's colour is encoded
  // (glTF fixes it per use: base colour and emission sRGB, the others linear).
  const Texture* get(int texture, bool srgb) {
    if (texture < 0) return nullptr;
    auto key = std::make_pair(texture, srgb);
    if (auto it = textures_.find(key); it != textures_.end()) return it->second;
    scene_->textures.push_back(make(desc_.textures[size_t(texture)], srgb));
    return textures_[key] = scene_->textures.back().get();
  }
  // The textures made so far, by (description texture, sRGB); and made ones to use again
  // (refreshMaterials: a new material reads the render scene's own).
  const std::map<std::pair<int, bool>, const Texture*>& made() const { return textures_; }
  void reuse(const std::map<std::pair<int, bool>, const Texture*>& made) { textures_ = made; }
  Texture* add(std::unique_ptr<Texture> t) {
    scene_->textures.push_back(std::move(t));
    return scene_->textures.back().get();
  }
  // Waits for the glTF images' pixels (`images`: the set this cache filled, wherever the
  // parts went since); one that cannot be decoded is a SceneError at the image.
  void waitForDecodes(TextureImages* images) {
    if (!images) return;
    for (const auto& [name, reason] : images->waitForDecodes())
      if (auto it = imageWhere_.find(name); it != imageWhere_.end())
        throw SceneError(it->second, reason);
  }

 private:
  std::unique_ptr<Texture> make(const TextureDesc& td, bool srgb) {
    switch (td.kind) {
      case TextureKind::Checker:
        return std::make_unique<CheckerTexture>(toMapping(td.mapping), td.colorA, td.colorB,
                                                td.solid);
      case TextureKind::Noise:
        return std::make_unique<NoiseTexture>(toMapping(td.mapping), toNoiseParams(td));
      case TextureKind::Random:
        return std::make_unique<RandomColorTexture>(toRandomMode(td.randomMode), td.seed);
      case TextureKind::ImageFile:
      case TextureKind::Image:
      default:
        return std::make_unique<ImageTexture>(images(), image(td, srgb), toMapping(td.mapping),
                                              toWrap(td.wrapS), toWrap(td.wrapT),
                                              td.nearest  ? TextureFilter::Nearest
                                              : td.mipmap ? TextureFilter::Mipmap
                                                          : TextureFilter::Linear);
    }
  }

  TextureImages& images() {
    if (!scene_->images)
      scene_->images =
          reuse_ ? std::move(reuse_) : std::make_shared<TextureImages>(&oiio::imageDecoder);
    return *scene_->images;
  }

  // The image of `td` in the scene's TextureImages, added once per (image, encoding).
  TextureImages::Handle image(const TextureDesc& td, bool srgb) {
    try {
      if (td.kind == TextureKind::ImageFile) {
        bool fileSrgb = td.encoding == TextureDesc::Encoding::Srgb ||
                        (td.encoding == TextureDesc::Encoding::Auto && !isLinearFormat(td.file));
        auto key = std::make_pair(td.file, fileSrgb);
        if (auto it = files_.find(key); it != files_.end()) return it->second;
        const ColorEncoding enc = fileSrgb ? ColorEncoding::Srgb : ColorEncoding::Linear;
        if (auto h = images().findFile(td.file, enc); h.valid()) return files_[key] = h;
        return files_[key] = images().addFile(td.file, enc);
      }
      auto key = std::make_pair(td.image, srgb);
      if (auto it = pixels_.find(key); it != pixels_.end()) return it->second;
      const ImageDesc& img = desc_.images[size_t(td.image)];
      std::string name =
          img.name + (srgb ? " (sRGB)" : " (linear)") + " #" + std::to_string(td.image);
      if (auto h = images().findEncoded(name, img.encoded.get()); h.valid()) {
        imageWhere_[name] = img.where;
        return pixels_[key] = h;
      }
      // An earlier frame's set may hold another image under this name (other bytes).
      const std::string base = name;
      for (int k = 2; images().contains(name); ++k) name = base + " [" + std::to_string(k) + "]";
      imageWhere_[name] = img.where;
      return pixels_[key] = images().addEncoded(name, img.encoded,
                                                srgb ? ColorEncoding::Srgb : ColorEncoding::Linear);
    } catch (const InputError& e) {
      // The image cannot be read ("<file>: <reason>", TextureImages): at the texture. A
      // FailureError (the OpenImageIO plugin is missing) and a bug pass as they are.
      throw SceneError(td.where, e.what());
    }
  }

  // Formats that store linear values (HDR, floating point); others are taken as sRGB.
  static bool isLinearFormat(const std::string& file) {
    std::string ext = std::filesystem::path(file).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".exr" || ext == ".hdr" || ext == ".tx" || ext == ".pfm";
  }

  const SceneDescription& desc_;
  SceneParts* scene_;
  std::map<std::pair<int, bool>, const Texture*> textures_;
  std::map<std::pair<int, bool>, TextureImages::Handle> pixels_;
  std::map<std::pair<std::string, bool>, TextureImages::Handle> files_;
  std::map<std::string, SourceLocation> imageWhere_;  // registered name -> the glTF image
  std::shared_ptr<TextureImages> reuse_;              // an earlier frame's set, taken on first use
};

AlphaMode toAlphaMode(AlphaModeDesc m) {
  switch (m) {
    case AlphaModeDesc::Mask:
      return AlphaMode::Mask;
    case AlphaModeDesc::Blend:
      return AlphaMode::Blend;
    case AlphaModeDesc::Opaque:
    default:
      return AlphaMode::Opaque;
  }
}

// glTF's material extensions (MaterialLayersDesc) as PbrParams.
void addLayers(const MaterialDesc& m, TextureCache& textures, PbrParams* p) {
  const MaterialLayersDesc& l = m.layers;
  auto linear = [&](int texture) { return textures.get(texture, false); };
  auto srgb = [&](int texture) { return textures.get(texture, true); };
  p->specular = {l.specular, linear(l.specularTexture), 3};
  p->specularColor = {l.specularColor, srgb(l.specularColorTexture), false};
  p->clearcoat = {l.clearcoat, linear(l.clearcoatTexture), 0};
  p->clearcoatRoughness = {l.clearcoatRoughness, linear(l.clearcoatRoughnessTexture), 1};
  p->clearcoatNormal = linear(l.clearcoatNormalTexture);
  p->clearcoatNormalScale = l.clearcoatNormalScale;
  p->sheenColor = {l.sheenColor, srgb(l.sheenColorTexture), false};
  p->sheenRoughness = {l.sheenRoughness, linear(l.sheenRoughnessTexture), 3};
  p->diffuseTransmission = {l.diffuseTransmission, linear(l.diffuseTransmissionTexture), 3};
  p->diffuseTransmissionColor = {l.diffuseTransmissionColor,
                                 srgb(l.diffuseTransmissionColorTexture), false};
  p->iridescence = {l.iridescence, linear(l.iridescenceTexture), 0};
  p->iridescenceIor = l.iridescenceIor;
  p->iridescenceThicknessMin = l.iridescenceThicknessMin;
  p->iridescenceThicknessMax = l.iridescenceThicknessMax;
  p->iridescenceThickness = linear(l.iridescenceThicknessTexture);
  p->anisotropy = l.anisotropy;
  p->anisotropyRotation = l.anisotropyRotation;
  p->anisotropyTexture = linear(l.anisotropyTexture);
  p->dispersion = l.dispersion;
  // KHR_materials_volume: Beer-Lambert absorption inside, sigma = -ln(colour) / distance (a
  // black channel absorbs everything: a large finite sigma keeps the arithmetic finite).
  if (!m.thinWalled && std::isfinite(l.attenuationDistance))
    for (int c = 0; c < 3; ++c)
      p->absorption[c] = std::min(-std::log(std::max(l.attenuationColor[c], 1e-30f)), 69.0f) /
                         l.attenuationDistance;
}

// The material of m's type (how it scatters and emits), before the modifiers every type shares
// (alpha, normal or bump map, snow), which makeMaterial adds.
std::unique_ptr<Material> makeTypedMaterial(const MaterialDesc& m, const ColorParam& base,
                                            const ColorParam& emission, TextureCache& textures) {
  switch (m.type) {
    case MaterialType::Eyelight:
      return std::make_unique<EyelightMaterial>(base);
    case MaterialType::Unlit:
      return std::make_unique<UnlitMaterial>(base);
    case MaterialType::Phong:
    case MaterialType::BlinnPhong:
      for (int c = 0; c < 3; ++c)
        if (m.baseColor[c] * (base.texture ? base.texture->upperBound()[c] : 1.0f) + m.specular[c] >
            1.0f + 1e-6f)
          throw SceneError(m.where,
                           "Phong diffuse + specular exceeds 1 in a channel; the "
                           "material would reflect more light than it receives");
      return std::make_unique<PhongMaterial>(base, m.specular, m.shininess, emission,
                                             m.type == MaterialType::BlinnPhong);
    case MaterialType::Mirror:
      return std::make_unique<MirrorMaterial>(base);
    case MaterialType::Glass: {
      if (m.roughness <= 0) return std::make_unique<GlassMaterial>(m.ior, base);
      // Rough glass: the microfacet dielectric (all transmission, no diffuse part).
      PbrParams p;
      p.baseColor = base;
      p.metallic = {0};
      p.roughness = {m.roughness};
      p.ior = m.ior;
      p.transmission = {1};
      return std::make_unique<PbrMaterial>(p);
    }
    case MaterialType::Pbr: {
      PbrParams p;
      p.baseColor = base;
      const Texture* mr = textures.get(m.metallicRoughnessTexture, false);
      p.metallic = {m.metallic, mr, 2};    // glTF: metallic in B
      p.roughness = {m.roughness, mr, 1};  // roughness in G
      p.emission = emission;
      p.ior = m.ior;
      p.transmission = {m.transmission, textures.get(m.transmissionTexture, false), 0};
      p.thinWalled = m.thinWalled;
      addLayers(m, textures, &p);
      return std::make_unique<PbrMaterial>(p);
    }
    case MaterialType::Random: {
      ColorParam random{{1, 1, 1},
                        textures.add(std::make_unique<RandomColorTexture>(
                            toRandomMode(m.randomMode), m.randomSeed)),
                        false};
      if (m.randomLit) return std::make_unique<LambertMaterial>(random, emission);
      return std::make_unique<EyelightMaterial>(random);
    }
    case MaterialType::Lambert:
    default:
      return std::make_unique<LambertMaterial>(base, emission);
  }
}

std::unique_ptr<Material> makeMaterial(const MaterialDesc& m, bool vertexColors,
                                       TextureCache& textures) {
  ColorParam base{m.baseColor, textures.get(m.baseColorTexture, true), vertexColors};
  ColorParam emission{m.emissive, textures.get(m.emissiveTexture, true), false};
  std::unique_ptr<Material> material = makeTypedMaterial(m, base, emission, textures);
  if (m.alphaMode != AlphaModeDesc::Opaque)
    material->setAlpha(toAlphaMode(m.alphaMode), m.opacity, m.alphaCutoff, base);
  if (m.normalTexture >= 0)
    material->setNormalModifier(
        std::make_unique<NormalMap>(textures.get(m.normalTexture, false), m.normalScale));
  else if (m.bumpTexture >= 0)
    material->setNormalModifier(
        std::make_unique<BumpMap>(textures.get(m.bumpTexture, false), m.bumpStrength));
  else if (m.snowAmount > 0)
    material->setNormalModifier(
        std::make_unique<SnowPerturbation>(m.snowAmount, m.snowGrain, m.snowSeed));
  return material;
}

// ---------------------------------------------------------------------------------------------
// Motion: placements sampled over the shutter
// ---------------------------------------------------------------------------------------------

// The scene times the shutter of the selected camera spans for this frame.
struct ShutterTimes {
  double open = 0, close = 0;
  bool moves() const { return close > open; }
};

// How far an interpolated placement may stray from the animation between its keys: a
// thousandth of the object's unit length (the test points are the object-space origin and unit
// axes). Small enough to be invisible, large enough that a smooth motion needs few keys.
constexpr float kMotionTolerance = 1e-3f;

// The largest distance between where `exact` and `approx` put the object-space origin and unit
// axes, relative to the larger of the exact axes' lengths.
float placementError(const Transform& exact, const Transform& approx) {
  float error = 0, scale = 0;
  for (Vec3f p : {Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, 0, 1}}) {
    error = std::max(error, length(exact.point(p) - approx.point(p)));
    if (p != Vec3f{0, 0, 0}) scale = std::max(scale, length(exact.vector(p)));
  }
  return scale > 0 ? error / scale : error;
}

// The placement worldFromNode(node, t) · nodeFromItem over the shutter, as keys at uniform
// times (Embree's time steps are uniform). Starting from one segment, the number of segments
// doubles until the interpolation (slerp for rotation, linear for scale and translation, as
// Embree blends) stays within kMotionTolerance of the animation at a quarter, the middle and
// three quarters of every segment and no segment turns by more than 90 degrees (slerp would
// take the short way). A single node moving linearly is then one segment; an object off its
// node's pivot swinging on an arc, curves and kinks get as many as they need, up to Embree's
// limit (a step inside the shutter never converges: it becomes a fast ramp). `staticWorld` is
// used when nothing moves.
AnimatedTransform placementOverShutter(const std::vector<NodeDesc>& nodes, int node,
                                       const Transform& nodeFromItem, const Transform& staticWorld,
                                       const ShutterTimes& shutter) {
  if (node < 0) return AnimatedTransform(staticWorld);
  auto at = [&](double t) { return worldFromNode(nodes, node, t) * nodeFromItem; };
  if (!shutter.moves() || !isAnimated(nodes, node)) return AnimatedTransform(at(shutter.open));
  const double span = shutter.close - shutter.open;
  for (int segments = 1;; segments *= 2) {
    std::vector<Transform> keys;
    keys.reserve(size_t(segments) + 1);
    for (int i = 0; i <= segments; ++i) keys.push_back(at(shutter.open + span * i / segments));
    AnimatedTransform motion(std::move(keys));
    if (2 * size_t(segments) + 1 > kMaxMotionKeys) return motion;
    bool good = true;
    for (int i = 0; good && i < segments; ++i) {
      if (motion.isAnimated() && std::abs(dot(motion.decomposedKey(size_t(i)).rotation,
                                              motion.decomposedKey(size_t(i) + 1).rotation)) <
                                     0.7071f) {  // cos(45°): a turn of over 90 degrees
        good = false;
        break;
      }
      for (double f : {0.25, 0.5, 0.75}) {
        const double u = (i + f) / segments;
        if (placementError(at(shutter.open + span * u), motion.at(float(u))) > kMotionTolerance) {
          good = false;
          break;
        }
      }
    }
    if (good) return motion;
  }
}

// A placement fixed for the frame (lights): the middle of the shutter, where it is closest on
// average to the geometry that moves with it (a lamp on a moving rig lights from the middle of
// its own blur streak rather than from one end).
Transform placementAtShutterMiddle(const std::vector<NodeDesc>& nodes, int node,
                                   const Transform& nodeFromItem, const Transform& staticWorld,
                                   const ShutterTimes& shutter) {
  return node < 0 ? staticWorld
                  : worldFromNode(nodes, node, 0.5 * (shutter.open + shutter.close)) * nodeFromItem;
}

// Lights are placed once per frame, where they are in the middle of the shutter.
void addLights(const SceneDescription& desc, const ShutterTimes& shutter, TextureCache* textures,
               SceneParts* scene) {
  for (const LightDesc& l : desc.lights) {
    Rgb power = l.color * l.intensity;
    Transform worldFromLight = placementAtShutterMiddle(desc.nodes, l.transformNode,
                                                        l.nodeFromLight, l.worldFromLight, shutter);
    Vec3f position = worldFromLight.point({0, 0, 0});
    Vec3f direction = normalize(worldFromLight.vector({0, 0, -1}));
    switch (l.type) {
      case LightType::Point:
        scene->lights.push_back(
            std::make_unique<PointLight>(position, power, l.range, l.castsShadows));
        break;
      case LightType::Spot:
        scene->lights.push_back(std::make_unique<SpotLight>(position, direction, power,
                                                            l.innerConeAngle, l.outerConeAngle,
                                                            l.range, l.castsShadows));
        break;
      case LightType::Directional:
        scene->lights.push_back(
            std::make_unique<DirectionalLight>(direction, power, l.castsShadows));
        break;
      default:  // area and projective lights (build_lights.cpp)
        scene->lights.push_back(makeSidecarLight(
            l, worldFromLight,
            l.type == LightType::Projective ? textures->get(l.texture, true) : nullptr));
        break;
    }
  }
}

}  // namespace

void resolveImageSize(const SceneDescription& desc, const CameraDesc* camera, int* width,
                      int* height) {
  float aspect = 4.0f / 3.0f;
  if (camera) {
    if (camera->aspectRatio > 0)
      aspect = camera->aspectRatio;
    else if (camera->type == CameraType::Orthographic && camera->ymag > 0)
      aspect = camera->xmag / camera->ymag;
  }
  const RenderSettings& r = desc.render;
  if (r.width && r.height) {
    *width = *r.width, *height = *r.height;
  } else if (r.width) {
    *width = *r.width, *height = std::max(1, int(std::lround(float(*r.width) / aspect)));
  } else if (r.height) {
    *height = *r.height, *width = std::max(1, int(std::lround(float(*r.height) * aspect)));
  } else {
    *width = 640, *height = std::max(1, int(std::lround(640.0f / aspect)));
  }
}

void imageSize(const SceneDescription& desc, int* width, int* height) {
  resolveImageSize(desc, selectCamera(desc), width, height);
}

// ---------------------------------------------------------------------------------------------
// The render scene, step by step (pbrt-v4's CreateMaterials / CreateLights / CreateAggregate)
// ---------------------------------------------------------------------------------------------

namespace {

// What the geometry step leaves for the material step: which description material each
// geometry mesh and each analytic shape's slot takes.
struct GeometryMaterials {
  struct Mesh {
    int material;  // description material, -1 = default
    bool colors;   // the mesh has vertex colours
  };
  std::vector<Mesh> meshes;                  // per geometry mesh
  std::vector<std::vector<int>> shapeSlots;  // per geometry shape: per material slot
  bool terrain = false;                      // a fractal terrain was meshed
};

// The material of `mesh` in variant `variant` (KHR_materials_variants): the variant's mapping,
// else the mesh's own.
int variantMaterial(const MeshDesc& mesh, const std::string& variant) {
  if (!variant.empty())
    for (const auto& [name, material] : mesh.variantMaterials)
      if (name == variant) return material;
  return mesh.material;
}

// Whether a mesh's vertices keep their detail when baked into world coordinates: the world
// box's largest coordinate is at most 1024 times the mesh's own size, so the float grid there
// (2^-23 of the coordinate) stays below 1e-4 of the mesh (a fraction of a pixel wherever the
// mesh fills one).
bool keepsDetailBaked(const std::vector<Vec3f>& positions, const Transform& world) {
  Bounds3f object;
  for (Vec3f p : positions) object.extend(p);
  if (object.empty()) return true;
  Bounds3f placed;
  for (int c = 0; c < 8; ++c)
    placed.extend(world.point({c & 1 ? object.upper.x : object.lower.x,
                               c & 2 ? object.upper.y : object.lower.y,
                               c & 4 ? object.upper.z : object.lower.z}));
  const float size = length(placed.diagonal());
  const float reach = maxComponent(max(abs(placed.lower), abs(placed.upper)));
  return reach <= 1024 * size;
}

// Whether `m` shades in glTF's tangent space: a normal map or anisotropy.
bool readsTangentSpace(const MaterialDesc& m) {
  return m.normalTexture >= 0 || m.layers.clearcoatNormalTexture >= 0 || m.layers.anisotropy > 0;
}

// Tangents for a mesh whose file gives none, when its material reads glTF's tangent space (a
// normal map or anisotropy): per vertex from the uv set the normal map reads (vertexTangents),
// as MikkTSpace would make them. Without normals or that uv set, or for materials that do not
// need them, none: the shading then takes each triangle's dp/du (bump.h, tangentFrame).
std::vector<Vec4f> derivedTangents(const SceneDescription& desc, const MeshDesc& mesh,
                                   int material) {
  if (!mesh.tangents.empty() || mesh.normals.empty() || material < 0 ||
      size_t(material) >= desc.materials.size())
    return mesh.tangents;
  const MaterialDesc& m = desc.materials[size_t(material)];
  if (!readsTangentSpace(m)) return {};
  const int map = m.normalTexture >= 0 ? m.normalTexture : m.layers.clearcoatNormalTexture;
  const int uvSet = map >= 0 ? desc.textures[size_t(map)].mapping.uvSet : 0;
  const std::vector<Vec2f>& uvs = uvSet == 1 ? mesh.uvs1 : mesh.uvs;
  if (uvs.empty()) return {};
  return vertexTangents(mesh.positions, mesh.normals, uvs, mesh.indices);
}

// Deformation blur: a skinned or morphed instance whose pose changes inside the shutter gets
// time steps (TriangleMesh::positionSteps), posed at K = 2^n + 1 uniform times over it. From
// two segments, the count doubles until posing at the middle of every segment lands within
// kMotionTolerance of the mesh's size (its middle pose's diagonal) of the linear blend of the
// segment's ends, for every vertex, or K reaches Embree's limit; the poses tested become the
// finer level's new steps, so nothing is posed twice. A morph whose weights change linearly
// over the shutter needs 3 steps; a limb swinging through an arc a few more. The middle step
// is `mesh`'s own positions and normals (the pose the rest of the renderer sees).
void poseOverShutter(const SceneDescription& desc, const InstanceDesc& inst,
                     const ShutterTimes& shutter, TriangleMesh* mesh) {
  const double span = shutter.close - shutter.open;
  std::vector<std::vector<Vec3f>> positions(3), normals(3);
  for (int i = 0; i < 3; ++i)
    posedVertices(desc, inst, shutter.open + span * i / 2, &positions[size_t(i)],
                  &normals[size_t(i)]);
  Bounds3f middle;
  for (Vec3f p : positions[1]) middle.extend(p);
  const float tolerance = kMotionTolerance * length(middle.upper - middle.lower);
  while (2 * positions.size() - 1 <= kMaxMotionKeys) {
    const size_t segments = positions.size() - 1;
    std::vector<std::vector<Vec3f>> midP(segments), midN(segments);
    float error = 0;
    for (size_t i = 0; i < segments; ++i) {
      posedVertices(desc, inst, shutter.open + span * (double(i) + 0.5) / double(segments),
                    &midP[i], &midN[i]);
      for (size_t v = 0; v < midP[i].size(); ++v)
        error =
            std::max(error, length(midP[i][v] - 0.5f * (positions[i][v] + positions[i + 1][v])));
    }
    if (!(error > tolerance)) break;  // a NaN pose stops refining too
    std::vector<std::vector<Vec3f>> finerP, finerN;
    for (size_t i = 0; i <= segments; ++i) {
      finerP.push_back(std::move(positions[i]));
      finerN.push_back(std::move(normals[i]));
      if (i < segments) {
        finerP.push_back(std::move(midP[i]));
        finerN.push_back(std::move(midN[i]));
      }
    }
    positions = std::move(finerP);
    normals = std::move(finerN);
  }
  const size_t mid = positions.size() / 2;
  mesh->positions = positions[mid];
  mesh->positionSteps = std::move(positions);
  if (!mesh->normals.empty()) {
    mesh->normals = normals[mid];
    mesh->normalSteps = std::move(normals);
  }
}

// The description's glTF instances into scene->geometry: single static placements are baked
// into world space, shared or moving meshes instanced. A mesh that nodes give different
// materials is one geometry mesh per material.
void buildMeshes(const SceneDescription& desc, const ShutterTimes& shutter, SceneParts* scene,
                 GeometryMaterials* materials) {
  using MeshKey = std::pair<int, int>;  // (description mesh, node material or -1)
  std::map<MeshKey, uint32_t> uses;
  for (const InstanceDesc& inst : desc.instances) ++uses[{inst.mesh, inst.material}];
  std::map<MeshKey, uint32_t> meshIndex;
  for (const InstanceDesc& inst : desc.instances) {
    const MeshKey key{inst.mesh, inst.material};
    AnimatedTransform motion = placementOverShutter(
        desc.nodes, inst.transformNode, inst.nodeFromObject, inst.worldFromObject, shutter);
    const Transform& world = motion.key(0);
    // Skinned and morphed instances get a mesh of their own, posed at the shutter's middle
    // (and over the shutter when the pose changes inside it: poseOverShutter).
    const bool posed = deforms(desc, inst);
    MeshDesc posedDesc;
    if (posed) posedDesc = posedMesh(desc, inst, 0.5 * (shutter.open + shutter.close));
    const MeshDesc& md = posed ? posedDesc : desc.meshes[size_t(inst.mesh)];
    // A moving mesh keeps its object space: Embree moves it as an instance. So does a mesh
    // placed far from the origin for its size: baked there, its vertices would snap to the
    // float grid of the world coordinates (0.06 at 1e6), and a dragon 8 units long lost its
    // shape; in object space the placement's rounding is the instance transform's alone.
    const bool bake =
        (posed || uses[key] == 1) && !motion.isAnimated() && keepsDetailBaked(md.positions, world);
    scene->objectFromWorld.push_back(world.inverse());
    if (auto it = meshIndex.find(key); !posed && !bake && it != meshIndex.end()) {
      Instance placed{it->second, world};
      placed.motion = motion;
      scene->geometry.instances.push_back(placed);
      continue;
    }
    const int material =
        inst.material >= 0 ? inst.material : variantMaterial(md, desc.render.variant);
    TriangleMesh mesh;
    mesh.positions = md.positions;
    mesh.normals = md.normals;
    mesh.tangents = derivedTangents(desc, md, material);
    mesh.uvs = md.uvs;
    mesh.uvs1 = md.uvs1;
    mesh.colors = md.colors;
    mesh.indices = md.indices;
    if (posed && shutter.moves() && deformationAnimated(desc, inst))
      poseOverShutter(desc, inst, shutter, &mesh);
    Transform placement = world;
    if (bake && !placement.isIdentity()) {
      placeVertices(placement, &mesh.positions, &mesh.indices);
      for (Vec3f& n : mesh.normals) n = normalize(placement.normal(n));
      for (std::vector<Vec3f>& step : mesh.positionSteps)
        for (Vec3f& p : step) p = placement.point(p);
      for (std::vector<Vec3f>& step : mesh.normalSteps)
        for (Vec3f& n : step) n = normalize(placement.normal(n));
      // A mirroring placement turns cross(n, t) against the bitangent it carries: w flips.
      const float handedness = placement.swapsHandedness() ? -1.0f : 1.0f;
      for (Vec4f& t : mesh.tangents) {
        Vec3f v = normalize(placement.vector({t.x, t.y, t.z}));
        t = {v.x, v.y, v.z, t.w * handedness};
      }
      placement = Transform();
    }
    if (!posed) meshIndex[key] = uint32_t(scene->geometry.meshes.size());
    materials->meshes.push_back({material, !md.colors.empty()});
    scene->geometry.meshes.push_back(std::move(mesh));
    Instance placed{uint32_t(scene->geometry.meshes.size() - 1), placement};
    if (motion.isAnimated()) placed.motion = motion;
    scene->geometry.instances.push_back(placed);
  }
}

// The sidecar's objects into scene->geometry: shapes and CSG trees stay in object space under
// their transform; terrain becomes a triangle mesh, baked into world space.
void buildObjects(const SceneDescription& desc, const ShutterTimes& shutter, SceneParts* scene,
                  GeometryMaterials* materials) {
  for (const ObjectDesc& obj : desc.objects) {
    AnimatedTransform motion = placementOverShutter(
        desc.nodes, obj.transformNode, obj.nodeFromObject, obj.worldFromObject, shutter);
    const Transform& world = motion.key(0);
    scene->objectFromWorld.push_back(world.inverse());
    if (obj.kind == ObjectKind::Terrain) {
      TriangleMesh mesh = makeFractalTerrain(terrainParams(obj.terrain));
      Instance placed{0, Transform()};
      if (motion.isAnimated()) {
        placed.worldFromObject = world;
        placed.motion = motion;
      } else if (!world.isIdentity()) {
        placeVertices(world, &mesh.positions, &mesh.indices);
        for (Vec3f& n : mesh.normals) n = normalize(world.normal(n));
      }
      materials->meshes.push_back({obj.material, false});
      scene->geometry.meshes.push_back(std::move(mesh));
      placed.mesh = uint32_t(scene->geometry.meshes.size() - 1);
      scene->geometry.instances.push_back(placed);
      materials->terrain = true;
      continue;
    }
    std::vector<int> slots;
    std::unique_ptr<Shape> shape;
    if (obj.kind == ObjectKind::Csg) {
      auto csg = std::make_unique<CsgShape>();
      uint32_t root = addCsgNode(obj.csg, obj.csg.root, Transform(), {}, csg.get(), &slots);
      csg->finish(root);
      for (int& m : slots)
        if (m < 0) m = obj.material;
      shape = std::move(csg);
    } else {
      shape = obj.shape->clone();
      slots.push_back(obj.material);
    }
    Instance inst;
    inst.shape = uint32_t(scene->geometry.shapes.size());
    inst.worldFromObject = world;
    if (motion.isAnimated()) inst.motion = motion;
    scene->geometry.shapes.push_back(std::move(shape));
    scene->geometry.instances.push_back(inst);
    materials->shapeSlots.push_back(std::move(slots));
  }
}

// Whether a mesh of description material `md` (null: the default) made as `made` hides its
// back faces: a single-sided material does, except where light must leave through them (a
// refracting interior, glass or glTF transmission, is seen from behind).
bool singleSided(const MaterialDesc* md, const Material& made) {
  return md && !md->doubleSided && !made.traits().refraction;
}

// One render material per description material (and per vertex-colour use), plus a default,
// assigned to the meshes and shape slots; `uses` (when given) records which is which.
void buildMaterials(const SceneDescription& desc, const GeometryMaterials& geometry,
                    TextureCache& textures, SceneParts* scene, MaterialUses* uses) {
  std::map<std::pair<int, bool>, uint32_t> materialIndex;
  auto materialFor = [&](int material, bool colors) -> uint32_t {
    auto key = std::make_pair(material, colors);
    if (auto it = materialIndex.find(key); it != materialIndex.end()) return it->second;
    MaterialDesc fallback;
    fallback.name = "default";
    fallback.type = MaterialType::Lambert;
    fallback.baseColor = {0.8f, 0.8f, 0.8f};
    const MaterialDesc& md = material >= 0 ? desc.materials[size_t(material)] : fallback;
    scene->materials.push_back(makeMaterial(md, colors, textures));
    const auto index = uint32_t(scene->materials.size() - 1);
    if (uses) {
      MaterialUses::Use& use = uses->ofDescription[material];
      use.made.push_back({index, colors});
      use.tangentSpace = readsTangentSpace(md);
    }
    return materialIndex[key] = index;
  };
  for (size_t i = 0; i < geometry.meshes.size(); ++i) {
    const GeometryMaterials::Mesh& m = geometry.meshes[i];
    const uint32_t index = materialFor(m.material, m.colors);
    scene->meshMaterial.push_back(index);
    if (uses) uses->meshMaterial.push_back(m.material);
    scene->geometry.meshes[i].singleSided = singleSided(
        m.material >= 0 ? &desc.materials[size_t(m.material)] : nullptr, *scene->materials[index]);
  }
  for (const std::vector<int>& slots : geometry.shapeSlots) {
    std::vector<uint32_t> materials;
    for (int m : slots) materials.push_back(materialFor(m, false));
    scene->shapeMaterials.push_back(std::move(materials));
  }
}

// What the automatic camera frames: the geometry where it is now (`now`), grown by where every
// animated mesh and shape goes over the whole animation, so that every frame of a sequence gets
// the same camera (framing each frame's own bounds zooms in and out). The animation is sampled
// at 129 evenly spaced times plus every key time; a shape between the samples can poke out by
// the distance it travels in 1/128 of the animation. Animated CSG trees and terrain count only
// where they are now.
Bounds3f framingBounds(const SceneDescription& desc, const Bounds3f& now) {
  Bounds3f b = now;
  const auto [t0, t1] = animationRange(desc);
  if (!(t1 > t0)) return b;
  // Skinned and morphed meshes change shape: posed at 33 times over the animation.
  for (const InstanceDesc& inst : desc.instances) {
    if (inst.mesh < 0 || !deforms(desc, inst) || !deformationAnimated(desc, inst)) continue;
    for (int i = 0; i <= 32; ++i) {
      const double t = t0 + (t1 - t0) * i / 32;
      const Transform world =
          inst.transformNode >= 0
              ? worldFromNode(desc.nodes, inst.transformNode, t) * inst.nodeFromObject
              : inst.worldFromObject;
      for (Vec3f p : posedPositions(desc, inst, t)) b.extend(world.point(p));
    }
  }
  std::vector<double> times;
  for (int i = 0; i <= 128; ++i) times.push_back(t0 + (t1 - t0) * i / 128);
  for (const NodeDesc& n : desc.nodes)
    for (const auto* track : {&n.translationTrack.times, &n.rotationTrack.times,
                              &n.scaleTrack.times, &n.angleTrack.times})
      for (float t : *track) times.push_back(t);
  std::vector<Bounds3f> meshBounds(desc.meshes.size());
  for (size_t i = 0; i < desc.meshes.size(); ++i)
    for (Vec3f p : desc.meshes[i].positions) meshBounds[i].extend(p);
  auto sweep = [&](int node, const Transform& nodeFromItem, const Bounds3f& local) {
    if (node < 0 || local.empty() || isUnbounded(local) || !isAnimated(desc.nodes, node)) return;
    for (double t : times)
      b.extend((worldFromNode(desc.nodes, node, t) * nodeFromItem).bounds(local));
  };
  for (const InstanceDesc& inst : desc.instances)
    if (inst.mesh >= 0 && size_t(inst.mesh) < meshBounds.size())
      sweep(inst.transformNode, inst.nodeFromObject, meshBounds[size_t(inst.mesh)]);
  for (const ObjectDesc& o : desc.objects)
    if (o.kind == ObjectKind::Shape && o.shape)
      sweep(o.transformNode, o.nodeFromObject, o.shape->bounds());
  return b;
}

// The selected camera (or one framing `bounds`, the geometry now, over the whole animation, when
// the scene names none) with its lens and its placement over the shutter; *name is its name.
Camera makeCamera(const SceneDescription& desc, const CameraDesc* selected,
                  const ShutterTimes& shutter, const Bounds3f& bounds, std::string* name) {
  int width = 0, height = 0;
  resolveImageSize(desc, selected, &width, &height);
  CameraDesc framing;
  if (!selected) {
    framing = framingCamera(framingBounds(desc, bounds), float(width) / float(height));
    selected = &framing;
  }
  *name = selected->name;
  AnimatedTransform worldFromCamera =
      placementOverShutter(desc.nodes, selected->transformNode, selected->nodeFromCamera,
                           selected->worldFromCamera, shutter);
  Camera camera = selected->type == CameraType::Perspective
                      ? Camera::perspective(worldFromCamera, selected->yfov, width, height,
                                            selected->znear, selected->zfar)
                      : Camera::orthographic(worldFromCamera, selected->ymag, width, height,
                                             selected->znear, selected->zfar);
  if (selected->apertureRadius > 0)
    camera.setLens({selected->apertureRadius, selected->focusDistance, selected->apertureBlades,
                    selected->apertureRotation});
  return camera;
}

void buildCamera(const SceneDescription& desc, const CameraDesc* selected,
                 const ShutterTimes& shutter, SceneParts* scene) {
  scene->camera = makeCamera(desc, selected, shutter, scene->geometry.bounds(), &scene->cameraName);
}

// The frame's shutter decides what moves: the render settings' when given, else the selected
// camera's; without either (the automatic camera has none of its own) nothing moves.
ShutterTimes frameShutter(const SceneDescription& desc, const CameraDesc* selected) {
  ShutterTimes shutter{desc.render.time, desc.render.time};
  if (desc.render.shutter) {
    shutter.open += (*desc.render.shutter)[0];
    shutter.close += (*desc.render.shutter)[1];
  } else if (selected) {
    shutter.open += selected->shutterOpen;
    shutter.close += selected->shutterClose;
  }
  return shutter;
}

// Every light (emitting surfaces too) and the sampler that picks among them; the studio
// environment when the scene brings no light of its own (RenderSettings::defaultLight), so a
// file without lights still gets a good first image. Returns whether the studio was added.
bool buildLights(const SceneDescription& desc, const ShutterTimes& shutter, TextureCache& textures,
                 SceneParts* scene) {
  addLights(desc, shutter, &textures, scene);
  if (desc.environment) scene->lights.push_back(makeEnvironmentLight(*desc.environment));
  // Emitting surfaces do not count: a glowing visor must not leave the rest of a helmet black.
  // A scene of unlit (eyelight) surfaces and no media has nothing a light could reach.
  const bool lightReachesSomething =
      !desc.media.empty() ||
      std::any_of(scene->materials.begin(), scene->materials.end(),
                  [](const auto& m) { return (m->flags() & kBsdfUnlit) == 0; });
  const bool defaultLight = scene->lights.empty() && desc.render.defaultLight &&
                            maxComponent(desc.render.background) <= 0 && lightReachesSomething;
  if (defaultLight) {
    EnvironmentDesc studio;
    studio.studio = true;
    scene->lights.push_back(makeEnvironmentLight(studio));
  }
  return defaultLight;
}

// A variant the scene does not define is an error that lists those it does.
void checkVariant(const SceneDescription& desc) {
  const std::string& v = desc.render.variant;
  if (v.empty() || std::find(desc.variants.begin(), desc.variants.end(), v) != desc.variants.end())
    return;
  const std::string names = quotedNames(desc.variants);
  throw SceneError({desc.file, "/render/variant"},
                   "no material variant named '" + v + "'" +
                       (names.empty() ? " (the scene has none)" : " (variants: " + names + ")"));
}

}  // namespace

RenderScene buildRenderScene(const SceneDescription& desc, BuildTimings* timings,
                             const BuildOptions& options) {
  auto start = Clock::now();
  checkVariant(desc);
  SceneParts parts;
  parts.background = desc.render.background;
  // The frame's shutter decides what moves: the render settings' when given, else the
  // camera's; without either (the automatic camera, framed below, has none of its own) nothing
  // moves.
  const CameraDesc* selected = selectCamera(desc);
  const ShutterTimes shutter = frameShutter(desc, selected);
  GeometryMaterials geometryMaterials;
  buildMeshes(desc, shutter, &parts, &geometryMaterials);
  buildObjects(desc, shutter, &parts, &geometryMaterials);
  TextureCache textures(desc, &parts, options.images);
  if (options.materialUses) *options.materialUses = {};
  buildMaterials(desc, geometryMaterials, textures, &parts, options.materialUses);
  // Image pixels decode on worker threads while the camera, lights and BVH are built.
  if (options.decodeImages && parts.images) parts.images->startDecoding();
  buildCamera(desc, selected, shutter, &parts);
  SceneAssembly assembly{.accelerator = desc.render.accel, .integrator = desc.render.integrator};
  assembly.notes.defaultLight = buildLights(desc, shutter, textures, &parts);
  assembly.notes.terrain = geometryMaterials.terrain;
  addMedia(desc, &parts);
  if (options.materialUses) options.materialUses->textures = textures.made();

  double acceleratorSeconds = 0;
  RenderScene scene(std::move(parts), assembly, &acceleratorSeconds);
  if (options.decodeImages) textures.waitForDecodes(scene.images().get());
  if (timings) {
    timings->acceleratorSeconds = acceleratorSeconds;
    timings->totalSeconds = std::chrono::duration<double>(Clock::now() - start).count();
  }
  return scene;
}

bool refreshRenderScene(const SceneDescription& desc, uint32_t what, RenderScene* scene) {
  const CameraDesc* selected = selectCamera(desc);
  const ShutterTimes shutter = frameShutter(desc, selected);
  // An open shutter decides what moves and how the geometry was built over it.
  if (shutter.open != shutter.close) return false;
  std::vector<std::unique_ptr<Light>> lights;
  if (what & kRefreshLights) {
    SceneParts parts;  // the lights alone: none of them reads a texture
    for (const LightDesc& l : desc.lights)
      if (l.texture >= 0) return false;
    TextureCache noTextures(desc, &parts, nullptr);
    addLights(desc, shutter, &noTextures, &parts);
    if (desc.environment) parts.lights.push_back(makeEnvironmentLight(*desc.environment));
    // The studio light of a scene without lights is the whole build's decision.
    if (parts.lights.empty()) return false;
    lights = std::move(parts.lights);
  }
  if (what & kRefreshCamera) {
    std::string name;
    Camera camera = makeCamera(desc, selected, shutter, scene->geometry().bounds(), &name);
    scene->setCamera(std::move(camera), std::move(name));
  }
  if (what & kRefreshLights) scene->setLights(std::move(lights));
  return true;
}

bool refreshMaterials(const SceneDescription& desc, const std::vector<int>& changed,
                      const MaterialUses& uses, RenderScene* scene) {
  std::vector<std::pair<uint32_t, std::unique_ptr<Material>>> made;
  for (int material : changed) {
    const auto use = uses.ofDescription.find(material);
    if (material < 0 || use == uses.ofDescription.end()) continue;  // no mesh or shape uses it
    const MaterialDesc& md = desc.materials[size_t(material)];
    if (readsTangentSpace(md) != use->second.tangentSpace) return false;
    for (const MaterialUses::Made& m : use->second.made) {
      // The scene's own textures serve; a texture it lacks lands in `noTextures`, and needs
      // the whole build.
      SceneParts noTextures;
      TextureCache textures(desc, &noTextures, nullptr);
      textures.reuse(uses.textures);
      std::unique_ptr<Material> fresh = makeMaterial(md, m.vertexColors, textures);
      const Material& old = *scene->materials()[m.index];
      if (!noTextures.textures.empty() ||
          (fresh->flags() & kBsdfUnlit) != (old.flags() & kBsdfUnlit))
        return false;
      made.emplace_back(m.index, std::move(fresh));
    }
  }
  // The meshes' back-face culling, which the accelerator was built with, stays as it was.
  const auto& meshes = scene->geometry().meshes;
  for (const auto& [index, material] : made)
    for (size_t i = 0; i < meshes.size(); ++i)
      if (scene->meshMaterialIndex(uint32_t(i)) == index &&
          singleSided(&desc.materials[size_t(uses.meshMaterial[i])], *material) !=
              meshes[i].singleSided)
        return false;
  for (auto& [index, material] : made) scene->replaceMaterial(index, std::move(material));
  return true;
}

}  // namespace glint
